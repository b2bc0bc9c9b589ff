//! Where a face that the image's rays meet in one row only crosses the
//! split's near and far planes (see the module above).
//!
//! A far slice of a view over a ground meets it in one row of rays, all at
//! the slice's near end (the rows below pass under it, the row above over
//! it): judged on those three points, at one depth, a warp that is worse
//! at the slice's far end passes. On a plane face the receivers in one
//! image column run from one split plane to the other, and the worst of a
//! split's is at one of its ends, so the face's points at those ends, in
//! the same column, are the samples that give the guard the slice's depth.
//! They count in the predicted maximum only: a ray's sample stands for a
//! ninth of the image, a crossing for one row of it, and counted in the
//! mean and the typical ratio the ground at a split's far end, seen at a
//! graze, outvoted the near ground that fills the image (the robot war's
//! practical first split: LiSPSM's warp held back, its maximum doubled).
//! With receiver boxes a crossing lies on the box the ray met, whether or
//! not another box stands in front of it there.

use crate::split_view::SplitView;
use glam::DVec3;

/// A box face a ray's sample lies on: its axis, its coordinate on that
/// axis, its normal toward the camera and the box it bounds.
#[derive(Clone, Copy)]
pub(super) struct Face {
    pub axis: usize,
    pub at: f64,
    pub normal: DVec3,
    pub lo: DVec3,
    pub hi: DVec3,
}

/// A sample on a box face from one of the image's rays, firmly lit.
#[derive(Clone, Copy)]
pub(super) struct FaceHit {
    /// The ray's image row (−1, 0 or 1 of the half field of view).
    pub row: f64,
    /// The ray's column: `forward + right·x·tan(fovx/2)`; the ray is
    /// `column + up·row·tan(fovy/2)`.
    pub column: DVec3,
    pub face: Face,
}

/// Whether the hits all come from one image row (and there is one at
/// least): the split's receivers are then seen at one depth per column.
pub(super) fn one_row(hits: &[Option<FaceHit>]) -> bool {
    let mut rows = hits.iter().flatten().map(|h| h.row);
    rows.next().is_some_and(|first| rows.all(|r| r == first))
}

