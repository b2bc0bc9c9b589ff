//! The rays through a body's part in a split, for the samples where the
//! image's own rays miss it (see the module above).

use super::RAYS;
use crate::split_view::SplitView;
use glam::DVec3;
use shadowfocus_geom::Body;

/// The body's part in a split's depth range, as the camera sees it: the
/// centre of its points and the extreme one in each of eight image
/// directions (image `x`, `y` and both diagonals, each way).
///
/// Its points are the body's vertices within the depth range and the
/// points where the body's edges cross the near or the far plane: the
/// part's vertices are among them, and the body being convex, each is a
/// point of it.
pub(super) struct Part {
    sum: DVec3,
    count: usize,
    /// Per direction: the greatest score and its point.
    extreme: [(f64, DVec3); RAYS - 1],
}

impl Part {
    pub(super) fn of(sv: &SplitView, body: &Body) -> Part {
        let mut part = Part { sum: DVec3::ZERO, count: 0, extreme: [(f64::NEG_INFINITY, DVec3::ZERO); RAYS - 1] };
        let (cam, verts) = (sv.camera, body.vertices());
        let depth = |p: DVec3| (p - cam.eye).dot(sv.basis.forward);
        let mut cross = |a: DVec3, b: DVec3| {
            let (da, db) = (depth(a), depth(b));
            for plane in [cam.near, cam.far] {
                if (da < plane) != (db < plane) {
                    // NOTE: from the nearer end, so that the point lies on
                    // the edge however the depths round.
                    let (p, q, dp, dq) = if da < db { (a, b, da, db) } else { (b, a, db, da) };
                    part.add(sv, p + (q - p) * ((plane - dp) / (dq - dp)).clamp(0.0, 1.0));
                }
            }
        };
        if body.face_count() > 0 {
            for face in body.faces() {
                for (&i, &j) in face.iter().zip(face.iter().cycle().skip(1)) {
                    cross(verts[i as usize], verts[j as usize]);
                }
            }
        } else {
            for (i, &a) in verts.iter().enumerate() {
                for &b in &verts[i + 1..] {
                    cross(a, b);
                }
            }
        }
        for &p in verts {
            let d = depth(p);
            if d >= cam.near && d <= cam.far {
                part.add(sv, p);
            }
        }
        part
    }

    fn add(&mut self, sv: &SplitView, p: DVec3) {
        let b = &sv.basis;
        let v = p - sv.camera.eye;
        let z = v.dot(b.forward);
        let (x, y) = (v.dot(b.right) / z, v.dot(b.up) / z);
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        self.sum += p;
        self.count += 1;
        let scores = [x, -x, y, -y, x + y, -x - y, x - y, y - x];
        for (e, score) in self.extreme.iter_mut().zip(scores) {
            if score > e.0 {
                *e = (score, p);
            }
        }
    }

    /// Camera rays (`d·forward = 1`) through the part's centre and halfway
    /// from it to each extreme point: every one meets the body's box within
    /// the split (for the guard's samples where the image's nine rays
    /// miss it: a thin, tilted part between them). `None` for an empty part.
    pub(super) fn rays(&self, sv: &SplitView) -> Option<[DVec3; RAYS]> {
        if self.count == 0 {
            return None;
        }
        let centre = self.sum / self.count as f64;
        let ray = |p: DVec3| {
            let v = p - sv.camera.eye;
            v / v.dot(sv.basis.forward)
        };
        let mut rays = [ray(centre); RAYS];
        for (r, e) in rays[1..].iter_mut().zip(self.extreme) {
            *r = ray(0.5 * (centre + e.1));
        }
        Some(rays)
    }
}
