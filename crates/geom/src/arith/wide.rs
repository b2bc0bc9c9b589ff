//! Exact 3D orientation in fixed-width integer arithmetic.
//!
//! The frustum's side faces are four corners that are coplanar up to
//! rounding, so the fold test `orient3d(a, b, c, d)` is near zero or zero
//! every time, and an adaptive predicate ends in its slowest, fully exact
//! stage, for the four to six quads of every frustum. Here the same
//! determinant is evaluated exactly in integers whenever each axis's four
//! coordinates share a narrow exponent range, which is the usual case for
//! frustum corners; otherwise the caller falls back.
//!
//! Scaling: the determinant of the differences is linear in each axis's
//! column, so every axis is scaled by its own power of two (its smallest
//! exponent): the sign is unchanged, and only the spread within an axis
//! counts.
//!
//! Bit budget: every coordinate is `m · 2^e` with `|m| < 2^53`. Scaled by
//! its axis's `2^-e_min` (in floating point: a power of two, exact) and
//! with `e − e_min ≤ MAX_SPREAD`, it is an integer below
//! `2^(53 + MAX_SPREAD)` = 2^76; differences stay below 2^77, a 2×2
//! minor below 2^155 and the determinant below 2^234. Products are formed
//! from 39-bit limbs so that every partial sum fits an `i128`, and the sign
//! is read after carrying the low limbs upward. With a spread of at most
//! [`NARROW_SPREAD`] (the common case) the coordinates fit an `i64` and
//! the minors an `i128`, and a shorter path suffices.

/// Largest exponent spread between one axis's four coordinates.
const MAX_SPREAD: i32 = 23;

/// Spread up to which the short path applies: coordinates below 2^61,
/// differences below 2^62, products and minors below 2^125.
const NARROW_SPREAD: i32 = 8;

/// Limb width of the split products: a difference below 2^77 splits into
/// a signed high part below 2^38 and a low part in [0, 2^39).
const LIMB: u32 = 39;

/// `d = hi · 2^39 + lo` with `0 ≤ lo < 2^39` (arithmetic shift).
#[inline]
fn limbs(d: i128) -> (i64, i64) {
    let hi = d >> LIMB;
    // NOTE: both parts fit an i64, so their products are single 64×64→128
    // multiplications.
    (hi as i64, (d - (hi << LIMB)) as i64)
}

/// The exact product of two limbs.
#[inline]
fn wide_mul(x: i64, y: i64) -> i128 {
    x as i128 * y as i128
}

/// A 2×2 minor `x0·y1 − x1·y0` of differences below 2^77, exactly, as
/// `(a, b)` with value `a · 2^78 + b` and `0 ≤ b < 2^78`.
///
/// NOTE: each product of split differences is `hi·hi·2^78 + (hi·lo + lo·hi)·2^39
/// + lo·lo`; the high parts stay below 2^77 and the rest below 2^118, so
/// every partial sum fits an `i128` with room, and one carry normalises `b`.
#[inline]
fn minor(x0: i128, y1: i128, x1: i128, y0: i128) -> (i128, i128) {
    let product = |x: i128, y: i128| {
        let ((xh, xl), (yh, yl)) = (limbs(x), limbs(y));
        (wide_mul(xh, yh), ((wide_mul(xh, yl) + wide_mul(xl, yh)) << LIMB) + wide_mul(xl, yl))
    };
    let ((a1, b1), (a0, b0)) = (product(x0, y1), product(x1, y0));
    let (a, b) = (a1 - a0, b1 - b0);
    let carry = b >> (2 * LIMB);
    (a + carry, b - (carry << (2 * LIMB)))
}

