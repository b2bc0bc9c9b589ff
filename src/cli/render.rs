//! `shadowfocus render` and `shadowfocus demo`: focusing + the validation renderer.

use super::fit::FitOptions;
use super::overrides::{Frame, Overrides};
use render::{contact_sheet, write_outputs, Image, LightSpec, RenderRequest, Renderer, Scene, ShadowMapSpec};
use serde_json::{json, Value};
use shadowfocus_focus::{
    cull_casters, fit, fit_prepared_with_state, predict_aliasing, BoxFace, DepthRange, DepthTest, FitState, FocusResult, FocusSettings,
    Ground, Method, PreparedView, ReceiverBoxes, VisibleReceivers,
};
use shadowfocus_geom::{Aabb, Camera, Frustum, Light};
use shadowfocus_render as render;
use std::path::Path;
use std::time::Instant;

/// The geometry-side camera, light and scene box of a render scene.
pub fn scene_inputs(scene: &Scene, aspect: f64) -> Result<(Camera, Light, Aabb), String> {
    frame_inputs(scene, &Frame::of(scene), aspect)
}

/// The geometry-side camera, light and scene box of a scene seen in `frame`.
pub fn frame_inputs(scene: &Scene, frame: &Frame, aspect: f64) -> Result<(Camera, Light, Aabb), String> {
    let c = frame.camera;
    let camera = Camera { eye: c.eye, forward: c.forward, up: c.up, fovy: c.fovy, aspect, near: c.near, far: c.far };
    let light = match frame.light {
        LightSpec::Directional { direction } => Light::directional(direction),
        LightSpec::Point { position } => Light::point(position),
        s @ LightSpec::Spot { position, .. } => {
            let corners = s.spot_frustum_corners().ok_or("spot light without a frustum")?;
            Frustum::from_corners(corners).and_then(|f| Light::spot(position, f))
        }
    }
    .map_err(|e| e.to_string())?;
    let bounds = Aabb::new(scene.bounds.min, scene.bounds.max).map_err(|e| e.to_string())?;
    Ok((camera, light, bounds))
}

/// Fits the maps for a scene and turns them into renderer map specs with
/// culled caster lists. Returns the specs, the focusing time in µs and the
/// fit's skip/notes summary.
pub fn fit_scene(scene: &Scene, aspect: f64, settings: &FocusSettings) -> Result<(Vec<ShadowMapSpec>, f64, Value), String> {
    fit_frame(scene, &Frame::of(scene), aspect, settings, None)
}

