//! The shadow test of one world point against the maps a frame read back, on the CPU: what a
//! point's shadow is in this frame's maps, independent of which pixel sees it. Temporal
//! measurements look fixed world points up frame after frame with it (`shadowfocus animate`).
//!
//! The test is the main pass's nearest-texel test with a receiver-plane reference (see
//! `shadow_lookup` in `scene.wgsl`), evaluated in f64: the texel `p` falls in is compared
//! against the depth that the receiver's tangent plane has at that texel's centre.
//!
//! Derivation. With M the map's world → clip matrix, the texel centre's light ray is the line
//! through the homogeneous points A = M⁻¹(x_c, y_c, 0, 1) and B = M⁻¹(x_c, y_c, 1, 1). It meets
//! the plane π = (n, −n·p) at X = (π·B) A − (π·A) B, and M X = (π·B − π·A)(x_c, y_c, ·, 1) with
//! z-row −π·A, so the plane's depth at the centre is z = π·A / (π·A − π·B): no division by a
//! world-space w, and exact for every projective map (perspective, warped or orthographic).

use glam::{DMat4, DVec3, DVec4};

use crate::frame::{DepthMap, RenderOutput};
use crate::types::DepthTest;

/// f32's unit roundoff.
const U32: f64 = 5.960_464_477_539_063e-8;

impl DepthMap {
    /// Whether the map lights the world point `p` on a receiver of unit normal `n`: `None`
    /// where the map does not cover `p` (outside its clip volume) and for linear-depth maps,
    /// whose stored depth is not the matrix's. A texel no caster was drawn into is lit.
    ///
    /// The tolerance is the main pass's: a sixteenth of the plane's depth change per texel
    /// (rasterisation snaps vertices to 1/16 texel) plus the f32 rounding of the rasterised and
    /// the stored depth.
    pub fn lit(&self, p: DVec3, n: DVec3) -> Option<bool> {
        if self.linear {
            return None;
        }
        let m = self.world_to_clip.as_dmat4();
        let c = m * p.extend(1.0);
        let inside = c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w;
        if !inside {
            return None;
        }
        let res = self.resolution as f64;
        let (s, t) = ((0.5 + 0.5 * c.x / c.w) * res, (0.5 - 0.5 * c.y / c.w) * res);
        let (i, j) = ((s.floor() as u32).min(self.resolution - 1), (t.floor() as u32).min(self.resolution - 1));
        let plane = DVec4::new(n.x, n.y, n.z, -n.dot(p));
        let inv = m.inverse();
        let z_at = |u: f64, v: f64| plane_depth(&inv, plane, u, v, res).unwrap_or(c.z / c.w);
        let (u, v) = (i as f64 + 0.5, j as f64 + 0.5);
        let z = z_at(u, v);
        let slope = (z_at(u + 1.0, v) - z).abs() + (z_at(u, v + 1.0) - z).abs();
        let tol = slope / 16.0 + 16.0 * U32 * rounding_scale(&m, p, c) + 2.0 * U32;
        let stored = self.depth[(j * self.resolution + i) as usize] as f64;
        if stored.is_nan() {
            return Some(true);
        }
        let own = if self.reversed { 1.0 - stored } else { stored };
        Some(match self.depth_test {
            DepthTest::Less => z <= own + tol,
            DepthTest::Greater => z >= own - tol,
        })
    }
}

/// The depth of the plane `plane` at texel centre (u, v) (texel units, rows top to bottom) of a
/// map with inverse matrix `inv`; `None` where the plane contains that texel's light ray.
fn plane_depth(inv: &DMat4, plane: DVec4, u: f64, v: f64, res: f64) -> Option<f64> {
    let (x, y) = (2.0 * u / res - 1.0, 1.0 - 2.0 * v / res);
    let a = plane.dot(*inv * DVec4::new(x, y, 0.0, 1.0));
    let b = plane.dot(*inv * DVec4::new(x, y, 1.0, 1.0));
    let z = a / (a - b);
    z.is_finite().then_some(z)
}

/// (Σ|m_zj||p_j| + |z| Σ|m_wj||p_j|) / w: the magnitude that f32 rounding of the point's depth
/// scales with (as `depth_rounding` in `scene.wgsl`).
fn rounding_scale(m: &DMat4, p: DVec3, c: DVec4) -> f64 {
    let ap = p.abs().extend(1.0);
    let row = |k: usize| DVec4::new(m.x_axis[k], m.y_axis[k], m.z_axis[k], m.w_axis[k]).abs().dot(ap);
    (row(2) + (c.z / c.w).abs() * row(3)) / c.w
}

