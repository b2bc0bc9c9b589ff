//! Point lights swept over a sphere around the camera: in front, in the
//! camera plane (exactly), behind, inside the view frustum, inside the
//! scene box; single and cube modes; one and four splits; every method.
//!
//! The guarantee (see `LightNear`): every point of a split's exact body
//! `H_i` (the untruncated body of the point light) farther than the split's
//! `r` from the light lies in some active map of the split, `r` being what
//! the maps report as `light_near`. Checked on every vertex of `H_i` and
//! on points inside it, against the body engine.

mod common;

use common::*;
use glam::DVec3;
use shadowfocus_focus::*;
use shadowfocus_geom::{focus_body, Aabb, Camera, Frustum, Light};

#[derive(Default, Debug)]
struct Counts {
    fits: usize,
    maps: usize,
    single_truncated: usize,
    single_whole: usize,
    as_cube: usize,
    points_checked: usize,
    points_within_r: usize,
}

/// One configuration; adds to `c`, fails with a description.
fn check(cam: &Camera, scene: &Aabb, l: DVec3, s: &FocusSettings, c: &mut Counts) -> Result<(), String> {
    let light = Light::point(l).unwrap();
    let mut out = FocusResult::new();
    fit(cam, &light, scene, s, &mut out).map_err(|e| format!("fit: {e}"))?;
    c.fits += 1;
    let d = out.split_depths().to_vec();
    for m in out.maps().iter().filter(|m| m.is_active()) {
        c.maps += 1;
        for p in m.body().vertices() {
            if !inside_f64(&m.fit.clip_from_world, *p) {
                return Err(format!("split {} face {:?}: own body vertex {p} outside", m.split, m.face));
            }
        }
    }
    if out.notes.contains(Notes::POINT_AS_CUBE) {
        c.as_cube += 1;
    }
    for i in 0..d.len() - 1 {
        let maps: Vec<&ShadowMap> = out.maps().iter().filter(|m| m.split == i).collect();
        let r = point_light_radius(&out, i).map_err(|e| e.to_string())?;
        if s.point == PointMode::Single && maps.len() == 1 {
            match maps[0].light {
                Light::Spot { .. } => c.single_truncated += 1,
                _ => c.single_whole += 1,
            }
        }
        let sub = Camera { near: d[i], far: d[i + 1], ..*cam };
        let h = focus_body(&Frustum::from_camera(&sub).unwrap(), &light, scene).map_err(|e| format!("body: {e}"))?;
        for (k, p) in body_points(&h, 24, 7 + i as u64).into_iter().enumerate() {
            if (p - l).length() <= r {
                c.points_within_r += 1;
                continue;
            }
            c.points_checked += 1;
            if !maps.iter().any(|m| m.is_active() && inside_f64(&m.fit.clip_from_world, p)) {
                let what = if k < h.vertices().len() { "vertex" } else { "interior point" };
                return Err(format!("split {i}: {what} {p} of H_i, {} from the light (r = {r}), in no map", (p - l).length()));
            }
        }
    }
    Ok(())
}

/// Light positions around `eye` at distance `rho`: the camera's axes and
/// diagonals (exactly in the camera plane among them) and a grid over the
/// sphere.
fn around(cam: &Camera, rho: f64) -> Vec<DVec3> {
    let b = cam.basis().unwrap();
    let (f, r, u) = (b.forward, b.right, b.up);
    let mut dirs = vec![f, -f, r, -r, u, -u, r + u, r - u, f + u, f - u * 0.5, -f + r, f * 2.0 + r * 0.3 + u * 0.2];
    for i in 0..8 {
        for j in -2..=2 {
            let (t, p) = (i as f64 * std::f64::consts::TAU / 8.0 + 0.3, j as f64 * 0.6);
            dirs.push(f * (p.cos() * t.cos()) + r * (p.cos() * t.sin()) + u * p.sin());
        }
    }
    dirs.into_iter().map(|d| cam.eye + d.normalize() * rho).collect()
}

