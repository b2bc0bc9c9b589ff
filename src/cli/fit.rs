//! `shadowfocus fit`: shadow-map matrices for JSON-lines cases.

use super::body::{case_median_ns, median, p99};
use super::case::{case_lines, parse_case, Case};
use serde_json::{json, Value};
use shadowfocus_focus::{camera_from_corners, fit, FocusResult, FocusSettings, Method, SplitScheme, SplitSettings};
use shadowfocus_geom::Camera;
use std::io::{BufRead, Write};

/// Method and split choices shared by `fit`, `render` and `demo`.
#[derive(Clone, Debug, clap::Args)]
pub struct FitOptions {
    /// uniform | psm | lispsm | tsm
    #[arg(long, default_value = "lispsm", value_parser = parse_method)]
    pub method: Method,
    /// Number of parallel splits (1 = a single map).
    #[arg(long, default_value_t = 1)]
    pub splits: usize,
    /// uniform | log | practical
    #[arg(long, default_value = "practical")]
    pub scheme: String,
    /// Weight of the logarithmic scheme in the practical one.
    #[arg(long, default_value_t = 0.5)]
    pub lambda: f64,
    /// Shadow-map resolution in texels per side.
    #[arg(long, default_value_t = 1024)]
    pub resolution: u32,
    /// Texel-snapped, rotation-invariant fitting (uniform, directional).
    #[arg(long)]
    pub stable: bool,
}

pub fn parse_method(s: &str) -> Result<Method, String> {
    match s {
        "uniform" => Ok(Method::Uniform),
        "psm" => Ok(Method::Psm),
        "lispsm" => Ok(Method::Lispsm),
        "tsm" => Ok(Method::Tsm),
        _ => Err(format!("unknown method {s:?}: expected uniform, psm, lispsm or tsm")),
    }
}

impl FitOptions {
    pub fn settings(&self) -> Result<FocusSettings, String> {
        let scheme = match self.scheme.as_str() {
            "uniform" => SplitScheme::Uniform,
            "log" => SplitScheme::Log,
            "practical" => SplitScheme::Practical { lambda: self.lambda },
            s => return Err(format!("unknown split scheme {s:?}: expected uniform, log or practical")),
        };
        let s = FocusSettings {
            method: self.method,
            splits: SplitSettings { count: self.splits, scheme, ..SplitSettings::default() },
            resolution: self.resolution,
            stable: self.stable,
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

fn result_json(case: &Case, settings: &FocusSettings, r: &FocusResult) -> Value {
    let maps: Vec<Value> = r
        .maps()
        .iter()
        .map(|m| {
            let body = m.body();
            let vertices: Vec<[f64; 3]> = body.vertices().iter().map(|v| v.to_array()).collect();
            json!({
                "split": m.split_range,
                "state": format!("{:?}", m.state).to_lowercase(),
                "face": m.face.map(|f| f.name()),
                "matrix": m.matrix.to_cols_array(),
                "depth_test": m.depth_test.name(),
                "texel_size": m.texel_size.map(|t| if t.is_finite() { Value::from(t) } else { Value::Null }),
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
            Ok(case) => match case_camera(&case)
                .and_then(|cam| fit(&cam, &case.light, &case.scene, settings, &mut result).map_err(|e| e.to_string()))
            {
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

/// `--bench`: per-case median time of a whole fit (bodies included).
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
        .map(|(c, cam)| case_median_ns(|| {
            let _ = fit(cam, &c.light, &c.scene, settings, &mut result);
        }))
        .collect();
    Ok(json!({"cases": ns.len(), "method": settings.method.name(), "splits": settings.splits.count, "median_ns": median(&mut ns), "p99_ns": p99(&mut ns)}))
}
