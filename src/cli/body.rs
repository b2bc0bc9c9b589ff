//! `shadowfocus body`: focus bodies for JSON-lines cases.

use super::case::{case_lines, parse_case, Case};
use parry3d_f64::transformation::try_convex_hull;
use serde_json::{json, Value};
use shadowfocus_geom::{Body, Focuser, Frustum, Light};
use std::io::{BufRead, Write};
use std::time::Instant;

/// The JSON result for one body.
pub fn body_json(id: &Value, body: &Body) -> Value {
    let vertices: Vec<[f64; 3]> = body.vertices().iter().map(|v| v.to_array()).collect();
    let faces: Vec<&[u16]> = body.faces().collect();
    json!({
        "id": id,
        "dimension": body.dimension().as_i32(),
        "vertices": vertices,
        "faces": faces,
        "volume": body.volume(),
    })
}

/// Processes every line; returns how many lines failed.
pub fn run(input: impl BufRead, mut out: impl Write) -> std::io::Result<usize> {
    let mut failed = 0;
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    for line in case_lines(input) {
        let line = line?;
        let result = match parse_case(&line) {
            Ok(case) => match focuser.focus_into(&mut body, &case.view, &case.light, &case.scene) {
                Ok(()) => body_json(&case.id, &body),
                Err(e) => {
                    failed += 1;
                    json!({"id": case.id, "error": e.to_string()})
                }
            },
            Err(e) => {
                failed += 1;
                json!({"id": e.id, "error": e.message})
            }
        };
        writeln!(out, "{result}")?;
    }
    Ok(failed)
}

/// `--float-path-cases`: copies the lines whose body the certified float
/// path answers; returns how many lines could not be computed.
pub fn float_path_cases(input: impl BufRead, mut out: impl Write) -> std::io::Result<usize> {
    let mut failed = 0;
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    for line in case_lines(input) {
        let line = line?;
        match parse_case(&line).map(|case| focuser.focus_into(&mut body, &case.view, &case.light, &case.scene)) {
            Ok(Ok(())) if body.stats().float_path => writeln!(out, "{line}")?,
            Ok(Ok(())) => {}
            _ => failed += 1,
        }
    }
    Ok(failed)
}

/// Median of a sample (sorted in place); 0 for an empty one.
pub fn median(xs: &mut [f64]) -> f64 {
    quantile(xs, 0.5)
}

/// 99th percentile of a sample (sorted in place); 0 for an empty one.
pub fn p99(xs: &mut [f64]) -> f64 {
    quantile(xs, 0.99)
}

/// The sample value at rank `⌊q·n⌋` (sorted in place); 0 for an empty sample.
fn quantile(xs: &mut [f64], q: f64) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs.get(((xs.len() as f64 * q) as usize).min(xs.len().saturating_sub(1))).copied().unwrap_or(0.0)
}

/// Per-case median time of `f` in nanoseconds: the median of at least 15
/// timed batches, ~2 ms per case in all.
pub fn case_median_ns(mut f: impl FnMut()) -> f64 {
    // One call to warm caches and branch predictors, one to size the batches.
    f();
    let t = Instant::now();
    f();
    let one = t.elapsed().as_nanos().max(1) as f64;
    // NOTE: a batch of ≥ 20 µs keeps the timer's own cost (tens of
    // nanoseconds a reading) a small fraction of what it measures.
    let batch = ((20_000.0 / one) as usize).clamp(1, 256);
    let reps = ((2e6 / (one * batch as f64)) as usize).clamp(15, 2000);
    let mut samples = Vec::with_capacity(reps);
    for _ in 0..reps {
        let t = Instant::now();
        for _ in 0..batch {
            f();
        }
        samples.push(t.elapsed().as_nanos() as f64 / batch as f64);
    }
    median(&mut samples)
}

