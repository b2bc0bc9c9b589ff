//! Render tests on whatever adapter the machine has (llvmpipe through GL in CI).
//!
//! GPU tests are skipped only when no adapter exists at all and SHADOWFOCUS_REQUIRE_GPU is unset.

use std::sync::{Mutex, OnceLock};

use glam::{DVec3, Mat4};
use shadowfocus_render::*;

fn renderer() -> Option<&'static Mutex<Renderer>> {
    static R: OnceLock<Option<Mutex<Renderer>>> = OnceLock::new();
    R.get_or_init(|| match Renderer::from_env() {
        Ok(r) => {
            eprintln!("adapter: {:?}", r.adapter());
            Some(Mutex::new(r))
        }
        Err(RenderError::NoAdapter { .. }) if std::env::var_os("SHADOWFOCUS_REQUIRE_GPU").is_none() => {
            eprintln!("no graphics adapter: GPU tests skipped (set SHADOWFOCUS_REQUIRE_GPU to fail instead)");
            None
        }
        Err(e) => panic!("opening an adapter failed: {e}"),
    })
    .as_ref()
}

fn render(req: &RenderRequest) -> Option<RenderOutput> {
    let r = renderer()?;
    let mut r = r.lock().unwrap_or_else(|e| e.into_inner());
    Some(r.render(req).expect("render"))
}

fn small(req: &mut RenderRequest, w: u32, h: u32, res: u32) {
    req.settings.width = w;
    req.settings.height = h;
    req.settings.shadow_resolution = res;
}

fn aspect(w: u32, h: u32) -> f64 {
    w as f64 / h as f64
}

#[test]
fn shadows_agree_with_ray_cast_ground_truth_away_from_edges() {
    // Spot (chessboard), directional (huge board), point light behind the camera (inverted).
    for name in ["chessboard", "huge-chessboard", "inverted"] {
        let scene = builtin_scene(name).unwrap();
        let map = testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(256, 144)).unwrap();
        let maps = [map];
        let mut req = RenderRequest::new(&scene, &maps);
        small(&mut req, 256, 144, 2048);
        let Some(out) = render(&req) else { return };
        let m = out.metrics.mismatch.expect("ground truth was requested");
        eprintln!("{name}: {m:?}");
        assert!(m.off_edge_pixels > 5_000, "{name}: too few off-edge pixels to judge ({m:?})");
        assert!(m.rate_off_edges < 0.01, "{name}: {:.4} of off-edge pixels disagree with the ray cast", m.rate_off_edges);
        assert!(m.rate < 0.05, "{name}: overall mismatch {:.4}", m.rate);
        // The scene has visible shadows at all (the comparison is not vacuous).
        let truth = out.truth.as_ref().unwrap();
        let occluded = truth.iter().filter(|v| **v == Visibility::Occluded).count();
        let lit = truth.iter().filter(|v| v.is_lit()).count();
        assert!(occluded > 200 && lit > 500, "{name}: occluded {occluded}, lit {lit}");
    }
}

