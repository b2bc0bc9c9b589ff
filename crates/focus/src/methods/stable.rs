//! Stable uniform maps: texel-snapped, with an extent and a depth range
//! that change only in fixed steps, so that from one frame to the next the
//! map moves by whole texels or not at all.
//!
//! - A directional light's map ([`stable`]): orthographic, its extent
//!   invariant under camera rotation, its depth range on powers of two.
//! - A spot light's map, and each face of a point light's cube
//!   ([`stable_spot`]): perspective in the spot's own frame, fixed in the
//!   world, its extent a quarter-octave step below the spot's, its depth
//!   range on powers of two.

use super::uniform::uniform;
use super::{Fitted, SplitView};
use crate::clip::{ClipConvention, DepthRange};
use crate::frame::tangent_frame;
use crate::project::{from_rows, h, Cropped};
use crate::settings::Method;
use glam::{DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Light, UNIT_ROUNDOFF_F32};

/// `x > 0` rounded up to a power of two.
fn pow2_ceil(x: f64) -> f64 {
    if !(x > 0.0) {
        return f64::MIN_POSITIVE;
    }
    2f64.powi(x.log2().ceil() as i32)
}

/// `x > 0` rounded down to a power of two.
fn pow2_floor(x: f64) -> f64 {
    if !(x > 0.0) {
        return f64::MIN_POSITIVE;
    }
    2f64.powi(x.log2().floor() as i32)
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
pub(super) fn stable(sv: &SplitView, light: &Light, body: &Body) -> Option<Fitted> {
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
    let u = UNIT_ROUNDOFF_F32;
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
    let zc = 0.5 * (zlo + zhi);
    let mut zh = (0.5 * (zhi - zlo)).max((zlo.abs().max(zhi.abs()) + r) * (1.0 / (1u64 << 20) as f64));
    // NOTE: a body flat across the light has almost no depth; the range is
    // grown to what f32 resolves at these magnitudes (σ ≤ 1/32 below), as
    // the crop grows a degenerate body's, so that f32 keeps it.
    zh = zh.max(256.0 * u * (mag + (zc - d.dot(o)).abs()));
    let sigma = (8.0 * u * (mag + (zc - d.dot(o)).abs() + zh) / zh).max(4.0 * u);
    let f32_exact = sigma <= 1.0 / 16.0 && m <= 0.25 * r;
    zh *= 1.0 + 8.0 * sigma.min(1.0 / 16.0);
    let (zc, zh) = quantise_depth(zc, zh);
    if !(zh.is_finite() && half.is_finite()) {
        return None;
    }
    let mm = from_rows(
        DVec4::new(ex.x, ex.y, ex.z, -sx) / half,
        DVec4::new(ey.x, ey.y, ey.z, -sy) / half,
        depth_row(sv.settings.clip, d, zc, zh),
        DVec4::new(0.0, 0.0, 0.0, 1.0),
    );
    // The disk argument above holds for exact arithmetic; check it as every
    // other map is checked: each vertex inside the clip volume by more than
    // the rounding bound of its clip coordinates (`K u₆₄ Σ|M_rj||p_j|`, as
    // in `crop`). Else the uniform fit (which crops to the body), and the
    // plan says that stability was given up.
    let z_min = sv.settings.clip.depth_min();
    let holds = mm.is_finite()
        && verts.iter().all(|p| {
            let q = mm * h(*p);
            let e = |r: usize| mm.row(r).abs().dot(h(*p).abs()) * (8.0 * f64::EPSILON);
            q.x.abs() + e(0) <= 1.0 && q.y.abs() + e(1) <= 1.0 && q.z - e(2) >= z_min && q.z + e(2) <= 1.0
        });
    if !holds {
        return uniform(sv, light, body).map(|mut f| {
            f.stable_ignored = true;
            f
        });
    }
    Some(Fitted::plain(Cropped { m: mm, f32_exact }, Method::Uniform))
}

/// The depth range `zc ± zh` quantised: half-depth `2^k ≥ 2 zh`, centre on
/// a grid of `2^(k−1)`. The snap moves the centre by at most `2^(k−2)`, so
/// `zc' ± 2^k ⊇ zc ± (2^k − 2^(k−2)) ⊇ zc ± zh`: a body moving within the
/// same quantum keeps the same depth row.
pub(super) fn quantise_depth(zc: f64, zh: f64) -> (f64, f64) {
    let zh_q = pow2_ceil(2.0 * zh);
    let step = 0.5 * zh_q;
    ((zc / step).round() * step, zh_q)
}

/// The depth row for light direction `d` whose depths along `d` lie in
/// `zc ± zh`, in the convention's range (the rows of [`crate::clip`]'s
/// table, with `Z_c = d·x − zc` and `W = 1`).
///
/// NOTE: the `[0, 1]` row divides by `2 zh` after subtracting `zc − zh`,
/// as this map always has, so default maps are unchanged bit for bit.
fn depth_row(clip: ClipConvention, d: DVec3, zc: f64, zh: f64) -> DVec4 {
    match (clip.depth, clip.reversed_z) {
        (DepthRange::ZeroToOne, false) => DVec4::new(d.x, d.y, d.z, -(zc - zh)) / (2.0 * zh),
        (DepthRange::ZeroToOne, true) => DVec4::new(-d.x, -d.y, -d.z, zc + zh) / (2.0 * zh),
        (DepthRange::MinusOneToOne, false) => DVec4::new(d.x, d.y, d.z, -zc) / zh,
        (DepthRange::MinusOneToOne, true) => DVec4::new(-d.x, -d.y, -d.z, zc) / zh,
    }
}

/// Extents of a stable spot map per halving: each is `2^(1/4)` times the
/// next, so that the quantisation costs at most that factor in texel size.
const STEPS_PER_OCTAVE: f64 = 4.0;
/// The finest extent, `T·2⁻⁶⁰`.
const MAX_STEP: f64 = 60.0 * STEPS_PER_OCTAVE;

/// Stable perspective map of a spot light (a cube face is one): the image
/// in the spot's own frame, fixed in the world, so that the camera only
/// moves the body's image, never the texel grid.
///
/// Frame: axis `a` from the apex to the far face's centre, up `u` along the
/// near face's `−u → +u` edge (made orthogonal to `a`), right `a × u`. A
/// point `p` has image coordinates `ξ = r·(p − l)/w`, `η = u·(p − l)/w`,
/// `w = a·(p − l)`; the spot's own image lies in `[−T, T]²`, `T` the
/// largest `|ξ|`, `|η|` of its far corners grown by 2⁻¹⁰.
///
/// Extent: half-size `S = T·2^(−k/4)` for the largest whole `k` at which the
/// body's image box (half-size `b`) still fits after the snap, `b + S/res + S·2⁻¹⁶
/// ≤ S` (the last term a rounding allowance); the centre is rounded to the
/// texel grid `2S/res`, anchored at the axis (`k = 0`: the spot's whole
/// image, centred on the axis). So from frame to frame the map is the same
/// grid translated by whole texels while `k` holds. With a
/// [`crate::FitState`], `k` keeps last frame's value while the body still
/// fits it and it is at most one step looser than the tightest: a body
/// whose size hovers at a step's boundary does not switch every frame.
///
/// Depth: perspective, `D/W = f/(f − n)·(1 − n/w)` with `n`, `f` the
/// body's nearest and farthest `w` rounded down and up to powers of two.
///
/// The construction is checked as [`stable`]'s is, every vertex inside by
/// more than twice its f64 rounding bound, and `f32_exact` is the same test
/// with the f32 matrix's bound (positions relative to the f32 origin);
/// where the first fails, the uniform fit, and the plan says that
/// stability was given up.
pub(super) fn stable_spot(sv: &SplitView, light: &Light, body: &Body, hold: i16) -> Option<Fitted> {
    let Light::Spot { position: l, frustum } = light else { return uniform(sv, light, body) };
    let c = frustum.corners();
    let a = ((c[4] + c[5] + c[6] + c[7]) * 0.25 - *l).normalize();
    let up = c[3] - c[0];
    let u = (up - a * a.dot(up)).normalize();
    let r = a.cross(u);
    let image = |p: DVec3| {
        let q = p - *l;
        let w = a.dot(q);
        (r.dot(q) / w, u.dot(q) / w, w)
    };
    // NOTE: grown by 2⁻¹⁰ so that the vertices of a body that fills the
    // spot (they lie on its faces, up to their rounding) stay inside.
    let t = c[4..].iter().map(|p| image(*p)).fold(0.0f64, |m, (x, y, _)| m.max(x.abs()).max(y.abs())) * (1.0 + 1.0 / 1024.0);
    let verts = body.vertices();
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in verts {
        let (x, y, w) = image(*p);
        lo = lo.min(DVec3::new(x, y, w));
        hi = hi.max(DVec3::new(x, y, w));
    }
    if !(lo.z > 0.0 && t > 0.0 && (hi - lo).is_finite()) {
        return uniform(sv, light, body);
    }
    let res = sv.settings.resolution as f64;
    let b = 0.5 * (hi.x - lo.x).max(hi.y - lo.y);
    let room = 1.0 - 1.0 / res - 1.0 / (1u64 << 16) as f64;
    let tightest = if b > 0.0 { (STEPS_PER_OCTAVE * (t * room / b).log2()).floor().clamp(0.0, MAX_STEP) } else { MAX_STEP };
    // Hysteresis: last frame's step while the body still fits it and it is
    // at most one step looser than the tightest.
    let held = f64::from(hold);
    let k = if hold >= 0 && held <= tightest && tightest - held <= 1.0 { held } else { tightest };
    let s = t * (-k / STEPS_PER_OCTAVE).exp2();
    let (sx, sy) = if k == 0.0 {
        (0.0, 0.0)
    } else {
        let texel = 2.0 * s / res;
        ((0.5 * (lo.x + hi.x) / texel).round() * texel, (0.5 * (lo.y + hi.y) / texel).round() * texel)
    };
    let (n, f) = (pow2_floor(lo.z), pow2_ceil(hi.z).max(2.0 * pow2_floor(lo.z)));
    let w_row = DVec4::new(a.x, a.y, a.z, -a.dot(*l));
    let row = |e: DVec3, shift: f64| (DVec4::new(e.x, e.y, e.z, -e.dot(*l)) - w_row * shift) / s;
    let d = (w_row - DVec4::new(0.0, 0.0, 0.0, n)) * (f / (f - n));
    let mm = from_rows(row(r, sx), row(u, sy), convention_row(sv.settings.clip, d, w_row), w_row);
    // NOTE: checked with the `[0, 1]` row `d` and twice the rounding bound:
    // then every convention's row (`d`, `w − d`, `2d − w`, `w − 2d`, whose
    // rounding is at most twice `d`'s plus `w`'s) holds the body too, and
    // the outcome — the fallback, `f32_exact` — is the same in every
    // convention.
    let canonical = from_rows(mm.row(0), mm.row(1), d, w_row);
    if !(mm.is_finite() && inside_by(&canonical, verts, 0.0, DVec3::ZERO, 16.0 * f64::EPSILON)) {
        return uniform(sv, light, body).map(|mut f| {
            f.stable_ignored = true;
            f
        });
    }
    let o = sv.settings.f32_origin;
    let f32_exact = inside_by(&(canonical * glam::DMat4::from_translation(o)), verts, 0.0, o, 16.0 * UNIT_ROUNDOFF_F32);
    let mut fitted = Fitted::plain(Cropped { m: mm, f32_exact }, Method::Uniform);
    fitted.held.step = k as i16;
    Some(fitted)
}

/// The row of the convention for the `[0, 1]` depth row `d` (`0 ≤ d ≤ w`):
/// `d`, `w − d`, `2d − w` or `w − 2d` (see [`crate::clip`]).
pub(super) fn convention_row(clip: ClipConvention, d: DVec4, w: DVec4) -> DVec4 {
    match (clip.depth, clip.reversed_z) {
        (DepthRange::ZeroToOne, false) => d,
        (DepthRange::ZeroToOne, true) => w - d,
        (DepthRange::MinusOneToOne, false) => d * 2.0 - w,
        (DepthRange::MinusOneToOne, true) => w - d * 2.0,
    }
}

/// Every vertex inside the clip volume of `m` (applied to `p − origin`) by
/// more than the rounding bound `eps·Σ|m_rj||p_j|` of its clip coordinates.
pub(super) fn inside_by(m: &glam::DMat4, verts: &[DVec3], z_min: f64, origin: DVec3, eps: f64) -> bool {
    verts.iter().all(|p| {
        let hp = h(*p - origin);
        let q = *m * hp;
        let e = |r: usize| m.row(r).abs().dot(hp.abs()) * eps;
        let w = q.w - e(3);
        w > 0.0 && q.x.abs() + e(0) <= w && q.y.abs() + e(1) <= w && q.z - e(2) >= z_min * q.w + e(3) && q.z + e(2) <= w
    })
}
