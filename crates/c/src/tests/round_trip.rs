//! Through the C ABI, the library's results, bit for bit.

use super::common::*;
use crate::*;
use shadowfocus_focus::{
    caster_planes, cull_casters, fit, fit_prepared_with_state, BoxFace, ClipConvention, CubeFace, DepthHintCoverage, DepthRange, DepthTest,
    FitState, FocusResult, FocusSettings, Footprint, Ground, MapSizes, Method, PointMode, PreparedView, ReceiverBoxes, ShadowMap,
    SplitScheme, TexelBudget, UvOrigin,
};
use shadowfocus_geom::{Aabb, Body, Focuser, Frustum};
use std::ffi::c_int;
use std::ptr;

const METHODS: [SfMethod; 5] =
    [SfMethod::SF_METHOD_UNIFORM, SfMethod::SF_METHOD_PSM, SfMethod::SF_METHOD_LISPSM, SfMethod::SF_METHOD_TSM, SfMethod::SF_METHOD_AUTO];

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|x| x.to_bits()).collect()
}

fn bits32(a: &[f32]) -> Vec<u32> {
    a.iter().map(|x| x.to_bits()).collect()
}

/// Every field of `c` is the Rust map's, bit for bit.
fn assert_same(c: &SfMap, r: &ShadowMap, what: &str) {
    assert_eq!(c.active != 0, r.is_active(), "{what}: active");
    assert_eq!(c.depth_greater != 0, r.fit.depth_test == DepthTest::Greater, "{what}: depth test");
    assert_eq!(bits(&c.split), bits(&r.split_range), "{what}: split range");
    assert_eq!(bits(&c.clip_from_world), bits(&r.fit.clip_from_world.to_cols_array()), "{what}: clip_from_world");
    assert_eq!(bits32(&c.clip_from_world_f32), bits32(&r.fit.clip_from_world_f32.to_cols_array()), "{what}: clip_from_world_f32");
    assert_eq!(bits(&c.uv_from_world), bits(&r.fit.uv_from_world().to_cols_array()), "{what}: uv_from_world");
    assert_eq!(bits32(&c.uv_from_world_f32), bits32(&r.fit.uv_from_world_f32().to_cols_array()), "{what}: uv_from_world_f32");
    assert_eq!(bits(&c.light_view), bits(&r.light_view().to_cols_array()), "{what}: light_view");
    assert_eq!(bits(&c.light_projection), bits(&r.light_projection().to_cols_array()), "{what}: light_projection");
    assert_eq!(c.inverted != 0, r.fit.inverted(), "{what}: inverted");
    assert_eq!(bits(&c.texel_size), bits(&r.fit.texel_size), "{what}: texel size");
    let method = [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm, Method::Auto][c.method as usize];
    assert!(c.active == 0 || method != Method::Auto, "{what}: an active map's method is the one chosen");
    assert_eq!(method, r.fit.method, "{what}: method");
    assert_eq!(c.split_index as usize, r.split, "{what}: split index");
    let face = usize::try_from(c.cube_face).ok().map(|i| CubeFace::ALL[i]);
    assert_eq!(face, r.face, "{what}: cube face");
    assert_eq!(c.f32_exact != 0, r.fit.f32_exact, "{what}: f32_exact");
    assert_eq!(bits(&[c.warp_near, c.psm_shift, c.light_near]), bits(&[r.fit.warp_near, r.fit.psm_shift, r.light_near]), "{what}: scalars");
    assert_eq!((c.notes, c.skipped), (r.notes().0, r.skipped().0), "{what}: notes and skipped");
    assert_eq!(c.body_vertex_count as usize, r.body().vertices().len(), "{what}: body size");
    assert_eq!(c.depth_clamp != 0, r.fit.depth_clamp, "{what}: depth clamp");
    assert_eq!(c.receiver_footprint != 0, r.fit.footprint != Footprint::Body, "{what}: receiver footprint");
    assert_eq!(c.resolution, r.fit.resolution, "{what}: resolution");
}

