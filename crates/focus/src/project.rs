//! Projective building blocks shared by every method: the central
//! projection from a (homogeneous, oriented) light, the LiSPSM/TSM warp in
//! the light's image plane, the crop to the clip volume with rounding
//! margins, and texel footprints.
//!
//! Maps are 4×4 matrices acting on homogeneous points `(x, 1)`; a row is a
//! plane (dual vector). A shadow map projecting from the light `L` must have
//! its `x`, `y` and `w` rows through `L` (`row · L = 0`): then every light
//! ray maps to one texel. The depth row `z` is any plane not through `L`;
//! along a light ray beyond a point `X` (the points `X − μL`, μ ∈ (0, 1)
//! for the oriented light point `L`) the stored depth `z/w` changes by
//! `−μ (z·L)/(w·X)`, so with `w > 0` on the body the point nearer the light
//! has the smaller depth exactly when `z·L < 0`. That sign is the depth test
//! ([`crate::DepthTest`]), and it is known from how each depth row is built:
//! `z·L < 0` for every light space's row but PSM's inverted light's (the
//! polar row's σ = −1), negated by reversed-Z. The fit takes it from there,
//! not from the rounded product `z·L`, whose sign rounding decides for a body
//! tiny against its coordinates.

use crate::clip::ClipConvention;
use crate::cone::{cone_axis, least_aligned, turn_into_cone};
use crate::frame::tangent_frame;
use crate::hull2::hull_area;
use glam::{DMat4, DVec2, DVec3, DVec4};
use shadowfocus_geom::{Camera, CameraBasis, MAX_VERTICES, UNIT_ROUNDOFF, UNIT_ROUNDOFF_F32};

/// Matrix from its four rows.
pub(crate) fn from_rows(x: DVec4, y: DVec4, z: DVec4, w: DVec4) -> DMat4 {
    DMat4::from_cols(x, y, z, w).transpose()
}

#[inline]
pub(crate) fn h(p: DVec3) -> DVec4 {
    p.extend(1.0)
}

/// How the depth row of a central projection is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DepthKind {
    /// `z/w = −1/w`: the usual perspective depth (finite lights with
    /// `L.w > 0`, world space).
    Perspective,
    /// The polar plane of the light about the body's centre `c`:
    /// `z = −σ (ℓ_c · (x − c) + ℓ_w)` with `ℓ_c = ℓ − ℓ_w c`, σ = sign(ℓ_w)
    /// (σ = 1 for ℓ_w = 0). Orthographic depth along the light for
    /// directional lights, close to perspective depth for a light near the
    /// body, and continuous as the light passes through infinity (PSM).
    Polar,
}

/// The result of [`central_projection`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Central {
    pub m: DMat4,
    /// Body centre (AABB centre of the points) in the working space.
    pub centre: DVec3,
}

