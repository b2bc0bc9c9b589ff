//! What LiSPSM and TSM share [LISPSM04, TSM04]: the light's image turned
//! so that image `y` runs along the view direction, the body's extent in
//! it, and the guarded choice of the warp's strength ([`choose_warp`]).

use super::stable_warp::stable_warped;
use super::uniform::uniform_from;
use super::{image, light_point, light_space, rotate_image, Fitted, SplitView};
use crate::predict::{Predicted, Samples};
use crate::project::{apply_warp, crop, h, Cropped, Warp};
use crate::settings::MapOrientation;
use crate::state::WarpHold;
use glam::{DMat4, DVec2, DVec3, DVec4};
use shadowfocus_geom::{Body, Light};

/// The light's image along the warp's view direction `v`, as both warps
/// read it.
#[derive(Clone, Copy)]
pub(super) struct Frame {
    /// The light's image, rows `x`, `y` turned so that `y` follows `v`.
    pub m: DMat4,
    /// The light as an oriented homogeneous point.
    pub lp: DVec4,
    /// The centre of the camera's near plane.
    pub p_near: DVec3,
    /// A point the light map sees: `p_near`, else the body's centre.
    pub p_ref: DVec3,
    /// The body's image extent: `(ξ0, ξ1)` across the warp, `(η0, η1)` along it.
    pub xi: (f64, f64),
    pub eta: (f64, f64),
}

/// LiSPSM or TSM along `v`: `warp_of` gives the warp's strength `ε` and
/// its centre line `ξ_c` in the frame, [`choose_warp`] the map. Where `v`
/// has no image direction (all but parallel to the light) the map is the
/// uniform one, marked as a vanished warp. Stable maps of a directional
/// light are [`stable_warped`]'s, holding the steps of `hold`. `share`
/// keeps what a second warp along the same `v` for the same body reuses
/// (see [`WarpShare`]); pass an empty [`ShareSlot`] for one warp.
pub(super) fn warped(
    sv: &SplitView,
    light: &Light,
    body: &Body,
    v: DVec3,
    hold: &WarpHold,
    share: &mut ShareSlot,
    warp_of: impl FnOnce(&Frame) -> (f64, f64),
) -> Option<Fitted> {
    let s = sv.settings;
    if s.stable_warp() && matches!(light, Light::Directional { .. }) {
        return stable_warped(sv, light, body, v, hold, warp_of);
    }
    let share = WarpShare::along(share, sv, light, body, v)?;
    let verts = body.vertices();
    let Some(frame) = share.frame(sv, light, verts) else {
        return share.reference(sv, verts).map(|u| Fitted { method: s.method, warp_vanished: true, ..u });
    };
    let (epsilon, xi_c) = warp_of(&frame);
    let epsilon = if epsilon.is_finite() && epsilon > 0.0 { epsilon } else { 0.0 };
    choose_warp(sv, light, body, share, &frame.m, Warp { epsilon, xi_c, eta0: frame.eta.0 })
}

/// What every map along one view vector `v` of one body shares, computed
/// once for [`crate::Method::Auto`]'s candidates: the light's central
/// projection, its frame along `v`, the uniform map of that projection (the
/// uniform candidate itself, for `v` the view direction) and the warp
/// guard's receiver samples judged against it. Each is computed on first
/// use exactly as a single fit computes it, so the maps are bit for bit
/// those each method fits alone.
pub(super) struct WarpShare {
    pub(super) v: DVec3,
    central: DMat4,
    /// The body's centre, for a point the light map sees.
    centre: DVec3,
    /// `Some(None)` where `v` has no image direction.
    frame: Option<Option<Frame>>,
    reference: Option<Option<Fitted>>,
    guard: Option<(Samples, Option<Predicted>)>,
    /// The guard's samples before judging, where the slot had them.
    unjudged: Option<Samples>,
}

/// Where the [`WarpShare`] of one body lives between the maps that share
/// it, with the guard's receiver samples before any map judged them, where
/// the caller has them already (Auto's candidates along two vectors: the
/// samples depend on the split, the body and the light only).
#[derive(Default)]
pub(super) struct ShareSlot {
    share: Option<WarpShare>,
    samples: Option<Samples>,
}

impl ShareSlot {
    /// A slot whose first share's guard judges `samples` (those
    /// [`Samples::new`] gives for the same split, body and light) instead of
    /// finding them again; a share made anew for another vector finds its own.
    pub(super) fn with_samples(samples: Samples) -> ShareSlot {
        ShareSlot { share: None, samples: Some(samples) }
    }
}

