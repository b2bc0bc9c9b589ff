//! `shadowfocus animate`: a camera path through a static scene, rendered
//! frame by frame, with how much the shadows flicker and crawl.
//!
//! - `path`: the camera paths;
//! - `screen`: where a world point lands in a frame;
//! - `flicker`: the answers at fixed world points from frame to frame;
//! - `crawl`: the screen motion of shadow edges beyond the camera's.

mod crawl;
mod flicker;
mod path;
mod screen;

pub use path::{parse_path, path_camera, CameraPath};

use super::fit::FitOptions;
use super::overrides::{parse_light, Frame, LightOverride};
use super::render::{frame_inputs, reduced_depth, render_frame_hinted, visible_receiver_boxes, PrePass};
use render::{contact_sheet, Image, Renderer, Scene};
use serde_json::{json, Value};
use shadowfocus_focus::{fit_prepared_with_state, visible_depth_after_motion, FitState, FocusResult, PreparedView, ReceiverBoxes};
use shadowfocus_geom::Camera;
use shadowfocus_render as render;
use std::path::Path;

/// Every how many pixels of the first frame a probe is taken.
const PROBE_STRIDE: usize = 7;
/// Frames in the strip.
const STRIP_FRAMES: usize = 8;
/// The animation's region: the middle third of the frame, magnified this much.
const ZOOM: u32 = 3;
/// Its frame time, ms.
const ZOOM_DELAY_MS: u16 = 100;

/// `animate`'s options besides the fit's.
#[derive(Clone, Debug, clap::Args)]
pub struct AnimateOptions {
    /// Built-in scene name or glTF file.
    #[arg(long)]
    pub scene: String,
    /// orbit | walk | turn | zoom
    #[arg(long, default_value = "orbit", value_parser = parse_path)]
    pub path: CameraPath,
    /// Number of frames (at least 2).
    #[arg(long, default_value_t = 120)]
    pub frames: usize,
    /// Image size, WxH.
    #[arg(long, default_value = "320x180", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    /// Replace the scene's light: directional:DX,DY,DZ (travel direction) |
    /// point:X,Y,Z | spot:X,Y,Z,FX,FY,FZ,FOVY_DEG.
    #[arg(long, value_parser = parse_light, allow_hyphen_values = true)]
    pub light: Option<LightOverride>,
    #[command(flatten)]
    pub fit: FitOptions,
    /// Output folder: temporal.json, frames.csv, strip.png, zoom.png.
    #[arg(long)]
    pub out: std::path::PathBuf,
}

/// Whether every active map of the frame's fit (from the state the frame
/// started with) holds its body (f64, in its clip convention): `misses`
/// counts the frames where one does not.
fn maps_hold_their_bodies(
    scene: &Scene,
    frame: &Frame,
    aspect: f64,
    opts: &FitOptions,
    mut state: FitState,
    pre: PrePass,
) -> Result<bool, String> {
    let (camera, light, bounds) = frame_inputs(scene, frame, aspect)?;
    let mut result = FocusResult::new();
    let settings = pre.settings(scene, opts)?;
    let view = PreparedView::new(&camera, &settings).map_err(|e| e.to_string())?;
    fit_prepared_with_state(&view, &light, &bounds, &mut state, &mut result).map_err(|e| e.to_string())?;
    Ok(result.maps().iter().filter(|m| m.is_active()).all(|m| {
        let z_min = m.fit.clip.depth_min();
        m.body().vertices().iter().all(|p| {
            let q = m.fit.clip_from_world * p.extend(1.0);
            q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= z_min * q.w && q.z <= q.w
        })
    }))
}