fn sweep(cam: &Camera, scene: &Aabb, radii: &[f64], extra: &[DVec3], counts: &mut Counts) {
    let mut lights: Vec<DVec3> = radii.iter().flat_map(|&rho| around(cam, rho)).collect();
    lights.extend_from_slice(extra);
    let mut failures = Vec::new();
    for l in lights {
        for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
            for point in [PointMode::Single, PointMode::Cube] {
                for count in [1, 4] {
                    let s = FocusSettings { method, point, splits: SplitSettings { count, ..Default::default() }, ..Default::default() };
                    if let Err(e) = check(cam, scene, l, &s, counts) {
                        failures.push(format!("light {l}, {method:?} {point:?} {count} splits: {e}"));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{} failures, first: {:#?}", failures.len(), &failures[..failures.len().min(5)]);
}

#[test]
fn point_light_sweep_keeps_every_point_farther_than_r() {
    let mut counts = Counts::default();
    let cam =
        Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap();
    // Inside the view (on the axis, at split depths and between), inside
    // the box but out of view, at the eye, on the box's faces.
    let b = cam.basis().unwrap();
    let extra: Vec<DVec3> = [0.5, 1.0, 3.0, 7.3, 25.0, 60.0, 99.0]
        .iter()
        .map(|z| cam.eye + b.forward * *z)
        .chain([
            cam.eye,
            DVec3::new(-49.0, 1.0, 19.0),
            DVec3::new(30.0, 15.0, 15.0),
            DVec3::new(0.0, 0.0, -50.0),
            DVec3::new(50.0, 10.0, -50.0),
        ])
        .collect();
    sweep(&cam, &scene, &[0.2, 3.0, 40.0, 150.0], &extra, &mut counts);
    // A tilted camera over a small scene (the light's reach and r at 1e-3
    // of the first's), and one 1e5 away from the origin.
    let small = Camera {
        eye: DVec3::new(0.001, 0.002, 0.003),
        forward: DVec3::new(0.3, -0.2, -1.0),
        up: DVec3::new(0.1, 1.0, 0.0),
        fovy: 1.2,
        aspect: 1.0,
        near: 1e-4,
        far: 0.05,
    };
    let small_box = Aabb::new(DVec3::new(-0.03, -0.01, -0.05), DVec3::new(0.03, 0.01, 0.01)).unwrap();
    sweep(&small, &small_box, &[3e-5, 0.004, 0.03], &[small.eye + small.basis().unwrap().forward * 0.01], &mut counts);
    let off = DVec3::new(1e5, -3e4, 2e5);
    let far_cam = Camera { eye: cam.eye + off, ..cam };
    let far_box = Aabb::new(scene.min + off, scene.max + off).unwrap();
    sweep(&far_cam, &far_box, &[3.0, 40.0], &[far_cam.eye + b.forward * 7.3], &mut counts);
    eprintln!("point-light sweep: {counts:?}");
    // The sweep reaches every construction.
    assert!(counts.single_truncated > 0 && counts.single_whole > 0 && counts.as_cube > 0 && counts.points_within_r > 0, "{counts:?}");
}

/// A fixed r is reported by every map of the light and kept as the
/// guarantee, however it compares with the scene.
#[test]
fn fixed_light_near_is_reported_and_kept() {
    let cam =
        Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap();
    let mut counts = Counts::default();
    for r in [1e-3, 0.05, 2.0] {
        for l in [DVec3::new(0.0, 2.0, -20.0), DVec3::new(-49.0, 1.0, 19.0), DVec3::new(30.0, 15.0, 15.0)] {
            for point in [PointMode::Single, PointMode::Cube] {
                let s = FocusSettings {
                    point,
                    light_near: LightNear::Fixed(r),
                    splits: SplitSettings { count: 4, ..Default::default() },
                    ..Default::default()
                };
                check(&cam, &scene, l, &s, &mut counts).unwrap();
                let mut out = FocusResult::new();
                fit(&cam, &Light::point(l).unwrap(), &scene, &s, &mut out).unwrap();
                assert!(out.maps().iter().all(|m| m.light_near == r), "{l} {point:?} r = {r}");
            }
        }
    }
}

/// Auto r follows the scene's scale: the same configuration scaled by
/// 2^-20 reports r scaled by 2^-20 (exactly: every input is), and the
/// single-map cut keeps H_i beyond it.
#[test]
fn auto_light_near_follows_the_scale() {
    let cam =
        Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap();
    let k = 2f64.powi(-20);
    let small_cam = Camera { eye: cam.eye * k, near: cam.near * k, far: cam.far * k, ..cam };
    let small_scene = Aabb::new(scene.min * k, scene.max * k).unwrap();
    let l = DVec3::new(-49.0, 1.0, 19.0);
    let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
    let s = FocusSettings::default();
    fit(&cam, &Light::point(l).unwrap(), &scene, &s, &mut a).unwrap();
    fit(&small_cam, &Light::point(l * k).unwrap(), &small_scene, &s, &mut b).unwrap();
    let (ra, rb) = (a.maps()[0].light_near, b.maps()[0].light_near);
    assert!(ra > 0.0 && ra < 1.0, "r = {ra}");
    assert_eq!(rb, ra * k);
    let mut counts = Counts::default();
    check(&small_cam, &small_scene, l * k, &s, &mut counts).unwrap();
    assert!(counts.single_truncated == 1 && counts.points_checked > 0, "{counts:?}");
}
