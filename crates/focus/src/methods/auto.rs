//! [`Method::Auto`]: per map, the parameterisation with the least
//! predicted maximum aliasing.
//!
//! Every candidate — the uniform map, LiSPSM, TSM and PSM, each with its
//! own warp guard (so each is already no worse than the uniform map by the
//! prediction) — is fitted to the same body and judged on the same receiver
//! samples ([`Samples`]: where nine camera rays leave the body's box on a
//! face the light reaches, with the receivers' normals there, the warp
//! guard's own). The least predicted
//! maximum wins; a tie goes to the earlier candidate, so the uniform map is
//! kept unless a warp is strictly better. Without samples (the split sees
//! nothing of the body's box) the uniform map is kept.
//!
//! For a single map over the whole view, LiSPSM's warp strength is then
//! swept continuously above `n_opt`'s (`warp::swept_warp`): `n_opt` balances
//! the view's near and far ends on the view axis, the swept warp on the
//! receiver samples. The swept map replaces the best candidate where its
//! predicted maximum is lower and its mean and typical sample are no worse.
//! Splits are not swept: a split spans a bounded depth ratio, where `n_opt`
//! is already close to the balance (with four splits on fixed planes the
//! sweep changed no built-in scene's render), and optimal planes are placed
//! by refitting every split, where a sweep that switches on and off between
//! rounds moves the planes without lowering the worst split.
//!
//! NOTE: the prediction is the quantity the renderer measures per pixel up
//! to a factor common to every map of one light and one split (the screen
//! and map resolutions), so comparing the candidates needs no absolute
//! scale.

use super::lispsm::lispsm_swept;
use super::warp::ShareSlot;
use super::{fit_body_shared, light_point, Fitted, SplitView};
use crate::predict::{Predicted, Samples};
use crate::settings::{FocusSettings, Method};
use crate::state::Held;
use shadowfocus_geom::{Body, Light};

/// The candidates, in the order ties are broken.
const CANDIDATES: [Method; 4] = [Method::Uniform, Method::Lispsm, Method::Tsm, Method::Psm];

/// The candidate map of `body` with the least predicted maximum aliasing.
pub(super) fn auto(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let mut samples = Samples::new(sv, body, light_point(light));
    let mut best: Option<(Fitted, Predicted)> = None;
    // The uniform map, TSM and PSM share the light's frame along the view
    // direction, LiSPSM and its sweep the frame along its warp direction,
    // with their guards' references and samples (the maps are those each
    // fits alone, bit for bit); both guards judge the samples found here.
    let mut along_view = ShareSlot::with_samples(samples.clone());
    let mut along_warp = ShareSlot::with_samples(samples.clone());
    for method in CANDIDATES {
        let settings = FocusSettings { method, ..*sv.settings };
        let view = SplitView { camera: sv.camera, basis: sv.basis, settings: &settings, ground: sv.ground };
        let share = if method == Method::Lispsm { &mut along_warp } else { &mut along_view };
        let Some(f) = fit_body_shared(&view, light, body, &Held::NONE, share) else { continue };
        let predicted = if method == Method::Uniform { samples.judge(&f.m) } else { samples.predict(&f.m) };
        let Some(p) = predicted else {
            // Nothing to judge by: the uniform map, or the first that fits.
            if best.is_none() {
                return Some(f);
            }
            continue;
        };
        // NOTE: NaN (a sample the map cannot see) fails the comparison.
        if best.as_ref().is_none_or(|(_, b)| p.max < b.max) {
            best = Some((f, p));
        }
    }
    // LiSPSM with its warp strength swept, for a map that covers the whole
    // view: taken where it lowers the best maximum and is no worse in the
    // mean and the typical sample either.
    if sv.settings.splits.count == 1 {
        let settings = FocusSettings { method: Method::Lispsm, ..*sv.settings };
        let view = SplitView { camera: sv.camera, basis: sv.basis, settings: &settings, ground: sv.ground };
        if let Some((f, p)) = lispsm_swept(&view, light, body, &mut along_warp, &samples) {
            if best.as_ref().is_some_and(|(_, b)| p.max < b.max && p.no_worse_than(b)) {
                best = Some((f, p));
            }
        }
    }
    best.map(|(f, _)| f)
}
