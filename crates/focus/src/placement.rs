//! [`crate::SplitScheme::Optimal`]: split planes that even out the splits'
//! predicted maximum aliasing for one light.
//!
//! With the same texels per split, the frame's worst aliasing is the worst
//! split's, so the planes are best where every split predicts the same
//! maximum `a_i`. Write split `i`'s length in log depth `ℓ_i = ln(C_{i+1}/C_i)`
//! (the logarithmic scheme makes them equal; the logarithmic bound is
//! reached by texels spread evenly in `ln z`), the first split's from the
//! nearest receiver rather than `near`. Modelling each split's
//! maximum as `a_i ≈ c_i ℓ_i²`, the planes with equal maxima and the same
//! total `L = ln(f/n)` are
//!
//! `ℓ_i' = L · (ℓ_i / √a_i) / Σ_j (ℓ_j / √a_j)`,
//!
//! which one round computes from the maps fitted to the current planes.
//! The square is a damping, not a law: a uniform map's maximum grows faster
//! than linearly with `ℓ`, a strong warp's more slowly, and the linear model
//! (`ℓ_i / a_i`) overshoots a near split whose receivers all lie beyond its
//! new far plane, so that the planes swing between two bad placements.
//!
//! The damping costs speed where the maxima grow more slowly than `ℓ²`: the
//! rounds then close the same fraction of the remaining gap each time
//! (about a third on the built-in scenes), a linearly converging fixed
//! point. From the second round on, the step is lengthened by the secant
//! of the last two rounds: with `u` the splits' log lengths and `g(u)` the
//! update's step there (`ln ℓ' − ln ℓ`), the scalar slope
//! `J = ⟨Δg, Δu⟩ / ⟨Δu, Δu⟩` (`−1` where the update lands on its fixed
//! point at once, `r − 1` for a contraction `r`) makes the step
//! `g / (−J)`, the Newton step of the one-dimensional model, at least the
//! plain step and at most `MAX_SPEEDUP` times it (Barzilai–Borwein's step
//! length, applied to a fixed point). Each
//! round's change of a split is limited to a factor `MAX_STEP` too, and the
//! planes of the round with the least predicted worst split are kept:
//! never worse, by the prediction, than the start.
//!
//! The rounds start from the better of two placements: the practical
//! planes, and the logarithmic planes over the receivers' depth range (the
//! nearest receiver sample to far, [`log_from`]): where the camera sees no
//! receiver for the first few metres (a viewer above a ground), the
//! logarithmic scheme from `near` spends its first splits on air, and the
//! update, which moves planes by at most `MAX_STEP` per round, would take
//! several rounds to leave it.
//!
//! The first plane never moves beyond the start's (the practical scheme's):
//! the first split's worst receivers are the nearest ones, which the
//! prediction misses where they stand in front of the faces it samples (a
//! terrain above the scene box's floor seen from eye height), so it
//! predicts that split too good and would lengthen it.

use crate::error::FocusError;
use crate::MAX_SPLITS;

/// Rounds of refitting after the start. With the secant, four rounds place
/// the planes about as well as six plain ones (`crates/eval/RESULTS.md`,
/// "Where the splits go"), and a fourth round recovers from a third that
/// overshot.
pub(crate) const PLACEMENT_ROUNDS: usize = 4;

/// Rounds for [`crate::Method::Auto`], whose split's maximum is the least
/// of four methods' and so grows more slowly with its length: its rounds
/// contract more slowly, and after four its planes stop short of where one
/// method's settle (light sweep, four splits: Auto within 5 % of the best
/// method's maximum in 192 of 252 suns after four rounds, 210 after six,
/// 217 after eight).
pub(crate) const AUTO_PLACEMENT_ROUNDS: usize = 6;

/// Most a split's log-depth length changes by in one round (either way).
const MAX_STEP: f64 = 4.0;

/// A round that moves no split by more than this fraction of `L` is the
/// last.
const SETTLED: f64 = 1e-3;

/// Most the secant lengthens a round's step by (the Newton step of a
/// contraction of 1/2 per plain round). The rounds on the built-in scenes
/// contract by about 2/3, yet a longer step overshoots where a split's
/// maximum jumps as a plane passes a receiver or Auto changes a split's
/// method (robot war: up to 4 lost what 2 gained).
const MAX_SPEEDUP: f64 = 2.0;