/// A projection from the oriented homogeneous light `light` (working space)
/// that sees every point of `pts` with `w > 0`; `None` when no single
/// projection can (the light lies in the points' hull, or the directions to
/// them do not fit in an open half-space). `v`, `w` orient the image (see
/// [`tangent_frame`]); `axis_hint` is tried when the default axis fails.
pub(crate) fn central_projection(
    light: DVec4,
    pts: &[DVec3],
    depth: DepthKind,
    v: DVec3,
    w: DVec3,
    axis_hint: Option<DVec3>,
) -> Option<Central> {
    let l = light.truncate();
    let lw = light.w;
    // Travel direction of the light at x (a positive multiple of x − l/lw
    // for lw > 0, of l/lw − x for lw < 0, and −l for lw = 0): lw·x − l.
    let travel = |x: DVec3| x * lw - l;

    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in pts {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let c = (lo + hi) * 0.5;
    let tc = travel(c);
    let tc_len = tc.length();
    if !(tc_len > 0.0) || !tc_len.is_finite() {
        return None;
    }
    let tc = tc / tc_len;

    // Axis: the maximin direction of the unit travel directions (see
    // `cone`); the hint and a few perceptron steps only when rounding leaves
    // it marginal. A light at infinity travels the same way everywhere.
    let a = if lw == 0.0 {
        -l.normalize()
    } else if pts.len() <= SMALL_BODY {
        travel_axis::<SMALL_BODY>(pts, travel, tc, axis_hint)?
    } else {
        travel_axis::<MAX_VERTICES>(pts, travel, tc, axis_hint)?
    };

    let (ex, ey) = tangent_frame(tc, v, w);
    // x and y rows: planes through c containing the travel direction at c,
    // hence through L (ex·t_c = 0 ⇒ (ex, −ex·c)·(l, lw) = −ex·t_c = 0).
    let rx = DVec4::new(ex.x, ex.y, ex.z, -ex.dot(c));
    let ry = DVec4::new(ey.x, ey.y, ey.z, -ey.dot(c));
    // w row: a·travel(x), scaled by 1/|L| so it stays bounded as L moves
    // through infinity.
    let norm = light.length();
    let aw = a * (lw / norm);
    let rw = DVec4::new(aw.x, aw.y, aw.z, -a.dot(l) / norm);
    let rz = match depth {
        DepthKind::Perspective => DVec4::new(0.0, 0.0, 0.0, -1.0),
        DepthKind::Polar => {
            let sigma = if lw < 0.0 { -1.0 } else { 1.0 };
            let lc = l - c * lw;
            let n = (lc.length_squared() + lw * lw).sqrt();
            let k = -sigma / n;
            DVec4::new(lc.x * k, lc.y * k, lc.z * k, (lw - lc.dot(c)) * k)
        }
    };
    Some(Central { m: from_rows(rx, ry, rz, rw), centre: c })
}

/// Bodies up to this many vertices take a small scratch array in
/// [`travel_axis`].
const SMALL_BODY: usize = 32;

/// The projection axis of a finite light: a direction with a positive dot
/// product with the unit travel direction at every point (see
/// `central_projection`), `None` when there is none.
///
/// NOTE: generic over the scratch size so that a typical body (≤ 32
/// vertices) zeroes 768 bytes instead of a full `MAX_VERTICES` array (3 KiB,
/// which cost more than the axis itself).
fn travel_axis<const N: usize>(pts: &[DVec3], travel: impl Fn(DVec3) -> DVec3, tc: DVec3, axis_hint: Option<DVec3>) -> Option<DVec3> {
    let mut units = [DVec3::ZERO; N];
    let units = &mut units[..pts.len().min(N)];
    for (u, p) in units.iter_mut().zip(pts) {
        let t = travel(*p);
        let len = t.length();
        if !(len > 0.0) {
            return None; // the light is a vertex of the body
        }
        // NOTE: one reciprocal for three divisions: the axis only has to
        // see every point with w > 0, which the crop checks again.
        *u = t * (1.0 / len);
    }
    let units = &*units;
    let a = cone_axis(units).unwrap_or(tc);
    if least_aligned(units, a).0 > 0.0 {
        return Some(a);
    }
    if let Some(hint) = axis_hint.map(DVec3::normalize_or_zero) {
        if hint != DVec3::ZERO && least_aligned(units, hint).0 > 0.0 {
            return Some(hint);
        }
    }
    turn_into_cone(units, a, 16)
}

/// The LiSPSM/TSM warp in the image plane: a perspective along the image
/// `y` axis with centre at `y = eta0 − 1/epsilon`, `x = xi_c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Warp {
    /// 1/n: 0 is no warp (the uniform map), never infinite.
    pub epsilon: f64,
    pub xi_c: f64,
    pub eta0: f64,
}

/// `m` followed by the warp. With image coordinates `ξ = X/W`, `η = Y/W`
/// and `t = η − η0 ≥ 0` on the body, the warp is the projective map
/// `(ξ, t, ζ) ↦ (ξ_c + (ξ − ξ_c)/(1 + εt), t/(1 + εt), ζ/(1 + εt))`: a
/// perspective with its centre a distance `n = 1/ε` before the body's near
/// end. Written with ε instead of n it is the identity at ε = 0 and never
/// divides, so the fall-back to the uniform map as the warp fades is
/// continuous and NaN-free. Rows stay combinations of X, Y, W, so they
/// still pass through the light, and `W' = W (1 + εt) ≥ W > 0` on the body.
pub(crate) fn apply_warp(m: &DMat4, wp: &Warp) -> DMat4 {
    let (x, y, z, w) = (m.row(0), m.row(1), m.row(2), m.row(3));
    let t = y - w * wp.eta0;
    let w2 = w + t * wp.epsilon;
    let x2 = x + t * (wp.xi_c * wp.epsilon);
    from_rows(x2, t, z, w2)
}