/// [`fit_scene`] with the camera and light of `frame`. The summary also
/// gives each active map's utilisation (the fraction of the map's area that
/// the projection of its focus body covers) and `h_depth_span`, the extent
/// of the focus body H in the map's stored depth: 1 when the depth range is
/// fitted to H, more when it is fitted to the receivers only
/// (`--depth-clamp`): by that factor the depth buffer's precision grows.
/// With `state`, the fit carries it from the previous frame (a camera path:
/// see [`FitState`]); the repeated fits timed here hold this frame's steps.
pub fn fit_frame(
    scene: &Scene,
    frame: &Frame,
    aspect: f64,
    settings: &FocusSettings,
    mut state: Option<&mut FitState>,
) -> Result<(Vec<ShadowMapSpec>, f64, Value), String> {
    let (camera, light, bounds) = frame_inputs(scene, frame, aspect)?;
    let mut result = FocusResult::new();
    // Focusing time: median of a few fits (the first one warms caches).
    let mut times = Vec::new();
    for _ in 0..7 {
        let t = Instant::now();
        match state.as_deref_mut() {
            Some(st) => PreparedView::new(&camera, settings).and_then(|v| fit_prepared_with_state(&v, &light, &bounds, st, &mut result)),
            None => fit(&camera, &light, &bounds, settings, &mut result),
        }
        .map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64() * 1e6);
    }
    let focusing_us = super::body::median(&mut times);
    let boxes: Vec<Aabb> = scene.objects.iter().map(|o| Aabb { min: o.aabb.min, max: o.aabb.max }).collect();
    let mut idx = vec![0u32; boxes.len()];
    let mut specs = Vec::new();
    let mut utilisation = Vec::new();
    let mut h_depth_span = Vec::new();
    let mut predicted = Vec::new();
    let mut resolutions = Vec::new();
    for m in result.maps().iter().filter(|m| m.is_active()) {
        utilisation.push(m.utilisation());
        resolutions.push(m.fit.resolution);
        predicted.push(predict_aliasing(m, &camera, &bounds, &settings.receivers, settings.ground).map(|p| p.max));
        h_depth_span.push(depth_span(&m.fit.clip_from_world, m.body().vertices()));
        let n = cull_casters(m, &boxes, &mut idx).map_err(|e| e.to_string())?;
        specs.push(ShadowMapSpec {
            world_to_clip: m.fit.clip_from_world_f32,
            depth_test: match m.fit.depth_test {
                DepthTest::Less => render::DepthTest::Less,
                DepthTest::Greater => render::DepthTest::Greater,
            },
            split: [m.split_range[0] as f32, m.split_range[1] as f32],
            casters: idx[..n].to_vec(),
            face: match (m.face, m.light) {
                (Some(f), Light::Spot { position, .. }) => Some(render::CubeFaceSpec { light: position, index: f as u32 }),
                _ => None,
            },
            resolution: Some(m.fit.resolution),
        });
    }
    let summary = json!({
        "skipped": result.skipped.names().collect::<Vec<_>>(),
        "notes": result.notes.names().collect::<Vec<_>>(),
        "maps_fitted": result.maps().len(),
        "maps_active": specs.len(),
        "utilisation": utilisation,
        "h_depth_span": h_depth_span,
        "predicted_aliasing": predicted,
        "resolutions": resolutions,
        "split_depths": result.split_depths(),
    });
    Ok((specs, focusing_us, summary))
}

/// A render of `specs` in `frame` at `size`, maps of `resolution`² texels.
fn request<'a>(
    scene: &'a Scene,
    frame: &Frame,
    specs: &'a [ShadowMapSpec],
    size: (u32, u32),
    resolution: u32,
    settings: &FocusSettings,
) -> RenderRequest<'a> {
    let mut req = RenderRequest::new(scene, specs);
    req.camera = frame.camera;
    req.light = frame.light;
    req.settings.width = size.0;
    req.settings.height = size.1;
    req.settings.shadow_resolution = resolution;
    req.settings.depth_clamp = settings.depth_clamp;
    req
}

/// A pre-pass of `frame`: what each pixel sees (its shadows coarse, no
/// ground truth), its receivers reduced into the slices between `slices`
/// where given.
fn pre_pass(
    renderer: &mut Renderer,
    scene: &Scene,
    frame: &Frame,
    settings: &FocusSettings,
    size: (u32, u32),
    slices: Option<ReceiverSlicePlanes>,
) -> Result<render::RenderOutput, String> {
    let aspect = size.0 as f64 / size.1 as f64;
    let (specs, _, _) = fit_frame(scene, frame, aspect, settings, None)?;
    let mut req = request(scene, frame, &specs, size, 64, settings);
    (req.settings.ground_truth, req.settings.save_shadow_maps) = (false, false);
    req.settings.receiver_slices = slices;
    renderer.render(&req).map_err(|e| e.to_string())
}

/// The view depths between the slices a frame's receivers are reduced into.
type ReceiverSlicePlanes = [f32; render::RECEIVER_SLICES - 1];

// The renderer's slices are the library's visible receiver boxes' slices.
const _: () = assert!(render::RECEIVER_SLICES == shadowfocus_focus::MAX_RECEIVER_BOXES);

