//! `shadowfocus sweep`: a directional light swept over elevations × azimuths
//! around the camera's view direction, every method rendered at each
//! configuration and compared with ray-traced ground truth.
//!
//! Directions: the azimuth is measured in the horizontal plane (+y up) from
//! the horizontal projection of the camera's forward direction. At azimuth 0°
//! the light travels along it (the sun behind the viewer); at 180° it
//! travels toward the viewer (the sun ahead, the duelling-frusta case); at
//! 90° it travels toward the camera's right (the sun on the left). The
//! elevation is the sun's angle above the horizon.
//!
//! Writes into the output folder:
//! - `sweep.csv`: one row per configuration;
//! - `sweep.json`: the same numbers, with each method's p95 and maximum
//!   aliasing over uniform's at the same configuration;
//! - `aliasing_p95.png`, `mismatch_off_edges.png`, `mismatch_adequate.png`:
//!   against azimuth, one curve per method, one panel per elevation;
//! - `worst.png`: the worst configurations (see [`worst`]) with their
//!   mismatch images and shadow maps, and each of them rendered in full
//!   (`worst/RANK-METHOD-elE-azA/`, as `render` writes a folder).

use super::fit::FitOptions;
use super::overrides::{CameraOverride, Frame, LightOverride};
use super::render::{parse_size, render_frame};
use glam::DVec3;
use render::{
    contact_sheet, mismatch_view, shadow_map_images, write_outputs, AliasingStats, Image, LightSpec, MismatchStats, Renderer, Scene,
};
use serde_json::{json, Value};
use shadowfocus_eval::lines::{self, Axes, Panel, Scale, Series};
use shadowfocus_focus::{Ground, Method};
use shadowfocus_render as render;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Options of `shadowfocus sweep`.
#[derive(Clone, Debug, clap::Args)]
pub struct SweepOptions {
    /// Built-in scene name or glTF file.
    #[arg(long)]
    pub scene: String,
    /// Methods: uniform, psm, lispsm, tsm, auto, and METHOD followed by a
    /// split count (lispsm4: four practical λ = 0.5 splits with the texel
    /// budget of one map, i.e. R/2 per side each), optionally with @SCHEME
    /// for the split planes (auto4@optimal, lispsm4@geometric:10); with
    /// -stable, stable maps compared with uniform-stable (lispsm-stable); with
    /// -shared, the splits share one map's texels by predicted aliasing
    /// (auto4-shared: each split its own size, at most R per side).
    #[arg(long, value_delimiter = ',', default_value = "uniform,psm,lispsm,tsm,lispsm4", value_parser = parse_sweep_method)]
    pub methods: Vec<SweepMethod>,
    /// Sun elevations above the horizon, degrees.
    #[arg(long, value_delimiter = ',', default_value = "10,35,65", allow_hyphen_values = true)]
    pub elevations: Vec<f64>,
    /// Sun azimuths from the view direction, degrees (0 = sun behind the viewer, 180 = ahead).
    #[arg(long, value_delimiter = ',', default_value = "0,30,60,90,120,150,180,210,240,270,300,330", allow_hyphen_values = true)]
    pub azimuths: Vec<f64>,
    /// Texels per side of a single map.
    #[arg(long, default_value_t = 1024)]
    pub resolution: u32,
    /// Image size, WxH.
    #[arg(long, default_value = "480x270", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Replace the scene's camera: EX,EY,EZ,FX,FY,FZ[,FOVY_DEG,NEAR,FAR].
    #[arg(long, value_parser = super::overrides::parse_camera, allow_hyphen_values = true)]
    pub camera: Option<CameraOverride>,
    /// One light instead of the grid (every method rendered with it):
    /// directional:DX,DY,DZ | point:X,Y,Z | spot:X,Y,Z,FX,FY,FZ,FOVY_DEG.
    #[arg(long, value_parser = super::overrides::parse_light, allow_hyphen_values = true, conflicts_with_all = ["elevations", "azimuths"])]
    pub light: Option<LightOverride>,
    /// How many of the worst configurations go on the contact sheet.
    #[arg(long, default_value_t = 8)]
    pub worst: usize,
    /// Fit every method to the visible depth range of a pre-pass of each frame.
    #[arg(long)]
    pub sdsm: bool,
    /// Pass every fit the boxes of the scene's receivers (see `render --receiver-boxes`).
    #[arg(long)]
    pub receiver_boxes: bool,
    /// Pass every fit boxes around what a pre-pass of its frame sees (see `render
    /// --visible-receivers`).
    #[arg(long, conflicts_with = "receiver_boxes")]
    pub visible_receivers: bool,
    /// Pass every fit the scene box's ground (see `render --ground`).
    #[arg(long, value_parser = super::fit::parse_ground)]
    pub ground: Option<Ground>,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
}