/// Every combination of the four clip fields (half of them with depth
/// clamping, half with receiver-fitted images, 3 texels of margin) gives
/// the maps of `fit` with those settings, bit for bit.
#[test]
fn every_clip_convention_gives_the_maps_of_fit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let (mut greater, mut clamped, mut fitted) = (0, 0, 0);
    for bits4 in 0..16 {
        let flag = |b: u32| c_int::from(bits4 & (1 << b) != 0);
        let clip = ClipConvention {
            depth: if flag(0) != 0 { DepthRange::ZeroToOne } else { DepthRange::MinusOneToOne },
            reversed_z: flag(1) != 0,
            uv_origin: if flag(2) != 0 { UvOrigin::TopLeft } else { UvOrigin::BottomLeft },
            y_down: flag(3) != 0,
        };
        for method in METHODS {
            let mut s = settings(method, 4);
            (s.depth_zero_to_one, s.reversed_z, s.uv_origin_top_left, s.clip_y_down) = (flag(0), flag(1), flag(2), flag(3));
            // Half of the conventions also with the depth range fitted to the receivers.
            s.depth_clamp = c_int::from(bits4 % 2 == 1);
            let receivers = bits4 % 4 >= 2;
            (s.receiver_footprint, s.receiver_margin_texels) = (c_int::from(receivers), 3.0);
            let footprint = if receivers { Footprint::Receivers { margin_texels: 3.0 } } else { Footprint::Body };
            let rs = FocusSettings { clip, depth_clamp: bits4 % 2 == 1, footprint, ..rust_settings(method, 4) };
            for light in lights() {
                let what = format!("{clip:?}, {method:?}, light kind {}", light.kind);
                fit(&rust_camera(&camera(37)), &rust_light(&light), &rust_scene(), &rs, &mut out).unwrap();
                let (rc, n) = ctx.fit(&camera(37), &light, &scene(), &s, &mut maps);
                assert_eq!((rc, n), (0, out.maps().len()), "{what}: {}", ctx.error());
                for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                    assert_same(c, r, &format!("{what}, map {i}"));
                    greater += usize::from(c.active != 0 && c.depth_greater != 0);
                    clamped += usize::from(c.depth_clamp != 0);
                    fitted += usize::from(c.receiver_footprint != 0);
                }
            }
        }
    }
    assert!(greater > 0, "reversed-Z gave no map the greater test");
    assert!(clamped > 0, "no map was fitted for depth clamping");
    assert!(fitted > 0, "no map was fitted to its receivers");
}

/// sf_fit against fit for every method, 1 and 4 splits, each light kind,
/// point lights also as cubes, over a few camera poses.
#[test]
fn sf_fit_gives_the_maps_of_fit_bit_for_bit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let (mut compared, mut active, mut cube) = (0, 0, 0);
    for k in [0, 37, 120, 299] {
        let cam = camera(k);
        for method in METHODS {
            for splits in [1, 4] {
                for light in lights() {
                    for point_mode in [SfPointMode::SF_POINT_SINGLE, SfPointMode::SF_POINT_CUBE] {
                        if point_mode == SfPointMode::SF_POINT_CUBE && light.kind != SfLightKind::SF_LIGHT_POINT as c_int {
                            continue;
                        }
                        let mut s = settings(method, splits);
                        s.point_mode = point_mode as c_int;
                        let mut rs = rust_settings(method, splits);
                        rs.point = [PointMode::Single, PointMode::Cube][point_mode as usize];
                        let what = format!("frame {k}, {method:?}, {splits} splits, light kind {}, {point_mode:?}", light.kind);
                        fit(&rust_camera(&cam), &rust_light(&light), &rust_scene(), &rs, &mut out).unwrap();
                        let (rc, n) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
                        assert_eq!(rc, 0, "{what}: {}", ctx.error());
                        assert_eq!(ctx.error(), "");
                        assert_eq!(n, out.maps().len(), "{what}");
                        for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                            assert_same(c, r, &format!("{what}, map {i}"));
                            let want: Vec<[f64; 3]> = r.body().vertices().iter().map(|v| v.to_array()).collect();
                            assert_eq!(ctx.body(i), want, "{what}, map {i}: body");
                            compared += 1;
                            active += usize::from(r.is_active());
                            cube += usize::from(r.face.is_some());
                        }
                    }
                }
            }
        }
    }
    // The comparison saw active maps, cube faces and several splits.
    assert!(compared > 400 && active > 300 && cube >= 6 * 8, "{compared} maps, {active} active, {cube} cube faces");
}