impl WarpShare {
    /// The share for `v` in `slot`, made anew where it holds another
    /// vector's; `None` where the light has no central projection.
    pub(super) fn along<'a>(slot: &'a mut ShareSlot, sv: &SplitView, light: &Light, body: &Body, v: DVec3) -> Option<&'a mut WarpShare> {
        if slot.share.as_ref().is_none_or(|w| w.v != v) {
            let c = light_space(sv, light, body.vertices(), v)?;
            slot.share = Some(WarpShare {
                v,
                central: c.m,
                centre: c.centre,
                frame: None,
                reference: None,
                guard: None,
                unjudged: slot.samples.take(),
            });
        }
        slot.share.as_mut()
    }

    /// The light's image turned along `v`, with the body's extent in it.
    fn frame(&mut self, sv: &SplitView, light: &Light, verts: &[DVec3]) -> Option<Frame> {
        let (central, centre, v) = (self.central, self.centre, self.v);
        *self.frame.get_or_insert_with(|| {
            let cam = sv.camera;
            let p_near = cam.eye + sv.basis.forward * cam.near;
            // A reference point the light map sees: the near-plane centre, else the
            // body's centre (a point light beside the eye can have w ≤ 0 there).
            let p_ref = if image(&central, p_near).2 > 0.0 { p_near } else { centre };
            // The warp runs along the image of the view direction [LISPSM04]: image
            // `y` is turned onto it. Where the view direction is (nearly) parallel
            // to the light it has no image direction and the warp no effect.
            let aligned = match sv.settings.orientation {
                MapOrientation::LeastArea => align_to(&central, p_ref, v),
                MapOrientation::ViewAligned => Some(central),
            };
            aligned.map(|m| {
                let (mut eta0, mut eta1) = (f64::INFINITY, f64::NEG_INFINITY);
                let (mut xi0, mut xi1) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in verts {
                    let (xi, eta, _) = image(&m, *p);
                    eta0 = eta0.min(eta);
                    eta1 = eta1.max(eta);
                    xi0 = xi0.min(xi);
                    xi1 = xi1.max(xi);
                }
                Frame { m, lp: light_point(light), p_near, p_ref, xi: (xi0, xi1), eta: (eta0, eta1) }
            })
        })
    }

    /// The uniform map of the central projection (the guard's reference).
    pub(super) fn reference(&mut self, sv: &SplitView, verts: &[DVec3]) -> Option<Fitted> {
        *self.reference.get_or_insert_with(|| uniform_from(&self.central, verts, sv))
    }

    /// The receiver samples of the body, judged against `reference`, and the
    /// reference's prediction.
    pub(super) fn guard(&mut self, sv: &SplitView, light: &Light, body: &Body, reference: &DMat4) -> &(Samples, Option<Predicted>) {
        let unjudged = &mut self.unjudged;
        self.guard.get_or_insert_with(|| {
            let mut samples = unjudged.take().unwrap_or_else(|| Samples::new(sv, body, light_point(light)));
            let target = samples.judge(reference);
            (samples, target)
        })
    }
}

/// Warp strengths tried before the uniform map: each halves ε.
const WARP_STEPS: i32 = 5;

