//! Tests per phase of the certified engine, each on a body whose answer is
//! known in closed form: the hull phase alone and the writer's exact input
//! vertices, box clips that remove everything, nothing or part, a spot
//! light's frustum clip, a flat body, and a decision floating point cannot
//! make (handed to the exact engine).

use super::{CertifiedClipper, Step};
use crate::body::Body;
use crate::input::aabb::Aabb;
use crate::input::camera::Camera;
use crate::input::frustum::{Frustum, HullOutline};
use crate::input::light::Light;
use glam::DVec3;

/// A camera at the origin looking down −z, near 1, far 10.
fn view() -> Frustum {
    let camera =
        Camera { eye: DVec3::ZERO, forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 60f64.to_radians(), aspect: 1.5, near: 1.0, far: 10.0 };
    Frustum::from_camera(&camera).unwrap()
}

fn outline(view: &Frustum, light: &Light) -> HullOutline {
    let mut out = HullOutline::new();
    view.hull_outline_into(light.apex(), &mut out).unwrap();
    out
}

/// A box around everything the tests build, so that it cuts nothing.
fn far_box() -> Aabb {
    Aabb::new(DVec3::splat(-1e3), DVec3::splat(1e3)).unwrap()
}

/// Hull phase and writer: a point light behind the eye on the view axis.
/// `hull(V ∪ {l})` is then the pyramid from `l` over the far face (the
/// near corners lie strictly inside it), so the body has exactly the light
/// and the four far corners as vertices — exact input points, unrounded.
#[test]
fn hull_of_a_light_behind_the_eye_is_the_pyramid_over_the_far_face() {
    let view = view();
    let l = DVec3::new(0.0, 0.0, 2.0);
    let light = Light::point(l).unwrap();
    let mut fast = CertifiedClipper::new();
    let step = fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &far_box(), None);
    assert_eq!(step, Step::Nonempty);
    let mut body = Body::new();
    assert!(fast.write(&mut body), "the writer could not certify a pyramid of exact input points");
    let mut got: Vec<DVec3> = body.vertices().to_vec();
    let mut want: Vec<DVec3> = view.corners()[4..].to_vec();
    want.push(l);
    let key = |p: &DVec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    got.sort_by_key(key);
    want.sort_by_key(key);
    assert_eq!(got, want, "vertices of hull(V ∪ l)");
    assert_eq!(body.dimension().as_i32(), 3);
}

/// Clip phase: a scene box beside the hull, not touching it, leaves nothing.
#[test]
fn a_box_beside_the_hull_clips_it_to_nothing() {
    let view = view();
    let light = Light::point(DVec3::new(0.0, 0.0, 2.0)).unwrap();
    let mut fast = CertifiedClipper::new();
    let scene = Aabb::new(DVec3::new(100.0, 100.0, -5.0), DVec3::new(110.0, 110.0, 5.0)).unwrap();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &scene, None), Step::Nonempty);
    assert_eq!(fast.clip_box(&scene), Step::Empty);
}

/// Clip phase: a box that holds the whole hull cuts none of its planes, and
/// the written body keeps the hull's vertices.
#[test]
fn a_box_around_the_hull_cuts_nothing() {
    let view = view();
    let light = Light::point(DVec3::new(0.0, 0.0, 2.0)).unwrap();
    let mut fast = CertifiedClipper::new();
    let scene = far_box();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &scene, None), Step::Nonempty);
    assert_eq!(fast.clip_box(&scene), Step::Nonempty);
    assert_eq!(fast.cuts, 0, "planes of the box that cut the hull");
    let mut body = Body::new();
    assert!(fast.write(&mut body));
    assert_eq!(body.vertices().len(), 5);
}

/// Clip phase: a box through the middle of the view keeps only its part of
/// the hull: every written vertex lies in the box (exactly, the box's
/// faces are axis planes) and the body is solid.
#[test]
fn a_box_through_the_view_cuts_the_hull_to_it() {
    let view = view();
    let light = Light::directional(DVec3::new(0.3, -1.0, 0.2)).unwrap();
    let mut fast = CertifiedClipper::new();
    let scene = Aabb::new(DVec3::new(-2.0, -1.0, -6.0), DVec3::new(2.0, 1.0, -3.0)).unwrap();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &scene, None), Step::Nonempty);
    assert_eq!(fast.clip_box(&scene), Step::Nonempty);
    assert!(fast.cuts > 0);
    let mut body = Body::new();
    assert!(fast.write(&mut body));
    assert_eq!(body.dimension().as_i32(), 3);
    for p in body.vertices() {
        assert!(p.cmpge(scene.min).all() && p.cmple(scene.max).all(), "vertex {p} outside the scene box");
    }
}