/// Receiver boxes through C: the maps of `fit` with the same boxes, bit for
/// bit, with optimal placement and receiver footprints (which use them),
/// for a few boxes and for more than the capacity (merged alike).
#[test]
fn receiver_boxes_give_the_maps_of_fit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let sc = rust_scene();
    let at = |k: usize, n: usize| {
        let t = k as f64 / n as f64;
        let lo = sc.min + (sc.max - sc.min) * glam::DVec3::new(t, 0.0, 1.0 - t) * 0.9;
        SfAabb { min: lo.to_array(), max: (lo + (sc.max - sc.min) * 0.1 * glam::DVec3::new(1.0, 0.02 + t, 1.0)).to_array() }
    };
    for n in [1, 3, 40] {
        let boxes: Vec<SfAabb> = (0..n).map(|k| at(k, n)).collect();
        let rust: Vec<Aabb> = boxes.iter().map(|b| Aabb { min: b.min.into(), max: b.max.into() }).collect();
        let receivers = ReceiverBoxes::new(&rust).unwrap();
        assert!(receivers.as_slice().len() == n.min(SF_MAX_RECEIVER_BOXES as usize) || n > SF_MAX_RECEIVER_BOXES as usize);
        for k in [0, 120] {
            let cam = camera(k);
            let mut s = settings(SfMethod::SF_METHOD_LISPSM, 4);
            (s.split_scheme, s.receiver_footprint, s.receivers, s.receiver_count) =
                (SfSplitScheme::SF_SPLIT_OPTIMAL as c_int, 1, boxes.as_ptr(), n as u32);
            let mut rs = rust_settings(SfMethod::SF_METHOD_LISPSM, 4);
            (rs.splits.scheme, rs.footprint, rs.receivers) = (SplitScheme::Optimal, Footprint::RECEIVERS, receivers);
            let light = lights()[0];
            fit(&rust_camera(&cam), &rust_light(&light), &sc, &rs, &mut out).unwrap();
            let (rc, m) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
            assert_eq!((rc, m), (0, out.maps().len()), "{n} boxes, frame {k}: {}", ctx.error());
            for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                assert_same(c, r, &format!("{n} boxes, frame {k}, map {i}"));
            }
        }
    }
}

/// The scene box's ground through C, each face: the maps of `fit` with the
/// same ground, bit for bit, with Auto on optimal planes (which predict on
/// it); `SF_GROUND_MIN_Y` moves them from those without a ground.
#[test]
fn a_ground_gives_the_maps_of_fit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let sc = rust_scene();
    let light = lights()[0];
    let faces = [BoxFace::MinX, BoxFace::MaxX, BoxFace::MinY, BoxFace::MaxY, BoxFace::MinZ, BoxFace::MaxZ];
    let mut moved = 0;
    // Each face, on the face and at a level a third of the way into the box.
    let grounds = faces.into_iter().enumerate().flat_map(|(k, face)| {
        let level = (2.0 * sc.min[face.axis()] + sc.max[face.axis()]) / 3.0;
        [(k, Ground::face(face)), (k, Ground::at(face, level))]
    });
    for (k, ground) in grounds {
        for frame in [0, 120] {
            let cam = camera(frame);
            let mut s = settings(SfMethod::SF_METHOD_AUTO, 4);
            (s.split_scheme, s.ground) = (SfSplitScheme::SF_SPLIT_OPTIMAL as c_int, k as c_int + 1);
            (s.ground_at_level, s.ground_level) = (ground.level.is_some().into(), ground.level.unwrap_or(0.0));
            let mut rs = rust_settings(SfMethod::SF_METHOD_AUTO, 4);
            (rs.splits.scheme, rs.ground) = (SplitScheme::Optimal, Some(ground));
            fit(&rust_camera(&cam), &rust_light(&light), &sc, &rs, &mut out).unwrap();
            let (rc, m) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
            assert_eq!((rc, m), (0, out.maps().len()), "{ground:?}, frame {frame}: {}", ctx.error());
            for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                assert_same(c, r, &format!("{ground:?}, frame {frame}, map {i}"));
            }
            if ground.face == BoxFace::MinY {
                let with: Vec<_> = out.maps().iter().map(|m| m.fit.clip_from_world).collect();
                fit(&rust_camera(&cam), &rust_light(&light), &sc, &FocusSettings { ground: None, ..rs }, &mut out).unwrap();
                moved += usize::from(out.maps().iter().map(|m| m.fit.clip_from_world).collect::<Vec<_>>() != with);
            }
        }
    }
    assert!(moved > 0, "the ground changed no fit");
}