/// Relative rounding errors of single and double precision.
const U32: f64 = UNIT_ROUNDOFF_F32;
const U64: f64 = UNIT_ROUNDOFF;
/// Error constant of one clip-space coordinate: entry rounding (u), position
/// rounding (u) and a 4-term dot product (≤ 4u), with room to spare.
const K: f64 = 8.0;

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

/// Centre and half extent of the image box of `pts` under `m`, the half
/// extent at least 2⁻²⁰ of the overall scale (so that a flat or point body
/// still gives a finite, invertible matrix); `None` where some point has no
/// positive finite image.
fn image_box(m: &DMat4, pts: &[DVec3]) -> Option<(DVec3, DVec3)> {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in pts {
        let q = *m * h(*p);
        if !(q.w > 0.0) || !q.is_finite() {
            return None;
        }
        // NOTE: one reciprocal instead of three divisions: the centre and
        // extents found here are only a starting point, which `crop` makes
        // conservative.
        let r = q.truncate() * (1.0 / q.w);
        lo = lo.min(r);
        hi = hi.max(r);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let mut scale = lo.abs().max(hi.abs()).max(hi - lo).max_element();
    if !(scale > 0.0) {
        scale = 1.0;
    }
    let half = ((hi - lo) * 0.5).max(DVec3::splat(scale * (1.0 / (1u64 << 20) as f64)));
    Some(((lo + hi) * 0.5, half))
}

/// `m` mapped so that the image box of `pts` fills the clip volume, as
/// [`crop`] does but without its rounding allowance: the same texel sizes
/// to a few ulps, for comparing candidate maps before the one kept is
/// cropped (a fraction of `crop`'s cost). `None` where `crop` would refuse
/// for want of a positive `w`.
pub(crate) fn crop_estimate(m: &DMat4, pts: &[DVec3]) -> Option<DMat4> {
    let (centre, half) = image_box(m, pts)?;
    let (x, y, z, w) = (m.row(0), m.row(1), m.row(2), m.row(3));
    let inv = DVec3::ONE / half;
    let out = from_rows((x - w * centre.x) * inv.x, (y - w * centre.y) * inv.y, (z - w * centre.z + w * half.z) * (0.5 * inv.z), w);
    out.is_finite().then_some(out)
}

/// The crop and whether its f32 guarantee holds.
pub(crate) struct Cropped {
    pub m: DMat4,
    /// The f32 matrix (for positions relative to the f32 origin) keeps every
    /// point inside the clip volume.
    pub f32_exact: bool,
}

/// Crops `m` (with `w > 0` at every point) to the clip volume:
/// `−w ≤ x, y ≤ w`, and `0 ≤ z ≤ w` or `−w ≤ z ≤ w` as `clip` has it (its
/// depth row from the centred one: see [`crate::clip`]). Returns `None` if
/// some point's `w` is not certainly positive (`w ≤ 0`, or within its
/// rounding bound of 0).
///
/// The crop maps the fitted image range `[c − h, c + h]` of each coordinate
/// to the clip range, and `h` is chosen so that rounding cannot push a point
/// out. With `X' = X − cW` (the centred row) and `W` evaluated at a point,
/// the test `|X'| ≤ h W` survives errors `e_x` in `X'` and `e_w` in `W` when
///
/// `h ≥ (|ξ − c| W + e_x) / (W − e_w)`,  ξ = X/W,
///
/// so `h` is the maximum of that over the points. The errors are bounded
/// for both ways the matrix is used: the f64 matrix on world positions
/// (`e = K u₆₄ Σ_j |M_rj| |p_j|`) and the f32 matrix on positions relative
/// to `origin` (see [`crate::FocusSettings::f32_origin`]) rounded to f32
/// (`e = K u₃₂ Σ_j |M'_rj| |p_j − o_j|`, `M' = M · translate(o)`); both are
/// added. These are rounding allowances, not geometric tolerances: for
/// ordinary coordinates they grow the map by a few f32 ulps of its extent,
/// and for degenerate bodies (thinner than the coordinates' resolution)
/// they give the map the smallest extent the arithmetic can honour. Where
/// f32 cannot even keep the sign of `w` (`e_w ≥ W` for positions that far
/// from the origin) only the f64 guarantee is kept and `f32_exact` is false.
pub(crate) fn crop(m: &DMat4, pts: &[DVec3], origin: DVec3, clip: ClipConvention) -> Option<Cropped> {
    crop_grown(m, pts, origin, clip, 1.0)
}

/// [`crop`] with the image (`x`, `y`) grown by the factor `grow ≥ 1` about
/// its centre, so that the points fill only `[−1/grow, 1/grow]²` of it.
///
/// NOTE: `fl(half · grow) ≥ half` for `grow ≥ 1` (rounding is monotone), so
/// growing never loses a point; `grow = 1` leaves `crop`'s result bit for
/// bit.
pub(crate) fn crop_grown(m: &DMat4, pts: &[DVec3], origin: DVec3, clip: ClipConvention, grow: f64) -> Option<Cropped> {
    debug_assert!(grow >= 1.0);
    let (centre, mut half) = image_box(m, pts)?;
    let (x, y, z, w) = (m.row(0), m.row(1), m.row(2), m.row(3));
    let centred = [x - w * centre.x, y - w * centre.y, z - w * centre.z, w];
    // NOTE: with the f32 origin at zero the rows relative to it are the
    // rows themselves (a product with the identity is exact), so the matrix
    // product is skipped; and both error terms below weigh the same |p|, so
    // one dot product of the summed rows replaces two. Both are sums of
    // non-negative terms; their roundings differ by a few u₆₄, well inside
    // the 4u₃₂ margin applied below.
    let at_origin = origin == DVec3::ZERO;
    let rel = if at_origin {
        centred
    } else {
        (from_rows(centred[0], centred[1], centred[2], centred[3]) * DMat4::from_translation(origin))
            .transpose()
            .to_cols_array_2d()
            .map(DVec4::from_array)
    };
    // Row magnitudes, scaled by the error constants, for the bounds below.
    let abs64 = centred.map(|r| r.abs() * (K * U64));
    let abs32: [DVec4; 4] = rel.map(|r| r.abs() * (K * U32));
    let abs_both: [DVec4; 4] = std::array::from_fn(|r| abs64[r] + abs32[r]);
    let mut f32_exact = true;
    for p in pts {
        let pw = h(*p);
        let pwa = pw.abs();
        // The position relative to the f32 origin, only where it is not zero.
        let pra = if at_origin { pwa } else { h(*p - origin).abs() };
        let e = |r: usize, with_f32: bool| match (with_f32, at_origin) {
            (false, _) => abs64[r].dot(pwa),
            (true, true) => abs_both[r].dot(pwa),
            (true, false) => abs64[r].dot(pwa) + abs32[r].dot(pra),
        };
        let wv = w.dot(pw);
        let ew32 = e(3, true);
        let use32 = ew32 < 0.5 * wv;
        f32_exact &= use32;
        let ew = if use32 { ew32 } else { e(3, false) };
        let q = DVec3::new(centred[0].dot(pw), centred[1].dot(pw), centred[2].dot(pw));
        // W's sign must be certain at every point: where its rounding bound
        // reaches W itself (a point all but on the plane w = 0 of a matrix
        // with much larger entries), no crop can promise to hold it.
        let certain_w = wv - ew;
        if !(certain_w > 0.0) {
            return None;
        }
        // NOTE: multiplying by a rounded reciprocal adds one rounding (2u₆₄
        // in all, against u₆₄ for a quotient), far inside the 4u₃₂ margin
        // applied below.
        let inv = 1.0 / certain_w;
        let err = DVec3::new(e(0, use32), e(1, use32), e(2, use32));
        half = half.max((q.abs() + err) * inv);
    }
    // A few ulps more: covers the rounding of the quantities just computed.
    half *= 1.0 + 4.0 * U32;
    half.x *= grow;
    half.y *= grow;
    // NOTE: rows scaled by reciprocals, three divisions instead of twelve:
    // each entry is then rounded twice (2u₆₄), still within K's budget
    // (entry 2u + position u + dot product 4u ≤ 8u).
    let inv = DVec3::ONE / half;
    let out = from_rows(centred[0] * inv.x, centred[1] * inv.y, clip.depth_row(centred[2], w, half.z, inv.z), w);
    out.is_finite().then_some(Cropped { m: out, f32_exact })
}

/// Texel footprint at world point `p`: the square root of the area one
/// texel covers on the plane through `p` perpendicular to the light ray,
/// for a `res × res` map. `f64::INFINITY` where the map does not see `p`.
pub(crate) fn texel_size(m: &DMat4, light: DVec4, p: DVec3, res: u32) -> f64 {
    let t = p * light.w - light.truncate();
    let len = t.length();
    if !(len > 0.0 && len.is_finite()) {
        return f64::INFINITY;
    }
    let s = (2.0 / res as f64) / image_area_scale(m, p, t / len).sqrt();
    if s.is_finite() {
        s
    } else {
        f64::INFINITY
    }
}

/// The light's grazing angle below which a receiver's predicted aliasing
/// fades out: `cos θ` of 85° (θ the angle of incidence), sin 5°.
pub(crate) const GRAZING_COS: f64 = 0.087_155_742_747_658_17;

/// The light's factor in a receiver's predicted aliasing: with `c = cos θ`,
/// `1/√c` down to [`GRAZING_COS`], then `√c / GRAZING_COS`, which meets it
/// there and falls to 0 at grazing.
///
/// A shadow map projects along the light rays, so on a receiver with unit
/// normal `n` its area scale is `a_M(p, n) = a_M(p, ℓ)·|n·ℓ|` (`ℓ` the unit
/// light ray at `p`): the aliasing is `√(a_C / a_M(p, ℓ)) / √c`, the same
/// `1/√c` for every map. As the light grazes a receiver that factor grows
/// without bound whatever the map, while the receiver darkens to nothing
/// (Lambert's `c`) and its shadow edges with it; past 85° the factor is
/// weighed by that contrast, `c / GRAZING_COS`, so that it is continuous and
/// vanishes where the receiver turns away from the light (and stops being
/// one). Without this, a scene box wall parallel to a sun in the camera's
/// vertical plane (lit by 10⁻¹⁷ after rounding) predicted 10⁸ screen pixels
/// per texel and placed the split planes alone, and the same wall lit by 0
/// was no receiver at all.
pub(crate) fn light_factor(c: f64) -> f64 {
    if c >= GRAZING_COS {
        1.0 / c.sqrt()
    } else {
        c.max(0.0).sqrt() / GRAZING_COS
    }
}

/// How much `m`'s image (`x/w`, `y/w`) magnifies areas on the plane
/// through `p` perpendicular to the unit vector `t`: `|det|` of the image
/// Jacobian restricted to that plane; NaN where `w ≤ 0` at `p`.
pub(crate) fn image_area_scale(m: &DMat4, p: DVec3, t: DVec3) -> f64 {
    let q = *m * h(p);
    if !(q.w > 0.0) {
        return f64::NAN;
    }
    // The image gradients: d(x/w) = (x_row·w − x·w_row)/w², likewise for y.
    // The area scale on the plane ⊥ t, in any orthonormal basis b₁, b₂ of
    // it, is (g_x·b₁)(g_y·b₂) − (g_x·b₂)(g_y·b₁) = (g_x × g_y)·(b₁ × b₂),
    // and b₁ × b₂ = t: no basis is needed.
    // NOTE: each gradient is divided by w² before the cross product, as the
    // quotient rule has it, so that a large w cannot overflow the product.
    let inv_w2 = 1.0 / (q.w * q.w);
    let w_row = m.row(3).truncate();
    let gx = (m.row(0).truncate() * q.w - w_row * q.x) * inv_w2;
    let gy = (m.row(1).truncate() * q.w - w_row * q.y) * inv_w2;
    gx.cross(gy).dot(t).abs()
}

/// The image points `(x/w, y/w)` of `pts` under the clip matrix `m`,
/// written into `out`; `None` where some point has no positive `w`.
pub(crate) fn image_points<'a>(m: &DMat4, pts: &[DVec3], out: &'a mut [DVec2; MAX_VERTICES]) -> Option<&'a mut [DVec2]> {
    for (o, p) in out.iter_mut().zip(pts) {
        let c = *m * h(*p);
        if !(c.w > 0.0) {
            return None;
        }
        *o = DVec2::new(c.x / c.w, c.y / c.w);
    }
    Some(&mut out[..pts.len()])
}

