//! Rendered validation on the built-in scenes (llvmpipe in CI): every
//! method's shadows agree with ray-traced ground truth away from shadow
//! edges, warped and split maps beat uniform aliasing at an equal texel
//! budget, inverted PSM lights render correctly, and splits cover every
//! visible pixel.

use glam::DVec3;
use shadowfocus_cli::cli::fit::FitOptions;
use shadowfocus_cli::cli::render::{builtin_ground, demo_configs, fit_scene, scene_settings};
use shadowfocus_cli::cli::sweep::{ADEQUATE_LIMIT, MIN_ADEQUATE_PIXELS};
use shadowfocus_cli::focus::{
    fit, BoxFace, ClipConvention, FocusResult, FocusSettings, Footprint, Ground, Method, PointMode, SplitScheme, VisibleReceivers,
};
use shadowfocus_cli::geom::Aabb;
use shadowfocus_cli::render::{
    builtin_scene, DepthTest, LightSpec, RenderMetrics, RenderOutput, RenderRequest, Renderer, Scene, ShadowMapSpec,
};
use std::sync::Mutex;

const SIZE: (u32, u32) = (320, 180);
const RES: u32 = 1024;

static RENDERER: Mutex<Option<Renderer>> = Mutex::new(None);

fn render(scene: &Scene, opts: &FitOptions) -> RenderMetrics {
    render_with(scene, opts, &scene_settings(scene, opts).unwrap())
}

fn render_with(scene: &Scene, opts: &FitOptions, settings: &FocusSettings) -> RenderMetrics {
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    let (maps, _, _) = fit_scene(scene, SIZE.0 as f64 / SIZE.1 as f64, settings).unwrap();
    let mut req = RenderRequest::new(scene, &maps);
    req.settings.width = SIZE.0;
    req.settings.height = SIZE.1;
    req.settings.shadow_resolution = opts.resolution;
    req.settings.depth_clamp = settings.depth_clamp;
    renderer.render(&req).unwrap().metrics
}

fn scene(name: &str) -> Scene {
    builtin_scene(name).unwrap()
}

#[test]
fn every_method_agrees_with_ground_truth_off_edges() {
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        for (label, opts) in demo_configs(RES) {
            let m = render(&s, &opts);
            let mismatch = m.mismatch.expect("ground truth is on by default");
            // NOTE: thin-casters is built to be undersampled by single maps
            // (slats of 0.12 m up to 220 m away): there only the pixels the
            // map resolves are judged, as in tests/sweep.rs.
            if name == "thin-casters" {
                assert!(
                    mismatch.adequate_pixels >= MIN_ADEQUATE_PIXELS && mismatch.rate_adequate <= ADEQUATE_LIMIT,
                    "{name}/{label}: {:.4} of {} adequately sampled pixels disagree with ray-traced ground truth",
                    mismatch.rate_adequate,
                    mismatch.adequate_pixels
                );
            } else {
                assert!(
                    mismatch.rate_off_edges < 0.01,
                    "{name}/{label}: {:.4} of pixels away from shadow edges disagree with ray-traced ground truth",
                    mismatch.rate_off_edges
                );
            }
            assert!(m.coverage.complete, "{name}/{label}: {} visible pixels lie in no split's map", m.coverage.uncovered);
            assert!(m.aliasing.pixels > 0 && m.aliasing.max.is_finite(), "{name}/{label}: no aliasing samples");
        }
    }
}

#[test]
fn warped_and_split_maps_beat_uniform_at_equal_texel_budget() {
    for name in ["forest", "huge-chessboard"] {
        let s = scene(name);
        let configs = demo_configs(RES);
        let get = |label: &str| configs.iter().find(|(l, _)| l == label).unwrap().1.clone();
        let uniform = render(&s, &get("uniform")).aliasing;
        for label in ["lispsm", "pssm4-lispsm"] {
            let a = render(&s, &get(label)).aliasing;
            assert!(a.max < uniform.max, "{name}: {label} max aliasing {} ≥ uniform {}", a.max, uniform.max);
            assert!(a.p95 < uniform.p95, "{name}: {label} p95 aliasing {} ≥ uniform {}", a.p95, uniform.p95);
        }
    }
}

#[test]
fn inverted_light_renders_correct_shadows_with_psm() {
    let s = scene("inverted");
    let opts = FitOptions { method: Method::Psm, resolution: RES, ..FitOptions::default() };
    // NOTE: the warp guard off, so that the inverted PSM map itself is rendered (the next test
    // checks that it is inverted).
    let settings = FocusSettings { warp_guard: false, ..opts.settings().unwrap() };
    let (maps, _, summary) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &settings).unwrap();
    assert!(!maps.is_empty());
    let m = render_with(&s, &opts, &settings);
    let mismatch = m.mismatch.unwrap();
    assert!(mismatch.rate_off_edges < 0.005, "inverted PSM: off-edge mismatch {:.4}; fit {summary}", mismatch.rate_off_edges);
    assert!(mismatch.rate < 0.02, "inverted PSM: mismatch {:.4}", mismatch.rate);
}

#[test]
fn inverted_scene_really_inverts_the_psm_light() {
    // The scene puts a point light behind the camera: in post-perspective
    // space it lies beyond infinity and PSM must reverse the depth test.
    let s = scene("inverted");
    let opts = FitOptions { method: Method::Psm, resolution: RES, ..FitOptions::default() };
    // NOTE: the warp guard off: the guard may prefer the uniform map here,
    // and this test is about PSM's inverted light itself.
    let settings = FocusSettings { warp_guard: false, ..opts.settings().unwrap() };
    let (maps, _, summary) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &settings).unwrap();
    assert!(maps.iter().any(|m| m.depth_test == DepthTest::Greater), "no reversed depth test in the inverted scene; fit {summary}");
}