/// The warp of `m` by `w`, or a weaker one, or the uniform map of the
/// central projection `central`: whichever is strongest among those whose
/// predicted aliasing ([`Samples`]) is no worse than the uniform map's
/// ([`Predicted::no_worse_than`]) and that keep the f32 guarantee where the
/// uniform map keeps it. Warps never lose to the uniform map by
/// construction; the weakening steps (ε, ε/2, …, ε/2^(WARP_STEPS−1), then
/// none) keep the choice close to continuous where the prediction crosses
/// over.
fn choose_warp(sv: &SplitView, light: &Light, body: &Body, share: &mut WarpShare, m: &DMat4, w: Warp) -> Option<Fitted> {
    let s = sv.settings;
    let verts = body.vertices();
    let reference = share.reference(sv, verts)?;
    let mut best = Fitted { method: s.method, warp_vanished: true, ..reference };
    if w.epsilon == 0.0 && s.orientation == MapOrientation::LeastArea {
        return Some(best);
    }
    if !s.warp_guard || w.epsilon == 0.0 {
        // The warp as designed (ε = 0: the unwarped map in the warp's frame).
        let cropped = match crop(&apply_warp(m, &w), verts, s.f32_origin, s.clip) {
            Some(c) => c,
            None if w.epsilon > 0.0 => return Some(best),
            None => return None,
        };
        let mut out = Fitted::plain(cropped, s.method);
        out.warp_near = if w.epsilon > 0.0 { 1.0 / w.epsilon } else { f64::INFINITY };
        out.warp_vanished = w.epsilon == 0.0;
        return Some(out);
    }
    let (samples, target) = share.guard(sv, light, body, &reference.m);
    for k in 0..WARP_STEPS {
        let epsilon = w.epsilon * 0.5f64.powi(k);
        let warped = apply_warp(m, &Warp { epsilon, ..w });
        // NOTE: candidates are judged on their estimated crop; only the one
        // kept is cropped. With no sample to judge by (no receiver box on
        // the camera rays through the split's body) no warp is kept: an
        // unjudged warp can alias several times more than the uniform map.
        let better = target.is_some_and(|t| samples.predict_estimated(&warped, verts).is_some_and(|p| p.no_worse_than(&t)));
        if !better {
            continue;
        }
        // A weaker warp is tried where this one would cost the f32 guarantee.
        if let Some(cropped) = crop_keeping_f32(sv, &warped, verts, &reference) {
            let mut out = Fitted::plain(cropped, s.method);
            out.warp_near = 1.0 / epsilon;
            out.warp_limited = k > 0;
            return Some(out);
        }
    }
    best.warp_limited = true;
    Some(best)
}

/// The warped map `m` cropped to `verts`, unless that costs the f32
/// guarantee (`Cropped::f32_exact`) the uniform map `reference` keeps.
///
/// NOTE: a strong warp can make `w` all but vanish at a vertex next to the
/// apex, below what f32 resolves; a warp may not cost the guarantee that
/// the uniform map keeps.
fn crop_keeping_f32(sv: &SplitView, m: &DMat4, verts: &[DVec3], reference: &Fitted) -> Option<Cropped> {
    crop(m, verts, sv.settings.f32_origin, sv.settings.clip).filter(|c| c.f32_exact || !reference.f32_exact)
}

/// Octaves of ε above the method's own that [`swept_warp`] walks, and the
/// golden-section steps that narrow the octave it stops in (each by 0.618).
const SWEEP_OCTAVES: i32 = 4;
const SWEEP_REFINE: u32 = 4;

/// The warp along `v` with its strength swept upward, for
/// [`crate::Method::Auto`]: of the warps `ε = ε_m · 2^k`, `ε_m` the
/// method's own (from `warp_of`) and `0 ≤ k ≤ SWEEP_OCTAVES` continuous,
/// the one with the least predicted maximum aliasing over the judged
/// `samples`, with its prediction; `None` where the method has no warp
/// (`ε_m = 0`), no warp sees every sample, or the best would cost the f32
/// guarantee that the uniform map keeps.
///
/// Only stronger warps are tried: the samples take each ray's receiver at
/// its far end or where it enters a receiver box, and a nearer receiver
/// favours a stronger warp, so the prediction errs toward weak warps. A
/// stronger warp it still prefers is preferred by the receivers actually
/// seen; a weaker one it prefers may be an artefact of the far samples
/// (the warp guard already weakens a warp the prediction finds worse than
/// the uniform map).
///
/// NOTE: each sample's aliasing is monotone in ε (a stronger warp enlarges
/// texels far from the apex and shrinks them near it), so their maximum
/// falls and then rises: a walk over whole octaves from `k = 0` brackets
/// its minimum, and golden-section steps narrow the bracket.
pub(super) fn swept_warp(
    sv: &SplitView,
    light: &Light,
    body: &Body,
    v: DVec3,
    share: &mut ShareSlot,
    samples: &Samples,
    warp_of: impl FnOnce(&Frame) -> (f64, f64),
) -> Option<(Fitted, Predicted)> {
    let s = sv.settings;
    let share = WarpShare::along(share, sv, light, body, v)?;
    let verts = body.vertices();
    let frame = share.frame(sv, light, verts)?;
    let reference = share.reference(sv, verts)?;
    let (eps_m, xi_c) = warp_of(&frame);
    if !(eps_m.is_finite() && eps_m > 0.0) {
        return None;
    }
    let warp = |k: f64| Warp { epsilon: eps_m * k.exp2(), xi_c, eta0: frame.eta.0 };
    // NOTE: a map that misses a sample (a NaN mean) scores infinity, so it
    // is never the least.
    let score = |k: f64| {
        let p = samples.predict_estimated(&apply_warp(&frame.m, &warp(k)), verts);
        p.filter(|p| p.mean.is_finite()).map_or(f64::INFINITY, |p| p.max)
    };
    let (k, at) = least_octave(score, SWEEP_OCTAVES);
    // NOTE: where neither the first octave nor half of it lowers the
    // score, the minimum of a score that falls and then rises lies close
    // to `k = 0`, the method's own map, which is a candidate already: three
    // scores spent, nothing swept.
    if k == 0.0 && !(score(0.5) < at) {
        return None;
    }
    let (k, at) = golden_section(score, (k - 1.0).max(0.0), (k + 1.0).min(SWEEP_OCTAVES as f64), SWEEP_REFINE, (k, at));
    if !at.is_finite() {
        return None;
    }
    let w = warp(k);
    let cropped = crop_keeping_f32(sv, &apply_warp(&frame.m, &w), verts, &reference)?;
    let predicted = samples.predict(&cropped.m)?;
    let mut out = Fitted::plain(cropped, s.method);
    out.warp_near = 1.0 / w.epsilon;
    Some((out, predicted))
}

