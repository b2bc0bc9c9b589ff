//! Arbitrary bytes through the JSON-lines reader and `shadowfocus fit`:
//! never a panic; one output line per non-blank input line. For every case
//! that parses, `fit_case` (`fit`, or `fit_frustum` for corner input) and
//! `fit_prepared` (from one view, refilled in place case after case by
//! `prepare_case`) give the same maps bit for bit or the same error, and
//! every active map holds its body's vertices in the clip volume.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shadowfocus_cli::cli::case::parse_case;
use shadowfocus_cli::cli::fit::{case_camera, fit_case, prepare_case, run};
use shadowfocus_cli::focus::{
    fit_prepared, DepthHintCoverage, FocusResult, FocusSettings, MapSizes, Method, PointMode, PreparedView, ReceiverBoxes, SplitScheme,
    SplitSettings, TexelBudget,
};
use shadowfocus_cli::geom::{Aabb, DVec3};
use shadowfocus_fuzz::check_result_lines;
use std::cell::RefCell;

/// The settings a case is fitted with, chosen by the input's length and the
/// line's place so that every method, split scheme and point mode is met.
fn settings(k: usize) -> FocusSettings {
    let method = [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm, Method::Auto][k % 5];
    let count = [1, 3, 4][(k / 4) % 3];
    let scheme = [
        SplitScheme::Practical { lambda: 0.5 },
        SplitScheme::Log,
        SplitScheme::Uniform,
        SplitScheme::Geometric { first: 10.0 },
        SplitScheme::Optimal,
    ][(k / 12) % 5];
    let point = if (k / 60) % 2 == 0 { PointMode::Single } else { PointMode::Cube };
    // Now and then a ground slab as the receivers (any case's scale: it may
    // miss the scene altogether), as a solid or as a pre-pass's seen points.
    let slab = Aabb { min: DVec3::new(-50.0, -1.0, -50.0), max: DVec3::new(50.0, 0.0, 50.0) };
    let receivers = match k % 7 {
        3 => ReceiverBoxes::new(&[slab]).unwrap_or_default(),
        5 => ReceiverBoxes::seen(&[slab]).unwrap_or_default(),
        _ => ReceiverBoxes::NONE,
    };
    // Now and then a texel budget, of either kind of size, from one map's
    // worth up (stable fits refuse it, with the error both paths must give).
    let texel_budget = (k % 3 == 1).then(|| TexelBudget {
        texels: [16_384, 1 << 22, 3 << 20][(k / 3) % 3],
        sizes: if (k / 9) % 2 == 0 { MapSizes::Any } else { MapSizes::PowerOfTwo },
    });
    FocusSettings {
        method,
        splits: SplitSettings { count, scheme, delta_bias: 0.0 },
        point,
        stable: k % 5 == 0,
        receivers,
        texel_budget,
        ..FocusSettings::default()
    }
}

thread_local! {
    static STATE: RefCell<(FocusResult, FocusResult, Option<PreparedView>)> = RefCell::new((FocusResult::new(), FocusResult::new(), None));
}

fn compare(k: usize, line: &str) {
    let Ok(case) = parse_case(line) else { return };
    let Ok(cam) = case_camera(&case) else { return };
    let mut s = settings(k);
    // Now and then a visible depth range inside the case's own camera,
    // covering that slab or the whole view.
    if k % 11 < 2 {
        let z = |t: f64| cam.near + (cam.far - cam.near) * t;
        s.visible_depth = Some([z(0.2), z(0.7)]);
        s.visible_depth_coverage = if k % 11 == 0 { DepthHintCoverage::Hint } else { DepthHintCoverage::View };
    }
    STATE.with(|st| {
        let (a, b, view) = &mut *st.borrow_mut();
        let direct = fit_case(&case, &s, a);
        let v = match view {
            Some(v) => v,
            None => match PreparedView::new(&cam, &s) {
                Ok(v) => view.insert(v),
                Err(e) => {
                    assert!(direct.is_err(), "fit {direct:?} but no view: {e}");
                    return;
                }
            },
        };
        let from_view =
            prepare_case(v, &case, &cam, &s).and_then(|()| fit_prepared(v, &case.light, &case.scene, b).map_err(|e| e.to_string()));
        match (&direct, &from_view) {
            (Ok(()), Ok(())) => {}
            (Err(e), Err(f)) => {
                assert_eq!(e, f, "different errors");
                return;
            }
            _ => panic!("fit {direct:?} but fit_prepared {from_view:?}"),
        }
        assert_eq!(a.split_depths(), b.split_depths());
        assert_eq!(a.maps().len(), b.maps().len());
        for (x, y) in a.maps().iter().zip(b.maps()) {
            assert_eq!(x.fit, y.fit);
            assert_eq!(x.fit.clip_from_world.to_cols_array().map(f64::to_bits), y.fit.clip_from_world.to_cols_array().map(f64::to_bits));
            assert_eq!(x.body().vertices(), y.body().vertices());
            if !x.is_active() {
                continue;
            }
            for p in x.body().vertices() {
                let q = x.fit.clip_from_world * p.extend(1.0);
                assert!(
                    q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= 0.0 && q.z <= q.w,
                    "vertex {p} of map {} outside its clip volume: {q}",
                    x.split
                );
            }
        }
    });
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        // Not UTF-8: the reader may stop with an I/O error, but not panic.
        let _ = run(std::io::Cursor::new(data), &mut Vec::new(), &FocusSettings::default());
        return;
    };
    for (i, line) in text.lines().enumerate() {
        compare(data.len() + i, line);
    }
    let mut out = Vec::new();
    let failed = run(std::io::Cursor::new(data), &mut out, &settings(data.len())).expect("UTF-8 input reads without I/O errors");
    check_result_lines(text, out, failed, |v, l| {
        assert!(v["maps"].as_array().is_some_and(|m| !m.is_empty()), "result without maps: {l}");
    });
});
