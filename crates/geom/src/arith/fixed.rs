//! Exact signs and points in fixed-width integers: where three exactly
//! defined planes meet, and on which side of a plane a direction points.
//!
//! The float path places a vertex from its planes' exact intersection when
//! the proven bound of its float estimate is too loose for output (planes
//! meeting at small angles), and decides a light direction against a
//! frustum face exactly when the filter cannot (a sun parallel to the face).
//! Big integers can do both for any input, but they allocate and cost tens
//! of thousands of instructions. The values involved almost always span few
//! binades on each axis, and then the whole computation fits a fixed number
//! of 64-bit limbs on the stack.
//!
//! Scaling: the diagonal map `x ↦ (2^-e₀ x₀, 2^-e₁ x₁, 2^-e₂ x₂)` takes the
//! plane through given points (and points at infinity) to the plane through
//! their images, and the planes' meeting point to its image; it multiplies
//! a determinant of three vectors by a positive factor. With `e_a` the
//! exponent of the last mantissa bit of axis `a`'s smallest nonzero value,
//! every image coordinate is an integer, and the scaling is exact in `f64`.
//!
//! Bit budget: with every axis's values spanning at most [`MAX_SPREAD`]
//! binades, scaled values are integers below 2^85, differences below 2^86,
//! normals (two products of differences) below 2^173, offsets (three
//! products of a normal and a value) below 2^260; Cramer's rule then gives
//! `W = n₁·(n₂ × n₃)` below 2^522 and `X, Y, Z` (three products of an
//! offset and a cross product of normals) below 2^609, inside [`LIMBS`]
//! limbs. An overflow is still detected, and declines.

use crate::arith::number::{cross, dot, scale_pow2, Ring};
use crate::arith::plane::{intersect3, Plane};
use glam::{DVec3, DVec4};

/// Largest exponent spread between one axis's values (see the bit budget).
const MAX_SPREAD: i32 = 32;

/// 640 bits: room for the 609-bit numerators.
const LIMBS: usize = 10;

/// The meeting point of three planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Meeting {
    /// The exact point, each coordinate within 3u relative (u = 2^-53).
    Point(DVec3),
    /// The normals are linearly dependent: no single point.
    Dependent,
    /// The inputs do not fit the fixed width (a wide spread of exponents,
    /// a subnormal value, a plane given by coefficients): use big integers.
    Unfit,
}

/// Where the three planes meet (see [`Meeting`]).
pub(crate) fn meet(planes: [&Plane; 3]) -> Meeting {
    let Some(scale) = axis_exponents(planes) else { return Meeting::Unfit };
    let scaled = planes.map(|p| scaled_plane(p, scale));
    let [a, b, c] = scaled.map(|p| p.coefficients::<Fixed>());
    let h = intersect3(&a, &b, &c);
    if h.iter().any(|v| v.overflow) {
        return Meeting::Unfit;
    }
    if h[3].len == 0 {
        return Meeting::Dependent;
    }
    let (w, w_exp) = h[3].approximate();
    // NOTE: X and W are each rounded once (u), their quotient once more;
    // the power-of-two scalings are exact while the result is normal.
    let coord = |k: usize| {
        let (x, x_exp) = h[k].approximate();
        scale_pow2(x / w, x_exp as i64 - w_exp as i64 + scale[k] as i64) + 0.0
    };
    Meeting::Point(DVec3::new(coord(0), coord(1), coord(2)))
}

/// A plane's exact coefficients `[a, b, c, d]` (see [`Plane::coefficients`]),
/// each correctly rounded, as `(m, k)` for the value `m · 2^k`; `None` when
/// its values do not fit.
///
/// NOTE: for the scaling `D = diag(2^-e)`, `(Da) × (Db) = det(D) D⁻¹ (a × b)`,
/// so the scaled plane's normal is `n' = det(D) D⁻¹ n` and its offset
/// `d' = −n'·(Dp) = det(D) d`: normal component `a` takes `e_a − Σe` off
/// its exponent, the offset `−Σe` (an axis plane, with zeros off its axis,
/// has `Σe = e_axis` and comes out the same way).
pub(crate) fn coefficients(plane: &Plane) -> Option<[(f64, i64); 4]> {
    let e = axis_exponents([plane, plane, plane])?;
    let c = scaled_plane(plane, e).coefficients::<Fixed>();
    if c.iter().any(|v| v.overflow) {
        return None;
    }
    let sum = e.iter().map(|&e| e as i64).sum::<i64>();
    Some(std::array::from_fn(|i| {
        let (m, k) = c[i].approximate();
        (m, k as i64 + sum - if i < 3 { e[i] as i64 } else { 0 })
    }))
}

