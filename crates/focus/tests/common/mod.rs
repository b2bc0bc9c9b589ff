//! Shared helpers for the focusing property tests.
#![allow(dead_code)]

use glam::{DMat4, DVec3, DVec4, Mat4, Vec4};
use proptest::prelude::*;
use shadowfocus_focus::*;
use shadowfocus_geom::{unit_direction, Aabb, Body, Camera, Frustum, Light};

/// The GPU clip test in f64, depth in [0, 1].
pub fn inside_f64(m: &DMat4, p: DVec3) -> bool {
    inside_f64_from(m, p, 0.0)
}

/// The GPU clip test in f64 with depth in `[z_min, 1]`.
pub fn inside_f64_from(m: &DMat4, p: DVec3, z_min: f64) -> bool {
    let q = *m * p.extend(1.0);
    q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= z_min * q.w && q.z <= q.w
}

/// The clip test of a fitted map in its own convention (f64).
pub fn inside_map_f64(fit: &MapFit, p: DVec3) -> bool {
    inside_f64_from(&fit.clip_from_world, p, fit.clip.depth_min())
}

/// The clip test of a fitted map's f32 matrix in its own convention.
pub fn inside_map_f32(fit: &MapFit, p: DVec3) -> bool {
    inside_f32_from(&fit.clip_from_world_f32, p, fit.clip.depth_min() as f32)
}

/// Every clip convention: both depth ranges, reversed-Z, both uv origins,
/// clip +y up or down.
pub fn clip_strategy() -> impl Strategy<Value = ClipConvention> {
    (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(zero, reversed_z, top, y_down)| ClipConvention {
        depth: if zero { DepthRange::ZeroToOne } else { DepthRange::MinusOneToOne },
        reversed_z,
        uv_origin: if top { UvOrigin::TopLeft } else { UvOrigin::BottomLeft },
        y_down,
    })
}

/// The GPU clip test with the f32 matrix, the point rounded to f32 and f32
/// arithmetic (row-by-row dot products, as a vertex shader computes them).
pub fn inside_f32(m: &Mat4, p: DVec3) -> bool {
    inside_f32_from(m, p, 0.0)
}

/// [`inside_f32`] with depth in `[z_min, 1]`.
pub fn inside_f32_from(m: &Mat4, p: DVec3, z_min: f32) -> bool {
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
        && z >= z_min * w
        && z <= w
        && q.w > 0.0
        && q.x.abs() <= q.w
        && q.y.abs() <= q.w
        && q.z >= z_min * q.w
        && q.z <= q.w
}