/// A method of the sweep: one map, or `splits` practical splits sharing one
/// map's texel budget.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepMethod {
    pub name: String,
    pub method: Method,
    pub splits: usize,
    /// Fit to the visible depth range of a pre-pass (`--sdsm`).
    pub sdsm: bool,
    /// Pass the scene's receiver boxes (`--receiver-boxes`).
    pub receiver_boxes: bool,
    /// Pass boxes around what a pre-pass sees (`--visible-receivers`).
    pub visible_receivers: bool,
    /// The scene box's ground (`--ground`).
    pub ground: Option<Ground>,
    /// Stable maps (`-stable`): compared with `uniform-stable`.
    pub stable: bool,
    /// The split scheme (`@SCHEME`, as `--scheme` takes it); `None`: the
    /// default.
    pub scheme: Option<String>,
    /// The splits share the method's texels by predicted aliasing
    /// (`-shared`, `--budget`), each at most the single map's side.
    pub shared: bool,
}

/// `uniform`, `psm`, `lispsm`, `tsm`, or one of them followed by a split
/// count of 2–16 (`lispsm4`; `pssm4-lispsm`, demo's name, also reads), each
/// also with `-stable` for stable maps (`lispsm-stable`).
pub fn parse_sweep_method(s: &str) -> Result<SweepMethod, String> {
    let t = s.trim().to_ascii_lowercase();
    if let Some(base) = t.strip_suffix("-shared") {
        let m = parse_sweep_method(base)?;
        if m.splits < 2 || m.stable {
            return Err(format!("sweep method {s:?}: -shared needs a split count and no -stable (auto4-shared)"));
        }
        return Ok(SweepMethod { name: format!("{}-shared", m.name), shared: true, ..m });
    }
    if let Some(base) = t.strip_suffix("-stable") {
        let m = parse_sweep_method(base)?;
        return Ok(SweepMethod { name: format!("{}-stable", m.name), stable: true, ..m });
    }
    if let Some((base, scheme)) = t.split_once('@') {
        let m = parse_sweep_method(base)?;
        if m.splits < 2 {
            return Err(format!("sweep method {s:?}: a split scheme needs a split count (lispsm4@{scheme})"));
        }
        let o = FitOptions { scheme: Some(scheme.to_string()), splits: m.splits, ..FitOptions::default() };
        o.settings().map_err(|e| format!("sweep method {s:?}: {e}"))?;
        return Ok(SweepMethod { name: format!("{}@{scheme}", m.name), scheme: Some(scheme.to_string()), ..m });
    }
    let t = match t.strip_prefix("pssm").and_then(|r| r.split_once('-')) {
        Some((k, m)) => format!("{m}{k}"),
        None => t,
    };
    let digits = t.trim_start_matches(|c: char| c.is_ascii_alphabetic()).len();
    let (m, k) = t.split_at(t.len() - digits);
    let method = super::fit::parse_method(m).map_err(|_| {
        format!("unknown sweep method {s:?}: expected uniform, psm, lispsm, tsm, or one of them followed by a split count (lispsm4)")
    })?;
    let splits = if k.is_empty() {
        1
    } else {
        k.parse::<usize>().ok().filter(|k| (1..=16).contains(k)).ok_or_else(|| format!("sweep method {s:?}: split count must be 1–16"))?
    };
    let name = if splits == 1 { m.to_string() } else { format!("{m}{splits}") };
    Ok(SweepMethod {
        name,
        method,
        splits,
        sdsm: false,
        receiver_boxes: false,
        visible_receivers: false,
        ground: None,
        stable: false,
        scheme: None,
        shared: false,
    })
}

impl SweepMethod {
    /// Fit options at a texel budget of `resolution`² for the whole method
    /// (k splits get resolution/√k per side each: R/2 for four; shared, each
    /// its own size within `resolution`² in all, at most `resolution`).
    pub fn options(&self, resolution: u32) -> FitOptions {
        let res = if self.splits == 1 || self.shared {
            resolution
        } else {
            ((resolution as f64 / (self.splits as f64).sqrt()).round() as u32).max(1)
        };
        FitOptions {
            method: self.method,
            splits: self.splits,
            resolution: res,
            budget: self.shared.then_some(u64::from(resolution).pow(2)),
            sdsm: self.sdsm,
            receiver_boxes: self.receiver_boxes,
            visible_receivers: self.visible_receivers,
            ground: self.ground,
            stable: self.stable,
            scheme: self.scheme.clone(),
            ..FitOptions::default()
        }
    }
}

/// The travel direction of a sun at `elevation_deg` above the horizon and
/// `azimuth_deg` from the camera's view direction (see the module docs).
pub fn sun_direction(camera: &render::CameraSpec, elevation_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (h, r) = horizontal_frame(camera);
    let (el, az) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    (h * az.cos() + r * az.sin()) * el.cos() - DVec3::Y * el.sin()
}

/// The horizontal view direction and the horizontal right of the camera
/// (for a camera looking straight up or down, its up vector's projection
/// stands in for the view direction).
fn horizontal_frame(camera: &render::CameraSpec) -> (DVec3, DVec3) {
    let flat = |v: DVec3| DVec3::new(v.x, 0.0, v.z);
    let f = camera.forward.normalize();
    let mut h = flat(f);
    if h.length() < 1e-9 {
        h = flat(camera.up.normalize()) * -f.y.signum();
    }
    if h.length() < 1e-9 {
        h = DVec3::NEG_Z;
    }
    let h = h.normalize();
    (h, h.cross(DVec3::Y).normalize())
}