/// Per axis, the exponent `e` of the last mantissa bit of the smallest
/// nonzero value among the planes' defining values; `None` when they do not
/// fit (see the module notes).
fn axis_exponents(planes: [&Plane; 3]) -> Option<[i32; 3]> {
    let mut points = [DVec3::ZERO; 9];
    let mut n = 0;
    for plane in planes {
        let defining: [DVec3; 3] = match *plane {
            Plane::Points(ps) => ps,
            Plane::PointsDirection { p, q, direction } => [p, q, direction],
            // An axis plane's value, on its axis; zeros elsewhere fit any scale.
            Plane::Axis { axis, value, .. } => {
                let mut v = DVec3::ZERO;
                v[axis as usize] = value;
                [v; 3]
            }
            Plane::Coefficients { .. } => return None,
        };
        points[n..n + 3].copy_from_slice(&defining);
        n += 3;
    }
    exponents_of(&points[..n])
}

/// Per axis, the exponent of the last mantissa bit of the smallest nonzero
/// coordinate (0 for an axis of zeros); `None` for a subnormal, or when an
/// axis spans more than [`MAX_SPREAD`] binades.
fn exponents_of(points: &[DVec3]) -> Option<[i32; 3]> {
    let unit_exponent = |bits: u64| (bits >> 52) as i32 - 1075;
    let mut out = [0; 3];
    for (axis, e) in out.iter_mut().enumerate() {
        // Magnitudes as bit patterns (ordered like the values for
        // non-negative floats); zero is left out of the smallest.
        let (mut largest, mut smallest) = (0u64, u64::MAX);
        for p in points {
            let bits = p[axis].to_bits() & !(1 << 63);
            largest = largest.max(bits);
            if bits != 0 {
                smallest = smallest.min(bits);
            }
        }
        if largest == 0 {
            continue;
        }
        // A subnormal has no implicit bit; a scale of 2^-e must be normal.
        if smallest < f64::MIN_POSITIVE.to_bits()
            || unit_exponent(smallest) < -1022
            || unit_exponent(largest) - unit_exponent(smallest) > MAX_SPREAD
        {
            return None;
        }
        *e = unit_exponent(smallest);
    }
    Some(out)
}

/// Factors `2^-e` per axis (normal numbers for the exponents
/// [`exponents_of`] gives).
fn factors(e: [i32; 3]) -> DVec3 {
    DVec3::from_array(e.map(|e| f64::from_bits(((1023 - e) as u64) << 52)))
}

/// The exact sign of `((q − p) × (r − p)) · d`, or `None` when the values
/// do not fit the fixed width (the caller falls back to big integers).
///
/// NOTE: a positive scaling per axis multiplies the determinant by a
/// positive factor: its sign is that of the scaled, integer-valued one.
pub(crate) fn direction_side(p: DVec3, q: DVec3, r: DVec3, d: DVec3) -> Option<i8> {
    let f = factors(exponents_of(&[p, q, r, d])?);
    let lift = |v: DVec3| {
        let v = v * f;
        [Fixed::lit(v.x), Fixed::lit(v.y), Fixed::lit(v.z)]
    };
    let (p, q, r, d) = (lift(p), lift(q), lift(r), lift(d));
    let diff = |a: &[Fixed; 3], b: &[Fixed; 3]| [a[0].sub(&b[0]), a[1].sub(&b[1]), a[2].sub(&b[2])];
    let v = dot(&cross(&diff(&q, &p), &diff(&r, &p)), &d);
    (!v.overflow).then(|| v.sign())
}

/// The plane's image under the scaling by `2^-e` per axis (exact: every
/// image value is an integer below 2^85).
fn scaled_plane(plane: &Plane, e: [i32; 3]) -> Plane {
    let factor = factors(e);
    let s = |p: DVec3| p * factor;
    match *plane {
        Plane::Points([p, q, r]) => Plane::Points([s(p), s(q), s(r)]),
        Plane::PointsDirection { p, q, direction } => Plane::PointsDirection { p: s(p), q: s(q), direction: s(direction) },
        Plane::Axis { axis, upper, value } => Plane::Axis { axis, upper, value: value * factor[axis as usize] },
        Plane::Coefficients { .. } => *plane,
    }
}