/// `--bench`: times every valid case, excluding parsing.
pub fn bench(input: impl BufRead) -> std::io::Result<Value> {
    let mut cases: Vec<Case> = Vec::new();
    let mut skipped = 0;
    for line in case_lines(input) {
        let line = line?;
        match parse_case(&line) {
            Ok(c) => cases.push(c),
            Err(_) => skipped += 1,
        }
    }
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    let mut body_ns = Vec::with_capacity(cases.len());
    let mut with_frustum_ns = Vec::with_capacity(cases.len());
    let mut exact_cases = 0;
    let (mut float_ns, mut engine_ns, mut exact_only_ns) = (Vec::new(), Vec::new(), Vec::new());
    // Point and spot lights: the body against parry's hull of the nine points
    // (what engines typically compute, without any clipping), case by case.
    let (mut finite_light_body_ns, mut parry_ns) = (Vec::new(), Vec::new());
    for case in &cases {
        let _ = focuser.focus_into(&mut body, &case.view, &case.light, &case.scene);
        exact_cases += (body.stats().exact_evaluations > 0) as usize;
        let on_float_path = body.stats().float_path;
        let ns = case_median_ns(|| {
            let _ = focuser.focus_into(&mut body, &case.view, &case.light, &case.scene);
        });
        body_ns.push(ns);
        if on_float_path { &mut float_ns } else { &mut engine_ns }.push(ns);
        if let Light::Point { position } | Light::Spot { position, .. } = case.light {
            let c = case.view.corners();
            let nine = [c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], position];
            // NOTE: parry's hull may panic on hostile input (its message goes
            // to stderr); such a case is left out of the comparison.
            if std::panic::catch_unwind(|| try_convex_hull(&nine).is_ok()).unwrap_or(false) {
                finite_light_body_ns.push(ns);
                parry_ns.push(case_median_ns(|| {
                    let _ = std::hint::black_box(try_convex_hull(std::hint::black_box(&nine)));
                }));
            }
        }
        exact_only_ns.push(case_median_ns(|| {
            let _ = focuser.focus_exact_into(&mut body, &case.view, &case.light, &case.scene);
        }));
        let corners = *case.view.corners();
        with_frustum_ns.push(case_median_ns(|| {
            if let Ok(view) = Frustum::from_corners(std::hint::black_box(corners)) {
                let _ = focuser.focus_into(&mut body, &view, &case.light, &case.scene);
            }
        }));
    }
    Ok(json!({
        "cases": cases.len(),
        "median_ns": median(&mut body_ns),
        "p99_ns": p99(&mut body_ns),
        "with_frustum_validation_median_ns": median(&mut with_frustum_ns),
        "with_frustum_validation_p99_ns": p99(&mut with_frustum_ns),
        "exact_engine_only_median_ns": median(&mut exact_only_ns),
        "cases_on_float_path": float_ns.len(),
        "float_path_median_ns": median(&mut float_ns),
        "exact_engine_median_ns": median(&mut engine_ns),
        "cases_using_big_integers": exact_cases,
        "finite_light_cases": parry_ns.len(),
        "finite_light_median_ns": median(&mut finite_light_body_ns),
        "parry_hull_of_9_points_median_ns": median(&mut parry_ns),
        "invalid_lines_skipped": skipped,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::bench_test::{assert_times, smoke_lines};

    /// The bench times every valid case, and compares against parry's hull
    /// exactly the point and spot cases.
    #[test]
    fn bench_counts_cases_and_compares_finite_lights_with_parry() {
        let lines = smoke_lines(12);
        let finite = lines.iter().filter(|l| !l.contains("\"directional\"")).count();
        assert!(finite > 0 && finite < lines.len(), "{finite} of {}", lines.len());
        let input = format!("{}\nnot json\n", lines.join("\n"));
        let r = bench(input.as_bytes()).unwrap();
        assert_eq!(r["cases"], lines.len());
        assert_eq!(r["invalid_lines_skipped"], 1);
        assert_eq!(r["finite_light_cases"], finite);
        assert_times(&r, &["median_ns", "finite_light_median_ns", "parry_hull_of_9_points_median_ns", "with_frustum_validation_median_ns"]);
    }

    /// The spot fixtures mix both kinds: a few coincidences go to the exact
    /// engine, the rest are answered by the float path.
    #[test]
    fn float_path_cases_keeps_exactly_the_cases_the_float_path_answers() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/cases/spot.jsonl");
        let text = std::fs::read_to_string(path).unwrap();
        let mut out = Vec::new();
        assert_eq!(float_path_cases(text.as_bytes(), &mut out).unwrap(), 0);
        let kept: Vec<&str> = std::str::from_utf8(&out).unwrap().lines().collect();
        let mut body = Body::new();
        let mut focuser = Focuser::new();
        let mut expected = Vec::new();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let case = parse_case(line).unwrap();
            focuser.focus_into(&mut body, &case.view, &case.light, &case.scene).unwrap();
            if body.stats().float_path {
                expected.push(line);
            }
        }
        assert!(!kept.is_empty() && kept.len() < text.lines().count(), "{} of {}", kept.len(), text.lines().count());
        assert_eq!(kept, expected);
    }
}
