//! One test per phase of the certified engine, each on a body whose answer
//! is known in closed form: the hull phase alone, a clip that removes
//! everything, and the writer's exact input vertices.

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
