//! LiSPSM [LISPSM04]: a perspective warp in the light's image plane with
//! its projection centre at `n_opt` before the body's near end, as the
//! practical formulation gives it [SCH05]; the warp direction is the view
//! direction or the middle vector.

use super::warp::{swept_warp, warped, Frame, ShareSlot};
use super::{image, image_scale, Fitted, SplitView};
use crate::predict::{Predicted, Samples};
use crate::settings::WarpDirection;
use crate::state::WarpHold;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Body, Camera, Dimension, Light};

/// The LiSPSM map of `body` (`share`: see [`ShareSlot`]).
pub(super) fn lispsm(sv: &SplitView, light: &Light, body: &Body, hold: &WarpHold, share: &mut ShareSlot) -> Option<Fitted> {
    let v = warp_direction(sv, body);
    warped(sv, light, body, v, hold, share, |fr: &Frame| n_opt_warp(sv, body, v, fr))
}

/// LiSPSM with its warp strength swept instead of `n_opt`'s, for
/// [`crate::Method::Auto`]: the map whose predicted maximum aliasing over
/// `samples` is least (see [`swept_warp`]), with its prediction.
pub(super) fn lispsm_swept(
    sv: &SplitView,
    light: &Light,
    body: &Body,
    share: &mut ShareSlot,
    samples: &Samples,
) -> Option<(Fitted, Predicted)> {
    let v = warp_direction(sv, body);
    swept_warp(sv, light, body, v, share, samples, |fr: &Frame| n_opt_warp(sv, body, v, fr))
}

/// The warp's view vector: the view direction or the middle vector.
fn warp_direction(sv: &SplitView, body: &Body) -> DVec3 {
    let f = sv.basis.forward;
    match sv.settings.lispsm.warp {
        WarpDirection::MiddleVector => (centroid(body) - sv.camera.eye).try_normalize().unwrap_or(f),
        WarpDirection::ViewProjected => f,
    }
}

/// `(ε, ξ_c)` of `n_opt` [SCH05] in the frame `fr` along `v`.
fn n_opt_warp(sv: &SplitView, body: &Body, v: DVec3, fr: &Frame) -> (f64, f64) {
    let s = sv.settings;
    let cam = sv.camera;
    let f = sv.basis.forward;
    let verts = body.vertices();
    let Frame { m, lp, p_ref, eta: (eta0, eta1), .. } = *fr;
    let zn = cam.near;
    let kappa = image_scale(&m, p_ref);
    let travel = (p_ref * lp.w - lp.truncate()).normalize_or_zero();
    // sin γ, γ the angle between the light and the (warp) view vector.
    let sin_g = v.cross(travel).length();
    let zmin = verts.iter().map(|p| f.dot(*p - cam.eye)).fold(f64::INFINITY, f64::min);
    // z0: view depth of H's nearest point, not before the near plane.
    let z0 = zmin.max(zn);
    let mut dz = if kappa > 0.0 { (eta1 - eta0) / kappa } else { 0.0 };
    if let Some(vf) = s.lispsm.visible_far {
        if vf < cam.far && kappa > 0.0 {
            dz = dz.min(visible_extent(&m, cam, vf) / kappa);
        }
    }
    // ε = 1/n_opt = sin γ / (z_n + √(z0 (z0 + Δz))): no division by
    // sin γ, so γ → 0 fades continuously into ε = 0 (uniform).
    let eps_world = sin_g / (zn + (z0 * (z0 + dz)).sqrt());
    let eps = if kappa > 0.0 && eps_world.is_finite() { eps_world / kappa } else { 0.0 };
    let (xe, _, we) = image(&m, cam.eye);
    let xi_c = if we > 0.0 { xe } else { image(&m, p_ref).0 };
    (eps, xi_c)
}

/// Centroid of the body (volume, area, length or point), a continuous
/// function of `H`, used as the end of LiSPSM's middle vector.
fn centroid(body: &Body) -> DVec3 {
    let v = body.vertices();
    match body.dimension() {
        Dimension::Empty => DVec3::ZERO,
        Dimension::Point => v[0],
        Dimension::Segment => (v[0] + v[v.len() - 1]) * 0.5,
        Dimension::Polygon | Dimension::Solid => {
            let r = v[0];
            let solid = body.dimension() == Dimension::Solid;
            let (mut acc, mut wsum) = (DVec3::ZERO, 0.0);
            for f in body.faces() {
                let a = v[f[0] as usize] - r;
                for k in 1..f.len() - 1 {
                    let b = v[f[k] as usize] - r;
                    let c = v[f[k + 1] as usize] - r;
                    if solid {
                        // Tetrahedron (r, a, b, c): signed volume, centroid.
                        let w = a.dot(b.cross(c));
                        acc += (a + b + c) * (0.25 * w);
                        wsum += w;
                    } else {
                        let w = (b - a).cross(c - a).length();
                        acc += (a + b + c) * (w / 3.0);
                        wsum += w;
                    }
                }
            }
            if wsum > 0.0 {
                r + acc / wsum
            } else {
                v.iter().copied().sum::<DVec3>() / v.len() as f64
            }
        }
    }
}

/// η extent of the view frustum cut at the visible far distance.
fn visible_extent(m: &DMat4, cam: &Camera, visible_far: f64) -> f64 {
    let far = visible_far.max(cam.near * (1.0 + 1e-9));
    let c = Camera { far, ..*cam };
    let Ok(corners) = c.corners() else { return f64::INFINITY };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in corners {
        let (_, eta, w) = image(m, p);
        if !(w > 0.0) {
            return f64::INFINITY;
        }
        lo = lo.min(eta);
        hi = hi.max(eta);
    }
    hi - lo
}
