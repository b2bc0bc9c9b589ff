//! Method-specific behaviour: PSM's inverted lights and shift, LiSPSM's
//! n_opt, TSM's 80 % line, stable snapping, empty bodies, errors, culling.

mod common;

use common::*;
use glam::DVec3;
use shadowfocus_focus::*;
use shadowfocus_geom::{Aabb, Camera, Frustum, Light};

/// Stable maps need split planes that hold still.
const PRACTICAL: SplitScheme = SplitScheme::Practical { lambda: 0.5 };

fn camera() -> Camera {
    Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 }
}

fn scene() -> Aabb {
    Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap()
}

fn fit1(cam: &Camera, light: &Light, scene: &Aabb, s: &FocusSettings) -> FocusResult {
    let mut out = FocusResult::new();
    fit(cam, light, scene, s, &mut out).unwrap();
    for m in out.maps().iter().filter(|m| m.is_active()) {
        for p in m.body().vertices() {
            assert!(inside_f64(&m.fit.clip_from_world, *p) && inside_f32(&m.fit.clip_from_world_f32, *p));
        }
    }
    out
}

/// The constructions as the papers define them: the warp guard (which may
/// weaken a warp or give it up, see `tests/sweep.rs`) is off in the tests
/// of their formulas.
fn psm() -> FocusSettings {
    FocusSettings { method: Method::Psm, warp_guard: false, ..Default::default() }
}

#[test]
fn psm_directional_from_front_is_a_point_light_without_shift() {
    let out = fit1(&camera(), &Light::directional(DVec3::new(0.1, -0.3, 1.0)).unwrap(), &scene(), &psm());
    let m = &out.maps()[0];
    assert_eq!((m.fit.method, m.fit.depth_test, m.fit.psm_shift), (Method::Psm, DepthTest::Less, 0.0));
    assert!(out.skipped.contains(Skipped::PSM_SHIFT));
    assert!(!out.notes.contains(Notes::INVERTED));
}

#[test]
fn psm_directional_from_behind_is_inverted_with_minimal_shift() {
    let cam = camera();
    let out = fit1(&cam, &Light::directional(DVec3::new(0.1, -0.3, -1.0)).unwrap(), &scene(), &psm());
    let m = &out.maps()[0];
    assert_eq!((m.fit.method, m.fit.depth_test), (Method::Psm, DepthTest::Greater));
    assert!(out.notes.contains(Notes::INVERTED) && !out.skipped.contains(Skipped::PSM_SHIFT));
    // Minimal: H's nearest point ends exactly at the kept near distance.
    let zmin = m.body().vertices().iter().map(|p| cam.forward.dot(*p - cam.eye)).fold(f64::INFINITY, f64::min);
    assert!(m.fit.psm_shift > 0.0);
    assert!((zmin + m.fit.psm_shift - cam.near).abs() < 1e-12 * 200.0, "{} {}", zmin, m.fit.psm_shift);
}

#[test]
fn psm_light_parallel_to_image_plane_stays_directional() {
    // f·d = 0 exactly: the transformed light is at infinity (w = 0).
    let out = fit1(&camera(), &Light::directional(DVec3::new(0.3, -1.0, 0.0)).unwrap(), &scene(), &psm());
    let m = &out.maps()[0];
    assert_eq!((m.fit.method, m.fit.depth_test, m.fit.psm_shift), (Method::Psm, DepthTest::Less, 0.0));
}

#[test]
fn psm_point_lights_in_front_behind_and_in_the_camera_plane() {
    let cam = camera();
    let scene = scene();
    for (l, want) in [
        (DVec3::new(0.0, 30.0, -150.0), DepthTest::Less),  // in front, outside S
        (DVec3::new(5.0, 30.0, 40.0), DepthTest::Greater), // behind the camera plane: inverted
        (DVec3::new(5.0, 30.0, 10.0), DepthTest::Less),    // in the camera plane: directional
    ] {
        let out = fit1(&cam, &Light::point(l).unwrap(), &scene, &psm());
        assert_eq!(out.maps().len(), 1, "{l}");
        let m = &out.maps()[0];
        assert_eq!((m.fit.method, m.fit.depth_test), (Method::Psm, want), "{l}");
    }
}

#[test]
fn psm_tightened_near_is_used() {
    let cam = camera();
    let s = FocusSettings { method: Method::Psm, psm: PsmSettings { near: Some(4.0), far: Some(60.0) }, ..Default::default() };
    let out = fit1(&cam, &Light::directional(DVec3::new(0.1, -0.3, 1.0)).unwrap(), &scene(), &s);
    assert_eq!(out.split_depths(), &[4.0, 60.0]);
    let bad = FocusSettings { method: Method::Psm, psm: PsmSettings { near: Some(200.0), far: None }, ..Default::default() };
    let mut o = FocusResult::new();
    assert!(matches!(
        fit(&cam, &Light::directional(DVec3::NEG_Y).unwrap(), &scene(), &bad, &mut o),
        Err(FocusError::InvalidSettings { .. })
    ));
}

fn lispsm(visible_far: Option<f64>) -> FocusSettings {
    FocusSettings {
        method: Method::Lispsm,
        lispsm: LispsmSettings { visible_far, warp: WarpDirection::ViewProjected },
        warp_guard: false,
        ..Default::default()
    }
}

#[test]
fn lispsm_n_opt_matches_the_formula() {
    // Light straight down, view horizontal: γ = 90°, the warp axis is the
    // view direction, image units are world units.
    let cam = Camera { eye: DVec3::new(0.0, 5.0, 0.0), ..camera() };
    let scene = Aabb::new(DVec3::new(-30.0, 0.0, -80.0), DVec3::new(30.0, 10.0, 5.0)).unwrap();
    let sun = Light::directional(DVec3::NEG_Y).unwrap();
    for vf in [None, Some(20.0)] {
        let out = fit1(&cam, &sun, &scene, &lispsm(vf));
        let m = &out.maps()[0];
        let depth = |p: &DVec3| cam.forward.dot(*p - cam.eye);
        let v = m.body().vertices();
        let (zmin, zmax) = v.iter().map(depth).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| (a.min(z), b.max(z)));
        let z0 = zmin.max(cam.near);
        let mut dz = zmax - zmin;
        if let Some(vf) = vf {
            dz = dz.min(vf - cam.near);
        }
        let n_opt = cam.near + (z0 * (z0 + dz)).sqrt();
        assert!((m.fit.warp_near - n_opt).abs() < 1e-9 * n_opt, "{vf:?}: {} vs {n_opt}", m.fit.warp_near);
    }
}

#[test]
fn lispsm_fades_into_uniform_as_gamma_vanishes() {
    let cam = camera();
    let scene = scene();
    let mut last = 0.0;
    for k in (0..6).rev() {
        let a = 0.2 * 0.3f64.powi(5 - k) * (k as f64 + 1.0) / 6.0;
        let d = DVec3::new(0.0, -a.sin(), -a.cos());
        let out = fit1(&cam, &Light::directional(d).unwrap(), &scene, &lispsm(None));
        let n = out.maps()[0].fit.warp_near;
        assert!(n.is_finite() && n > last, "n_opt must grow as γ shrinks: {n} after {last}");
        last = n;
    }
    // γ = 0 exactly: no warp, and exactly the uniform map.
    let sun = Light::directional(cam.forward).unwrap();
    let l = fit1(&cam, &sun, &scene, &lispsm(None));
    let u = fit1(&cam, &sun, &scene, &FocusSettings::default());
    assert!(l.skipped.contains(Skipped::WARP) && l.maps()[0].fit.warp_near == f64::INFINITY);
    let (a, b) = (l.maps()[0].fit.clip_from_world, u.maps()[0].fit.clip_from_world);
    assert!(a.abs_diff_eq(b, 1e-12 * b.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()))), "{a} vs {b}");
}

