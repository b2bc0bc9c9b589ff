//! `shadowfocus fit`: shadow-map matrices for JSON-lines cases.

use super::body::{case_median_ns, median, p99};
use super::case::{case_lines, parse_case, Case};
use serde_json::{json, Value};
use shadowfocus_focus::{
    camera_from_corners, fit, fit_frustum, fit_map, fit_prepared, BoxFace, ClipConvention, DepthHintCoverage, FocusResult, FocusSettings,
    Footprint, Ground, MapSizes, Method, PreparedView, SplitScheme, SplitSettings, TexelBudget,
};
use shadowfocus_geom::{Body, Camera, Focuser, Frustum};
use std::hint::black_box;
use std::io::{BufRead, Write};

/// Method and split choices shared by `fit`, `render` and `demo`.
#[derive(Clone, Debug, clap::Args)]
pub struct FitOptions {
    /// uniform | psm | lispsm | tsm | auto (per map, the least predicted aliasing)
    #[arg(long, default_value = "lispsm", value_parser = parse_method)]
    pub method: Method,
    /// Number of parallel splits (1 = a single map).
    #[arg(long, default_value_t = 1)]
    pub splits: usize,
    /// uniform | log | practical | geometric:FIRST (the first split ends at view depth FIRST, the
    /// rest geometric, as engines ship cascades) | optimal (per light, splits of even predicted
    /// aliasing). Default optimal; practical with --stable, whose planes must hold still
    #[arg(long)]
    pub scheme: Option<String>,
    /// Weight of the logarithmic scheme in the practical one.
    #[arg(long, default_value_t = 0.5)]
    pub lambda: f64,
    /// Shadow-map resolution in texels per side.
    #[arg(long, default_value_t = 1024)]
    pub resolution: u32,
    /// Stable maps: texel-snapped, their extents and warps on world-fixed lattices (every method but PSM).
    #[arg(long)]
    pub stable: bool,
    /// The clip convention of the matrices: wgpu | d3d | metal | vulkan | opengl.
    #[arg(long, default_value = "wgpu", value_parser = parse_clip)]
    pub clip: ClipConvention,
    /// Reversed-Z in that convention (depth 1 nearest the light).
    #[arg(long)]
    pub reversed_z: bool,
    /// Fit each map's depth range to its receivers, for rendering with depth clamping.
    #[arg(long)]
    pub depth_clamp: bool,
    /// Fit each map's image to its receivers (the visible part of its body), not the whole body.
    #[arg(long)]
    pub fit_receivers: bool,
    /// With --fit-receivers: texels added around the receivers for the lookup filter.
    #[arg(long, default_value_t = Footprint::DEFAULT_MARGIN_TEXELS)]
    pub receiver_margin: f64,
    /// Fit to the visible depth range of the frame, reduced from a depth pre-pass
    /// (sample-distribution shadow maps; rendering commands only).
    #[arg(long)]
    pub sdsm: bool,
    /// With --sdsm: what the splits cover, hint (only the visible depth range: exact for this
    /// frame's own pre-pass) | view (the planes placed over the range, the outer splits reaching
    /// near and far: no pixel without a map when the range is a frame old).
    #[arg(long, default_value = "hint", value_parser = parse_coverage)]
    pub sdsm_coverage: DepthHintCoverage,
    /// Pass the boxes of the scene's receivers (rendering commands only): the predicted aliasing
    /// that auto and optimal placement use takes its receivers on them, and --fit-receivers and
    /// --depth-clamp fit to their bounds.
    #[arg(long)]
    pub receiver_boxes: bool,
    /// Pass boxes around what a depth pre-pass of the frame sees (rendering commands only; not
    /// with --receiver-boxes): the receivers the scene's pixels show, sliced by view depth, in
    /// place of boxes the engine knows.
    #[arg(long, conflicts_with = "receiver_boxes")]
    pub visible_receivers: bool,
    /// The ground of an open scene, FACE[@LEVEL]: the face of the scene box it is parallel to,
    /// min-y for a y-up world (min-x | max-x | min-y | max-y | min-z | max-z), and where it lies
    /// above that face, its level on the face's axis (min-y@0: a world on a slab whose top is
    /// y = 0). The predicted aliasing that auto, the warp guard and optimal placement use takes
    /// its receivers on it, not on the box's walls.
    #[arg(long, value_parser = parse_ground)]
    pub ground: Option<Ground>,
    /// Texels the maps share by their predicted aliasing, as TEXELS or COUNTxSIDE (COUNT maps of
    /// SIDE² texels, e.g. 4x1024): each map takes its own size, at most --resolution.
    #[arg(long, value_parser = parse_budget)]
    pub budget: Option<u64>,
    /// With --budget: the sizes a map may take, any | pow2 (powers of two: coarse, they gain
    /// only where the maps' aliasing differs by more than 2×).
    #[arg(long, default_value = "any", value_parser = parse_sizes)]
    pub budget_sizes: MapSizes,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            method: Method::Lispsm,
            splits: 1,
            scheme: None,
            lambda: 0.5,
            resolution: 1024,
            stable: false,
            clip: ClipConvention::WGPU,
            reversed_z: false,
            depth_clamp: false,
            fit_receivers: false,
            receiver_margin: Footprint::DEFAULT_MARGIN_TEXELS,
            sdsm: false,
            sdsm_coverage: DepthHintCoverage::Hint,
            receiver_boxes: false,
            visible_receivers: false,
            ground: None,
            budget: None,
            budget_sizes: MapSizes::Any,
        }
    }
}

