//! Texels shared among a fit's maps ([`TexelBudget`]).
//!
//! A map `r` texels wide shows its receivers at `e/r` screen pixels per
//! texel (times the image's `√(W·H)`), `e` its dimensionless predicted
//! aliasing ([`crate::predict_aliasing`]): the aliasing is inversely
//! proportional to the side. The sizes that minimise the largest `e_i/r_i`
//! under `Σ r_i² ≤ T` make them all equal:
//!
//! - **Derivation.** Let `t = max e_i/r_i`. Then `r_i ≥ e_i/t`, so
//!   `T ≥ Σ r_i² ≥ Σ e_i²/t²`, i.e. `t ≥ √(Σ e_i² / T)`, with equality
//!   exactly when `r_i = e_i/t` for every map.
//! - **Bounds.** With sides bounded to `[lo, hi]` the optimum is
//!   `r_i = clamp(e_i/t, lo, hi)` for the least `t` whose sizes fit `T`
//!   (the same argument over the maps not at a bound); `Σ clamp(·)²`
//!   decreases in `t`, so `t` is found by bisection.
//! - **Rounding.** Each size is rounded down to an allowed one (the sum
//!   stays within `T`); then the texels left go, one step at a time, to the
//!   map whose `e_i/r_i` is largest among those whose next size still fits.
//!
//! No map falls below half the side of an equal share, `√(T/n)/2`: the
//! prediction can miss a split's receivers (without receiver boxes, the
//! scene box's faces stand in for them, and where those are empty it judges
//! the split on nothing), and this floor bounds what such a miss costs at
//! 2× that split's aliasing, where an unbounded share once gave a split 11
//! texels a side and the frame 47× the equal maps' maximum (the light
//! sweep's duelling frusta, a sun ahead).
//!
//! The prediction is taken on the fitted maps (receiver footprints
//! included) at the settings' resolution. A receiver footprint's margin is
//! a number of texels, so a resized map's image is grown or shrunk about its
//! centre to keep that many of its own texels.

use crate::error::FocusError;
use crate::receivers::{margin_grow, texel_sizes};
use crate::result::{FocusResult, MapState};
use crate::settings::{Footprint, MapSizes, TexelBudget};
use crate::view::PreparedView;
use crate::view_aliasing::{map_aliasing, ReceiverRays};
use crate::MAX_MAPS;
use glam::DVec4;

/// Bisection steps for the water level `t`: each halves its log-range,
/// which starts within ±2¹⁵ of the answer (sizes lie in `[4, 2¹⁵)`); 64
/// steps leave it exact to f64 rounding.
const BISECTION_STEPS: usize = 64;

/// Sizes the active maps of `out` by `budget` and refits them to their
/// sizes: each map's [`crate::MapFit::resolution`], texel sizes and (for
/// receiver footprints) margin.
pub(crate) fn share_texels(out: &mut FocusResult, view: &PreparedView, rays: &ReceiverRays, budget: TexelBudget) -> Result<(), FocusError> {
    let settings = view.settings();
    let mut aliasing = [0.0; MAX_MAPS];
    let mut sizes = [0u32; MAX_MAPS];
    let n = out.maps().len();
    map_aliasing(out.maps(), out.split_depths(), rays, &mut aliasing[..n]);
    let active: [bool; MAX_MAPS] = std::array::from_fn(|k| k < n && out.maps()[k].fit.state == MapState::Active);
    let margin = match settings.footprint {
        Footprint::Body => 0.0,
        Footprint::Receivers { margin_texels } => margin_texels,
    };
    let mut count = 0;
    for k in (0..n).filter(|&k| active[k]) {
        aliasing[count] = aliasing[k];
        count += 1;
    }
    let [lo, hi] = size_bounds(budget.sizes, margin, settings.resolution);
    let bounds = [lo.max(half_share(budget, count, hi)), hi];
    share_seen(&aliasing[..count], budget, bounds, &mut sizes[..count])?;
    let mut next = sizes[..count].iter();
    for map in out.maps_and_work().0.iter_mut().filter(|m| m.fit.state == MapState::Active) {
        let Some(&size) = next.next() else { break };
        let was = map.fit.resolution;
        map.fit.resolution = size;
        if matches!(map.fit.footprint, Footprint::Receivers { .. }) && size != was {
            keep_margin(map, margin, was, settings.f32_origin);
        }
        map.fit.texel_size = texel_sizes(&map.fit.clip_from_world, &map.light, view, map.split_range, size);
    }
    Ok(())
}