/// Elevation and azimuth (degrees) of a directional light's travel direction.
pub fn sun_angles(camera: &render::CameraSpec, direction: DVec3) -> (f64, f64) {
    let (h, r) = horizontal_frame(camera);
    let d = direction.normalize();
    let el = (-d.y).clamp(-1.0, 1.0).asin().to_degrees();
    let az = d.dot(r).atan2(d.dot(h)).to_degrees();
    (el, if az < 0.0 { az + 360.0 } else { az })
}

/// One light of a sweep.
#[derive(Clone, Copy, Debug)]
pub struct SweepLight {
    /// Degrees; NaN for a point or spot light.
    pub elevation: f64,
    pub azimuth: f64,
    pub light: LightSpec,
}

/// What a sweep renders.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    pub camera: render::CameraSpec,
    pub lights: Vec<SweepLight>,
    pub methods: Vec<SweepMethod>,
    pub resolution: u32,
    pub size: (u32, u32),
}

impl SweepPlan {
    /// The grid of elevations × azimuths seen by `camera`.
    pub fn grid(
        camera: render::CameraSpec,
        elevations: &[f64],
        azimuths: &[f64],
        methods: Vec<SweepMethod>,
        resolution: u32,
        size: (u32, u32),
    ) -> SweepPlan {
        let mut lights = Vec::new();
        for &elevation in elevations {
            for &azimuth in azimuths {
                lights.push(SweepLight {
                    elevation,
                    azimuth,
                    light: LightSpec::Directional { direction: sun_direction(&camera, elevation, azimuth) },
                });
            }
        }
        SweepPlan { camera, lights, methods, resolution, size }
    }

    /// The plan `sweep`'s options describe for `scene`.
    pub fn from_options(scene: &Scene, o: &SweepOptions) -> Result<SweepPlan, String> {
        if o.methods.is_empty() {
            return Err("--methods: no method given".into());
        }
        for (what, v) in [("--elevations", &o.elevations), ("--azimuths", &o.azimuths)] {
            if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
                return Err(format!("{what}: need at least one finite angle"));
            }
        }
        if let Some(&e) = o.elevations.iter().find(|e| !(**e > 0.0 && **e <= 90.0)) {
            return Err(format!("--elevations: {e}° is not within (0°, 90°] (a sun above the horizon)"));
        }
        let camera = o.camera.map_or(scene.camera, |c| c.resolve(&scene.camera));
        camera.validate().map_err(|e| e.to_string())?;
        let methods = o
            .methods
            .iter()
            .map(|m| SweepMethod {
                sdsm: o.sdsm,
                receiver_boxes: o.receiver_boxes,
                visible_receivers: o.visible_receivers,
                ground: o.ground,
                ..m.clone()
            })
            .collect();
        let mut plan = SweepPlan::grid(camera, &o.elevations, &o.azimuths, methods, o.resolution, o.size);
        if let Some(l) = o.light {
            let light = l.resolve(&scene.bounds);
            light.validate().map_err(|e| e.to_string())?;
            let (elevation, azimuth) = match light {
                LightSpec::Directional { direction } => sun_angles(&camera, direction),
                _ => (f64::NAN, f64::NAN),
            };
            plan.lights = vec![SweepLight { elevation, azimuth, light }];
        }
        Ok(plan)
    }
}

/// The measurements of one configuration.
#[derive(Clone, Debug)]
pub struct SweepRow {
    pub scene: String,
    pub method: String,
    /// Index into the plan's lights and methods.
    pub light_index: usize,
    pub method_index: usize,
    pub elevation: f64,
    pub azimuth: f64,
    pub light: LightSpec,
    /// Texels per side of each map.
    pub resolution: u32,
    pub maps: usize,
    pub aliasing: AliasingStats,
    pub mismatch: MismatchStats,
    /// Each active map's utilisation (the fraction of its area that the
    /// projection of its focus body covers), their mean and minimum.
    pub utilisation: Vec<f64>,
    pub utilisation_mean: f64,
    pub utilisation_min: f64,
    /// The fit's notes and skip reasons (`skipped:NAME`).
    pub notes: Vec<String>,
    /// p95 and maximum aliasing over uniform's at the same light (NaN
    /// without a uniform row).
    pub p95_ratio: f64,
    pub max_ratio: f64,
    /// The largest of the maps' predicted maximum aliasing, in screen pixels
    /// per texel (`render`'s `predicted_aliasing_px`; NaN where no map
    /// predicts any).
    pub predicted_max: f64,
}

impl SweepRow {
    pub fn label(&self) -> String {
        if self.elevation.is_finite() {
            format!("{} el {} az {}", self.method, self.elevation, self.azimuth)
        } else {
            format!("{} light {}", self.method, self.light_index)
        }
    }

    pub fn has_note(&self, note: &str) -> bool {
        self.notes.iter().any(|n| n == note)
    }
}

/// A sweep's result.
#[derive(Clone, Debug)]
pub struct Sweep {
    pub scene: String,
    pub plan: SweepPlan,
    pub adapter: render::AdapterSummary,
    pub rows: Vec<SweepRow>,
}