/// A texel budget: `TEXELS`, or `COUNTxSIDE` for COUNT maps of SIDE² texels.
pub fn parse_budget(s: &str) -> Result<u64, String> {
    let bad = || format!("texel budget {s:?} is not TEXELS or COUNTxSIDE (e.g. 4194304 or 4x1024)");
    let texels = match s.split_once('x') {
        Some((count, side)) => {
            let (count, side): (u64, u64) = (count.parse().map_err(|_| bad())?, side.parse().map_err(|_| bad())?);
            count.checked_mul(side).and_then(|c| c.checked_mul(side)).ok_or_else(bad)?
        }
        None => s.parse().map_err(|_| bad())?,
    };
    Ok(texels)
}

pub fn parse_sizes(s: &str) -> Result<MapSizes, String> {
    match s {
        "pow2" => Ok(MapSizes::PowerOfTwo),
        "any" => Ok(MapSizes::Any),
        _ => Err(format!("unknown map sizes {s:?}: expected pow2 or any")),
    }
}

/// A ground as `--ground` names it: FACE or FACE@LEVEL.
pub fn parse_ground(s: &str) -> Result<Ground, String> {
    let names = ["min-x", "max-x", "min-y", "max-y", "min-z", "max-z"];
    let (face, level) = match s.split_once('@') {
        Some((face, level)) => (face, Some(level)),
        None => (s, None),
    };
    let k = names.iter().position(|n| *n == face).ok_or_else(|| format!("unknown face {face:?}: expected one of {}", names.join(", ")))?;
    let level = match level {
        Some(l) => {
            Some(l.parse::<f64>().ok().filter(|l| l.is_finite()).ok_or_else(|| format!("ground level {l:?} is not a finite number"))?)
        }
        None => None,
    };
    Ok(Ground { face: BoxFace::ALL[k], level })
}

pub fn parse_coverage(s: &str) -> Result<DepthHintCoverage, String> {
    match s {
        "hint" => Ok(DepthHintCoverage::Hint),
        "view" => Ok(DepthHintCoverage::View),
        _ => Err(format!("unknown coverage {s:?}: expected hint or view")),
    }
}

