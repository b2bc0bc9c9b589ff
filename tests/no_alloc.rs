//! Allocation in the hot path, counted with a global allocator (per
//! thread, so that tests running side by side do not see each other's).
//!
//! - A frame allocates nothing once the result buffer exists, over fits of
//!   every method, light kind and split count. The one exception lies in the
//!   body engine: its exact engine, taken when the certified float path
//!   cannot prove a decision, allocates; so a fit may allocate only when one
//!   of its bodies comes from that engine. Fitting and culling themselves
//!   never do; nor do preparing a view and fitting from it.
//! - The certified float path allocates nothing once a `Body` has been used,
//!   including the bodies that place a vertex from its planes' exact
//!   intersection: checked over every fixture.

use glam::DVec3;
use shadowfocus_cli::cli::case::parse_case;
use shadowfocus_cli::focus::*;
use shadowfocus_cli::geom::{Aabb, Body, Camera, Focuser, Frustum, Light};
use std::path::Path;

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{allocations, Counting};

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn fitting_a_frame_does_not_allocate() {
    let cam = Camera {
        eye: DVec3::new(0.0, 2.0, 10.0),
        forward: DVec3::new(0.1, -0.1, -1.0),
        up: DVec3::Y,
        fovy: 1.0,
        aspect: 1.5,
        near: 0.5,
        far: 100.0,
    };
    let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap();
    let spot_cam = Camera { eye: DVec3::new(10.0, 30.0, 0.0), forward: DVec3::new(-0.2, -1.0, -0.5), ..cam };
    let lights = [
        Light::directional(DVec3::new(0.4, -1.0, 0.3)).unwrap(),
        Light::directional(DVec3::new(0.1, -0.3, -1.0)).unwrap(),
        Light::point(DVec3::new(30.0, 15.0, 15.0)).unwrap(),
        Light::point(DVec3::new(0.0, 2.0, -20.0)).unwrap(),
        Light::spot(spot_cam.eye, Frustum::from_camera(&spot_cam).unwrap()).unwrap(),
    ];
    let casters = [Aabb::new(DVec3::new(-1.0, 0.0, -5.0), DVec3::new(1.0, 3.0, -3.0)).unwrap(); 8];
    let mut idx = [0u32; 8];
    let receiver_boxes = ReceiverBoxes::new(&[
        Aabb::new(DVec3::new(-40.0, -1.0, -60.0), DVec3::new(40.0, 0.0, 5.0)).unwrap(),
        Aabb::new(DVec3::new(-2.0, 0.0, -8.0), DVec3::new(2.0, 4.0, -4.0)).unwrap(),
    ])
    .unwrap();
    let mut out = FocusResult::new();
    let mut state = FitState::default();
    let mut run = |out: &mut FocusResult, check: bool| {
        for light in &lights {
            for method in [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm, Method::Auto] {
                for count in [1, 4] {
                    for (stable, depth_clamp) in [(false, false), (true, false), (false, true)] {
                        // Stable maps with the practical planes, the others with
                        // the default optimal placement.
                        let scheme = if stable { SplitScheme::Practical { lambda: 0.5 } } else { SplitScheme::Optimal };
                        let splits = SplitSettings { count, scheme, ..Default::default() };
                        // Receiver boxes with the receiver fit (they cut R, and
                        // the optimal placement predicts on them).
                        let receivers = if depth_clamp { receiver_boxes } else { ReceiverBoxes::NONE };
                        // A texel budget with them too (stable maps refuse one).
                        let texel_budget = depth_clamp.then_some(TexelBudget { texels: 4 * 1024 * 1024, sizes: MapSizes::Any });
                        // And a visible depth range a frame old, the outer
                        // splits covering the whole view.
                        let (visible_depth, visible_depth_coverage) = (depth_clamp.then_some([3.0, 60.0]), DepthHintCoverage::View);
                        let s = FocusSettings {
                            method,
                            stable,
                            depth_clamp,
                            splits,
                            receivers,
                            texel_budget,
                            visible_depth,
                            visible_depth_coverage,
                            ..Default::default()
                        };
                        let a0 = allocations();
                        fit(&cam, light, &scene, &s, out).unwrap();
                        let a1 = allocations();
                        for m in out.maps() {
                            cull_casters(m, &casters, &mut idx).unwrap();
                        }
                        let a2 = allocations();
                        let exact_engine = out.maps().iter().filter(|m| !m.body().stats().float_path).count();
                        // The same frame from a view prepared beforehand.
                        let view = PreparedView::new(&cam, &s).unwrap();
                        let a3 = allocations();
                        fit_prepared(&view, light, &scene, out).unwrap();
                        // And with a state carried from the last frame.
                        fit_prepared_with_state(&view, light, &scene, &mut state, out).unwrap();
                        let a4 = allocations();
                        if !check {
                            continue;
                        }
                        assert_eq!(a2, a1, "culling allocated");
                        assert!(
                            a1 == a0 || exact_engine > 0,
                            "{light:?} {method:?} {count} {stable} {depth_clamp}: {} allocations on the float path",
                            a1 - a0
                        );
                        assert_eq!(a3, a2, "preparing a view allocated");
                        assert!(
                            a4 == a3 || exact_engine > 0,
                            "{light:?} {method:?} {count} {stable} {depth_clamp}: {} allocations in fit_prepared",
                            a4 - a3
                        );
                    }
                }
            }
        }
    };
    run(&mut out, false); // first use fills the bodies' scratch space
    run(&mut out, true);
}

