//! Planes defined implicitly by their exact inputs.
//!
//! A plane is never stored as rounded coefficients: it remembers the input
//! values that define it, and its coefficients are polynomials in them,
//! evaluated by the predicates in a filtered or exact ring. The halfspace a
//! plane bounds is `a·x + b·y + c·z + d ≤ 0`.

use crate::arith::number::{cross, diff, dot, lift, Ring};
use glam::DVec3;

/// A closed halfspace bounded by an exactly defined plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Plane {
    /// `normal · x + offset ≤ 0`, taking the coefficients as exact numbers.
    Coefficients {
        /// The normal, pointing outside.
        normal: DVec3,
        /// The constant term.
        offset: f64,
    },
    /// The plane through three points; inside is where the points appear
    /// clockwise, i.e. the normal `(q − p) × (r − p)` points outside.
    Points([DVec3; 3]),
    /// The plane through `p`, `q` and the point at infinity in `direction`,
    /// oriented like `Points([p, q, p + t·direction])` for t > 0.
    PointsDirection {
        /// A point of the plane.
        p: DVec3,
        /// Another point of the plane.
        q: DVec3,
        /// A direction in the plane, not along `q − p`.
        direction: DVec3,
    },
    /// `x[axis] ≤ value` when `upper`, else `x[axis] ≥ value`.
    Axis {
        /// 0, 1 or 2 for x, y, z.
        axis: u8,
        /// Whether `value` bounds the coordinate from above.
        upper: bool,
        /// The bound.
        value: f64,
    },
}

impl Plane {
    /// The same plane bounding the opposite closed halfspace.
    pub fn flipped(&self) -> Plane {
        match *self {
            Plane::Coefficients { normal, offset } => Plane::Coefficients { normal: -normal, offset: -offset },
            Plane::Points([p, q, r]) => Plane::Points([p, r, q]),
            Plane::PointsDirection { p, q, direction } => Plane::PointsDirection { p: q, q: p, direction },
            Plane::Axis { axis, upper, value } => Plane::Axis { axis, upper: !upper, value },
        }
    }

    /// Whether every input value is finite.
    pub fn is_finite(&self) -> bool {
        match *self {
            Plane::Coefficients { normal, offset } => normal.is_finite() && offset.is_finite(),
            Plane::Points(p) => p.iter().all(|v| v.is_finite()),
            Plane::PointsDirection { p, q, direction } => p.is_finite() && q.is_finite() && direction.is_finite(),
            Plane::Axis { value, axis, .. } => value.is_finite() && axis < 3,
        }
    }

    /// Largest magnitude among the input values (for output tolerances).
    pub(crate) fn magnitude(&self) -> f64 {
        match *self {
            Plane::Coefficients { .. } => 0.0,
            Plane::Points(p) => p.iter().map(|v| v.abs().max_element()).fold(0.0, f64::max),
            Plane::PointsDirection { p, q, .. } => p.abs().max_element().max(q.abs().max_element()),
            Plane::Axis { value, .. } => value.abs(),
        }
    }

    /// Exact coefficients `[a, b, c, d]` evaluated in a ring.
    pub(crate) fn coefficients<T: Ring>(&self) -> [T; 4] {
        match *self {
            Plane::Coefficients { normal, offset } => [T::lit(normal.x), T::lit(normal.y), T::lit(normal.z), T::lit(offset)],
            Plane::Points([p, q, r]) => {
                let n = cross(&diff::<T>(q, p), &diff::<T>(r, p));
                let d = dot(&n, &lift::<T>(p)).neg();
                let [a, b, c] = n;
                [a, b, c, d]
            }
            Plane::PointsDirection { p, q, direction } => {
                let n = cross(&diff::<T>(q, p), &lift::<T>(direction));
                let d = dot(&n, &lift::<T>(p)).neg();
                let [a, b, c] = n;
                [a, b, c, d]
            }
            Plane::Axis { axis, upper, value } => {
                let (one, off) = if upper { (1.0, -value) } else { (-1.0, value) };
                let mut out = [T::lit(0.0), T::lit(0.0), T::lit(0.0), T::lit(off)];
                out[axis as usize] = T::lit(one);
                out
            }
        }
    }