#[test]
fn reversed_z_maps_render_the_same_shadows() {
    // The same maps with their depth rows reversed (depth 1 at the light,
    // the greater test; PSM's inverted light then takes the less one) over
    // every built-in scene and method: the renderer draws them into a
    // reversed depth buffer (cleared to 0, compared with "greater") whenever
    // every map of the frame is a "greater" one, and the shadows agree with
    // the default convention's pixel for pixel up to the rounding of the
    // reversed depths.
    let (mut compared, mut reversed_buffers) = (0, 0);
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        for (label, opts) in demo_configs(RES) {
            let settings = scene_settings(&s, &opts).unwrap();
            let reversed = FocusSettings { clip: ClipConvention::WGPU.reversed(), ..settings };
            let (maps, _, _) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &reversed).unwrap();
            let (plain, _, _) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &settings).unwrap();
            assert_eq!(maps.len(), plain.len());
            for (r, p) in maps.iter().zip(&plain) {
                assert_ne!(r.depth_test, p.depth_test, "{name}/{label}: reversed-Z kept the depth test");
            }
            let (plain_run, reversed_run) = (render_with(&s, &opts, &settings), render_with(&s, &opts, &reversed));
            let all_greater = maps.iter().all(|m| m.depth_test == DepthTest::Greater);
            let buffer = if all_greater { DepthTest::Greater } else { DepthTest::Less };
            assert_eq!(reversed_run.shadow_buffer_test, buffer, "{name}/{label}: the renderer's depth buffer");
            reversed_buffers += all_greater as usize;
            let (a, b) = (plain_run.mismatch.unwrap(), reversed_run.mismatch.unwrap());
            eprintln!(
                "{name}/{label}: mismatched {} vs {} reversed, off edges {} vs {}",
                a.mismatched, b.mismatched, a.off_edge_mismatched, b.off_edge_mismatched
            );
            assert_eq!(a.pixels, b.pixels);
            let differ = a.mismatched.abs_diff(b.mismatched) + a.off_edge_mismatched.abs_diff(b.off_edge_mismatched);
            assert!(differ * 2000 <= a.pixels, "{name}/{label}: mismatch {a:?} with the default, {b:?} reversed");
            compared += 1;
        }
    }
    assert_eq!(compared, shadowfocus_cli::render::BUILTIN_SCENES.len() * demo_configs(RES).len());
    // Only PSM's inverted light (flipped back to "less") keeps a frame out of a reversed
    // buffer: PSM's own frames and the Auto splits that take it (38 of 49 use one).
    assert!(reversed_buffers * 4 >= compared * 3, "{reversed_buffers} of {compared} frames used a reversed buffer");
}

#[test]
fn depth_clamped_maps_render_the_same_shadows_with_a_tighter_depth_range() {
    // Every built-in scene and method with each map's depth range fitted to
    // its receivers, rendered with depth clamping: casters toward the light
    // are clamped rather than clipped, so the shadows stay right, and the
    // depth range shrinks (the factor by which the receivers' depth spread
    // grows, measured on the bodies' vertices).
    let aspect = SIZE.0 as f64 / SIZE.1 as f64;
    let (mut factors, mut worse, mut emptied) = (Vec::new(), Vec::new(), 0);
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        let (camera, light, bounds) = shadowfocus_cli::cli::render::scene_inputs(&s, aspect).unwrap();
        for (label, opts) in demo_configs(RES) {
            let plain = scene_settings(&s, &opts).unwrap();
            let clamped = FocusSettings { depth_clamp: true, ..plain };
            let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
            fit(&camera, &light, &bounds, &plain, &mut a).unwrap();
            fit(&camera, &light, &bounds, &clamped, &mut b).unwrap();
            for (x, y) in a.maps().iter().zip(b.maps()).filter(|(x, _)| x.is_active()) {
                if !y.is_active() {
                    emptied += 1; // no receivers: nothing to render
                    continue;
                }
                assert!(y.fit.depth_clamp, "{name}/{label}: an active map was not clamped");
                let z = |m: &glam::DMat4, p: &glam::DVec3| {
                    let q = *m * p.extend(1.0);
                    q.z / q.w
                };
                let (lo, hi) = x.body().vertices().iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(z(&x.fit.clip_from_world, p)), hi.max(z(&x.fit.clip_from_world, p)))
                });
                let (lo2, hi2) = x.body().vertices().iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(z(&y.fit.clip_from_world, p)), hi.max(z(&y.fit.clip_from_world, p)))
                });
                factors.push((hi2 - lo2) / (hi - lo));
            }
            let m = render_with(&s, &opts, &plain);
            let c = render_with(&s, &opts, &clamped);
            assert!(c.depth_clamp, "the renderer did not clamp (adapter {:?} lacks DEPTH_CLIP_CONTROL)", c.adapter);
            let (m, c) = (m.mismatch.unwrap(), c.mismatch.unwrap());
            eprintln!(
                "{name}/{label}: mismatched {} unclamped, {} clamped; off edges {} and {}",
                m.mismatched, c.mismatched, m.off_edge_mismatched, c.off_edge_mismatched
            );
            worse.push(c.off_edge_mismatched as f64 - m.off_edge_mismatched as f64);
            assert!(
                c.off_edge_mismatched <= m.off_edge_mismatched + m.off_edge_pixels / 1000,
                "{name}/{label}: clamped {c:?}, unclamped {m:?}"
            );
        }
    }
    factors.sort_by(f64::total_cmp);
    eprintln!(
        "depth range of H over the receivers' range, {} maps ({emptied} emptied: no receivers): min {:.2}, median {:.2}, max {:.2}; off-edge mismatch change max {}",
        factors.len(),
        factors[0],
        factors[factors.len() / 2],
        factors[factors.len() - 1],
        worse.iter().fold(f64::NEG_INFINITY, |a, b| a.max(*b))
    );
    assert!(factors.iter().all(|f| *f >= 1.0 - 1e-9), "clamping widened a depth range");
    assert!(factors[factors.len() / 2] > 1.0, "clamping tightened no depth range");
}

