//! The four parameterisations, each turning one focus body into a matrix.
//!
//! All of them are `crop ∘ warp ∘ Λ`: `Λ` projects from the light
//! ([`central_projection`]; for PSM composed with the camera's
//! post-perspective transform), the warp is LiSPSM's or TSM's perspective in
//! the light's image plane (identity for uniform and PSM), and the crop fits
//! the body into the clip volume with rounding margins.

//!
//! One file per construction, named after it: `uniform`, `stable`, `psm`
//! [PSM02], `lispsm` [LISPSM04, SCH05], `tsm` [TSM04], `stable_warp` (LiSPSM
//! and TSM on world-fixed lattices); `warp` holds what LiSPSM and TSM share
//! (the light-space frame along the view direction and the guarded choice of
//! the warp's strength); `auto` chooses among them.

mod auto;
mod lispsm;
mod psm;
mod stable;
mod stable_warp;
mod tsm;
mod uniform;
mod warp;

use crate::frame::perpendicular_hint;
use crate::hull2::min_area_direction;
use crate::project::{central_projection, from_rows, h, image_points, Central, Cropped, DepthKind};
use crate::settings::{MapOrientation, Method};
pub(crate) use crate::split_view::SplitView;
use crate::state::Held;
use glam::{DMat4, DVec2, DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Light, MAX_VERTICES};

/// A fitted matrix and how it came about.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fitted {
    pub m: DMat4,
    pub method: Method,
    pub warp_near: f64,
    pub psm_shift: f64,
    /// LiSPSM/TSM ended with no warp.
    pub warp_vanished: bool,
    /// The warp was weakened (LiSPSM/TSM: ε; PSM: the shift), or given up
    /// for the uniform map, because the prediction said it would alias more
    /// (see `predict`).
    pub warp_limited: bool,
    pub psm_fell_back: bool,
    pub stable_ignored: bool,
    /// The steps a stable spot map (see `stable::stable_spot`) or a stable
    /// warped map (see `stable_warp`) chose, to hold in the next frame.
    pub held: Held,
    /// The f32 matrix keeps the body inside (see `project::crop`).
    pub f32_exact: bool,
    /// PSM's light is inverted: the depth row was built to grow toward the
    /// light (the polar row's sign σ = −1, see `project::DepthKind`).
    pub inverted: bool,
}

impl Fitted {
    pub(super) fn plain(c: Cropped, method: Method) -> Fitted {
        Fitted {
            m: c.m,
            f32_exact: c.f32_exact,
            method,
            warp_near: f64::INFINITY,
            psm_shift: 0.0,
            warp_vanished: false,
            warp_limited: false,
            psm_fell_back: false,
            stable_ignored: false,
            held: Held::NONE,
            inverted: false,
        }
    }
}

/// The light as an oriented homogeneous point: `(l, 1)` for point and spot
/// lights, `(−d̂, 0)` — the point at infinity the light comes from — for
/// directional ones (normalised without overflow or underflow, see
/// [`unit_direction`]).
pub(crate) fn light_point(light: &Light) -> DVec4 {
    match *light {
        Light::Directional { direction } => (-unit_direction(direction)).extend(0.0),
        Light::Point { position } | Light::Spot { position, .. } => position.extend(1.0),
    }
}

/// Axis of a spot light's frustum (apex → far-face centre).
fn spot_axis(light: &Light) -> Option<DVec3> {
    match light {
        Light::Spot { position, frustum } => {
            let c = frustum.corners();
            let far = (c[4] + c[5] + c[6] + c[7]) * 0.25;
            Some(far - *position)
        }
        _ => None,
    }
}

/// Fits `body` (non-empty) for `light` with the configured method; `hold`
/// is what the map's stable construction chose in the previous frame
/// ([`Held::NONE`]: nothing, see [`crate::FitState`]).
pub(crate) fn fit_body(sv: &SplitView, light: &Light, body: &Body, hold: &Held) -> Option<Fitted> {
    fit_body_shared(sv, light, body, hold, &mut warp::ShareSlot::default())
}