/// The planes between [`VisibleReceivers`]' slices of `camera`'s view, for
/// the renderer's reduction of a `height`-pixel frame.
///
/// NOTE: in f32 a plane moves by an ulp of its depth, and the GPU computes
/// a pixel's depth in f32: a point within ulps of a plane may fall in the
/// slice beside the one `VisibleReceivers::add` gives it. Either box holds
/// it, so the boxes' union still holds every receiver pixel.
pub fn receiver_slice_planes(camera: &Camera, height: u32) -> Result<ReceiverSlicePlanes, String> {
    let v = VisibleReceivers::new(camera, height).map_err(|e| e.to_string())?;
    Ok(v.slice_planes().map(|p| p as f32))
}

/// Boxes around the receivers a rendered frame shows (the pixels its
/// aliasing statistics count), sliced by view depth and by the axis their
/// normals face ([`VisibleReceivers`]); no hint where no pixel shows a
/// receiver. The
/// GPU's reduction into the slices where the frame was rendered with
/// [`receiver_slice_planes`] of `camera` and the adapter has compute
/// shaders, else the CPU's of the read-back positions.
///
/// NOTE: the positions are the main pass's, interpolated in f32; each box
/// is widened by 2⁻¹⁶ of the largest coordinate, far above their rounding
/// (the boxes steer the prediction; with --fit-receivers or --depth-clamp
/// they also bound the maps, and this frame's own pre-pass holds every
/// receiver the frame shades).
pub fn visible_receiver_boxes(out: &render::RenderOutput, camera: &Camera) -> Result<ReceiverBoxes, String> {
    let v = match &out.receiver_slices {
        Some(slices) => gpu_visible_receivers(slices, camera, out.height)?,
        None => cpu_visible_receivers(out, camera)?,
    };
    v.boxes(v.magnitude() / 65536.0).map_err(|e| e.to_string())
}

/// The visible receivers of the GPU's slices of a frame of `camera`.
fn gpu_visible_receivers(slices: &render::ReceiverSlices, camera: &Camera, height: u32) -> Result<VisibleReceivers, String> {
    let mut v = VisibleReceivers::new(camera, height).map_err(|e| e.to_string())?;
    let dvec = |p: [f32; 3]| glam::DVec3::from(p.map(f64::from));
    for (axis, slices) in slices.iter().enumerate() {
        for (k, s) in slices.iter().enumerate() {
            if let Some(s) = s {
                let bounds = Aabb { min: dvec(s.min), max: dvec(s.max) };
                v.add_slice(k, Some(axis), bounds, s.far as f64).map_err(|e| e.to_string())?;
            }
        }
    }
    Ok(v)
}

/// The visible receivers of a frame's read-back receiver pixels, by the
/// axis their normal faces (for adapters without compute shaders, and to
/// check the GPU's).
pub fn cpu_visible_receivers(out: &render::RenderOutput, camera: &Camera) -> Result<VisibleReceivers, String> {
    let mut v = VisibleReceivers::new(camera, out.height).map_err(|e| e.to_string())?;
    let dvec = |p: &[f32; 4]| glam::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64);
    for (w, n) in out.world.iter().zip(&out.normal).filter(|(w, _)| w[3] == 1.0) {
        v.add_facing(dvec(w), dvec(n));
    }
    Ok(v)
}

/// What a depth pre-pass of a frame gives its fit: the visible depth range
/// (`--sdsm`) and boxes around the visible receivers
/// (`--visible-receivers`).
#[derive(Clone, Copy, Debug, Default)]
pub struct PrePass {
    pub visible_depth: Option<[f64; 2]>,
    pub receivers: Option<ReceiverBoxes>,
}

