//! Temporal stability (llvmpipe in CI): the CPU shadow lookup that
//! `animate` measures with agrees with the rendered shadows, and stable
//! uniform and LiSPSM maps hold still along a camera path where plain ones
//! flicker.

use glam::DVec3;
use shadowfocus_cli::cli::animate::{animate, AnimateOptions, CameraPath};
use shadowfocus_cli::cli::fit::FitOptions;
use shadowfocus_cli::cli::overrides::{parse_light, LightOverride};
use shadowfocus_cli::cli::render::fit_scene;
use shadowfocus_cli::focus::{DepthHintCoverage, Method};
use shadowfocus_cli::render::{builtin_scene, Pcf, RenderRequest, Renderer};
use std::sync::Mutex;

/// One render at a time: the tests share the machine's cores.
static GPU: Mutex<()> = Mutex::new(());

#[test]
fn the_cpu_lookup_agrees_with_the_rendered_shadow() {
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let mut renderer = Renderer::from_env().expect("a wgpu adapter (llvmpipe on a fresh machine)");
    for (name, method) in [("forest", Method::Uniform), ("robot-war", Method::Lispsm), ("inverted", Method::Psm)] {
        let scene = builtin_scene(name).unwrap();
        let opts = FitOptions { method, ..FitOptions::default() };
        let (maps, _, _) = fit_scene(&scene, 320.0 / 180.0, &opts.settings().unwrap()).unwrap();
        let mut req = RenderRequest::new(&scene, &maps);
        (req.settings.width, req.settings.height, req.settings.pcf) = (320, 180, Pcf::Off);
        let out = renderer.render(&req).unwrap();
        let (mut compared, mut differ) = (0u32, 0u32);
        for i in 0..out.world.len() {
            let (w, n) = (out.world[i], out.normal[i]);
            if w[3] != 1.0 || out.split[i] < 0 {
                continue;
            }
            let p = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
            let Some(lit) = out.lit_at(p, DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)) else { continue };
            compared += 1;
            differ += u32::from(lit != (out.shadow[i] >= 0.5));
        }
        // NOTE: the GPU evaluates the same test in f32 from the f32 world
        // position it interpolated, so a few pixels on shadow edges may fall
        // on the other side; anything more is a different test.
        eprintln!("{name}: {differ} of {compared} receiver pixels differ");
        assert!(compared > 10_000, "{name}: only {compared} receiver pixels found a map");
        assert!(f64::from(differ) <= 0.005 * f64::from(compared), "{name}: {differ} of {compared} pixels differ");
    }
}

fn run(stable: bool, dir: &str) -> serde_json::Value {
    run_in("forest", None, stable, dir)
}

fn run_in(scene: &str, light: Option<LightOverride>, stable: bool, dir: &str) -> serde_json::Value {
    run_method(scene, light, Method::Uniform, stable, dir)
}

fn run_method(scene: &str, light: Option<LightOverride>, method: Method, stable: bool, dir: &str) -> serde_json::Value {
    let fit = FitOptions { method, stable, ..FitOptions::default() };
    let out = std::env::temp_dir().join(format!("shadowfocus-temporal-{}-{dir}", std::process::id()));
    let o = AnimateOptions { scene: scene.into(), path: CameraPath::Orbit, frames: 24, size: (320, 180), light, fit, out: out.clone() };
    let summary = animate(&o).unwrap();
    assert!(out.join("strip.png").is_file() && out.join("frames.csv").is_file() && out.join("temporal.json").is_file());
    let zoom = shadowfocus_cli::render::Image::load_png(&out.join("zoom.png")).unwrap();
    assert!(zoom.width > 0 && zoom.height > 0, "zoom.png is an image");
    std::fs::remove_dir_all(&out).unwrap();
    summary
}

/// The robot war's 24-frame orbit animated with `fit`, in a folder named
/// by `tag`: the summary, or animate's refusal.
fn robot_war_orbit(fit: FitOptions, tag: &str) -> Result<serde_json::Value, String> {
    let out = std::env::temp_dir().join(format!("shadowfocus-temporal-{}-{tag}", std::process::id()));
    let o = AnimateOptions {
        scene: "robot-war".into(),
        path: CameraPath::Orbit,
        frames: 24,
        size: (320, 180),
        light: None,
        fit,
        out: out.clone(),
    };
    let summary = animate(&o);
    let _ = std::fs::remove_dir_all(&out);
    summary
}

