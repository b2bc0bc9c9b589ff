//! Shared helpers for the focusing property tests.
#![allow(dead_code)]

use glam::{DMat4, DVec3, DVec4, Mat4, Vec4};
use proptest::prelude::*;
use shadowfocus_focus::*;
use shadowfocus_geom::{Aabb, Body, Camera, Frustum, Light};

/// The GPU clip test in f64.
pub fn inside_f64(m: &DMat4, p: DVec3) -> bool {
    let q = *m * p.extend(1.0);
    q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= 0.0 && q.z <= q.w
}

/// The GPU clip test with the f32 matrix, the point rounded to f32 and f32
/// arithmetic (row-by-row dot products, as a vertex shader computes them).
pub fn inside_f32(m: &Mat4, p: DVec3) -> bool {
    let v = Vec4::new(p.x as f32, p.y as f32, p.z as f32, 1.0);
    let r = |i: usize| {
        let row = m.row(i);
        row.x * v.x + row.y * v.y + row.z * v.z + row.w * v.w
    };
    let (x, y, z, w) = (r(0), r(1), r(2), r(3));
    // Also with glam's own (SIMD) product.
    let q = *m * v;
    w > 0.0
        && x.abs() <= w
        && y.abs() <= w
        && z >= 0.0
        && z <= w
        && q.w > 0.0
        && q.x.abs() <= q.w
        && q.y.abs() <= q.w
        && q.z >= 0.0
        && q.z <= q.w
}

pub fn light_point(l: &Light) -> DVec4 {
    match *l {
        Light::Directional { direction } => (-direction.normalize()).extend(0.0),
        Light::Point { position } | Light::Spot { position, .. } => position.extend(1.0),
    }
}

/// Travel direction of the light at `p`.
pub fn travel(l: &Light, p: DVec3) -> DVec3 {
    let lp = light_point(l);
    (p * lp.w - lp.truncate()).normalize()
}

pub fn unit(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(phi.cos() * theta.cos(), phi.sin(), phi.cos() * theta.sin())
}

pub fn camera_strategy() -> impl Strategy<Value = Camera> {
    (
        (-20.0..20.0f64, -20.0..20.0f64, -20.0..20.0f64),
        (0.0..std::f64::consts::TAU, -1.3..1.3f64, -0.6..0.6f64),
        (0.3..2.2f64, 0.5..2.5f64, 0.05..2.0f64, 3.0..400.0f64),
    )
        .prop_map(|((x, y, z), (yaw, pitch, roll), (fovy, aspect, near, ratio))| {
            let forward = unit(yaw, pitch);
            let side = forward.cross(DVec3::Y).normalize();
            let up0 = side.cross(forward);
            let up = up0 * roll.cos() + side * roll.sin();
            Camera { eye: DVec3::new(x, y, z), forward, up, fovy, aspect, near, far: near * ratio }
        })
}

pub fn scene_strategy() -> impl Strategy<Value = Aabb> {
    ((-15.0..15.0f64, -15.0..15.0f64, -15.0..15.0f64), (2.0..80.0f64, 2.0..80.0f64, 2.0..80.0f64))
        .prop_map(|((x, y, z), (a, b, c))| Aabb::new(DVec3::new(x - a, y - b, z - c), DVec3::new(x + a, y + b, z + c)).unwrap())
}

#[derive(Clone, Copy, Debug)]
pub enum LightKind {
    Directional,
    Point,
    Spot,
}

pub fn light_strategy() -> impl Strategy<Value = Light> {
    (0..3u8, (0.0..std::f64::consts::TAU, -1.5..1.5f64), (-90.0..90.0f64, -90.0..90.0f64, -90.0..90.0f64), 0.4..2.0f64)
        .prop_map(|(kind, (t, p), (x, y, z), fov)| match kind {
            0 => Light::directional(unit(t, p)).unwrap(),
            1 => Light::point(DVec3::new(x, y, z)).unwrap(),
            _ => {
                let pos = DVec3::new(x, y, z);
                // Aim roughly at the origin, where scenes are.
                let fwd = (-pos).try_normalize().unwrap_or(DVec3::NEG_Y) * 0.8 + unit(t, p) * 0.2;
                let up = if fwd.cross(DVec3::Y).length() > 1e-3 { DVec3::Y } else { DVec3::X };
                let cam = Camera { eye: pos, forward: fwd, up, fovy: fov, aspect: 1.0, near: 0.5, far: 400.0 };
                Light::spot(pos, Frustum::from_camera(&cam).unwrap()).unwrap()
            }
        })
}

pub fn method_strategy() -> impl Strategy<Value = Method> {
    prop_oneof![Just(Method::Uniform), Just(Method::Psm), Just(Method::Lispsm), Just(Method::Tsm)]
}

pub fn settings_strategy() -> impl Strategy<Value = FocusSettings> {
    (method_strategy(), 1..=4usize, 0..3u8, 0.0..1.0f64, any::<bool>(), any::<bool>(), any::<bool>())
        .prop_map(|(method, count, scheme, lambda, stable, middle, cube)| FocusSettings {
            method,
            splits: SplitSettings {
                count,
                scheme: match scheme {
                    0 => SplitScheme::Uniform,
                    1 => SplitScheme::Log,
                    _ => SplitScheme::Practical { lambda },
                },
                delta_bias: 0.0,
            },
            resolution: 1024,
            stable,
            lispsm: LispsmSettings {
                visible_far: None,
                warp: if middle { WarpDirection::MiddleVector } else { WarpDirection::ViewProjected },
            },
            point: if cube { PointMode::Cube } else { PointMode::Single },
            ..FocusSettings::default()
        })
}

/// Points of a body: its vertices and a few interior combinations.
pub fn body_points(b: &Body, extra: usize, seed: u64) -> Vec<DVec3> {
    let v = b.vertices();
    let mut out = v.to_vec();
    let mut s = seed | 1;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..extra {
        let mut acc = DVec3::ZERO;
        let mut wsum = 0.0;
        for p in v {
            let w = rnd().powi(3);
            acc += *p * w;
            wsum += w;
        }
        if wsum > 0.0 {
            out.push(acc / wsum);
        }
    }
    out
}

/// Normalised map coordinates `(x/w, y/w, depth)` with depth taken in the
/// "less" orientation (1 − z for a greater test).
pub fn ndc(map: &ShadowMap, p: DVec3) -> DVec3 {
    let q = map.matrix * p.extend(1.0);
    let z = q.z / q.w;
    DVec3::new(q.x / q.w, q.y / q.w, if map.depth_test == DepthTest::Greater { 1.0 - z } else { z })
}

/// The r of split `i` of a point light's frame: every map of the split
/// reports the same one, positive for a split with a cut (a truncated or
/// cube-face map), and 0 only for a single map that cuts nothing.
pub fn point_light_radius(out: &FocusResult, i: usize) -> Result<f64, TestCaseError> {
    let maps: Vec<&ShadowMap> = out.maps().iter().filter(|m| m.split == i).collect();
    prop_assert!(!maps.is_empty(), "split {i} has no map");
    let r = maps[0].light_near;
    prop_assert!(maps.iter().all(|m| m.light_near == r), "split {i}: maps report different r");
    prop_assert!(r.is_finite() && r >= 0.0);
    if r == 0.0 {
        prop_assert!(maps.len() == 1 && matches!(maps[0].light, Light::Point { .. }), "split {i}: r = 0 for a map that cuts");
    }
    Ok(r)
}