impl PrePass {
    /// The pre-pass `opts` asks for (none without `--sdsm` or
    /// `--visible-receivers`).
    pub fn of(renderer: &mut Renderer, scene: &Scene, frame: &Frame, opts: &FitOptions, size: (u32, u32)) -> Result<PrePass, String> {
        if !(opts.sdsm || opts.visible_receivers) {
            return Ok(PrePass::default());
        }
        let (camera, _, _) = frame_inputs(scene, frame, size.0 as f64 / size.1 as f64)?;
        let slices = if opts.visible_receivers { Some(receiver_slice_planes(&camera, size.1)?) } else { None };
        let out = pre_pass(renderer, scene, frame, &opts.settings()?, size, slices)?;
        Ok(PrePass {
            visible_depth: if opts.sdsm { reduced_depth(&out, renderer.adapter().compute) } else { None },
            receivers: if opts.visible_receivers { Some(visible_receiver_boxes(&out, &camera)?) } else { None },
        })
    }

    /// The settings of `opts` for `scene` ([`scene_settings`]) with these
    /// hints; refused where `opts` asks for visible receivers and there are
    /// none.
    pub fn settings(&self, scene: &Scene, opts: &FitOptions) -> Result<FocusSettings, String> {
        if opts.visible_receivers && self.receivers.is_none() {
            return Err("--visible-receivers takes its boxes from a pre-pass of the frame, and none was rendered".into());
        }
        let settings = scene_settings(scene, opts)?;
        Ok(FocusSettings { visible_depth: self.visible_depth, receivers: self.receivers.unwrap_or(settings.receivers), ..settings })
    }
}

/// The view depths `[z_min, z_max]` of every pixel of a rendered frame
/// that sees geometry (sample-distribution shadow maps [SDSM10]: the hint
/// of `FocusSettings::visible_depth`), `None` when no pixel does: the GPU's
/// reduction (a compute pass over the G-buffer) where the adapter has
/// compute shaders (`compute`), else the CPU's of the read-back positions.
///
/// NOTE: the main pass computes a pixel's position in f32, and the
/// reduction its depth in f32: a few ulps of |eye| + depth off the f64
/// depth of the same point. The range is widened by 2⁻¹⁶ of that
/// magnitude, far above those ulps.
pub(crate) fn reduced_depth(out: &render::RenderOutput, compute: bool) -> Option<[f64; 2]> {
    let c = &out.camera;
    let [lo, hi] = match out.visible_depth {
        Some([lo, hi]) => [lo as f64, hi as f64],
        None if compute => return None,
        None => cpu_visible_depth(out)?,
    };
    let slack = (c.eye.length() + hi.abs()) * (1.0 / 65536.0);
    Some([lo - slack, hi + slack])
}

/// The visible depth range reduced on the CPU from the read-back positions
/// (for adapters without compute shaders, and to check the GPU's).
pub fn cpu_visible_depth(out: &render::RenderOutput) -> Option<[f64; 2]> {
    let c = &out.camera;
    let forward = c.forward.normalize();
    let (lo, hi) = out.world.iter().filter(|w| w[3] != 0.0).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
        let z = (glam::DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64) - c.eye).dot(forward);
        (lo.min(z), hi.max(z))
    });
    (lo <= hi).then_some([lo, hi])
}

/// max − min of the clip depth z / w of `points` under `clip_from_world`.
fn depth_span(clip_from_world: &glam::DMat4, points: &[glam::DVec3]) -> f64 {
    let (lo, hi) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
        let q = *clip_from_world * p.extend(1.0);
        (lo.min(q.z / q.w), hi.max(q.z / q.w))
    });
    (hi - lo).max(0.0)
}

/// Renders one scene with one configuration and writes its outputs.
pub fn render_to(
    renderer: &mut Renderer,
    scene: &Scene,
    opts: &FitOptions,
    size: (u32, u32),
    dir: &Path,
) -> Result<render::RenderOutput, String> {
    render_frame_to(renderer, scene, &Frame::of(scene), opts, size, dir)
}