/// A signed integer of up to `64 · LIMBS` bits, with an overflow flag that
/// every result inherits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fixed {
    /// Magnitude, least significant limb first; limbs from `len` on are 0.
    mag: [u64; LIMBS],
    len: u8,
    /// Never set for zero.
    negative: bool,
    overflow: bool,
}

impl Fixed {
    const ZERO: Fixed = Fixed { mag: [0; LIMBS], len: 0, negative: false, overflow: false };

    /// −1, 0 or 1.
    fn sign(&self) -> i8 {
        match (self.len, self.negative) {
            (0, _) => 0,
            (_, true) => -1,
            _ => 1,
        }
    }

    fn poisoned() -> Fixed {
        Fixed { overflow: true, ..Fixed::ZERO }
    }

    /// Sets `len` for a magnitude with no nonzero limb from `bound` on.
    fn with_len(mut self, bound: usize) -> Fixed {
        let mut len = bound;
        while len > 0 && self.mag[len - 1] == 0 {
            len -= 1;
        }
        self.len = len as u8;
        self.negative &= len > 0;
        self
    }

    /// `(m, k)` with the value ≈ `m · 2^k`, `m` correctly rounded from the
    /// exact value (0 for zero).
    ///
    /// NOTE: the top two limbs as one `u128`, with any lower bit folded into
    /// its last bit (sticky): 64 or more bits lie below the rounding
    /// position of the conversion, so it rounds as the full value would.
    fn approximate(&self) -> (f64, i32) {
        let n = self.len as usize;
        let m = match n {
            0 => return (0.0, 0),
            1 => (self.mag[0] as u128 as f64, 0),
            _ => {
                let top = (self.mag[n - 1] as u128) << 64 | self.mag[n - 2] as u128;
                let sticky = self.mag[..n - 2].iter().any(|&l| l != 0);
                ((top | sticky as u128) as f64, 64 * (n as i32 - 2))
            }
        };
        (if self.negative { -m.0 } else { m.0 }, m.1)
    }

    fn magnitude_cmp(&self, o: &Fixed) -> std::cmp::Ordering {
        self.len.cmp(&o.len).then_with(|| self.mag[..self.len as usize].iter().rev().cmp(o.mag[..o.len as usize].iter().rev()))
    }

    /// `|self| + |o|` with `negative` as given.
    fn add_magnitudes(&self, o: &Fixed, negative: bool) -> Fixed {
        let mut out = Fixed { negative, overflow: self.overflow || o.overflow, ..Fixed::ZERO };
        let mut carry = 0u64;
        for i in 0..(self.len.max(o.len) as usize) {
            let (s, c1) = self.mag[i].overflowing_add(o.mag[i]);
            let (s, c2) = s.overflowing_add(carry);
            out.mag[i] = s;
            carry = (c1 || c2) as u64;
        }
        let n = self.len.max(o.len) as usize;
        if carry != 0 {
            if n == LIMBS {
                return Fixed::poisoned();
            }
            out.mag[n] = carry;
        }
        out.with_len((n + 1).min(LIMBS))
    }

    /// `|self| − |o|` for `|self| ≥ |o|`, with `negative` as given.
    fn sub_magnitudes(&self, o: &Fixed, negative: bool) -> Fixed {
        let mut out = Fixed { negative, overflow: self.overflow || o.overflow, ..Fixed::ZERO };
        let mut borrow = 0u64;
        for i in 0..self.len as usize {
            let (s, b1) = self.mag[i].overflowing_sub(o.mag[i]);
            let (s, b2) = s.overflowing_sub(borrow);
            out.mag[i] = s;
            borrow = (b1 || b2) as u64;
        }
        out.with_len(self.len as usize)
    }

    /// `self + (−1)^flip · o`.
    fn add_signed(&self, o: &Fixed, flip: bool) -> Fixed {
        let o_negative = o.negative != (flip && o.len > 0);
        if self.negative == o_negative {
            return self.add_magnitudes(o, self.negative);
        }
        match self.magnitude_cmp(o) {
            std::cmp::Ordering::Less => o.sub_magnitudes(self, o_negative),
            _ => self.sub_magnitudes(o, self.negative),
        }
    }
}

