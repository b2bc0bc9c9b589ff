//! The four parameterisations, each turning one focus body into a matrix.
//!
//! All of them are `crop ∘ warp ∘ Λ`: `Λ` projects from the light
//! ([`central_projection`]; for PSM composed with the camera's
//! post-perspective transform), the warp is LiSPSM's or TSM's perspective in
//! the light's image plane (identity for uniform and PSM), and the crop fits
//! the body into the clip volume with rounding margins.

use crate::frame::{perpendicular_hint, tangent_frame};
use crate::hull2::min_area_direction;
#[cfg(doc)]
use crate::predict::Predicted;
use crate::predict::Samples;
use crate::project::{apply_warp, central_projection, crop, crop_estimate, from_rows, h, image_points, Central, Cropped, DepthKind, Warp};
use crate::settings::{FocusSettings, MapOrientation, Method, WarpDirection};
use glam::{DMat4, DVec2, DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Camera, CameraBasis, Dimension, Light, MAX_VERTICES};

/// The camera of one split and what every method reads from it.
pub(crate) struct SplitView<'a> {
    pub camera: &'a Camera,
    pub basis: CameraBasis,
    pub settings: &'a FocusSettings,
}

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
    /// The f32 matrix keeps the body inside (see `project::crop`).
    pub f32_exact: bool,
}

