//! Regressions found by the property tests and the fuzz targets, replayed
//! as fixed inputs so that they keep failing loudly if they come back.

use shadowfocus_geom::{focus_body, Aabb, Apex, Body, Camera, DVec3, Dimension, Focuser, Frustum, Light, Plane, Polytope};

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
    let mut focuser = Focuser::new();
    focuser.focus_into(&mut reused, &view, &sun, &around).unwrap();
    assert_eq!(reused.dimension(), Dimension::Solid);
    focuser.focus_into(&mut reused, &view, &sun, &far_away).unwrap();
    assert!(reused.is_empty());
    let exact = reused.exact().expect("exact() after a successful computation");
    assert!(exact.is_empty(), "exact() still holds the previous body (dimension {})", exact.dimension());
    assert!(!exact.contains_point(DVec3::new(0.0, 0.0, -4.0)));
}

/// Found by the `body_api` fuzz target: a point light 1e285 away behind a
/// frustum 2^47 deep with one creased side. Side tests through the light
/// overflow f64 (products of three coordinate differences reach ~1e315), and
/// an overflowed orientation must not be taken as "coplanar": the clipper
/// built an inconsistent solid and panicked ("every edge has a twin").
#[test]
fn point_light_near_the_top_of_the_f64_range() {
    let (n, f) = (2f64.powi(41), 2f64.powi(47));
    let mut c = [
        DVec3::new(-n, -n, -n),
        DVec3::new(n, -n, -n),
        DVec3::new(n, n, -n),
        DVec3::new(-n, n, -n),
        DVec3::new(-f, -f, -f),
        DVec3::new(f, -f, -f),
        DVec3::new(f, f, -f),
        DVec3::new(-f, f, -f),
    ];
    c[6] += DVec3::new(63.5, -0.5, -0.5);
    let view = Frustum::from_corners(c).unwrap();
    let scene = Aabb::new(DVec3::splat(-1e306), DVec3::splat(1e306)).unwrap();
    for light in [DVec3::new(0.0, 0.0, 1e285), DVec3::new(0.0, 1e300, 0.0)] {
        let body = focus_body(&view, &Light::point(light).unwrap(), &scene).unwrap();
        // S holds V and the light, so H = hull(V ∪ l) holds every corner.
        let h = body.exact().unwrap();
        assert_eq!(body.dimension(), Dimension::Solid);
        for (i, corner) in c.iter().enumerate() {
            assert!(h.contains_point(*corner), "corner {i} lost for a light at {light:?}");
        }
        assert!(h.contains_point(light));
    }
}

/// A valid frustum scaled by a power of two is still valid: its corners are
/// exact, and so are the predicates deciding its shape. Orientation tests
/// that overflow (|x| ≳ 2^340) or underflow (|x| ≲ 2^-340) in f64 must fall
/// back to exact arithmetic rather than report "all corners are coplanar".
#[test]
fn frusta_at_the_ends_of_the_f64_range() {
    let mut c = [DVec3::ZERO; 8];
    for (k, t) in [1.0, 8.0].into_iter().enumerate() {
        for (i, (x, y)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
            c[4 * k + i] = DVec3::new(x * t, y * t, -t);
        }
    }
    for k in [-600, -400, -340, 340, 400, 600, 1000] {
        let s = 2f64.powi(k);
        let f = Frustum::from_corners(c.map(|p| p * s)).unwrap_or_else(|e| panic!("scaled by 2^{k}: {e}"));
        assert!(f.contains(DVec3::new(0.0, 0.0, -4.0) * s), "2^{k}: centre not inside");
        assert!(!f.contains(DVec3::new(0.0, 0.0, 4.0) * s), "2^{k}: point behind the eye inside");
    }
}

