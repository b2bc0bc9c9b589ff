//! Every committed CGAL fixture (exact constructions, rounded once) against
//! the body engine: dimension exactly, vertices within the proven rounding
//! bound, faces combinatorially, volume within a derived tolerance.

use glam::DVec3;
use serde_json::Value;
use shadowfocus_cli::cli::case::parse_case;
use shadowfocus_cli::geom::{Body, Focuser};
use std::path::Path;

const FILES: [&str; 7] = ["classic", "directional", "point", "spot", "scene", "extreme", "smoke"];

struct Expected {
    dimension: i32,
    vertices: Vec<DVec3>,
    faces: Vec<Vec<usize>>,
    volume: f64,
}

fn expected(v: &Value) -> Expected {
    let vertices = v["vertices"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| DVec3::new(p[0].as_f64().unwrap(), p[1].as_f64().unwrap(), p[2].as_f64().unwrap()))
        .collect();
    let faces = v["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_array().unwrap().iter().map(|i| i.as_u64().unwrap() as usize).collect())
        .collect();
    Expected { dimension: v["dimension"].as_i64().unwrap() as i32, vertices, faces, volume: v["volume"].as_f64().unwrap() }
}

/// Largest input magnitude of a case line (all numbers in it).
fn magnitude(v: &Value) -> f64 {
    match v {
        Value::Number(n) => n.as_f64().unwrap().abs(),
        Value::Array(a) => a.iter().map(magnitude).fold(0.0, f64::max),
        Value::Object(o) => o.values().map(magnitude).fold(0.0, f64::max),
        _ => 0.0,
    }
}

/// Rotates a cycle to start at its smallest index.
fn canonical(cycle: &[usize]) -> Vec<usize> {
    let k = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap();
    cycle[k..].iter().chain(&cycle[..k]).copied().collect()
}

/// `Ok((ambiguous, light_first))`: whether vertices were rounding-ambiguous,
/// and whether the float path answered with `L` clipped first.
fn check_case(case_line: &str, exp_line: &str) -> Result<(bool, bool), String> {
    let case_json: Value = serde_json::from_str(case_line).unwrap();
    let exp_json: Value = serde_json::from_str(exp_line).unwrap();
    let id = case_json["id"].as_str().unwrap_or("?").to_string();
    assert_eq!(case_json["id"], exp_json["id"], "fixture files out of order");
    let case = parse_case(case_line).map_err(|e| format!("{id}: rejected: {e}"))?;
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    focuser.focus_into(&mut body, &case.view, &case.light, &case.scene).map_err(|e| format!("{id}: error {e}"))?;
    let exp = expected(&exp_json);
    let got_dim = body.dimension().as_i32();
    if got_dim != exp.dimension {
        return Err(format!("{id}: dimension {got_dim}, CGAL {}", exp.dimension));
    }
    if body.vertices().len() != exp.vertices.len() {
        return Err(format!("{id}: {} vertices, CGAL {}", body.vertices().len(), exp.vertices.len()));
    }
    // NOTE: both sides are the exact vertices rounded; ours within the proven
    // ROUNDING_ULPS of the input magnitude, CGAL's to nearest.
    let m = magnitude(&case_json);
    let tol = (shadowfocus_cli::geom::ROUNDING_ULPS + 1.0) * f64::EPSILON * m;
    let mut map = vec![usize::MAX; exp.vertices.len()];
    let mut used = vec![false; exp.vertices.len()];
    for (i, v) in body.vertices().iter().enumerate() {
        let best = (0..exp.vertices.len())
            .filter(|&j| !used[j])
            .min_by(|&a, &b| (exp.vertices[a] - *v).length().total_cmp(&(exp.vertices[b] - *v).length()))
            .unwrap();
        let d = (exp.vertices[best] - *v).abs().max_element();
        if d > tol {
            return Err(format!("{id}: vertex {v:?} is {d:e} from the nearest CGAL vertex (tolerance {tol:e})"));
        }
        used[best] = true;
        map[i] = best;
    }
    // Faces: the same set of cycles under the vertex matching. Where two
    // CGAL vertices lie within the rounding bound of each other (tiny facets
    // at a light on the view's apex), coordinates cannot tell them apart:
    // there only the multiset of face sizes is compared.
    let ambiguous = body.vertices().iter().any(|v| exp.vertices.iter().filter(|w| (**w - *v).abs().max_element() <= 2.0 * tol).count() > 1);
    if body.face_count() != exp.faces.len() {
        return Err(format!("{id}: {} faces, CGAL {}", body.face_count(), exp.faces.len()));
    }
    if ambiguous {
        let mut ours: Vec<usize> = body.faces().map(|f| f.len()).collect();
        let mut theirs: Vec<usize> = exp.faces.iter().map(|f| f.len()).collect();
        ours.sort();
        theirs.sort();
        if ours != theirs {
            return Err(format!("{id}: face sizes differ: {ours:?} vs {theirs:?}"));
        }
    } else {
        let mut ours: Vec<Vec<usize>> = body.faces().map(|f| canonical(&f.iter().map(|&i| map[i as usize]).collect::<Vec<_>>())).collect();
        let mut theirs: Vec<Vec<usize>> = exp.faces.iter().map(|f| canonical(f)).collect();
        if exp.dimension == 2 {
            // A polygon's single face may be listed in either orientation.
            let rev: Vec<usize> = ours[0].iter().rev().copied().collect();
            if canonical(&rev) == theirs[0] {
                ours[0] = canonical(&rev);
            }
        }
        ours.sort();
        theirs.sort();
        if ours != theirs {
            return Err(format!("{id}: faces differ:\n ours   {ours:?}\n theirs {theirs:?}"));
        }
    }
    // Volume: each vertex moves by ≤ tol, so the volume moves by at most
    // (surface area)·tol; the surface area is at most that of the bounding
    // box, 6·E². The f64 sum adds a few ulps of E³.
    let e = body.bounds().map(|b| (b.max - b.min).max_element()).unwrap_or(0.0);
    let vol_tol = 6.0 * e * e * 2.0 * tol + 64.0 * f64::EPSILON * e * e * e;
    if (body.volume() - exp.volume).abs() > vol_tol {
        return Err(format!("{id}: volume {} vs CGAL {} (tolerance {vol_tol:e})", body.volume(), exp.volume));
    }
    Ok((ambiguous, body.stats().light_clipped_first))
}

#[test]
fn every_cgal_fixture_agrees() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut failures = Vec::new();
    let mut total = 0;
    let mut ambiguous_total = 0;
    let mut light_first_total = 0;
    for name in FILES {
        let cases = std::fs::read_to_string(root.join("cases").join(format!("{name}.jsonl"))).unwrap();
        let exp = std::fs::read_to_string(root.join("expected").join(format!("{name}.jsonl"))).unwrap();
        let (cases, exp): (Vec<&str>, Vec<&str>) = (cases.lines().collect(), exp.lines().collect());
        assert_eq!(cases.len(), exp.len(), "{name}: case and result counts differ");
        for (c, e) in cases.iter().zip(&exp) {
            total += 1;
            match check_case(c, e) {
                Ok((ambiguous, light_first)) => {
                    ambiguous_total += ambiguous as usize;
                    light_first_total += light_first as usize;
                }
                Err(msg) => failures.push(msg),
            }
        }
    }
    assert!(total >= 3800, "expected the full fixture set, found {total} cases");
    eprintln!(
        "{total} fixtures checked, {ambiguous_total} with rounding-ambiguous vertices, {light_first_total} answered with L clipped first"
    );
    // The second clipping order of spot lights is checked here too.
    assert!(light_first_total > 0, "no fixture takes the float path's L-first order");
    assert!(
        failures.is_empty(),
        "{} of {total} fixtures disagree:\n{}",
        failures.len(),
        failures.iter().take(25).cloned().collect::<Vec<_>>().join("\n")
    );
}