/// Fraction of the map's image square `[−1, 1]²` covered by the projection
/// of `pts` under the clip matrix `m` (every point with `w > 0`): the area
/// of the convex hull of the projected points, divided by 4.
pub(crate) fn utilisation(m: &DMat4, pts: &[DVec3]) -> f64 {
    let mut q = [DVec2::ZERO; MAX_VERTICES];
    image_points(m, pts, &mut q).map_or(0.0, |q| (0.25 * hull_area(q)).min(1.0))
}

/// `m` relative to the f32 origin, rounded to f32.
///
/// NOTE: with the origin at zero the product with the identity is skipped:
/// it is exact, up to the sign of zero entries.
pub(crate) fn f32_matrix(m: &DMat4, origin: DVec3) -> glam::Mat4 {
    if origin == DVec3::ZERO {
        m.as_mat4()
    } else {
        (*m * DMat4::from_translation(origin)).as_mat4()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inside(m: &DMat4, p: DVec3) -> bool {
        let q = *m * h(p);
        q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= 0.0 && q.z <= q.w
    }

    #[test]
    fn directional_projection_is_orthographic_along_the_light() {
        let d = DVec3::new(0.3, -1.0, 0.2).normalize();
        let pts = [DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0), DVec3::new(-4.0, 0.5, 1.0)];
        let c = central_projection((-d).extend(0.0), &pts, DepthKind::Polar, DVec3::NEG_Z, DVec3::X, None).unwrap();
        let m = crop(&c.m, &pts, DVec3::ZERO, ClipConvention::WGPU).unwrap().m;
        for p in pts {
            assert!(inside(&m, p));
            // Moving along the light keeps the texel and increases depth.
            let (a, b) = (m * h(p), m * h(p + d * 0.5));
            assert!((a.x / a.w - b.x / b.w).abs() < 1e-12 && (a.y / a.w - b.y / b.w).abs() < 1e-12);
            assert!(b.z / b.w > a.z / a.w);
        }
        assert!(m.row(2).dot((-d).extend(0.0)) < 0.0, "less test");
    }

    #[test]
    fn point_projection_rays_share_texels() {
        let l = DVec3::new(0.0, 10.0, 0.0);
        let pts = [DVec3::new(-3.0, 0.0, -3.0), DVec3::new(3.0, 0.0, -3.0), DVec3::new(0.0, 1.0, 4.0)];
        let c = central_projection(l.extend(1.0), &pts, DepthKind::Perspective, DVec3::NEG_Z, DVec3::X, None).unwrap();
        let m = crop(&c.m, &pts, DVec3::ZERO, ClipConvention::WGPU).unwrap().m;
        for p in pts {
            assert!(inside(&m, p));
            let q = l + (p - l) * 0.7;
            let (a, b) = (m * h(p), m * h(q));
            assert!((a.x / a.w - b.x / b.w).abs() < 1e-12);
            assert!(b.z / b.w < a.z / a.w, "nearer the light, smaller depth");
        }
    }

    /// Against finite differences: one texel's area on the plane across
    /// the light ray, measured with an explicit basis of that plane.
    #[test]
    fn texel_size_of_perspective_map_matches_finite_differences() {
        let l = DVec3::new(2.0, 10.0, -1.0);
        let pts = [DVec3::new(-3.0, 0.0, -3.0), DVec3::new(3.0, 0.5, -3.0), DVec3::new(0.0, 1.0, 4.0), DVec3::new(1.0, -2.0, 0.0)];
        let c = central_projection(l.extend(1.0), &pts, DepthKind::Perspective, DVec3::NEG_Z, DVec3::X, None).unwrap();
        let m = crop(&c.m, &pts, DVec3::ZERO, ClipConvention::WGPU).unwrap().m;
        let image = |p: DVec3| {
            let q = m * h(p);
            (q.x / q.w, q.y / q.w)
        };
        for p in pts {
            let t = (p - l).normalize();
            let b1 = t.any_orthonormal_vector();
            let b2 = t.cross(b1);
            let step = 1e-5;
            let (x0, y0) = image(p);
            let (x1, y1) = image(p + b1 * step);
            let (x2, y2) = image(p + b2 * step);
            let area = ((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)).abs() / (step * step);
            let want = (2.0 / 512.0) / area.sqrt();
            let got = texel_size(&m, l.extend(1.0), p, 512);
            assert!((got - want).abs() < 1e-4 * want, "{got} vs {want}");
        }
        // Behind the light (w ≤ 0) no texel sees the point.
        assert_eq!(texel_size(&m, l.extend(1.0), l * 2.0 - pts[0], 512), f64::INFINITY);
    }

    #[test]
    fn light_inside_points_has_no_single_projection() {
        let pts = [DVec3::new(-1.0, -1.0, -1.0), DVec3::new(1.0, 1.0, 1.0), DVec3::new(1.0, -1.0, 0.0), DVec3::new(-1.0, 1.0, 0.5)];
        assert!(central_projection(DVec4::new(0.0, 0.0, 0.0, 1.0), &pts, DepthKind::Perspective, DVec3::Z, DVec3::X, None).is_none());
    }

    #[test]
    fn warp_is_identity_at_zero_and_keeps_rays() {
        let m = DMat4::from_cols_array(&[1.0, 2.0, 3.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.3, 1.0, 0.0, 0.1, 0.2, 0.3, 1.0]);
        assert_eq!(apply_warp(&m, &Warp { epsilon: 0.0, xi_c: 3.0, eta0: 0.0 }), m);
        let w = apply_warp(&m, &Warp { epsilon: 0.5, xi_c: 1.0, eta0: -2.0 });
        // Rows x, y, w of the warped map are combinations of the originals.
        let l = DVec4::new(0.2, -0.4, 1.0, 0.0); // some vector
        let _ = w * l;
        assert!(w.is_finite());
    }

    #[test]
    fn crop_handles_point_bodies() {
        let pts = [DVec3::new(5.0, 5.0, 5.0)];
        let c = central_projection(DVec4::new(0.0, 1.0, 0.0, 0.0), &pts, DepthKind::Polar, DVec3::NEG_Z, DVec3::X, None).unwrap();
        let m = crop(&c.m, &pts, DVec3::ZERO, ClipConvention::WGPU).unwrap().m;
        assert!(m.is_finite() && inside(&m, pts[0]));
    }

    #[test]
    fn texel_size_of_orthographic_map() {
        let pts = [DVec3::new(-5.0, 0.0, -5.0), DVec3::new(5.0, 0.0, 5.0), DVec3::new(5.0, 0.0, -5.0), DVec3::new(-5.0, 0.0, 5.0)];
        let down = DVec4::new(0.0, 1.0, 0.0, 0.0); // light above, travelling −y
        let c = central_projection(down, &pts, DepthKind::Polar, DVec3::NEG_Z, DVec3::X, None).unwrap();
        let m = crop(&c.m, &pts, DVec3::ZERO, ClipConvention::WGPU).unwrap().m;
        let s = texel_size(&m, down, DVec3::ZERO, 100);
        // 10 world units over 100 texels, plus the rounding margin.
        assert!((s - 0.1).abs() < 1e-5, "{s}");
    }
}