pub fn parse_clip(s: &str) -> Result<ClipConvention, String> {
    match s {
        "wgpu" => Ok(ClipConvention::WGPU),
        "d3d" => Ok(ClipConvention::D3D),
        "metal" => Ok(ClipConvention::METAL),
        "vulkan" => Ok(ClipConvention::VULKAN),
        "opengl" => Ok(ClipConvention::OPENGL),
        _ => Err(format!("unknown clip convention {s:?}: expected wgpu, d3d, metal, vulkan or opengl")),
    }
}

pub fn parse_method(s: &str) -> Result<Method, String> {
    match s {
        "uniform" => Ok(Method::Uniform),
        "psm" => Ok(Method::Psm),
        "lispsm" => Ok(Method::Lispsm),
        "tsm" => Ok(Method::Tsm),
        "auto" => Ok(Method::Auto),
        _ => Err(format!("unknown method {s:?}: expected uniform, psm, lispsm, tsm or auto")),
    }
}

impl FitOptions {
    /// The split scheme's name: as given, else `practical` with `--stable`
    /// and `optimal` otherwise.
    pub fn scheme_name(&self) -> &str {
        match &self.scheme {
            Some(s) => s,
            None if self.stable => "practical",
            None => "optimal",
        }
    }

    pub fn settings(&self) -> Result<FocusSettings, String> {
        if self.visible_receivers && self.receiver_boxes {
            return Err("--visible-receivers and --receiver-boxes both give the receiver boxes: pass one".into());
        }
        if self.sdsm_coverage != DepthHintCoverage::Hint && !self.sdsm {
            return Err("--sdsm-coverage says what a visible depth hint covers: use it with --sdsm".into());
        }
        let scheme = match self.scheme_name() {
            "uniform" => SplitScheme::Uniform,
            "log" => SplitScheme::Log,
            "practical" => SplitScheme::Practical { lambda: self.lambda },
            "optimal" => SplitScheme::Optimal,
            s => match s.strip_prefix("geometric:").map(str::parse::<f64>) {
                Some(Ok(first)) => SplitScheme::Geometric { first },
                _ => return Err(format!("unknown split scheme {s:?}: expected uniform, log, practical, geometric:FIRST or optimal")),
            },
        };
        let s = FocusSettings {
            method: self.method,
            splits: SplitSettings { count: self.splits, scheme, ..SplitSettings::default() },
            resolution: self.resolution,
            stable: self.stable,
            clip: if self.reversed_z { self.clip.reversed() } else { self.clip },
            depth_clamp: self.depth_clamp,
            footprint: if self.fit_receivers { Footprint::Receivers { margin_texels: self.receiver_margin } } else { Footprint::Body },
            texel_budget: self.budget.map(|texels| TexelBudget { texels, sizes: self.budget_sizes }),
            visible_depth_coverage: self.sdsm_coverage,
            ground: self.ground,
            ..FocusSettings::default()
        };
        s.validate().map_err(|e| e.to_string())?;
        Ok(s)
    }
}

/// The case's camera: given, or recovered from the corners.
pub fn case_camera(case: &Case) -> Result<Camera, String> {
    match case.camera {
        Some(c) => Ok(c),
        None => camera_from_corners(case.view.corners()).map(|r| r.camera).map_err(|e| e.to_string()),
    }
}

/// Fits a case as `shadowfocus fit` does: a case given by a camera with
/// [`fit`]; a case given by its eight corners with [`fit_frustum`], so that
/// every body comes from exactly those corners (the recovered camera only
/// chooses the parameterisation and the split depths).
pub fn fit_case(case: &Case, settings: &FocusSettings, out: &mut FocusResult) -> Result<(), String> {
    let cam = case_camera(case)?;
    let r = match case.camera {
        Some(_) => fit(&cam, &case.light, &case.scene, settings, out),
        None => fit_frustum(&case.view, &cam, &case.light, &case.scene, settings, out),
    };
    r.map_err(|e| e.to_string())
}

