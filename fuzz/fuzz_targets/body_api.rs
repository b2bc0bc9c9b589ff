//! Frustum, light and box constructors and `focus_body` on arbitrary
//! numbers: never a panic; on success, a body whose counts match its
//! dimension, with finite vertices near S, the same body as the exact engine
//! alone gives, and the same result when a `Body` is reused.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use shadowfocus_fuzz::{magnitude, FrustumIn, LightIn, SceneIn};
use shadowfocus_geom::{focus_body, Aabb, Body, DVec3, Dimension, Focuser, Frustum, Light, ROUNDING_ULPS};
use std::cell::RefCell;

#[derive(Arbitrary, Debug)]
struct Input {
    view: FrustumIn,
    light: LightIn,
    scene: SceneIn,
}

thread_local! {
    static REUSED: RefCell<(Focuser, Body)> = RefCell::new((Focuser::new(), Body::new()));
}

fn check(body: &Body, scene: &Aabb, tol: f64) {
    let n = body.vertices().len();
    let faces = body.face_count();
    match body.dimension() {
        Dimension::Empty => assert!(n == 0 && faces == 0 && body.is_empty()),
        Dimension::Point => assert!(n == 1 && faces == 0),
        Dimension::Segment => assert!(n == 2 && faces == 0),
        Dimension::Polygon => {
            assert!(n >= 3 && faces == 1, "polygon with {n} vertices and {faces} faces");
            assert_eq!(body.face(0).map(<[u16]>::len), Some(n));
            assert!(body.face(faces).is_none());
        }
        Dimension::Solid => {
            assert!(n >= 4 && faces >= 4, "solid with {n} vertices and {faces} faces");
            // Euler: V − E + F = 2 with E = half the directed edges.
            let directed: usize = body.faces().map(|f| f.len()).sum();
            assert_eq!(directed % 2, 0);
            assert_eq!(n as i64 - (directed / 2) as i64 + faces as i64, 2, "Euler characteristic");
        }
    }
    for f in body.faces() {
        assert!(f.iter().all(|&i| (i as usize) < n), "face index out of range");
    }
    assert_eq!(body.face_planes().len(), faces);
    let v = body.volume();
    assert!(!v.is_nan() && v >= 0.0, "volume {v}");
    if body.dimension() != Dimension::Solid {
        assert_eq!(v, 0.0);
    }
    // Rounded vertices lie in S up to the rounding bound.
    let g = tol * 1.01;
    for p in body.vertices() {
        assert!(p.is_finite(), "vertex {p:?}");
        for k in 0..3 {
            assert!(p[k] >= scene.min[k] - g && p[k] <= scene.max[k] + g, "vertex {p:?} outside S by more than {g:e}");
        }
    }
    if let Some(h) = body.exact() {
        assert_eq!(h.dimension() as i32, body.dimension().as_i32(), "exact and rounded bodies disagree");
    }
}

/// The floating-point path (when it answered) and the exact engine give the
/// same body: dimension, vertex count and face sizes.
fn check_against_exact_engine(body: &Body, view: &Frustum, light: &Light, scene: &Aabb) {
    let mut reference = Body::new();
    Focuser::new().focus_exact_into(&mut reference, view, light, scene).expect("the exact engine accepts what the fast path accepted");
    assert_eq!(body.dimension(), reference.dimension(), "float path {}", body.stats().float_path);
    assert_eq!(body.vertices().len(), reference.vertices().len(), "float path {}", body.stats().float_path);
    let sizes = |b: &Body| {
        let mut v: Vec<usize> = b.faces().map(|f| f.len()).collect();
        v.sort_unstable();
        v
    };
    assert_eq!(sizes(body), sizes(&reference));
}

fuzz_target!(|input: Input| {
    let Ok(view) = input.view.build() else { return };
    let light = input.light.build(&view, &input.view);
    let scene = input.scene.build(&view);
    let (Ok(light), Ok(scene)) = (light, scene) else { return };
    let result = focus_body(&view, &light, &scene);
    let valid = scene.min.is_finite()
        && scene.max.is_finite()
        && scene.min.cmple(scene.max).all()
        && match light {
            Light::Directional { direction } => direction.is_finite() && direction != DVec3::ZERO,
            Light::Point { position } | Light::Spot { position, .. } => position.is_finite(),
        };
    assert_eq!(result.is_ok(), valid, "validity {valid} but {result:?}");
    let Ok(body) = result else { return };

    let mut pts: Vec<_> = view.corners().to_vec();
    pts.extend([scene.min, scene.max]);
    if let Light::Point { position } | Light::Spot { position, .. } = light {
        pts.push(position);
    }
    if let Light::Spot { frustum, .. } = light {
        pts.extend(frustum.corners());
    }
    let tol = ROUNDING_ULPS * f64::EPSILON * magnitude(&pts);
    check(&body, &scene, tol);
    check_against_exact_engine(&body, &view, &light, &scene);

    REUSED.with(|r| {
        let (focuser, reused) = &mut *r.borrow_mut();
        focuser.focus_into(reused, &view, &light, &scene).expect("same input, same result");
        assert_eq!(format!("{reused:?}"), format!("{body:?}"), "reused body differs");
    });
});
