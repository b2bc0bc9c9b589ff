//! `shadowfocus bench --quick` end to end (llvmpipe in CI): the sweep's
//! files are written and hold what they claim — one CSV row per
//! configuration with finite measurements, decodable PNG plots beside the
//! SVGs, and a stress report in which the body agrees with the oracle.

use shadowfocus_cli::cli::bench::{run, BenchOptions};
use std::path::{Path, PathBuf};

#[test]
fn quick_sweep_writes_consistent_results() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("shadowfocus-bench-quick-{}", std::process::id()));
    let options = BenchOptions {
        quick: true,
        out: out.clone(),
        scenes: Vec::new(),
        resolutions: Vec::new(),
        size: None,
        full: false,
        no_stress: false,
        fixtures: root.join("fixtures"),
    };
    let summary = run(&options).expect("the quick sweep runs");

    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    let header = fields(lines.next().unwrap());
    let col = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("column {name}"));
    let rows: Vec<Vec<String>> = lines.map(fields).collect();
    assert_eq!(rows.len() as u64, summary["rows"].as_u64().unwrap());
    // Two scenes × (5 configurations at 512 with the plan on and off + 5 at 1024).
    assert_eq!(rows.len(), 30);
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        let x = |name: &str| r[col(name)].parse::<f64>().unwrap_or(f64::NAN);
        assert!(x("focusing_us") > 0.0 && x("focusing_us").is_finite(), "{r:?}");
        assert!(x("aliasing_p95") > 0.0 && x("aliasing_max") >= x("aliasing_p95"), "{r:?}");
        assert!(x("bound") > 0.0 && (x("ratio") - x("aliasing_max") / x("bound")).abs() < 1e-2 * x("ratio"), "{r:?}");
    }

    let plots: Vec<PathBuf> = summary["plots"].as_array().unwrap().iter().map(|p| out.join(p.as_str().unwrap())).collect();
    assert_eq!(plots.iter().filter(|p| p.extension().is_some_and(|e| e == "png")).count(), 4);
    for p in plots.iter().filter(|p| p.extension().is_some_and(|e| e == "png")) {
        let (w, h, _) = shadowfocus_raster::png::decode_rgba(&std::fs::read(p).unwrap()).unwrap();
        assert_eq!((w, h), (760, 480), "{}", p.display());
        assert!(p.with_extension("svg").exists(), "{} has no SVG twin", p.display());
    }

    let stress = std::fs::read_to_string(out.join("stress.md")).unwrap();
    let line = stress.lines().find(|l| l.contains("agrees with the big-integer oracle")).expect("oracle summary");
    let words: Vec<&str> = line.split_whitespace().collect();
    let (total, agree) = (words[0], words[words.iter().position(|w| *w == "on").unwrap() + 1].trim_end_matches(','));
    assert_eq!(total, agree, "{line}");
    std::fs::remove_dir_all(&out).ok();
}

/// The fields of one CSV line (quoted fields may hold commas and `""`).
fn fields(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    out.push(cur);
    out
}
