//! Focus-body throughput on the committed fixture cases, per light kind and
//! mixed, with and without frustum validation, and the epsilon-based hull
//! of just the nine points (what engines typically use) for comparison.
//!
//! `cargo bench -p shadowfocus-geom --bench bodies`

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use glam::DVec3;
use shadowfocus_case::parse_case;
use shadowfocus_geom::{Aabb, Body, Focuser, Frustum, GeomError, Light};
use std::hint::black_box;
use std::path::Path;

struct Case {
    corners: [DVec3; 8],
    view: Frustum,
    light: Light,
    scene: Aabb,
}

/// Reads the corners-form fixture cases of one file (all of them are).
fn load(name: &str) -> Vec<Case> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/cases").join(format!("{name}.jsonl"));
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter_map(|line| {
            let c = parse_case(line).ok()?;
            Some(Case { corners: *c.view.corners(), view: c.view, light: c.light, scene: c.scene })
        })
        .collect()
}

/// One of the body entry points (`Focuser::focus_into` and its variants).
type Engine = fn(&mut Focuser, &mut Body, &Frustum, &Light, &Aabb) -> Result<(), GeomError>;

/// Times `engine` over every case, reusing one `Focuser` and one `Body` (as
/// an engine would across frames); throughput is counted in bodies.
fn bench_engine(group: &mut BenchmarkGroup<WallTime>, name: &str, body: &mut Body, cases: &[&Case], engine: Engine) {
    let mut focuser = Focuser::new();
    group.throughput(Throughput::Elements(cases.len().max(1) as u64));
    group.bench_function(name, |b| {
        b.iter(|| {
            for case in cases {
                let _ = engine(&mut focuser, body, &case.view, &case.light, &case.scene);
            }
        })
    });
}

fn bench(c: &mut Criterion) {
    let sets = ["directional", "point", "spot", "scene", "extreme"].map(|n| (n, load(n)));
    let mut group = c.benchmark_group("focus_body");
    group.sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    for (name, cases) in &sets {
        bench_engine(&mut group, name, &mut body, &cases.iter().collect::<Vec<_>>(), Focuser::focus_into);
    }
    let mixed: Vec<&Case> = sets.iter().flat_map(|(_, c)| c.iter()).collect();
    group.throughput(Throughput::Elements(mixed.len() as u64));
    group.bench_function("mixed_with_frustum_validation", |b| {
        b.iter(|| {
            for case in &mixed {
                if let Ok(view) = Frustum::from_corners(black_box(case.corners)) {
                    let _ = focuser.focus_into(&mut body, &view, &case.light, &case.scene);
                }
            }
        })
    });
    group.bench_function("frustum_validation_only", |b| {
        b.iter(|| {
            for case in &mixed {
                let _ = black_box(Frustum::from_corners(black_box(case.corners)));
            }
        })
    });
    // What the scene-clip skip saves: point and spot cases with V ⊆ S and
    // l ∈ S, computed by the engine (which starts from the box around V ∪ l)
    // and the plain way (clip S by every plane of hull(V ∪ l) and L).
    let skippable: Vec<&Case> = mixed
        .iter()
        .copied()
        .filter(|c| focuser.focus_into(&mut body, &c.view, &c.light, &c.scene).is_ok() && body.stats().scene_clip_skipped)
        .collect();
    eprintln!("scene-clip skip applies to {} of {} cases", skippable.len(), mixed.len());
    bench_engine(&mut group, "skippable_cases_with_skip", &mut body, &skippable, Focuser::focus_into);
    bench_engine(&mut group, "skippable_cases_without_skip", &mut body, &skippable, Focuser::focus_into_without_skip);
    // What the floating-point path saves: the same cases through the exact
    // engine alone.
    bench_engine(&mut group, "mixed_exact_engine_only", &mut body, &mixed, Focuser::focus_exact_into);
    bench_engine(&mut group, "mixed", &mut body, &mixed, Focuser::focus_into);
    // The usual engine approach for comparison: parry's epsilon-based hull
    // of the 8 corners and the light (point lights only; no clipping).
    let points = &sets[1].1;
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("parry_convex_hull_of_9_points", |b| {
        b.iter(|| {
            for case in points {
                if let Light::Point { position } = case.light {
                    let mut pts = case.corners.to_vec();
                    pts.push(position);
                    let _ = black_box(parry3d_f64::transformation::try_convex_hull(&pts));
                }
            }
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
