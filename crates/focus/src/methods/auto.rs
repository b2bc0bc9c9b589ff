//! [`Method::Auto`]: per map, the parameterisation with the least
//! predicted maximum aliasing.
//!
//! Every candidate — the uniform map, LiSPSM, TSM and PSM, each with its
//! own warp guard (so each is already no worse than the uniform map by the
//! prediction) — is fitted to the same body and judged on the same receiver
//! samples ([`Samples`]: where nine camera rays leave the body's box, with
//! the receivers' normals there, the warp guard's own). The least predicted maximum wins; a tie
//! goes to the earlier candidate, so the uniform map is kept unless a warp
//! is strictly better. Without samples (the split sees nothing of the
//! body's box) the uniform map is kept.
//!
//! NOTE: the prediction is the quantity the renderer measures per pixel up
//! to a factor common to every map of one light and one split (the screen
//! and map resolutions), so comparing the candidates needs no absolute
//! scale.

use super::{fit_body_shared, light_point, Fitted, SplitView};
use crate::predict::Samples;
use crate::settings::{FocusSettings, Method};
use crate::state::Held;
use shadowfocus_geom::{Body, Light};

/// The candidates, in the order ties are broken.
const CANDIDATES: [Method; 4] = [Method::Uniform, Method::Lispsm, Method::Tsm, Method::Psm];

/// The candidate map of `body` with the least predicted maximum aliasing.
pub(super) fn auto(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let lp = light_point(light);
    let mut samples = Samples::new(sv, body);
    let mut best: Option<(Fitted, f64)> = None;
    // LiSPSM and TSM along the same view vector share their frame and
    // their guard's reference and samples (the maps are those each fits
    // alone, bit for bit).
    let mut share = None;
    for method in CANDIDATES {
        let settings = FocusSettings { method, ..*sv.settings };
        let view = SplitView { camera: sv.camera, basis: sv.basis, settings: &settings };
        let Some(f) = fit_body_shared(&view, light, body, &Held::NONE, &mut share) else { continue };
        let predicted = if method == Method::Uniform { samples.judge(&f.m, lp) } else { samples.predict(&f.m) };
        let Some(p) = predicted else {
            // Nothing to judge by: the uniform map, or the first that fits.
            if best.is_none() {
                return Some(f);
            }
            continue;
        };
        // NOTE: NaN (a sample the map cannot see) fails the comparison.
        if best.as_ref().is_none_or(|(_, max)| p.max < *max) {
            best = Some((f, p.max));
        }
    }
    best.map(|(f, _)| f)
}