/// The whole `k` in `0..=octaves` where `score` stops falling, walking up
/// from 0, with its score.
fn least_octave(score: impl Fn(f64) -> f64, octaves: i32) -> (f64, f64) {
    let (mut k, mut at) = (0.0, score(0.0));
    while k < octaves as f64 {
        let next = score(k + 1.0);
        if !(next < at) {
            break;
        }
        (k, at) = (k + 1.0, next);
    }
    (k, at)
}

/// Golden-section search for the least `score` on `[a, b]`, `steps`
/// steps; the best of its points and `start`.
fn golden_section(score: impl Fn(f64) -> f64, mut a: f64, mut b: f64, steps: u32, start: (f64, f64)) -> (f64, f64) {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let (mut c, mut d) = (b - INV_PHI * (b - a), a + INV_PHI * (b - a));
    let (mut fc, mut fd) = (score(c), score(d));
    for _ in 0..steps {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - INV_PHI * (b - a);
            fc = score(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + INV_PHI * (b - a);
            fd = score(d);
        }
    }
    [(c, fc), (d, fd)].into_iter().fold(start, |best, x| if x.1 < best.1 { x } else { best })
}

/// `m` turned so that image `y` follows the image of the direction `v` at
/// `p`; `None` where that image is shorter than 2⁻²⁶ of the image scale
/// (v all but parallel to the light ray at `p`).
fn align_to(m: &DMat4, p: DVec3, v: DVec3) -> Option<DMat4> {
    let q = *m * h(p);
    let dv = *m * v.extend(0.0);
    // d(x/w, y/w) along v: (ẋ w − x ẇ)/w², likewise for y.
    let d = DVec2::new(dv.x * q.w - q.x * dv.w, dv.y * q.w - q.y * dv.w);
    let scale = DVec2::new(m.row(0).truncate().length(), m.row(1).truncate().length()).max_element() * q.w.abs() * v.length();
    let len = d.length();
    if !(len > scale * (1.0 / (1u64 << 26) as f64)) {
        return None;
    }
    Some(rotate_image(m, d / len))
}

#[cfg(test)]
mod tests {
    use super::{golden_section, least_octave};

    #[test]
    fn the_octave_walk_brackets_a_v_shaped_minimum_and_the_section_narrows_it() {
        for m in [0.0, 0.37, 1.0, 2.6, 3.9] {
            let f = |k: f64| (k - m).abs();
            let (k, at) = least_octave(f, 4);
            assert!((k - m).abs() <= 1.0, "minimum {m}: octave {k}");
            let (g, fg) = golden_section(f, (k - 1.0).max(0.0), k + 1.0, 4, (k, at));
            assert!(fg <= at && (g - m).abs() <= 2.0 * 0.618_034f64.powi(4), "minimum {m}: {g}");
        }
        // Falling all the way: the last octave; rising from the start: 0.
        assert_eq!(least_octave(|k| -k, 4), (4.0, -4.0));
        assert_eq!(least_octave(|k| k, 4), (0.0, 0.0));
    }

    #[test]
    fn scores_that_are_never_finite_keep_the_start() {
        let (k, at) = least_octave(|_| f64::INFINITY, 4);
        assert_eq!((k, at), (0.0, f64::INFINITY));
        assert_eq!(golden_section(|_| f64::INFINITY, 0.0, 1.0, 4, (k, at)), (0.0, f64::INFINITY));
    }
}
