//! Focusing time of every configuration that `shadowfocus bench` sweeps,
//! on every built-in scene, measured by criterion: one `fit` per frame
//! (bodies, matrices, splits), one thread. The sweep's `focusing_us` column
//! is a median of 7 calls; these are the careful numbers behind it.
//!
//! `cargo bench --bench scenes` (all), or a filter such as
//! `cargo bench --bench scenes -- forest/` .

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use shadowfocus_cli::cli::bench::{configs, label};
use shadowfocus_cli::cli::render::scene_inputs;
use shadowfocus_focus::{fit, FocusResult};
use shadowfocus_render::{builtin_scene, BUILTIN_SCENES};
use std::time::Duration;

fn bench(c: &mut Criterion) {
    let mut out = FocusResult::new();
    for name in BUILTIN_SCENES {
        let scene = builtin_scene(name).expect("built-in scene");
        // The sweep renders 640×360; the resolution does not change the fit's
        // work, so one resolution covers every row of the sweep.
        let (camera, light, bounds) = scene_inputs(&scene, 640.0 / 360.0).expect("scene inputs");
        for o in configs(false, false, 1024) {
            let settings = o.settings().expect("sweep settings are valid");
            c.bench_function(&format!("{name}/{}", label(&o)), |b| {
                b.iter(|| fit(black_box(&camera), black_box(&light), black_box(&bounds), black_box(&settings), &mut out).unwrap())
            });
        }
    }
}

criterion_group! {
    name = benches;
    // 108 configurations: short runs keep the whole set to a few minutes.
    config = Criterion::default().sample_size(20).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(1));
    targets = bench
}
criterion_main!(benches);
