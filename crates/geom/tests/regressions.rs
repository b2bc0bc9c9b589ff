//! Regressions found by the property tests and the fuzz targets, replayed
//! as fixed inputs so that they keep failing loudly if they come back.

use shadowfocus_geom::{focus_body, focus_body_into, Aabb, Body, Dimension, DVec3, Frustum, Light};

/// A point light 1e13 away with the scene holding both V and the light:
/// H is the pyramid over V's far face with its apex at the light. Volume
/// from tetrahedra fanned out of a body vertex cancels catastrophically when
/// that vertex is the far apex (the result came out negative).
#[test]
fn volume_of_a_body_with_a_far_vertex() {
    let c = [
        DVec3::new(-3957.0, 63022.5, 94269.0),
        DVec3::new(-3957.0, 63022.5, 94243.0),
        DVec3::new(-3957.0, 63053.5, 94243.0),
        DVec3::new(-3957.0, 63053.5, 94269.0),
        DVec3::new(-12145.0, 31294.0, 120880.0),
        DVec3::new(-12145.0, 31294.0, 67632.0),
        DVec3::new(-12145.0, 94782.0, 67632.0),
        DVec3::new(-12145.0, 94782.0, 120880.0),
    ];
    let view = Frustum::from_corners(c).unwrap();
    let l = DVec3::new(6952521159707.724, -5029296471556.252, -7324650991975.916);
    let scene = Aabb::new(DVec3::new(-12145.0, l.y, l.z), DVec3::new(l.x, 94782.0, 120880.0)).unwrap();
    let body = focus_body(&view, &Light::point(l).unwrap(), &scene).unwrap();
    assert_eq!(body.dimension(), Dimension::Solid);
    assert_eq!(body.vertices().len(), 5, "{body:?}");
    // base (63488 × 53248) × height (l.x + 12145) / 3, evaluated exactly and rounded.
    let expected = 7.834585271038791e21;
    let rel = (body.volume() - expected).abs() / expected;
    assert!(rel < 1e-9, "volume {} but the pyramid has {expected} (relative error {rel:e})", body.volume());
}

fn simple_view() -> Frustum {
    let mut c = [DVec3::ZERO; 8];
    for (k, t) in [1.0, 8.0].into_iter().enumerate() {
        for (i, (x, y)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
            c[4 * k + i] = DVec3::new(x * t, y * t, -t);
        }
    }
    Frustum::from_corners(c).unwrap()
}

/// An empty body found without clipping (the scene misses everything that
/// can cast into V) must still describe itself: `exact()` is the empty
/// polytope of this computation, not `None` and not a previous body.
#[test]
fn exact_body_after_an_early_empty_result() {
    let view = simple_view();
    let sun = Light::directional(DVec3::new(0.0, -1.0, 0.0)).unwrap();
    let far_away = Aabb::new(DVec3::splat(1000.0), DVec3::splat(1001.0)).unwrap();
    let fresh = focus_body(&view, &sun, &far_away).unwrap();
    assert!(fresh.is_empty());
    let exact = fresh.exact().expect("exact() after a successful computation");
    assert!(exact.is_empty());

    let around = Aabb::new(DVec3::splat(-100.0), DVec3::splat(100.0)).unwrap();
    let mut reused = Body::new();
    focus_body_into(&mut reused, &view, &sun, &around).unwrap();
    assert_eq!(reused.dimension(), Dimension::Solid);
    focus_body_into(&mut reused, &view, &sun, &far_away).unwrap();
    assert!(reused.is_empty());
    let exact = reused.exact().expect("exact() after a successful computation");
    assert!(exact.is_empty(), "exact() still holds the previous body (dimension {})", exact.dimension());
    assert!(!exact.contains_point(DVec3::new(0.0, 0.0, -4.0)));
}