impl Fitted {
    fn plain(c: Cropped, method: Method) -> Fitted {
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

/// Fits `body` (non-empty) for `light` with the configured method.
pub(crate) fn fit_body(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let s = sv.settings;
    let directional = matches!(light, Light::Directional { .. });
    let mut out = match s.method {
        Method::Uniform if s.stable && directional => stable(sv, light, body),
        Method::Uniform => uniform(sv, light, body),
        Method::Psm => match psm(sv, light, body) {
            Some(f) => Some(f),
            None => uniform(sv, light, body).map(|mut f| {
                f.psm_fell_back = true;
                f
            }),
        },
        Method::Lispsm | Method::Tsm => warped(sv, light, body),
    }?;
    out.stable_ignored |= s.stable && !(s.method == Method::Uniform && directional);
    Some(out)
}

/// Camera-relative image orientation: up follows the (projected) reference
/// `v`; the secondary reference is the camera's right+up diagonal, which
/// puts the frame's two singular light directions in the plane of the view
/// direction and that diagonal, about 11° off the view axis — away from
/// sweeps in the view/up and view/right planes.
fn references(sv: &SplitView, v: DVec3) -> (DVec3, DVec3) {
    (v, perpendicular_hint(v, sv.basis.right + sv.basis.up))
}

fn light_space(sv: &SplitView, light: &Light, verts: &[DVec3], v: DVec3) -> Option<Central> {
    let lp = light_point(light);
    let depth = if lp.w == 0.0 { DepthKind::Polar } else { DepthKind::Perspective };
    let (v, w) = references(sv, v);
    central_projection(lp, verts, depth, v, w, spot_axis(light))
}

fn uniform(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let verts = body.vertices();
    let c = light_space(sv, light, verts, sv.basis.forward)?;
    uniform_from(&c.m, verts, sv)
}

/// The uniform map of the central projection `m`: turned to the
/// least-area rectangle around the body's image, then cropped.
fn uniform_from(m: &DMat4, verts: &[DVec3], sv: &SplitView) -> Option<Fitted> {
    let m = orient(m, verts, sv);
    Some(Fitted::plain(crop(&m, verts, sv.settings.f32_origin)?, Method::Uniform))
}

/// `m` with its image rows `x`, `y` turned so that image `y` runs along the
/// unit image direction `dir`: `y' = d_x x + d_y y`, `x' = d_y x − d_x y`.
/// A rotation (determinant +1): the rows stay combinations of rows through
/// the light, so they still pass through it, and `z`, `w` are kept.
fn rotate_image(m: &DMat4, dir: DVec2) -> DMat4 {
    let (x, y) = (m.row(0), m.row(1));
    from_rows(x * dir.y - y * dir.x, x * dir.x + y * dir.y, m.row(2), m.row(3))
}

/// `m` turned as the settings' [`MapOrientation`] asks.
fn orient(m: &DMat4, verts: &[DVec3], sv: &SplitView) -> DMat4 {
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
fn orient_min_area(m: &DMat4, verts: &[DVec3]) -> DMat4 {
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
fn image(m: &DMat4, p: DVec3) -> (f64, f64, f64) {
    let q = *m * h(p);
    let inv = 1.0 / q.w;
    (q.x * inv, q.y * inv, q.w)
}

/// Length of the gradient of η (world length → image length), ≥ 0.
fn image_scale(m: &DMat4, p: DVec3) -> f64 {
    let q = *m * h(p);
    let g = (m.row(1).truncate() * q.w - m.row(3).truncate() * q.y) / (q.w * q.w);
    g.length()
}

/// Centroid of the body (volume, area, length or point), a continuous
/// function of `H`, used as the end of LiSPSM's middle vector.
pub(crate) fn centroid(body: &Body) -> DVec3 {
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

/// LiSPSM and TSM.
fn warped(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let s = sv.settings;
    let cam = sv.camera;
    let f = sv.basis.forward;
    let verts = body.vertices();
    let v = match (s.method, s.lispsm.warp) {
        (Method::Lispsm, WarpDirection::MiddleVector) => {
            let m = centroid(body) - cam.eye;
            m.try_normalize().unwrap_or(f)
        }
        _ => f,
    };
    let c = light_space(sv, light, verts, v)?;
    let lp = light_point(light);
    let zn = cam.near;
    let p_near = cam.eye + f * zn;
    // A reference point the light map sees: the near-plane centre, else the
    // body's centre (a point light beside the eye can have w ≤ 0 there).
    let p_ref = if image(&c.m, p_near).2 > 0.0 { p_near } else { c.centre };
    // The warp runs along the image of the view direction [LISPSM04]: image
    // `y` is turned onto it. Where the view direction is (nearly) parallel
    // to the light it has no image direction and the warp no effect.
    let aligned = match s.orientation {
        MapOrientation::LeastArea => align_to(&c.m, p_ref, v),
        MapOrientation::ViewAligned => Some(c.m),
    };
    let Some(m) = aligned else {
        return uniform_from(&c.m, verts, sv).map(|u| Fitted { method: s.method, warp_vanished: true, ..u });
    };
    let (mut eta0, mut eta1) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut xi0, mut xi1) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in verts {
        let (xi, eta, _) = image(&m, *p);
        eta0 = eta0.min(eta);
        eta1 = eta1.max(eta);
        xi0 = xi0.min(xi);
        xi1 = xi1.max(xi);
    }

    let (epsilon, xi_c) = match s.method {
        Method::Lispsm => {
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
        _ => {
            // TSM: top line at η0, base at η1 (λ apart); the focus point at
            // depth z_n + δ on the view axis (δ' past the top line) goes to
            // the 80 % line: with u(t) = (t/(η+t)) / (λ/(η+λ)) = 0.8 at
            // t = δ' the apex distance is η = 0.2 λ δ' / (0.8 λ − δ'); ε = 1/η.
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
        }
    };
    let epsilon = if epsilon.is_finite() && epsilon > 0.0 { epsilon } else { 0.0 };
    choose_warp(sv, light, body, &c.m, &m, Warp { epsilon, xi_c, eta0 })
}

/// The warp of `m` by `w`, or a weaker one, or the uniform map of the
/// central projection `central`: whichever is strongest among those whose
/// predicted aliasing ([`Samples`]) is no worse than the uniform map's
/// ([`Predicted::no_worse_than`]). Warps never lose to the uniform map by
/// construction; the weakening steps (ε, ε/2, …, ε/2^(WARP_STEPS−1), then
/// none) keep the choice close to continuous where the prediction crosses
/// over.
/// Warp strengths tried before the uniform map: each halves ε.
const WARP_STEPS: i32 = 5;

fn choose_warp(sv: &SplitView, light: &Light, body: &Body, central: &DMat4, m: &DMat4, w: Warp) -> Option<Fitted> {
    let s = sv.settings;
    let verts = body.vertices();
    let reference = uniform_from(central, verts, sv)?;
    let mut best = Fitted { method: s.method, warp_vanished: true, ..reference };
    if w.epsilon == 0.0 && s.orientation == MapOrientation::LeastArea {
        return Some(best);
    }
    if !s.warp_guard || w.epsilon == 0.0 {
        // The warp as designed (ε = 0: the unwarped map in the warp's frame).
        let cropped = match crop(&apply_warp(m, &w), verts, s.f32_origin) {
            Some(c) => c,
            None if w.epsilon > 0.0 => return Some(best),
            None => return None,
        };
        let mut out = Fitted::plain(cropped, s.method);
        out.warp_near = if w.epsilon > 0.0 { 1.0 / w.epsilon } else { f64::INFINITY };
        out.warp_vanished = w.epsilon == 0.0;
        return Some(out);
    }
    let lp = light_point(light);
    let mut samples = Samples::new(sv, body);
    let target = samples.judge(&reference.m, lp);
    for k in 0..WARP_STEPS {
        let epsilon = w.epsilon * 0.5f64.powi(k);
        let warped = apply_warp(m, &Warp { epsilon, ..w });
        let better = match &target {
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
        if let Some(cropped) = crop(&warped, verts, s.f32_origin) {
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

/// The camera's post-perspective transform after the virtual shift: eye
/// moved back by `shift` along −forward, near kept, far grown by the shift.
/// Symmetric NDC: depth `n ↦ −1`, `f ↦ 1`, infinity `↦ (f + n)/(f − n)`.
pub(crate) fn post_perspective(cam: &Camera, b: &CameraBasis, shift: f64) -> DMat4 {
    let eye = cam.eye - b.forward * shift;
    let (n, fa) = (cam.near, cam.far + shift);
    let t = (0.5 * cam.fovy).tan();
    let sx = 1.0 / (cam.aspect * t);
    let sy = 1.0 / t;
    let row = |v: DVec3, k: f64| DVec4::new(v.x * k, v.y * k, v.z * k, -v.dot(eye) * k);
    let rw = row(b.forward, 1.0);
    let a = (fa + n) / (fa - n);
    let bb = 2.0 * fa * n / (fa - n);
    from_rows(row(b.right, sx), row(b.up, sy), rw * a - DVec4::new(0.0, 0.0, 0.0, bb), rw)
}

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
fn psm(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
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
    let plain = |m: &DMat4, shift: f64| {
        crop(m, verts, sv.settings.f32_origin).map(|c| {
            let mut out = Fitted::plain(c, Method::Psm);
            out.psm_shift = shift;
            out
        })
    };
    if !sv.settings.warp_guard {
        return plain(&psm_map(sv, light, body, shift)?, shift);
    }
    let reference = uniform(sv, light, body)?;
    let mut samples = Samples::new(sv, body);
    let lp = light_point(light);
    let Some(target) = samples.judge(&reference.m, lp) else { return plain(&psm_map(sv, light, body, shift)?, shift) };
    let spread = zmax - zmin;
    for k in 0..PSM_STEPS {
        let s = shift + if k == 0 { 0.0 } else { spread * 4f64.powi(k - 2) };
        let Some(m) = psm_map(sv, light, body, s) else { continue };
        let accepted = crop_estimate(&m, verts).and_then(|e| samples.predict(&e)).is_some_and(|p| p.no_worse_than(&target));
        if let Some(out) = accepted.then(|| plain(&m, s)).flatten() {
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
/// cropped.
fn psm_map(sv: &SplitView, light: &Light, body: &Body, shift: f64) -> Option<DMat4> {
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
    Some(orient(&(lam.m * c), verts, sv))
}

/// Largest absolute coordinate, quantised up to a power of two.
fn pow2_ceil(x: f64) -> f64 {
    if !(x > 0.0) {
        return f64::MIN_POSITIVE;
    }
    2f64.powi(x.log2().ceil() as i32)
}

/// Stable (texel-snapped, camera-rotation-invariant) orthographic map for a
/// directional light.
///
/// Extent: the smallest sphere around the split's sub-frustum depends only
/// on `(near, far, fovy, aspect)`, not on the camera's orientation; its
/// centre is on the view axis at depth `min(f, (n + f)(1 + k²)/2)`,
/// `k² = tan²(fovy/2)(1 + aspect²)`, equidistant from near and far corners.
/// `H ⊆ hull(V_i ∪ l)` projects along the light into the projection of
/// `V_i`, hence into the sphere's disk of radius r.
///
/// Snapping: the light frame is fixed in the world (up from world +Z, see
/// [`tangent_frame`]), the disk centre is rounded to whole texels, and the
/// half-extent is `(r + m)·res/(res − 2)`: then `half = r + m + texel`,
/// which covers the ≤ ½ texel snap. `m` is the f32 rounding margin
/// (16 u · magnitude of the coordinates involved) rounded up to a power of
/// two, so the extent — and the texel size — only change when a magnitude
/// crosses a power of two.
fn stable(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
    let cam = sv.camera;
    let b = &sv.basis;
    let Light::Directional { direction } = *light else { return uniform(sv, light, body) };
    let d = unit_direction(direction);
    let (ex, ey) = tangent_frame(d, DVec3::Z, DVec3::X);
    let (n, f) = (cam.near, cam.far);
    let t = (0.5 * cam.fovy).tan();
    let k2 = t * t * (1.0 + cam.aspect * cam.aspect);
    let cd = (0.5 * (n + f) * (1.0 + k2)).min(f);
    let r = (((cd - n) * (cd - n) + n * n * k2).sqrt()).max(((f - cd) * (f - cd) + f * f * k2).sqrt());
    let centre = cam.eye + b.forward * cd;
    let (cx, cy) = (ex.dot(centre), ey.dot(centre));
    let verts = body.vertices();
    // Magnitudes as the f32 user sees them: relative to the f32 origin.
    let o = sv.settings.f32_origin;
    let mag = verts.iter().map(|p| (*p - o).abs().element_sum()).fold(0.0, f64::max);
    let (ox, oy) = (ex.dot(o), ey.dot(o));
    let u = 1.0 / (1u64 << 24) as f64;
    let m = pow2_ceil(16.0 * u * (mag + (cx - ox).abs() + (cy - oy).abs() + r));
    let res = sv.settings.resolution as f64;
    let half = (r + m) * res / (res - 2.0);
    let texel = 2.0 * half / res;
    let (sx, sy) = ((cx / texel).round() * texel, (cy / texel).round() * texel);
    // Depth: fitted to H along the light, with the crop's margin rule.
    let (mut zlo, mut zhi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in verts {
        let z = d.dot(*p);
        zlo = zlo.min(z);
        zhi = zhi.max(z);
    }
    let mut zc = 0.5 * (zlo + zhi);
    let mut zh = (0.5 * (zhi - zlo)).max((zlo.abs().max(zhi.abs()) + r) * (1.0 / (1u64 << 20) as f64));
    let sigma = (8.0 * u * (mag + (zc - d.dot(o)).abs() + zh) / zh).max(4.0 * u);
    let f32_exact = sigma <= 1.0 / 16.0 && m <= 0.25 * r;
    zh *= 1.0 + 8.0 * sigma.min(1.0 / 16.0);
    if !(zh.is_finite() && half.is_finite()) {
        return None;
    }
    zc -= zh;
    let mm = from_rows(
        DVec4::new(ex.x, ex.y, ex.z, -sx) / half,
        DVec4::new(ey.x, ey.y, ey.z, -sy) / half,
        DVec4::new(d.x, d.y, d.z, -zc) / (2.0 * zh),
        DVec4::new(0.0, 0.0, 0.0, 1.0),
    );
    // The disk argument above holds for exact arithmetic; check it as every
    // other map is checked: each vertex inside the clip volume by more than
    // the rounding bound of its clip coordinates (`K u₆₄ Σ|M_rj||p_j|`, as
    // in `crop`). Else the uniform fit (which crops to the body), and the
    // plan says that stability was given up.
    let holds = mm.is_finite()
        && verts.iter().all(|p| {
            let q = mm * h(*p);
            let e = |r: usize| mm.row(r).abs().dot(h(*p).abs()) * (8.0 * f64::EPSILON);
            q.x.abs() + e(0) <= 1.0 && q.y.abs() + e(1) <= 1.0 && q.z - e(2) >= 0.0 && q.z + e(2) <= 1.0
        });
    if !holds {
        return uniform(sv, light, body).map(|mut f| {
            f.stable_ignored = true;
            f
        });
    }
    Some(Fitted::plain(Cropped { m: mm, f32_exact }, Method::Uniform))
}