/// [`fit_body`], LiSPSM and TSM reusing what `share` holds for the same
/// body and view vector (see [`warp::WarpShare`]).
fn fit_body_shared(sv: &SplitView, light: &Light, body: &Body, hold: &Held, share: &mut warp::ShareSlot) -> Option<Fitted> {
    let s = sv.settings;
    let directional = matches!(light, Light::Directional { .. });
    let spot = matches!(light, Light::Spot { .. });
    let stable = s.stable_uniform();
    let mut out = match s.method {
        _ if stable && directional => stable::stable(sv, light, body),
        // NOTE: a stable spot map is the spot's own perspective, fixed in
        // the world; a warp in its image would follow the camera.
        _ if s.stable_applies() && spot => stable::stable_spot(sv, light, body, hold.step).map(|f| match s.stable_warp() {
            true => Fitted { method: s.method, warp_vanished: true, ..f },
            false => f,
        }),
        Method::Uniform => warp::WarpShare::along(share, sv, light, body, sv.basis.forward)?.reference(sv, body.vertices()),
        Method::Psm => match psm::psm(sv, light, body, share) {
            Some(f) => Some(f),
            None => uniform::uniform(sv, light, body).map(|mut f| {
                f.psm_fell_back = true;
                f
            }),
        },
        Method::Lispsm => lispsm::lispsm(sv, light, body, &hold.warp, share),
        Method::Tsm => tsm::tsm(sv, light, body, &hold.warp, share),
        Method::Auto => auto::auto(sv, light, body),
    }?;
    // Every method but PSM has stable maps (a point light's are its cube
    // faces, which are spots).
    out.stable_ignored |= s.stable && !s.stable_applies();
    Some(out)
}

/// Camera-relative image orientation: up follows the (projected) reference
/// `v`; the secondary reference is the camera's right+up diagonal, which
/// puts the frame's two singular light directions in the plane of the view
/// direction and that diagonal, about 11° off the view axis — away from
/// sweeps in the view/up and view/right planes.
pub(super) fn references(sv: &SplitView, v: DVec3) -> (DVec3, DVec3) {
    (v, perpendicular_hint(v, sv.basis.right + sv.basis.up))
}

pub(super) fn light_space(sv: &SplitView, light: &Light, verts: &[DVec3], v: DVec3) -> Option<Central> {
    let lp = light_point(light);
    let depth = if lp.w == 0.0 { DepthKind::Polar } else { DepthKind::Perspective };
    let (v, w) = references(sv, v);
    central_projection(lp, verts, depth, v, w, spot_axis(light))
}

/// `m` with its image rows `x`, `y` turned so that image `y` runs along the
/// unit image direction `dir`: `y' = d_x x + d_y y`, `x' = d_y x − d_x y`.
/// A rotation (determinant +1): the rows stay combinations of rows through
/// the light, so they still pass through it, and `z`, `w` are kept.
pub(super) fn rotate_image(m: &DMat4, dir: DVec2) -> DMat4 {
    let (x, y) = (m.row(0), m.row(1));
    from_rows(x * dir.y - y * dir.x, x * dir.x + y * dir.y, m.row(2), m.row(3))
}

/// `m` turned as the settings' [`MapOrientation`] asks.
pub(super) fn orient(m: &DMat4, verts: &[DVec3], sv: &SplitView) -> DMat4 {
    match sv.settings.orientation {
        MapOrientation::LeastArea => orient_min_area(m, verts),
        MapOrientation::ViewAligned => *m,
    }
}

/// `m` turned so that the rectangle of least area around the image of
/// `verts` is axis-aligned: the square map then fills with the body
/// ([PSM02]'s focusing, with the image orientation free; the rectangle
/// [FS75]). Of the four ways to
/// align it, the one nearest the current orientation (the least turn) is
/// kept, so the camera-relative orientation of `references` survives where
/// it is already a least-area one. `m` unchanged where a vertex has no
/// positive `w` (the crop refuses such a map anyway) or the image is a point.
pub(super) fn orient_min_area(m: &DMat4, verts: &[DVec3]) -> DMat4 {
    let mut q = [DVec2::ZERO; MAX_VERTICES];
    let Some(e) = image_points(m, verts, &mut q).and_then(min_area_direction) else { return *m };
    let perp = DVec2::new(-e.y, e.x);
    let dir = [e, -e, perp, -perp].into_iter().fold(e, |best, d| if d.y > best.y { d } else { best });
    rotate_image(m, dir)
}

/// Image coordinates `(ξ, η)` and `w` of a world point under `m`.
///
/// NOTE: one reciprocal instead of two divisions (an ulp more per
/// coordinate): image coordinates only choose the warp, and the crop that
/// follows makes the map conservative whatever they are.
pub(super) fn image(m: &DMat4, p: DVec3) -> (f64, f64, f64) {
    let q = *m * h(p);
    let inv = 1.0 / q.w;
    (q.x * inv, q.y * inv, q.w)
}

/// Length of the gradient of η (world length → image length), ≥ 0.
pub(super) fn image_scale(m: &DMat4, p: DVec3) -> f64 {
    let q = *m * h(p);
    let g = (m.row(1).truncate() * q.w - m.row(3).truncate() * q.y) / (q.w * q.w);
    g.length()
}