#[test]
fn receiver_fitted_maps_render_right_shadows_with_finer_texels() {
    // Every built-in scene and method with each map's image fitted to its
    // receivers (plus the default two-texel margin for the 2×2 lookup):
    // the shadows stay right wherever the map resolves them, and the
    // measured aliasing is never worse than the body fit's by more than the
    // margin costs (4 texels of the map's side: 0.4 % of 1024), and better where the body
    // spends texels on casters over nothing visible.
    let mut gains = Vec::new();
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        for (label, opts) in demo_configs(RES) {
            let plain = scene_settings(&s, &opts).unwrap();
            let fitted = FocusSettings { footprint: Footprint::RECEIVERS, ..plain };
            let (a, b) = (render_with(&s, &opts, &plain), render_with(&s, &opts, &fitted));
            let mb = b.mismatch.unwrap();
            eprintln!(
                "{name}/{label}: p95 aliasing {:.3} body, {:.3} receivers; max {:.3}, {:.3}; adequate mismatch {:.4} % of {}",
                a.aliasing.p95,
                b.aliasing.p95,
                a.aliasing.max,
                b.aliasing.max,
                100.0 * mb.rate_adequate,
                mb.adequate_pixels
            );
            assert!(
                mb.adequate_pixels >= MIN_ADEQUATE_PIXELS && mb.rate_adequate <= ADEQUATE_LIMIT,
                "{name}/{label}: {:.4} of {} adequately sampled pixels wrong with receiver-fitted maps",
                mb.rate_adequate,
                mb.adequate_pixels
            );
            // The margin is in each map's own texels: a budget's smallest map pays most.
            let (maps, _, _) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &fitted).unwrap();
            let side = maps.iter().filter_map(|m| m.resolution).min().unwrap_or(opts.resolution);
            let slack = 1.0 + 2.0 * 2.0 / side as f64 + 1e-3;
            assert!(b.aliasing.p95 <= a.aliasing.p95 * slack, "{name}/{label}: p95 {} → {}", a.aliasing.p95, b.aliasing.p95);
            assert!(b.aliasing.max <= a.aliasing.max * slack, "{name}/{label}: max {} → {}", a.aliasing.max, b.aliasing.max);
            gains.push(a.aliasing.p95 / b.aliasing.p95);
        }
    }
    gains.sort_by(f64::total_cmp);
    eprintln!("p95 aliasing gain: min {:.3}, median {:.3}, max {:.3}", gains[0], gains[gains.len() / 2], gains[gains.len() - 1]);
    assert!(gains[gains.len() - 1] > 1.05, "fitting the receivers gained no texels anywhere");
}

#[test]
fn auto_renders_about_as_well_as_the_best_method() {
    // Every built-in scene at an equal texel budget (one 1024² map, four
    // 512² splits): Method::Auto, which picks per map the method of least
    // predicted max aliasing, against each method rendered on its own.
    // Auto never aliases more than the uniform map (the warp guard's bar,
    // 10 % measured), its shadows are right where the maps resolve them, and
    // it comes within 5 % of the best method's measured max and p95 in all
    // but at most one configuration: robot-war's single map (the
    // prediction samples nine receivers, the render every pixel: that is
    // where they part). The chessboard's four splits, 5.6 % above PSM's
    // p95 while a split between the guard's rays kept its warp unjudged,
    // are within 4 %.
    let methods = [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm];
    let (mut configs, mut misses) = (0, Vec::new());
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        for (splits, res) in [(1, RES), (4, RES / 2)] {
            let opts = |method| FitOptions { method, splits, resolution: res, ..FitOptions::default() };
            let single: Vec<RenderMetrics> = methods.iter().map(|m| render(&s, &opts(*m))).collect();
            let auto = render(&s, &opts(Method::Auto));
            let (best_max, best_p95) =
                single.iter().fold((f64::INFINITY, f64::INFINITY), |(a, b), m| (a.min(m.aliasing.max), b.min(m.aliasing.p95)));
            let (a, u) = (&auto.aliasing, &single[0].aliasing);
            eprintln!(
                "{name}/{splits}x{res}: auto max {:.3} p95 {:.3}; best single max {best_max:.3} p95 {best_p95:.3}; uniform {:.3} {:.3}",
                a.max, a.p95, u.max, u.p95
            );
            assert!(a.max <= 1.1 * u.max && a.p95 <= 1.1 * u.p95, "{name}/{splits}x{res}: auto {a:?} against uniform {u:?}");
            let mm = auto.mismatch.unwrap();
            assert!(mm.rate_adequate <= ADEQUATE_LIMIT, "{name}/{splits}x{res}: {mm:?}");
            if a.max > 1.05 * best_max || a.p95 > 1.05 * best_p95 {
                misses.push(format!("{name}/{splits}x{res}"));
            }
            configs += 1;
        }
    }
    eprintln!("auto more than 5 % above the best method in {} of {configs}: {misses:?}", misses.len());
    assert!(misses.len() <= 1, "auto more than 5 % above the best method in {misses:?}");
}

