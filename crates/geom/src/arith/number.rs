//! Numbers for exact predicates.
//!
//! Every predicate is written once, generic over [`Ring`], and evaluated
//! twice at most:
//!
//! 1. with [`Filtered`]: an `f64` value together with a rigorous bound on
//!    its distance from the exact real value. If the bound proves the sign,
//!    we are done — this is the common path and costs a few flops per op;
//! 2. otherwise with [`Exact`]: a dyadic number `m·2^e` with a big-integer
//!    mantissa. Every `f64` is dyadic and dyadics are closed under `+ − ×`,
//!    so the polynomial predicates below are evaluated without any rounding.
//!
//! This is the classic "floating-point filter + exact fallback" scheme; the
//! filter is semi-dynamic (the bound is propagated with the value) so it
//! also covers constructed points that are never rounded (intersections of
//! three planes kept as homogeneous coordinates).

use crate::arith::floor::{BOUND_SLACK, UNDERFLOW_FLOOR, UNIT_ROUNDOFF};
use glam::DVec3;
use num_bigint::{BigInt, Sign};
use num_traits::{ToPrimitive, Zero};

/// The arithmetic a predicate needs.
pub(crate) trait Ring: Clone {
    fn lit(x: f64) -> Self;
    fn add(&self, o: &Self) -> Self;
    fn sub(&self, o: &Self) -> Self;
    fn mul(&self, o: &Self) -> Self;
    fn neg(&self) -> Self;
}

/// An f64 value `v` with `|exact − v| ≤ e`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Filtered {
    pub v: f64,
    pub e: f64,
}

impl Filtered {
    /// The sign of the exact value if the bound proves it.
    #[inline]
    pub fn sign(self) -> Option<i8> {
        if self.e == 0.0 && self.v.is_finite() {
            // Every step was exact (e.g. differences of equal inputs).
            return Some(if self.v > 0.0 {
                1
            } else if self.v < 0.0 {
                -1
            } else {
                0
            });
        }
        let bound = self.e * BOUND_SLACK + UNDERFLOW_FLOOR;
        // NaN or infinity in either part fails both comparisons.
        if self.v > bound && bound.is_finite() {
            Some(1)
        } else if self.v < -bound && bound.is_finite() {
            Some(-1)
        } else {
            None
        }
    }
}

impl Ring for Filtered {
    #[inline]
    fn lit(x: f64) -> Self {
        Filtered { v: x, e: 0.0 }
    }
    #[inline]
    fn add(&self, o: &Self) -> Self {
        let v = self.v + o.v;
        // |fl(a+b) − (a+b)| ≤ u·|fl(a+b)|; subnormal sums are exact.
        Filtered { v, e: self.e + o.e + UNIT_ROUNDOFF * v.abs() }
    }
    #[inline]
    fn sub(&self, o: &Self) -> Self {
        let v = self.v - o.v;
        Filtered { v, e: self.e + o.e + UNIT_ROUNDOFF * v.abs() }
    }
    #[inline]
    fn mul(&self, o: &Self) -> Self {
        let v = self.v * o.v;
        // (a+δa)(b+δb) = ab + a·δb + b·δa + δa·δb, plus the rounding of ab.
        let mut e = self.v.abs() * o.e + o.v.abs() * self.e + self.e * o.e + UNIT_ROUNDOFF * v.abs();
        // NOTE: below the normal range the relative bound fails (a product can
        // underflow to zero); an absolute term covers it. Exact zero factors
        // keep the product exact.
        let exact_zero = (self.v == 0.0 && self.e == 0.0) || (o.v == 0.0 && o.e == 0.0);
        if v.abs() <= f64::MIN_POSITIVE && !exact_zero {
            e += f64::MIN_POSITIVE;
        }
        Filtered { v, e }
    }
    #[inline]
    fn neg(&self) -> Self {
        Filtered { v: -self.v, e: self.e }
    }
}

/// An exact dyadic rational `m · 2^e`.
#[derive(Clone, Debug)]
pub(crate) struct Exact {
    m: BigInt,
    e: i64,
}

impl Exact {
    pub fn sign(&self) -> i8 {
        match self.m.sign() {
            Sign::Minus => -1,
            Sign::NoSign => 0,
            Sign::Plus => 1,
        }
    }

    fn aligned(a: &Exact, b: &Exact) -> (BigInt, BigInt, i64) {
        if a.m.is_zero() {
            return (BigInt::zero(), b.m.clone(), b.e);
        }
        if b.m.is_zero() {
            return (a.m.clone(), BigInt::zero(), a.e);
        }
        let e = a.e.min(b.e);
        (&a.m << (a.e - e) as usize, &b.m << (b.e - e) as usize, e)
    }

    /// `num / den` rounded to an f64 within one ulp (two roundings of a
    /// 64+-bit quotient); `den` must be non-zero.
    pub fn ratio_to_f64(num: &Exact, den: &Exact) -> f64 {
        if num.m.is_zero() {
            return 0.0;
        }
        let negative = (num.sign() < 0) != (den.sign() < 0);
        let n = num.m.magnitude();
        let d = den.m.magnitude();
        // Shift so the integer quotient carries at least 66 significant bits.
        let shift = (d.bits() as i64 - n.bits() as i64 + 66).max(0);
        let q = (n << shift as usize) / d;
        let exp = num.e - den.e - shift;
        let top = q.bits() as i64;
        // Keep 64 bits of q, folding the rest into a sticky bit so the
        // conversion below rounds the way the full quotient would.
        let drop = (top - 64).max(0);
        let mut head = (&q >> drop as usize).to_u64().unwrap_or(u64::MAX);
        if drop > 0 && (&q & ((num_bigint::BigUint::from(1u8) << drop as usize) - 1u8)) != Zero::zero() {
            head |= 1;
        }
        let mag = scale_pow2(head as f64, exp + drop);
        if negative {
            -mag
        } else {
            mag
        }
    }
}