/// Found by the `polytope_ops` fuzz target: `hull_with` is public and takes
/// any `Apex`; a non-finite one (here the point at infinity along −∞·x, from
/// an unchecked `Light::Directional`) reached the exact arithmetic, whose
/// literals must be finite (a debug assertion; meaningless signs in release
/// builds). Whatever planes come back, clipping by them must either be
/// rejected or keep the frustum.
#[test]
fn hull_with_a_non_finite_apex() {
    let view = simple_view();
    let inside = DVec3::new(0.0, 0.0, -4.0);
    for apex in [
        Apex::Infinite(DVec3::new(f64::NEG_INFINITY, 0.0, 0.0)),
        Apex::Infinite(DVec3::new(f64::NAN, 1.0, 0.0)),
        Apex::Infinite(DVec3::ZERO),
        Apex::Finite(DVec3::new(0.0, f64::INFINITY, 0.0)),
        Apex::Finite(DVec3::splat(f64::NAN)),
    ] {
        // The hull of a non-finite apex is undefined: a typed error.
        assert!(view.hull_with(apex).is_err(), "{apex:?}: accepted");
    }
    // A valid apex far away still keeps V.
    for apex in [Apex::Infinite(DVec3::new(1e300, 0.0, 0.0)), Apex::Finite(DVec3::new(0.0, 1e300, 0.0))] {
        let planes = view.hull_with(apex).unwrap();
        let mut p = Polytope::from_aabb(&Aabb::new(DVec3::splat(-100.0), DVec3::splat(100.0)).unwrap()).unwrap();
        p.clip_all(planes.as_slice()).unwrap();
        assert!(p.contains_point(inside), "{apex:?}: the hull lost V's centre");
    }
}

/// Found by the `body_api` fuzz target: a body reaching to −f64::MAX (a
/// point light there, a scene box down to it). Its volume exceeds the f64
/// range; it must come out as +∞, not NaN (∞ − ∞ in the sum).
#[test]
fn volume_beyond_the_f64_range_is_infinite_not_nan() {
    let eye = DVec3::new(3044096.0, -5297105.0, 3044096.0);
    let (a, b) = (253.0 / 16.0, 253.0 / 16.0);
    let mut c = [DVec3::ZERO; 8];
    for (k, t) in [1.0, 2.0].into_iter().enumerate() {
        for (i, (sx, sy)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
            c[4 * k + i] = eye + DVec3::new(sx * a * t, sy * b * t, -t);
        }
    }
    c[5] += DVec3::new(0.0, -0.375, -0.375);
    let view = Frustum::from_corners(c).unwrap();
    let light = Light::point(DVec3::new(-f64::MAX, f64::from_bits(3866109), -1e12)).unwrap();
    let scene = Aabb::new(DVec3::new(-f64::MAX, -f64::MAX, -205.0), DVec3::ZERO).unwrap();
    let body = focus_body(&view, &light, &scene).unwrap();
    assert!(body.vertices().iter().all(|v| v.is_finite()));
    let v = body.volume();
    assert!(!v.is_nan() && v >= 0.0, "volume {v} for a {:?} body", body.dimension());
    if body.dimension() == Dimension::Solid {
        assert!(v > 0.0);
    }
}

/// Found by the `polytope_ops` fuzz target: a box out to f64::MAX clipped by
/// the plane through (ε, −1, ε), (41·2^−1074, 0, 0) and the origin. Its exact
/// normal is 41·2^−1074·(0, ε, 1), far below the subnormal range, so the
/// adaptive orientation predicate underflows to a false "on the plane" for
/// box corners that are strictly outside, although the differences of the
/// points are not small. Exactly, the plane touches the box along one edge:
/// the result is the segment y = −1, z = ε.
#[test]
fn clip_whose_orientation_underflows() {
    let eps = f64::EPSILON;
    let b = Aabb::new(DVec3::new(-1.0, -1.0, eps), DVec3::new(f64::MAX, 5e-324, f64::MAX)).unwrap();
    let mut p = Polytope::from_aabb(&b).unwrap();
    let plane = Plane::Points([DVec3::new(eps, -1.0, eps), DVec3::new(f64::from_bits(41), 0.0, 0.0), DVec3::ZERO]);
    p.clip(&plane).unwrap();
    assert_eq!(p.dimension(), 1, "the plane touches the box along an edge");
    assert!(p.contains_point(DVec3::new(0.0, -1.0, eps)));
    assert!(p.contains_point(DVec3::new(f64::MAX, -1.0, eps)));
    assert!(!p.contains_point(DVec3::new(0.0, 0.0, eps)));
    assert!(!p.contains_point(DVec3::new(0.0, -1.0, 2.0 * eps)));
}