/// A progress line on stderr: `[12/90] lispsm el 35 az 120`, rewritten in
/// place on a terminal.
pub fn progress_line(done: usize, total: usize, what: &str) {
    if std::io::stderr().is_terminal() {
        eprint!("\r[{done}/{total}] {what:<40}");
        if done == total {
            eprintln!();
        }
    } else {
        eprintln!("[{done}/{total}] {what}");
    }
}

fn render_one(
    renderer: &mut Renderer,
    scene: &Scene,
    plan: &SweepPlan,
    light: &SweepLight,
    m: &SweepMethod,
    maps: bool,
) -> Result<(render::RenderOutput, Value), String> {
    let frame = Frame { camera: plan.camera, light: light.light };
    render_frame(renderer, scene, &frame, &m.options(plan.resolution), plan.size, maps, None)
}

/// Renders every configuration of `plan`, lights in order and every method
/// at each; `progress(k, total, label)` is called before the k-th render.
pub fn sweep(
    renderer: &mut Renderer,
    scene: &Scene,
    plan: &SweepPlan,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Sweep, String> {
    let total = plan.lights.len() * plan.methods.len();
    let mut rows = Vec::with_capacity(total);
    for (li, light) in plan.lights.iter().enumerate() {
        let first = rows.len();
        for (mi, m) in plan.methods.iter().enumerate() {
            let mut row = SweepRow {
                scene: scene.name.clone(),
                method: m.name.clone(),
                light_index: li,
                method_index: mi,
                elevation: light.elevation,
                azimuth: light.azimuth,
                light: light.light,
                resolution: m.options(plan.resolution).resolution,
                maps: 0,
                aliasing: AliasingStats::default(),
                mismatch: MismatchStats::default(),
                utilisation: Vec::new(),
                utilisation_mean: f64::NAN,
                utilisation_min: f64::NAN,
                notes: Vec::new(),
                p95_ratio: f64::NAN,
                max_ratio: f64::NAN,
                predicted_max: f64::NAN,
            };
            progress(rows.len() + 1, total, &row.label());
            let (out, extra) =
                render_one(renderer, scene, plan, light, m, false).map_err(|e| format!("{} {}: {e}", scene.name, row.label()))?;
            let met = &out.metrics;
            row.maps = met.maps;
            row.aliasing = met.aliasing;
            row.mismatch = met.mismatch.ok_or("the renderer gave no ground truth")?;
            let fit = &extra["fit"];
            row.utilisation = met.map_utilisation.clone();
            row.utilisation_mean = met.utilisation_mean.unwrap_or(f64::NAN);
            row.utilisation_min = met.utilisation_min.unwrap_or(f64::NAN);
            let names = |k: &str| {
                fit[k].as_array().map_or(Vec::new(), |a| a.iter().filter_map(|v| v.as_str().map(str::to_owned)).collect::<Vec<_>>())
            };
            row.predicted_max = predicted_max(&extra["predicted_aliasing_px"]);
            row.notes = names("notes");
            row.notes.extend(names("skipped").into_iter().map(|s| format!("skipped:{s}")));
            rows.push(row);
        }
        set_uniform_ratios(&mut rows[first..]);
    }
    Ok(Sweep { scene: scene.name.clone(), plan: plan.clone(), adapter: renderer.adapter().clone(), rows })
}

/// Each row's p95 and maximum over its uniform map's at the same light:
/// stable maps over the stable uniform map, the others over the plain one
/// (`uniform`, one map); in a run without that one map, over the uniform
/// maps of the row's own splits (`uniform4@practical` for
/// `lispsm4@practical`, else `uniform4` for `lispsm4…`), so that a run of
/// splits alone still ranks its worst.
fn set_uniform_ratios(rows: &mut [SweepRow]) {
    for i in 0..rows.len() {
        let method = &rows[i].method;
        let stable = if method.ends_with("-stable") { "-stable" } else { "" };
        // What follows the method's name: its split count, scheme and kind.
        let tail = method.trim_start_matches(|c: char| c.is_ascii_alphabetic());
        let count: String = tail.chars().take_while(char::is_ascii_digit).collect();
        let named = |name: String| rows.iter().find(|r| r.method == name).map(|r| r.aliasing);
        let reference = named(format!("uniform{stable}"))
            .or_else(|| named(format!("uniform{tail}")))
            .or_else(|| named(format!("uniform{count}{stable}")));
        let Some(u) = reference else { continue };
        let r = &mut rows[i];
        (r.p95_ratio, r.max_ratio) = (r.aliasing.p95 / u.p95, r.aliasing.max / u.max);
    }
}

/// The largest of the maps' predictions in `render`'s `predicted_aliasing_px`
/// (NaN where there is none).
fn predicted_max(per_map: &Value) -> f64 {
    per_map.as_array().map_or(f64::NAN, |a| a.iter().filter_map(Value::as_f64).fold(f64::NAN, f64::max))
}

/// Mismatch among adequately sampled pixels above which a configuration is
/// wrong (not merely undersampled).
pub const ADEQUATE_LIMIT: f64 = 0.005;

/// Adequately sampled pixels below which a configuration's `rate_adequate`
/// does not rank it among the worst (with fewer than 200, one wrong pixel
/// alone exceeds 0.5 %).
pub const MIN_ADEQUATE_PIXELS: u64 = 400;

/// The rows in order of badness: those whose `rate_adequate` exceeds
/// [`ADEQUATE_LIMIT`] over at least [`MIN_ADEQUATE_PIXELS`], worst first,
/// then the others by their p95 aliasing over uniform's, highest first.
pub fn worst(rows: &[SweepRow]) -> Vec<usize> {
    let key = |r: &SweepRow| {
        let a = if r.mismatch.adequate_pixels >= MIN_ADEQUATE_PIXELS { r.mismatch.rate_adequate } else { 0.0 };
        let ratio = if r.p95_ratio.is_finite() { r.p95_ratio } else { 0.0 };
        (if a > ADEQUATE_LIMIT { a } else { 0.0 }, ratio)
    };
    let mut idx: Vec<usize> = (0..rows.len()).collect();
    idx.sort_by(|&i, &j| {
        let (a, b) = (key(&rows[i]), key(&rows[j]));
        b.0.total_cmp(&a.0).then(b.1.total_cmp(&a.1)).then(i.cmp(&j))
    });
    idx
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        String::new()
    }
}