impl Ring for Fixed {
    /// An integer-valued `f64` below 2^127 (other values poison the result).
    ///
    /// NOTE: read from the bits, not with `fract` and a cast to `u128`:
    /// without SSE4.1 both are library calls.
    fn lit(x: f64) -> Fixed {
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let frac = bits & ((1 << 52) - 1);
        if biased == 0 {
            // Zero, or a subnormal: no integer.
            return if frac == 0 { Fixed::ZERO } else { Fixed::poisoned() };
        }
        let (mant, e) = (frac | 1 << 52, biased - 1075);
        let m: u128 = if e >= 0 {
            if e > 74 {
                return Fixed::poisoned(); // 2^127 or more, or not finite
            }
            (mant as u128) << e
        } else {
            if e < -52 || mant & ((1 << -e) - 1) != 0 {
                return Fixed::poisoned(); // a fraction
            }
            (mant >> -e) as u128
        };
        let mut out = Fixed { negative: bits >> 63 == 1, ..Fixed::ZERO };
        out.mag[0] = m as u64;
        out.mag[1] = (m >> 64) as u64;
        out.len = if out.mag[1] != 0 { 2 } else { 1 };
        out
    }

    fn add(&self, o: &Fixed) -> Fixed {
        self.add_signed(o, false)
    }

    fn sub(&self, o: &Fixed) -> Fixed {
        self.add_signed(o, true)
    }

    fn mul(&self, o: &Fixed) -> Fixed {
        let (n, m) = (self.len as usize, o.len as usize);
        let overflow = self.overflow || o.overflow;
        if n == 0 || m == 0 {
            return Fixed { overflow, ..Fixed::ZERO };
        }
        if n + m > LIMBS + 1 {
            return Fixed::poisoned();
        }
        let mut wide = [0u64; LIMBS + 1];
        for i in 0..n {
            let mut carry = 0u128;
            for j in 0..m {
                let t = self.mag[i] as u128 * o.mag[j] as u128 + wide[i + j] as u128 + carry;
                wide[i + j] = t as u64;
                carry = t >> 64;
            }
            wide[i + m] = carry as u64;
        }
        if wide[LIMBS] != 0 {
            return Fixed::poisoned();
        }
        let mut out = Fixed { negative: self.negative != o.negative, overflow, ..Fixed::ZERO };
        out.mag.copy_from_slice(&wide[..LIMBS]);
        out.with_len((n + m).min(LIMBS))
    }

    fn neg(&self) -> Fixed {
        Fixed { negative: !self.negative && self.len > 0, ..*self }
    }
}