/// Found by the `polytope_ops` fuzz target: the segment x = z = ε,
/// y ∈ [ε, 12289] clipped by the plane through (0, −3.4e178, −2.9e298),
/// (6.7e-310, 0, 0) and the origin. Exactly, that halfspace is
/// `a·z ≤ b·y` with b/a ≈ 8.3e119, which holds on the whole segment; but
/// with coordinates far outside the range where the adaptive orientation
/// predicate is exact (1e298 and a subnormal), its nonzero answer had the
/// wrong sign: the clip cut off the endpoint y = ε and put a new one outside
/// the segment, so the result was not even a subset of the input.
#[test]
fn clip_with_orientation_outside_the_safe_range() {
    let e = f64::EPSILON;
    let segment = Polytope::from_aabb(&Aabb::new(DVec3::new(e, e, e), DVec3::new(e, 12289.0, e)).unwrap()).unwrap();
    let plane = Plane::Points([
        DVec3::new(0.0, f64::from_bits(16501470511038005114), f64::from_bits(18295281948936896485)),
        DVec3::new(f64::from_bits(135012313726976), 0.0, 0.0),
        DVec3::ZERO,
    ]);
    let mut p = segment.clone();
    let cut = p.clip(&plane).unwrap();
    assert!(!cut, "the halfspace holds the whole segment");
    assert!(p.contains_point(DVec3::new(e, e, e)));
    assert!(segment.contains(&p).unwrap() && p.contains(&segment).unwrap());
}

/// Found by the `body_api` fuzz target: a frustum whose far corner 7 lies in
/// the near plane (y = −1082182204), so the near face and one triangle of
/// the creased left side are coplanar and near corner 3 lies inside the
/// merged face. Beneath–beyond over the frustum's faces kept corner 3 as a
/// ninth vertex; the exact body (checked independently) has eight.
#[test]
fn coplanar_frustum_faces_do_not_add_a_vertex() {
    let c = [
        DVec3::new(-473731958.0625, -1082182204.0, 16.9375),
        DVec3::new(-473731958.0625, -1082182204.0, -14.9375),
        DVec3::new(-473731989.9375, -1082182204.0, -14.9375),
        DVec3::new(-473731989.9375, -1082182204.0, 16.9375),
        DVec3::new(-473731942.125, -1082182203.0, 32.875),
        DVec3::new(-473731942.125, -1082182203.0, -30.875),
        DVec3::new(-473732005.875, -1082182203.0, -30.875),
        DVec3::new(-473732006.875, -1082182204.0, 96.875),
    ];
    let view = Frustum::from_corners(c).unwrap();
    let light = Light::point(DVec3::new(-1.0, 32451.0, -1.0)).unwrap();
    let scene = Aabb::new(DVec3::new(-473732006.875, -1082182204.0, -30.875), DVec3::new(-473731942.125, -1082182203.0, 96.875)).unwrap();
    let body = focus_body(&view, &light, &scene).unwrap();
    let mut reference = Body::new();
    let mut focuser = Focuser::new();
    focuser.focus_exact_into(&mut reference, &view, &light, &scene).unwrap();
    assert_eq!(body.dimension(), Dimension::Solid);
    assert_eq!(body.vertices().len(), 8, "{body:?}");
    assert_eq!(reference.vertices().len(), 8, "{reference:?}");
    assert!(!body.vertices().contains(&c[3]), "corner 3 lies inside a face, it is no vertex: {body:?}");
}