#[test]
fn lispsm_middle_vector_differs_but_is_valid() {
    let cam = camera();
    let sun = Light::directional(DVec3::new(0.5, -1.0, 0.3)).unwrap();
    let s = FocusSettings {
        method: Method::Lispsm,
        lispsm: LispsmSettings { visible_far: None, warp: WarpDirection::MiddleVector },
        warp_guard: false,
        ..Default::default()
    };
    let a = fit1(&cam, &sun, &scene(), &s);
    let b = fit1(&cam, &sun, &scene(), &lispsm(None));
    assert!(a.maps()[0].fit.warp_near.is_finite());
    assert!(!a.maps()[0].fit.clip_from_world.abs_diff_eq(b.maps()[0].fit.clip_from_world, 1e-6));
}

#[test]
fn tsm_puts_the_focus_point_on_the_80_percent_line() {
    let cam = Camera { eye: DVec3::new(0.0, 5.0, 0.0), ..camera() };
    let scene = Aabb::new(DVec3::new(-30.0, 0.0, -80.0), DVec3::new(30.0, 10.0, 5.0)).unwrap();
    for (d, focus) in [(DVec3::NEG_Y, 0.25), (DVec3::new(0.3, -1.0, 0.4), 0.1), (DVec3::new(-0.2, -1.0, -0.3), 0.4)] {
        let s = FocusSettings { method: Method::Tsm, tsm: TsmSettings { focus }, warp_guard: false, ..Default::default() };
        let out = fit1(&cam, &Light::directional(d).unwrap(), &scene, &s);
        let m = &out.maps()[0];
        assert!(m.fit.warp_near.is_finite(), "{d}: no warp");
        let p = cam.eye + cam.forward * (cam.near + focus * (cam.far - cam.near));
        let q = m.fit.clip_from_world * p.extend(1.0);
        assert!((q.y / q.w - 0.6).abs() < 1e-5, "{d}: focus point at y = {}", q.y / q.w);
    }
}

#[test]
fn stable_maps_snap_to_texels_and_ignore_rotation() {
    let s = FocusSettings {
        stable: true,
        resolution: 1024,
        splits: SplitSettings { count: 3, scheme: PRACTICAL, ..Default::default() },
        ..Default::default()
    };
    let sun = Light::directional(DVec3::new(0.3, -1.0, 0.45)).unwrap();
    let scene = Aabb::new(DVec3::new(-500.0, -50.0, -500.0), DVec3::new(500.0, 50.0, 500.0)).unwrap();
    let base = camera();
    let a = fit1(&base, &sun, &scene, &s);
    let yaw = 0.7f64;
    for cam in [
        Camera { eye: base.eye + DVec3::new(0.37, 0.11, -2.3), ..base },
        Camera { eye: base.eye + DVec3::new(-13.01, 0.5, 7.77), forward: DVec3::new(yaw.sin(), -0.2, -yaw.cos()), ..base },
    ] {
        let b = fit1(&cam, &sun, &scene, &s);
        for (ma, mb) in a.maps().iter().zip(b.maps()) {
            // Same extent (texel size) bit for bit …
            assert_eq!(ma.fit.clip_from_world.row(0).truncate(), mb.fit.clip_from_world.row(0).truncate());
            assert_eq!(ma.fit.clip_from_world.row(1).truncate(), mb.fit.clip_from_world.row(1).truncate());
            // … and the origin moved by whole texels.
            for r in 0..2 {
                let shift = (ma.fit.clip_from_world.row(r).w - mb.fit.clip_from_world.row(r).w) * s.resolution as f64 / 2.0;
                assert!((shift - shift.round()).abs() < 1e-6, "row {r}: shift {shift} texels");
            }
        }
    }
    // Not applicable to PSM: ignored, and said so.
    let out = fit1(&base, &sun, &scene, &FocusSettings { method: Method::Psm, ..s });
    assert!(out.notes.contains(Notes::STABLE_IGNORED));
}

/// Stable LiSPSM and TSM over a walk (the eye moving forward and turning
/// a little each frame, a low sun from the side): every frame keeps its
/// body and a real warp (no fall-back); with a `FitState` the texel grid
/// changes at most twice over the 10 m walk (the warp's centre re-anchored
/// as the eye walks away from it) and otherwise moves by whole texels, and
/// the warp still gives the ground at the viewer's feet more texels than
/// the stable uniform map does. Without a state the lattices' nearest steps
/// change the grid more often.
#[test]
fn stable_warps_hold_one_grid_over_a_walk() {
    let sun = Light::directional(DVec3::new(1.0, -0.6, 0.2)).unwrap();
    let scene = Aabb::new(DVec3::new(-200.0, 0.0, -300.0), DVec3::new(200.0, 10.0, 100.0)).unwrap();
    let res = 1024;
    let cam = |k: usize| {
        let yaw = 0.004 * k as f64;
        let forward = DVec3::new(yaw.sin(), -0.15, -yaw.cos());
        Camera { eye: DVec3::new(0.0, 1.7, 20.0) + forward * (0.25 * k as f64), forward, ..camera() }
    };
    // World points 10 cm apart on the ground a few metres ahead: their
    // distance in texels.
    let texels_at_feet = |m: &glam::DMat4| {
        let p = |x: f64| {
            let q = *m * glam::DVec4::new(x, 0.0, 15.0, 1.0);
            glam::DVec2::new(q.x, q.y) / q.w * (res as f64 / 2.0)
        };
        (p(0.1) - p(0.0)).length()
    };
    for method in [Method::Lispsm, Method::Tsm] {
        let s = FocusSettings { method, stable: true, resolution: res, ..FocusSettings::default() };
        let uniform = FocusSettings { method: Method::Uniform, ..s };
        let mut changes = [0; 2];
        for (held, changes) in [true, false].into_iter().zip(&mut changes) {
            let mut state = FitState::default();
            let mut prev: Option<glam::DMat4> = None;
            for k in 0..40 {
                let view = PreparedView::new(&cam(k), &s).unwrap();
                let mut out = FocusResult::new();
                if held {
                    fit_prepared_with_state(&view, &sun, &scene, &mut state, &mut out).unwrap();
                } else {
                    fit_prepared(&view, &sun, &scene, &mut out).unwrap();
                }
                let m = &out.maps()[0];
                assert!(
                    m.body().vertices().iter().all(|p| inside_map_f64(&m.fit, *p) && inside_map_f32(&m.fit, *p)),
                    "{method:?} frame {k}: body outside"
                );
                assert!(
                    !m.notes().contains(Notes::STABLE_IGNORED) && !m.notes().contains(Notes::WARP_LIMITED),
                    "{method:?} frame {k}: {:?}",
                    m.notes()
                );
                assert!(m.fit.warp_near.is_finite(), "{method:?} frame {k}: no warp");
                let mm = m.fit.clip_from_world;
                if let Some(p) = prev {
                    // The same grid: the same `w` row, image rows that differ
                    // by a multiple δ of it (δ·res/2 texels).
                    let w = mm.row(3);
                    let delta = |r: usize| {
                        let d = mm.row(r) - p.row(r);
                        let delta = d.truncate().dot(w.truncate()) / w.truncate().length_squared();
                        ((d - w * delta).abs().max_element() <= 1e-9 * mm.row(r).abs().max_element()).then_some(delta)
                    };
                    match (mm.row(3) == p.row(3), delta(0), delta(1)) {
                        (true, Some(dx), Some(dy)) => {
                            for shift in [dx, dy].map(|d| d * res as f64 / 2.0) {
                                assert!((shift - shift.round()).abs() < 1e-6, "{method:?} frame {k}: moved {shift} texels");
                            }
                        }
                        _ => *changes += 1,
                    }
                }
                prev = Some(mm);
                if k % 13 == 0 {
                    let u = fit1(&cam(k), &sun, &scene, &uniform);
                    let (w, un) = (texels_at_feet(&mm), texels_at_feet(&u.maps()[0].fit.clip_from_world));
                    assert!(w > 1.5 * un, "{method:?} frame {k}: {w} texels at the feet against the stable uniform map's {un}");
                }
            }
        }
        eprintln!("{method:?}: grid changes over 40 frames, held {}, stateless {}", changes[0], changes[1]);
        assert!(changes[0] <= 2 && changes[1] > changes[0], "{method:?}: grid changes held/stateless {changes:?}");
    }
}