/// Sign of `det[q − p, r − p, x − p]` (the orientation of `x` against the
/// plane through `p, q, r`, with the sign convention of a plain
/// determinant), or `None` when an axis's coordinates span too many
/// binades or reach below the normal range. Inputs must be finite.
pub(crate) fn orient_det_sign(p: [f64; 3], q: [f64; 3], r: [f64; 3], x: [f64; 3]) -> Option<i8> {
    let points = [p, q, r, x];
    let mut scale = [0.0f64; 3];
    let mut narrow = true;
    for (axis, scale) in scale.iter_mut().enumerate() {
        // NOTE: only the largest and the smallest nonzero magnitude of the
        // axis are decomposed. Scaled by 2^-e (e: the smallest one's last
        // mantissa bit) every coordinate of the axis is an integer, since
        // larger magnitudes have their last bit at or above it; the scaling
        // is exact, and so is the conversion of those integers below.
        // NOTE: magnitudes compared as bit patterns (ordered like the values
        // for non-negative floats; inputs are finite), with zero mapped past
        // every other so that it is never the smallest: integer min and max,
        // no branches.
        let (mut largest, mut smallest) = (0u64, u64::MAX);
        for point in &points {
            let bits = point[axis].to_bits() & !(1 << 63);
            largest = largest.max(bits);
            smallest = smallest.min(if bits == 0 { u64::MAX } else { bits });
        }
        if largest == 0 {
            // Every difference has a zero in this column.
            return Some(0);
        }
        // Exponent of the last mantissa bit; the scale 2^-e must be a
        // normal f64 (e ≥ −1022), and subnormals are declined.
        let unit_exponent = |bits: u64| (bits >> 52) as i32 - 1075;
        let e = unit_exponent(smallest);
        if smallest < f64::MIN_POSITIVE.to_bits() || e < -1022 {
            return None;
        }
        let spread = unit_exponent(largest) - e;
        if spread > MAX_SPREAD {
            return None;
        }
        narrow &= spread <= NARROW_SPREAD;
        *scale = f64::from_bits(((1023 - e) as u64) << 52);
    }
    // NOTE: the short path converts straight to i64 (one instruction per
    // coordinate); only the long one needs `to_integer`'s split.
    Some(if narrow {
        narrow_det_sign(&points.map(|point| std::array::from_fn(|a| (point[a] * scale[a]) as i64)))
    } else {
        wide_det_sign(&points.map(|point| std::array::from_fn(|a| to_integer(point[a] * scale[a]))))
    })
}

/// An integer-valued `f64` below 2^76 in magnitude, exactly, as an `i128`.
///
/// NOTE: `high` = v / 2^38 truncated (by the conversion) is below 2^38 and
/// `high · 2^38` is exact; `v − high · 2^38` is an integer below 2^38 with
/// v's sign, so it is representable and the subtraction exact. (A direct
/// `as i128` is a library call, and so is `trunc` without SSE4.1.)
#[inline]
fn to_integer(v: f64) -> i128 {
    const SPLIT: f64 = (1u64 << 38) as f64;
    let high = (v * (1.0 / SPLIT)) as i64;
    let low = v - high as f64 * SPLIT;
    ((high as i128) << 38) + low as i64 as i128
}

/// The determinant's sign when every scaled coordinate is below 2^61.
///
/// NOTE: differences are below 2^62, so a minor `b_j c_k − b_k c_j` is an
/// exact `i128` below 2^125. Each term `a_i · m_i` is split at bit 64 of the
/// minor: `a·m_hi` stays below 2^123 and `a·m_lo` below 2^126, so the high
/// sums and the low sums (below 2^66) fit an `i128`.
fn narrow_det_sign(int: &[[i64; 3]; 4]) -> i8 {
    let diff = |k: usize| [int[k][0] - int[0][0], int[k][1] - int[0][1], int[k][2] - int[0][2]];
    let (a, b, c) = (diff(1), diff(2), diff(3));
    let product = |x: i64, y: i64| x as i128 * y as i128;
    let minors =
        [product(b[1], c[2]) - product(b[2], c[1]), product(b[2], c[0]) - product(b[0], c[2]), product(b[0], c[1]) - product(b[1], c[0])];
    const LOW: i128 = (1 << 64) - 1;
    let (mut high, mut low) = (0i128, 0i128);
    for (ai, m) in a.iter().zip(minors) {
        let ai = *ai as i128;
        let low_product = ai * (m & LOW);
        high += ai * (m >> 64) + (low_product >> 64);
        low += low_product & LOW;
    }
    high += low >> 64;
    low &= LOW;
    if high != 0 {
        high.signum() as i8
    } else {
        i8::from(low != 0)
    }
}

