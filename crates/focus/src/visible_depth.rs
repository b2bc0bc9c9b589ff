//! The visible depth range as a hint (sample-distribution shadow maps
//! [SDSM10]): the view depths `[z_min, z_max]` of the samples a frame
//! actually shades, read back from its depth buffer.
//!
//! With [`crate::FocusSettings::visible_depth`] the fit uses
//! `[max(near, z_min), min(far, z_max)]` as the camera's range: the splits
//! are placed over it and every split's `V_i` is cut to it, so no texel goes
//! to depths where nothing is seen. Every receiver shaded with the maps
//! must lie in that slab, or its pixel has no map:
//!
//! - a range reduced from this frame's own depth pre-pass holds it exactly
//!   (round outward by the depth buffer's precision);
//! - a range from an earlier frame holds the points seen then, once widened
//!   by the camera's motion ([`visible_depth_after_motion`]); points that
//!   become visible only in this frame (disocclusion, objects moving in)
//!   can lie outside it. With
//!   [`crate::FocusSettings::visible_depth_coverage`] set to
//!   [`crate::DepthHintCoverage::View`] the planes are still placed over the
//!   range, but the first split reaches back to `near` and the last out to
//!   `far`, so such a pixel has a map, at the outer split's resolution; an
//!   engine that takes the hint with a frame of latency sets it (or gives
//!   those pixels a fallback of its own).

use shadowfocus_geom::Camera;

/// A visible depth range `[a, b]` measured with camera `then`, widened so
/// that it holds the view depth, seen from `now`, of every point that had a
/// depth in `[a, b]` inside `then`'s frustum. `None` for an empty or
/// non-finite range or a degenerate camera.
///
/// Derivation. A point `p` of `then`'s frustum at depth `z = (p − e₀)·f₀`
/// is at most `k·z` from the eye, `k = √(1 + t²(1 + α²))` (`t = tan(fovy/2)`,
/// `α` the aspect ratio: the corner ray's length per unit depth). Its depth
/// from `now` is `z' = (p − e₁)·f₁ = z + (p − e₀)·(f₁ − f₀) + (e₀ − e₁)·f₁`,
/// so `|z' − z| ≤ k·z·δ + d` with `δ = |f₁ − f₀|` (unit forward vectors) and
/// `d = |e₁ − e₀|`. Over `z ∈ [a, b]`: `z' ≥ min(a(1 − kδ), b(1 − kδ)) − d`
/// and `z' ≤ b(1 + kδ) + d`. The bounds are rounded outward by a few ulps.
pub fn visible_depth_after_motion(range: [f64; 2], then: &Camera, now: &Camera) -> Option<[f64; 2]> {
    let [a, b] = range;
    if !(a.is_finite() && b.is_finite() && a <= b) {
        return None;
    }
    let (f0, f1) = (then.basis().ok()?.forward, now.basis().ok()?.forward);
    let t = (0.5 * then.fovy).tan();
    let k = (1.0 + t * t * (1.0 + then.aspect * then.aspect)).sqrt();
    let (delta, d) = ((f1 - f0).length(), (now.eye - then.eye).length());
    let shrink = 1.0 - k * delta;
    let lo = (a * shrink).min(b * shrink) - d;
    let hi = b * (1.0 + k * delta) + d;
    // NOTE: each bound is a handful of roundings of terms no larger than
    // |hi| (or |lo|) plus d; 16 ulps of their sum covers them.
    let slack = 16.0 * f64::EPSILON * (lo.abs().max(hi.abs()) + d);
    let out = [lo - slack, hi + slack];
    (out[0].is_finite() && out[1].is_finite()).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn camera(eye: DVec3, forward: DVec3) -> Camera {
        Camera { eye, forward, up: DVec3::Y, fovy: 1.1, aspect: 1.8, near: 0.1, far: 500.0 }
    }

    #[test]
    fn moved_points_stay_in_the_widened_range() {
        let then = camera(DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.1, -0.2, -1.0));
        let now = camera(DVec3::new(1.4, 1.9, 2.2), DVec3::new(0.16, -0.25, -1.0));
        let (range, mut seen) = ([7.0, 60.0], 0);
        let widened = visible_depth_after_motion(range, &then, &now).unwrap();
        let (b0, b1) = (then.basis().unwrap(), now.basis().unwrap());
        let t = (0.5 * then.fovy).tan();
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let z = range[0] + (range[1] - range[0]) * next();
            let (x, y) = ((2.0 * next() - 1.0) * t * then.aspect * z, (2.0 * next() - 1.0) * t * z);
            let p = then.eye + b0.forward * z + b0.right * x + b0.up * y;
            let z1 = (p - now.eye).dot(b1.forward);
            assert!(widened[0] <= z1 && z1 <= widened[1], "{p}: depth {z1} outside {widened:?}");
            seen += 1;
        }
        assert_eq!(seen, 20_000);
        // Not widened without motion beyond its rounding.
        let still = visible_depth_after_motion(range, &then, &then).unwrap();
        assert!((still[0] - 7.0).abs() < 1e-12 && (still[1] - 60.0).abs() < 1e-12, "{still:?}");
        // Bad ranges are refused.
        assert_eq!(visible_depth_after_motion([3.0, 2.0], &then, &now), None);
        assert_eq!(visible_depth_after_motion([f64::NAN, 2.0], &then, &now), None);
    }
}
