//! Regression: output face planes must describe their faces even when the
//! exact plane is defined by nearly collinear points (a light at the apex of
//! a long, thin frustum: each side plane passes through a near corner, a far
//! corner and the light, almost on one line).

use glam::DVec3;
use shadowfocus_geom::{focus_body, Aabb, Frustum, Light};

#[test]
fn face_planes_hold_their_vertices_for_a_light_at_the_apex() {
    let c = [
        DVec3::new(4.071751446695598, -3.7179286851489897, -5.450861866581199),
        DVec3::new(4.071751446695598, -4.650917342310994, 4.680155624698138),
        DVec3::new(4.071751446695598, 3.7179286851489897, 5.450861866581199),
        DVec3::new(4.071751446695598, 4.650917342310994, -4.680155624698138),
        DVec3::new(308252.3173589797, -281466.1326890859, -412657.99840040255),
        DVec3::new(308252.3173589797, -352098.12469665974, 354311.61155100766),
        DVec3::new(308252.3173589797, 281466.1326890859, 412657.99840040255),
        DVec3::new(308252.3173589797, 352098.12469665974, -354311.61155100766),
    ];
    let view = Frustum::from_corners(c).unwrap();
    let scene = Aabb::new(
        c[0].min(c[4]).with_y(-352098.12469665974).with_z(-412657.99840040255),
        DVec3::new(308252.3173589797, 352098.12469665974, 412657.99840040255),
    )
    .unwrap();
    let body = focus_body(&view, &Light::point(DVec3::ZERO).unwrap(), &scene).unwrap();
    let m = 412657.99840040255f64;
    assert!(body.face_count() >= 6);
    for (f, face) in body.faces().enumerate() {
        let plane = body.face_planes()[f];
        assert!((plane.truncate().length() - 1.0).abs() < 1e-12, "face {f}: normal not unit");
        for &i in face {
            let off = plane.truncate().dot(body.vertices()[i as usize]) + plane.w;
            assert!(off.abs() <= 1e-12 * m, "face {f}: vertex {i} is {off:e} off its plane");
        }
        for v in body.vertices() {
            let off = plane.truncate().dot(*v) + plane.w;
            assert!(off <= 1e-12 * m, "face {f}: a vertex is {off:e} outside its plane");
        }
    }
}