#[test]
fn aliasing_matches_the_analytic_footprint_ratio() {
    // Camera 10 m above a plane looking straight down, sun straight down, an orthographic map
    // 100 m wide at 512²: at the image centre one pixel spans 2·10·tan(30°)/128 m and one texel
    // 100/512 m, so e = (100/512) / (20·tan 30° / 128) screen pixels per texel.
    let quad = [(-100.0f32, -100.0f32), (100.0, -100.0), (100.0, 100.0), (-100.0, 100.0)];
    let vertices: Vec<Vertex> = quad.iter().map(|&(x, z)| Vertex { position: [x, 0.0, z], color: [200, 200, 200, 255] }).collect();
    let camera =
        CameraSpec { eye: DVec3::new(0.0, 10.0, 0.0), forward: -DVec3::Y, up: DVec3::Z, fovy: 60f64.to_radians(), near: 1.0, far: 50.0 };
    let light = LightSpec::Directional { direction: -DVec3::Y };
    let scene = Scene::new("plane", vertices, vec![0, 1, 2, 0, 2, 3], &[(0, 6, true)], camera, light).unwrap();
    let view = glam::dcamera::rh::view::look_to_mat4(DVec3::new(0.0, 100.0, 0.0), -DVec3::Y, DVec3::Z);
    let proj = glam::dcamera::rh::proj::directx::orthographic(-50.0, 50.0, -50.0, 50.0, 1.0, 200.0);
    let maps = [ShadowMapSpec {
        world_to_clip: (proj * view).as_mat4(),
        depth_test: DepthTest::Less,
        split: [1.0, 50.0],
        casters: vec![0],
        face: None,
        resolution: None,
    }];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, 128, 128, 512);
    let Some(out) = render(&req) else { return };
    let expected = (100.0 / 512.0) / (20.0 * 30f64.to_radians().tan() / 128.0);
    // The plane is parallel to the image plane, so its image is a uniform scaling of it: e is the
    // same at every pixel, corners included.
    for (x, y) in [(63u32, 63u32), (64, 64), (0, 0), (127, 5), (3, 120)] {
        let e = out.aliasing[(y * 128 + x) as usize] as f64;
        assert!((e / expected - 1.0).abs() < 0.02, "pixel ({x}, {y}): e = {e}, expected {expected}");
    }
    assert!(out.metrics.coverage.complete);
    assert!((out.metrics.aliasing.mean / expected - 1.0).abs() < 0.02, "{:?}", out.metrics.aliasing);
    // The logarithmic bound for 512² texels, a 128² image and depths [1, 50]:
    // sqrt(W·P·ln(f/n)/T) with P = 64 / tan 30°.
    let a = &out.metrics.aliasing;
    let bound = (128.0 * (64.0 / 30f64.to_radians().tan()) * 50f64.ln() / (512.0 * 512.0)).sqrt();
    assert!((a.bound / bound - 1.0).abs() < 1e-12 && (a.ratio - a.max / bound).abs() < 1e-9 * a.ratio, "{a:?}, bound {bound}");
}

#[test]
fn a_wrong_depth_test_is_caught_by_the_mismatch_metric() {
    // The inverted case: a map whose depth order is reversed must be compared with "greater".
    let scene = builtin_scene("inverted").unwrap();
    let plain = testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(192, 108)).unwrap();
    let reversed = testfit::reverse_depth(&plain);
    assert_eq!(reversed.depth_test, DepthTest::Greater);
    let right = [reversed.clone()];
    let wrong = [ShadowMapSpec { depth_test: DepthTest::Less, ..reversed }];
    let mut req = RenderRequest::new(&scene, &right);
    small(&mut req, 192, 108, 1024);
    let Some(good) = render(&req) else { return };
    req.maps = &wrong;
    let bad = render(&req).unwrap();
    let (g, b) = (good.metrics.mismatch.unwrap(), bad.metrics.mismatch.unwrap());
    eprintln!("greater: {g:?}\nless: {b:?}");
    assert!(g.rate_off_edges < 0.01, "correct depth test: {:.4}", g.rate_off_edges);
    assert!(b.rate > 0.1 && b.rate > 20.0 * g.rate, "a wrong depth test must show as a large mismatch, got {:.4}", b.rate);
    // The pixels the map resolves hide no such error: there it shows at least as clearly.
    assert!(g.adequate_pixels > 1000 && b.adequate_pixels > 1000, "{g:?} {b:?}");
    assert!(
        g.rate_adequate < 0.005 && b.rate_adequate > 0.1,
        "adequately sampled: right {:.4}, wrong {:.4}",
        g.rate_adequate,
        b.rate_adequate
    );
}