/// Spot clip: `hull(V ∪ l) ∩ L` for a spot at `l` looking down the view
/// axis whose frustum holds the whole view: only L's near plane cuts (the
/// hull's tip at `l` lies before it), so every vertex of the body is a far
/// corner of V or lies on that near plane, at distance `near` from `l`.
#[test]
fn a_spot_around_the_view_cuts_only_the_tip_at_its_near_plane() {
    let view = view();
    let l = DVec3::new(0.0, 0.0, 2.0);
    let near = 0.5;
    let spot_cam = Camera { eye: l, forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 120f64.to_radians(), aspect: 1.5, near, far: 100.0 };
    let frustum = Frustum::from_camera(&spot_cam).unwrap();
    let light = Light::spot(l, frustum).unwrap();
    let mut fast = CertifiedClipper::new();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &far_box(), None), Step::Nonempty);
    assert_eq!(fast.clip_frustum(&frustum), Step::Nonempty);
    assert!(fast.cuts >= 1, "the near plane must cut the tip");
    let mut body = Body::new();
    assert!(fast.write(&mut body));
    assert_eq!(body.dimension().as_i32(), 3);
    let far = &view.corners()[4..];
    for p in body.vertices() {
        let on_near = (p.z - (l.z - near)).abs() <= 1e-14;
        assert!(far.contains(p) || on_near, "vertex {p} is neither a far corner nor on the spot's near plane");
    }
    assert!(body.vertices().iter().any(|p| (p.z - (l.z - near)).abs() <= 1e-14));
}

/// Flat body: a scene box of zero height through the view leaves the
/// polygon of `hull(V ∪ l)` in that plane, every vertex exactly on it.
#[test]
fn a_box_of_zero_height_leaves_a_polygon_in_its_plane() {
    let view = view();
    let light = Light::directional(DVec3::new(0.3, -1.0, 0.2)).unwrap();
    let mut fast = CertifiedClipper::new();
    let scene = Aabb::new(DVec3::new(-20.0, -0.5, -20.0), DVec3::new(20.0, -0.5, 20.0)).unwrap();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &scene, None), Step::Nonempty);
    assert_eq!(fast.clip_box(&scene), Step::Nonempty);
    let mut body = Body::new();
    assert!(fast.write(&mut body));
    assert_eq!(body.dimension().as_i32(), 2);
    assert!(body.vertices().len() >= 3);
    assert!(body.vertices().iter().all(|p| p.y == -0.5), "a vertex off the plane y = -0.5");
}

/// Uncertain: an axis plane through the rounded position of a vertex that
/// an oblique cut placed (its true coordinate is known only to within its
/// rounding radius) cannot be decided in floating point; the clipper says
/// so instead of guessing, and the focus body comes from the exact engine,
/// equal to the exact engine's own answer.
#[test]
fn a_plane_through_a_rounded_vertex_is_left_to_the_exact_engine() {
    let view = view();
    let light = Light::point(DVec3::new(0.3, 0.7, 2.0)).unwrap();
    let first = Aabb::new(DVec3::splat(-1e3), DVec3::new(1e3, 0.4, 1e3)).unwrap();
    let mut fast = CertifiedClipper::new();
    assert_eq!(fast.reset_to_hull(&view, light.apex(), &outline(&view, &light), &first, None), Step::Nonempty);
    assert_eq!(fast.clip_box(&first), Step::Nonempty);
    // A vertex on y = 0.4 whose x was rounded (nonzero x radius).
    let v = (0..fast.verts.len).find(|&v| fast.verts.pos[v].y == 0.4 && fast.verts.rad[v].x > 0.0).expect("a rounded vertex on the cut");
    let x = fast.verts.pos[v].x;
    let second = Aabb::new(DVec3::splat(-1e3), DVec3::new(x, 1e3, 1e3)).unwrap();
    assert_eq!(fast.clip_box(&second), Step::Uncertain, "the side of x = {x} for a vertex rounded to it");
    // The whole computation with both bounds in one box: exactly the exact engine's body.
    let scene = Aabb::new(DVec3::splat(-1e3), DVec3::new(x, 0.4, 1e3)).unwrap();
    let (mut focuser, mut body, mut exact) = (crate::Focuser::new(), Body::new(), Body::new());
    focuser.focus_into(&mut body, &view, &light, &scene).unwrap();
    focuser.focus_exact_into(&mut exact, &view, &light, &scene).unwrap();
    assert!(!body.stats().float_path, "the float path claimed a body it cannot decide");
    assert_eq!(body.vertices(), exact.vertices());
}
