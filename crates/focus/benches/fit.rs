//! Per-frame cost of fitting: one map per method including the focus body,
//! and four practical splits.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use glam::DVec3;
use shadowfocus_focus::{
    cull_casters, fit, fit_map, fit_prepared, CasterRegion, FocusResult, FocusSettings, Method, PointMode, PreparedView, SplitScheme,
    SplitSettings, VisibleReceivers,
};
use shadowfocus_geom::{focus_body, Aabb, Camera, Frustum, Light};

fn camera() -> Camera {
    Camera {
        eye: DVec3::new(3.0, 2.5, 12.0),
        forward: DVec3::new(-0.1, -0.12, -1.0),
        up: DVec3::Y,
        fovy: 60f64.to_radians(),
        aspect: 16.0 / 9.0,
        near: 0.3,
        far: 150.0,
    }
}

fn scene() -> Aabb {
    Aabb::new(DVec3::new(-80.0, 0.0, -160.0), DVec3::new(80.0, 25.0, 30.0)).unwrap()
}

fn bench(c: &mut Criterion) {
    let cam = camera();
    let scene = scene();
    let lights = [
        ("sun", Light::directional(DVec3::new(0.35, -1.0, 0.25)).unwrap()),
        ("sun_behind", Light::directional(DVec3::new(0.2, -0.5, -1.0)).unwrap()),
        ("point", Light::point(DVec3::new(40.0, 20.0, 10.0)).unwrap()),
    ];
    let mut out = FocusResult::new();
    for (lname, light) in &lights {
        for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
            for splits in [1, 4] {
                let s = FocusSettings {
                    method,
                    splits: SplitSettings { count: splits, scheme: SplitScheme::Practical { lambda: 0.5 }, delta_bias: 0.0 },
                    point: PointMode::Single,
                    ..FocusSettings::default()
                };
                let name = format!("fit/{lname}/{}/{splits}", method.name());
                c.bench_function(&name, |b| {
                    b.iter(|| fit(black_box(&cam), black_box(light), black_box(&scene), black_box(&s), &mut out).unwrap())
                });
            }
        }
    }
    // Per light from a view prepared once (its split frusta validated), and
    // the preparation itself.
    for splits in [1, 4] {
        let s = FocusSettings {
            method: Method::Lispsm,
            splits: SplitSettings { count: splits, scheme: SplitScheme::Practical { lambda: 0.5 }, delta_bias: 0.0 },
            ..FocusSettings::default()
        };
        let mut view = PreparedView::new(&cam, &s).unwrap();
        c.bench_function(&format!("prepare_view/lispsm/{splits}"), |b| b.iter(|| view.prepare(black_box(&cam), black_box(&s)).unwrap()));
        for (lname, light) in &lights[..2] {
            c.bench_function(&format!("fit_prepared/{lname}/lispsm/{splits}"), |b| {
                b.iter(|| fit_prepared(black_box(&view), black_box(light), black_box(&scene), &mut out).unwrap())
            });
        }
    }
    // The fitting alone, on a precomputed body.
    for (lname, light) in &lights[..2] {
        let body = focus_body(&Frustum::from_camera(&cam).unwrap(), light, &scene).unwrap();
        for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] {
            let s = FocusSettings { method, ..FocusSettings::default() };
            c.bench_function(&format!("fit_map/{lname}/{}", method.name()), |b| {
                b.iter(|| fit_map(black_box(&cam), black_box(light), black_box(&body), black_box(&s)).unwrap())
            });
        }
    }
    c.bench_function("focus_body/sun", |b| {
        let view = Frustum::from_camera(&cam).unwrap();
        b.iter(|| focus_body(black_box(&view), black_box(&lights[0].1), black_box(&scene)).unwrap())
    });
    // Caster culling: a 40 × 40 grid of boxes over the scene.
    let mut casters = Vec::new();
    for i in 0..40 {
        for j in 0..40 {
            let p = DVec3::new(-80.0 + 4.0 * i as f64 + 2.0, 0.0, -160.0 + 4.75 * j as f64 + 2.0);
            casters.push(Aabb::new(p - DVec3::new(1.0, 0.0, 1.0), p + DVec3::new(1.0, 6.0, 1.0)).unwrap());
        }
    }
    let mut idx = vec![0u32; casters.len()];
    for (lname, light) in &lights {
        let s = FocusSettings { splits: SplitSettings { count: 4, ..Default::default() }, ..FocusSettings::default() };
        fit(&cam, light, &scene, &s, &mut out).unwrap();
        let kept: usize = out.maps().iter().filter(|m| m.is_active()).map(|m| cull_casters(m, &casters, &mut idx).unwrap()).sum();
        let maps = out.maps().iter().filter(|m| m.is_active()).count();
        eprintln!("cull/{lname}: {} maps, kept {kept} of {} caster-map pairs", maps, maps * casters.len());
        let map = out.maps()[0].clone();
        c.bench_function(&format!("cull/{lname}/region"), |b| b.iter(|| CasterRegion::of_map(black_box(&map))));
        c.bench_function(&format!("cull/{lname}/1600_boxes"), |b| b.iter(|| cull_casters(black_box(&map), black_box(&casters), &mut idx)));
    }
    // A 320×180 pre-pass's points of a ground, gathered into visible receiver boxes.
    let basis = cam.basis().unwrap();
    let t = (0.5 * cam.fovy).tan();
    let points: Vec<DVec3> = (0..180 * 320)
        .map(|k| {
            let (u, v) = ((k % 320) as f64 / 160.0 - 1.0, (k / 320) as f64 / -90.0);
            let d = basis.forward + basis.right * (u * t * cam.aspect) + basis.up * (v * t);
            cam.eye + d * (cam.eye.y / -d.y.min(-1e-3))
        })
        .collect();
    c.bench_function("visible_receivers/320x180", |b| {
        b.iter(|| {
            let mut v = VisibleReceivers::new(&cam, 180).unwrap();
            black_box(&points).iter().for_each(|p| v.add(*p));
            v.boxes(0.0).unwrap()
        })
    });
    let s = FocusSettings { stable: true, splits: SplitSettings { count: 4, ..Default::default() }, ..FocusSettings::default() };
    c.bench_function("fit/sun/uniform_stable/4", |b| {
        b.iter(|| fit(black_box(&cam), black_box(&lights[0].1), black_box(&scene), black_box(&s), &mut out).unwrap())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(300)).measurement_time(std::time::Duration::from_millis(800));
    targets = bench
}
criterion_main!(benches);