#[test]
fn a_wider_filter_resolves_fewer_pixels_and_both_resolve_right() {
    // The adequate set keeps pixels whose lookup reads only texels that agree with the pixel's
    // ground truth: a wider PCF footprint reads more texels, so it can only keep fewer.
    let scene = builtin_scene("forest").unwrap();
    let map = testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(256, 144)).unwrap();
    let maps = [map];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, 256, 144, 2048);
    let mut stats = Vec::new();
    for pcf in [Pcf::Off, Pcf::Hardware2x2, Pcf::Kernel { radius: 2 }] {
        req.settings.pcf = pcf;
        let Some(out) = render(&req) else { return };
        let m = out.metrics.mismatch.unwrap();
        assert!(m.rate_adequate <= 0.005, "{pcf:?}: {m:?}");
        stats.push(m.adequate_pixels);
    }
    eprintln!("adequate pixels, nearest / bilinear / 6×6 kernel: {stats:?}");
    assert!(stats[0] >= stats[1] && stats[1] > stats[2] && stats[2] > 500, "{stats:?}");
}

#[test]
fn every_pixel_is_covered_by_parallel_splits_and_gaps_are_reported() {
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (192, 108);
    let maps = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 4).unwrap();
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, w, h, 512);
    req.settings.ground_truth = false;
    let Some(out) = render(&req) else { return };
    let c = out.metrics.coverage;
    assert!(c.complete && c.required > 5_000, "{c:?}");
    assert_eq!(out.metrics.split_pixels.len(), 4);
    assert!(out.metrics.split_pixels.iter().all(|&n| n > 0), "every split serves pixels: {:?}", out.metrics.split_pixels);
    // Caster culling: the near splits draw fewer objects than the scene has.
    assert!(out.metrics.casters.per_map[0] < out.metrics.casters.total, "{:?}", out.metrics.casters);
    // Shrinking one map's footprint must leave pixels uncovered.
    let mut shrunk = maps.clone();
    shrunk[1] = testfit::zoom(&maps[1], 20.0);
    req.maps = &shrunk;
    let out = render(&req).unwrap();
    assert!(!out.metrics.coverage.complete && out.metrics.coverage.uncovered > 100, "{:?}", out.metrics.coverage);
}

#[test]
fn aliasing_halves_when_the_shadow_resolution_doubles() {
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (192, 108);
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(w, h)).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, w, h, 512);
    req.settings.ground_truth = false;
    req.settings.save_shadow_maps = false;
    let Some(lo) = render(&req) else { return };
    req.settings.shadow_resolution = 1024;
    let hi = render(&req).unwrap();
    let (a, b) = (lo.metrics.aliasing, hi.metrics.aliasing);
    eprintln!("512: {a:?}\n1024: {b:?}");
    assert!(a.pixels > 5_000 && a.pixels == b.pixels);
    for v in [a.max, a.p95, a.mean, b.max, b.p95, b.mean] {
        assert!(v.is_finite() && v > 0.0, "{v}");
    }
    assert!(a.mean <= a.p95 * 1.0001 + 1e-9 || a.mean <= a.max, "mean ≤ max");
    let r = b.mean / a.mean;
    assert!((r - 0.5).abs() < 0.02, "mean e ratio {r}");
    let r95 = b.p95 / a.p95;
    assert!((r95 - 0.5).abs() < 0.05, "p95 ratio {r95}");
    // A uniform map over a 700 m board is undersampled near the viewer: e > 1 somewhere.
    assert!(a.max > 1.0, "{a:?}");
}