/// [`allocate`] among the maps some receiver sample lands in (`aliasing`
/// positive). A map none lands in may still serve receivers the prediction
/// does not know of (a terrain above its box's floor, casters that receive),
/// so it keeps an equal share, `√(T/n)` rounded down to an allowed size: never
/// fewer texels than without a budget.
fn share_seen(aliasing: &[f64], budget: TexelBudget, [lo, hi]: [u32; 2], sizes: &mut [u32]) -> Result<(), FocusError> {
    let n = aliasing.len();
    if n == 0 {
        return Ok(());
    }
    let equal = round_down(budget.sizes, ((budget.texels / n as u64) as f64).sqrt().clamp(lo as f64, hi as f64), lo);
    let mut seen = [0.0; MAX_MAPS];
    let mut k = 0;
    for &e in aliasing.iter().filter(|&&e| e > 0.0) {
        seen[k] = e;
        k += 1;
    }
    let unseen = (n - k) as u64 * u64::from(equal).pow(2);
    let rest = TexelBudget { texels: budget.texels.saturating_sub(unseen), ..budget };
    let mut seen_sizes = [0u32; MAX_MAPS];
    allocate(&seen[..k], rest, [lo, hi], &mut seen_sizes[..k])?;
    let mut next = seen_sizes[..k].iter();
    for (s, &e) in sizes.iter_mut().zip(aliasing) {
        *s = if e > 0.0 { next.next().copied().unwrap_or(equal) } else { equal };
    }
    Ok(())
}

/// The least allowed side of at least half an equal share's, `√(T/n)/2`
/// (at most `hi`), for `n` maps.
fn half_share(budget: TexelBudget, n: usize, hi: u32) -> u32 {
    let half = (0.5 * (budget.texels as f64 / n.max(1) as f64).sqrt()).ceil() as u32;
    let up = match budget.sizes {
        MapSizes::Any => half,
        MapSizes::PowerOfTwo => half.next_power_of_two(),
    };
    up.min(hi)
}

/// The least and greatest side a map may take: at least
/// [`MapSizes::SMALLEST`] and 8 margins (the settings' own bound on a
/// margin), at most `resolution`, each an allowed size.
fn size_bounds(sizes: MapSizes, margin_texels: f64, resolution: u32) -> [u32; 2] {
    let lo = MapSizes::SMALLEST.max((8.0 * margin_texels).ceil().min(resolution as f64) as u32);
    match sizes {
        MapSizes::Any => [lo, resolution],
        MapSizes::PowerOfTwo => {
            let hi = 1u32 << resolution.ilog2();
            [lo.next_power_of_two().min(hi), hi]
        }
    }
}

/// The sizes minimising the largest `aliasing[k] / sizes[k]` under
/// `Σ sizes² ≤ budget.texels` with sizes in `[lo, hi]` (see the module's
/// derivation). `aliasing` is positive.
pub(crate) fn allocate(aliasing: &[f64], budget: TexelBudget, [lo, hi]: [u32; 2], sizes: &mut [u32]) -> Result<(), FocusError> {
    let texels = budget.texels as f64;
    let total = |t: f64| aliasing.iter().map(|e| (e / t).clamp(lo as f64, hi as f64).powi(2)).sum::<f64>();
    if aliasing.len() as u64 * u64::from(lo).pow(2) > budget.texels {
        return Err(FocusError::InvalidSettings {
            what: "texel_budget.texels",
            reason: "fewer than the active maps need at their smallest size (16 texels each, 64 margins² with a receiver footprint)",
        });
    }
    // The water level: `total` is n·hi² below `t_lo` and n·lo² above `t_hi`.
    let emax = aliasing.iter().copied().fold(0.0, f64::max);
    let emin = aliasing.iter().copied().fold(f64::INFINITY, f64::min);
    let (mut t_lo, mut t_hi) = (emin / hi as f64, emax / lo as f64);
    if total(t_lo) <= texels {
        t_hi = t_lo;
    }
    for _ in 0..BISECTION_STEPS {
        let mid = (t_lo * t_hi).sqrt();
        if !(mid > t_lo && mid < t_hi) {
            break;
        }
        if total(mid) <= texels {
            t_hi = mid;
        } else {
            t_lo = mid;
        }
    }
    for (s, e) in sizes.iter_mut().zip(aliasing) {
        *s = round_down(budget.sizes, (e / t_hi).clamp(lo as f64, hi as f64), lo);
    }
    spend_rest(aliasing, budget, hi, sizes);
    Ok(())
}