/// Split planes.
pub(crate) type Planes = [f64; MAX_SPLITS + 1];

/// Each split's predicted maximum aliasing; `None` where nothing is
/// predicted (no map, or no receiver in the split).
pub(crate) type SplitAliasing = [Option<f64>; MAX_SPLITS];

/// Moves the `m` splits' inner planes toward equal predicted aliasing,
/// from the better (by the prediction) of the planes in `planes` and the
/// logarithmic planes from the nearest receiver `lo` ([`log_from`]), into
/// `planes`, in at most `rounds` rounds. `fit` fits every split to the
/// planes it is given and predicts each split's maximum; when this returns,
/// the last call of `fit` was with the planes left in `planes`.
///
/// NOTE: the planes are fitted again only where the last fit was not with
/// the planes kept. Where the start beats the logarithmic planes the first
/// round's fit follows it; fitting the start a second time before it would
/// cost Auto a ninth of its placement on the robot war.
pub(crate) fn place(
    planes: &mut Planes,
    lo: Option<f64>,
    m: usize,
    rounds: usize,
    mut fit: impl FnMut(&Planes) -> Result<SplitAliasing, FocusError>,
) -> Result<(), FocusError> {
    let first = planes[1];
    let mut a = fit(planes)?;
    let mut best = (*planes, worst(&a, m));
    let mut fitted = *planes;
    let other = lo.and_then(|lo| log_from(planes[0], lo, planes[m], m)).map(|mut o| {
        o[1] = o[1].min(first);
        o
    });
    if let Some(other) = other.filter(|o| o != planes) {
        let b = fit(&other)?;
        fitted = other;
        let w = worst(&b, m);
        if w < best.1 {
            (*planes, a, best) = (other, b, (other, w));
        }
    }
    let mut last = None;
    for _ in 0..rounds {
        if !rebalance(planes, m, &a, first, lo, &mut last) {
            break;
        }
        a = fit(planes)?;
        fitted = *planes;
        let w = worst(&a, m);
        if w < best.1 {
            best = (*planes, w);
        }
    }
    *planes = best.0;
    if fitted != best.0 {
        fit(planes)?;
    }
    Ok(())
}

/// The logarithmic planes over the receivers' depth range `[lo, far]`
/// ([PSSM06] eq. 4 with the camera's `near` replaced by `lo`, the nearest
/// receiver), the first split reaching down to `near`; `None` where `lo`
/// is not inside `(near, far)`.
pub(crate) fn log_from(near: f64, lo: f64, far: f64, m: usize) -> Option<Planes> {
    if !(lo > near && lo < far) {
        return None;
    }
    let mut p = [0.0; MAX_SPLITS + 1];
    p[0] = near;
    for (i, c) in p.iter_mut().enumerate().take(m).skip(1) {
        // NOTE: lo·(far/lo)^(i/m) as exp(t·ln(far/lo)), as `split_depths` does.
        *c = lo * (i as f64 / m as f64 * (far / lo).ln()).exp();
    }
    p[m] = far;
    Some(p)
}

/// The worst split's prediction (0 where none predicts anything).
fn worst(a: &SplitAliasing, m: usize) -> f64 {
    a[..m].iter().flatten().fold(0.0, |w: f64, &x| if x.is_nan() { f64::INFINITY } else { w.max(x) })
}

/// A round's splits in log length `u` and the plain update's step `g` at
/// them (`NaN` for a split without a prediction), for the next round's
/// secant.
#[derive(Clone, Copy)]
struct Step {
    at: [f64; MAX_SPLITS],
    step: [f64; MAX_SPLITS],
}

/// The factor, in `[1, MAX_SPEEDUP]`, the secant from `last` to `now`
/// lengthens the plain step by (see the module's text); 1 where the two
/// rounds judged different splits, did not move, or the update's step did
/// not shrink along the move.
fn speedup(last: &Step, now: &Step, m: usize) -> f64 {
    let (mut ss, mut sd) = (0.0, 0.0);
    for i in 0..m {
        if last.at[i].is_nan() != now.at[i].is_nan() {
            return 1.0;
        }
        if now.at[i].is_nan() {
            continue;
        }
        let s = now.at[i] - last.at[i];
        ss += s * s;
        sd += s * (now.step[i] - last.step[i]);
    }
    if ss > 0.0 && sd < 0.0 {
        (-ss / sd).clamp(1.0, MAX_SPEEDUP)
    } else {
        1.0
    }
}