/// A map drawn into the corner of a larger array (its own `resolution`, beside a larger map)
/// is rasterised, looked up and read back as the same map in an array of its own size: the
/// same depths, shadow terms and aliasing, pixel for pixel.
#[test]
fn a_map_in_a_corner_of_a_larger_array_is_the_map_of_its_own_size() {
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (192, 108);
    let own = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 3).unwrap();
    let mut req = RenderRequest::new(&scene, &own);
    small(&mut req, w, h, 256);
    req.settings.ground_truth = false;
    req.settings.save_shadow_maps = true;
    let Some(alone) = render(&req) else { return };
    // The same three maps at 256² each, then a 1024² map that answers for no receiver (w < 0
    // everywhere) and draws nothing: the array is 1024² and the three sit in its corners.
    let mut cornered: Vec<ShadowMapSpec> = own.iter().map(|m| ShadowMapSpec { resolution: Some(256), ..m.clone() }).collect();
    let nowhere = Mat4::from_cols_array(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]);
    cornered.push(ShadowMapSpec { world_to_clip: nowhere, casters: Vec::new(), resolution: Some(1024), ..own[0].clone() });
    req.maps = &cornered;
    req.settings.shadow_resolution = 64;
    let big = render(&req).unwrap();
    assert_eq!(big.shadow_maps[3].resolution, 1024);
    for k in 0..3 {
        let (a, b) = (&alone.shadow_maps[k], &big.shadow_maps[k]);
        assert_eq!((a.resolution, b.resolution), (256, 256), "map {k}");
        let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.depth), bits(&b.depth), "map {k}: depths");
        assert!(a.depth.iter().filter(|d| !d.is_nan()).count() > 1000, "map {k} drew casters");
    }
    let differ = |x: &[f32], y: &[f32]| x.iter().zip(y).filter(|(a, b)| a.to_bits() != b.to_bits()).count();
    assert_eq!(differ(&alone.shadow, &big.shadow), 0, "shadow terms");
    assert_eq!(differ(&alone.aliasing, &big.aliasing), 0, "aliasing");
    assert!(alone.shadow.iter().filter(|&&v| v < 0.5).count() > 500, "the frame has shadows to compare");
    // The bound counts the texels of every map: 3·256² + 1024².
    assert!(big.metrics.aliasing.bound < alone.metrics.aliasing.bound);
}

#[test]
fn parallel_splits_lower_aliasing_at_an_equal_texel_budget() {
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (192, 108);
    let one = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(w, h)).unwrap()];
    let four = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 4).unwrap();
    let mut req = RenderRequest::new(&scene, &one);
    small(&mut req, w, h, 1024);
    req.settings.ground_truth = false;
    req.settings.save_shadow_maps = false;
    let Some(a) = render(&req) else { return };
    req.maps = &four;
    req.settings.shadow_resolution = 512;
    let b = render(&req).unwrap();
    let (a, b) = (a.metrics.aliasing, b.metrics.aliasing);
    eprintln!("uniform 1x1024²: {a:?}\nsplits 4x512²: {b:?}");
    assert!(b.p95 < a.p95 && b.max < a.max, "splits {b:?} vs one map {a:?}");
}

#[test]
fn filtering_blending_blur_and_linear_depth_keep_shadows_correct() {
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (224, 126);
    let maps = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 3).unwrap();
    let variants = [
        ("kernel pcf + blend", Pcf::Kernel { radius: 1 }, 0.15, None, RenderSettings::default().depth),
        ("no pcf, linear depth", Pcf::Off, 0.0, None, DepthMode::Linear { constant: 2e-5, slope_scale: 2.0 }),
        (
            "eye-space blur",
            Pcf::Hardware2x2,
            0.0,
            Some(EyeBlur { world_radius: 1.5, max_radius_px: 6.0, iterations: 2 }),
            RenderSettings::default().depth,
        ),
    ];
    for (label, pcf, band, blur, depth) in variants {
        let mut req = RenderRequest::new(&scene, &maps);
        small(&mut req, w, h, 1024);
        req.settings.pcf = pcf;
        req.settings.blend_band = band;
        req.settings.blur = blur;
        req.settings.depth = depth;
        let Some(out) = render(&req) else { return };
        let m = out.metrics.mismatch.unwrap();
        eprintln!("{label}: {m:?}");
        assert!(m.rate_off_edges < 0.01, "{label}: off-edge mismatch {:.4}", m.rate_off_edges);
        assert!(out.shadow.iter().all(|s| (0.0..=1.0).contains(s)), "{label}: shadow term out of [0, 1]");
        if blur.is_some() {
            // Blurring produces intermediate values along shadow edges.
            let soft = out.shadow.iter().filter(|&&s| s > 0.05 && s < 0.95).count();
            assert!(soft > 100, "{label}: only {soft} soft pixels");
        }
    }
    // Linear depth under a point light (distance from the light).
    let scene = builtin_scene("inverted").unwrap();
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(w, h)).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, w, h, 1024);
    req.settings.depth = DepthMode::Linear { constant: 2e-5, slope_scale: 2.0 };
    let Some(out) = render(&req) else { return };
    let m = out.metrics.mismatch.unwrap();
    assert!(m.rate_off_edges < 0.01, "linear depth, point light: {m:?}");
}

