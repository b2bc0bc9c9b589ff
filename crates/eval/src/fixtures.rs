//! The committed CGAL fixtures (`fixtures/cases/*.jsonl` with the exact
//! bodies, rounded to nearest, in `fixtures/expected/`) as an oracle for the
//! body engine and for the naive pipeline.

use crate::naive::{naive_body, NaiveBody, NaiveLight};
use glam::DVec3;
use serde_json::Value;
use shadowfocus_case::parse_case;
use shadowfocus_geom::{focus_body, Aabb, Frustum, Light};
use std::path::Path;

/// The fixture files.
pub const FILES: [&str; 7] = ["classic", "directional", "point", "spot", "scene", "extreme", "smoke"];

/// A naive result counts as losing part of `H` when an exact vertex lies
/// outside it by more than this, relative to the case's magnitude (far
/// above the rounding of either side).
pub const LOSS_TOLERANCE: f64 = 1e-9;

/// Per-file comparison with the exact bodies.
#[derive(Clone, Debug, Default)]
pub struct FixtureSummary {
    pub file: String,
    pub cases: usize,
    /// Cases not read (no `view.corners`, or malformed).
    pub skipped: usize,
    pub ours_errors: usize,
    pub ours_dimension_mismatches: usize,
    /// Largest distance from one of our vertices to the nearest exact
    /// vertex, relative to the case's magnitude.
    pub ours_max_vertex_error: f64,
    /// Cases the naive pipeline ran on (non-spot lights, solid exact body).
    pub naive_cases: usize,
    pub naive_lost: usize,
    pub naive_degenerate: usize,
    pub naive_failed: usize,
    /// Largest distance of an exact vertex outside the naive body (relative).
    pub naive_max_excess: f64,
}

fn vec3(v: &Value) -> Option<DVec3> {
    let a = v.as_array()?;
    if a.len() != 3 {
        return None;
    }
    Some(DVec3::new(a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?))
}

fn magnitude(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.as_f64().map_or(0.0, f64::abs),
        Value::Array(a) => a.iter().map(magnitude).fold(0.0, f64::max),
        Value::Object(o) => o.values().map(magnitude).fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// One fixture case with its exact (CGAL) body, rounded to nearest.
#[derive(Clone, Debug)]
pub struct FixtureCase {
    pub id: String,
    pub view: [DVec3; 8],
    pub light: Light,
    pub scene: Aabb,
    /// Largest input coordinate magnitude (errors are relative to it).
    pub magnitude: f64,
    pub expected_dimension: i32,
    pub expected_vertices: Vec<DVec3>,
    naive: Option<NaiveLight>,
}

fn parse(line: &str, expected: &Value) -> Option<FixtureCase> {
    let case = parse_case(line).ok()?;
    let raw: Value = serde_json::from_str(line).ok()?;
    // The fixtures give the view as corners: a camera-form view is not one of them.
    raw["view"].get("corners")?;
    let naive = match case.light {
        Light::Directional { direction } => Some(NaiveLight::Directional(direction)),
        Light::Point { position } => Some(NaiveLight::Point(position)),
        Light::Spot { .. } => None,
    };
    Some(FixtureCase {
        id: case.id.as_str().unwrap_or("").to_string(),
        view: *case.view.corners(),
        light: case.light,
        scene: case.scene,
        magnitude: magnitude(&raw).max(f64::MIN_POSITIVE),
        expected_dimension: expected["dimension"].as_i64().unwrap_or(-2) as i32,
        expected_vertices: expected["vertices"].as_array().map(|a| a.iter().filter_map(vec3).collect()).unwrap_or_default(),
        naive,
    })
}

/// The cases of one fixture file that carry explicit view corners, and the
/// number of lines that could not be read as such.
pub fn read_file(dir: &Path, name: &str) -> Result<(Vec<FixtureCase>, usize), String> {
    let read =
        |sub: &str| std::fs::read_to_string(dir.join(sub).join(format!("{name}.jsonl"))).map_err(|e| format!("{sub}/{name}.jsonl: {e}"));
    let (cases, expected) = (read("cases")?, read("expected")?);
    let mut out = Vec::new();
    let mut skipped = 0;
    for (cl, el) in cases.lines().zip(expected.lines()) {
        let parsed = serde_json::from_str::<Value>(el).ok().and_then(|ev| parse(cl, &ev));
        match parsed {
            Some(c) => out.push(c),
            None => skipped += 1,
        }
    }
    Ok((out, skipped))
}

/// Compares one fixture file (cases and expected bodies, line by line).
pub fn compare_file(dir: &Path, name: &str) -> Result<FixtureSummary, String> {
    let (cases, skipped) = read_file(dir, name)?;
    let mut s = FixtureSummary { file: name.to_string(), cases: cases.len() + skipped, skipped, ..Default::default() };
    for p in &cases {
        let (mag, exp_dim, exp_v) = (p.magnitude, p.expected_dimension, &p.expected_vertices);
        let Ok(view) = Frustum::from_corners(p.view) else {
            s.ours_errors += 1;
            continue;
        };
        match focus_body(&view, &p.light, &p.scene) {
            Err(_) => s.ours_errors += 1,
            Ok(body) => {
                if body.dimension().as_i32() != exp_dim {
                    s.ours_dimension_mismatches += 1;
                }
                for v in body.vertices() {
                    let d = exp_v.iter().map(|e| (*e - *v).length()).fold(f64::INFINITY, f64::min);
                    if d.is_finite() {
                        s.ours_max_vertex_error = s.ours_max_vertex_error.max(d / mag);
                    }
                }
            }
        }
        if let (Some(nl), 3) = (p.naive, exp_dim) {
            s.naive_cases += 1;
            match naive_body(&p.view, nl, &p.scene) {
                nb @ NaiveBody::Hull { .. } => {
                    let excess = exp_v.iter().map(|e| nb.distance_outside(*e)).fold(0.0, f64::max) / mag;
                    s.naive_max_excess = s.naive_max_excess.max(excess);
                    if excess > LOSS_TOLERANCE {
                        s.naive_lost += 1;
                    }
                }
                NaiveBody::Degenerate { .. } => s.naive_degenerate += 1,
                NaiveBody::Failed(_) => s.naive_failed += 1,
            }
        }
    }
    Ok(s)
}

/// Every fixture file under `dir` (the repository's `fixtures/`).
pub fn compare_all(dir: &Path) -> Result<Vec<FixtureSummary>, String> {
    FILES.iter().map(|f| compare_file(dir, f)).collect()
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.1e}")
    }
}

/// Markdown table of [`compare_all`].
pub fn report_markdown(rows: &[FixtureSummary]) -> String {
    let mut s = String::from(
        "| fixtures | cases | ours: errors | dim. mismatches | max vertex error (rel.) | naive: cases | lost part of H | degenerate | failed | max excess (rel.) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.file,
            r.cases - r.skipped,
            r.ours_errors,
            r.ours_dimension_mismatches,
            sci(r.ours_max_vertex_error),
            r.naive_cases,
            r.naive_lost,
            r.naive_degenerate,
            r.naive_failed,
            sci(r.naive_max_excess)
        ));
    }
    s
}