/// [`PreparedView::prepare`] (camera cases) or
/// [`PreparedView::prepare_frustum`] (corner cases), as [`fit_case`] fits.
pub fn prepare_case(view: &mut PreparedView, case: &Case, cam: &Camera, settings: &FocusSettings) -> Result<(), String> {
    let r = match case.camera {
        Some(_) => view.prepare(cam, settings),
        None => view.prepare_frustum(&case.view, cam, settings),
    };
    r.map_err(|e| e.to_string())
}

fn result_json(case: &Case, settings: &FocusSettings, r: &FocusResult) -> Value {
    let maps: Vec<Value> = r
        .maps()
        .iter()
        .map(|m| {
            let body = m.body();
            let vertices: Vec<[f64; 3]> = body.vertices().iter().map(|v| v.to_array()).collect();
            json!({
                "split": m.split_range,
                "state": format!("{:?}", m.fit.state).to_lowercase(),
                "face": m.face.map(|f| f.name()),
                "matrix": m.fit.clip_from_world.to_cols_array(),
                "depth_test": m.fit.depth_test.name(),
                "texel_size": m.fit.texel_size.map(|t| if t.is_finite() { Value::from(t) } else { Value::Null }),
                "resolution": m.fit.resolution,
                "utilisation": m.utilisation(),
                "light_near": m.light_near,
                "body": {"dimension": body.dimension().as_i32(), "vertices": vertices},
            })
        })
        .collect();
    json!({
        "id": case.id,
        "method": settings.method.name(),
        "maps": maps,
        "split_depths": r.split_depths(),
        "skipped": r.skipped.names().collect::<Vec<_>>(),
        "notes": r.notes.names().collect::<Vec<_>>(),
    })
}

/// Processes every line; returns how many failed.
pub fn run(input: impl BufRead, mut out: impl Write, settings: &FocusSettings) -> std::io::Result<usize> {
    let mut failed = 0;
    let mut result = FocusResult::new();
    for line in case_lines(input) {
        let line = line?;
        let value = match parse_case(&line) {
            Ok(case) => match fit_case(&case, settings, &mut result) {
                Ok(()) => result_json(&case, settings, &result),
                Err(e) => {
                    failed += 1;
                    json!({"id": case.id, "error": e})
                }
            },
            Err(e) => {
                failed += 1;
                json!({"id": e.id, "error": e.message})
            }
        };
        writeln!(out, "{value}")?;
    }
    Ok(failed)
}

/// `--bench`: per-case median time of a whole fit (bodies included); and,
/// over the cases whose camera a view can be prepared for, the time of
/// preparing it in place ([`PreparedView::prepare`]) and of one light's fit from it
/// ([`fit_prepared`]): the cost per light when a camera serves several.
pub fn bench(input: impl BufRead, settings: &FocusSettings) -> std::io::Result<Value> {
    let mut cases = Vec::new();
    for line in case_lines(input) {
        let line = line?;
        if let Ok(c) = parse_case(&line) {
            if let Ok(cam) = case_camera(&c) {
                cases.push((c, cam));
            }
        }
    }
    let mut result = FocusResult::new();
    let mut ns: Vec<f64> = cases
        .iter()
        .map(|(c, _)| {
            case_median_ns(|| {
                let _ = fit_case(c, settings, &mut result);
            })
        })
        .collect();
    let (mut prepare_ns, mut prepared_ns) = (Vec::new(), Vec::new());
    for (c, cam) in &cases {
        let Ok(mut view) = PreparedView::new(cam, settings) else { continue };
        if prepare_case(&mut view, c, cam, settings).is_err() {
            continue;
        }
        prepare_ns.push(case_median_ns(|| {
            let _ = black_box(prepare_case(&mut view, black_box(c), cam, settings));
        }));
        prepared_ns.push(case_median_ns(|| {
            let _ = fit_prepared(black_box(&view), &c.light, &c.scene, &mut result);
        }));
    }
    Ok(json!({
        "cases": ns.len(),
        "method": settings.method.name(),
        "splits": settings.splits.count,
        "median_ns": median(&mut ns),
        "p99_ns": p99(&mut ns),
        "prepared_view_cases": prepared_ns.len(),
        "prepare_view_median_ns": median(&mut prepare_ns),
        "fit_prepared_median_ns": median(&mut prepared_ns),
        "fit_prepared_p99_ns": p99(&mut prepared_ns),
    }))
}

