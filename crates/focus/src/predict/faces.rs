//! Rays through the faces of a box that a split's camera sees from inside
//! it, for the samples where neither the image's rays nor the rays through
//! the body's part find receivers the light reaches (see the module above).
//!
//! Looking up from beyond the edge of a board, the ground is a strip of
//! the image between the nine rays, and the body's part lies mostly in
//! the air above it: every one of those rays leaves the box through a face
//! the light does not reach, and no warp could be judged. The faces the
//! camera sees, clipped to the split's frustum, show where the strip is.

use crate::split_view::SplitView;
use glam::{DVec3, DVec4};

/// Rays through one face: its clipped part's centre and halfway from it
/// to each of its first four corners.
pub(super) const FACE_RAYS: usize = 5;

/// Most corners of a quadrilateral clipped by the frustum's six planes.
const MAX_CORNERS: usize = 4 + 6;

/// Camera rays (`d·forward = 1`) through the part of face `face` of the box
/// `[lo, hi]` (`face / 2` its axis, an odd `face` its upper side) inside
/// the split's frustum, where the camera lies on the box's side of that
/// face (so that a ray through it leaves the box there, the box being
/// convex); none where it does not or the face lies outside the frustum.
pub(super) fn face_rays(sv: &SplitView, lo: DVec3, hi: DVec3, face: usize) -> [Option<DVec3>; FACE_RAYS] {
    let mut rays = [None; FACE_RAYS];
    let (axis, upper, plane) = face_plane(lo, hi, face);
    let inside = if upper { sv.camera.eye[axis] < plane } else { sv.camera.eye[axis] > plane };
    if !(inside && lo.is_finite() && hi.is_finite()) {
        return rays;
    }
    let mut poly = [DVec3::ZERO; MAX_CORNERS];
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    for (q, (ua, ub)) in poly.iter_mut().zip([(lo[a], lo[b]), (hi[a], lo[b]), (hi[a], hi[b]), (lo[a], hi[b])]) {
        let mut p = DVec3::ZERO;
        (p[axis], p[a], p[b]) = (plane, ua, ub);
        *q = to_camera(sv, p);
    }
    let n = clip_to_frustum(sv, &mut poly, 4);
    if n == 0 {
        return rays;
    }
    // NOTE: every corner lies at a depth of at least `near` > 0 after the
    // clip, so the image coordinates are finite.
    let image = |q: DVec3| (q.x / q.z, q.y / q.z);
    let (mut cx, mut cy) = (0.0, 0.0);
    for q in &poly[..n] {
        let (x, y) = image(*q);
        (cx, cy) = (cx + x, cy + y);
    }
    (cx, cy) = (cx / n as f64, cy / n as f64);
    let ray = |x: f64, y: f64| sv.basis.forward + sv.basis.right * x + sv.basis.up * y;
    rays[0] = Some(ray(cx, cy));
    for (r, q) in rays[1..].iter_mut().zip(&poly[..n]) {
        let (x, y) = image(*q);
        *r = Some(ray(0.5 * (cx + x), 0.5 * (cy + y)));
    }
    rays
}

/// The faces of the box `[lo, hi]` (numbered as in [`face_rays`]) whose
/// inner side the light reaches at their centre, the most directly lit
/// first, and how many there are: under a high sun the floor's rays come
/// first, under a low one a wall's.
pub(super) fn lit_faces(lo: DVec3, hi: DVec3, light_point: DVec4) -> ([usize; 6], usize) {
    let mut cosines = [0.0; 6];
    for (face, c) in cosines.iter_mut().enumerate() {
        let (axis, upper, plane) = face_plane(lo, hi, face);
        let mut centre = (lo + hi) * 0.5;
        centre[axis] = plane;
        let inward = if upper { -1.0 } else { 1.0 };
        let toward = (light_point.truncate() - centre * light_point.w).normalize_or_zero();
        *c = toward[axis] * inward;
    }
    let mut order = [0, 1, 2, 3, 4, 5];
    order.sort_by(|&i, &j| cosines[j].total_cmp(&cosines[i]));
    let lit = order.iter().take_while(|&&f| cosines[f] > 0.0).count();
    (order, lit)
}

/// Face `face` of the box `[lo, hi]`: its axis, whether it is the upper
/// side, and the coordinate of its plane on that axis.
fn face_plane(lo: DVec3, hi: DVec3, face: usize) -> (usize, bool, f64) {
    let (axis, upper) = (face / 2, face % 2 == 1);
    (axis, upper, if upper { hi[axis] } else { lo[axis] })
}

/// `p` in the camera's coordinates: right, up and view depth from the eye.
fn to_camera(sv: &SplitView, p: DVec3) -> DVec3 {
    let (r, b) = (p - sv.camera.eye, &sv.basis);
    DVec3::new(r.dot(b.right), r.dot(b.up), r.dot(b.forward))
}

