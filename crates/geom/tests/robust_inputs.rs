//! Public API on unusual input: long and short directions, checked boxes,
//! checked face indices. Typed errors or right answers, never a panic.

use shadowfocus_geom::{
    focus_body, unit_direction, Aabb, Body, Camera, DVec3, Focuser, Frustum, GeomError, Light, Polytope, ROUNDING_ULPS,
};

fn view() -> Frustum {
    Frustum::from_camera(&Camera {
        eye: DVec3::new(0.0, 2.0, 10.0),
        forward: DVec3::NEG_Z,
        up: DVec3::Y,
        fovy: 1.0,
        aspect: 1.5,
        near: 0.5,
        far: 100.0,
    })
    .unwrap()
}

fn scene() -> Aabb {
    Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0)).unwrap()
}

/// Scales by 2^k exactly (two steps, each factor a normal power of two).
fn scaled(d: DVec3, k: i32) -> DVec3 {
    let (a, b) = (k / 2, k - k / 2);
    d * 2f64.powi(a) * 2f64.powi(b)
}

#[test]
fn unit_direction_of_long_and_short_vectors() {
    let d = DVec3::new(3.0, -8.0, 2.0);
    let want = d.normalize();
    for k in [-1074 + 4, -1060, -1000, -600, -520, -300, -1, 0, 1, 300, 520, 600, 1000, 1020] {
        let dk = scaled(d, k);
        assert_eq!(dk / 2f64.powi(k / 2) / 2f64.powi(k - k / 2), d, "2^{k}: scaling not exact");
        let u = unit_direction(dk);
        // Where `normalize` itself overflows or underflows.
        if k.abs() >= 600 {
            assert_ne!(dk.normalize(), want, "2^{k}: normalize would do");
        }
        assert_eq!(u, want, "2^{k}");
    }
    // The largest and smallest magnitudes f64 has.
    for d in [DVec3::new(f64::MAX, -f64::MAX, f64::MAX), DVec3::new(f64::MIN_POSITIVE / 4.0, 0.0, 0.0), DVec3::new(0.0, 0.0, -5e-324)] {
        let u = unit_direction(d);
        assert!(u.is_finite() && (u.length() - 1.0).abs() < 4.0 * f64::EPSILON, "{d} → {u}");
        assert!(u.dot(d.signum()) > 0.0);
    }
    // Powers of ten (not exact multiples of d): the direction's unit vector
    // to within a few ulps.
    for k in [1e300, 1e-300, 1e200, 1e-200] {
        let u = unit_direction(d * k);
        assert!((u - want).abs().max_element() < 4.0 * f64::EPSILON, "{k:e}: {u}");
    }
    assert!(unit_direction(DVec3::ZERO).is_nan());
    assert!(unit_direction(DVec3::new(f64::INFINITY, 0.0, 0.0)).is_nan());
    assert_eq!(Light::directional(DVec3::new(0.0, -1e300, 0.0)).unwrap().unit_direction(), Some(DVec3::NEG_Y));
    assert_eq!(Light::point(DVec3::ONE).unwrap().unit_direction(), None);
}

/// A direction and every exact power-of-two multiple of it are one light:
/// the same body from both engines.
#[test]
fn long_and_short_directions_give_the_same_body() {
    let (v, s) = (view(), scene());
    for d in [DVec3::new(3.0, -8.0, 2.0), DVec3::new(0.0, -1.0, 0.0), DVec3::new(1.0, -1.0, -3.0), DVec3::new(0.0, 0.0, 1.0)] {
        let base = focus_body(&v, &Light::directional(d).unwrap(), &s).unwrap();
        for k in [-1060, -1000, -520, -300, 300, 520, 1000, 1020] {
            let light = Light::directional(scaled(d, k)).unwrap();
            let b = focus_body(&v, &light, &s).unwrap();
            if b.stats().float_path {
                // The same decisions and the same roundings.
                assert_eq!(b.vertices(), base.vertices(), "{d} · 2^{k}");
                assert_eq!(b.faces().collect::<Vec<_>>(), base.faces().collect::<Vec<_>>(), "{d} · 2^{k}");
            } else {
                same_vertices(&b, &base, &format!("{d} · 2^{k}"));
            }
            let mut e = Body::new();
            let mut focuser = Focuser::new();
            focuser.focus_exact_into(&mut e, &v, &light, &s).unwrap();
            same_vertices(&e, &base, &format!("{d} · 2^{k} (exact engine)"));
        }
    }
}

/// The same vertex set within both bodies' rounding bound (ROUNDING_ULPS
/// of the inputs' magnitude, 100 here).
fn same_vertices(a: &Body, b: &Body, what: &str) {
    let tol = 2.0 * ROUNDING_ULPS * f64::EPSILON * 100.0;
    assert_eq!(a.vertices().len(), b.vertices().len(), "{what}");
    for p in a.vertices() {
        assert!(b.vertices().iter().any(|q| (*p - *q).abs().max_element() <= tol), "{what}: {p} not in the other body");
    }
}

#[test]
fn face_index_past_the_faces_is_none() {
    let b = focus_body(&view(), &Light::directional(DVec3::new(3.0, -8.0, 2.0)).unwrap(), &scene()).unwrap();
    let n = b.face_count();
    assert!(n >= 4);
    for i in 0..n {
        assert_eq!(b.face(i), b.faces().nth(i));
    }
    assert_eq!(b.face(n), None);
    assert_eq!(b.face(usize::MAX), None);
    assert_eq!(Body::new().face(0), None);
}

#[test]
fn polytope_boxes_are_checked() {
    let good = Aabb::new(DVec3::ZERO, DVec3::ONE).unwrap();
    let bad = [
        (Aabb { min: DVec3::ONE, max: DVec3::ZERO }, GeomError::InvertedBox { axis: 0 }),
        (Aabb { min: DVec3::new(0.0, 2.0, 0.0), max: DVec3::ONE }, GeomError::InvertedBox { axis: 1 }),
        (Aabb { min: DVec3::new(f64::NAN, 0.0, 0.0), max: DVec3::ONE }, GeomError::NonFinite { what: "scene box min" }),
        (Aabb { min: DVec3::ZERO, max: DVec3::new(0.0, 0.0, f64::INFINITY) }, GeomError::NonFinite { what: "scene box max" }),
    ];
    for (b, want) in bad {
        assert_eq!(Polytope::from_aabb(&b).err(), Some(want.clone()), "{b:?}");
        let mut p = Polytope::from_aabb(&good).unwrap();
        assert_eq!(p.reset_to_aabb(&b), Err(want), "{b:?}");
        // Unchanged by the refused reset.
        assert!(p.contains_point(DVec3::ONE) && p.contains_point(DVec3::splat(0.5)) && !p.contains_point(DVec3::splat(1.5)));
    }
    let mut p = Polytope::from_aabb(&good).unwrap();
    p.reset_to_aabb(&Aabb::new(DVec3::splat(2.0), DVec3::splat(3.0)).unwrap()).unwrap();
    assert!(p.contains_point(DVec3::splat(2.5)) && !p.contains_point(DVec3::splat(0.5)));
}