#[test]
fn stable_uniform_maps_hold_still_where_plain_ones_flicker() {
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let (plain, stable) = (run(false, "plain"), run(true, "stable"));
    let f = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k} missing in {s}"));
    assert!(f(&plain, "point_frames_near_edges") > 1000.0, "too few probes near edges: {plain}");
    assert!(f(&plain, "flicker_near_edges") > 0.01, "the plain map's edges should crawl on an orbit: {plain}");
    assert!(f(&stable, "flicker_near_edges") * 10.0 <= f(&plain, "flicker_near_edges"), "plain {plain}\nstable {stable}");
    assert!(f(&stable, "flicker") * 10.0 <= f(&plain, "flicker").max(1e-9), "plain {plain}\nstable {stable}");
    assert_eq!(stable["misses"], 0, "{stable}");
    assert_eq!(plain["misses"], 0, "{plain}");
}

/// A spot light over the chessboard: its plain map, fitted to the body each
/// frame, crawls; the stable one (the spot's own frame, extents in quarter
/// octaves, texel-snapped) holds still.
#[test]
fn stable_spot_maps_hold_still_where_plain_ones_flicker() {
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let spot = || Some(parse_light("spot:2,14,4,-0.15,-1,-0.3,75").unwrap());
    let (plain, stable) = (run_in("chessboard", spot(), false, "spot-plain"), run_in("chessboard", spot(), true, "spot-stable"));
    let f = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k} missing in {s}"));
    assert!(f(&plain, "point_frames_near_edges") > 1000.0, "too few probes near edges: {plain}");
    // NOTE: measured 0.0106 here (24 frames). Counted also at the probes the light does not
    // reach (back-facing, outside the pyramid), where no shadow shows, it was 0.152: most of
    // them on a wall in the light's own plane.
    assert!(f(&plain, "flicker_near_edges") > 0.005, "the plain spot map's edges should crawl on an orbit: {plain}");
    assert!(f(&plain, "flicker_near_edges") < 0.05, "flips counted where the light does not reach? {plain}");
    assert!(f(&stable, "flicker_near_edges") * 10.0 <= f(&plain, "flicker_near_edges"), "plain {plain}\nstable {stable}");
    assert_eq!(stable["misses"], 0, "{stable}");
}

/// Stable LiSPSM on the duelling-frusta orbit: its warp's lattice steps hold
/// (the carried state does not change), so it holds still where plain
/// LiSPSM crawls, and it keeps the warp's gain: p95 aliasing at most half
/// the stable uniform map's and at most twice plain LiSPSM's.
#[test]
fn stable_lispsm_maps_hold_still_and_keep_their_gain() {
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let scene = "duelling-frusta";
    let plain = run_method(scene, None, Method::Lispsm, false, "lispsm-plain");
    let stable = run_method(scene, None, Method::Lispsm, true, "lispsm-stable");
    let uniform = run_method(scene, None, Method::Uniform, true, "lispsm-uniform-stable");
    let f = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap_or_else(|| panic!("{k} missing in {s}"));
    assert!(f(&plain, "point_frames_near_edges") > 1000.0, "too few probes near edges: {plain}");
    assert!(f(&plain, "flicker_near_edges") > 0.01, "plain LiSPSM's edges should crawl on an orbit: {plain}");
    assert!(f(&stable, "flicker_near_edges") * 10.0 <= f(&plain, "flicker_near_edges"), "plain {plain}\nstable {stable}");
    assert_eq!(stable["state_changes"], 0, "{stable}");
    assert_eq!(stable["misses"], 0, "{stable}");
    let p95 = |s: &serde_json::Value| f(s, "aliasing_p95_mean");
    assert!(2.0 * p95(&stable) <= p95(&uniform), "stable LiSPSM {stable}\nstable uniform {uniform}");
    assert!(p95(&stable) <= 2.0 * p95(&plain), "stable LiSPSM {stable}\nplain LiSPSM {plain}");
}