#[test]
fn sdsm_splits_alias_less_than_the_practical_scheme() {
    // Every built-in scene, four LiSPSM splits and four auto splits: fitted
    // to the visible depth range of a pre-pass of the same frame (the
    // default optimal planes placed over it, [SDSM10]) against the practical
    // splits over [near, far] and against the default planes without the
    // range. The shadows stay right and every visible pixel is covered (the
    // range holds every shaded sample); p95 and max aliasing are lower than
    // the practical scheme's everywhere. Against the default planes without
    // the range, p95 is lower in most scenes and nowhere more than 1.5 %
    // higher: the placement's rounds stop at slightly different planes over
    // a different range (measured: LiSPSM 0.9 % higher in one scene,
    // inverted).
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    for method in [Method::Lispsm, Method::Auto] {
        let mut lower = 0;
        for name in shadowfocus_cli::render::BUILTIN_SCENES {
            let s = scene(name);
            let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
            let unhinted = FitOptions { method, splits: 4, resolution: RES / 2, ..FitOptions::default() };
            let practical = FitOptions { scheme: Some("practical".into()), ..unhinted.clone() };
            let sdsm = FitOptions { sdsm: true, ..unhinted.clone() };
            let run =
                |r: &mut Renderer, o: &FitOptions| shadowfocus_cli::cli::render::render_frame(r, &s, &frame, o, SIZE, false, None).unwrap();
            let ((a, _), (u, _), (b, extra)) = (run(renderer, &practical), run(renderer, &unhinted), run(renderer, &sdsm));
            let (a, u, b) = (&a.metrics, &u.metrics, &b.metrics);
            eprintln!(
                "{method:?} {name}: visible depth {}, p95 {:.3} (practical), {:.3} (optimal) → {:.3}, max {:.3}, {:.3} → {:.3}",
                extra["visible_depth"], a.aliasing.p95, u.aliasing.p95, b.aliasing.p95, a.aliasing.max, u.aliasing.max, b.aliasing.max
            );
            assert!(extra["visible_depth"].is_array() && extra["scheme"] == "optimal", "{name}: {extra}");
            assert!(b.coverage.complete, "{name}: a visible pixel outside every map: {:?}", b.coverage);
            let m = b.mismatch.unwrap();
            assert!(m.rate_adequate <= ADEQUATE_LIMIT, "{name}: {m:?}");
            assert!(b.aliasing.p95 < a.aliasing.p95 && b.aliasing.max < a.aliasing.max, "{name}: {:?} → {:?}", a.aliasing, b.aliasing);
            assert!(b.aliasing.p95 <= 1.015 * u.aliasing.p95, "{method:?} {name}: {:?} → {:?}", u.aliasing, b.aliasing);
            lower += usize::from(b.aliasing.p95 < u.aliasing.p95);
        }
        assert!(lower >= 6, "{method:?}: the range lowers p95 against the default planes in {lower} of 7 scenes");
    }
}

/// The receiver hints the prediction tests run: none, the scene's receiver
/// boxes, the scene box's floor as the ground, and the scene's own ground
/// (`builtin_ground`: the slabs' tops).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Hint {
    None,
    Boxes,
    Floor,
    Ground,
}

impl Hint {
    const ALL: [Hint; 4] = [Hint::None, Hint::Boxes, Hint::Floor, Hint::Ground];

    fn ground(self, scene: &str) -> Option<Ground> {
        match self {
            Hint::Floor => Some(BoxFace::MinY.into()),
            Hint::Ground => Some(builtin_ground(scene)),
            _ => None,
        }
    }
}

#[test]
fn optimal_splits_render_right_and_alias_less_than_practical() {
    // Every built-in scene, four splits at half resolution each, LiSPSM and
    // Auto, under each receiver hint: planes placed per light for even
    // predicted aliasing (the default) against the practical planes. Shadows
    // stay right, every visible pixel is covered, p95 is lower everywhere and
    // the maximum never higher, lower in all but one scene (the forest's
    // worst pixel is its nearest terrain, in a first split the placement
    // does not lengthen and cannot see to shorten). Auto, told where the
    // receivers are (their boxes, or the scene's ground), stays within 2× of
    // the logarithmic bound in every scene (measured: at most 1.78×, thin
    // casters).
    for method in [Method::Lispsm, Method::Auto] {
        for hint in Hint::ALL {
            let (mut lower, mut p95_lower) = (0, 0);
            for name in shadowfocus_cli::render::BUILTIN_SCENES {
                let s = scene(name);
                let (boxes, ground) = (hint == Hint::Boxes, hint.ground(name));
                let optimal = FitOptions { method, splits: 4, resolution: RES / 2, ground, ..FitOptions::default() };
                let practical = FitOptions { scheme: Some("practical".into()), ..optimal.clone() };
                let mut settings = optimal.settings().unwrap();
                assert_eq!(settings.splits.scheme, SplitScheme::Optimal, "the default");
                if boxes {
                    settings.receivers = shadowfocus_cli::cli::render::receiver_boxes(&s).unwrap();
                }
                let (a, b) = (render(&s, &practical), render_with(&s, &optimal, &settings));
                eprintln!(
                    "{name} {method:?} {hint:?} {ground:?}: max {:.3} → {:.3}, p95 {:.3} → {:.3}, ×bound {:.2}",
                    a.aliasing.max, b.aliasing.max, a.aliasing.p95, b.aliasing.p95, b.aliasing.ratio
                );
                assert!(b.coverage.complete, "{name}: a visible pixel outside every map: {:?}", b.coverage);
                let m = b.mismatch.unwrap();
                assert!(m.rate_adequate <= ADEQUATE_LIMIT, "{name}: {m:?}");
                assert!(
                    b.aliasing.max <= a.aliasing.max && b.aliasing.p95 <= a.aliasing.p95,
                    "{name} {method:?}: {:?} → {:?}",
                    a.aliasing,
                    b.aliasing
                );
                if method == Method::Auto && matches!(hint, Hint::Boxes | Hint::Ground) {
                    assert!(b.aliasing.ratio <= 2.0, "{name} {hint:?}: {:?}", b.aliasing);
                }
                lower += usize::from(b.aliasing.max < a.aliasing.max);
                p95_lower += usize::from(b.aliasing.p95 < a.aliasing.p95);
            }
            let scenes = shadowfocus_cli::render::BUILTIN_SCENES.len();
            assert!(lower + 1 >= scenes, "{method:?} {hint:?}: max lower in {lower} scenes");
            // NOTE: on the ground, Auto's practical planes in the forest
            // choose the maps of its default planes' first split, which holds
            // the view's p95 too.
            let p95_missed = usize::from(matches!(hint, Hint::Floor | Hint::Ground) && method == Method::Auto);
            assert!(p95_lower + p95_missed >= scenes, "{method:?} {hint:?}: p95 lower in {p95_lower} scenes");
        }
    }
}