/// The new lengths `new` of the `judged` splits limited to a factor
/// `MAX_STEP` of `len` each and scaled back to sum to `share`.
fn limit(new: &mut [f64; MAX_SPLITS], len: &[f64; MAX_SPLITS], judged: &[bool; MAX_SPLITS], m: usize, share: f64) {
    let mut sum = 0.0;
    for i in (0..m).filter(|&i| judged[i]) {
        new[i] = new[i].clamp(len[i] / MAX_STEP, len[i] * MAX_STEP);
        sum += new[i];
    }
    for i in (0..m).filter(|&i| judged[i]) {
        new[i] *= share / sum;
    }
}

/// One round of the update above, the first plane at most `first`, the
/// first split's length counted from the nearest receiver `lo` where that
/// lies inside the split: its texels go to its receivers, and counting its
/// length from `near` would weigh the empty space in front of them. (A
/// first split that ends before `lo` has no prediction and holds; it can
/// only be the start's, as a round keeps its far plane beyond `lo`.)
/// `last` is the previous round's [`Step`], replaced by this one's.
/// `false` when it has nothing to move.
fn rebalance(planes: &mut Planes, m: usize, a: &SplitAliasing, first: f64, lo: Option<f64>, last: &mut Option<Step>) -> bool {
    let (near, far) = (planes[0], planes[m]);
    let base = lo.filter(|&l| l > near && l < planes[1]).unwrap_or(near);
    let total = (far / base).ln();
    let mut len = [0.0; MAX_SPLITS];
    for i in 0..m {
        len[i] = (planes[i + 1] / if i == 0 { base } else { planes[i] }).ln();
    }
    // Splits with a positive prediction (judged) share what the others
    // leave; `x` is the prediction of a judged split.
    let mut x = [0.0; MAX_SPLITS];
    let mut judged = [false; MAX_SPLITS];
    let (mut share, mut weight, mut count) = (total, 0.0, 0);
    for i in 0..m {
        match a[i] {
            Some(v) if v > 0.0 && len[i] > 0.0 => {
                (x[i], judged[i]) = (v, true);
                weight += len[i] / v.sqrt();
                count += 1;
            }
            _ => share -= len[i],
        }
    }
    if count < 2 || !(weight > 0.0) || !(share > 0.0) {
        return false;
    }
    let mut new = len;
    for i in (0..m).filter(|&i| judged[i]) {
        new[i] = share * (len[i] / x[i].sqrt()) / weight;
    }
    limit(&mut new, &len, &judged, m, share);
    let mut now = Step { at: [f64::NAN; MAX_SPLITS], step: [f64::NAN; MAX_SPLITS] };
    let mut moved = 0.0f64;
    for i in (0..m).filter(|&i| judged[i]) {
        (now.at[i], now.step[i]) = (len[i].ln(), (new[i] / len[i]).ln());
        moved = moved.max((new[i] - len[i]).abs());
    }
    if !(moved > SETTLED * total) {
        return false;
    }
    let k = last.as_ref().map_or(1.0, |l| speedup(l, &now, m));
    *last = Some(now);
    if k > 1.0 {
        for i in (0..m).filter(|&i| judged[i]) {
            new[i] = len[i] * (k * now.step[i]).exp();
        }
        limit(&mut new, &len, &judged, m, share);
    }
    planes[1] = (base * new[0].exp()).clamp(near, far).min(first);
    for i in 2..m {
        // NOTE: each plane from the near end keeps relative precision; the
        // far plane stays exactly `far` and the order is kept by the clamp.
        planes[i] = (planes[i - 1] * new[i - 1].exp()).clamp(planes[i - 1], far);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splits whose maximum is `c_i · ℓ_i²` are evened out in one round.
    #[test]
    fn the_model_is_solved_in_one_round() {
        let c = [4.0, 1.0, 1.5, 2.0];
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..5].copy_from_slice(&[0.1, 1.0, 10.0, 100.0, 1000.0]);
        let mut rounds = 0;
        let model = |p: &Planes| {
            let mut a = [None; MAX_SPLITS];
            for i in 0..4 {
                a[i] = Some(c[i] * (p[i + 1] / p[i]).ln().powi(2));
            }
            a
        };
        place(&mut planes, None, 4, PLACEMENT_ROUNDS, |p| {
            rounds += 1;
            Ok(model(p))
        })
        .unwrap();
        let a = model(&planes);
        let (lo, hi) = a[..4].iter().flatten().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        assert!(hi / lo < 1.0 + 1e-9, "{a:?}");
        assert_eq!(planes[0], 0.1);
        assert_eq!(planes[4], 1000.0);
        assert!(planes[..5].windows(2).all(|w| w[0] < w[1]), "{planes:?}");
        // The start and one round, after which nothing moves.
        assert_eq!(rounds, 2);
    }

    /// Splits whose maximum grows only linearly with their length
    /// (`c_i · ℓ_i`): the damped update halves the gap in log length each
    /// round, and the secant, from the second round on, closes it.
    #[test]
    fn the_secant_closes_a_slow_contraction() {
        let c = [4.0, 1.0, 1.5, 2.0];
        let start = [0.1, 1.0, 10.0, 100.0, 1000.0];
        let model = |q: &Planes| {
            let mut a = [None; MAX_SPLITS];
            for i in 0..4 {
                a[i] = Some(c[i] * (q[i + 1] / q[i]).ln());
            }
            a
        };
        let spread = |q: &Planes| {
            let a = model(q);
            let (lo, hi) = a[..4].iter().flatten().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
            hi / lo
        };
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..5].copy_from_slice(&start);
        place(&mut planes, None, 4, PLACEMENT_ROUNDS, |q| Ok(model(q))).unwrap();
        // Plain rounds, each without the last one's step.
        let mut plain = [0.0; MAX_SPLITS + 1];
        plain[..5].copy_from_slice(&start);
        for _ in 0..PLACEMENT_ROUNDS {
            let a = model(&plain);
            rebalance(&mut plain, 4, &a, 1.0, None, &mut None);
        }
        assert!(spread(&planes) < 1.01, "{planes:?}: {}", spread(&planes));
        assert!(spread(&plain) > 1.05, "{plain:?}: {}", spread(&plain));
        assert!(planes[..5].windows(2).all(|w| w[0] < w[1]), "{planes:?}");
    }

    /// The secant's factor: the plain step where the rounds judged other
    /// splits or the step grew along the move, the Newton step of the
    /// one-dimensional model within `[1, MAX_SPEEDUP]` otherwise.
    #[test]
    fn the_speedup_follows_the_secant() {
        let nan = f64::NAN;
        let step = |at: [f64; 2], step: [f64; 2]| {
            let mut s = Step { at: [nan; MAX_SPLITS], step: [nan; MAX_SPLITS] };
            s.at[..2].copy_from_slice(&at);
            s.step[..2].copy_from_slice(&step);
            s
        };
        // A contraction of 3/5 per round: slope -0.4, factor 2.5, capped.
        let (last, now) = (step([0.0, 0.0], [1.0, -1.0]), step([1.0, -1.0], [0.6, -0.6]));
        assert_eq!(speedup(&last, &now, 2), MAX_SPEEDUP);
        // A contraction of 1/5: factor 1.25.
        let now = step([1.0, -1.0], [0.2, -0.2]);
        assert!((speedup(&last, &now, 2) - 1.25).abs() < 1e-12);
        // Overshooting (the step changes sign beyond -1): the plain step.
        assert_eq!(speedup(&last, &step([1.0, -1.0], [-0.5, 0.5]), 2), 1.0);
        // Growing steps, or no move, or other splits judged: the plain step.
        assert_eq!(speedup(&last, &step([1.0, -1.0], [2.0, -2.0]), 2), 1.0);
        assert_eq!(speedup(&last, &step([0.0, 0.0], [0.5, -0.5]), 2), 1.0);
        assert_eq!(speedup(&last, &step([1.0, nan], [0.5, nan]), 2), 1.0);
    }

    /// With the nearest receiver known, the first split's maximum follows
    /// its length from that receiver, not from `near`: the model is solved
    /// with the empty space in front of the receivers left out, and the
    /// first plane stays at most the start's.
    #[test]
    fn the_first_split_is_measured_from_the_nearest_receiver() {
        let (c, lo) = ([40.0, 1.0, 1.5, 2.0], 0.5);
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..5].copy_from_slice(&[0.1, 1.0, 10.0, 100.0, 1000.0]);
        let model = |p: &Planes| {
            let mut a = [None; MAX_SPLITS];
            for i in 0..4 {
                a[i] = Some(c[i] * (p[i + 1] / p[i].max(lo)).ln().powi(2));
            }
            a
        };
        place(&mut planes, Some(lo), 4, PLACEMENT_ROUNDS, |p| Ok(model(p))).unwrap();
        let a = model(&planes);
        let (l, h) = a[..4].iter().flatten().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        assert!(h / l < 1.0 + 1e-9, "{a:?}");
        assert!(planes[1] > lo && planes[1] <= 1.0, "{planes:?}");
    }

    /// A round that predicts worse than an earlier one is undone: the
    /// planes kept are the best seen, and the last fit is with them.
    #[test]
    fn the_best_round_is_kept() {
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..3].copy_from_slice(&[1.0, 10.0, 100.0]);
        let start = planes;
        let mut last = planes;
        // Whatever the planes, moving them makes things worse.
        place(&mut planes, None, 2, PLACEMENT_ROUNDS, |p| {
            last = *p;
            let moved = (p[1] - 10.0).abs();
            Ok([Some(1.0 + moved), Some(3.0 + moved), None, None, None, None, None, None])
        })
        .unwrap();
        assert_eq!(planes, start);
        assert_eq!(last, start);
    }

    /// The better start is kept, and the last fit is with it.
    #[test]
    fn the_better_start_is_taken() {
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..3].copy_from_slice(&[1.0, 50.0, 100.0]);
        let other = log_from(1.0, 4.0, 100.0, 2).unwrap();
        let lo = Some(4.0);
        assert_eq!((other[0], other[2]), (1.0, 100.0));
        assert!((other[1] - 20.0).abs() < 1e-12, "{other:?}");
        let mut last = planes;
        // Worse the farther the inner plane is from 20, and balanced there.
        place(&mut planes, lo, 2, PLACEMENT_ROUNDS, |p| {
            last = *p;
            let off = (p[1] / other[1]).ln().abs();
            Ok([Some(1.0 + off), Some(1.0 + off), None, None, None, None, None, None])
        })
        .unwrap();
        assert_eq!(planes, other);
        assert_eq!(last, planes);
        assert_eq!(log_from(1.0, 0.5, 100.0, 2), None);
        assert_eq!(log_from(1.0, 100.0, 100.0, 2), None);
    }

    /// Where the start beats the logarithmic planes and rounds follow, the
    /// start is fitted once: the rounds' fits follow it.
    #[test]
    fn the_start_is_fitted_once() {
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..3].copy_from_slice(&[1.0, 30.0, 100.0]);
        let mut calls = Vec::new();
        // Balanced at 25: the start (30) predicts 1.2, the log planes (20)
        // 1.25.
        place(&mut planes, Some(4.0), 2, PLACEMENT_ROUNDS, |p| {
            calls.push(p[1]);
            let r = p[1] / 25.0;
            Ok([Some(r), Some(1.0 / r), None, None, None, None, None, None])
        })
        .unwrap();
        assert!((calls[1] - 20.0).abs() < 1e-9 && calls.len() > 3, "{calls:?}");
        assert_eq!(calls.iter().filter(|&&c| c == 30.0).count(), 1, "{calls:?}");
        assert!((planes[1] - 25.0).abs() < 1.0 && *calls.last().unwrap() == planes[1], "{calls:?}");
    }

    /// Splits without a prediction keep their length; a single judged split
    /// has nothing to be balanced against.
    #[test]
    fn unjudged_splits_hold() {
        let mut planes = [0.0; MAX_SPLITS + 1];
        planes[..4].copy_from_slice(&[1.0, 2.0, 20.0, 200.0]);
        let start = planes;
        place(&mut planes, None, 3, PLACEMENT_ROUNDS, |_| Ok([None, Some(5.0), None, None, None, None, None, None])).unwrap();
        assert_eq!(planes, start);
    }
}