/// A visible depth range through C, covering the hinted slab or the whole
/// view: the maps of `fit` with the same range and coverage, bit for bit;
/// covering the view, the outer splits reach the camera's near and far.
#[test]
fn a_visible_depth_range_gives_the_maps_of_fit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    for covers in [0, 1] {
        for k in [0, 120] {
            let cam = camera(k);
            let mut s = settings(SfMethod::SF_METHOD_LISPSM, 4);
            (s.visible_depth_min, s.visible_depth_max, s.visible_depth_covers_view) = (4.0, 60.0, covers);
            let mut rs = rust_settings(SfMethod::SF_METHOD_LISPSM, 4);
            rs.visible_depth = Some([4.0, 60.0]);
            rs.visible_depth_coverage = if covers != 0 { DepthHintCoverage::View } else { DepthHintCoverage::Hint };
            let light = lights()[0];
            fit(&rust_camera(&cam), &rust_light(&light), &rust_scene(), &rs, &mut out).unwrap();
            let (rc, m) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
            assert_eq!((rc, m), (0, out.maps().len()), "coverage {covers}, frame {k}: {}", ctx.error());
            for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                assert_same(c, r, &format!("coverage {covers}, frame {k}, map {i}"));
            }
            let ends = [maps[0].split[0], maps[m - 1].split[1]];
            let whole = [cam.near_dist, cam.far_dist];
            assert_eq!(ends, if covers != 0 { whole } else { [4.0, 60.0] }, "coverage {covers}, frame {k}");
        }
    }
}

/// A texel budget through C: the maps of `fit` with the same budget, bit for
/// bit (sizes included), for both kinds of sizes, with body and receiver
/// footprints, every light kind and a point light's cube.
#[test]
fn texel_budgets_give_the_maps_of_fit() {
    let ctx = Ctx::new();
    let mut out = FocusResult::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let mut resized = 0;
    for (sizes, any) in [(SfMapSizes::SF_SIZES_POWER_OF_TWO, false), (SfMapSizes::SF_SIZES_ANY, true)] {
        for footprint in [0, 1] {
            for light in lights() {
                for k in [0, 120] {
                    let cam = camera(k);
                    let mut s = settings(SfMethod::SF_METHOD_AUTO, 4);
                    (s.texel_budget, s.budget_sizes, s.receiver_footprint, s.point_mode) =
                        (3_000_000, sizes as c_int, footprint, SfPointMode::SF_POINT_CUBE as c_int);
                    let mut rs = rust_settings(SfMethod::SF_METHOD_AUTO, 4);
                    let kind = if any { MapSizes::Any } else { MapSizes::PowerOfTwo };
                    rs.texel_budget = Some(TexelBudget { texels: 3_000_000, sizes: kind });
                    rs.footprint = if footprint != 0 { Footprint::RECEIVERS } else { Footprint::Body };
                    rs.point = PointMode::Cube;
                    let what = format!("{sizes:?}, footprint {footprint}, light kind {}, frame {k}", light.kind);
                    fit(&rust_camera(&cam), &rust_light(&light), &rust_scene(), &rs, &mut out).unwrap();
                    let (rc, n) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
                    assert_eq!((rc, n), (0, out.maps().len()), "{what}: {}", ctx.error());
                    let mut used = 0u64;
                    for (i, (c, r)) in maps.iter().zip(out.maps()).enumerate() {
                        assert_same(c, r, &format!("{what}, map {i}"));
                        used += u64::from(c.resolution).pow(2);
                        resized += usize::from(c.active != 0 && c.resolution != s.resolution);
                    }
                    assert!(used <= 3_000_000, "{what}: {used} texels");
                }
            }
        }
    }
    assert!(resized > 20, "the budget resized only {resized} maps");
}