#[test]
fn visible_receivers_bring_every_scene_within_twice_the_bound() {
    // Every built-in scene, Auto over four splits at half resolution each,
    // with boxes around what a pre-pass of the frame sees
    // (`--visible-receivers`): no scene knowledge, only the depth buffer.
    // Shadows right, every visible pixel covered; the maximum no higher than
    // without the boxes (1 % for rounding) nor than on the practical planes,
    // and within 2× of the logarithmic bound in every scene (without them
    // thin casters are at 4.29×, their scene box's floor 2 m below the
    // ground seen; with them at most 1.79×, thin casters).
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
        let visible = FitOptions { method: Method::Auto, splits: 4, resolution: RES / 2, visible_receivers: true, ..FitOptions::default() };
        let plain = FitOptions { visible_receivers: false, ..visible.clone() };
        let practical = FitOptions { scheme: Some("practical".into()), ..plain.clone() };
        let mut run = |o: &FitOptions| {
            let (out, extra) = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, o, SIZE, false, None).unwrap();
            (out.metrics, extra["receiver_boxes"].as_u64().unwrap())
        };
        let ((v, count), (n, _), (p, _)) = (run(&visible), run(&plain), run(&practical));
        eprintln!(
            "{name}: {count} visible boxes, max {:.3} (×bound {:.2}); without them {:.3} ({:.2}); practical {:.3}",
            v.aliasing.max, v.aliasing.ratio, n.aliasing.max, n.aliasing.ratio, p.aliasing.max
        );
        assert!(count >= 1, "{name}: the pre-pass saw no receiver");
        assert!(v.coverage.complete, "{name}: a visible pixel outside every map: {:?}", v.coverage);
        let m = v.mismatch.unwrap();
        assert!(m.rate_adequate <= ADEQUATE_LIMIT, "{name}: {m:?}");
        assert!(v.aliasing.max <= 1.01 * n.aliasing.max, "{name}: {:?} against {:?} without the boxes", v.aliasing, n.aliasing);
        assert!(v.aliasing.max <= p.aliasing.max, "{name}: {:?} against practical {:?}", v.aliasing, p.aliasing);
        assert!(v.aliasing.ratio <= 2.0, "{name}: {:?}", v.aliasing);
    }
}

#[test]
fn a_texel_budget_lowers_the_maximum_of_equal_maps() {
    // Every built-in scene, Auto with the default (optimal) planes, without
    // and with receiver boxes: four 512² maps against the same 4·512² texels
    // shared by predicted aliasing (any sizes, each at most 1024²). Shadows
    // stay right, every visible pixel is covered, the budget holds, the
    // maximum is never more than 1 % higher and p95 never more than 2 %
    // (where the planes already even out the predicted maxima, the sides
    // move by a few texels and the measured figures with them: robot war
    // with boxes, maximum +0.5 %; the sides follow the maxima, not p95:
    // chessboard with boxes, p95 +1.2 %). Where the equal maps' predicted
    // maxima differ by 10 % or more there is something to share, and the
    // measured maximum is lower by at least 2 %; where the planes have
    // evened the predictions out, there is little to share.
    const BUDGET: u64 = 4 * 512 * 512;
    let mut uneven = 0;
    for boxes in [false, true] {
        for name in shadowfocus_cli::render::BUILTIN_SCENES {
            let s = scene(name);
            let equal = FitOptions { method: Method::Auto, splits: 4, resolution: RES / 2, receiver_boxes: boxes, ..FitOptions::default() };
            let shared = FitOptions { resolution: RES, budget: Some(BUDGET), ..equal.clone() };
            let (a, b) = (render(&s, &equal), render(&s, &shared));
            let aspect = SIZE.0 as f64 / SIZE.1 as f64;
            let (maps, _, summary) = fit_scene(&s, aspect, &scene_settings(&s, &shared).unwrap()).unwrap();
            let (_, _, before) = fit_scene(&s, aspect, &scene_settings(&s, &equal).unwrap()).unwrap();
            let predicted: Vec<f64> = before["predicted_aliasing"].as_array().unwrap().iter().filter_map(|p| p.as_f64()).collect();
            let spread = predicted.iter().copied().fold(0.0, f64::max) / predicted.iter().copied().fold(f64::INFINITY, f64::min);
            let sides: Vec<u64> = maps.iter().map(|m| u64::from(m.resolution.unwrap())).collect();
            eprintln!(
                "{name} boxes {boxes}: predictions {spread:.3}× apart, sides {sides:?}, max {:.3} → {:.3}, p95 {:.3} → {:.3}, ×bound {:.2} → {:.2} ({})",
                a.aliasing.max, b.aliasing.max, a.aliasing.p95, b.aliasing.p95, a.aliasing.ratio, b.aliasing.ratio, summary["resolutions"]
            );
            assert!(sides.iter().map(|r| r * r).sum::<u64>() <= BUDGET && sides.iter().all(|&r| r <= u64::from(RES)), "{name}: {sides:?}");
            assert!(b.coverage.complete, "{name}: a visible pixel outside every map: {:?}", b.coverage);
            let m = b.mismatch.unwrap();
            assert!(m.rate_adequate <= ADEQUATE_LIMIT, "{name}: {m:?}");
            assert!(b.aliasing.max <= a.aliasing.max * 1.01, "{name} boxes {boxes}: {:?} → {:?}", a.aliasing, b.aliasing);
            assert!(b.aliasing.p95 <= a.aliasing.p95 * 1.02, "{name} boxes {boxes}: {:?} → {:?}", a.aliasing, b.aliasing);
            if spread >= 1.1 {
                uneven += 1;
                assert!(
                    b.aliasing.max < a.aliasing.max * 0.98,
                    "{name} boxes {boxes}: predictions {spread}× apart, max {:?} → {:?}",
                    a.aliasing,
                    b.aliasing
                );
            }
        }
    }
    // The scenes have something to share (three of the fourteen): the rule
    // above is not vacuous.
    assert!(uneven >= 3, "only {uneven} configurations with uneven predictions");
}