pub fn light_point(l: &Light) -> DVec4 {
    match *l {
        Light::Directional { direction } => (-unit_direction(direction)).extend(0.0),
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
    (0..3u8, (0.0..std::f64::consts::TAU, -1.5..1.5f64), (-90.0..90.0f64, -90.0..90.0f64, -90.0..90.0f64), 0.4..2.0f64).prop_map(
        |(kind, (t, p), (x, y, z), fov)| match kind {
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
        },
    )
}

pub fn method_strategy() -> impl Strategy<Value = Method> {
    prop_oneof![Just(Method::Uniform), Just(Method::Psm), Just(Method::Lispsm), Just(Method::Tsm), Just(Method::Auto)]
}

pub fn settings_strategy() -> impl Strategy<Value = FocusSettings> {
    // A third of the fits share a texel budget (never with stable maps,
    // which refuse it): enough for every map of a cube at the largest
    // receiver margin the properties ask for.
    let budget = prop_oneof![2 => Just(None), 1 => ((1u64 << 20)..(1u64 << 24), any::<bool>()).prop_map(Some)];
    // A quarter name a face of the scene box as the ground (any face: the
    // prediction moves, never what a map covers); `framed_strategy` puts
    // half of them at a level inside the scene box.
    let ground = prop_oneof![3 => Just(None), 1 => (0..6usize).prop_map(|k| Some(Ground::face(BoxFace::ALL[k])))];
    let options = (any::<bool>(), any::<bool>(), any::<bool>(), clip_strategy(), budget, ground);
    (method_strategy(), 1..=4usize, 0..5u8, 0.0..1.0f64, options).prop_map(
        |(method, count, scheme, lambda, (stable, middle, cube, clip, budget, ground))| FocusSettings {
            method,
            splits: SplitSettings {
                count,
                scheme: match scheme {
                    0 => SplitScheme::Uniform,
                    1 => SplitScheme::Log,
                    // A first split of any length, down to none (clamped to near).
                    2 => SplitScheme::Geometric { first: 0.05 + 100.0 * lambda * lambda },
                    // Optimal placement refuses stable maps.
                    3 if !stable => SplitScheme::Optimal,
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
            clip,
            texel_budget: budget
                .filter(|_| !stable)
                .map(|(texels, any)| TexelBudget { texels, sizes: if any { MapSizes::Any } else { MapSizes::PowerOfTwo } }),
            ground,
            ..FocusSettings::default()
        },
    )
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
    let q = map.fit.clip_from_world * p.extend(1.0);
    let z = q.z / q.w;
    DVec3::new(q.x / q.w, q.y / q.w, if map.fit.depth_test == DepthTest::Greater { 1.0 - z } else { z })
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

/// A frame and settings for it: where the settings name a ground, half of
/// the time at a level inside the frame's scene box (anywhere from its face
/// to the opposite one).
pub fn framed_strategy() -> impl Strategy<Value = ((Camera, Aabb, Light), FocusSettings)> {
    (frame_strategy(), settings_strategy(), prop_oneof![Just(None), (0.0..=1.0f64).prop_map(Some)]).prop_map(|(frame, mut s, t)| {
        let scene = &frame.1;
        if let (Some(g), Some(t)) = (&mut s.ground, t) {
            let k = g.face.axis();
            g.level = Some((scene.min[k] + t * (scene.max[k] - scene.min[k])).clamp(scene.min[k], scene.max[k]));
        }
        (frame, s)
    })
}

/// Camera, scene box and light of one frame: the independent generators
/// above, mixed on purpose with the cases they never produce by chance:
///
/// - the whole frame moved by `p ↦ o + k p` with `k` ∈ {1e-4, 1e6} (tiny and
///   huge scenes) and `o` up to 1e8 from the origin (directions unchanged);
/// - a directional light exactly parallel to the view direction (γ = 0),
///   either way;
/// - a point light exactly in the camera plane (an axis-aligned camera, the
///   light sharing the eye's coordinate along the axis);
/// - directional lights 1e200 and 1e-200 long.
pub fn frame_strategy() -> impl Strategy<Value = (Camera, Aabb, Light)> {
    let plain = (camera_strategy(), scene_strategy(), light_strategy());
    let moved = (
        (camera_strategy(), scene_strategy(), light_strategy()),
        prop_oneof![Just(1.0), Just(1e-4), Just(1e6)],
        prop_oneof![Just(DVec3::ZERO), Just(DVec3::new(1e8, 0.0, 0.0)), Just(DVec3::new(-7.5e7, 3e7, 1e8))],
    )
        .prop_map(|((cam, scene, light), k, o)| moved_frame(&cam, &scene, &light, k, o));
    let gamma_zero = (camera_strategy(), scene_strategy(), any::<bool>())
        .prop_map(|(cam, scene, toward)| (cam, scene, Light::directional(if toward { cam.forward } else { -cam.forward }).unwrap()));
    let in_camera_plane = (axis_camera_strategy(), scene_strategy(), (-60.0..60.0f64, -60.0..60.0f64)).prop_map(|(cam, scene, (a, b))| {
        // The two axes other than the camera's: the light keeps the
        // eye's coordinate along the view axis exactly.
        let k = cam.forward.abs().max_position();
        let mut l = cam.eye;
        l[(k + 1) % 3] += a;
        l[(k + 2) % 3] += b;
        (cam, scene, Light::point(l).unwrap())
    });
    let long_short = (
        camera_strategy(),
        scene_strategy(),
        (0.0..std::f64::consts::TAU, -1.5..1.5f64),
        prop_oneof![Just(1e200), Just(1e-200), Just(1e300), Just(1e-300)],
    )
        .prop_map(|(cam, scene, (t, p), k)| (cam, scene, Light::directional(unit(t, p) * k).unwrap()));
    prop_oneof![4 => plain, 3 => moved, 1 => gamma_zero, 1 => in_camera_plane, 1 => long_short]
}

/// A camera looking along ±X, ±Y or ±Z.
pub fn axis_camera_strategy() -> impl Strategy<Value = Camera> {
    (camera_strategy(), 0..6usize).prop_map(|(cam, k)| {
        let axes = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
        let forward = axes[k];
        let up = if k / 2 == 1 { DVec3::Z } else { DVec3::Y };
        Camera { forward, up, ..cam }
    })
}

/// The frame under `p ↦ o + k p` (lengths scaled, directions kept).
pub fn moved_frame(cam: &Camera, scene: &Aabb, light: &Light, k: f64, o: DVec3) -> (Camera, Aabb, Light) {
    let p = |x: DVec3| o + x * k;
    let cam2 = Camera { eye: p(cam.eye), near: cam.near * k, far: cam.far * k, ..*cam };
    let scene2 = Aabb::new(p(scene.min), p(scene.max)).unwrap();
    let light2 = match *light {
        Light::Directional { direction } => Light::directional(direction).unwrap(),
        Light::Point { position } => Light::point(p(position)).unwrap(),
        // A spot frustum whose moved corners round into a degenerate one
        // (small and far from the origin) becomes a point light there.
        Light::Spot { position, frustum } => match Frustum::from_corners(frustum.corners().map(p)) {
            Ok(f) => Light::spot(p(position), f).unwrap(),
            Err(_) => Light::point(p(position)).unwrap(),
        },
    };
    (cam2, scene2, light2)
}

/// Whether f32 positions resolve the frame: its coordinates at most 1e3
/// times the scene box's extent (no large offset from the origin).
pub fn modest_coordinates(cam: &Camera, scene: &Aabb) -> bool {
    let mag = scene.min.abs().max(scene.max.abs()).max(cam.eye.abs()).max_element();
    mag <= 1e3 * (scene.max - scene.min).max_element()
}

/// How far `(x/w, y/w, z/w)` under `m` can move when `p` moves by the
/// rounding of its coordinates (4 ulps of its magnitude on each axis): the
/// resolution at which a test can compare map coordinates of computed
/// points (far from the origin it is coarse).
pub fn ndc_sensitivity(m: &DMat4, p: DVec3) -> DVec3 {
    let d = 4.0 * f64::EPSILON * p.abs().max_element();
    let f = |q: DVec3| {
        let v = *m * q.extend(1.0);
        v.truncate() / v.w
    };
    let c = f(p);
    (0..3).fold(DVec3::ZERO, |acc, k| {
        let mut e = DVec3::ZERO;
        e[k] = d;
        acc + (f(p + e) - c).abs()
    })
}
