//! The stable uniform map of a directional light: texel-snapped and
//! invariant under camera rotation.

use super::uniform::uniform;
use super::{Fitted, SplitView};
use crate::clip::{ClipConvention, DepthRange};
use crate::frame::tangent_frame;
use crate::project::{from_rows, h, Cropped};
use crate::settings::Method;
use glam::{DVec3, DVec4};
use shadowfocus_geom::{unit_direction, Body, Light, UNIT_ROUNDOFF_F32};

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
    let sigma = (8.0 * u * (mag + (zc - d.dot(o)).abs() + zh) / zh).max(4.0 * u);
    let f32_exact = sigma <= 1.0 / 16.0 && m <= 0.25 * r;
    zh *= 1.0 + 8.0 * sigma.min(1.0 / 16.0);
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
