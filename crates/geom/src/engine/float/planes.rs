//! Planes of the fast path with proven error bounds on their side values,
//! and certified line–plane crossings.

use crate::arith::floor::{BOUND_SLACK as SLACK, UNDERFLOW_FLOOR as FLOOR, UNIT_ROUNDOFF as U};
use crate::arith::number::abs_cross;
use crate::arith::plane::Plane;
use crate::input::frustum::Frustum;
use glam::{DVec3, DVec4};

#[derive(Clone, Copy, Debug)]
pub(super) struct FloatPlane {
    pub(super) src: Plane,
    /// `x[axis] ≤ value` (or `≥`) when `axis < 3`; a general plane otherwise.
    pub(super) axis: u8,
    pub(super) upper: bool,
    pub(super) value: f64,
    /// `n · (x − anchor) + offset ≤ 0` inside, with `|ñ − n| ≤ en` per component.
    pub(super) n: DVec3,
    pub(super) en: DVec3,
    pub(super) anchor: DVec3,
    pub(super) offset: f64,
    /// Input points the plane passes through by definition.
    pub(super) through: u32,
}

impl FloatPlane {
    // NOTE: inlined so that callers build the ~250-byte plane in its slot
    // instead of copying it out of a temporary.
    #[inline(always)]
    pub(super) fn new(src: Plane, through: u32) -> FloatPlane {
        let general = |n: DVec3, en: DVec3, anchor: DVec3, offset: f64| FloatPlane::general(src, n, en, anchor, offset, through);
        match src {
            Plane::Axis { axis, upper, value } => FloatPlane { through, ..FloatPlane::axis(axis, upper, value) },
            Plane::Points([p, q, r]) => {
                let (a, b) = (q - p, r - p);
                FloatPlane::through_points(src, p, a.cross(b), abs_cross(a, b), through)
            }
            // NOTE: as in `through_points`, with an exact direction: 3u.
            Plane::PointsDirection { p, q, direction } => {
                let a = q - p;
                general(a.cross(direction), abs_cross(a, direction) * (3.0 * U * SLACK), p, 0.0)
            }
            Plane::Coefficients { normal, offset } => general(normal, DVec3::ZERO, DVec3::ZERO, offset),
        }
    }

    /// The plane `src` = `Plane::Points([p, q, r])` from its cross product
    /// `(q − p) × (r − p)` and the same with absolute values (computed here,
    /// or stored by the frustum that validated the face).
    ///
    /// NOTE: a cross-product component is ã·b̃ − ã′·b̃′ over rounded
    /// differences: each product is off by 2u (its two differences) plus u
    /// (its rounding), the subtraction by u of the result, so
    /// |ñ − n| ≤ 4u·(|ã·b̃| + |ã′·b̃′|).
    #[inline(always)]
    pub(super) fn through_points(src: Plane, p: DVec3, cross: DVec3, abs_cross: DVec3, through: u32) -> FloatPlane {
        FloatPlane::general(src, cross, abs_cross * (4.0 * U * SLACK), p, 0.0, through)
    }

    /// The plane of face `f` of a validated frustum, from the cross product
    /// its validation computed.
    #[inline(always)]
    pub(super) fn of_face(frustum: &Frustum, f: usize, through: u32) -> FloatPlane {
        let (n, abs_n) = frustum.face_normal(f);
        let p = frustum.corners()[frustum.face(f)[0] as usize];
        FloatPlane::through_points(frustum.face_plane(f), p, n, abs_n, through)
    }

    /// `x[axis] ≤ value` (`upper`) or `≥ value`: exact, through no input point.
    pub(super) fn axis(axis: u8, upper: bool, value: f64) -> FloatPlane {
        let mut n = DVec3::ZERO;
        *coord_mut(&mut n, axis as usize) = if upper { 1.0 } else { -1.0 };
        FloatPlane { axis, upper, value, ..FloatPlane::general(Plane::Axis { axis, upper, value }, n, DVec3::ZERO, DVec3::ZERO, 0.0, 0) }
    }

    /// `n · (x − anchor) + offset` with `|ñ − n| ≤ en`.
    #[inline(always)]
    pub(super) fn general(src: Plane, n: DVec3, en: DVec3, anchor: DVec3, offset: f64, through: u32) -> FloatPlane {
        FloatPlane { src, axis: 3, upper: false, value: 0.0, n, en, anchor, offset, through }
    }

    /// Side value at a point known within `r`, and a bound on its error.
    #[inline]
    pub(super) fn side(&self, x: DVec3, r: DVec3) -> (f64, f64) {
        if self.axis < 3 {
            let k = self.axis as usize;
            let d = coord(&x, k) - self.value;
            let s = if self.upper { d } else { -d };
            // NOTE: with an exact coordinate (r = 0) the rounded difference
            // has the exact sign, zero included: the bound is 2u·|s| < |s|.
            return (s, coord(&r, k) * SLACK + 2.0 * U * s.abs());
        }
        self.general_side(x, r, &self.side_bound())
    }

    /// The coefficients of a general plane's side bound.
    ///
    /// NOTE: |s̃ − s| ≤ 6u(|ñ|·|w̃| + |offset|) (the dot product, the
    /// difference w̃ = x̃ − anchor and the offset's addition) + en·|w̃|
    /// (the normal's error) + (|ñ| + en)·r (the point's error). Computed
    /// where a plane is tested rather than stored with it: most planes
    /// (the hull's, in a body without a spot light) are never tested.
    #[inline]
    pub(super) fn side_bound(&self) -> SideBound {
        let na = self.n.abs();
        SideBound { w: na * (6.0 * U) + self.en, r: na + self.en, offset: 6.0 * U * self.offset.abs() }
    }