/// A scene face lying exactly in the frustum's far plane touches four
/// vertices without cutting. The float path must not record that plane as a
/// second plane through those vertices: it finds edges as vertex pairs on two
/// common planes, and a repeated face plane would pair every two vertices of
/// the face. The body is the exact engine's, with the float path answering.
#[test]
fn a_scene_face_in_a_frustum_face_plane_adds_no_edges() {
    let view = simple_view();
    let light = Light::directional(DVec3::new(0.0, 0.0, -1.0)).unwrap();
    for max in [3.0, -0.5] {
        let scene = Aabb::new(DVec3::new(-5.0, -5.0, -8.0), DVec3::new(5.0, 5.0, max)).unwrap();
        let body = focus_body(&view, &light, &scene).unwrap();
        assert_eq!(body.dimension(), Dimension::Solid);
        assert_float_path_matches_exact_engine(&body, &view, &light, &scene);
    }
}

/// The float path answered, with the exact engine's vertex count, face sizes
/// and volume.
fn assert_float_path_matches_exact_engine(body: &Body, view: &Frustum, light: &Light, scene: &Aabb) {
    let mut reference = Body::new();
    let mut focuser = Focuser::new();
    focuser.focus_exact_into(&mut reference, view, light, scene).unwrap();
    assert!(body.stats().float_path, "the float path declined: {body:?}");
    assert_eq!(body.vertices().len(), reference.vertices().len(), "{body:?}\n{reference:?}");
    let sizes = |b: &Body| {
        let mut s: Vec<usize> = b.faces().map(|f| f.len()).collect();
        s.sort();
        s
    };
    assert_eq!(sizes(body), sizes(&reference), "{body:?}\n{reference:?}");
    assert!((body.volume() - reference.volume()).abs() <= 1e-12 * reference.volume());
}

/// Faces of S and L that the body's bounding box lies strictly inside of are
/// not clipped (they could neither cut nor touch), and the body is still the
/// exact engine's. The counts fail if the skip stops happening or starts
/// skipping a face that cuts.
#[test]
fn faces_the_body_clears_are_skipped_without_changing_it() {
    let view = simple_view();
    // A sun high above (the light enters through S's top face, which closes
    // the hull): S's faces at x = ±100, y = −100 and z = 50 clear the swept
    // frustum; z = −5 cuts it.
    let sun = Light::directional(DVec3::new(0.125, -1.0, 0.0625)).unwrap();
    let scene = Aabb::new(DVec3::new(-100.0, -100.0, -5.0), DVec3::new(100.0, 100.0, 50.0)).unwrap();
    let body = focus_body(&view, &sun, &scene).unwrap();
    assert_eq!((body.stats().planes_cleared, body.stats().planes_cut), (4, 1), "{:?}", body.stats());
    assert_float_path_matches_exact_engine(&body, &view, &sun, &scene);

    // A spot light above V whose frustum holds all of hull(V ∪ {l}) ∩ S: its
    // four side faces and its far face clear the body; its near face (the
    // apex's side of the body) is clipped, and cuts nothing.
    let apex = DVec3::new(0.0, 30.0, -4.0);
    let mut corners = [DVec3::ZERO; 8];
    for (k, t) in [1.0, 60.0].into_iter().enumerate() {
        for (i, (x, z)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
            corners[4 * k + i] = apex + DVec3::new(x * t, -t, z * t);
        }
    }
    let spot = Light::spot(apex, Frustum::from_corners(corners).unwrap()).unwrap();
    let body = focus_body(&view, &spot, &scene).unwrap();
    assert!(body.stats().planes_cleared >= 5, "{:?}", body.stats());
    assert_float_path_matches_exact_engine(&body, &view, &spot, &scene);
}