#[test]
fn gpu_phase_times_lie_within_the_wall_clock_times() {
    let scene = builtin_scene("chessboard").unwrap();
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(128, 72)).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, 128, 72, 512);
    req.settings.timing_repeats = 2;
    let Some(out) = render(&req) else { return };
    let m = &out.metrics;
    let phases = [("shadow", m.shadow_gpu_ms, m.shadow_pass_ms), ("main", m.main_gpu_ms, m.main_pass_ms)];
    for (phase, gpu, wall) in phases {
        if !m.adapter.timestamps {
            assert_eq!(gpu, None, "{phase}: a GPU time without timestamp queries");
            continue;
        }
        let gpu = gpu.unwrap_or_else(|| panic!("{phase}: no GPU time on {:?}", m.adapter));
        // The GPU's work lies between the submission and the fence; the
        // slack covers converting its ticks to milliseconds.
        assert!(gpu > 0.0 && gpu <= wall * 1.01 + 0.05, "{phase}: GPU {gpu} ms against wall clock {wall} ms");
    }
}

#[test]
fn outputs_are_written_as_png_and_json() {
    let scene = builtin_scene("inverted").unwrap();
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(128, 72)).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, 128, 72, 256);
    let Some(out) = render(&req) else { return };
    let dir = std::env::temp_dir().join(format!("sf-render-out-{}", std::process::id()));
    let files = write_outputs(&dir, &out, Some(&serde_json::json!({ "method": "uniform", "focusing_us": 1.5 }))).unwrap();
    for f in ["image.png", "shadow_map_0.png", "aliasing.png", "mismatch.png", "metrics.json"] {
        assert!(files.contains(&dir.join(f)), "{f} missing from {files:?}");
    }
    let img = Image::load_png(&dir.join("image.png")).unwrap();
    assert_eq!((img.width, img.height), (128, 72));
    assert_eq!(img, out.color);
    let sm = Image::load_png(&dir.join("shadow_map_0.png")).unwrap();
    assert_eq!(sm.width, 256);
    let j: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(j["method"], "uniform");
    assert_eq!(j["scene"], "inverted");
    assert!(j["aliasing"]["p95"].as_f64().unwrap() > 0.0);
    assert!(j["mismatch"]["rate_off_edges"].as_f64().is_some());
    assert!(j["render_ms"].as_f64().unwrap() > 0.0);
    assert!(!j["adapter"]["name"].as_str().unwrap().is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_requests_are_typed_errors() {
    let scene = builtin_scene("inverted").unwrap();
    let good = testfit::scene_box_map(&scene, &scene.camera, &scene.light, 16.0 / 9.0).unwrap();
    let mut nan = good.clone();
    nan.world_to_clip = Mat4::from_cols_array(&[f32::NAN; 16]);
    let maps = [nan];
    assert!(matches!(RenderRequest::new(&scene, &maps).validate(), Err(RenderError::NonFinite { .. })));
    let mut bad_caster = good.clone();
    bad_caster.casters.push(10_000);
    let maps = [bad_caster];
    assert!(matches!(RenderRequest::new(&scene, &maps).validate(), Err(RenderError::Invalid { .. })));
    let maps = [good.clone()];
    let mut req = RenderRequest::new(&scene, &maps);
    req.settings.width = 0;
    assert!(matches!(req.validate(), Err(RenderError::Invalid { .. })));
    let mut req = RenderRequest::new(&scene, &maps);
    req.camera.near = req.camera.far;
    assert!(req.validate().is_err());
    let mut req = RenderRequest::new(&scene, &maps);
    req.light = LightSpec::Directional { direction: DVec3::ZERO };
    assert!(req.validate().is_err());
    for bad in [0, 16385] {
        let sized = [ShadowMapSpec { resolution: Some(bad), ..good.clone() }];
        let err = RenderRequest::new(&scene, &sized).validate().unwrap_err().to_string();
        assert!(err.contains("shadow map 0 resolution"), "{err}");
    }
    let ascending: [f32; RECEIVER_SLICES - 1] = std::array::from_fn(|k| 1.0 + k as f32);
    for (k, bad) in [(3, f32::NAN), (7, f32::INFINITY), (9, 0.5)] {
        let mut req = RenderRequest::new(&scene, &maps);
        req.settings.receiver_slices = Some(ascending);
        assert!(req.validate().is_ok());
        req.settings.receiver_slices.as_mut().unwrap()[k] = bad;
        let err = req.validate().unwrap_err().to_string();
        assert!(err.contains("receiver slice planes"), "{err}");
    }
    let many = vec![good; MAX_MAPS + 1];
    assert!(RenderRequest::new(&scene, &many).validate().is_err());
    assert!(BackendChoice::parse("metal").is_err());
    assert_eq!(BackendChoice::parse("GL").unwrap(), BackendChoice::Gl);
    // Rendering refuses the same request before touching the GPU.
    if let Some(r) = renderer() {
        let mut r = r.lock().unwrap_or_else(|e| e.into_inner());
        let mut req = RenderRequest::new(&scene, &maps);
        req.settings.shadow_resolution = 0;
        assert!(r.render(&req).is_err());
    }
}

/// A glTF file with nested transforms, a perspective camera and a KHR_lights_punctual spot light:
/// a 20 m × 20 m floor (a 10 m quad scaled by 2) and a 2 m square floating 2 m above it.
fn write_test_gltf(dir: &std::path::Path, offset: [f64; 3]) -> std::path::PathBuf {
    let pos: [f32; 24] = [
        -5.0, 0.0, -5.0, 5.0, 0.0, -5.0, 5.0, 0.0, 5.0, -5.0, 0.0, 5.0, //
        -0.5, 2.0, -1.0, 0.5, 2.0, -1.0, 0.5, 2.0, 1.0, -0.5, 2.0, 1.0,
    ];
    let idx: [u32; 12] = [0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7];
    let mut bytes: Vec<u8> = pos.iter().flat_map(|v| v.to_le_bytes()).collect();
    bytes.extend(idx.iter().flat_map(|v| v.to_le_bytes()));
    let b64 = {
        const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut s = String::new();
        for c in bytes.chunks(3) {
            let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
            for k in 0..4 {
                if k <= c.len() {
                    s.push(A[(n >> (18 - 6 * k)) as usize & 63] as char);
                } else {
                    s.push('=');
                }
            }
        }
        s
    };
    let half = |a: f64| (a / 2.0).sin();
    let halfc = |a: f64| (a / 2.0).cos();
    let cam_tilt = -(0.5f64).atan(); // look down toward the origin from (0, 5, 10)
    let at = |x: f64, y: f64, z: f64| [x + offset[0], y + offset[1], z + offset[2]];
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "spot", "spot": { "innerConeAngle": 0.3, "outerConeAngle": 0.6 }, "range": 50.0 }
        ] } },
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, 2] }],
        "nodes": [
            { "translation": at(0.0, 0.0, 0.0), "children": [3] },
            { "camera": 0, "translation": at(0.0, 5.0, 10.0), "rotation": [half(cam_tilt), 0.0, 0.0, halfc(cam_tilt)] },
            { "translation": at(0.0, 10.0, 0.0), "rotation": [half(-std::f64::consts::FRAC_PI_2), 0.0, 0.0, halfc(-std::f64::consts::FRAC_PI_2)],
              "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "mesh": 0, "scale": [2.0, 1.0, 2.0] }
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1, "zfar": 100.0 } }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "buffers": [{ "byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{b64}") }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 96 },
            { "buffer": 0, "byteOffset": 96, "byteLength": 48 }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-5.0, 0.0, -5.0], "max": [5.0, 2.0, 5.0] },
            { "bufferView": 1, "componentType": 5125, "count": 12, "type": "SCALAR" }
        ]
    });
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("floating quad.gltf");
    std::fs::write(&p, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    p
}