#[test]
fn float_path_bodies_do_not_allocate() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/cases");
    let mut cases = Vec::new();
    for name in ["classic", "directional", "point", "spot", "scene", "extreme"] {
        let text = std::fs::read_to_string(root.join(format!("{name}.jsonl"))).unwrap();
        cases.extend(text.lines().filter(|l| !l.trim().is_empty()).map(|l| parse_case(l).unwrap()));
    }
    let mut body = Body::new();
    let mut focuser = Focuser::new();
    // A first pass sizes the body's scratch space.
    for case in &cases {
        focuser.focus_into(&mut body, &case.view, &case.light, &case.scene).unwrap();
    }
    let (mut float_path, mut placed_exactly, mut exact_engine) = (0, 0, 0);
    for case in &cases {
        let before = allocations();
        focuser.focus_into(&mut body, &case.view, &case.light, &case.scene).unwrap();
        let allocated = allocations() - before;
        let stats = body.stats();
        if stats.float_path {
            assert_eq!(allocated, 0, "{}", case.id);
            float_path += 1;
            placed_exactly += (stats.exact_evaluations > 0) as usize;
        } else {
            exact_engine += 1;
        }
    }
    eprintln!("{float_path} float-path bodies ({placed_exactly} with a vertex placed exactly), {exact_engine} from the exact engine");
    assert!(float_path > 3700 && placed_exactly > 50, "{float_path} float-path bodies, {placed_exactly} placed exactly");
}

#[test]
fn gathering_visible_receivers_does_not_allocate() {
    // A frame's points of every facing and none, more boxes than allowed
    // merged down, the boxes taken: no allocation.
    let cam = Camera {
        eye: DVec3::new(0.0, 2.0, 0.0),
        forward: DVec3::new(0.0, -0.2, 1.0),
        up: DVec3::Y,
        fovy: 1.0,
        aspect: 1.5,
        near: 0.5,
        far: 400.0,
    };
    let normals = [DVec3::X, DVec3::Y, DVec3::Z];
    let before = allocations();
    let mut v = VisibleReceivers::new(&cam, 180).unwrap();
    for i in 0..20_000 {
        let t = i as f64 / 20_000.0;
        let p = DVec3::new((i % 97) as f64 - 48.0, (i % 13) as f64 * 0.7, 0.6 * 400f64.powf(t));
        match i % 4 {
            3 => v.add(p),
            k => v.add_facing(p, normals[k]),
        }
    }
    let boxes = v.boxes(1e-3).unwrap();
    assert_eq!(allocations() - before, 0);
    assert_eq!(boxes.as_slice().len(), MAX_RECEIVER_BOXES, "the merge down to 16 ran");
}