/// The texel scale `1/S` of a map's image `x` row: its part across the
/// light's axis (the `w` row's direction).
fn image_scale(m: &glam::DMat4) -> f64 {
    let (x, a) = (m.row(0).truncate(), m.row(3).truncate().normalize());
    (x - a * x.dot(a)).length()
}

/// A stable spot map whose body hovers at a boundary of its extent ladder:
/// without a `FitState` its texel grid switches every frame, with one it
/// holds (the looser step keeps the body), and every frame keeps its body.
#[test]
fn fit_state_holds_a_stable_spot_map_at_a_step_boundary() {
    let apex = DVec3::new(0.0, 40.0, 0.0);
    let cone = Camera { eye: apex, forward: DVec3::NEG_Y, up: DVec3::Z, fovy: 1.2, aspect: 1.0, near: 1.0, far: 100.0 };
    let spot = Light::spot(apex, Frustum::from_camera(&cone).unwrap()).unwrap();
    let scene = Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 10.0, 50.0)).unwrap();
    let s = FocusSettings { stable: true, ..FocusSettings::default() };
    let cam = |far: f64| Camera {
        eye: DVec3::new(0.0, 5.0, -30.0),
        forward: DVec3::new(0.0, -0.3, 1.0),
        up: DVec3::Y,
        fovy: 0.8,
        aspect: 1.5,
        near: 0.5,
        far,
    };
    let scale = |far: f64| image_scale(&fit1(&cam(far), &spot, &scene, &s).maps()[0].fit.clip_from_world);
    // Two depth ranges a little apart whose bodies take different steps.
    let far = (0..320).map(|i| 20.0 + 0.25 * i as f64).find(|&f| scale(f) != scale(f + 0.25)).expect("a step boundary in range");
    let frames = [far, far + 0.25, far, far + 0.25, far, far + 0.25];
    let stateless: Vec<f64> = frames.iter().map(|&f| scale(f)).collect();
    assert!(stateless.windows(2).all(|w| w[0] != w[1]), "stateless scales {stateless:?}");
    let mut state = FitState::default();
    let mut held = Vec::new();
    for &f in &frames {
        let mut out = FocusResult::new();
        fit_prepared_with_state(&PreparedView::new(&cam(f), &s).unwrap(), &spot, &scene, &mut state, &mut out).unwrap();
        let m = &out.maps()[0];
        assert!(!m.notes().contains(Notes::STABLE_IGNORED));
        assert!(m.body().vertices().iter().all(|p| inside_map_f64(&m.fit, *p)), "body outside the held map at far {f}");
        held.push(image_scale(&m.fit.clip_from_world));
    }
    assert!(held[1..].windows(2).all(|w| w[0] == w[1]), "held scales {held:?}");
    assert_eq!(held[1], stateless[1], "the held step is the looser one");
}

#[test]
fn empty_body_gives_an_explicit_empty_map() {
    // Scene behind the camera, light travelling from the front toward the
    // camera: the view swept toward the light never reaches the scene.
    let scene = Aabb::new(DVec3::new(-5.0, -5.0, 20.0), DVec3::new(5.0, 5.0, 30.0)).unwrap();
    for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
        let s = FocusSettings { method, splits: SplitSettings { count: 2, ..Default::default() }, ..Default::default() };
        let out = fit1(&camera(), &Light::directional(DVec3::new(0.0, 0.0, 1.0)).unwrap(), &scene, &s);
        assert_eq!(out.maps().len(), 2);
        for m in out.maps() {
            assert_eq!(m.fit.state, MapState::Empty);
            assert_eq!(m.fit.clip_from_world, glam::DMat4::ZERO);
            assert!(m.fit.texel_size.iter().all(|t| *t == f64::INFINITY));
            assert!(m.body().is_empty());
        }
        assert!(out.skipped.contains(Skipped::EMPTY_MAPS));
    }
}

#[test]
fn invalid_input_is_a_typed_error() {
    let good = camera();
    let scene = scene();
    let sun = Light::Directional { direction: DVec3::NEG_Y };
    let s = FocusSettings::default();
    let mut out = FocusResult::new();
    let cams = [
        Camera { eye: DVec3::new(f64::NAN, 0.0, 0.0), ..good },
        Camera { forward: DVec3::ZERO, ..good },
        Camera { near: 5.0, far: 5.0, ..good },
        Camera { fovy: 3.2, ..good },
        Camera { up: DVec3::NEG_Z, ..good },
    ];
    for c in cams {
        assert!(matches!(fit(&c, &sun, &scene, &s, &mut out), Err(FocusError::Geom(_))), "{c:?}");
    }
    for l in [Light::Directional { direction: DVec3::ZERO }, Light::Point { position: DVec3::new(0.0, f64::INFINITY, 0.0) }] {
        assert!(matches!(fit(&good, &l, &scene, &s, &mut out), Err(FocusError::Geom(_))));
    }
    let inverted = Aabb { min: DVec3::ONE, max: DVec3::ZERO };
    assert!(matches!(fit(&good, &sun, &inverted, &s, &mut out), Err(FocusError::Geom(_))));
    for bad in [
        FocusSettings { splits: SplitSettings { count: 0, ..Default::default() }, ..s },
        FocusSettings { splits: SplitSettings { count: MAX_SPLITS + 1, ..Default::default() }, ..s },
        FocusSettings { splits: SplitSettings { scheme: SplitScheme::Practical { lambda: 1.5 }, ..Default::default() }, ..s },
        FocusSettings { splits: SplitSettings { delta_bias: f64::NAN, ..Default::default() }, ..s },
        FocusSettings { resolution: 2, ..s },
        FocusSettings { light_near: LightNear::Fixed(0.0), ..s },
        FocusSettings { light_near: LightNear::Fixed(f64::INFINITY), ..s },
        FocusSettings { light_near: LightNear::Auto { fraction: 0.0 }, ..s },
        FocusSettings { light_near: LightNear::Auto { fraction: 1.0 }, ..s },
        FocusSettings { light_near: LightNear::Auto { fraction: f64::NAN }, ..s },
        FocusSettings { lispsm: LispsmSettings { visible_far: Some(-1.0), ..Default::default() }, ..s },
        FocusSettings { tsm: TsmSettings { focus: 0.0 }, ..s },
        FocusSettings { footprint: Footprint::Receivers { margin_texels: f64::NAN }, ..s },
        FocusSettings { footprint: Footprint::Receivers { margin_texels: -1.0 }, ..s },
        FocusSettings { footprint: Footprint::Receivers { margin_texels: s.resolution as f64 / 8.0 + 1.0 }, ..s },
        FocusSettings { footprint: Footprint::RECEIVERS, stable: true, ..s },
        FocusSettings { visible_depth: Some([2.0, 1.0]), ..s },
        FocusSettings { visible_depth: Some([f64::NAN, 1.0]), ..s },
        FocusSettings { visible_depth: Some([good.far + 1.0, good.far + 2.0]), ..s },
    ] {
        assert!(matches!(fit(&good, &sun, &scene, &bad, &mut out), Err(FocusError::InvalidSettings { .. })), "{bad:?}");
    }
    assert!(out.maps().is_empty());
}