#[test]
fn gltf_scenes_load_with_camera_light_and_transforms_and_render() {
    let dir = std::env::temp_dir().join(format!("sf-render-gltf-{}", std::process::id()));
    let path = write_test_gltf(&dir, [0.0; 3]);
    let (scene, report) = load_gltf(&path, None, None).unwrap();
    assert!(report.camera_from_file && report.light_from_file && report.primitives == 1, "{report:?}");
    assert_eq!(scene.triangle_count(), 4);
    assert!((scene.bounds.min - DVec3::new(-10.0, 0.0, -10.0)).length() < 1e-9, "scale applied: {:?}", scene.bounds);
    assert!((scene.bounds.max - DVec3::new(10.0, 2.0, 10.0)).length() < 1e-9, "{:?}", scene.bounds);
    assert!((scene.camera.eye - DVec3::new(0.0, 5.0, 10.0)).length() < 1e-6);
    let f = scene.camera.forward.normalize();
    assert!((f - DVec3::new(0.0, -1.0, -2.0).normalize()).length() < 1e-6, "camera looks along its −Z: {f:?}");
    let LightSpec::Spot { position, direction, fovy, far, .. } = scene.light else { panic!("{:?}", scene.light) };
    assert!((position - DVec3::new(0.0, 10.0, 0.0)).length() < 1e-6);
    assert!((direction.normalize() - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-6, "{direction:?}");
    assert!((fovy - 1.2).abs() < 1e-6 && (far - 50.0).abs() < 1e-6);
    // Overrides win.
    let sun = LightSpec::Directional { direction: DVec3::new(0.0, -1.0, 0.2) };
    let (s2, r2) = load_gltf(&path, None, Some(sun)).unwrap();
    assert!(!r2.light_from_file && s2.light == sun);
    assert!(load_scene(path.to_str().unwrap()).is_ok());
    // Malformed files are errors, not panics.
    let broken = dir.join("broken.gltf");
    std::fs::write(&broken, "{ not json").unwrap();
    assert!(matches!(load_gltf(&broken, None, None), Err(RenderError::Gltf { .. })));
    assert!(load_gltf(&dir.join("missing.glb"), None, None).is_err());

    // The floating square casts a shadow on the floor under the spot light.
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(160, 90)).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, 160, 90, 1024);
    if let Some(out) = render(&req) {
        let truth = out.truth.as_ref().unwrap();
        let occluded = truth.iter().filter(|v| **v == Visibility::Occluded).count();
        assert!(occluded > 100, "shadow of the floating square: {occluded} pixels");
        let m = out.metrics.mismatch.unwrap();
        assert!(m.rate_off_edges < 0.01, "{m:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_receiver_facing_the_light_on_the_maps_near_plane_does_not_shadow_itself() {
    // The glTF scene's floating square faces the spot light from the map's near plane (depth 0),
    // where neither a float depth buffer's constant bias nor the slope bias (zero on a surface
    // facing the light) covers the rounding of the receiver's depth: without the main pass's
    // rounding bound, the receiver shadows itself in some pixels away from shadow edges, more of
    // them the farther the scene is from the origin.
    for offset in [[0.0; 3], [3000.5, 0.0, -2000.25]] {
        let dir = std::env::temp_dir().join(format!("sf-render-near-{}", std::process::id()));
        let path = write_test_gltf(&dir, offset);
        let (scene, _) = load_gltf(&path, None, None).unwrap();
        let map = testfit::scene_box_map(&scene, &scene.camera, &scene.light, aspect(160, 90));
        let maps = [map.unwrap()];
        let mut req = RenderRequest::new(&scene, &maps);
        small(&mut req, 160, 90, 1024);
        if let Some(out) = render(&req) {
            let m = out.metrics.mismatch.unwrap();
            assert!(m.off_edge_mismatched * 1000 < m.off_edge_pixels, "{offset:?}: {m:?}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}

#[test]
fn thin_casters_get_right_shadows_wherever_the_maps_resolve_them() {
    // A low sun ahead of an eye-height viewer over a 400 m ground: four parallel splits.
    let scene = builtin_scene("thin-casters").unwrap();
    let (w, h) = (240, 135);
    let maps = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 4).unwrap();
    let util = vec![0.5; maps.len()];
    let mut req = RenderRequest::new(&scene, &maps);
    req.utilisation = &util;
    small(&mut req, w, h, 1024);
    let Some(out) = render(&req) else { return };
    let m = out.metrics.mismatch.unwrap();
    eprintln!("thin-casters: {m:?}");
    assert!(out.metrics.coverage.complete, "{:?}", out.metrics.coverage);
    assert!(m.adequate_pixels > 2_000, "too few adequately sampled pixels to judge: {m:?}");
    assert!(m.rate_adequate <= 0.005, "adequately sampled pixels wrong: {m:?}");
    let truth = out.truth.as_ref().unwrap();
    let occluded = truth.iter().filter(|v| **v == Visibility::Occluded).count();
    assert!(occluded > 1_000, "the view shows shadows: {occluded} pixels");
    assert_eq!(out.metrics.map_utilisation, util);
    assert_eq!(out.metrics.utilisation_mean, Some(0.5));
}

#[test]
fn receiver_plane_bias_removes_acne_without_leaking() {
    // The huge board under a 21° sun: with no bias at all the ground shadows itself; the
    // per-map receiver-plane bias must leave the adequately sampled pixels right, with every
    // filter, kernel taps up to three texels away included.
    let scene = builtin_scene("huge-chessboard").unwrap();
    let (w, h) = (224, 126);
    let maps = testfit::split_maps(&scene, &scene.camera, &scene.light, aspect(w, h), 3).unwrap();
    let mut req = RenderRequest::new(&scene, &maps);
    small(&mut req, w, h, 1024);
    req.settings.depth = DepthMode::Projective { constant: 0, slope_scale: 0.0, receiver_plane: false };
    let Some(none) = render(&req) else { return };
    let none = none.metrics.mismatch.unwrap();
    eprintln!("no bias: {none:?}");
    assert!(
        none.rate_adequate > 0.05 && none.false_shadow > 5 * none.false_light,
        "without a bias the ground must shadow itself: {none:?}"
    );
    for pcf in [Pcf::Off, Pcf::Hardware2x2, Pcf::Kernel { radius: 2 }] {
        req.settings.pcf = pcf;
        req.settings.depth = RenderSettings::default().depth;
        let m = render(&req).unwrap().metrics.mismatch.unwrap();
        eprintln!("{pcf:?}: {m:?}");
        assert!(m.adequate_pixels > 2_000, "{pcf:?}: {m:?}");
        assert!(m.rate_adequate <= 0.005, "{pcf:?}: {m:?}");
    }
}

#[test]
fn utilisation_must_match_the_maps() {
    let scene = builtin_scene("inverted").unwrap();
    let maps = [testfit::scene_box_map(&scene, &scene.camera, &scene.light, 16.0 / 9.0).unwrap()];
    let mut req = RenderRequest::new(&scene, &maps);
    assert!(req.validate().is_ok());
    req.utilisation = &[0.3, 0.4];
    assert!(matches!(req.validate(), Err(RenderError::Invalid { .. })));
    req.utilisation = &[1.5];
    assert!(matches!(req.validate(), Err(RenderError::Invalid { .. })));
    req.utilisation = &[0.3];
    assert!(req.validate().is_ok());
}