#[test]
fn visible_receivers_a_frame_old_lower_p95_on_an_orbit() {
    // Auto's four splits on boxes around what the previous frame's main pass
    // saw (`--visible-receivers`, one frame of latency, the first frame from
    // its own pre-pass): the boxes steer the prediction only, so no map
    // misses its body and no pixel is left without a map, and p95 drops
    // against the same splits without them. Maps fitted to receivers would
    // lose what comes into view since: refused.
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let run = |visible_receivers: bool, fit_receivers: bool| {
        let fit =
            FitOptions { method: Method::Auto, splits: 4, resolution: 512, visible_receivers, fit_receivers, ..FitOptions::default() };
        robot_war_orbit(fit, &format!("visible-{visible_receivers}"))
    };
    let (plain, visible) = (run(false, false).unwrap(), run(true, false).unwrap());
    eprintln!("plain {plain}\nvisible {visible}");
    assert_eq!((plain["visible_receivers"].as_bool(), visible["visible_receivers"].as_bool()), (Some(false), Some(true)));
    assert_eq!((visible["misses"].as_u64(), visible["uncovered_pixels"].as_u64()), (Some(0), Some(0)), "{visible}");
    let p95 = |s: &serde_json::Value| s["aliasing_p95_mean"].as_f64().unwrap();
    // NOTE: measured 0.607 against 0.743 over 60 frames.
    assert!(p95(&visible) < 0.9 * p95(&plain), "p95 {} with the boxes, {} without", p95(&visible), p95(&plain));
    let refused = run(true, true).unwrap_err();
    assert!(refused.contains("--fit-receivers"), "{refused}");
}

#[test]
fn the_visible_depth_hint_with_a_frame_of_latency_covers_an_orbit() {
    // Four LiSPSM splits fitted, frame after frame, to the depth range the
    // previous frame's main pass reduced on the GPU, widened by the camera's
    // motion: on an orbit through open ground nearly every visible pixel
    // stays inside it (what is not came into view nearer or farther than
    // anything the last frame saw), no map misses its body, and p95 aliasing
    // drops against splits over [near, far]. Covering the whole view (the
    // planes placed over the range, the outer splits reaching near and far),
    // no pixel is left without a map, at a few percent of p95.
    let _one = GPU.lock().unwrap_or_else(|e| e.into_inner());
    let run = |sdsm: bool, sdsm_coverage: DepthHintCoverage| {
        let scheme = (!sdsm).then(|| "practical".to_string());
        let fit = FitOptions { method: Method::Lispsm, splits: 4, resolution: 512, sdsm, sdsm_coverage, scheme, ..FitOptions::default() };
        robot_war_orbit(fit, &format!("sdsm-{sdsm}-{sdsm_coverage:?}")).unwrap()
    };
    let (plain, hinted, covering) =
        (run(false, DepthHintCoverage::Hint), run(true, DepthHintCoverage::Hint), run(true, DepthHintCoverage::View));
    eprintln!("plain {plain}\nhinted {hinted}\ncovering {covering}");
    assert_eq!((plain["sdsm"].as_bool(), hinted["sdsm"].as_bool()), (Some(false), Some(true)));
    assert_eq!((plain["uncovered_pixels"].as_u64(), hinted["misses"].as_u64()), (Some(0), Some(0)));
    // 24 frames of 57 600 pixels: at most 1 in 10 000 outside the hint.
    let uncovered = hinted["uncovered_pixels"].as_u64().unwrap();
    assert!(uncovered <= 24 * 57_600 / 10_000, "{uncovered} pixels outside the hint");
    let p95 = |s: &serde_json::Value| s["aliasing_p95_mean"].as_f64().unwrap();
    // NOTE: measured 0.72 against 1.17 (2.51 while the warp guard took
    // samples on faces the light does not reach).
    assert!(p95(&hinted) < 2.0 / 3.0 * p95(&plain), "p95 {} with the hint, {} without", p95(&hinted), p95(&plain));
    assert!(uncovered > 0, "the orbit should bring something into view outside a hint a frame old");
    assert_eq!((covering["uncovered_pixels"].as_u64(), covering["misses"].as_u64()), (Some(0), Some(0)), "{covering}");
    assert!(p95(&covering) <= 1.1 * p95(&hinted), "p95 {} covering the view, {} the hint only", p95(&covering), p95(&hinted));
}