/// One prepared view, two lights: the maps of sf_fit for each.
#[test]
fn sf_fit_light_from_a_prepared_view_gives_the_maps_of_sf_fit() {
    let (a, b) = (Ctx::new(), Ctx::new());
    let s = settings(SfMethod::SF_METHOD_LISPSM, 4);
    let mut want = vec![canary_map(); SF_MAX_MAPS as usize];
    let mut got = want.clone();
    for k in [3, 150] {
        let cam = camera(k);
        // SAFETY: valid pointers.
        assert_eq!(unsafe { sf_prepare_view(a.0, &cam, &s) }, 0, "{}", a.error());
        for light in lights() {
            let (rc, n) = b.fit(&cam, &light, &scene(), &s, &mut want);
            assert_eq!(rc, 0, "{}", b.error());
            let mut m = 0;
            // SAFETY: `got` holds SF_MAX_MAPS maps.
            let rc = unsafe { sf_fit_light(a.0, &light, &scene(), got.as_mut_ptr(), got.len(), &mut m) };
            assert_eq!((rc, m), (0, n), "{}", a.error());
            for i in 0..n {
                assert_eq!(bits(&got[i].clip_from_world), bits(&want[i].clip_from_world));
                assert_eq!(bits32(&got[i].clip_from_world_f32), bits32(&want[i].clip_from_world_f32));
            }
        }
    }
}

/// sf_fit_light_held over a camera path gives, frame after frame, the maps
/// of fit_prepared_with_state with a state carried alongside (stable and
/// not, every light kind), and its state is the library's.
#[test]
fn sf_fit_light_held_carries_the_state_of_the_library() {
    let ctx = Ctx::new();
    let methods = [SfMethod::SF_METHOD_UNIFORM, SfMethod::SF_METHOD_LISPSM, SfMethod::SF_METHOD_TSM];
    for (stable, method) in [0, 1].into_iter().flat_map(|s| methods.map(|m| (s, m))) {
        // Stable maps need planes that hold still: the practical ones.
        let s = SfSettings { stable, split_scheme: SfSplitScheme::SF_SPLIT_PRACTICAL as c_int, ..settings(method, 2) };
        let mut rs = FocusSettings { stable: stable != 0, ..rust_settings(method, 2) };
        rs.splits.scheme = SplitScheme::Practical { lambda: 0.5 };
        let mut held_warps = 0;
        for light in lights() {
            let junk = SfWarpHold { direction: 3, strength: 9, extent: [1, 2], apex: [5, 6] };
            let mut c_state = SfFitState { steps: [7; 48], warps: [junk; 48] };
            // SAFETY: a valid pointer.
            unsafe { sf_fit_state_init(&mut c_state) };
            let mut state = FitState::default();
            assert_eq!(c_state.steps, state.to_steps());
            assert!(c_state.warps.iter().all(|w| w.direction < 0));
            let mut got = vec![canary_map(); SF_MAX_MAPS as usize];
            for k in 0..12 {
                let cam = camera(k);
                let mut m = 0;
                // SAFETY: valid pointers; `got` holds SF_MAX_MAPS maps.
                let rc = unsafe {
                    assert_eq!(sf_prepare_view(ctx.0, &cam, &s), 0, "{}", ctx.error());
                    sf_fit_light_held(ctx.0, &light, &scene(), &mut c_state, got.as_mut_ptr(), got.len(), &mut m)
                };
                assert_eq!(rc, 0, "{}", ctx.error());
                let view = PreparedView::new(&rust_camera(&cam), &rs).unwrap();
                let mut want = FocusResult::new();
                fit_prepared_with_state(&view, &rust_light(&light), &rust_scene(), &mut state, &mut want).unwrap();
                assert_eq!(m, want.maps().len());
                for (i, r) in want.maps().iter().enumerate() {
                    assert_same(&got[i], r, &format!("frame {k}, map {i}"));
                }
                assert_eq!(c_state.steps, state.to_steps(), "frame {k}");
                let warps = state.to_warps();
                for (c, w) in c_state.warps.iter().zip(&warps) {
                    assert_eq!((c.direction, c.strength, c.extent, c.apex), (w.direction, w.strength, w.extent, w.apex), "frame {k}");
                }
                held_warps += warps.iter().filter(|w| w.is_held()).count();
            }
        }
        // The warps' state really crosses: stable LiSPSM and TSM hold some.
        let warp = method != SfMethod::SF_METHOD_UNIFORM;
        assert_eq!(held_warps > 0, stable == 1 && warp, "{method:?}, stable {stable}: {held_warps} warps held");
    }
}