impl RenderOutput {
    /// The shadow test of world point `p` (receiver normal `n`) in this frame's maps, choosing the
    /// map as the main pass does (the first whose split holds p's view depth and whose clip
    /// volume holds p, among a point light's cube faces only the face of p's direction) and
    /// looking p up, as it does, lifted by the surface offset: `Some(true)` lit, `Some(false)`
    /// shadowed, `None` where no map covers p or the maps were not read back
    /// (`save_shadow_maps`).
    pub fn lit_at(&self, p: DVec3, n: DVec3) -> Option<bool> {
        let c = &self.camera;
        let (f, eye) = (c.forward.normalize(), c.eye);
        // NOTE: clamped as in the main pass, so that points at the frustum's ends find a map.
        let depth = (p - eye).dot(f).clamp(c.near, c.far);
        let answers = |m: &&DepthMap| depth >= m.split[0] as f64 && depth <= m.split[1] as f64 && m.face.is_none_or(|c| c.holds(p));
        let lifted = p + n * self.surface_offset;
        self.shadow_maps.iter().filter(answers).find_map(|m| m.lit(lifted, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    /// An orthographic map looking down −z over [−1, 1]² at depths z ∈ [0, 1] for world
    /// z ∈ [1, −1]: a caster at height `h` over the texels of x < 0.
    fn half_covered(h: f32, test: DepthTest, reversed: bool) -> DepthMap {
        let res = 8u32;
        let world_to_clip = Mat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.0, 0.0, 0.0, 0.5, 1.0]);
        let z = 0.5 - 0.5 * h;
        let mut depth = vec![f32::NAN; (res * res) as usize];
        for j in 0..res {
            for i in 0..res / 2 {
                depth[(j * res + i) as usize] = if reversed { 1.0 - z } else { z };
            }
        }
        DepthMap { resolution: res, depth, reversed, world_to_clip, depth_test: test, split: [0.0, 1.0], face: None, linear: false }
    }

    #[test]
    fn a_point_under_a_caster_is_shadowed_and_beside_it_lit() {
        let up = DVec3::Z;
        for reversed in [false, true] {
            let map = half_covered(0.5, DepthTest::Less, reversed);
            assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.0), up), Some(false), "under the caster");
            assert_eq!(map.lit(DVec3::new(0.5, 0.3, 0.0), up), Some(true), "beside it: no caster");
            assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.75), up), Some(true), "above the caster");
            assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.5), up), Some(true), "on the caster itself");
            assert_eq!(map.lit(DVec3::new(1.5, 0.3, 0.0), up), None, "outside the map");
        }
    }

    #[test]
    fn a_tilted_receiver_is_compared_at_the_texel_centre() {
        // The receiver is the caster itself, a plane of slope 1 in x: at p it lies half a texel
        // away from the centre's depth, which a plain comparison of p's own depth would get
        // wrong on one side.
        let res = 8u32;
        let world_to_clip = Mat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -0.5, 0.0, 0.0, 0.0, 0.5, 1.0]);
        let height = |x: f64| 0.5 * x;
        let mut depth = vec![0.0f32; (res * res) as usize];
        for j in 0..res {
            for i in 0..res {
                let x = 2.0 * (i as f64 + 0.5) / res as f64 - 1.0;
                depth[(j * res + i) as usize] = (0.5 - 0.5 * height(x)) as f32;
            }
        }
        let map = DepthMap {
            resolution: res,
            depth,
            reversed: false,
            world_to_clip,
            depth_test: DepthTest::Less,
            split: [0.0, 1.0],
            face: None,
            linear: false,
        };
        let n = DVec3::new(-0.5, 0.0, 1.0).normalize();
        for k in 0..64 {
            let x = -0.99 + 1.98 * k as f64 / 63.0;
            assert_eq!(map.lit(DVec3::new(x, 0.1, height(x)), n), Some(true), "x = {x}");
            assert_eq!(map.lit(DVec3::new(x, 0.1, height(x) - 0.3), n), Some(false), "x = {x}, below");
        }
    }

    #[test]
    fn greater_maps_and_linear_maps() {
        let mut map = half_covered(0.5, DepthTest::Less, false);
        // The same map with z' = 1 − z, compared with greater.
        map.world_to_clip = Mat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.5, 1.0]);
        map.depth.iter_mut().for_each(|d| *d = 1.0 - *d);
        map.depth_test = DepthTest::Greater;
        assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.0), DVec3::Z), Some(false));
        assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.75), DVec3::Z), Some(true));
        map.linear = true;
        assert_eq!(map.lit(DVec3::new(-0.5, 0.3, 0.0), DVec3::Z), None);
    }
}