/// A view whose preparation failed gives that error from every fit, and a
/// later preparation with valid input serves fits again.
#[test]
fn prepared_view_keeps_its_error_until_prepared_again() {
    let (good, scene, sun) = (camera(), scene(), Light::Directional { direction: DVec3::NEG_Y });
    let s = FocusSettings { splits: SplitSettings { count: 3, ..Default::default() }, ..Default::default() };
    let mut view = PreparedView::new(&good, &s).unwrap();
    let mut out = FocusResult::new();
    let no_range = FocusSettings { method: Method::Psm, psm: PsmSettings { near: Some(200.0), ..Default::default() }, ..s };
    let bad_camera = Camera { forward: DVec3::ZERO, ..good };
    for (cam, settings) in [(&good, &no_range), (&bad_camera, &s)] {
        let e = view.prepare(cam, settings).unwrap_err();
        assert_eq!(fit(cam, &sun, &scene, settings, &mut out).unwrap_err(), e);
        assert_eq!(fit_prepared(&view, &sun, &scene, &mut out).unwrap_err(), e);
        assert!(out.maps().is_empty() && view.split_depths().is_empty());
    }
    view.prepare(&good, &s).unwrap();
    fit_prepared(&view, &sun, &scene, &mut out).unwrap();
    assert_eq!((out.maps().len(), view.split_depths().len()), (3, 4));
    assert!(out.maps().iter().all(|m| m.is_active()));
}

