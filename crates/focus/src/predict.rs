//! Predicted perspective aliasing of a map, to compare parameterisations
//! before choosing one.
//!
//! A receiver point `p` seen by the camera at view depth `z` is drawn over
//! a screen pixel of world size proportional to `z`; the map draws it with
//! a texel whose footprint, on the plane through `p` across the light ray,
//! has the size `texel_size(p)` (see `project::texel_size`). The renderer's
//! aliasing `e` (screen pixels per texel, as a square root of areas) is
//! their ratio times factors that depend only on the receiver's
//! orientation to the light and to the eye, and on the camera — the same
//! for every map of one light. So two maps of one light compare exactly
//! through
//!
//! `q(p) = texel_size(p) / z(p)`,
//!
//! point by point: that is the quantity LiSPSM's `n_opt` balances between
//! the near and far ends of the view [LISPSM], without its restriction to
//! the view axis.
//!
//! Where receivers are is not known to the fit, only that they lie in
//! `V_i ∩ H`. The samples are points on nine rays of the split's camera (the
//! corners, edge midpoints and centre of the image), clipped to the split's
//! depth range and to the bounding box of `H`, at the clipped segment's
//! ends and its depth-geometric middle: the near ends carry the worst
//! undersampling, the rest the spread along the view.

use crate::methods::SplitView;
use crate::project::texel_size;
use glam::{DMat4, DVec3, DVec4};
use shadowfocus_geom::Body;

/// Most samples: nine rays, three points each.
pub(crate) const MAX_SAMPLES: usize = 27;

/// Receiver samples of one split, with their view depths.
pub(crate) struct Samples {
    pts: [DVec3; MAX_SAMPLES],
    depth: [f64; MAX_SAMPLES],
    len: usize,
}

/// A map's predicted aliasing over the samples, in `q` units (relative:
/// comparable between maps of one light and one split only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Predicted {
    pub max: f64,
    pub mean: f64,
}

impl Predicted {
    /// Whether `self` is at least as good as `other` in both the worst and
    /// the mean sample.
    pub fn no_worse_than(&self, other: &Predicted) -> bool {
        self.max <= other.max && self.mean <= other.mean
    }
}

impl Samples {
    /// Samples of the split of `sv` inside the bounding box of `body`.
    pub fn new(sv: &SplitView, body: &Body) -> Samples {
        let mut s = Samples { pts: [DVec3::ZERO; MAX_SAMPLES], depth: [0.0; MAX_SAMPLES], len: 0 };
        let (lo, hi) = bounds(body.vertices());
        let cam = sv.camera;
        let b = &sv.basis;
        let ty = (0.5 * cam.fovy).tan();
        let tx = ty * cam.aspect;
        for gy in [-1.0, 0.0, 1.0] {
            for gx in [-1.0, 0.0, 1.0] {
                // The ray eye + z·d, z the view depth (d·forward = 1).
                let d = b.forward + b.right * (gx * tx) + b.up * (gy * ty);
                let Some((z0, z1)) = clip_ray(cam.eye, d, cam.near, cam.far, lo, hi) else { continue };
                for z in [z0, (z0 * z1).sqrt(), z1] {
                    s.pts[s.len] = cam.eye + d * z;
                    s.depth[s.len] = z;
                    s.len += 1;
                }
            }
        }
        s
    }

    /// The prediction for `reference` (the map others are compared
    /// against), and which samples it sees; `None` without samples.
    pub fn judge(&mut self, reference: &DMat4, lp: DVec4) -> Option<Predicted> {
        let mut k = 0;
        for i in 0..self.len {
            if texel_size(reference, lp, self.pts[i], 2).is_finite() {
                self.pts[k] = self.pts[i];
                self.depth[k] = self.depth[i];
                k += 1;
            }
        }
        self.len = k;
        self.predict(reference, lp)
    }

    /// The prediction for the clip matrix `m` of the light `lp` over the
    /// samples kept by [`Samples::judge`]; one that `m` does not see makes
    /// its maximum infinite.
    pub fn predict(&self, m: &DMat4, lp: DVec4) -> Option<Predicted> {
        let (mut max, mut sum) = (0.0f64, 0.0);
        for i in 0..self.len {
            let q = texel_size(m, lp, self.pts[i], 2) / self.depth[i];
            max = max.max(q);
            sum += q;
        }
        (self.len > 0).then(|| Predicted { max, mean: sum / self.len as f64 })
    }
}

fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in pts {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo, hi)
}

/// The depth range `[z0, z1] ⊆ [near, far]` where `eye + z·d` lies in the
/// box `[lo, hi]` (slab clipping); `None` when empty.
fn clip_ray(eye: DVec3, d: DVec3, near: f64, far: f64, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (mut z0, mut z1) = (near, far);
    for k in 0..3 {
        let (e, dk) = (eye[k], d[k]);
        if dk == 0.0 {
            if e < lo[k] || e > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - e) / dk, (hi[k] - e) / dk);
        z0 = z0.max(a.min(b));
        z1 = z1.min(a.max(b));
    }
    (z0 <= z1 && z0 > 0.0).then_some((z0, z1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_clipped_to_a_box() {
        let eye = DVec3::ZERO;
        let d = DVec3::new(0.0, -0.5, 1.0);
        // The box y ∈ [−2, −1] is crossed between z = 2 and z = 4.
        let r = clip_ray(eye, d, 0.1, 100.0, DVec3::new(-10.0, -2.0, -10.0), DVec3::new(10.0, -1.0, 10.0));
        assert_eq!(r, Some((2.0, 4.0)));
        // Beyond far: nothing.
        assert_eq!(clip_ray(eye, d, 0.1, 1.5, DVec3::new(-10.0, -2.0, -10.0), DVec3::new(10.0, -1.0, 10.0)), None);
        // Parallel to a slab and outside it.
        assert_eq!(clip_ray(eye, DVec3::Z, 0.1, 10.0, DVec3::new(1.0, -1.0, 0.0), DVec3::new(2.0, 1.0, 5.0)), None);
    }
}