/// Clips the convex polygon `poly[..n]` (camera coordinates) to the split's
/// frustum (Sutherland–Hodgman), in place; its new corner count.
fn clip_to_frustum(sv: &SplitView, poly: &mut [DVec3; MAX_CORNERS], mut n: usize) -> usize {
    let cam = sv.camera;
    let ty = (0.5 * cam.fovy).tan();
    let tx = ty * cam.aspect;
    // The frustum as half-spaces `g · (q, 1) ≥ 0`.
    let planes = [
        DVec4::new(0.0, 0.0, 1.0, -cam.near),
        DVec4::new(0.0, 0.0, -1.0, cam.far),
        DVec4::new(-1.0, 0.0, tx, 0.0),
        DVec4::new(1.0, 0.0, tx, 0.0),
        DVec4::new(0.0, -1.0, ty, 0.0),
        DVec4::new(0.0, 1.0, ty, 0.0),
    ];
    for g in planes {
        let side = |q: DVec3| g.truncate().dot(q) + g.w;
        let mut out = [DVec3::ZERO; MAX_CORNERS];
        let mut m = 0;
        for i in 0..n {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            let (sp, sq) = (side(p), side(q));
            // NOTE: a plane adds at most one corner to a convex polygon, so
            // `m` stays within `4 + 6`.
            if sp >= 0.0 {
                out[m] = p;
                m += 1;
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                out[m] = p + (q - p) * (sp / (sp - sq));
                m += 1;
            }
        }
        (*poly, n) = (out, m);
        if n == 0 {
            break;
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::FocusSettings;
    use shadowfocus_geom::Camera;

    /// Looking up from beyond a board's edge, 3 m above it: the floor's rays
    /// all meet the floor inside the view; the ceiling, seen from below the
    /// box's top, too; the side face the camera stands outside of, none.
    #[test]
    fn the_rays_pass_through_the_faces_the_camera_sees() {
        let camera = Camera {
            eye: DVec3::new(-385.0, 3.0, -100.0),
            forward: DVec3::new(585.0, 60.0, 160.0),
            up: DVec3::Y,
            fovy: 60f64.to_radians(),
            aspect: 16.0 / 9.0,
            near: 1.0,
            far: 800.0,
        };
        let settings = FocusSettings::default();
        let sv = SplitView { camera: &camera, basis: camera.basis().unwrap(), settings: &settings, ground: None };
        let (lo, hi) = (DVec3::new(-350.0, 0.0, -350.0), DVec3::new(350.0, 40.0, 350.0));
        let floor = face_rays(&sv, lo, hi, 2);
        assert!(floor.iter().all(Option::is_some), "{floor:?}");
        for d in floor.iter().flatten() {
            // Where the ray meets y = 0: inside the board and the frustum.
            let z = -camera.eye.y / d.y;
            let p = camera.eye + *d * z;
            assert!(z > camera.near && z < camera.far, "{z}");
            assert!(p.x > lo.x && p.x < hi.x && p.z > lo.z && p.z < hi.z, "{p}");
            let (x, y) = (d.dot(sv.basis.right), d.dot(sv.basis.up));
            let t = (0.5 * camera.fovy).tan();
            assert!(y.abs() <= t && x.abs() <= t * camera.aspect, "{d}");
        }
        assert!(face_rays(&sv, lo, hi, 0).iter().all(Option::is_none), "the camera is outside the face x = −350");
        assert!(face_rays(&sv, lo, hi, 3).iter().any(Option::is_some), "the box's top, seen from below");
        // Behind the camera: no part of the face x = −1000 lies in the
        // frustum, though the camera is on the box's side of it.
        let behind = (DVec3::new(-1000.0, 0.0, -1000.0), DVec3::new(-390.0, 40.0, 1000.0));
        assert!(face_rays(&sv, behind.0, behind.1, 0).iter().all(Option::is_none));
    }

    /// A high sun behind and left of +z lights the floor most directly, then
    /// the walls that face it; the ceiling and the walls turned away, not.
    #[test]
    fn the_most_directly_lit_faces_come_first() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        let toward_sun = DVec3::new(-0.2, 1.0, -0.4).extend(0.0);
        let (order, lit) = lit_faces(lo, hi, toward_sun);
        // Floor (y low, inward +y), then the z-high face (inward −z), then
        // the x-high face (inward −x).
        assert_eq!((&order[..lit], lit), (&[2, 5, 1][..], 3));
        // A point light inside the box reaches the inner side of every face.
        assert_eq!(lit_faces(lo, hi, DVec4::new(0.1, 0.2, 0.3, 1.0)).1, 6);
    }
}