/// A spot light whose frustum's sides are all creased (twelve faces) cuts
/// `hull(V ∪ {l}) ∩ S` into a 42-vertex body. The float path keeps vertex
/// sets in 64 slots; a body this rich must still fit them and agree with the
/// exact engine (it fails if the slots run out and the case falls back).
#[test]
fn a_body_with_many_vertices_stays_on_the_float_path() {
    let view = Frustum::from_camera(&Camera {
        eye: DVec3::new(0.4682129922669358, 0.08628054349405512, 3.0),
        forward: DVec3::new(-0.017894668484396914, 0.11510552535890395, -1.0),
        up: DVec3::Y,
        fovy: 1.1172327274196434,
        aspect: 1.3135358815147984,
        near: 0.44503044448864537,
        far: 4.699923527976738,
    })
    .unwrap();
    let corners = [
        DVec3::new(1.0483580117438709, 0.6710081739813443, -1.3713250780315636),
        DVec3::new(0.4375100959336477, 0.7639916523528196, -1.84007355703426),
        DVec3::new(0.2172431620844644, 1.7689709003082126, -1.4394535205742232),
        DVec3::new(0.699624634837466, 1.7801760431232339, -0.9752605094750428),
        DVec3::new(10.629717682450872, -20.694746046361836, 4.146491241392994),
        DVec3::new(-9.108692380101703, -19.64157899704856, -10.34162974017888),
        DVec3::new(-17.015541729911977, 17.89060252539349, 3.275495060789109),
        DVec3::new(2.7406127912072593, 16.81129285364017, 17.648894844067513),
    ];
    let light_frustum = Frustum::from_corners(corners).unwrap();
    assert_eq!(light_frustum.face_count(), 12);
    let spot = Light::spot(DVec3::new(0.7186010723925556, 1.328133716263383, -1.5124660813762065), light_frustum).unwrap();
    let scene = Aabb::new(
        DVec3::new(-1.0588714438021745, -1.379759842987455, -1.6610307063924088),
        DVec3::new(1.9029556630235498, 1.9520563401994455, 1.933068521329564),
    )
    .unwrap();
    let body = focus_body(&view, &spot, &scene).unwrap();
    assert_eq!(body.vertices().len(), 42);
    assert_float_path_matches_exact_engine(&body, &view, &spot, &scene);
}

/// Flat results stay on the float path, with the exact engine's dimension,
/// vertex count and face sizes: a zero-thickness scene (a ground plane
/// through V: a polygon, with its two box faces one plane), a scene whose
/// face touches V along an edge of V's far face (a segment) and one that
/// touches V in a far corner only (a point). Each would fail if flat bodies
/// went back to the exact engine, or came out with another shape.
#[test]
fn flat_bodies_stay_on_the_float_path() {
    let view = simple_view(); // near z = −1 (half-width 1), far z = −8 (half-width 8)
    let sun = Light::directional(DVec3::new(0.25, -1.0, 0.125)).unwrap();
    let ground = Aabb::new(DVec3::new(-50.0, 0.0, -50.0), DVec3::new(50.0, 0.0, 50.0)).unwrap();
    // The far face's top edge lies in y = 8; the corner (8, 8, −8) is the
    // only point of V with x ≥ 8 and y ≥ 8.
    let edge = Aabb::new(DVec3::new(-50.0, 8.0, -50.0), DVec3::new(50.0, 20.0, -8.0)).unwrap();
    let corner = Aabb::new(DVec3::new(8.0, 8.0, -50.0), DVec3::new(20.0, 20.0, -8.0)).unwrap();
    // Travelling along −z: V swept toward +z, so nothing beyond the far
    // face (z < −8) but the far face itself.
    let behind = Light::directional(DVec3::new(0.0, 0.0, -1.0)).unwrap();
    for (scene, light, dim, verts) in
        [(ground, sun, Dimension::Polygon, None), (edge, behind, Dimension::Segment, Some(2)), (corner, behind, Dimension::Point, Some(1))]
    {
        let body = focus_body(&view, &light, &scene).unwrap();
        assert_eq!(body.dimension(), dim, "{body:?}");
        if let Some(n) = verts {
            assert_eq!(body.vertices().len(), n);
        }
        assert_float_path_matches_exact_engine(&body, &view, &light, &scene);
    }
}

