//! The exact side of a point with respect to a plane.

use crate::arith::number::{Exact, Filtered};
use crate::arith::plane::Plane;
use crate::predicates::orient::orient;
use glam::DVec3;

/// Exact side of an explicit point w.r.t. a plane: −1 inside, 0 on, +1 outside.
#[inline]
pub(crate) fn point_side(plane: &Plane, x: DVec3) -> i8 {
    // NOTE: for a plane through three points this is an orientation, whose
    // own static filter is as tight as the dynamic one and cheaper, and
    // whose exact stages are far cheaper than big integers on the
    // near-coplanar corners of a frustum side.
    if let Plane::Points([p, q, r]) = *plane {
        return orient(p, q, r, x);
    }
    match plane.eval_at::<Filtered>(x).sign() {
        Some(s) => s,
        None => plane.eval_at::<Exact>(x).sign(),
    }
}