// NOTE: `Plane::approximate` lives here rather than in `plane.rs`: it falls
// back on this module's exact fixed-width coefficients, and `plane.rs` is
// the lower module (this one builds on its planes).
impl Plane {
    /// Rounded unit normal and offset (`xyz·p + w ≤ 0` inside), for output.
    ///
    /// NOTE: a plane through three nearly collinear points (a frustum edge
    /// and a light at its apex) has a normal that cancels almost completely
    /// in floating point. The filtered coefficients are used only when their
    /// proven error is below 2^-40 of the normal's length; otherwise the
    /// exact coefficients are scaled exactly by one of their non-zero
    /// components before rounding, so the direction is right to an ulp.
    pub fn approximate(&self) -> DVec4 {
        let [a, b, c, d] = self.coefficients::<crate::arith::number::Filtered>();
        let n = DVec3::new(a.v, b.v, c.v);
        let len = n.length();
        let err = a.e + b.e + c.e;
        let scale = len.max(d.v.abs() / (1.0 + self.magnitude()));
        if len > 0.0 && len.is_finite() && err <= len * 2f64.powi(-40) && d.e <= scale * 2f64.powi(-40) * (1.0 + self.magnitude()) {
            return (n / len).extend(d.v / len);
        }
        if let Some(c) = coefficients(self) {
            // NOTE: scaled by the largest normal component's power of two,
            // so every component is at most 2^128 and the length finite;
            // the offset is divided by the length before its scaling, since
            // d/|n| (a distance) stays in range where d alone may not.
            let Some(top) = c[..3].iter().filter(|(m, _)| *m != 0.0).map(|(_, k)| *k).max() else { return DVec4::ZERO };
            let n = DVec3::from_array(std::array::from_fn(|i| scale_pow2(c[i].0, c[i].1 - top)));
            let len = n.length();
            return (n / len).extend(scale_pow2(c[3].0 / len, c[3].1 - top));
        }
        use crate::arith::number::Exact;
        let e = self.coefficients::<Exact>();
        let Some(j) = (0..3).find(|&k| e[k].sign() != 0) else { return DVec4::ZERO };
        let mut r = DVec3::from_array(std::array::from_fn(|k| Exact::ratio_to_f64(&e[k], &e[j])));
        let mut off = Exact::ratio_to_f64(&e[3], &e[j]);
        // Rescale by the largest component to keep the ratios in range.
        let big = (0..3).max_by(|&x, &y| r[x].abs().total_cmp(&r[y].abs())).unwrap_or(j);
        if big != j {
            r = DVec3::from_array(std::array::from_fn(|k| Exact::ratio_to_f64(&e[k], &e[big])));
            off = Exact::ratio_to_f64(&e[3], &e[big]);
        }
        // The ratio's sign may have flipped the normal: restore it.
        let sign = if e[big].sign() < 0 { -1.0 } else { 1.0 };
        let l = r.length();
        (r * (sign / l)).extend(off * sign / l)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::number::{diff, lift, Exact};
    use crate::arith::wide::tests::unit;
    use proptest::prelude::Rng;
    use proptest::test_runner::{RngAlgorithm, TestRng};

    /// The big-integer intersection, correctly rounded.
    fn reference(planes: [&Plane; 3]) -> Option<DVec3> {
        let [a, b, c] = planes.map(|p| p.coefficients::<Exact>());
        let h = intersect3(&a, &b, &c);
        (h[3].sign() != 0).then(|| DVec3::from_array(std::array::from_fn(|k| Exact::ratio_to_f64(&h[k], &h[3]))))
    }

    /// A vector of uniform values in [−1, 1).
    fn random_vec(rng: &mut TestRng) -> DVec3 {
        DVec3::new(unit(rng), unit(rng), unit(rng))
    }

    /// Fixed-width integers against `i128` where both apply.
    #[test]
    fn ring_operations_agree_with_i128() {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        for _ in 0..20000 {
            let a = (rng.next_u64() >> (rng.next_u64() % 64)) as i64 as i128 * if rng.next_u64().is_multiple_of(2) { 1 } else { -1 };
            let b = (rng.next_u64() >> (rng.next_u64() % 64)) as i64 as i128 * if rng.next_u64().is_multiple_of(3) { 1 } else { -1 };
            // Exactly representable operands: below 2^53.
            let (a, b) = (a >> 11, b >> 11);
            let (fa, fb) = (Fixed::lit(a as f64), Fixed::lit(b as f64));
            let value = |f: Fixed| {
                let m = f.mag[0] as i128 | (f.mag[1] as i128) << 64;
                assert!(f.mag[2..].iter().all(|&l| l == 0) && !f.overflow);
                if f.negative {
                    -m
                } else {
                    m
                }
            };
            assert_eq!(value(fa.add(&fb)), a + b);
            assert_eq!(value(fa.sub(&fb)), a - b);
            assert_eq!(value(fa.mul(&fb)), a * b);
            assert_eq!(value(fa.neg()), -a);
            // Zero is never negative.
            assert!(!fa.sub(&fa).negative && fa.sub(&fa).len == 0);
        }
    }

    /// Products past the width poison, and the poison spreads.
    #[test]
    fn overflow_is_detected_and_inherited() {
        let big = Fixed::lit(2f64.powi(100));
        let mut x = big;
        for _ in 0..5 {
            x = x.mul(&big);
        }
        assert!(!x.overflow); // 2^600 fits 640 bits
        let y = x.mul(&big);
        assert!(y.overflow);
        assert!(y.add(&Fixed::lit(1.0)).overflow && Fixed::lit(1.0).sub(&y).overflow);
        assert!(Fixed::lit(0.5).overflow && Fixed::lit(2f64.powi(130)).overflow);
    }

    /// Random planes through rounded points (and axis planes), at scales
    /// 2^-30..2^30: each coordinate within 3u of the correctly rounded one.
    #[test]
    fn meeting_points_agree_with_big_integers() {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let (mut points, mut dependent, mut unfit) = (0, 0, 0);
        for k in 0..4000 {
            let s = 2f64.powi((rng.next_u64() % 61) as i32 - 30);
            let o = random_vec(&mut rng) * s * 4.0;
            let mut pt = || o + random_vec(&mut rng) * s;
            let mut plane = |i: u64| match (k + i) % 4 {
                0 | 1 => Plane::Points([pt(), pt(), pt()]),
                2 => Plane::PointsDirection { p: pt(), q: pt(), direction: pt() - o },
                _ => Plane::Axis { axis: (i % 3) as u8, upper: i.is_multiple_of(2), value: pt().x },
            };
            let mut planes = [plane(0), plane(1), plane(2)];
            if k % 4 == 3 {
                // The first plane again, oriented the other way: dependent
                // normals, W = 0.
                planes[2] = planes[0].flipped();
            }
            let refs = [&planes[0], &planes[1], &planes[2]];
            match (meet(refs), reference(refs)) {
                (Meeting::Point(got), Some(want)) => {
                    for a in 0..3 {
                        assert!((got[a] - want[a]).abs() <= 3.0 * f64::EPSILON * want[a].abs(), "case {k}: {got:?} vs {want:?}");
                    }
                    points += 1;
                }
                (Meeting::Dependent, None) => dependent += 1,
                (Meeting::Unfit, _) => unfit += 1,
                (got, want) => panic!("case {k}: {got:?} vs {want:?}"),
            }
        }
        eprintln!("{points} points, {dependent} dependent, {unfit} unfit");
        assert!(points > 2500 && dependent > 900 && unfit < 200, "{points} points, {dependent} dependent, {unfit} unfit");
    }

    /// A plane's coefficients, each correctly rounded: equal to the big
    /// integers' correctly rounded values, bit for bit.
    #[test]
    fn coefficients_are_correctly_rounded() {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        for k in 0..3000 {
            let s = 2f64.powi((rng.next_u64() % 81) as i32 - 40);
            let o = random_vec(&mut rng) * s * 8.0;
            let mut pt = || o + random_vec(&mut rng) * s;
            let plane = match k % 3 {
                0 => Plane::Points([pt(), pt(), pt()]),
                1 => Plane::PointsDirection { p: pt(), q: pt(), direction: pt() - o },
                _ => Plane::Axis { axis: (k % 5 % 3) as u8, upper: k % 2 == 0, value: pt().y },
            };
            let got = coefficients(&plane).expect("fits");
            let want = plane.coefficients::<Exact>();
            for i in 0..4 {
                let want = Exact::ratio_to_f64(&want[i], &Exact::lit(1.0));
                assert_eq!(scale_pow2(got[i].0, got[i].1), want, "case {k}, coefficient {i}: {plane:?}");
            }
        }
    }

    /// Directions against planes through rounded, nearly coplanar points
    /// (the sign is a rounding accident) and exactly in them.
    #[test]
    fn direction_sides_agree_with_big_integers() {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let (mut zeros, mut signs) = (0, 0);
        for k in 0..6000 {
            let s = 2f64.powi((rng.next_u64() % 41) as i32 - 20);
            let o = random_vec(&mut rng) * s * 8.0;
            let (u, v) = (random_vec(&mut rng), random_vec(&mut rng));
            let (p, q, r) = (o, o + u * s, o + v * s);
            let d = match k % 3 {
                0 => q - p,                                         // in the plane, exactly
                1 => (u * unit(&mut rng) + v * unit(&mut rng)) * s, // in it up to rounding
                _ => random_vec(&mut rng),
            };
            let want = dot(&cross(&diff::<Exact>(q, p), &diff::<Exact>(r, p)), &lift::<Exact>(d)).sign();
            let Some(got) = direction_side(p, q, r, d) else { panic!("case {k} declined") };
            assert_eq!(got, want, "case {k}: {p:?} {q:?} {r:?} {d:?}");
            zeros += (got == 0) as usize;
            signs += (got != 0) as usize;
        }
        assert!(zeros > 1000 && signs > 3000, "{zeros} zeros, {signs} signs");
    }

    /// Exponents too far apart on one axis, subnormals and coefficient
    /// planes are declined rather than answered wrongly.
    #[test]
    fn unfit_inputs_are_declined() {
        let p = Plane::Points([DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 1.0)]);
        let far = Plane::Points([DVec3::new(1e30, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 1.0)]);
        let tiny = Plane::Axis { axis: 0, upper: true, value: 1e-310 };
        let coefficients = Plane::Coefficients { normal: DVec3::X, offset: 1.0 };
        let x = Plane::Axis { axis: 0, upper: true, value: 0.25 };
        let y = Plane::Axis { axis: 1, upper: false, value: 0.5 };
        assert_eq!(meet([&p, &x, &y]), Meeting::Point(DVec3::new(0.25, 0.5, 0.25)));
        assert_eq!(meet([&far, &x, &y]), Meeting::Unfit);
        assert_eq!(meet([&p, &tiny, &y]), Meeting::Unfit);
        assert_eq!(meet([&p, &coefficients, &y]), Meeting::Unfit);
        assert_eq!(meet([&x, &x, &y]), Meeting::Dependent);
    }
}