/// [`render_to`] with the camera and light of `frame`.
pub fn render_frame_to(
    renderer: &mut Renderer,
    scene: &Scene,
    frame: &Frame,
    opts: &FitOptions,
    size: (u32, u32),
    dir: &Path,
) -> Result<render::RenderOutput, String> {
    let (out, extra) = render_frame(renderer, scene, frame, opts, size, true, None)?;
    write_outputs(dir, &out, Some(&extra)).map_err(|e| e.to_string())?;
    Ok(out)
}

/// Fits and renders one frame (ground truth on; the shadow maps read back
/// when `maps` is set). Returns the output and the fields `metrics.json`
/// adds in front of the renderer's metrics (method, focusing time, the
/// fit's summary).
pub fn render_frame(
    renderer: &mut Renderer,
    scene: &Scene,
    frame: &Frame,
    opts: &FitOptions,
    size: (u32, u32),
    maps: bool,
    state: Option<&mut FitState>,
) -> Result<(render::RenderOutput, Value), String> {
    let pre = PrePass::of(renderer, scene, frame, opts, size)?;
    render_frame_hinted(renderer, scene, frame, opts, size, maps, state, pre)
}

/// [`render_frame`] with the pre-pass's hints given (`--sdsm`'s visible
/// depth range from an earlier frame) instead of a pre-pass of this one.
#[allow(clippy::too_many_arguments)]
pub fn render_frame_hinted(
    renderer: &mut Renderer,
    scene: &Scene,
    frame: &Frame,
    opts: &FitOptions,
    size: (u32, u32),
    maps: bool,
    state: Option<&mut FitState>,
    pre: PrePass,
) -> Result<(render::RenderOutput, Value), String> {
    let settings = pre.settings(scene, opts)?;
    let sdsm = pre.visible_depth;
    // NOTE: the renderer is wgpu: clip depth in [0, 1] (reversed-Z maps
    // render through their greater test), and clamping where the adapter
    // has it. Anything else would render wrong shadows, so it is refused.
    if settings.clip.depth != DepthRange::ZeroToOne {
        return Err("the renderer uses wgpu's clip depth [0, 1]: render with --clip wgpu, d3d, metal or vulkan".into());
    }
    if settings.depth_clamp && !renderer.adapter().depth_clamp {
        return Err(format!("--depth-clamp needs depth clamping (DEPTH_CLIP_CONTROL), which {} lacks", renderer.adapter().name));
    }
    let aspect = size.0 as f64 / size.1 as f64;
    let (specs, focusing_us, summary) = fit_frame(scene, frame, aspect, &settings, state)?;
    // Reported in the metrics; a map the body fills exactly can come out a
    // rounding error above 1.
    let utilisation: Vec<f64> =
        summary["utilisation"].as_array().map_or(Vec::new(), |a| a.iter().filter_map(Value::as_f64).map(|u| u.clamp(0.0, 1.0)).collect());
    let mut req = request(scene, frame, &specs, size, opts.resolution, &settings);
    if utilisation.len() == specs.len() {
        req.utilisation = &utilisation;
    }
    req.settings.save_shadow_maps = maps;
    // The frame's own receivers, for a later frame's hint (`animate`).
    if opts.visible_receivers {
        let (camera, _, _) = frame_inputs(scene, frame, aspect)?;
        req.settings.receiver_slices = Some(receiver_slice_planes(&camera, size.1)?);
    }
    let out = renderer.render(&req).map_err(|e| e.to_string())?;
    // Each map's predicted maximum in screen pixels per texel, beside the
    // measured `map_aliasing_max` (receivers facing the camera: a receiver
    // the light or the eye grazes measures more or less).
    let pixels = ((size.0 as f64) * (size.1 as f64)).sqrt();
    let predicted_px: Vec<Option<f64>> = specs
        .iter()
        .enumerate()
        .map(|(k, m)| summary["predicted_aliasing"][k].as_f64().map(|e| e * pixels / req.map_resolution(m) as f64))
        .collect();
    let extra = json!({
        "method": opts.method.name(),
        "splits": opts.splits,
        "scheme": opts.scheme_name(),
        "resolution": opts.resolution,
        "budget": settings.texel_budget.map(|b| b.texels),
        "reversed_z": settings.clip.reversed_z,
        "depth_clamp": settings.depth_clamp,
        "fit_receivers": opts.fit_receivers,
        "receiver_boxes": settings.receivers.as_slice().len(),
        "visible_receivers": opts.visible_receivers,
        "ground": settings.ground.map(|g| json!({ "face": format!("{:?}", g.face), "level": g.level })),
        "visible_depth": sdsm,
        "focusing_us": focusing_us,
        "predicted_aliasing_px": predicted_px,
        "fit": summary,
    });
    Ok((out, extra))
}