/// The largest allowed size at most `x` (and at least `lo`, itself allowed).
fn round_down(sizes: MapSizes, x: f64, lo: u32) -> u32 {
    let s = (x.floor() as u32).max(lo);
    match sizes {
        MapSizes::Any => s,
        MapSizes::PowerOfTwo => (1u32 << s.ilog2()).max(lo),
    }
}

/// The next allowed size above `s`.
fn step_up(sizes: MapSizes, s: u32) -> u32 {
    match sizes {
        MapSizes::Any => s + 1,
        MapSizes::PowerOfTwo => s * 2,
    }
}

/// Hands the texels the rounding left, one step at a time, to the map of
/// largest `aliasing / size` whose next size fits (at most `hi`).
///
/// NOTE: every step raises one size and sizes are bounded by `hi`, so the
/// loop ends; after rounding down, what is left is less than one step of
/// every map, so in practice each map steps at most once or twice.
fn spend_rest(aliasing: &[f64], budget: TexelBudget, hi: u32, sizes: &mut [u32]) {
    let mut used: u64 = sizes.iter().map(|&s| u64::from(s).pow(2)).sum();
    loop {
        let mut best: Option<(usize, f64)> = None;
        for (k, (&s, &e)) in sizes.iter().zip(aliasing).enumerate() {
            let up = step_up(budget.sizes, s);
            let cost = u64::from(up).pow(2) - u64::from(s).pow(2);
            if up <= hi && used + cost <= budget.texels && best.is_none_or(|(_, b)| e / s as f64 > b) {
                best = Some((k, e / s as f64));
            }
        }
        let Some((k, _)) = best else { return };
        let up = step_up(budget.sizes, sizes[k]);
        used += u64::from(up).pow(2) - u64::from(sizes[k]).pow(2);
        sizes[k] = up;
    }
}

/// Rescales a receiver footprint fitted `was` texels wide so that its margin
/// is `margin` texels of the map's new size: the receivers filled
/// `[−1/g, 1/g]²` of the image with `g = margin_grow(margin, was)`, and the
/// `x`, `y` rows scaled by `g / g'` make that `[−1/g', 1/g']²`.
///
/// NOTE: the crop's rounding margins are relative to the image's extent
/// and scale with it; the one rounding of each product (u₆₄) is far inside
/// them. With no margin, `g = g' = 1` and the rows are unchanged.
fn keep_margin(map: &mut crate::result::ShadowMap, margin: f64, was: u32, origin: glam::DVec3) {
    let s = margin_grow(margin, was) / margin_grow(margin, map.fit.resolution);
    let m = &mut map.fit.clip_from_world;
    let scale = DVec4::new(s, s, 1.0, 1.0);
    // Rows 0 and 1 are the x and y of every column.
    for c in [&mut m.x_axis, &mut m.y_axis, &mut m.z_axis, &mut m.w_axis] {
        *c *= scale;
    }
    map.fit.clip_from_world_f32 = crate::project::f32_matrix(m, origin);
}

#[cfg(test)]
mod tests {
    use super::*;

    const POW2: MapSizes = MapSizes::PowerOfTwo;

    fn sizes_for(aliasing: &[f64], texels: u64, sizes: MapSizes, bounds: [u32; 2]) -> Vec<u32> {
        let mut out = vec![0; aliasing.len()];
        allocate(aliasing, TexelBudget { texels, sizes }, bounds, &mut out).unwrap();
        out
    }

    fn worst(aliasing: &[f64], sizes: &[u32]) -> f64 {
        aliasing.iter().zip(sizes).map(|(e, &s)| e / s as f64).fold(0.0, f64::max)
    }

    #[test]
    fn equal_aliasing_shares_equally() {
        assert_eq!(sizes_for(&[1.0; 4], 4 * 1024 * 1024, POW2, [4, 4096]), [1024; 4]);
        assert_eq!(sizes_for(&[3.0; 4], 4 * 1000 * 1000, MapSizes::Any, [4, 4096]), [1000; 4]);
    }

    #[test]
    fn sizes_follow_the_aliasing() {
        // e = 2:1 → sides 2:1, Σ s² = 5 s₁² = 5·1024².
        assert_eq!(sizes_for(&[2.0, 1.0], 5 * 1024 * 1024, MapSizes::Any, [4, 8192]), [2048, 1024]);
        assert_eq!(sizes_for(&[2.0, 1.0], 5 * 1024 * 1024, POW2, [4, 8192]), [2048, 1024]);
    }