/// The point of `hit`'s face at view depth `z` in its ray's image column,
/// where the image holds it and it lies on the face.
///
/// On the plane `x_k = at` the point `eye + z·(column + up·t)` has
/// `t = ((at − eye_k)/z − column_k) / up_k`; `t` beyond the half field of
/// view is outside the image, and `up_k = 0` (a face the column runs
/// along) gives no finite `t`.
pub(super) fn crossing(sv: &SplitView, hit: &FaceHit, z: f64) -> Option<DVec3> {
    let (f, eye, up) = (&hit.face, sv.camera.eye, sv.basis.up);
    let k = f.axis;
    let t = ((f.at - eye[k]) / z - hit.column[k]) / up[k];
    if !(t.abs() <= (0.5 * sv.camera.fovy).tan()) {
        return None;
    }
    let mut p = eye + (hit.column + up * t) * z;
    // NOTE: on the face exactly; the depth moves by the rounding only.
    p[k] = f.at;
    (0..3).all(|j| j == k || (f.lo[j] <= p[j] && p[j] <= f.hi[j])).then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::FocusSettings;
    use shadowfocus_geom::Camera;

    /// The robot war's camera, 14 m over its ground, cut to the far slice
    /// 316–750 m: the image's middle row meets the ground inside the slice
    /// (its lower rows pass under it, its upper row over the buildings).
    fn far_slice() -> Camera {
        Camera {
            eye: DVec3::new(-20.0, 14.0, -590.0),
            forward: DVec3::new(0.08, -0.04, 1.0),
            up: DVec3::Y,
            fovy: 60f64.to_radians(),
            aspect: 16.0 / 9.0,
            near: 316.0,
            far: 750.0,
        }
    }

    fn ground_hit(sv: &SplitView, gx: f64) -> FaceHit {
        let tx = (0.5 * sv.camera.fovy).tan() * sv.camera.aspect;
        let column = sv.basis.forward + sv.basis.right * (gx * tx);
        let (lo, hi) = (DVec3::new(-600.0, 0.0, -600.0), DVec3::new(600.0, 80.0, 600.0));
        FaceHit { row: 0.0, column, face: Face { axis: 1, at: 0.0, normal: DVec3::Y, lo, hi } }
    }

    #[test]
    fn a_ground_crosses_the_far_plane_in_the_column_of_its_ray() {
        let camera = far_slice();
        let settings = FocusSettings::default();
        let sv = SplitView { camera: &camera, basis: camera.basis().unwrap(), settings: &settings, ground: None };
        // The image's side columns reach 770 m to either side at the far
        // plane, beyond the ground's 600 m: off the face.
        for gx in [-1.0, 1.0] {
            assert!(crossing(&sv, &ground_hit(&sv, gx), camera.far).is_none());
        }
        for gx in [-0.5, 0.0, 0.5] {
            let hit = ground_hit(&sv, gx);
            let p = crossing(&sv, &hit, camera.far).expect("the ground reaches the far plane");
            let d = p - camera.eye;
            let depth = d.dot(sv.basis.forward);
            assert_eq!(p.y, 0.0);
            assert!((depth - camera.far).abs() <= 1e-9 * camera.far, "{depth}");
            // In the ray's column: the same image x as the ray.
            let x = d.dot(sv.basis.right) / depth;
            assert!((x - hit.column.dot(sv.basis.right)).abs() <= 1e-12, "{x}");
            // Inside the image, above its centre row, which meets the
            // ground nearer (at 350 m).
            let y = d.dot(sv.basis.up) / depth;
            assert!(y > 0.0 && y <= (0.5 * camera.fovy).tan(), "{y}");
            // The slice's near end: just below the centre row, which meets
            // the ground beyond it.
            let q = crossing(&sv, &hit, camera.near).expect("the ground reaches the near plane") - camera.eye;
            let y = q.dot(sv.basis.up) / q.dot(sv.basis.forward);
            assert!(y < 0.0 && y > -0.01, "{y}");
        }
    }

    #[test]
    fn a_crossing_off_the_face_or_along_it_is_none() {
        let camera = far_slice();
        let settings = FocusSettings::default();
        let sv = SplitView { camera: &camera, basis: camera.basis().unwrap(), settings: &settings, ground: None };
        // The ground ends 100 m ahead of the camera: its far-plane crossing is off it.
        let ground = ground_hit(&sv, 0.0);
        let short = FaceHit { face: Face { hi: DVec3::new(600.0, 80.0, -490.0), ..ground.face }, ..ground };
        assert!(crossing(&sv, &short, camera.far).is_none());
        // A wall x = 0 beside a camera looking along it (no image up in x):
        // its centre column never reaches the wall.
        let along = Camera { forward: DVec3::new(0.0, -0.04, 1.0), ..camera };
        let sv = SplitView { camera: &along, basis: along.basis().unwrap(), settings: &settings, ground: None };
        assert_eq!(sv.basis.up.x, 0.0);
        let ground = ground_hit(&sv, 0.0);
        let wall = FaceHit { face: Face { axis: 0, at: 0.0, normal: DVec3::NEG_X, ..ground.face }, ..ground };
        assert!(crossing(&sv, &wall, along.far).is_none());
    }

    #[test]
    fn only_hits_in_one_row_call_for_crossings() {
        let camera = far_slice();
        let settings = FocusSettings::default();
        let sv = SplitView { camera: &camera, basis: camera.basis().unwrap(), settings: &settings, ground: None };
        let h = |row: f64| Some(FaceHit { row, ..ground_hit(&sv, 0.0) });
        assert!(one_row(&[None, h(0.0), None, h(0.0)]));
        assert!(!one_row(&[h(0.0), h(-1.0)]));
        assert!(!one_row(&[None, None]));
    }
}