#[test]
fn predicted_aliasing_agrees_with_the_measured_maximum() {
    // Every built-in scene and single-projection method, one map: the
    // maximum `predict_aliasing` gives from the matrices (in pixels) against
    // the renderer's measured maximum over the pixels the map serves.
    // Without receiver boxes the prediction's receivers are the scene box's
    // faces, so it agrees where the worst receiver is such a face and is
    // off, both ways, where casters stand in front of the faces or a far
    // face is not seen: within 4× either way everywhere, within 5 % in at
    // least a third of the configurations. With the scene's receiver boxes
    // it agrees within 5 % in at least two thirds, and is nowhere more than
    // 5 % above the measurement (the surface in a box lies at or beyond the
    // face a ray enters it through; below it where that surface is farther,
    // a terrain seen from inside its box). On the scene box's floor as the
    // ground (`--ground min-y`) it agrees within 5 % in at least half, and is
    // nowhere more than 5 % above the measurement either: what stands on the
    // ground, and a slab's top above the box's floor, are nearer. On the
    // scenes' own grounds (`builtin_ground`: the slabs' tops) it agrees as the
    // receiver boxes do.
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    for hint in Hint::ALL {
        let (mut close, mut all) = (0, 0);
        for name in shadowfocus_cli::render::BUILTIN_SCENES {
            let s = scene(name);
            let (boxes, ground) = (hint == Hint::Boxes, hint.ground(name));
            let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
            let mut row = format!("| {name} |");
            for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
                let o = FitOptions { method, resolution: RES, receiver_boxes: boxes, ground, ..FitOptions::default() };
                let (out, extra) = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, &o, SIZE, false, None).unwrap();
                let measured = out.metrics.map_aliasing_max[0];
                let predicted = extra["predicted_aliasing_px"][0].as_f64().unwrap();
                let r = measured / predicted;
                row += &format!(" {measured:.3} / {predicted:.3} |");
                assert!((0.25..=4.0).contains(&r), "{name} {method:?} {hint:?}: measured {measured}, predicted {predicted}");
                assert!(hint == Hint::None || r >= 0.95, "{name} {method:?}: measured {measured}, predicted {predicted} on {hint:?}");
                all += 1;
                if (r - 1.0).abs() <= 0.05 {
                    close += 1;
                }
            }
            eprintln!("{row}");
        }
        eprintln!("{hint:?}: within 5 %: {close} of {all}");
        let share = match hint {
            Hint::Boxes | Hint::Ground => 3 * close >= 2 * all,
            Hint::Floor => 2 * close >= all,
            Hint::None => 3 * close >= all,
        };
        assert!(share, "{hint:?}: within 5 % in {close} of {all}");
    }
}

#[test]
fn receivers_at_a_maps_far_face_are_not_shadowed_by_nothing() {
    // A sun low behind a viewer 1.7 m above the ground: each split's
    // farthest point from the light is its receivers at its far end, on the
    // map's far depth face. Sweeping the first split's length (engine-style
    // geometric planes) moves those receivers across the map's texel rows, so
    // that in some configurations a pixel row's receivers sit within a texel
    // of the far face, where the receiver-plane filter's taps read texels
    // that nothing was drawn into. Those must read as lit.
    let s = scene("robot-war");
    let o = shadowfocus_cli::cli::overrides::Overrides {
        camera: Some(shadowfocus_cli::cli::overrides::parse_camera("-20,1.7,-590,0.08,-0.04,1,60,0.1,1000").unwrap()),
        light: Some(shadowfocus_cli::cli::overrides::parse_light("directional:0.078534,-0.173648,0.981671").unwrap()),
    };
    let frame = shadowfocus_cli::cli::overrides::Frame::with(&s, &o).unwrap();
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    for k in 0..9 {
        let first = 9.0 + 0.25 * k as f64;
        let opts = FitOptions {
            method: Method::Uniform,
            splits: 4,
            resolution: RES / 2,
            scheme: Some(format!("geometric:{first}")),
            ..FitOptions::default()
        };
        let (out, _) = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, &opts, SIZE, false, None).unwrap();
        let m = out.metrics.mismatch.unwrap();
        assert!(m.adequate_pixels >= MIN_ADEQUATE_PIXELS, "first split {first}: {m:?}");
        assert!(m.rate_adequate <= ADEQUATE_LIMIT, "first split {first}: {m:?}");
    }
}