/// Found by the `fit_case` fuzz target: a point light at the eye of a
/// camera with an absurdly wide aspect (1.3e80). PSM's composed matrix then
/// has a body vertex 2 units from the light at W ≈ 3e-11, below W's own
/// rounding bound, and the crop used to let it fall outside the map. Such a
/// map is now refused (PSM falls back to a uniform map), and every map holds
/// its body.
#[test]
fn maps_hold_bodies_where_w_is_below_its_rounding_bound() {
    let cam = Camera {
        eye: DVec3::new(100000.0, 2.0, 10.0),
        forward: DVec3::X,
        up: DVec3::Z,
        fovy: std::f64::consts::FRAC_PI_2,
        aspect: 1.3333333333333334e80,
        near: 0.02,
        far: 10000.0,
    };
    let scene = Aabb::new(DVec3::new(99000.0, -103.0, -100.0), DVec3::new(101000.0, 100.0, 100.0)).unwrap();
    let light = Light::point(cam.eye).unwrap();
    let mut out = FocusResult::new();
    for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
        for count in [1, 3, 4] {
            for point in [PointMode::Single, PointMode::Cube] {
                let s = FocusSettings { method, point, splits: SplitSettings { count, ..Default::default() }, ..Default::default() };
                fit(&cam, &light, &scene, &s, &mut out).unwrap();
                for m in out.maps().iter().filter(|m| m.is_active()) {
                    for p in m.body().vertices() {
                        assert!(
                            inside_f64(&m.fit.clip_from_world, *p),
                            "{method:?} {count} {point:?}: split {} face {:?} loses {p}",
                            m.split,
                            m.face
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn point_light_modes() {
    let cam = camera();
    let scene = scene();
    // Outside the view, inside the scene, H seen over a cone narrower than
    // a cube face's: one truncated map.
    let l = DVec3::new(-49.0, 1.0, 19.0);
    let out = fit1(&cam, &Light::point(l).unwrap(), &scene, &FocusSettings::default());
    assert_eq!(out.maps().len(), 1);
    assert!(matches!(out.maps()[0].light, Light::Spot { .. }) && out.notes.contains(Notes::LIGHT_NEAR));
    assert!(!out.notes.contains(Notes::POINT_AS_CUBE));
    // Outside the view, inside the scene, H around the light over a cone
    // wider than a cube face's: six faces rather than a map cut so near
    // the light that it would drop points farther than r.
    let l = DVec3::new(30.0, 15.0, 15.0);
    let out = fit1(&cam, &Light::point(l).unwrap(), &scene, &FocusSettings::default());
    assert_eq!(out.maps().len(), 6);
    assert!(out.notes.contains(Notes::POINT_AS_CUBE) && out.notes.contains(Notes::LIGHT_NEAR));
    // Inside the view frustum: six faces.
    let l = DVec3::new(0.0, 2.0, -20.0);
    let out = fit1(&cam, &Light::point(l).unwrap(), &scene, &FocusSettings::default());
    assert_eq!(out.maps().len(), 6);
    assert!(out.notes.contains(Notes::POINT_AS_CUBE));
    // Outside the scene: no truncation.
    let l = DVec3::new(0.0, 60.0, -20.0);
    let out = fit1(&cam, &Light::point(l).unwrap(), &scene, &FocusSettings::default());
    assert_eq!(out.maps().len(), 1);
    assert!(matches!(out.maps()[0].light, Light::Point { .. }) && !out.notes.contains(Notes::LIGHT_NEAR));
}

#[test]
fn culling_drops_far_casters_and_keeps_shadowing_ones() {
    let cam = camera();
    let scene = Aabb::new(DVec3::new(-200.0, 0.0, -200.0), DVec3::new(200.0, 20.0, 200.0)).unwrap();
    let mut casters = Vec::new();
    for i in -20..20 {
        for j in -20..20 {
            let c = DVec3::new(i as f64 * 10.0 + 5.0, 0.0, j as f64 * 10.0 + 5.0);
            casters.push(Aabb::new(c - DVec3::new(1.0, 0.0, 1.0), c + DVec3::new(1.0, 4.0, 1.0)).unwrap());
        }
    }
    for light in [Light::directional(DVec3::new(0.4, -1.0, 0.3)).unwrap(), Light::point(DVec3::new(20.0, 18.0, -30.0)).unwrap()] {
        for count in [1, 4] {
            let s = FocusSettings { splits: SplitSettings { count, ..Default::default() }, ..Default::default() };
            let out = fit1(&cam, &light, &scene, &s);
            let mut idx = vec![0u32; casters.len()];
            let mut kept_total = 0;
            for m in out.maps().iter().filter(|m| m.is_active()) {
                let n = cull_casters(m, &casters, &mut idx).unwrap();
                kept_total += n;
                // Every caster meeting H (a vertex inside the box, or the box
                // holding a body point) is kept.
                for (k, b) in casters.iter().enumerate() {
                    if body_points(m.body(), 20, k as u64 + 1).iter().any(|p| b.contains(*p)) {
                        assert!(idx[..n].contains(&(k as u32)), "caster {k} meets H but was culled");
                    }
                }
            }
            let maps = out.maps().iter().filter(|m| m.is_active()).count();
            eprintln!("{:?} splits {count}: {} of {} caster-map pairs kept", light_kind(&light), kept_total, maps * casters.len());
            assert!(kept_total < maps * casters.len() / 2, "culling kept {kept_total}");
            assert!(kept_total > 0);
        }
    }
}

fn light_kind(l: &Light) -> &'static str {
    match l {
        Light::Directional { .. } => "directional",
        Light::Point { .. } => "point",
        Light::Spot { .. } => "spot",
    }
}

#[test]
fn corners_form_reproduces_the_camera_fit() {
    let cam = Camera {
        eye: DVec3::new(1.5, 3.0, 7.0),
        forward: DVec3::new(0.2, -0.3, -1.0),
        up: DVec3::Y,
        fovy: 0.8,
        aspect: 1.3,
        near: 0.4,
        far: 90.0,
    };
    let rec = camera_from_corners(&cam.corners().unwrap()).unwrap();
    assert!(rec.residual < 1e-12);
    let sun = Light::directional(DVec3::new(0.4, -1.0, 0.2)).unwrap();
    let s = FocusSettings { method: Method::Lispsm, splits: SplitSettings { count: 3, ..Default::default() }, ..Default::default() };
    let (a, b) = (fit1(&cam, &sun, &scene(), &s), fit1(&rec.camera, &sun, &scene(), &s));
    for (x, y) in a.split_depths().iter().zip(b.split_depths()) {
        assert!((x - y).abs() < 1e-9 * y.abs());
    }
    for (x, y) in a.maps().iter().zip(b.maps()) {
        assert!(x.fit.clip_from_world.abs_diff_eq(y.fit.clip_from_world, 1e-6), "{} vs {}", x.fit.clip_from_world, y.fit.clip_from_world);
    }
    // A spot light whose frustum is the view itself: L ⊇ V.
    let spot = Light::spot(
        cam.eye + DVec3::new(0.0, 0.0, 0.0),
        Frustum::from_camera(&Camera { near: 0.1, far: 200.0, fovy: 1.2, ..cam }).unwrap(),
    )
    .unwrap();
    let out = fit1(&cam, &spot, &scene(), &FocusSettings::default());
    assert!(out.maps().iter().all(|m| m.is_active()));
}

/// Directions far above and below unit length (|d|² overflows or
/// underflows): the same light. With exact power-of-two multiples the maps
/// are those of the unit direction bit for bit; with 1e±300 multiples every
/// map holds its body, the depth test is the unit direction's and culling
/// keeps the casters the unit direction's maps keep.
#[test]
fn long_and_short_light_directions_fit_like_unit_ones() {
    let (cam, scene) = (camera(), scene());
    let d = DVec3::new(0.3, -1.0, 0.2);
    let casters: Vec<Aabb> = (0..40)
        .map(|k| {
            let c = DVec3::new((k % 8) as f64 * 12.0 - 45.0, (k / 8) as f64 * 4.0, -(k as f64) * 2.4);
            Aabb::new(c - DVec3::splat(1.5), c + DVec3::splat(1.5)).unwrap()
        })
        .collect();
    let mut idx = vec![0u32; casters.len()];
    let settings = [
        FocusSettings::default(),
        FocusSettings { stable: true, splits: SplitSettings { count: 4, scheme: PRACTICAL, ..Default::default() }, ..Default::default() },
        psm(),
        lispsm(None),
        FocusSettings { method: Method::Tsm, splits: SplitSettings { count: 4, ..Default::default() }, ..Default::default() },
    ];
    for s in &settings {
        let unit = fit1(&cam, &Light::directional(d).unwrap(), &scene, s);
        let kept = |out: &FocusResult, idx: &mut [u32]| -> Vec<Vec<u32>> {
            out.maps()
                .iter()
                .filter(|m| m.is_active())
                .map(|m| {
                    let n = cull_casters(m, &casters, idx).unwrap();
                    idx[..n].to_vec()
                })
                .collect()
        };
        let unit_kept = kept(&unit, &mut idx);
        assert!(unit_kept.iter().any(|k| !k.is_empty()));
        // Exponents that keep every component a normal number (exact).
        for e in [-1000, -600, 600, 1000] {
            let dk = d * 2f64.powi(e / 2) * 2f64.powi(e - e / 2);
            let out = fit1(&cam, &Light::directional(dk).unwrap(), &scene, s);
            assert_eq!(out.notes, unit.notes, "2^{e} {:?}", s.method);
            for (a, b) in out.maps().iter().zip(unit.maps()) {
                assert_eq!(a.fit.clip_from_world, b.fit.clip_from_world, "2^{e} {:?}", s.method);
                assert_eq!(a.fit.depth_test, b.fit.depth_test);
            }
        }
        for k in [1e300, 1e-300] {
            let out = fit1(&cam, &Light::directional(d * k).unwrap(), &scene, s);
            assert_eq!(out.maps().len(), unit.maps().len());
            for (a, b) in out.maps().iter().zip(unit.maps()) {
                assert!(a.fit.clip_from_world.is_finite() && a.fit.clip_from_world.determinant() != 0.0, "{k:e} {:?}", s.method);
                assert_eq!(a.fit.depth_test, b.fit.depth_test, "{k:e} {:?}", s.method);
            }
            assert_eq!(out.notes.contains(Notes::INVERTED), unit.notes.contains(Notes::INVERTED));
            assert_eq!(kept(&out, &mut idx), unit_kept, "{k:e} {:?}", s.method);
        }
    }
}

/// `cull_casters` with an output shorter than the casters is a typed error
/// (checked before any work), never an out-of-bounds panic.
#[test]
fn cull_casters_refuses_a_short_output() {
    let out = fit1(&camera(), &Light::directional(DVec3::new(0.4, -1.0, 0.3)).unwrap(), &scene(), &FocusSettings::default());
    let m = &out.maps()[0];
    let casters = [Aabb::new(DVec3::new(-1.0, 0.0, -5.0), DVec3::new(1.0, 3.0, -3.0)).unwrap(); 3];
    for len in [0, 1, 2] {
        let mut idx = vec![0u32; len];
        assert!(matches!(cull_casters(m, &casters, &mut idx), Err(FocusError::Capacity { .. })), "{len}");
    }
    let mut idx = [0u32; 3];
    assert_eq!(cull_casters(m, &casters, &mut idx), Ok(3));
    assert_eq!(idx, [0, 1, 2]);
    assert_eq!(cull_casters(m, &[], &mut []), Ok(0));
}

/// `predict_aliasing` against the closed form: a camera `h` above a floor
/// looking straight down, a uniform sun map from straight above. Under the
/// image centre the floor is `h` away and faces the camera, so a pixel
/// covers `2h·tan(fovy/2)/H` of it per side and a texel `2/(|x row|·T)` by
/// `2/(|y row|·T)`; everywhere else the floor is farther and oblique, so the
/// centre is the maximum and the nearest sample.
#[test]
fn predicted_aliasing_matches_the_closed_form_over_a_floor() {
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -50.0), DVec3::new(50.0, 10.0, 50.0)).unwrap();
    for (h, fovy) in [(5.0, 1.0), (2.5, 0.4), (9.0, 1.3)] {
        let cam = Camera { eye: DVec3::new(1.0, h, -2.0), forward: DVec3::NEG_Y, up: DVec3::Z, fovy, aspect: 1.0, near: 0.1, far: 100.0 };
        let s = FocusSettings { method: Method::Uniform, ..FocusSettings::default() };
        let out = fit1(&cam, &Light::directional(DVec3::NEG_Y).unwrap(), &scene, &s);
        let map = &out.maps()[0];
        let m = map.fit.clip_from_world;
        assert_eq!(m.row(3), glam::DVec4::W, "an orthographic map");
        let (size, texels) = (720.0, 1024.0);
        let texel = (4.0 / (m.row(0).truncate().length() * m.row(1).truncate().length())).sqrt() / texels;
        let pixel = 2.0 * h * (0.5 * fovy).tan() / size;
        let p = predict_aliasing(map, &cam, &scene, &ReceiverBoxes::NONE, None).unwrap().in_pixels(size, size, texels);
        let want = texel / pixel;
        assert!((p.max / want - 1.0).abs() < 1e-9, "h {h}: predicted {p:?}, closed form {want}");
        assert_eq!((p.near, p.depths[0]), (p.max, h));
        // A map with nothing to render predicts nothing.
        let mut empty = FocusResult::new();
        let away = Camera { eye: DVec3::new(0.0, 50.0, 0.0), forward: DVec3::Y, up: DVec3::Z, ..cam };
        fit(&away, &Light::directional(DVec3::NEG_Y).unwrap(), &scene, &s, &mut empty).unwrap();
        assert!(
            !empty.maps().is_empty()
                && empty.maps().iter().all(|m| !m.is_active() && predict_aliasing(m, &away, &scene, &ReceiverBoxes::NONE, None).is_none())
        );
    }
}

/// With receiver boxes the prediction's receivers are on them: a ground slab
/// whose top is 2 below the camera, in a scene box whose floor is lower. The
/// closed form (as above) holds at the slab's top with its boxes, at the
/// box's floor without; a ray that meets no box (into the sky) has no
/// receiver, and boxes the camera stands in are seen from inside.
#[test]
fn predicted_aliasing_takes_receivers_on_their_boxes() {
    let scene = Aabb::new(DVec3::new(-50.0, -6.0, -50.0), DVec3::new(50.0, 10.0, 50.0)).unwrap();
    let slab = Aabb::new(DVec3::new(-50.0, -6.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
    let h = 2.0;
    let cam = Camera { eye: DVec3::new(1.0, h, -2.0), forward: DVec3::NEG_Y, up: DVec3::Z, fovy: 0.8, aspect: 1.0, near: 0.1, far: 100.0 };
    let s = FocusSettings { method: Method::Uniform, ..FocusSettings::default() };
    let out = fit1(&cam, &Light::directional(DVec3::NEG_Y).unwrap(), &scene, &s);
    let map = &out.maps()[0];
    let m = map.fit.clip_from_world;
    let (size, texels) = (720.0, 1024.0);
    let texel = (4.0 / (m.row(0).truncate().length() * m.row(1).truncate().length())).sqrt() / texels;
    let closed_form = |distance: f64| texel / (2.0 * distance * (0.5 * cam.fovy).tan() / size);
    for (boxes, distance) in [(&[slab][..], h), (&[][..], h + 6.0), (&[slab, scene][..], h)] {
        let p = predict_aliasing(map, &cam, &scene, &ReceiverBoxes::new(boxes).unwrap(), None).unwrap().in_pixels(size, size, texels);
        assert!((p.max / closed_form(distance) - 1.0).abs() < 1e-9, "{boxes:?}: predicted {p:?}, closed form {}", closed_form(distance));
        assert_eq!(p.depths[0], distance);
    }
    // Looking up at a roof box lit from below: its underside at 8 − h; a
    // ray that meets no box has no receiver.
    let up = Camera { forward: DVec3::Y, ..cam };
    let roof = Aabb::new(DVec3::new(-50.0, 8.0, -50.0), DVec3::new(50.0, 9.0, 50.0)).unwrap();
    let aside = Aabb::new(DVec3::new(40.0, 8.0, 40.0), DVec3::new(50.0, 9.0, 50.0)).unwrap();
    let below = Light::directional(DVec3::Y).unwrap();
    let o = fit1(&up, &below, &scene, &s);
    assert_eq!(predict_aliasing(&o.maps()[0], &up, &scene, &ReceiverBoxes::new(&[roof]).unwrap(), None).unwrap().depths[0], 8.0 - h);
    assert_eq!(predict_aliasing(&o.maps()[0], &up, &scene, &ReceiverBoxes::new(&[aside]).unwrap(), None), None);
    let room = Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 9.0, 50.0)).unwrap();
    let p = predict_aliasing(map, &cam, &scene, &ReceiverBoxes::new(&[room]).unwrap(), None).unwrap();
    assert_eq!(p.depths[0], h + 1.0);
    // Boxes of seen points: the receiver where a ray leaves the last one,
    // the farthest a seen point on it can be (the slab's underside; below
    // two thin boxes, the lower's).
    let seen = |b: &[Aabb]| predict_aliasing(map, &cam, &scene, &ReceiverBoxes::seen(b).unwrap(), None).unwrap().depths[0];
    let (top, low) = (
        Aabb::new(DVec3::new(-50.0, -1.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap(),
        Aabb::new(DVec3::new(-50.0, -3.0, -50.0), DVec3::new(50.0, -2.0, 50.0)).unwrap(),
    );
    assert_eq!(seen(&[slab]), h + 6.0);
    assert_eq!(seen(&[top, low]), h + 3.0);
    assert_eq!(seen(&[low, top]), h + 3.0);
    // Bad boxes are refused with the setting named.
    let bad = Aabb { min: DVec3::ONE, max: DVec3::ZERO };
    assert!(matches!(ReceiverBoxes::new(&[slab, bad]), Err(FocusError::InvalidSettings { what: "receivers", .. })));
}

/// With the scene box's ground named, the prediction's receivers are on it
/// alone. A camera 10 m above a city's 1200 m box, seeing 1000 m, the sun
/// 35° up behind it: without a ground, the box's side wall 630 m out, lit at
/// 86°, stands for receivers and sets the far splits' prediction (and the
/// optimal planes by it); on the ground, a ray past the box's edge meets
/// nothing, and the far split's prediction is the ground's, many times
/// lower. The same camera over a floor with nothing beyond (a room) predicts
/// the same either way, but for the ground's edge; and from below the
/// ground, a camera sees none of it.
#[test]
fn a_ground_takes_the_walls_out_of_the_prediction() {
    let scene = Aabb::new(DVec3::new(-600.0, 0.0, -600.0), DVec3::new(600.0, 80.0, 600.0)).unwrap();
    let cam = Camera {
        eye: DVec3::new(-20.0, 10.0, -590.0),
        forward: DVec3::new(0.08, -0.04, 1.0),
        up: DVec3::Y,
        fovy: 60f64.to_radians(),
        aspect: 16.0 / 9.0,
        near: 0.1,
        far: 1000.0,
    };
    let sun = Light::directional(DVec3::new(0.0653, -0.5736, 0.8165)).unwrap();
    let s =
        FocusSettings { method: Method::Auto, splits: SplitSettings { count: 4, ..SplitSettings::default() }, ..FocusSettings::default() };
    let out = fit1(&cam, &sun, &scene, &s);
    let far = out.maps().last().unwrap();
    let walls = predict_aliasing(far, &cam, &scene, &ReceiverBoxes::NONE, None).unwrap();
    let ground = predict_aliasing(far, &cam, &scene, &ReceiverBoxes::NONE, Some(BoxFace::MinY.into())).unwrap();
    assert!(walls.max > 8.0 * ground.max, "far split: walls {walls:?}, ground {ground:?}");
    // The optimal planes follow: the first split ends nearer on the ground
    // (measured: 36 m against 44 m).
    let on_ground = fit1(&cam, &sun, &scene, &FocusSettings { ground: Some(BoxFace::MinY.into()), ..s });
    let (first, first_ground) = (out.split_depths()[1], on_ground.split_depths()[1]);
    assert!(first_ground < 0.9 * first, "first split ends at {first_ground} on the ground, {first} without");
    // Looking straight down at the floor of a room, far from its walls:
    // the ground is all the box's faces the rays meet.
    let down = Camera { eye: DVec3::new(0.0, 20.0, 0.0), forward: DVec3::NEG_Y, up: DVec3::Z, fovy: 0.5, ..cam };
    let o = fit1(&down, &Light::directional(DVec3::new(0.2, -1.0, 0.1)).unwrap(), &scene, &FocusSettings::default());
    let (a, b) = (
        predict_aliasing(&o.maps()[0], &down, &scene, &ReceiverBoxes::NONE, None).unwrap(),
        predict_aliasing(&o.maps()[0], &down, &scene, &ReceiverBoxes::NONE, Some(BoxFace::MinY.into())).unwrap(),
    );
    let close = |x: f64, y: f64| (x / y - 1.0).abs() < 1e-12;
    assert!(close(a.max, b.max) && close(a.depths[0], b.depths[0]) && close(a.depths[1], b.depths[1]), "{a:?} {b:?}");
    // From under the ground's plane, or with the box's top as the ground
    // seen from above it: nothing.
    let under = Camera { eye: DVec3::new(0.0, -5.0, 0.0), forward: DVec3::new(0.0, 0.3, 1.0), ..cam };
    let u = fit1(&under, &sun, &scene, &FocusSettings::default());
    assert!(u.maps().iter().all(|m| predict_aliasing(m, &under, &scene, &ReceiverBoxes::NONE, Some(BoxFace::MinY.into())).is_none()));
    let above = Camera { eye: DVec3::new(0.0, 200.0, 0.0), forward: DVec3::new(0.0, -1.0, 1.0), ..cam };
    let a = fit1(&above, &sun, &scene, &FocusSettings::default());
    assert!(a.maps().iter().all(|m| predict_aliasing(m, &above, &scene, &ReceiverBoxes::NONE, Some(BoxFace::MaxY.into())).is_none()));
}

/// A world on a slab: the scene box reaches 2 m below the slab's top, where
/// the receivers are. On the box's floor the prediction sees a ground 2 m
/// too low (for an eye 1.7 m up, more than twice as far below it); at the
/// slab's level it predicts what a receiver box around the slab does. A
/// level at the face is the face, bit for bit; one outside the box is
/// refused.
#[test]
fn a_ground_level_stands_for_a_slab_top() {
    let scene = Aabb::new(DVec3::new(-200.0, -2.0, -200.0), DVec3::new(200.0, 8.0, 200.0)).unwrap();
    let slab = [Aabb::new(DVec3::new(-200.0, -2.0, -200.0), DVec3::new(200.0, 0.0, 200.0)).unwrap()];
    let cam = Camera {
        eye: DVec3::new(0.0, 1.7, -150.0),
        forward: DVec3::new(0.0, -0.12, 1.0),
        up: DVec3::Y,
        fovy: 60f64.to_radians(),
        aspect: 16.0 / 9.0,
        near: 0.1,
        far: 250.0,
    };
    let sun = Light::directional(DVec3::new(0.1, -0.17, 0.98)).unwrap();
    let s =
        FocusSettings { method: Method::Auto, splits: SplitSettings { count: 4, ..SplitSettings::default() }, ..FocusSettings::default() };
    let out = fit1(&cam, &sun, &scene, &s);
    let (level, face) = (Ground::at(BoxFace::MinY, 0.0), Ground::face(BoxFace::MinY));
    for m in out.maps() {
        let on_box = predict_aliasing(m, &cam, &scene, &ReceiverBoxes::new(&slab).unwrap(), None).unwrap();
        let on_level = predict_aliasing(m, &cam, &scene, &ReceiverBoxes::NONE, Some(level)).unwrap();
        let on_face = predict_aliasing(m, &cam, &scene, &ReceiverBoxes::NONE, Some(face)).unwrap();
        // Measured: 6.05, 1.89, 1.89, 1.91 on the box and the level; 2.78,
        // 2.79, 2.79, 2.79 on the floor.
        let what = format!("split {}: box {on_box:?}, level {on_level:?}, face {on_face:?}", m.split);
        assert!((on_level.max / on_box.max - 1.0).abs() < 0.005, "{what}");
        assert!((on_face.max / on_box.max - 1.0).abs() > 0.25, "{what}");
    }
    let at_face = FocusSettings { ground: Some(Ground::at(BoxFace::MinY, -2.0)), ..s };
    let (a, b) = (fit1(&cam, &sun, &scene, &at_face), fit1(&cam, &sun, &scene, &FocusSettings { ground: Some(face), ..s }));
    assert!(a.maps().iter().zip(b.maps()).all(|(a, b)| a.fit.clip_from_world == b.fit.clip_from_world));
    let mut o = FocusResult::new();
    for l in [8.5, -2.5] {
        let e = fit(&cam, &sun, &scene, &FocusSettings { ground: Some(Ground::at(BoxFace::MinY, l)), ..s }, &mut o).unwrap_err();
        assert!(e.to_string().contains("ground.level: must lie in the scene box"), "{e}");
    }
}

/// A texel budget sizes the maps by their predicted aliasing: over a sweep
/// of suns, with the practical planes (whose splits are uneven) and the
/// optimal ones, the worst predicted screen pixels per texel
/// (`e / resolution`) is never above the equal maps' for the same texels,
/// the budget holds, and the sizes differ where the predictions do.
#[test]
fn a_texel_budget_evens_the_predicted_aliasing() {
    let (cam, scene) = (camera(), scene());
    let worst = |out: &FocusResult, boxes: &[Aabb]| {
        let mut worst = 0.0f64;
        for m in out.maps().iter().filter(|m| m.is_active()) {
            if let Some(p) = predict_aliasing(m, &cam, &scene, &ReceiverBoxes::new(boxes).unwrap(), None) {
                worst = worst.max(p.max / m.fit.resolution as f64);
            }
        }
        worst
    };
    let ground = [Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 0.5, 20.0)).unwrap()];
    let (mut uneven, mut cases) = (0, 0);
    for scheme in [PRACTICAL, SplitScheme::Optimal] {
        for boxes in [&[][..], &ground[..]] {
            for k in 0..12 {
                let a = k as f64 * 0.52;
                let light = Light::directional(DVec3::new(a.cos(), -0.3 - 0.2 * (k % 3) as f64, a.sin())).unwrap();
                let equal = FocusSettings {
                    method: Method::Lispsm,
                    resolution: 512,
                    splits: SplitSettings { count: 4, scheme, ..Default::default() },
                    receivers: ReceiverBoxes::new(boxes).unwrap(),
                    ..FocusSettings::default()
                };
                let texels = 4 * 512 * 512;
                let shared = FocusSettings { resolution: 1024, texel_budget: Some(TexelBudget { texels, sizes: MapSizes::Any }), ..equal };
                let (a, b) = (fit1(&cam, &light, &scene, &equal), fit1(&cam, &light, &scene, &shared));
                let sides: Vec<u64> = b.maps().iter().filter(|m| m.is_active()).map(|m| u64::from(m.fit.resolution)).collect();
                assert!(sides.iter().map(|s| s * s).sum::<u64>() <= texels, "{sides:?}");
                let (wa, wb) = (worst(&a, boxes), worst(&b, boxes));
                assert!(wb <= wa * (1.0 + 1e-9), "{scheme:?}, light {k}: worst {wa} → {wb} with sides {sides:?}");
                uneven += usize::from(sides.iter().any(|&s| s != sides[0]));
                cases += 1;
            }
        }
    }
    assert!(uneven * 4 >= cases * 3, "the sizes differ in only {uneven} of {cases} fits");
}

/// A sun in the camera's vertical plane, its direction rounded a hair to
/// either side (as a sweep's cos/sin leave it): the scene box's side walls
/// are then lit by 10⁻¹⁷ or not at all. The predicted aliasing on such
/// grazed receivers fades out with their light instead of growing without
/// bound, so the fits (Auto's choice, the optimal planes, a budget's sizes)
/// are the same whichever side rounding falls on, and every prediction
/// stays within a few times the unrounded one.
#[test]
fn a_sun_in_the_cameras_vertical_plane_fits_the_same_either_side() {
    let scene = Aabb::new(DVec3::new(-150.0, 0.0, -150.0), DVec3::new(150.0, 14.0, 150.0)).unwrap();
    let cam = Camera {
        eye: DVec3::new(0.0, 9.0, -125.0),
        forward: DVec3::new(0.0, -0.15, 1.0),
        up: DVec3::Y,
        fovy: 60f64.to_radians(),
        aspect: 16.0 / 9.0,
        near: 0.5,
        far: 250.0,
    };
    let s = FocusSettings {
        method: Method::Auto,
        resolution: 1024,
        splits: SplitSettings { count: 4, ..Default::default() },
        texel_budget: Some(TexelBudget { texels: 4 * 512 * 512, sizes: MapSizes::Any }),
        ..FocusSettings::default()
    };
    for (y, z) in [(-0.906_307_787_036_649_9, -0.422_618_261_740_699_44), (-0.5, 1.0), (-0.17, -1.0)] {
        let fitted = |x: f64| fit1(&cam, &Light::directional(DVec3::new(x, y, z)).unwrap(), &scene, &s);
        let base = fitted(0.0);
        let worst = |out: &FocusResult| {
            out.maps()
                .iter()
                .filter_map(|m| predict_aliasing(m, &cam, &scene, &ReceiverBoxes::NONE, None))
                .map(|p| p.max)
                .fold(0.0, f64::max)
        };
        for x in [-5.175_581_015_019_659e-17, 5e-17, -1e-13, 1e-13] {
            let out = fitted(x);
            for (a, b) in base.split_depths().iter().zip(out.split_depths()) {
                assert!((a - b).abs() <= 1e-6 * a.abs().max(1.0), "x {x}: planes {:?} → {:?}", base.split_depths(), out.split_depths());
            }
            let sides = |o: &FocusResult| o.maps().iter().map(|m| m.fit.resolution).collect::<Vec<_>>();
            assert_eq!(sides(&base), sides(&out), "x {x}: sizes");
            let (wa, wb) = (worst(&base), worst(&out));
            assert!(wb.is_finite() && wb <= 1.01 * wa && wa <= 1.01 * wb, "x {x}: worst predicted {wa} → {wb}");
        }
    }
}

/// Over a sweep of suns, Auto sometimes takes LiSPSM with its warp swept
/// stronger than `n_opt` (at most 2⁴ times); a weaker LiSPSM map is only
/// ever the warp guard's (`n_opt` weakened by whole octaves); and a swept
/// map holds its body like any other (`fit1`). The camera looks down on a
/// floor, so the samples lie on it and the sweep has receivers to judge by.
#[test]
fn auto_sweeps_the_lispsm_warp_only_stronger() {
    let cam = Camera { eye: DVec3::new(0.0, 3.0, 10.0), forward: DVec3::new(0.0, -0.3, -1.0), ..camera() };
    let free = |method| FocusSettings { method, warp_guard: false, ..FocusSettings::default() };
    let (auto, lispsm) = (FocusSettings { method: Method::Auto, ..FocusSettings::default() }, free(Method::Lispsm));
    let mut swept = 0;
    for k in 0..72 {
        let (az, el) = (f64::from(k % 12) * 30f64.to_radians(), [15.0f64, 40.0, 70.0, 85.0, 25.0, 55.0][k as usize / 12].to_radians());
        let light = Light::directional(DVec3::new(az.sin() * el.cos(), -el.sin(), az.cos() * el.cos())).unwrap();
        let (a, l) = (fit1(&cam, &light, &scene(), &auto), fit1(&cam, &light, &scene(), &lispsm));
        let (a, n_opt) = (&a.maps()[0].fit, l.maps()[0].fit.warp_near);
        if a.method == Method::Lispsm && a.warp_near < n_opt {
            assert!(a.warp_near >= n_opt / 16.0 * (1.0 - 1e-12), "az {az} el {el}: n {} below n_opt {n_opt} / 2⁴", a.warp_near);
            swept += 1;
        } else if a.method == Method::Lispsm && a.warp_near.is_finite() {
            // The warp guard's: n_opt weakened by whole octaves.
            let octaves = (a.warp_near / n_opt).log2();
            assert!(
                octaves >= 0.0 && (octaves - octaves.round()).abs() < 1e-9,
                "az {az} el {el}: n {} is n_opt {n_opt}·2^{octaves}",
                a.warp_near
            );
        }
    }
    assert!(swept > 0, "no sun gave a swept warp");
}
