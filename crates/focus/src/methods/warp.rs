//! What LiSPSM and TSM share [LISPSM04, TSM04]: the light's image turned
//! so that image `y` runs along the view direction, the body's extent in
//! it, and the guarded choice of the warp's strength ([`choose_warp`]).

use super::stable_warp::stable_warped;
use super::uniform::uniform_from;
use super::{image, light_point, light_space, rotate_image, Fitted, SplitView};
use crate::predict::{Predicted, Samples};
use crate::project::{apply_warp, crop, crop_estimate, h, Warp};
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
/// (see [`WarpShare`]); pass `&mut None` for one warp.
pub(super) fn warped(
    sv: &SplitView,
    light: &Light,
    body: &Body,
    v: DVec3,
    hold: &WarpHold,
    share: &mut Option<WarpShare>,
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
}

impl WarpShare {
    /// The share for `v` in `slot`, made anew where it holds another
    /// vector's; `None` where the light has no central projection.
    pub(super) fn along<'a>(
        slot: &'a mut Option<WarpShare>,
        sv: &SplitView,
        light: &Light,
        body: &Body,
        v: DVec3,
    ) -> Option<&'a mut WarpShare> {
        if slot.as_ref().is_none_or(|w| w.v != v) {
            let c = light_space(sv, light, body.vertices(), v)?;
            *slot = Some(WarpShare { v, central: c.m, centre: c.centre, frame: None, reference: None, guard: None });
        }
        slot.as_mut()
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
        self.guard.get_or_insert_with(|| {
            let mut samples = Samples::new(sv, body);
            let target = samples.judge(reference, light_point(light));
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
        let better = match target {
            // No sample to judge by (the split sees nothing of the body's
            // box): the warp as designed.
            None => true,
            // NOTE: candidates are judged on their estimated crop (the same
            // texel sizes to a few ulps); only the one kept is cropped.
            Some(t) => crop_estimate(&warped, verts).and_then(|e| samples.predict(&e)).is_some_and(|p| p.no_worse_than(t)),
        };
        if !better {
            continue;
        }
        // NOTE: a strong warp can make w all but vanish at a vertex next to
        // the apex, below what f32 resolves; a warp may not cost the f32
        // guarantee that the uniform map keeps, so a weaker one is tried.
        if let Some(cropped) = crop(&warped, verts, s.f32_origin, s.clip).filter(|c| c.f32_exact || !reference.f32_exact) {
            let mut out = Fitted::plain(cropped, s.method);
            out.warp_near = 1.0 / epsilon;
            out.warp_limited = k > 0;
            return Some(out);
        }
    }
    best.warp_limited = true;
    Some(best)
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