#[test]
fn the_gpu_reduces_the_visible_depth_range_as_the_cpu_does() {
    // Every built-in scene: the compute pass's least and greatest view depth
    // of the pixels that see geometry against the same reduction of the
    // read-back positions in f64, to the f32 rounding of a depth (the
    // adapter here, llvmpipe through GL 4.5, has compute shaders: a build
    // that lost the pass fails rather than skips).
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    assert!(renderer.adapter().compute, "{:?}", renderer.adapter());
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
        let (out, _) = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, &FitOptions::default(), SIZE, false, None).unwrap();
        let gpu = out.visible_depth.unwrap_or_else(|| panic!("{name}: no visible depth from the GPU"));
        let cpu = shadowfocus_cli::cli::render::cpu_visible_depth(&out).unwrap();
        let tol = 8.0 * f32::EPSILON as f64 * (out.camera.eye.length() + cpu[1]);
        for k in 0..2 {
            assert!((gpu[k] as f64 - cpu[k]).abs() <= tol, "{name}: GPU {gpu:?}, CPU {cpu:?}");
        }
        assert!(cpu[0] >= out.camera.near * (1.0 - 1e-6) && cpu[1] <= out.camera.far * (1.0 + 1e-6), "{name}: {cpu:?}");
    }
}

#[test]
fn the_gpu_reduces_the_visible_receivers_as_the_cpu_does() {
    // Every built-in scene, rendered as `--visible-receivers` renders it:
    // the compute pass's slices against the read-back receiver pixels. The
    // slices' bounds together are the pixels' bounds bit for bit (min and
    // max round nothing); each pixel lies in the slice of the axis its
    // normal faces and its f64 depth falls in, or, within the f32 rounding
    // of a depth of a plane, in the slice beside it; each slice's greatest
    // depth lies in its depth range and is a pixel's; the boxes from the
    // slices hold every pixel and are the CPU's.
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    assert!(renderer.adapter().compute, "{:?}", renderer.adapter());
    let opts = FitOptions { method: Method::Auto, splits: 4, resolution: RES / 2, visible_receivers: true, ..FitOptions::default() };
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let s = scene(name);
        let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
        let (out, _) = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, &opts, SIZE, false, None).unwrap();
        let slices = out.receiver_slices.unwrap_or_else(|| panic!("{name}: no receiver slices from the GPU"));
        let (camera, _, _) = shadowfocus_cli::cli::render::frame_inputs(&s, &frame, SIZE.0 as f64 / SIZE.1 as f64).unwrap();
        let planes = VisibleReceivers::new(&camera, SIZE.1).unwrap().slice_planes().to_vec();
        let forward = camera.forward.normalize();
        let dvec = |p: &[f32; 4]| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
        let points: Vec<(DVec3, usize)> = out
            .world
            .iter()
            .zip(&out.normal)
            .filter(|(w, _)| w[3] == 1.0)
            .map(|(w, n)| (dvec(w), VisibleReceivers::facing(dvec(n)).unwrap()))
            .collect();
        assert!(points.len() > 1000, "{name}: {} receiver pixels", points.len());
        // (axis, slice, bounds, greatest depth) of each slice that holds a pixel.
        let filled: Vec<(usize, usize, Aabb, f64)> = (0..3)
            .flat_map(|axis| (0..slices[axis].len()).map(move |k| (axis, k)))
            .filter_map(|(axis, k)| {
                let s = slices[axis][k]?;
                Some((axis, k, Aabb { min: s.min.map(f64::from).into(), max: s.max.map(f64::from).into() }, s.far as f64))
            })
            .collect();
        let facings = (0..3).filter(|&a| filled.iter().any(|f| f.0 == a)).count();
        assert!(facings >= if name == "huge-chessboard" { 2 } else { 1 }, "{name}: the slab's top and side face apart");
        let bounds = |b: &mut Aabb, p: DVec3, q: DVec3| (b.min, b.max) = (b.min.min(p), b.max.max(q));
        let empty = Aabb { min: DVec3::INFINITY, max: DVec3::NEG_INFINITY };
        let (mut all, mut of_slices) = (empty, empty);
        points.iter().for_each(|&(p, _)| bounds(&mut all, p, p));
        filled.iter().for_each(|(_, _, b, _)| bounds(&mut of_slices, b.min, b.max));
        assert_eq!(all, of_slices, "{name}: the slices' bounds are not the pixels'");
        let depth_tol = |z: f64| 8.0 * f32::EPSILON as f64 * (camera.eye.length() + z.abs());
        let holds = |axis: usize, k: usize, p: DVec3| filled.iter().any(|(a, j, b, _)| (*a, *j) == (axis, k) && b.contains(p));
        for &(p, axis) in &points {
            let z = (p - camera.eye).dot(forward);
            let k = planes.partition_point(|&c| c <= z);
            let beside = |j: usize| planes.get(j).is_some_and(|&c| (z - c).abs() <= depth_tol(z));
            let found = holds(axis, k, p) || (k > 0 && beside(k - 1) && holds(axis, k - 1, p)) || (beside(k) && holds(axis, k + 1, p));
            assert!(found, "{name}: the pixel at {p} (facing {axis}, depth {z}, slice {k}) is in no slice it may fall in");
        }
        let depths: Vec<f64> = points.iter().map(|&(p, _)| (p - camera.eye).dot(forward)).collect();
        for (_, k, _, far) in &filled {
            let (lo, hi) = (if *k == 0 { f64::NEG_INFINITY } else { planes[k - 1] }, planes.get(*k).copied().unwrap_or(f64::INFINITY));
            assert!(
                *far >= lo - depth_tol(*far) && *far <= hi + depth_tol(*far),
                "{name}: slice {k}'s far depth {far} outside [{lo}, {hi})"
            );
            assert!(depths.iter().any(|z| (z - far).abs() <= depth_tol(*far)), "{name}: slice {k}'s far depth {far} is no pixel's");
        }
        let boxes = shadowfocus_cli::cli::render::visible_receiver_boxes(&out, &camera).unwrap();
        assert!(boxes.is_seen(), "{name}");
        // On the boxes' grid the f32 reduction's last bits are gone: the
        // CPU's gathering of the same pixels in f64 gives the same boxes.
        let cpu = shadowfocus_cli::cli::render::cpu_visible_receivers(&out, &camera).unwrap();
        assert_eq!(boxes, cpu.boxes(cpu.magnitude() / 65536.0).unwrap(), "{name}");
        for &(p, _) in &points {
            assert!(boxes.as_slice().iter().any(|b| b.contains(p)), "{name}: the pixel at {p} is in no box");
        }
    }
}