/// sf_view_body is the body of the whole fitted view; sf_cull_casters is
/// cull_casters on the same map and boxes.
#[test]
fn view_body_and_culling_match_the_library() {
    let ctx = Ctx::new();
    let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
    let mut boxes = Vec::new();
    for i in 0..20 {
        for j in 0..20 {
            let (x, z) = (-95.0 + 10.0 * i as f64, -95.0 + 10.0 * j as f64);
            boxes.push(SfAabb { min: [x, 0.0, z], max: [x + 3.0, 4.0 + (i + j) as f64 % 7.0, z + 3.0] });
        }
    }
    let rust_boxes: Vec<Aabb> = boxes.iter().map(|b| Aabb::new(b.min.into(), b.max.into()).unwrap()).collect();
    let mut out = FocusResult::new();
    let (mut kept_total, mut culled_total) = (0, 0);
    for light in lights() {
        let cam = camera(40);
        let s = settings(SfMethod::SF_METHOD_LISPSM, 4);
        let (rc, n) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
        assert_eq!(rc, 0, "{}", ctx.error());
        fit(&rust_camera(&cam), &rust_light(&light), &rust_scene(), &rust_settings(SfMethod::SF_METHOD_LISPSM, 4), &mut out).unwrap();

        let (mut want, mut focuser) = (Body::new(), Focuser::new());
        focuser.focus_into(&mut want, &Frustum::from_camera(&rust_camera(&cam)).unwrap(), &rust_light(&light), &rust_scene()).unwrap();
        let mut v = vec![[0.0; 3]; SF_MAX_BODY_VERTICES as usize];
        let mut nv = 0;
        // SAFETY: `v` holds SF_MAX_BODY_VERTICES vertices.
        assert_eq!(unsafe { sf_view_body(ctx.0, v.as_mut_ptr().cast(), v.len(), &mut nv) }, 0, "{}", ctx.error());
        assert!(nv > 0);
        assert_eq!(&v[..nv], &want.vertices().iter().map(|p| p.to_array()).collect::<Vec<_>>()[..]);

        for i in 0..n {
            let mut got = vec![u32::MAX; boxes.len()];
            let mut count = 0;
            // SAFETY: `boxes` and `got` hold boxes.len() entries.
            let rc = unsafe { sf_cull_casters(ctx.0, i, boxes.as_ptr(), boxes.len(), got.as_mut_ptr(), got.len(), &mut count) };
            assert_eq!(rc, 0, "{}", ctx.error());
            let mut want = vec![0u32; boxes.len()];
            let kept = cull_casters(&out.maps()[i], &rust_boxes, &mut want).unwrap();
            assert_eq!(&got[..count], &want[..kept]);
            // The caster planes, bit for bit; a short buffer gets the count only.
            let mut planes = vec![[f64::NAN; 4]; SF_MAX_CASTER_PLANES as usize];
            let mut np = 0;
            // SAFETY: `planes` holds SF_MAX_CASTER_PLANES planes of four doubles.
            let rc = unsafe { sf_caster_planes(ctx.0, i, planes.as_mut_ptr().cast(), planes.len(), &mut np) };
            assert_eq!(rc, 0, "{}", ctx.error());
            let mut want_planes = [glam::DVec4::ZERO; shadowfocus_focus::MAX_REGION_PLANES];
            let wn = caster_planes(&out.maps()[i], &mut want_planes).unwrap();
            assert!(np > 0 && np == wn);
            assert_eq!(bits(planes[..np].as_flattened()), bits(&want_planes[..wn].iter().flat_map(|p| p.to_array()).collect::<Vec<_>>()));
            let mut short = vec![[f64::NAN; 4]; np - 1];
            // SAFETY: `short` holds np − 1 planes.
            let rc = unsafe { sf_caster_planes(ctx.0, i, short.as_mut_ptr().cast(), short.len(), &mut np) };
            assert_eq!((rc, np), (SfStatus::SF_ERR_BUFFER_TOO_SMALL as c_int, wn));
            assert!(short.as_flattened().iter().all(|x| x.is_nan()), "a short buffer was written");
            kept_total += kept;
            culled_total += boxes.len() - kept;
        }
    }
    assert!(kept_total > 0 && culled_total > 0, "kept {kept_total}, culled {culled_total}");
}

