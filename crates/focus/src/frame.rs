//! Orientation of a map's image plane about its projection axis.
//!
//! A map looking along the unit axis `a` still needs an "up" direction in
//! the plane perpendicular to `a`. The warping methods want it along a
//! reference direction `v` (the view direction) projected into that plane,
//! `v⊥ = v − (v·a)a`, but `v⊥` vanishes when `a ∥ v` and flips through it,
//! which would rotate the map by 180° in one step. No unit tangent field on
//! the sphere of directions is continuous everywhere (hairy ball theorem),
//! so the singularity is moved where it costs least:
//!
//! `up = normalize(v⊥ + c(s)·w⊥)`, `s = |v⊥| = sin∠(a, v)`,
//! `c(s) = max(0, 1 − s/S0)`,
//!
//! with `w ⊥ v` a second reference. For `s ≥ S0` the up direction is exactly
//! the projected view direction (the paper's choice); below it blends
//! continuously into `w⊥`, which is non-zero there. The sum vanishes only
//! for `a` in the plane of `v` and `w`, at the two directions
//! `±(cos θ v + sin θ w)` with `tan θ = c(sin θ)` (θ ≈ S0/(1 + S0)); the
//! callers choose `w` so these lie off the sweeps that matter (see
//! [`crate::fit`]). Near them the frame still exists (a fallback axis is
//! used) but may turn quickly.

use glam::DVec3;

/// `sin γ` below which the up direction starts blending away from the
/// projected view direction (γ = 30°). A design choice of the
/// orientation, not a geometric tolerance.
pub const S0: f64 = 0.5;

/// Image basis `(right, up)` for a map looking along unit `a`, oriented like
/// a camera (`right = a × up`, so `right × up = −a`); see the module docs
/// for the choice of `up`. `v` and `w` must be orthonormal.
pub(crate) fn tangent_frame(a: DVec3, v: DVec3, w: DVec3) -> (DVec3, DVec3) {
    let v_perp = v - a * v.dot(a);
    let w_perp = w - a * w.dot(a);
    let s = v_perp.length();
    let c = (1.0 - s / S0).max(0.0);
    let mut up = v_perp + w_perp * c;
    let len = up.length();
    if !(len > 1e-3 * S0) {
        // NOTE: only near the two documented singular directions; any
        // direction perpendicular to `a` is a valid (if not continuous) up.
        up = a.any_orthonormal_vector();
    } else {
        up /= len;
    }
    // Re-orthogonalise once: `up` is perpendicular to `a` up to rounding.
    let up = (up - a * up.dot(a)).normalize();
    let right = a.cross(up);
    (right, up)
}

/// Unit `w` perpendicular to unit `v` built from a hint (falls back to any
/// perpendicular when the hint is parallel to `v`).
pub(crate) fn perpendicular_hint(v: DVec3, hint: DVec3) -> DVec3 {
    let p = hint - v * hint.dot(v);
    let l = p.length();
    if l > 1e-6 * hint.length() && l > 0.0 {
        p / l
    } else {
        v.any_orthonormal_vector()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_projected_view_for_large_angles() {
        let v = DVec3::new(0.0, 0.0, -1.0);
        let w = DVec3::new(1.0, 1.0, 0.0).normalize();
        let a = DVec3::new(0.0, -1.0, -0.3).normalize();
        let (right, up) = tangent_frame(a, v, w);
        let want = (v - a * v.dot(a)).normalize();
        assert!((up - want).length() < 1e-12);
        assert!(right.dot(a).abs() < 1e-12 && right.dot(up).abs() < 1e-12);
        assert!((right.cross(up) + a).length() < 1e-12, "right-handed looking along a");
    }

    #[test]
    fn continuous_through_the_view_direction() {
        // Sweep a through v in the plane of v and the camera up (⊥ w's plane).
        let v = DVec3::new(0.0, 0.0, -1.0);
        let upc = DVec3::Y;
        let w = (DVec3::X + DVec3::Y).normalize();
        let mut prev: Option<DVec3> = None;
        let n = 2000;
        for k in 0..=n {
            let t = -0.6 + 1.2 * k as f64 / n as f64;
            let a = (v * t.cos() + upc * t.sin()).normalize();
            let (_, up) = tangent_frame(a, v, w);
            assert!(up.is_finite());
            if let Some(p) = prev {
                // Step is 6e-4 rad; the frame may turn at most ~1/S0 times faster.
                assert!((up - p).length() < 0.02, "jump at t = {t}: {p} → {up}");
            }
            prev = Some(up);
        }
    }
}