/// The determinant's sign for scaled coordinates below 2^76.
fn wide_det_sign(int: &[[i128; 3]; 4]) -> i8 {
    let diff = |k: usize| [int[k][0] - int[0][0], int[k][1] - int[0][1], int[k][2] - int[0][2]];
    let (a, b, c) = (diff(1), diff(2), diff(3));
    // det = Σ a_i · m_i over the minors of b and c.
    let minors = [minor(b[1], c[2], b[2], c[1]), minor(b[2], c[0], b[0], c[2]), minor(b[0], c[1], b[1], c[0])];
    // With a_i = h·2^39 + l and m_i = A·2^78 + B the determinant is
    // t3·2^117 + t2·2^78 + t1·2^39 + t0 (each t a sum of three products
    // below 2^118).
    let (mut t3, mut t2, mut t1, mut t0) = (0i128, 0i128, 0i128, 0i128);
    for (ai, (big, small)) in a.iter().zip(minors) {
        let (h, l) = limbs(*ai);
        let (h, l) = (h as i128, l as i128);
        t3 += h * big;
        t2 += l * big;
        t1 += h * small;
        t0 += l * small;
    }
    // Carry upward so that t0, t1, t2 end in [0, 2^39): the sign is then
    // t3's, or positive when t3 = 0 and anything below is not.
    let carry = t0 >> LIMB;
    t0 -= carry << LIMB;
    t1 += carry;
    let carry = t1 >> LIMB;
    t1 -= carry << LIMB;
    t2 += carry;
    let carry = t2 >> LIMB;
    t2 -= carry << LIMB;
    t3 += carry;
    if t3 != 0 {
        t3.signum() as i8
    } else {
        i8::from((t0 | t1 | t2) != 0)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::Rng;
    use proptest::test_runner::{RngAlgorithm, TestRng};

    /// The same determinant with big integers.
    fn reference(p: [f64; 3], q: [f64; 3], r: [f64; 3], x: [f64; 3]) -> i8 {
        use num_bigint::BigInt;
        use num_traits::Signed;
        // Decomposed independently of `split`: num-traits' integer_decode.
        let decode = |v: f64| {
            let (m, e, sign) = num_traits::float::FloatCore::integer_decode(v);
            (m != 0).then(|| (BigInt::from(m) * i64::from(sign), i32::from(e)))
        };
        let e_min = [p, q, r, x].iter().flatten().filter_map(|v| decode(*v)).map(|(_, e)| e).min().unwrap_or(0);
        let int = |v: f64| decode(v).map_or(BigInt::from(0), |(m, e)| m << (e - e_min) as usize);
        let d = |a: [f64; 3]| [0, 1, 2].map(|i| int(a[i]) - int(p[i]));
        let (a, b, c) = (d(q), d(r), d(x));
        let det =
            &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0]) + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
        if det.is_positive() {
            1
        } else if det.is_negative() {
            -1
        } else {
            0
        }
    }

    /// A uniform value in [−1, 1) from the test suite's deterministic generator.
    pub(crate) fn unit(rng: &mut TestRng) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
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
            let x = if k % 3 == 0 {
                pt(1.0, 1.0)
            } else {
                let (a, b) = (unit(&mut rng), unit(&mut rng));
                pt(a, b)
            };
            // Exactly coplanar too: a point repeated, or the midpoint of two.
            let x = if k % 10 == 0 {
                q
            } else if k % 10 == 1 {
                [0, 1, 2].map(|i| (p[i] + q[i]) * 0.5)
            } else {
                x
            };
            let Some(got) = orient_det_sign(p, q, r, x) else { continue };
            assert_eq!(got, reference(p, q, r, x), "case {k}: {p:?} {q:?} {r:?} {x:?}");
            decided += 1;
            zeros += usize::from(got == 0);
        }
        assert!(decided > 15000 && zeros > 1000, "decided {decided}, zeros {zeros}");
    }

    /// A random full 53-bit mantissa in binade `e`, either sign.
    fn full_mantissa(rng: &mut TestRng, e: i32) -> f64 {
        let v = ((1u64 << 52) | (rng.next_u64() >> 12)) as f64 * 2f64.powi(e - 52);
        if rng.next_u64().is_multiple_of(2) {
            v
        } else {
            -v
        }
    }

    /// 20000 cases whose coordinates on each axis sit in binade `base(k)[axis]`
    /// or `spread(k)` binades above, near and exactly coplanar too (a last
    /// point one ulp off `q`, or `q` itself): every sign must be the big
    /// integers'. Returns how many were nonzero.
    fn agreement_at_spread(base: impl Fn(usize) -> [i32; 3], spread: impl Fn(usize) -> i32) -> usize {
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let mut nonzero = 0;
        for k in 0..20000 {
            let (base, spread) = (base(k), spread(k));
            let mut pt = || {
                [0, 1, 2].map(|axis| {
                    let up = if rng.next_u64().is_multiple_of(2) { 0 } else { spread };
                    full_mantissa(&mut rng, base[axis] + up)
                })
            };
            let (p, q, r, mut x) = (pt(), pt(), pt(), pt());
            match k % 4 {
                1 => x = [f64::from_bits(q[0].to_bits() + 1), q[1], q[2]],
                2 => x = q,
                _ => {}
            }
            let got = orient_det_sign(p, q, r, x).expect("within the spread");
            assert_eq!(got, reference(p, q, r, x), "case {k}: {p:?} {q:?} {r:?} {x:?}");
            nonzero += usize::from(got != 0);
        }
        nonzero
    }

    #[test]
    fn agrees_with_big_integers_at_the_edge_of_its_bit_budget() {
        // Exponents MAX_SPREAD apart on every axis: the largest differences,
        // minors and determinants the limbs must hold, and their carries.
        let nonzero = agreement_at_spread(|k| [[-60; 3], [0; 3], [300; 3]][k % 3], |_| MAX_SPREAD);
        assert!(nonzero > 14000 && nonzero < 16000, "nonzero {nonzero}");
    }

    #[test]
    fn agrees_with_big_integers_at_the_edge_of_the_short_path() {
        // Each axis spans exactly NARROW_SPREAD binades (or one more, just
        // past the short path), each axis at its own scale: the largest
        // values the short path must hold.
        let nonzero = agreement_at_spread(|k| [[-40, 0, 90], [7, -300, 12], [0, 0, 0]][k % 3], |k| NARROW_SPREAD + (k % 2) as i32);
        assert!(nonzero > 14000 && nonzero < 16000, "nonzero {nonzero}");
    }

    #[test]
    fn agrees_with_big_integers_on_signed_zeros_and_declines_subnormals() {
        // Signed zeros among the coordinates take no part in an axis's
        // exponent range; a subnormal (no power of two scales it to an
        // integer through a normal scale) is declined, never misjudged.
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let (mut decided, mut subnormal_cases) = (0, 0);
        for k in 0..5000 {
            let with_subnormals = k % 5 == 0;
            let mut coord = || match rng.next_u64() % 4 {
                0 => 0.0,
                1 => -0.0,
                2 if with_subnormals => f64::from_bits(1 + rng.next_u64() % (1 << 40)),
                // In [1, 2), at one of three binades a few apart.
                _ => f64::from_bits((1023 << 52) + rng.next_u64() % (1 << 52)) * [1.0, -8.0, 0.25][(rng.next_u64() % 3) as usize],
            };
            let mut pt = || [coord(), coord(), coord()];
            let (p, q, r, x) = (pt(), pt(), pt(), pt());
            let has_subnormal = [p, q, r, x].iter().flatten().any(|c| c.is_subnormal());
            subnormal_cases += usize::from(has_subnormal);
            let Some(got) = orient_det_sign(p, q, r, x) else {
                assert!(has_subnormal, "case {k} declined: {p:?} {q:?} {r:?} {x:?}");
                continue;
            };
            assert_eq!(got, reference(p, q, r, x), "case {k}: {p:?} {q:?} {r:?} {x:?}");
            decided += 1;
        }
        assert!(decided > 3500 && subnormal_cases > 500, "decided {decided}, with subnormals {subnormal_cases}");
    }

    #[test]
    fn declines_wide_exponent_ranges_within_an_axis() {
        let p = [0.0, 0.0, 0.0];
        assert_eq!(orient_det_sign(p, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1e-30, 0.0, 1.0]), None);
        // Spread across axes is scaled away: each axis has its own exponent.
        assert_eq!(orient_det_sign(p, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e-30]), Some(1));
        assert_eq!(orient_det_sign(p, [1e200, 0.0, 0.0], [0.0, 1e-200, 0.0], [0.0, 0.0, -1e-30]), Some(-1));
        assert_eq!(orient_det_sign(p, p, p, p), Some(0));
    }
}