/// The settings of `opts` for `scene`: with `--receiver-boxes`, its
/// receiver boxes.
pub fn scene_settings(scene: &Scene, opts: &FitOptions) -> Result<FocusSettings, String> {
    let mut settings = opts.settings()?;
    if opts.receiver_boxes {
        settings.receivers = receiver_boxes(scene)?;
    }
    Ok(settings)
}

/// The boxes of the scene's receivers (the objects its aliasing statistics
/// count), as an engine would pass them.
pub fn receiver_boxes(scene: &Scene) -> Result<ReceiverBoxes, String> {
    let boxes: Vec<Aabb> = scene.objects.iter().filter(|o| o.receiver).map(|o| Aabb { min: o.aabb.min, max: o.aabb.max }).collect();
    ReceiverBoxes::new(&boxes).map_err(|e| e.to_string())
}

/// A built-in scene's ground as its engine would name it: the top of the
/// slab the world stands on (y = 0) where the scene box reaches below it
/// (the huge chessboard's 6 m board, thin casters' 2 m ground block), else
/// the box's floor (`--ground min-y@0` and `--ground min-y`).
pub fn builtin_ground(scene: &str) -> Ground {
    match scene {
        "huge-chessboard" | "thin-casters" => Ground::at(BoxFace::MinY, 0.0),
        _ => BoxFace::MinY.into(),
    }
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once('x').ok_or_else(|| format!("size {s:?} is not WxH"))?;
    let w: u32 = w.parse().map_err(|_| format!("bad width in {s:?}"))?;
    let h: u32 = h.parse().map_err(|_| format!("bad height in {s:?}"))?;
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        return Err(format!("size {s:?} out of range (1..8192)"));
    }
    Ok((w, h))
}

/// The demo's configurations at one texel budget: four single-map methods
/// at R², and four splits at (R/2)² each.
pub fn demo_configs(resolution: u32) -> Vec<(String, FitOptions)> {
    let base = |method, splits, res| FitOptions { method, splits, resolution: res, ..FitOptions::default() };
    vec![
        ("uniform".into(), base(Method::Uniform, 1, resolution)),
        ("psm".into(), base(Method::Psm, 1, resolution)),
        ("lispsm".into(), base(Method::Lispsm, 1, resolution)),
        ("tsm".into(), base(Method::Tsm, 1, resolution)),
        ("pssm4-lispsm".into(), base(Method::Lispsm, 4, resolution / 2)),
        // Auto per split, the planes placed on the scene's receiver boxes.
        ("pssm4-auto-boxes".into(), FitOptions { receiver_boxes: true, ..base(Method::Auto, 4, resolution / 2) }),
        // The same four maps' texels shared by their predicted aliasing, each at most R².
        (
            "pssm4-auto-budget".into(),
            FitOptions { receiver_boxes: true, budget: Some(4 * (resolution as u64 / 2).pow(2)), ..base(Method::Auto, 4, resolution) },
        ),
    ]
}

fn progress(done: usize, total: usize, label: &str) {
    let width = 30;
    let filled = done * width / total.max(1);
    eprint!("\r[{}{}] {done}/{total} {label:<40}", "#".repeat(filled), "-".repeat(width - filled));
    if done == total {
        eprintln!();
    }
}