/// `sweep.csv`.
pub fn csv(sweep: &Sweep) -> String {
    let mut s = String::from("scene,method,elevation_deg,azimuth_deg,resolution,maps,aliasing_max,aliasing_p95,aliasing_mean,ratio_to_bound,angle_free_ratio,predicted_max,mismatch_rate,rate_off_edges,rate_adequate,adequate_pixels,utilisation_mean,utilisation_min,p95_ratio_to_uniform,max_ratio_to_uniform,notes\n");
    for r in &sweep.rows {
        let m = &r.mismatch;
        let fields = [
            csv_field(&r.scene),
            r.method.clone(),
            num(r.elevation),
            num(r.azimuth),
            r.resolution.to_string(),
            r.maps.to_string(),
            num(r.aliasing.max),
            num(r.aliasing.p95),
            num(r.aliasing.mean),
            num(r.aliasing.ratio),
            num(r.aliasing.angle_free_ratio),
            num(r.predicted_max),
            num(m.rate),
            num(m.rate_off_edges),
            num(m.rate_adequate),
            m.adequate_pixels.to_string(),
            num(r.utilisation_mean),
            num(r.utilisation_min),
            num(r.p95_ratio),
            num(r.max_ratio),
            csv_field(&r.notes.join(";")),
        ];
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    s
}

fn jnum(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

/// `sweep.json`.
pub fn summary(sweep: &Sweep, worst_rows: &[usize]) -> Value {
    let p = &sweep.plan;
    let configs: Vec<Value> = sweep
        .rows
        .iter()
        .map(|r| {
            let m = &r.mismatch;
            json!({
                "method": r.method, "elevation_deg": jnum(r.elevation), "azimuth_deg": jnum(r.azimuth), "light": r.light,
                "resolution": r.resolution, "maps": r.maps,
                "aliasing": {"max": jnum(r.aliasing.max), "p95": jnum(r.aliasing.p95), "mean": jnum(r.aliasing.mean), "pixels": r.aliasing.pixels,
                             "bound": jnum(r.aliasing.bound), "ratio_to_bound": jnum(r.aliasing.ratio),
                             "angle_free_ratio": jnum(r.aliasing.angle_free_ratio), "predicted_max": jnum(r.predicted_max)},
                "mismatch": {"rate": jnum(m.rate), "rate_off_edges": jnum(m.rate_off_edges), "rate_adequate": jnum(m.rate_adequate),
                             "pixels": m.pixels, "off_edge_pixels": m.off_edge_pixels, "adequate_pixels": m.adequate_pixels,
                             "false_shadow": m.false_shadow, "false_light": m.false_light},
                "utilisation": {"maps": r.utilisation, "mean": jnum(r.utilisation_mean), "min": jnum(r.utilisation_min)},
                "ratio_to_uniform": {"p95": jnum(r.p95_ratio), "max": jnum(r.max_ratio)},
                "notes": r.notes,
            })
        })
        .collect();
    json!({
        "scene": sweep.scene, "adapter": sweep.adapter, "size": [p.size.0, p.size.1], "resolution": p.resolution,
        "camera": p.camera, "methods": p.methods.iter().map(|m| &m.name).collect::<Vec<_>>(),
        "adequate_limit": ADEQUATE_LIMIT,
        "configurations": configs,
        "worst": worst_rows.iter().map(|&i| sweep.rows[i].label()).collect::<Vec<_>>(),
    })
}

/// One plot: `value` of every row against azimuth, a panel per elevation.
fn azimuth_plot(sweep: &Sweep, value: impl Fn(&SweepRow) -> f64) -> Vec<Panel> {
    let mut elevations: Vec<f64> = Vec::new();
    for r in &sweep.rows {
        if !elevations.iter().any(|e| e.total_cmp(&r.elevation).is_eq()) {
            elevations.push(r.elevation);
        }
    }
    elevations
        .iter()
        .map(|&el| Panel {
            title: format!("sun elevation {el} deg"),
            series: sweep
                .plan
                .methods
                .iter()
                .map(|m| {
                    let mut points: Vec<(f64, f64)> = sweep
                        .rows
                        .iter()
                        .filter(|r| r.method == m.name && r.elevation.total_cmp(&el).is_eq())
                        .map(|r| (r.azimuth, value(r)))
                        .collect();
                    points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    Series { name: m.name.clone(), points }
                })
                .collect(),
        })
        .collect()
}

fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// A sweep row's plotted quantity.
type RowValue = dyn Fn(&SweepRow) -> f64;

/// Writes the plots; the x axis spans the swept azimuths.
fn write_plots(dir: &Path, sweep: &Sweep) -> Result<(), String> {
    let az: Vec<f64> = sweep.rows.iter().map(|r| r.azimuth).filter(|a| a.is_finite()).collect();
    if az.is_empty() {
        return Ok(());
    }
    let lo = az.iter().cloned().fold(f64::INFINITY, f64::min).min(0.0);
    let hi = az.iter().cloned().fold(f64::NEG_INFINITY, f64::max).max(lo + 1.0);
    let hi = if hi <= 360.0 { 360.0_f64.max(hi) } else { hi };
    let step = if hi - lo > 180.0 { 60.0 } else { 30.0 };
    let ticks: Vec<f64> = (0..).map(|k| (lo / step).ceil() * step + k as f64 * step).take_while(|&x| x <= hi + 1e-9).collect();
    let scene = &sweep.scene;
    let (w, h) = sweep.plan.size;
    let base = |title: String, y_label: &str, y_scale, guide| Axes {
        title,
        x_label: "sun azimuth from view direction, degrees".into(),
        y_label: y_label.into(),
        x_range: (lo, hi),
        x_ticks: ticks.clone(),
        y_scale,
        guide,
    };
    let plots: [(&str, Axes, &RowValue); 3] = [
        (
            "aliasing_p95.png",
            base(format!("{scene}: p95 aliasing, {w}x{h}, {}²", sweep.plan.resolution), "screen pixels per texel (p95)", Scale::Log, None),
            &|r| r.aliasing.p95,
        ),
        ("mismatch_off_edges.png", base(format!("{scene}: mismatch off shadow edges"), "pixels wrong, %", Scale::Linear, None), &|r| {
            100.0 * r.mismatch.rate_off_edges
        }),
        (
            "mismatch_adequate.png",
            base(
                format!("{scene}: mismatch where the map resolves the shadow"),
                "pixels wrong, %",
                Scale::Linear,
                Some((100.0 * ADEQUATE_LIMIT, "0.5% limit".into())),
            ),
            &|r| 100.0 * r.mismatch.rate_adequate,
        ),
    ];
    for (name, axes, value) in plots {
        let panels = azimuth_plot(sweep, value);
        write_file(&dir.join(name), &lines::panels_png(&axes, &panels)?)?;
    }
    Ok(())
}

/// Re-renders the `worst` rows with their shadow maps, writes each one's
/// folder under `dir/worst/` and the contact sheet `dir/worst.png`: a row
/// per configuration (image, mismatch, maps).
fn write_worst(dir: &Path, renderer: &mut Renderer, scene: &Scene, sweep: &Sweep, worst_rows: &[usize]) -> Result<(), String> {
    if worst_rows.is_empty() {
        return Ok(());
    }
    let plan = &sweep.plan;
    let (w, _) = plan.size;
    let k = w.div_ceil(240).max(1);
    let mut lines: Vec<Vec<(Image, String)>> = Vec::new();
    for (rank, &i) in worst_rows.iter().enumerate() {
        let r = &sweep.rows[i];
        let m = &plan.methods[r.method_index];
        let (out, extra) = render_one(renderer, scene, plan, &plan.lights[r.light_index], m, true)?;
        let folder = if r.elevation.is_finite() {
            format!("{:02}-{}-el{}-az{}", rank + 1, r.method, r.elevation, r.azimuth)
        } else {
            format!("{:02}-{}-light{}", rank + 1, r.method, r.light_index)
        };
        write_outputs(&dir.join("worst").join(folder), &out, Some(&extra)).map_err(|e| e.to_string())?;
        let color = out.color.downscale(k);
        let th = color.height.max(1);
        let mut tiles = vec![(color, format!("{} p95 x{:.2} max x{:.2}", r.label(), r.p95_ratio, r.max_ratio))];
        if let Some(mm) = mismatch_view(&out) {
            let m = &r.mismatch;
            tiles.push((mm.downscale(k), format!("adequate {:.2}% off-edge {:.2}%", 100.0 * m.rate_adequate, 100.0 * m.rate_off_edges)));
        }
        for (j, map) in shadow_map_images(&out).iter().enumerate() {
            let f = map.height.div_ceil(th).max(1);
            let util = r.utilisation.get(j).map_or(String::new(), |u| format!(" util {u:.2}"));
            tiles.push((map.downscale(f), format!("map {j}{util}")));
        }
        lines.push(tiles);
    }
    let columns = lines.iter().map(Vec::len).max().unwrap_or(1);
    let blank = Image::new(1, 1, [255, 255, 255, 255]);
    let mut refs: Vec<(&Image, &str)> = Vec::new();
    for l in &lines {
        for c in 0..columns {
            refs.push(l.get(c).map_or((&blank, ""), |(i, s)| (i, s.as_str())));
        }
    }
    contact_sheet(&refs, columns).save_png(&dir.join("worst.png")).map_err(|e| e.to_string())
}

/// Writes `sweep.csv`, `sweep.json`, the plots and the worst configurations.
pub fn write(dir: &Path, renderer: &mut Renderer, scene: &Scene, sweep: &Sweep, worst_count: usize) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let order = worst(&sweep.rows);
    let worst_rows = &order[..worst_count.min(order.len())];
    write_file(&dir.join("sweep.csv"), csv(sweep).as_bytes())?;
    let text = serde_json::to_string_pretty(&summary(sweep, worst_rows)).map_err(|e| e.to_string())?;
    write_file(&dir.join("sweep.json"), (text + "\n").as_bytes())?;
    write_plots(dir, sweep)?;
    write_worst(dir, renderer, scene, sweep, worst_rows)
}

/// Runs `shadowfocus sweep` with `renderer`.
pub fn run_with(renderer: &mut Renderer, o: &SweepOptions, progress: impl FnMut(usize, usize, &str)) -> Result<Sweep, String> {
    let scene = render::load_scene(&o.scene).map_err(|e| e.to_string())?;
    let plan = SweepPlan::from_options(&scene, o)?;
    let result = sweep(renderer, &scene, &plan, progress)?;
    write(&o.out, renderer, &scene, &result, o.worst)?;
    Ok(result)
}

/// `shadowfocus sweep`.
pub fn run(o: &SweepOptions) -> Result<Sweep, String> {
    let mut renderer = Renderer::from_env().map_err(|e| e.to_string())?;
    run_with(&mut renderer, o, progress_line)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(forward: DVec3) -> render::CameraSpec {
        render::CameraSpec { eye: DVec3::ZERO, forward, up: DVec3::Y, fovy: 1.0, near: 0.1, far: 10.0 }
    }

    #[test]
    fn azimuth_zero_is_the_sun_behind_the_viewer() {
        let c = camera(DVec3::new(0.0, -0.3, 1.0));
        let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-12;
        // Behind: the light travels along the view direction (and down).
        assert!(close(sun_direction(&c, 0.0, 0.0), DVec3::Z));
        assert!(close(sun_direction(&c, 0.0, 180.0), DVec3::NEG_Z), "ahead: toward the viewer");
        // The camera looks along +z with +y up: its right is −x.
        assert!(close(sun_direction(&c, 0.0, 90.0), DVec3::NEG_X));
        assert!(close(sun_direction(&c, 90.0, 123.0), DVec3::NEG_Y));
        let d = sun_direction(&c, 30.0, 0.0);
        assert!((d.y + 0.5).abs() < 1e-12 && d.z > 0.0 && (d.length() - 1.0).abs() < 1e-12);
        for (el, az) in [(10.0, 0.0), (35.0, 120.0), (65.0, 330.0), (12.0, 180.0)] {
            let (e, a) = sun_angles(&c, sun_direction(&c, el, az));
            assert!((e - el).abs() < 1e-9 && (a - az).abs() < 1e-9, "{el} {az} → {e} {a}");
        }
        // A camera looking straight down still has a frame.
        let down = render::CameraSpec { up: DVec3::Z, ..camera(DVec3::NEG_Y) };
        assert!(sun_direction(&down, 20.0, 40.0).is_finite());
    }

    #[test]
    fn sweep_methods_parse() {
        let m = parse_sweep_method("lispsm4").unwrap();
        assert_eq!((m.name.as_str(), m.method, m.splits), ("lispsm4", Method::Lispsm, 4));
        assert_eq!(parse_sweep_method("pssm4-lispsm").unwrap(), m);
        assert_eq!(m.options(1024).resolution, 512, "four splits share one map's texel budget, as in demo");
        let u = parse_sweep_method("Uniform").unwrap();
        assert_eq!((u.name.as_str(), u.splits, u.options(1024).resolution), ("uniform", 1, 1024));
        assert!(parse_sweep_method("cascades").unwrap_err().contains("unknown sweep method"));
        assert!(parse_sweep_method("tsm99").unwrap_err().contains("1–16"));
        assert!(parse_sweep_method("4").is_err());
        let o = parse_sweep_method("auto4@optimal").unwrap();
        assert_eq!((o.name.as_str(), o.method, o.splits, o.scheme.as_deref()), ("auto4@optimal", Method::Auto, 4, Some("optimal")));
        assert_eq!(o.options(1024).settings().unwrap().splits.scheme, shadowfocus_focus::SplitScheme::Optimal);
        let g = parse_sweep_method("lispsm4@geometric:10-stable").unwrap();
        assert_eq!((g.scheme.as_deref(), g.stable), (Some("geometric:10"), true));
        assert!(parse_sweep_method("lispsm@optimal").unwrap_err().contains("needs a split count"));
        assert!(parse_sweep_method("lispsm4@sideways").unwrap_err().contains("unknown split scheme"));
        assert!(parse_sweep_method("lispsm4@geometric:-1").unwrap_err().contains("splits.first"));
        // Shared: one map's texels among the splits, each at most one map's side.
        let s = parse_sweep_method("auto4-shared").unwrap();
        let o = s.options(1024);
        assert_eq!((s.name.as_str(), o.resolution, o.budget), ("auto4-shared", 1024, Some(1024 * 1024)));
        assert!(o.settings().unwrap().texel_budget.is_some());
        assert!(parse_sweep_method("auto-shared").unwrap_err().contains("needs a split count"));
        assert!(parse_sweep_method("lispsm4-stable-shared").unwrap_err().contains("no -stable"));
    }

    fn row(method: &str, adequate: f64, ratio: f64) -> SweepRow {
        SweepRow {
            scene: "s".into(),
            method: method.into(),
            light_index: 0,
            method_index: 0,
            elevation: 10.0,
            azimuth: 0.0,
            light: LightSpec::Directional { direction: DVec3::NEG_Y },
            resolution: 1,
            maps: 1,
            aliasing: AliasingStats::default(),
            mismatch: MismatchStats { rate_adequate: adequate, adequate_pixels: 1000, ..MismatchStats::default() },
            utilisation: Vec::new(),
            utilisation_mean: f64::NAN,
            utilisation_min: f64::NAN,
            notes: vec!["a,b".into()],
            p95_ratio: ratio,
            max_ratio: ratio,
            predicted_max: f64::NAN,
        }
    }

    #[test]
    fn worst_puts_wrong_shadows_first_then_aliasing_ratios() {
        let mut few = row("g", 0.5, 1.2);
        few.mismatch.adequate_pixels = MIN_ADEQUATE_PIXELS - 1;
        let rows = [
            row("a", 0.0, 1.0),
            row("b", 0.001, 3.0),
            row("c", 0.02, 1.0),
            row("d", 0.3, 0.5),
            row("e", 0.0, f64::NAN),
            row("f", 0.0, 1.5),
            few,
        ];
        assert_eq!(worst(&rows), vec![3, 2, 1, 5, 6, 0, 4], "too few adequate pixels to rank by their mismatch");
    }

    #[test]
    fn splits_alone_are_ranked_over_their_own_uniform_splits() {
        let with = |method: &str, p95: f64| SweepRow {
            aliasing: AliasingStats { p95, max: 2.0 * p95, ..Default::default() },
            ..row(method, 0.0, f64::NAN)
        };
        let ratios = |rows: &[SweepRow]| rows.iter().map(|r| r.p95_ratio).collect::<Vec<_>>();
        // One uniform map: every row over it, splits too.
        let mut rows = vec![with("uniform", 2.0), with("lispsm", 1.0), with("uniform4", 4.0), with("lispsm4", 3.0)];
        set_uniform_ratios(&mut rows);
        assert_eq!(ratios(&rows), [1.0, 0.5, 2.0, 1.5]);
        // Splits alone: over the uniform splits of the same scheme where
        // there are any, else of the same count; the stable ones over theirs.
        let mut rows = vec![
            with("lispsm4", 3.0),
            with("uniform4", 4.0),
            with("tsm4-stable", 1.0),
            with("uniform4-stable", 2.0),
            with("psm4@practical", 8.0),
            with("uniform4@practical", 5.0),
            with("auto4@geometric:10", 2.0),
        ];
        set_uniform_ratios(&mut rows);
        assert_eq!(ratios(&rows), [0.75, 1.0, 0.5, 1.0, 1.6, 1.0, 0.5]);
        assert_eq!(rows[4].max_ratio, 1.6);
        assert_eq!(worst(&rows), vec![4, 1, 3, 5, 0, 2, 6]);
        // No uniform map of either kind: no ratio.
        let mut rows = vec![with("lispsm4", 3.0), with("uniform2", 1.0)];
        set_uniform_ratios(&mut rows);
        assert!(rows[0].p95_ratio.is_nan() && rows[1].p95_ratio == 1.0);
    }

    #[test]
    fn csv_has_one_row_per_configuration_and_quotes_notes() {
        let plan = SweepPlan::grid(camera(DVec3::Z), &[10.0], &[0.0], vec![], 64, (16, 9));
        let s = Sweep { scene: "s".into(), plan, adapter: Default::default(), rows: vec![row("a", 0.0, 1.0), row("b", 0.5, f64::NAN)] };
        let text = csv(&s);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let columns = lines[0].split(',').count();
        assert!(lines[0].contains("rate_adequate,adequate_pixels") && lines[0].ends_with(",notes"));
        assert!(lines[1].ends_with(",\"a,b\"") && lines[2].starts_with("s,b,10,0,"));
        assert_eq!(lines[2].matches(',').count(), columns, "one comma more inside the quoted notes");
        let j = summary(&s, &[1]);
        assert_eq!(j["configurations"][1]["ratio_to_uniform"]["p95"], Value::Null);
        assert_eq!(j["worst"][0], "b el 10 az 0");
    }

    #[test]
    fn the_predicted_maximum_is_the_largest_of_the_maps() {
        assert_eq!(predicted_max(&json!([null, 0.5, 0.75, 0.25])), 0.75);
        assert!(predicted_max(&json!([null, null])).is_nan() && predicted_max(&json!([])).is_nan());
        assert!(predicted_max(&Value::Null).is_nan());
    }
}
