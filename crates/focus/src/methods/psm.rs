//! Perspective shadow maps [PSM02]: a uniform map in the camera's
//! post-perspective space, with the virtual camera shift, weakened by
//! longer shifts where the prediction says it would alias more than the
//! uniform map.

use super::warp::{ShareSlot, WarpShare};
use super::{light_point, orient, Fitted, SplitView};
#[cfg(doc)]
use crate::predict::Predicted;
use crate::project::{central_projection, crop, h, post_perspective, DepthKind};
use crate::settings::Method;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Body, Light, MAX_VERTICES};

/// PSM: a uniform map from the transformed light in the camera's
/// post-perspective space [PSM02 §3], with the virtual camera shift of
/// [PSM02 §4.2].
///
/// Shift: with `z_min` the smallest view depth over `H`, the projection
/// centre moves back by `max(0, n − z_min)`: the least shift that puts all
/// of `H` beyond the (kept) near distance, hence in front of the centre —
/// and none when `H` already lies beyond the near plane. Every vertex then
/// has clip `w ≥ n > 0`, so nothing crosses `w = 0` and the divide is safe.
///
/// The light `L' = C'·L` stays homogeneous: a point light (`L'.w > 0`), a
/// directional light on or off the infinity plane (`L'.w = 0` when it is
/// parallel to the image plane, or a point light in the camera plane), or an
/// inverted light (`L'.w < 0`, behind the camera): the central projection
/// handles all three with one formula, and the depth row's sign against
/// `L'` gives the reversed test for the inverted case.
///
/// With the warp guard on, a PSM map predicted to alias more than the
/// uniform map ([`Predicted::no_worse_than`]) is weakened by shifting the
/// centre further back: with the extra shift `s`, `H` spans view depths
/// `[z_min + s, z_max + s]` from the shifted centre, whose ratio tends to 1,
/// so the post-perspective image tends to an affine one and the map to the
/// uniform one. The extra shifts are `Δz·4^(k−2)` for `k = 1 … PSM_STEPS−1`
/// (`Δz = z_max − z_min`), from a quarter of H's depth to sixteen times it;
/// the first that the prediction accepts is kept, else the uniform map,
/// marked as PSM's fallback (`psm_fell_back`). `None` only where no PSM
/// projection exists (the caller then fits the uniform map).
pub(super) fn psm(sv: &SplitView, light: &Light, body: &Body, share: &mut ShareSlot) -> Option<Fitted> {
    let cam = sv.camera;
    let b = &sv.basis;
    let verts = body.vertices();
    let depth = |p: &DVec3| b.forward.dot(*p - cam.eye);
    let zmin = verts.iter().map(depth).fold(f64::INFINITY, f64::min);
    let zmax = verts.iter().map(depth).fold(f64::NEG_INFINITY, f64::max);
    // NOTE: vertices on the near plane come back with depths a few ulps on
    // either side of `near`; such rounding noise is not a reach behind the
    // near plane. ρ bounds the error of the rounded vertex and of the dot
    // product (relative 16 ε of the magnitudes involved).
    let mag = verts.iter().map(|p| p.abs().max_element()).fold(0.0, f64::max) + cam.eye.abs().max_element();
    let rho = 16.0 * f64::EPSILON * (mag + cam.near);
    let shift = if zmin < cam.near - rho { cam.near - zmin } else { 0.0 };
    let plain = |(m, inverted): (DMat4, bool), shift: f64| {
        crop(&m, verts, sv.settings.f32_origin, sv.settings.clip).map(|c| Fitted {
            psm_shift: shift,
            inverted,
            ..Fitted::plain(c, Method::Psm)
        })
    };
    if !sv.settings.warp_guard {
        return plain(psm_map(sv, light, body, shift)?, shift);
    }
    // The uniform map and the judged samples: `uniform`'s and the warps'
    // own (see `WarpShare`).
    let share = WarpShare::along(share, sv, light, body, sv.basis.forward)?;
    let reference = share.reference(sv, verts)?;
    let (samples, target) = share.guard(sv, light, body, &reference.m);
    // NOTE: with no sample to judge by, no PSM map is kept (see `choose_warp`).
    let Some(target) = *target else { return Some(Fitted { psm_fell_back: true, ..reference }) };
    let spread = zmax - zmin;
    for k in 0..PSM_STEPS {
        let s = shift + if k == 0 { 0.0 } else { spread * 4f64.powi(k - 2) };
        let Some(map) = psm_map(sv, light, body, s) else { continue };
        let accepted = samples.predict_estimated(&map.0, verts).is_some_and(|p| p.no_worse_than(&target));
        if let Some(out) = accepted.then(|| plain(map, s)).flatten() {
            return Some(Fitted { warp_limited: k > 0, ..out });
        }
        if !(spread > 0.0) {
            break;
        }
    }
    Some(Fitted { psm_fell_back: true, ..reference })
}

/// PSM shifts tried before the uniform map: the least one, then four
/// growing by 4× from a quarter of H's depth.
const PSM_STEPS: i32 = 5;

/// The PSM projection of `body` with the camera's centre moved back by
/// `shift` (one that keeps every vertex in front of it), oriented, not yet
/// cropped; and whether its light is inverted (`L'.w < 0`, the sign the
/// polar depth row was built with: its depth then grows toward the light).
fn psm_map(sv: &SplitView, light: &Light, body: &Body, shift: f64) -> Option<(DMat4, bool)> {
    let verts = body.vertices();
    let c = post_perspective(sv.camera, &sv.basis, shift);
    let mut pts = [DVec3::ZERO; MAX_VERTICES];
    for (i, p) in verts.iter().enumerate() {
        let q = c * h(*p);
        if !(q.w > 0.0) {
            return None;
        }
        pts[i] = q.truncate() / q.w;
    }
    let lp = c * light_point(light);
    let v = DVec3::Z; // the view direction in post-perspective space
    let w = DVec3::new(1.0, 1.0, 0.0).normalize();
    // For a directional light every point of H' lies before the infinity
    // plane z = (f + n)/(f − n), which holds L': its normal is a valid axis
    // however wide the cone (a fallback; the maximin axis is tried first).
    let hint = (lp.w != 0.0).then(|| DVec3::new(0.0, 0.0, -lp.w.signum()));
    let lam = central_projection(lp, &pts[..verts.len()], DepthKind::Polar, v, w, hint)?;
    Some((orient(&(lam.m * c), verts, sv), lp.w < 0.0))
}