    #[test]
    fn the_budget_is_never_exceeded_and_no_map_could_grow() {
        let cases: [&[f64]; 4] = [&[1.0, 0.3, 7.0, 2.2], &[5.0], &[1e-9, 1.0, 1e9], &[0.5, 0.5, 0.51]];
        for aliasing in cases {
            for texels in [1000u64, 65_536, 3_000_000, 4 * 2048 * 2048, 1 << 40] {
                for sizes in [POW2, MapSizes::Any] {
                    let got = sizes_for(aliasing, texels, sizes, [4, 4096]);
                    let used: u64 = got.iter().map(|&s| u64::from(s).pow(2)).sum();
                    assert!(used <= texels, "{aliasing:?} {texels} {sizes:?}: {got:?} uses {used}");
                    for (k, &s) in got.iter().enumerate() {
                        assert!((4..=4096).contains(&s), "{got:?}");
                        assert!(sizes == MapSizes::Any || s.is_power_of_two(), "{got:?}");
                        // The map with the worst aliasing cannot take one more step.
                        if aliasing[k] / s as f64 == worst(aliasing, &got) {
                            let up = step_up(sizes, s);
                            assert!(up > 4096 || used - u64::from(s).pow(2) + u64::from(up).pow(2) > texels, "{got:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn no_other_sizes_within_the_budget_do_better() {
        // Exhaustive over powers of two for three maps.
        let aliasing = [3.0, 1.0, 0.4];
        let texels = 3 * 512 * 512;
        let got = sizes_for(&aliasing, texels, POW2, [4, 2048]);
        let pow2: Vec<u32> = (2..=11).map(|k| 1 << k).collect();
        for &a in &pow2 {
            for &b in &pow2 {
                for &c in &pow2 {
                    let s = [a, b, c];
                    if s.iter().map(|&x| u64::from(x).pow(2)).sum::<u64>() <= texels {
                        assert!(worst(&aliasing, &got) <= worst(&aliasing, &s) + 1e-12, "{got:?} vs {s:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn too_small_a_budget_is_refused() {
        let mut out = [0; 3];
        let err = allocate(&[1.0; 3], TexelBudget { texels: 47, sizes: POW2 }, [4, 64], &mut out).unwrap_err();
        assert!(err.to_string().contains("texel_budget.texels"), "{err}");
    }

    #[test]
    fn no_map_falls_below_half_an_equal_share() {
        let any = TexelBudget { texels: 4 * 512 * 512, sizes: MapSizes::Any };
        assert_eq!(half_share(any, 4, 4096), 256);
        assert_eq!(half_share(TexelBudget { sizes: POW2, ..any }, 4, 4096), 256);
        assert_eq!(half_share(TexelBudget { texels: 3 * 700 * 700, sizes: POW2 }, 3, 4096), 512);
        assert_eq!(half_share(any, 4, 200), 200);
        // A map predicted 100× better than the others still gets half a share.
        let mut sizes = [0; 4];
        share_seen(&[1.0, 1.0, 1.0, 0.01], any, [half_share(any, 4, 2048), 2048], &mut sizes).unwrap();
        assert_eq!(sizes[3], 256, "{sizes:?}");
        assert!(sizes.iter().map(|&s| u64::from(s).pow(2)).sum::<u64>() <= any.texels);
    }

    #[test]
    fn bounds_keep_the_margin_and_the_sizes() {
        assert_eq!(size_bounds(POW2, 2.0, 2048), [16, 2048]);
        assert_eq!(size_bounds(POW2, 0.0, 3000), [4, 2048]);
        assert_eq!(size_bounds(MapSizes::Any, 2.5, 3000), [20, 3000]);
    }

    #[test]
    fn unseen_maps_keep_an_equal_share() {
        let budget = TexelBudget { texels: 4 * 512 * 512, sizes: MapSizes::Any };
        let mut sizes = [0; 4];
        share_seen(&[0.0, 2.0, 1.0, 0.0], budget, [4, 2048], &mut sizes).unwrap();
        // The two seen maps share 2·512² as 2:1.
        assert_eq!(sizes[0], 512);
        assert_eq!(sizes[3], 512);
        assert!(sizes[1] * sizes[1] + sizes[2] * sizes[2] <= 2 * 512 * 512, "{sizes:?}");
        assert!((647..=648).contains(&sizes[1]) && (323..=326).contains(&sizes[2]), "{sizes:?}");
        share_seen(&[0.0; 4], budget, [4, 2048], &mut sizes).unwrap();
        assert_eq!(sizes, [512; 4]);
        // Too small a budget for the seen maps once the unseen ones have theirs.
        let tight = TexelBudget { texels: 3 * 16 - 8, sizes: MapSizes::Any };
        assert!(share_seen(&[0.0, 1.0, 1.0], tight, [4, 2048], &mut sizes[..3]).is_err());
    }
}
