//! Exact 3D orientation in fixed-width integer arithmetic.
//!
//! The frustum's side faces are four corners that are coplanar up to
//! rounding, so the fold test `orient3d(a, b, c, d)` is near zero or zero
//! every time, and an adaptive predicate ends in its slowest, fully exact
//! stage (≈ 0.5–1 µs, for the four to six quads of every frustum). Here the
//! same determinant is evaluated exactly in 256-bit integers whenever the
//! twelve coordinates share a narrow exponent range, which is the usual
//! case for frustum corners; otherwise the caller falls back.
//!
//! Bit budget: every coordinate is `m · 2^e` with `|m| < 2^53`. Scaled by
//! `2^-e_min` and with `e − e_min ≤ MAX_SPREAD`, it is an integer below
//! `2^(53 + MAX_SPREAD)` = 2^76; differences stay below 2^77, a 2×2 minor
//! below 2^155, and the determinant (three minor × difference products)
//! below 2^234 — inside a signed 256-bit integer, so arithmetic modulo
//! 2^256 gives the exact value.

/// Largest exponent spread between the twelve coordinates.
const MAX_SPREAD: i32 = 23;

/// A 256-bit two's-complement integer, little-endian limbs. All arithmetic
/// wraps modulo 2^256; callers keep the true values in range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct I256([u64; 4]);

impl I256 {
    fn from_i128(v: i128) -> I256 {
        let ext = if v < 0 { u64::MAX } else { 0 };
        I256([v as u64, (v >> 64) as u64, ext, ext])
    }

    fn add(self, o: I256) -> I256 {
        let mut r = [0u64; 4];
        let mut carry = false;
        for (i, limb) in r.iter_mut().enumerate() {
            let (s, c1) = self.0[i].overflowing_add(o.0[i]);
            let (s, c2) = s.overflowing_add(carry as u64);
            *limb = s;
            carry = c1 || c2;
        }
        I256(r)
    }

    fn neg(self) -> I256 {
        I256(self.0.map(|l| !l)).add(I256([1, 0, 0, 0]))
    }

    fn sub(self, o: I256) -> I256 {
        self.add(o.neg())
    }

    /// The product modulo 2^256 (schoolbook on the limbs that reach it).
    fn mul(self, o: I256) -> I256 {
        let mut r = [0u64; 4];
        for i in 0..4 {
            let mut carry = 0u128;
            for j in 0..4 - i {
                let t = self.0[i] as u128 * o.0[j] as u128 + r[i + j] as u128 + carry;
                r[i + j] = t as u64;
                carry = t >> 64;
            }
        }
        I256(r)
    }

    fn sign(self) -> i8 {
        if self.0[3] >> 63 == 1 {
            -1
        } else if self.0 == [0; 4] {
            0
        } else {
            1
        }
    }
}