/// The header's constants are the library's.
#[test]
fn constants_match_the_library() {
    use shadowfocus_focus::{Notes, Skipped, MAX_MAPS, MAX_SPLITS};
    assert_eq!(SF_MAX_SPLITS as usize, MAX_SPLITS);
    assert_eq!(SF_MAX_RECEIVER_BOXES as usize, shadowfocus_focus::MAX_RECEIVER_BOXES);
    assert_eq!(SF_MAX_MAPS as usize, MAX_MAPS);
    assert_eq!(SF_MAX_BODY_VERTICES as usize, shadowfocus_geom::MAX_VERTICES);
    assert_eq!(SF_MAX_CASTER_PLANES as usize, shadowfocus_focus::MAX_REGION_PLANES);
    let notes = [
        (SF_NOTE_PSM_FELL_BACK, Notes::PSM_FELL_BACK),
        (SF_NOTE_POINT_AS_CUBE, Notes::POINT_AS_CUBE),
        (SF_NOTE_LIGHT_NEAR, Notes::LIGHT_NEAR),
        (SF_NOTE_INVERTED, Notes::INVERTED),
        (SF_NOTE_STABLE_IGNORED, Notes::STABLE_IGNORED),
        (SF_NOTE_F32_IMPRECISE, Notes::F32_IMPRECISE),
        (SF_NOTE_WARP_LIMITED, Notes::WARP_LIMITED),
    ];
    for (c, r) in notes {
        assert_eq!(c, r.0);
    }
    let skipped = [
        (SF_SKIPPED_LIGHT_CLIP, Skipped::LIGHT_CLIP),
        (SF_SKIPPED_SCENE_CLIP, Skipped::SCENE_CLIP),
        (SF_SKIPPED_PSM_SHIFT, Skipped::PSM_SHIFT),
        (SF_SKIPPED_EMPTY_MAPS, Skipped::EMPTY_MAPS),
        (SF_SKIPPED_WARP, Skipped::WARP),
    ];
    for (c, r) in skipped {
        assert_eq!(c, r.0);
    }
}

/// sf_settings_default stands for FocusSettings::default().
#[test]
fn default_settings_are_the_library_defaults() {
    let s = settings(SfMethod::SF_METHOD_UNIFORM, 1);
    // SAFETY: no receiver boxes.
    assert_eq!(unsafe { crate::convert::settings(&s) }.unwrap(), shadowfocus_focus::FocusSettings::default());
    assert_eq!((s.depth_zero_to_one, s.reversed_z, s.uv_origin_top_left), (1, 0, 1));
}