/// Renders every built-in scene with every demo configuration into `dir`,
/// plus `contact_sheet.png` and `summary.json`.
/// With `overrides`, every scene is seen with that camera and/or light.
pub fn demo(dir: &Path, size: (u32, u32), resolution: u32, scenes: &[String], overrides: &Overrides) -> Result<Value, String> {
    let mut renderer = Renderer::from_env().map_err(|e| e.to_string())?;
    let mut configs = demo_configs(resolution);
    // LiSPSM again with its depth range fitted to the receivers and casters
    // toward the light clamped, beside the plain fit, where the adapter can
    // clamp; the summary says why the column is missing where it cannot.
    let clamping = renderer.adapter().depth_clamp;
    // The four splits again, fitted to the visible depth range of a
    // pre-pass, their planes placed over it [SDSM10].
    let pssm = configs.iter().find(|(l, _)| l == "pssm4-lispsm").map(|(_, o)| o.clone()).ok_or("no pssm4-lispsm column")?;
    configs.push(("pssm4-lispsm-sdsm".into(), FitOptions { sdsm: true, ..pssm }));
    // Auto's four splits again, on boxes around what that pre-pass sees
    // instead of the scene's own receiver boxes.
    let auto = configs.iter().find(|(l, _)| l == "pssm4-auto-boxes").map(|(_, o)| o.clone()).ok_or("no pssm4-auto-boxes column")?;
    configs.push(("pssm4-auto-visible".into(), FitOptions { receiver_boxes: false, visible_receivers: true, ..auto }));
    if clamping {
        let lispsm = configs.iter().find(|(l, _)| l == "lispsm").map(|(_, o)| o.clone()).ok_or("no lispsm column")?;
        configs.push(("lispsm-clamped".into(), FitOptions { depth_clamp: true, ..lispsm }));
    } else {
        eprintln!("demo: {} lacks depth clamping (DEPTH_CLIP_CONTROL): no lispsm-clamped column", renderer.adapter().name);
    }
    let total = scenes.len() * configs.len();
    let mut tiles: Vec<(Image, String)> = Vec::new();
    let mut rows = Vec::new();
    let mut done = 0;
    for name in scenes {
        let scene = render::load_scene(name).map_err(|e| e.to_string())?;
        let frame = Frame::with(&scene, overrides)?;
        for (label, opts) in &configs {
            progress(done, total, &format!("{name} / {label}"));
            let sub = dir.join(name).join(label);
            let (out, extra) = render_frame(&mut renderer, &scene, &frame, opts, size, true, None)?;
            write_outputs(&sub, &out, Some(&extra)).map_err(|e| e.to_string())?;
            let m = &out.metrics;
            rows.push(json!({
                "scene": name, "config": label, "aliasing": m.aliasing, "mismatch": m.mismatch,
                "render_ms": m.render_ms, "casters": m.casters,
                "depth_clamp": m.depth_clamp, "h_depth_span": extra["fit"]["h_depth_span"], "visible_depth": extra["visible_depth"],
            }));
            let k = (size.0 / 320).max(1);
            tiles.push((out.color.downscale(k), format!("{name} {label}")));
            done += 1;
        }
    }
    progress(done, total, "done");
    let refs: Vec<(&Image, &str)> = tiles.iter().map(|(i, l)| (i, l.as_str())).collect();
    let sheet = contact_sheet(&refs, configs.len());
    sheet.save_png(&dir.join("contact_sheet.png")).map_err(|e| e.to_string())?;
    let summary = json!({
        "adapter": renderer.adapter(), "size": [size.0, size.1], "resolution": resolution,
        "depth_clamp_column": clamping, "results": rows,
    });
    std::fs::write(dir.join("summary.json"), serde_json::to_string_pretty(&summary).unwrap()).map_err(|e| e.to_string())?;
    Ok(summary)
}