    /// The plane's value at an explicit point, from differences of inputs
    /// (`n · (x − p)` rather than `n · x + d`, which cancels badly).
    pub(crate) fn eval_at<T: Ring>(&self, x: DVec3) -> T {
        match *self {
            Plane::Coefficients { normal, offset } => dot(&lift::<T>(normal), &lift::<T>(x)).add(&T::lit(offset)),
            Plane::Points([p, q, r]) => dot(&cross(&diff::<T>(q, p), &diff::<T>(r, p)), &diff::<T>(x, p)),
            Plane::PointsDirection { p, q, direction } => dot(&cross(&diff::<T>(q, p), &lift::<T>(direction)), &diff::<T>(x, p)),
            Plane::Axis { axis, upper, value } => {
                let d = T::lit(x[axis as usize]).sub(&T::lit(value));
                if upper {
                    d
                } else {
                    d.neg()
                }
            }
        }
    }
}

/// Homogeneous intersection `(X, Y, Z, W)` of three planes: the point is
/// `(X/W, Y/W, Z/W)`; `W = 0` iff the normals are dependent.
///
/// Cramer's rule on `n_i · x = −d_i`: W = det[n1; n2; n3] and X, Y, Z are
/// the same determinant with one column replaced by `−d`. Written as
/// `W = n1 · (n2 × n3)` and `(X, Y, Z) = −(d1 (n2×n3) + d2 (n3×n1) + d3 (n1×n2))`.
pub(crate) fn intersect3<T: Ring>(p: &[T; 4], q: &[T; 4], r: &[T; 4]) -> [T; 4] {
    let n1 = [p[0].clone(), p[1].clone(), p[2].clone()];
    let n2 = [q[0].clone(), q[1].clone(), q[2].clone()];
    let n3 = [r[0].clone(), r[1].clone(), r[2].clone()];
    let c23 = cross(&n2, &n3);
    let c31 = cross(&n3, &n1);
    let c12 = cross(&n1, &n2);
    let w = dot(&n1, &c23);
    let coord = |k: usize| p[3].mul(&c23[k]).add(&q[3].mul(&c31[k])).add(&r[3].mul(&c12[k])).neg();
    [coord(0), coord(1), coord(2), w]
}

/// `a·X + b·Y + c·Z + d·W` — the side of a homogeneous point, up to sign(W).
#[inline]
pub(crate) fn side_value<T: Ring>(plane: &[T; 4], point: &[T; 4]) -> T {
    plane[0].mul(&point[0]).add(&plane[1].mul(&point[1])).add(&plane[2].mul(&point[2])).add(&plane[3].mul(&point[3]))
}

/// A line known exactly from input values: through `a` along `c − a`, or
/// through `a` along an input direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Line {
    TwoPoints(DVec3, DVec3),
    PointDirection(DVec3, DVec3),
}

impl Line {
    pub(crate) fn anchor(&self) -> DVec3 {
        match *self {
            Line::TwoPoints(a, _) | Line::PointDirection(a, _) => a,
        }
    }

    pub(crate) fn direction<T: Ring>(&self) -> [T; 3] {
        match *self {
            Line::TwoPoints(a, c) => diff::<T>(c, a),
            Line::PointDirection(_, d) => lift::<T>(d),
        }
    }
}

fn axis_unit(k: usize) -> DVec3 {
    let mut u = DVec3::ZERO;
    u[k] = 1.0;
    u
}

impl Plane {
    /// The explicit input points the plane passes through by definition.
    pub(crate) fn points(&self) -> ([DVec3; 3], usize) {
        match *self {
            Plane::Points(p) => (p, 3),
            Plane::PointsDirection { p, q, .. } => ([p, q, q], 2),
            _ => ([DVec3::ZERO; 3], 0),
        }
    }

    /// Whether the plane passes through `x`, when this follows from the
    /// definitions alone (bitwise-equal defining point, or an axis plane);
    /// `None` when it would take arithmetic to tell.
    pub(crate) fn passes_through(&self, x: DVec3) -> Option<bool> {
        match *self {
            Plane::Points([p, q, r]) if p == x || q == x || r == x => Some(true),
            Plane::PointsDirection { p, q, .. } if p == x || q == x => Some(true),
            Plane::Axis { axis, value, .. } => Some(x[axis as usize] == value),
            _ => None,
        }
    }