/// A light in the plane of frustum faces: the hull's face on that plane is
/// the frustum face merged with the light (a corner can vanish into it), and
/// no horizon face rises on its edges. The float path builds that hull; a
/// light on V's boundary leaves V itself. Each case fails if the float path
/// declines it or disagrees with the exact engine.
#[test]
fn lights_in_a_face_plane_stay_on_the_float_path() {
    let view = simple_view(); // faces: z = −1, z = −8, y = ±(−z), x = ±(−z)
    let points = [
        DVec3::new(20.0, 0.0, -8.0),  // far plane, beside the far face
        DVec3::new(20.0, 8.0, -8.0),  // far and top planes: corner (8, 8, −8) vanishes
        DVec3::new(0.5, 0.25, -1.0),  // inside the near face
        DVec3::new(0.0, 8.0, -8.0),   // on a far edge
        DVec3::new(8.0, 8.0, -8.0),   // a corner
        DVec3::new(3.0, 0.0, -3.0),   // inside the right face
        DVec3::new(0.0, 12.0, -12.0), // top plane, beyond the far face
    ];
    let directions = [
        DVec3::new(1.0, 0.0, 0.0),   // parallel to near, far, top and bottom
        DVec3::new(0.0, -1.0, 1.0),  // parallel to the top face
        DVec3::new(0.0, 0.0, -1.0),  // parallel to no face (control)
        DVec3::new(-1.0, 0.0, -1.0), // parallel to the right face
    ];
    let scenes = [
        Aabb::new(DVec3::new(-40.3, -41.7, -43.1), DVec3::new(39.1, 42.9, 38.3)).unwrap(),
        // Faces in general position against the frustum's planes.
        Aabb::new(DVec3::new(-5.3, -3.1, -20.7), DVec3::new(25.9, 6.3, 0.7)).unwrap(),
        Aabb::new(DVec3::new(-2.3, -9.1, -6.7), DVec3::new(30.1, 2.9, -2.6)).unwrap(),
    ];
    let lights = points.map(|p| Light::point(p).unwrap()).into_iter().chain(directions.map(|d| Light::directional(d).unwrap()));
    for light in lights {
        for scene in &scenes {
            let body = focus_body(&view, &light, scene).unwrap();
            assert!(!body.is_empty(), "{light:?} {scene:?}");
            assert_float_path_matches_exact_engine(&body, &view, &light, scene);
        }
    }
}

/// A vertex whose float estimate is proven only loosely (its planes meet at
/// a small angle: the bound is above the output tolerance) is placed from
/// its planes' exact intersection, and the float path still answers the
/// body. Fails if the float path declines or the body differs from the
/// exact engine's.
#[test]
fn a_loosely_bounded_vertex_is_placed_exactly_on_the_float_path() {
    let corners = [
        [23.89472788401646, 2.0749077772560964, 6.35],
        [23.89472788401646, 2.4250922227439036, 6.35],
        [24.091706634603355, 2.4250922227439036, 6.35],
        [24.091706634603355, 2.0749077772560964, 6.35],
        [-24.337742438346105, -83.67170612916624, 55.32225734111483],
        [-24.337742438346105, 88.17170612916624, 55.32225734111483],
        [72.32417695696591, 88.17170612916624, 55.32225734111483],
        [72.32417695696591, -83.67170612916624, 55.32225734111483],
    ];
    let view = Frustum::from_corners(corners.map(DVec3::from_array)).unwrap();
    let light = Light::point(DVec3::new(18.98889081720511, 9.77587382772554, 6.25)).unwrap();
    let scene = Aabb::new(
        DVec3::new(-6.675206755009029, -82.24755691894177, 8.141940478029543),
        DVec3::new(24.936930825898813, 61.09631574774872, 46.35613727956077),
    )
    .unwrap();
    let body = focus_body(&view, &light, &scene).unwrap();
    assert!(body.stats().exact_evaluations > 0, "no vertex needed exact placement: {:?}", body.stats());
    assert_float_path_matches_exact_engine(&body, &view, &light, &scene);
}