/// `(m, e)` with `x = m · 2^e`, `|m| < 2^53`; `None` for zero.
fn split(x: f64) -> Option<(i64, i32)> {
    if x == 0.0 {
        return None;
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 { (frac, -1074) } else { (frac | 1 << 52, exp - 1075) };
    Some((if bits >> 63 == 1 { -m } else { m }, e))
}

/// Sign of `det[q − p, r − p, x − p]` (the orientation of `x` against the
/// plane through `p, q, r`, with the sign convention of a plain
/// determinant), or `None` when the coordinates span too many binades for
/// 256 bits. Inputs must be finite.
pub(crate) fn orient_det_sign(p: [f64; 3], q: [f64; 3], r: [f64; 3], x: [f64; 3]) -> Option<i8> {
    let coords = [p, q, r, x];
    let mut e_min = i32::MAX;
    let mut e_max = i32::MIN;
    for c in coords.iter().flatten() {
        if let Some((_, e)) = split(*c) {
            e_min = e_min.min(e);
            e_max = e_max.max(e);
        }
    }
    if e_min == i32::MAX {
        return Some(0); // all zero
    }
    if e_max - e_min > MAX_SPREAD {
        return None;
    }
    let int = |v: f64| split(v).map_or(0i128, |(m, e)| (m as i128) << (e - e_min));
    let d = |a: [f64; 3]| [0, 1, 2].map(|i| int(a[i]) - int(p[i]));
    let (a, b, c) = (d(q), d(r), d(x));
    let w = |v: i128| I256::from_i128(v);
    let minor = |i: usize, j: usize| w(b[i]).mul(w(c[j])).sub(w(b[j]).mul(w(c[i])));
    let det = w(a[0]).mul(minor(1, 2)).sub(w(a[1]).mul(minor(0, 2))).add(w(a[2]).mul(minor(0, 1)));
    Some(det.sign())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::Rng;
    use proptest::test_runner::{RngAlgorithm, TestRng};

    /// The same determinant with big integers.
    fn reference(p: [f64; 3], q: [f64; 3], r: [f64; 3], x: [f64; 3]) -> i8 {
        use num_bigint::BigInt;
        use num_traits::Signed;
        let e_min = [p, q, r, x].iter().flatten().filter_map(|v| split(*v)).map(|(_, e)| e).min().unwrap_or(0);
        let int = |v: f64| split(v).map_or(BigInt::from(0), |(m, e)| BigInt::from(m) << (e - e_min) as usize);
        let d = |a: [f64; 3]| [0, 1, 2].map(|i| int(a[i]) - int(p[i]));
        let (a, b, c) = (d(q), d(r), d(x));
        let det = &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0]) + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
        if det.is_positive() {
            1
        } else if det.is_negative() {
            -1
        } else {
            0
        }
    }

    /// A uniform value in [−1, 1) from the test suite's deterministic generator.
    fn unit(rng: &mut TestRng) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    #[test]
    fn wide_arithmetic_wraps_like_integers() {
        let a = I256::from_i128(-(1i128 << 120));
        let b = I256::from_i128(3 << 100);
        // −2^120 · 3·2^100 = −3·2^220: the top limb carries it.
        let p = a.mul(b);
        assert_eq!(p.sign(), -1);
        assert_eq!(p.neg().0, [0, 0, 0, 3 << 28]);
        assert_eq!(a.sub(a).sign(), 0);
        assert_eq!(I256::from_i128(-1).add(I256::from_i128(1)).0, [0; 4]);
    }

    #[test]
    fn agrees_with_big_integers_on_near_coplanar_points() {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let (mut decided, mut zeros) = (0, 0);
        for k in 0..20000 {
            // Points on a random plane, rounded, so the exact sign is a
            // rounding-level accident; each case picks a scale of
            // 2^-20..2^20 and an offset, to vary the binades.
            let s = 2f64.powi((rng.next_u64() % 41) as i32 - 20);
            let o = [0; 3].map(|_| unit(&mut rng) * s * 8.0);
            let (u, v) = ([0; 3].map(|_| unit(&mut rng)), [0; 3].map(|_| unit(&mut rng)));
            let pt = |a: f64, b: f64| [0, 1, 2].map(|i| o[i] + (a * u[i] + b * v[i]) * s);
            let (p, q, r) = (pt(0.0, 0.0), pt(1.0, 0.0), pt(0.0, 1.0));
            let x = if k % 3 == 0 { pt(1.0, 1.0) } else { let (a, b) = (unit(&mut rng), unit(&mut rng)); pt(a, b) };
            // Exactly coplanar too: a point repeated, or the midpoint of two.
            let x = if k % 10 == 0 { q } else if k % 10 == 1 { [0, 1, 2].map(|i| (p[i] + q[i]) * 0.5) } else { x };
            let Some(got) = orient_det_sign(p, q, r, x) else { continue };
            assert_eq!(got, reference(p, q, r, x), "case {k}: {p:?} {q:?} {r:?} {x:?}");
            decided += 1;
            zeros += usize::from(got == 0);
        }
        assert!(decided > 15000 && zeros > 1000, "decided {decided}, zeros {zeros}");
    }

    #[test]
    fn declines_wide_exponent_ranges() {
        let p = [0.0, 0.0, 0.0];
        assert_eq!(orient_det_sign(p, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e-30]), None);
        assert_eq!(orient_det_sign(p, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e-3]), Some(1));
        assert_eq!(orient_det_sign(p, p, p, p), Some(0));
    }
}