/// `x · 2^k` without intermediate overflow or premature underflow.
pub(crate) fn scale_pow2(mut x: f64, mut k: i64) -> f64 {
    while k > 1000 {
        x *= 2f64.powi(1000);
        k -= 1000;
        if x.is_infinite() {
            return x;
        }
    }
    while k < -1000 {
        x *= 2f64.powi(-1000);
        k += 1000;
        if x == 0.0 {
            return x;
        }
    }
    x * 2f64.powi(k as i32)
}

impl Ring for Exact {
    fn lit(x: f64) -> Self {
        debug_assert!(x.is_finite());
        if x == 0.0 {
            return Exact { m: BigInt::zero(), e: 0 };
        }
        let bits = x.to_bits();
        let negative = bits >> 63 == 1;
        let biased = ((bits >> 52) & 0x7ff) as i64;
        let frac = bits & ((1u64 << 52) - 1);
        let (mant, e) = if biased == 0 { (frac, -1074) } else { (frac | (1u64 << 52), biased - 1075) };
        let m = BigInt::from(mant);
        Exact { m: if negative { -m } else { m }, e }
    }
    fn add(&self, o: &Self) -> Self {
        let (a, b, e) = Exact::aligned(self, o);
        Exact { m: a + b, e }
    }
    fn sub(&self, o: &Self) -> Self {
        let (a, b, e) = Exact::aligned(self, o);
        Exact { m: a - b, e }
    }
    fn mul(&self, o: &Self) -> Self {
        Exact { m: &self.m * &o.m, e: self.e + o.e }
    }
    fn neg(&self) -> Self {
        Exact { m: -&self.m, e: self.e }
    }
}

/// Small vector helpers over any ring.
#[inline]
pub(crate) fn cross<T: Ring>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [a[1].mul(&b[2]).sub(&a[2].mul(&b[1])), a[2].mul(&b[0]).sub(&a[0].mul(&b[2])), a[0].mul(&b[1]).sub(&a[1].mul(&b[0]))]
}

#[inline]
pub(crate) fn dot<T: Ring>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0].mul(&b[0]).add(&a[1].mul(&b[1])).add(&a[2].mul(&b[2]))
}

#[inline]
pub(crate) fn lift<T: Ring>(p: glam::DVec3) -> [T; 3] {
    [T::lit(p.x), T::lit(p.y), T::lit(p.z)]
}

#[inline]
pub(crate) fn diff<T: Ring>(a: glam::DVec3, b: glam::DVec3) -> [T; 3] {
    [T::lit(a.x).sub(&T::lit(b.x)), T::lit(a.y).sub(&T::lit(b.y)), T::lit(a.z).sub(&T::lit(b.z))]
}

/// `|a| × |b|` with every product added: bounds the rounding of `a × b`.
pub(crate) fn abs_cross(a: DVec3, b: DVec3) -> DVec3 {
    let (a, b) = (a.abs(), b.abs());
    DVec3::new(a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z, a.x * b.y + a.y * b.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact_of(x: f64) -> Exact {
        Exact::lit(x)
    }

    #[test]
    fn exact_round_trips_every_kind_of_f64() {
        for x in [1.0, -3.5, 1e-310, -5e-324, 1.7976931348623157e308, 0.1, 123456.789] {
            let one = exact_of(1.0);
            assert_eq!(Exact::ratio_to_f64(&exact_of(x), &one), x, "{x}");
        }
    }

    #[test]
    fn exact_arithmetic_cancels_where_floats_do_not() {
        // (1e16 + 1) − 1e16 is 0 in f64 but 1 exactly.
        let a = exact_of(1e16).add(&exact_of(1.0)).sub(&exact_of(1e16));
        assert_eq!(a.sign(), 1);
        let f = Filtered::lit(1e16).add(&Filtered::lit(1.0)).sub(&Filtered::lit(1e16));
        assert_eq!(f.sign(), None, "the filter must not claim a sign it cannot prove");
    }

    #[test]
    fn ratio_rounds_to_nearest() {
        let third = Exact::ratio_to_f64(&exact_of(1.0), &exact_of(3.0));
        assert_eq!(third, 1.0 / 3.0);
        let big = Exact::ratio_to_f64(&exact_of(2f64.powi(900)).mul(&exact_of(2f64.powi(900))), &exact_of(2f64.powi(800)));
        assert_eq!(big, 2f64.powi(1000));
    }

    #[test]
    fn filter_proves_clear_signs() {
        let x = Filtered::lit(3.0).mul(&Filtered::lit(7.0)).sub(&Filtered::lit(20.0));
        assert_eq!(x.sign(), Some(1));
        let z = Filtered::lit(0.1).sub(&Filtered::lit(0.1));
        assert_eq!(z.sign(), Some(0));
    }
}