#[test]
fn the_renderer_refuses_what_it_cannot_render_right() {
    // wgpu keeps clip depth in [0, 1]: OpenGL's [−1, 1] maps would lose
    // every caster in front of the map's middle. Refused, with the reason.
    let s = scene("chessboard");
    let opts = FitOptions { clip: ClipConvention::OPENGL, ..FitOptions::default() };
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    let frame = shadowfocus_cli::cli::overrides::Frame::of(&s);
    let err = shadowfocus_cli::cli::render::render_frame(renderer, &s, &frame, &opts, SIZE, false, None).unwrap_err();
    assert!(err.contains("[0, 1]"), "{err}");
}

/// Point lights with six cube faces, three positions per built-in scene (ahead of the eye and
/// above it, in proportion to the scene's size): shadows agree with ray-traced ground truth
/// wherever the maps resolve them, every visible pixel is covered, and every pixel was looked up
/// in the face of its own direction from the light. A face's image may reach past its 90° cone
/// into a neighbour's (the test asserts that it does, on many pixels); the casters on the light
/// rays there are in the neighbour's map, not in this face's.
#[test]
fn point_light_cube_faces_answer_for_their_own_cones() {
    let (mut overlapping, mut judged) = (0u64, 0u64);
    for name in shadowfocus_cli::render::BUILTIN_SCENES {
        let mut s = scene(name);
        let c = s.camera;
        let (forward, diag) = (c.forward.normalize(), (s.bounds.max - s.bounds.min).length());
        for (along, above) in [(0.1, 0.05), (0.3, 0.1), (0.5, 0.2)] {
            let light = c.eye + forward * (along * c.far.min(diag)) + DVec3::Y * (above * diag);
            s.light = LightSpec::Point { position: light };
            let settings = FocusSettings { method: Method::Uniform, point: PointMode::Cube, resolution: RES, ..FocusSettings::default() };
            let (maps, _, _) = fit_scene(&s, SIZE.0 as f64 / SIZE.1 as f64, &settings).unwrap();
            assert!(maps.iter().all(|m| m.face.is_some()), "{name}: every map a cube face");
            let out = render_output(&s, &maps, RES);
            let label = format!("{name}, light at {light}");
            let mismatch = out.metrics.mismatch.unwrap();
            assert!(
                mismatch.adequate_pixels >= MIN_ADEQUATE_PIXELS && mismatch.rate_adequate <= ADEQUATE_LIMIT,
                "{label}: {:.4} of {} adequately sampled pixels disagree with ray-traced ground truth",
                mismatch.rate_adequate,
                mismatch.adequate_pixels
            );
            assert!(out.metrics.coverage.complete, "{label}: {} visible pixels lie in no face", out.metrics.coverage.uncovered);
            for (w, &k) in out.world.iter().zip(&out.split) {
                if w[3] != 1.0 || k < 0 {
                    continue;
                }
                let p = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
                let d = (p - light).abs();
                let mut a = [d.x, d.y, d.z];
                a.sort_by(f64::total_cmp);
                // NOTE: the shader picks the face from p − light in f32; where the two largest
                // coordinates are within its rounding, either face holds p (the cones overlap).
                if a[2] - a[1] <= 1e-5 * a[2] {
                    continue;
                }
                judged += 1;
                let face = maps[k as usize].face.unwrap();
                assert!(face.holds(p), "{label}: pixel at {p} looked up in face {} outside its cone", face.index);
                let images = maps.iter().filter(|m| in_image(&m.world_to_clip.as_dmat4(), p)).count();
                overlapping += u64::from(images > 1);
            }
        }
    }
    assert!(overlapping > 1000, "faces' images overlap on only {overlapping} of {judged} judged pixels: the test sees too few");
}

fn render_output(scene: &Scene, maps: &[ShadowMapSpec], resolution: u32) -> RenderOutput {
    let mut guard = RENDERER.lock().unwrap_or_else(|e| e.into_inner());
    let renderer = guard.get_or_insert_with(|| Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)"));
    let mut req = RenderRequest::new(scene, maps);
    req.settings.width = SIZE.0;
    req.settings.height = SIZE.1;
    req.settings.shadow_resolution = resolution;
    renderer.render(&req).unwrap()
}

fn in_image(m: &glam::DMat4, p: DVec3) -> bool {
    let c = *m * p.extend(1.0);
    c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
}
