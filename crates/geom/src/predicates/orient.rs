//! The orientation predicate `sign(((q − p) × (r − p)) · (x − p))`, exact,
//! and its variant for a point at infinity, as a cascade of stages, cheapest
//! first: a static floating-point filter, a dynamic one outside the filter's
//! safe range, the determinant in fixed-width integers, and an adaptive
//! predicate or big integers.

use crate::arith::floor::UNIT_ROUNDOFF;
use crate::arith::number::{abs_cross, cross, diff, dot, lift, Exact, Filtered, Ring};
use glam::DVec3;

/// The static filter's relative bound for orient3d [SHE97] (see
/// [`FaceFilter`]).
const ORIENT3D_BOUND: f64 = (7.0 + 56.0 * UNIT_ROUNDOFF) * UNIT_ROUNDOFF;
/// Sign of `((q − p) × (r − p)) · (x − p)`: positive when `x` lies on the
/// side the normal of the CCW triangle `p, q, r` points to.
///
/// Three stages, cheapest first: a floating-point filter; the exact
/// determinant in fixed-width integers ([`crate::wide`]) when the coordinates
/// span few binades — where frustum corners almost always are, and where
/// their nearly coplanar side faces would otherwise cost an adaptive
/// predicate its slowest stage; else an adaptive predicate or big integers.
#[inline]
pub(crate) fn orient(p: DVec3, q: DVec3, r: DVec3, x: DVec3) -> i8 {
    orient_checked(p, q, r, x, in_safe_range(p) && in_safe_range(q) && in_safe_range(r) && in_safe_range(x))
}

/// Whether every coordinate is 0 or within [2^-200, 2^200].
///
/// NOTE: in that range no product of an orientation determinant can
/// overflow or underflow, so a static error bound and the adaptive
/// predicate are exact. Outside it any of their results may be wrong (an
/// infinity, a false zero, a false sign from underflowed products): there
/// the dynamic filter and big integers decide.
#[inline]
pub(crate) fn in_safe_range(v: DVec3) -> bool {
    v.to_array().iter().all(|c| *c == 0.0 || (c.abs() >= 2f64.powi(-200) && c.abs() <= 2f64.powi(200)))
}

/// [`orient`] with the range test done by the caller (once per frustum).
#[inline]
pub(crate) fn orient_checked(p: DVec3, q: DVec3, r: DVec3, x: DVec3, in_range: bool) -> i8 {
    if in_range {
        if let Some(s) = FaceFilter::new(p, q, r).side(x) {
            return s;
        }
    }
    orient_past_static_filter(p, q, r, x, in_range)
}

/// [`orient`]'s stages after the static filter, for callers that ran the
/// filter themselves (with a face's stored [`FaceFilter`]).
#[inline]
pub(crate) fn orient_past_static_filter(p: DVec3, q: DVec3, r: DVec3, x: DVec3, in_range: bool) -> i8 {
    fn eval<T: Ring>(p: DVec3, q: DVec3, r: DVec3, x: DVec3) -> T {
        dot(&cross(&diff::<T>(q, p), &diff::<T>(r, p)), &diff::<T>(x, p))
    }
    if !in_range {
        if let Some(s) = eval::<Filtered>(p, q, r, x).sign() {
            return s;
        }
    }
    if let Some(s) = crate::arith::wide::orient_det_sign(p.to_array(), q.to_array(), r.to_array(), x.to_array()) {
        return s;
    }
    if !in_range {
        return eval::<Exact>(p, q, r, x).sign();
    }
    // robust::orient3d is positive when x lies *below* the CCW triangle.
    let c = |v: DVec3| robust::Coord3D { x: v.x, y: v.y, z: v.z };
    let d = robust::orient3d(c(p), c(q), c(r), c(x));
    if d > 0.0 {
        -1
    } else if d < 0.0 {
        1
    } else {
        0
    }
}

/// [`orient`]'s static filter, with the work that depends only on the plane
/// `p, q, r` done once (for testing many points against one face).
///
/// NOTE: `(x − p) · ((q − p) × (r − p))` is a 3×3 determinant of rounded
/// differences expanded into 2×2 minors; rounding every difference, product
/// and sum once keeps it within `(7 + 56ε)ε` times the permanent (the same
/// expression with absolute values) of the exact value — Shewchuk's orient3d
/// bound [SHE97], ε = 2^-53. Valid only for inputs in the safe range.
pub(crate) struct FaceFilter {
    pub(crate) p: DVec3,
    pub(crate) normal: DVec3,
    pub(crate) abs_normal: DVec3,
}

impl FaceFilter {
    #[inline]
    pub(crate) fn new(p: DVec3, q: DVec3, r: DVec3) -> FaceFilter {
        let (a, b) = (q - p, r - p);
        FaceFilter { p, normal: a.cross(b), abs_normal: abs_cross(a, b) }
    }

    #[inline]
    pub(crate) fn side(&self, x: DVec3) -> Option<i8> {
        self.side_of_direction(x - self.p)
    }

    /// The sign of `d · ((q − p) × (r − p))`: for a direction `d`, whether
    /// the point at infinity along it lies on the outer side.
    ///
    /// NOTE: with `d` exact (a direction, not a rounded difference) the
    /// determinant carries one rounding fewer, so the bound holds with room.
    #[inline]
    pub(crate) fn side_of_direction(&self, d: DVec3) -> Option<i8> {
        let det = self.normal.dot(d);
        let bound = ORIENT3D_BOUND * self.abs_normal.dot(d.abs());
        if det > bound {
            Some(1)
        } else if -det > bound {
            Some(-1)
        } else {
            None
        }
    }
}

/// Sign of `((q − p) × (r − p)) · dir`: whether the point at infinity in
/// `dir` lies on the outer side of the triangle's plane, for callers that
/// ran the static filter themselves (or whose inputs are outside its range).
#[inline]
pub(crate) fn orient_direction_past_static_filter(p: DVec3, q: DVec3, r: DVec3, dir: DVec3) -> i8 {
    fn eval<T: Ring>(p: DVec3, q: DVec3, r: DVec3, dir: DVec3) -> T {
        dot(&cross(&diff::<T>(q, p), &diff::<T>(r, p)), &lift::<T>(dir))
    }
    // NOTE: fixed-width integers before big integers: a sun parallel to a
    // frustum face lands here on every frame, and big integers allocate.
    match eval::<Filtered>(p, q, r, dir).sign() {
        Some(s) => s,
        None => crate::arith::fixed::direction_side(p, q, r, dir).unwrap_or_else(|| eval::<Exact>(p, q, r, dir).sign()),
    }
}