    /// Whether the plane contains the line, when this follows from the
    /// definitions alone.
    pub(crate) fn contains_line(&self, line: &Line) -> bool {
        match *line {
            Line::TwoPoints(a, c) => self.passes_through(a) == Some(true) && self.passes_through(c) == Some(true),
            Line::PointDirection(a, d) => match *self {
                Plane::PointsDirection { direction, .. } => direction == d && self.passes_through(a) == Some(true),
                Plane::Axis { axis, value, .. } => {
                    let k = axis as usize;
                    d[k] == 0.0 && a[k] == value && d.abs().max_element() > 0.0
                }
                _ => false,
            },
        }
    }

    /// A line both planes contain by definition, if any.
    pub(crate) fn shared_line(&self, other: &Plane) -> Option<Line> {
        if let (Plane::Axis { axis: i, value: vi, .. }, Plane::Axis { axis: j, value: vj, .. }) = (*self, *other) {
            if i == j {
                return None;
            }
            let (i, j) = (i as usize, j as usize);
            let mut a = DVec3::ZERO;
            a[i] = vi;
            a[j] = vj;
            return Some(Line::PointDirection(a, axis_unit(3 - i - j)));
        }
        if let (Plane::PointsDirection { p: p1, q: q1, direction: d1 }, Plane::PointsDirection { p: p2, q: q2, direction: d2 }) =
            (*self, *other)
        {
            if d1 == d2 {
                for a in [p1, q1] {
                    if a == p2 || a == q2 {
                        return Some(Line::PointDirection(a, d1));
                    }
                }
            }
        }
        // Two distinct defining points of one plane that the other plane
        // passes through by definition.
        for (a, b) in [(self, other), (other, self)] {
            let (pts, n) = a.points();
            let mut found = [DVec3::ZERO; 2];
            let mut k = 0;
            for &x in &pts[..n] {
                if b.passes_through(x) == Some(true) && (k == 0 || found[0] != x) {
                    found[k] = x;
                    k += 1;
                    if k == 2 {
                        return Some(Line::TwoPoints(found[0], found[1]));
                    }
                }
            }
        }
        None
    }
}

/// Homogeneous intersection of a line with a plane: for x(t) = a + t·u,
/// P(x) = P(a) + t·(n·u) = 0 gives `(a·(n·u) − u·P(a), n·u)`; `W = n·u`
/// vanishes iff the line is parallel to the plane.
pub(crate) fn line_plane<T: Ring>(line: &Line, plane: &Plane, coef: &[T; 4]) -> [T; 4] {
    let a = lift::<T>(line.anchor());
    let u = line.direction::<T>();
    let n = [coef[0].clone(), coef[1].clone(), coef[2].clone()];
    let nu = dot(&n, &u);
    let pa = plane.eval_at::<T>(line.anchor());
    let coord = |k: usize| a[k].mul(&nu).sub(&u[k].mul(&pa));
    [coord(0), coord(1), coord(2), nu]
}

/// For planes `P` and `Q` sharing `line`, and any point x on `P`:
/// `sign Q(x) = sign(n_Q · m) · sign(m · (x − a))` with `m = u × n_P`.
///
/// Derivation: n_Q ⟂ u and n_P ⟂ u, so n_Q = λ·n_P + μ·m with
/// μ = (n_Q · m)/|m|²; on P, n_P · (x − a) = 0, leaving Q(x) = μ·m·(x − a).
/// The second factor is well conditioned even when P and Q are nearly
/// coplanar, which is exactly when evaluating Q(x) directly is not.
/// Returns `(n_Q · m, [m, −m·a])`: the fold sign and the plane through the
/// line perpendicular to `P`.
pub(crate) fn fold<T: Ring>(line: &Line, p: &[T; 4], q: &[T; 4]) -> (T, [T; 4]) {
    let u = line.direction::<T>();
    let np = [p[0].clone(), p[1].clone(), p[2].clone()];
    let nq = [q[0].clone(), q[1].clone(), q[2].clone()];
    let m = cross(&u, &np);
    let s = dot(&nq, &m);
    let off = dot(&m, &lift::<T>(line.anchor())).neg();
    let [m0, m1, m2] = m;
    (s, [m0, m1, m2, off])
}
