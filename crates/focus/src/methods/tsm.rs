//! TSM [TSM04]: the trapezoid around the body's image whose top line is
//! its near end, with the focus point mapped to the 80 % line.

use super::warp::{warped, Frame, ShareSlot};
use super::{image, Fitted, SplitView};
use crate::state::WarpHold;
use shadowfocus_geom::{Body, Light};

/// The TSM map of `body` (`share`: see [`ShareSlot`]).
pub(super) fn tsm(sv: &SplitView, light: &Light, body: &Body, hold: &WarpHold, share: &mut ShareSlot) -> Option<Fitted> {
    let s = sv.settings;
    let cam = sv.camera;
    let f = sv.basis.forward;
    warped(sv, light, body, f, hold, share, |fr: &Frame| {
        let Frame { m, p_near, xi: (xi0, xi1), eta: (eta0, eta1), .. } = *fr;
        let zn = cam.near;
        // Top line at η0, base at η1 (λ apart); the focus point at depth
        // z_n + δ on the view axis (δ' past the top line) goes to the 80 %
        // line: with u(t) = (t/(η+t)) / (λ/(η+λ)) = 0.8 at t = δ' the apex
        // distance is η = 0.2 λ δ' / (0.8 λ − δ'); ε = 1/η.
        let lambda = eta1 - eta0;
        let p_focus = cam.eye + f * (zn + s.tsm.focus * (cam.far - zn));
        let (_, ef, wf) = image(&m, p_focus);
        let eps = if lambda > 0.0 && wf > 0.0 {
            // NOTE: δ' ≥ λ/32 keeps the apex at least ~0.8 % of λ before
            // the top line (δ' → 0 would put it on the top line).
            let dp = (ef - eta0).max(lambda / 32.0);
            if dp >= 0.8 * lambda {
                0.0
            } else {
                (0.8 * lambda - dp) / (0.2 * lambda * dp)
            }
        } else {
            0.0
        };
        // The centre line passes through the projected near-plane centre.
        let (xn, _, wn) = image(&m, p_near);
        let xi_c = if wn > 0.0 { xn } else { 0.5 * (xi0 + xi1) };
        (eps, xi_c)
    })
}