    /// [`FloatPlane::side`] of a general plane, its bound's coefficients
    /// given (for testing many points against one plane).
    #[inline]
    pub(super) fn general_side(&self, x: DVec3, r: DVec3, b: &SideBound) -> (f64, f64) {
        let w = x - self.anchor;
        let s = self.n.dot(w) + self.offset;
        let e = (b.w.dot(w.abs()) + b.r.dot(r) + b.offset) * SLACK + FLOOR;
        (s, e)
    }

    /// Rounded unit normal and offset for output.
    pub(super) fn approximate(&self) -> DVec4 {
        if self.axis < 3 {
            let s = if self.upper { 1.0 } else { -1.0 };
            return self.n.extend(-s * self.value);
        }
        // NOTE: one division for the four coefficients: the output plane is
        // a rounded one, and a product by the reciprocal is one rounding more
        // (an ulp), against four divisions' latency per face.
        let len = self.n.length();
        let inv = 1.0 / len;
        if len > 0.0 && len.is_finite() && inv.is_finite() && self.en.max_element() <= len * 2f64.powi(-40) {
            return (self.n * inv).extend((self.offset - self.n.dot(self.anchor)) * inv);
        }
        self.src.approximate()
    }
}

/// A general plane's side bound `e = w·|x − anchor| + r·rad + offset`
/// (see [`FloatPlane::side_bound`]).
pub(super) struct SideBound {
    pub(super) w: DVec3,
    pub(super) r: DVec3,
    pub(super) offset: f64,
}

/// A plane through the line `a`–`c` of plane `p`, perpendicular to `p`:
/// with `p` it defines that line well even where another plane through the
/// line meets `p` at a tiny angle.
#[inline]
pub(super) fn line_proxy(p: &FloatPlane, a: DVec3, c: DVec3) -> FloatPlane {
    // NOTE: m = (c − a) × n_p; its error comes from the rounded difference,
    // from n_p's error, and from the cross product's own rounding.
    let e = c - a;
    let en = abs_cross(e, p.en) * SLACK + abs_cross(e, p.n) * (5.0 * U);
    FloatPlane::general(Plane::Coefficients { normal: DVec3::ZERO, offset: 0.0 }, e.cross(p.n), en, a, 0.0, 0)
}

/// Coordinate `axis` (0, 1 or 2) of `p`, and its place.
///
/// NOTE: glam's `p[axis]` is a three-way match on every access, in the
/// per-vertex loops too; as an array index it is one load (the `min` lets
/// the bounds check go).
#[inline(always)]
pub(super) fn coord(p: &DVec3, axis: usize) -> f64 {
    p.as_ref()[axis.min(2)]
}

#[inline(always)]
pub(super) fn coord_mut(p: &mut DVec3, axis: usize) -> &mut f64 {
    &mut p.as_mut()[axis.min(2)]
}

/// Where the line `a + t·d` meets a plane: `a` exact, `d` exact or the
/// rounded difference of two exact points (`d_rounded`).
#[inline]
pub(super) fn line_crossing(a: DVec3, d: DVec3, d_rounded: bool, p: &FloatPlane) -> Option<(DVec3, DVec3)> {
    if p.axis < 3 {
        let axis = p.axis as usize;
        if coord(&d, axis) == 0.0 {
            return None;
        }
        // NOTE: t = (value − a_k)/d_k carries at most three roundings (the
        // two differences and the quotient), so |t̃ − t| ≤ 3u|t| (plus second
        // order); x_m = a_m + t·d_m adds two more of |t·d_m| and one of |x_m|.
        let t = (p.value - coord(&a, axis)) / coord(&d, axis);
        let td = d * t;
        let mut x = a + td;
        *coord_mut(&mut x, axis) = p.value;
        let mut rad = exact_where_still((td.abs() * (6.0 * U) + x.abs() * (2.0 * U)) * SLACK + DVec3::splat(1e-300), d);
        *coord_mut(&mut rad, axis) = 0.0;
        // NOTE: `a` is finite, so a finite `x` has a finite `td`, and then
        // `rad` is finite too.
        return x.is_finite().then_some((x, rad));
    }
    // NOTE: t = −P(a)/(n·d). P(a) is known within e_q (the side bound at an
    // exact point); n·d within e_δ = en·|d| + 4u·|n|·|d| (+2u|n|·|d| when d
    // is a rounded difference). Then |t̃ − t| ≤ (e_q + |t̃|·e_δ)/(|δ̃| − e_δ)
    // + 2u|t̃|, and x = a + t·d adds |d|·|t̃ − t| and the final roundings.
    let (q, eq) = p.side(a, DVec3::ZERO);
    let delta = p.n.dot(d);
    let (na, da) = (p.n.abs(), d.abs());
    let ed = (p.en.dot(da) + na.dot(da) * if d_rounded { 6.0 * U } else { 4.0 * U }) * SLACK;
    if !(delta.abs() > 2.0 * ed) {
        return None;
    }
    let t = -q / delta;
    let et = (eq + t.abs() * ed) / (delta.abs() - ed) + 2.0 * U * t.abs();
    let td = d * t;
    let x = a + td;
    let rad = exact_where_still((da * et * (1.0 + 4.0 * U) + td.abs() * (4.0 * U) + x.abs() * (2.0 * U)) * SLACK + DVec3::splat(1e-300), d);
    (x.is_finite() && rad.is_finite()).then_some((x, rad))
}

/// Zero radius on the axes the line does not move along.
///
/// NOTE: a zero component of `d` is exact (a rounded difference is zero only
/// when the two coordinates are equal), so there `x = a + t·0 = a` exactly.
#[inline]
pub(super) fn exact_where_still(rad: DVec3, d: DVec3) -> DVec3 {
    DVec3::select(d.cmpeq(DVec3::ZERO), DVec3::ZERO, rad)
}