/// `--bench --phases`: where one map's time goes. Over the cases that
/// `fit` answers with exactly one map, the median time of each step on its
/// own (lines that do not parse or give no camera are skipped, as in
/// [`bench`]): the view frustum from the camera (its exact validation included),
/// the body in that frustum, fitting the map to that body, and the whole
/// `fit`. Medians of the parts need not add up to the median of the whole.
pub fn phases(input: impl BufRead, settings: &FocusSettings) -> std::io::Result<Value> {
    let mut result = FocusResult::new();
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    let (mut frustum_ns, mut body_ns, mut map_ns, mut whole_ns) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut other, mut skipped) = (0, 0);
    for line in case_lines(input) {
        let line = line?;
        let Ok(c) = parse_case(&line) else {
            skipped += 1;
            continue;
        };
        let Ok(cam) = case_camera(&c) else {
            skipped += 1;
            continue;
        };
        let one_map = fit(&cam, &c.light, &c.scene, settings, &mut result).is_ok() && result.maps().len() == 1;
        // NOTE: a point light that `fit` truncates or splits into cube faces
        // has no single body to time apart; such cases are only counted.
        let Some(view) = one_map.then(|| Frustum::from_camera(&cam).ok()).flatten() else {
            other += 1;
            continue;
        };
        if focuser.focus_into(&mut body, &view, &c.light, &c.scene).is_err() || fit_map(&cam, &c.light, &body, settings).is_err() {
            other += 1;
            continue;
        }
        frustum_ns.push(case_median_ns(|| {
            let _ = black_box(Frustum::from_camera(black_box(&cam)));
        }));
        body_ns.push(case_median_ns(|| {
            let _ = focuser.focus_into(&mut body, black_box(&view), &c.light, &c.scene);
        }));
        map_ns.push(case_median_ns(|| {
            let _ = black_box(fit_map(&cam, &c.light, black_box(&body), settings));
        }));
        whole_ns.push(case_median_ns(|| {
            let _ = fit(&cam, &c.light, &c.scene, settings, &mut result);
        }));
    }
    Ok(json!({
        "cases": whole_ns.len(),
        "cases_not_timed": other,
        "lines_skipped": skipped,
        "method": settings.method.name(),
        "frustum_median_ns": median(&mut frustum_ns),
        "body_median_ns": median(&mut body_ns),
        "fit_map_median_ns": median(&mut map_ns),
        "whole_fit_median_ns": median(&mut whole_ns),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::bench_test::{assert_times, smoke_lines};

    /// `--clip`, `--reversed-z` and `--depth-clamp` reach the settings, and
    /// an unknown convention is refused with the names it accepts.
    #[test]
    fn clip_options_reach_the_settings() {
        for (name, clip) in [("wgpu", ClipConvention::WGPU), ("vulkan", ClipConvention::VULKAN), ("opengl", ClipConvention::OPENGL)] {
            let opts = FitOptions { clip: parse_clip(name).unwrap(), reversed_z: true, depth_clamp: true, ..FitOptions::default() };
            let s = opts.settings().unwrap();
            assert_eq!(s.clip, clip.reversed(), "{name}");
            assert!(s.depth_clamp);
        }
        assert_eq!(FitOptions::default().settings().unwrap().clip, ClipConvention::WGPU);
        let err = parse_clip("directx9").unwrap_err();
        assert!(err.contains("wgpu, d3d, metal, vulkan or opengl"), "{err}");
    }

    /// `--sdsm-coverage` reaches the settings with `--sdsm` and is refused
    /// without it; an unknown coverage is refused with the names it accepts.
    #[test]
    fn sdsm_coverage_needs_sdsm() {
        let view = parse_coverage("view").unwrap();
        let with = FitOptions { sdsm: true, sdsm_coverage: view, ..FitOptions::default() };
        assert_eq!(with.settings().unwrap().visible_depth_coverage, DepthHintCoverage::View);
        let err = FitOptions { sdsm_coverage: view, ..FitOptions::default() }.settings().unwrap_err();
        assert!(err.contains("use it with --sdsm"), "{err}");
        assert!(parse_coverage("all").unwrap_err().contains("hint or view"));
    }

    /// `--ground` takes a face alone or at a level; an unknown face and a
    /// level that is not a finite number are refused, naming what is wrong.
    #[test]
    fn ground_takes_a_face_and_a_level() {
        assert_eq!(parse_ground("min-y"), Ok(Ground::face(BoxFace::MinY)));
        assert_eq!(parse_ground("max-z@-2.5"), Ok(Ground::at(BoxFace::MaxZ, -2.5)));
        let opts = FitOptions { ground: Some(parse_ground("min-y@0").unwrap()), ..FitOptions::default() };
        assert_eq!(opts.settings().unwrap().ground, Some(Ground::at(BoxFace::MinY, 0.0)));
        assert!(parse_ground("down").unwrap_err().contains("expected one of min-x"));
        for bad in ["min-y@", "min-y@zero", "min-y@inf", "min-y@NaN"] {
            assert!(parse_ground(bad).unwrap_err().contains("is not a finite number"), "{bad}");
        }
    }

    /// `--bench` times every readable case whole and, for each camera a view
    /// can be prepared for, the preparation and the fit from it; a line that
    /// is not JSON is left out of both.
    #[test]
    fn bench_times_whole_and_prepared_fits() {
        let lines = smoke_lines(5);
        let input = format!("{}\nnot json\n", lines.join("\n"));
        let settings = FocusSettings { splits: SplitSettings { count: 2, ..Default::default() }, ..Default::default() };
        let r = bench(input.as_bytes(), &settings).unwrap();
        assert_eq!(r["cases"].as_u64(), Some(lines.len() as u64));
        assert_eq!(r["prepared_view_cases"].as_u64(), Some(lines.len() as u64));
        assert_eq!(r["splits"].as_u64(), Some(2));
        assert_times(&r, &["median_ns", "p99_ns", "prepare_view_median_ns", "fit_prepared_median_ns", "fit_prepared_p99_ns"]);
    }

    /// Every readable case is either timed in all four phases or counted
    /// as not timed: here a point light inside the view, which `fit` answers
    /// with six cube faces.
    #[test]
    fn phases_time_one_map_cases_and_count_the_rest() {
        let lines = smoke_lines(8);
        let inside = r#"{"id": "light-in-view", "view": {"eye": [0, 2, 10], "forward": [0, 0, -1], "up": [0, 1, 0], "fovy_deg": 60, "aspect": 1.5, "near": 0.5, "far": 50}, "light": {"point": [0, 2, 0]}, "scene": {"min": [-20, 0, -40], "max": [20, 8, 5]}}"#;
        let input = format!("{}\n{inside}\nnot json\n", lines.join("\n"));
        let settings = FocusSettings::default();
        let mut result = FocusResult::new();
        let c = parse_case(inside).unwrap();
        fit(&case_camera(&c).unwrap(), &c.light, &c.scene, &settings, &mut result).unwrap();
        assert_eq!(result.maps().len(), 6);

        let r = phases(input.as_bytes(), &settings).unwrap();
        let count = |key: &str| r[key].as_u64().unwrap();
        assert_eq!(count("cases") + count("cases_not_timed") + count("lines_skipped"), lines.len() as u64 + 2);
        assert!(count("cases_not_timed") >= 1 && count("lines_skipped") >= 1);
        assert!(count("cases") >= 1);
        assert_times(&r, &["frustum_median_ns", "body_median_ns", "fit_map_median_ns", "whole_fit_median_ns"]);
    }
}