/// Renders the path and writes `temporal.json`, `frames.csv`, `strip.png`
/// and `zoom.png` (the middle third of every frame, magnified, as an
/// animated PNG) into `out`; returns the summary.
pub fn animate(o: &AnimateOptions) -> Result<Value, String> {
    if o.frames < 2 {
        return Err("--frames: at least 2 frames are needed to compare one with the next".into());
    }
    if o.fit.visible_receivers && (o.fit.fit_receivers || o.fit.depth_clamp) {
        return Err(
            "--visible-receivers takes the boxes a frame late, without what comes into view since: fit the maps to their bodies (no --fit-receivers or --depth-clamp)".into()
        );
    }
    let scene = render::load_scene(&o.scene).map_err(|e| e.to_string())?;
    let mut renderer = Renderer::from_env().map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&o.out).map_err(|e| e.to_string())?;
    let aspect = o.size.0 as f64 / o.size.1 as f64;
    let light = o.light.map_or(scene.light, |l| l.resolve(&scene.bounds));
    light.validate().map_err(|e| e.to_string())?;
    let (mut flicker, mut crawl, mut misses) = (None, crawl::Crawl::default(), 0usize);
    // NOTE: carried from frame to frame as an engine would (stable maps'
    // hysteresis); without --stable it holds nothing.
    let mut state = FitState::default();
    let mut state_changes = 0usize;
    let mut p95s = Vec::new();
    let mut rows =
        vec!["frame,aliasing_p95,aliasing_max,mismatch_adequate,probes_seen,maps_hold_h,hint_min,hint_max,uncovered".to_string()];
    let mut strip = Vec::new();
    let mut zoomed = Vec::with_capacity(o.frames);
    // --sdsm: the first frame from its own pre-pass, every later one from
    // the range the last frame's main pass reduced, widened by the camera's
    // motion — one frame of latency, as an engine takes it.
    let mut last: Option<([f64; 2], Camera)> = None;
    // --visible-receivers: the same, the boxes around what the last frame's
    // main pass saw (they steer the prediction only).
    let mut last_boxes: Option<ReceiverBoxes> = None;
    let mut uncovered = (0u64, 0usize);
    for k in 0..o.frames {
        let frame = Frame { camera: path_camera(&scene, o.path, k, o.frames), light };
        let (now, _, _) = frame_inputs(&scene, &frame, aspect)?;
        let before = state;
        // A pre-pass of this frame where a hint has no earlier frame's to go by.
        let fresh = if (o.fit.sdsm && last.is_none()) || (o.fit.visible_receivers && last_boxes.is_none()) {
            PrePass::of(&mut renderer, &scene, &frame, &o.fit, o.size)?
        } else {
            PrePass::default()
        };
        let sdsm = match (o.fit.sdsm, &last) {
            (false, _) => None,
            (true, None) => fresh.visible_depth,
            (true, Some((range, then))) => visible_depth_after_motion(*range, then, &now),
        };
        let receivers = match (o.fit.visible_receivers, last_boxes) {
            (false, _) => None,
            (true, Some(b)) => Some(b),
            (true, None) => fresh.receivers,
        };
        let pre = PrePass { visible_depth: sdsm, receivers };
        let (out, _) = render_frame_hinted(&mut renderer, &scene, &frame, &o.fit, o.size, true, Some(&mut state), pre)?;
        if o.fit.visible_receivers {
            last_boxes = Some(visible_receiver_boxes(&out, &now)?);
        }
        if o.fit.sdsm {
            last = reduced_depth(&out, renderer.adapter().compute).map(|r| (r, now));
        }
        let c = &out.metrics.coverage;
        uncovered = (uncovered.0 + c.uncovered, uncovered.1 + usize::from(!c.complete));
        state_changes += usize::from(k > 0 && state != before);
        let screen = screen::Screen::new(&out)?;
        let truth = out.truth.as_ref().ok_or("the render has no ground truth")?;
        let probes = flicker.get_or_insert_with(|| flicker::Flicker::new(&out, truth, PROBE_STRIDE));
        let seen = probes.frame(&out, &screen);
        crawl.frame(&out, &screen);
        let holds = maps_hold_their_bodies(&scene, &frame, aspect, &o.fit, before, pre)?;
        misses += usize::from(!holds);
        let m = &out.metrics;
        p95s.push(m.aliasing.p95);
        let adequate = m.mismatch.map_or(f64::NAN, |x| x.rate_adequate);
        // The hint this frame was fitted with (empty without --sdsm) and the
        // pixels no map covered.
        let [lo, hi] = sdsm.map_or([String::new(), String::new()], |r| r.map(|z| z.to_string()));
        rows.push(format!("{k},{},{},{adequate},{seen},{holds},{lo},{hi},{}", m.aliasing.p95, m.aliasing.max, m.coverage.uncovered));
        let (w, h) = (out.color.width / ZOOM, out.color.height / ZOOM);
        zoomed.push(out.color.zoom(w, h, w, h, ZOOM));
        if k % (o.frames / STRIP_FRAMES).max(1) == 0 && strip.len() < STRIP_FRAMES {
            strip.push((out.color, format!("frame {k}")));
        }
    }
    let counts = flicker.map(|f| f.counts).unwrap_or_default();
    let finite: Vec<f64> = p95s.into_iter().filter(|x| x.is_finite()).collect();
    let summary = json!({
        "frames": o.frames,
        "path": o.path.name(),
        "method": o.fit.method.name(),
        "splits": o.fit.splits,
        "stable": o.fit.stable,
        "flicker": counts.rate(),
        "flicker_near_edges": counts.rate_near_edges(),
        "point_frames": counts.compared,
        "point_frames_near_edges": counts.compared_near_edges,
        "edge_crawl_px": crawl.rendered_px(),
        "edge_crawl_truth_px": crawl.truth_px(),
        "aliasing_p95_mean": finite.iter().sum::<f64>() / finite.len().max(1) as f64,
        "misses": misses,
        "state_changes": state_changes,
        "sdsm": o.fit.sdsm,
        "visible_receivers": o.fit.visible_receivers,
        "uncovered_pixels": uncovered.0,
        "uncovered_frames": uncovered.1,
    });
    let refs: Vec<(&Image, &str)> = strip.iter().map(|(i, l)| (i, l.as_str())).collect();
    contact_sheet(&refs, 4).save_png(&o.out.join("strip.png")).map_err(|e| e.to_string())?;
    Image::save_animation(&zoomed, ZOOM_DELAY_MS, &o.out.join("zoom.png")).map_err(|e| e.to_string())?;
    write(&o.out.join("frames.csv"), &(rows.join("\n") + "\n"))?;
    write(&o.out.join("temporal.json"), &serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?)?;
    Ok(summary)
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}