/// Visible receiver boxes through C: those of `VisibleReceivers` from the
/// same float points (and normals, on every other frame), bit for bit, for
/// a bumpy ground seen from frames of the walk; none for no points; a short
/// buffer gets the count.
#[test]
fn visible_receivers_are_those_of_the_library() {
    let ctx = Ctx::new();
    for k in [0, 40, 120] {
        let cam = camera(k);
        let rc = rust_camera(&cam);
        let b = rc.basis().unwrap();
        // The points a 64-row pre-pass sees of y = 0.3 sin(x) cos(z), on a grid of rays.
        let (mut pts, mut normals): (Vec<f32>, Vec<f32>) = (Vec::new(), Vec::new());
        for j in 0..32 {
            for i in 0..48 {
                let (u, v) = (i as f64 / 47.0 * 2.0 - 1.0, -(j as f64) / 31.0);
                let d = b.forward + b.right * (u * 0.9) + b.up * (v * 0.5);
                if d.y >= 0.0 {
                    continue;
                }
                let p = rc.eye + d * (-rc.eye.y / d.y);
                let p = glam::DVec3::new(p.x, 0.3 * p.x.sin() * p.z.cos(), p.z);
                pts.extend([p.x as f32, p.y as f32, p.z as f32]);
                // The normal of y = 0.3 sin(x) cos(z), steepened so that some face x or z.
                let n = glam::DVec3::new(-3.0 * p.x.cos() * p.z.cos(), 1.0, 3.0 * p.x.sin() * p.z.sin());
                normals.extend([n.x as f32, n.y as f32, n.z as f32]);
            }
        }
        let with_normals = k % 80 == 40;
        let mut v = shadowfocus_focus::VisibleReceivers::new(&rc, 64).unwrap();
        let dvec = |p: &[f32]| glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
        for (p, m) in pts.chunks(3).zip(normals.chunks(3)) {
            if with_normals {
                v.add_facing(dvec(p), dvec(m));
            } else {
                v.add(dvec(p));
            }
        }
        let want = v.boxes(1e-3).unwrap();
        if with_normals {
            let mut plain = shadowfocus_focus::VisibleReceivers::new(&rc, 64).unwrap();
            pts.chunks(3).for_each(|p| plain.add(dvec(p)));
            assert_ne!(want, plain.boxes(1e-3).unwrap(), "frame {k}: the normals part no points");
        }
        let mut out = [SfAabb { min: [9.0; 3], max: [9.0; 3] }; SF_MAX_RECEIVER_BOXES as usize];
        let mut n = 99;
        let normals = if with_normals { normals.as_ptr() } else { ptr::null() };
        let count = pts.len() / 3;
        let rc = unsafe { sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), normals, count, 1e-3, out.as_mut_ptr(), out.len(), &mut n) };
        assert_eq!(rc, 0, "frame {k}: {}", ctx.error());
        assert_eq!(n, want.as_slice().len(), "frame {k}");
        assert!(n >= 1);
        for (c, r) in out[..n].iter().zip(want.as_slice()) {
            assert_eq!((bits(&c.min), bits(&c.max)), (bits(&r.min.to_array()), bits(&r.max.to_array())), "frame {k}");
        }
        // Fitted with the boxes marked seen: the maps of `fit` with them.
        let mut s = settings(SfMethod::SF_METHOD_AUTO, 4);
        (s.split_scheme, s.receivers, s.receiver_count, s.receivers_seen) =
            (SfSplitScheme::SF_SPLIT_OPTIMAL as c_int, out.as_ptr(), n as u32, 1);
        let mut rs = rust_settings(SfMethod::SF_METHOD_AUTO, 4);
        (rs.splits.scheme, rs.receivers) = (SplitScheme::Optimal, want);
        assert!(want.is_seen());
        let mut result = FocusResult::new();
        let mut maps = vec![canary_map(); SF_MAX_MAPS as usize];
        let light = lights()[0];
        fit(&rust_camera(&cam), &rust_light(&light), &rust_scene(), &rs, &mut result).unwrap();
        let (code, m) = ctx.fit(&cam, &light, &scene(), &s, &mut maps);
        assert_eq!((code, m), (0, result.maps().len()), "frame {k}: {}", ctx.error());
        for (i, (c, r)) in maps.iter().zip(result.maps()).enumerate() {
            assert_same(c, r, &format!("seen boxes, frame {k}, map {i}"));
        }
        let mut short = [SfAabb { min: [9.0; 3], max: [9.0; 3] }; 1];
        let rc = unsafe { sf_visible_receivers(ctx.0, &cam, 64, pts.as_ptr(), normals, count, 1e-3, short.as_mut_ptr(), n - 1, &mut n) };
        if n > 1 {
            assert_eq!(rc, SfStatus::SF_ERR_BUFFER_TOO_SMALL as c_int);
            assert_eq!(short[0].min, [9.0; 3], "nothing written");
        }
    }
    let mut n = 99;
    let rc = unsafe { sf_visible_receivers(ctx.0, &camera(0), 64, ptr::null(), ptr::null(), 0, 0.0, ptr::null_mut(), 0, &mut n) };
    assert_eq!((rc, n), (0, 0), "no points: no hint");
}
