//! Clip conventions: the depth range, depth direction and texture layout of
//! the graphics API a map is rendered and sampled with.
//!
//! A map's `x`, `y` and `w` rows do not depend on the convention (a map is
//! the same set of light rays in every API); only its depth row does, and
//! the matrix a shader looks the map up with. The depth row is written
//! from the centred row `Z_c = Z − c W` and the half extent `h` that the
//! crop proves (`|Z_c| ≤ h W` at every body vertex, rounding included; see
//! `project::crop`):
//!
//! | depth range | reversed | depth row            | body vertices in |
//! |-------------|----------|----------------------|------------------|
//! | `[0, 1]`    | no       | `(Z_c + h W) / 2h`   | `0 ≤ z ≤ w`      |
//! | `[0, 1]`    | yes      | `(h W − Z_c) / 2h`   | `0 ≤ z ≤ w`      |
//! | `[−1, 1]`   | no       | `Z_c / h`            | `−w ≤ z ≤ w`     |
//! | `[−1, 1]`   | yes      | `−Z_c / h`           | `−w ≤ z ≤ w`     |
//!
//! Negating `Z_c` is exact and `|Z_c ± hW| ≤ |Z_c| + h|W|` entrywise, so
//! every row has the rounding bound the crop already allowed for the first
//! one (the `[−1, 1]` rows are written exactly as the `x` and `y` rows
//! are): the guarantee holds in every convention with the same margins.
//! Reversing negates the depth row, so the depth test derived from its side
//! of the light ([`crate::DepthTest`]) flips by itself.

use crate::result::DepthTest;
use glam::{DMat4, DVec4};

/// The range of clip depth `z/w` that the rasteriser keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DepthRange {
    /// `0 ≤ z/w ≤ 1`: wgpu, Vulkan, Direct3D, Metal (and OpenGL with
    /// `glClipControl(…, GL_ZERO_TO_ONE)`).
    ZeroToOne,
    /// `−1 ≤ z/w ≤ 1`: OpenGL and OpenGL ES by default.
    MinusOneToOne,
}

/// Where texture coordinate `v = 0` lies: at the texel row the API stores
/// first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum UvOrigin {
    /// The first row is the image's top (wgpu, Vulkan, Direct3D, Metal).
    TopLeft,
    /// The first row is the image's bottom (OpenGL).
    BottomLeft,
}

/// How an API maps clip space to the depth buffer and the rendered image
/// to texture coordinates. [`ClipConvention::WGPU`] is the default; the
/// presets name the APIs, and [`ClipConvention::reversed`] turns on
/// reversed-Z for any of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ClipConvention {
    /// The clip depth range.
    pub depth: DepthRange,
    /// Depth 1 (the range's top) nearest the light, decreasing away from
    /// it; rendered and sampled with the greater test.
    pub reversed_z: bool,
    /// Which texel row `v = 0` names.
    pub uv_origin: UvOrigin,
    /// Clip `+y` points down the rendered image (Vulkan); up otherwise.
    pub y_down: bool,
}

impl Default for ClipConvention {
    fn default() -> Self {
        ClipConvention::WGPU
    }
}

impl ClipConvention {
    /// wgpu: depth in `[0, 1]`, `+y` up, first texel row at the top.
    pub const WGPU: ClipConvention =
        ClipConvention { depth: DepthRange::ZeroToOne, reversed_z: false, uv_origin: UvOrigin::TopLeft, y_down: false };
    /// Direct3D 11 and 12: as wgpu.
    pub const D3D: ClipConvention = ClipConvention::WGPU;
    /// Metal: as wgpu.
    pub const METAL: ClipConvention = ClipConvention::WGPU;
    /// Vulkan: depth in `[0, 1]`, `+y` down, first texel row at the top.
    pub const VULKAN: ClipConvention = ClipConvention { y_down: true, ..ClipConvention::WGPU };
    /// OpenGL: depth in `[−1, 1]`, `+y` up, first texel row at the bottom.
    pub const OPENGL: ClipConvention =
        ClipConvention { depth: DepthRange::MinusOneToOne, reversed_z: false, uv_origin: UvOrigin::BottomLeft, y_down: false };

    /// The same convention with reversed-Z.
    pub const fn reversed(self) -> ClipConvention {
        ClipConvention { reversed_z: true, ..self }
    }

    /// The lower end of clip depth `z/w` (the upper one is 1).
    pub fn depth_min(self) -> f64 {
        match self.depth {
            DepthRange::ZeroToOne => 0.0,
            DepthRange::MinusOneToOne => -1.0,
        }
    }

    /// The depth test of a map whose light is not inverted: less, or
    /// greater with reversed-Z. A PSM map of an inverted light uses the
    /// other one.
    pub fn normal_depth_test(self) -> DepthTest {
        self.depth_test(false)
    }

    /// The depth test of a map: the depth row's side of the light (see
    /// `project`), known from how the row was built rather than from the
    /// sign of the rounded product `z·L`, which rounding decides where the
    /// body is tiny against its coordinates. Every light space's depth row
    /// has `z·L < 0` (less) except PSM's inverted light's; reversed-Z
    /// negates it.
    pub(crate) fn depth_test(self, inverted: bool) -> DepthTest {
        if inverted != self.reversed_z {
            DepthTest::Greater
        } else {
            DepthTest::Less
        }
    }

    /// The depth row from the centred row `zc`, the `w` row and `1/h` (see
    /// the module's table).
    ///
    /// NOTE: `zc · 1.0` is exact, so the default convention's row is the
    /// same expression, bit for bit, as the `[0, 1]` crop always wrote.
    #[inline]
    pub(crate) fn depth_row(self, zc: DVec4, w: DVec4, h: f64, inv_h: f64) -> DVec4 {
        let s = if self.reversed_z { -1.0 } else { 1.0 };
        match self.depth {
            DepthRange::ZeroToOne => (zc * s + w * h) * (0.5 * inv_h),
            DepthRange::MinusOneToOne => zc * (s * inv_h),
        }
    }

    /// The rows `u`, `v`, depth and `w` of the lookup from clip space:
    /// `u = (x/w + 1)/2` left to right, `v` from the first texel row
    /// (`(1 ∓ y/w)/2`), and depth as the depth buffer stores it, in
    /// `[0, 1]` for every convention (OpenGL's window transform maps clip
    /// `[−1, 1]` to `0.5 z/w + 0.5`), which is what a comparison sampler
    /// compares with.
    pub fn uv_from_clip(self) -> DMat4 {
        // v = 0 at clip y = +1 exactly when the image's top is stored first
        // and clip +y points up the image (or both are flipped).
        let top_first = self.uv_origin == UvOrigin::TopLeft;
        let sv = if top_first != self.y_down { -0.5 } else { 0.5 };
        let depth = match self.depth {
            DepthRange::ZeroToOne => DVec4::new(0.0, 0.0, 1.0, 0.0),
            DepthRange::MinusOneToOne => DVec4::new(0.0, 0.0, 0.5, 0.5),
        };
        crate::project::from_rows(DVec4::new(0.5, 0.0, 0.0, 0.5), DVec4::new(0.0, sv, 0.0, 0.5), depth, DVec4::W)
    }

    /// Clip depth `z/w` of the view depth `z` under the right-handed camera
    /// projection with near `n` and far `f` in this convention:
    /// `d = f (z − n) / (z (f − n))` for `[0, 1]` (glam's
    /// `dcamera::rh::proj::directx::perspective`), `1 − d` reversed, and
    /// `2d − 1` (resp. `1 − 2d`) for `[−1, 1]`.
    pub fn camera_depth(self, near: f64, far: f64, z: f64) -> f64 {
        let (n, f) = (near, far);
        // NOTE: the reversed depth as n (f − z) / (z (f − n)) rather than
        // 1 − d keeps its full relative precision near the far plane.
        let d = if self.reversed_z { n / (f - n) * (f / z - 1.0) } else { f / (f - n) * (1.0 - n / z) };
        match self.depth {
            DepthRange::ZeroToOne => d,
            DepthRange::MinusOneToOne => 2.0 * d - 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    const ALL: [ClipConvention; 4] =
        [ClipConvention::WGPU, ClipConvention::VULKAN, ClipConvention::OPENGL, ClipConvention::WGPU.reversed()];

    #[test]
    fn camera_depths_run_over_the_range_from_near_to_far() {
        let (n, f) = (0.3, 250.0);
        for clip in ALL.into_iter().chain([ClipConvention::OPENGL.reversed()]) {
            let (at_near, at_far) = (clip.camera_depth(n, f, n), clip.camera_depth(n, f, f));
            let (lo, hi) = (clip.depth_min(), 1.0);
            let (want_near, want_far) = if clip.reversed_z { (hi, lo) } else { (lo, hi) };
            assert!((at_near - want_near).abs() < 1e-15 && (at_far - want_far).abs() < 1e-15, "{clip:?}: {at_near}, {at_far}");
            // Monotone in between, and the reversed one is 1 − the plain one.
            let mid = clip.camera_depth(n, f, 10.0);
            assert!((mid - want_near) * (want_far - mid) > 0.0, "{clip:?}: {mid}");
        }
        let (d, r) = (ClipConvention::WGPU.camera_depth(n, f, 10.0), ClipConvention::WGPU.reversed().camera_depth(n, f, 10.0));
        assert!((d + r - 1.0).abs() < 1e-15);
    }

    #[test]
    fn lookup_maps_the_clip_square_to_the_unit_square() {
        // Clip (x, y) = (−1, +1), the image's top-left corner in every API
        // with clip +y up; Vulkan draws it at the bottom-left.
        let corner = DVec4::new(-1.0, 1.0, 0.25, 1.0);
        let uv = |c: ClipConvention| c.uv_from_clip() * corner;
        assert_eq!(uv(ClipConvention::WGPU), DVec4::new(0.0, 0.0, 0.25, 1.0));
        assert_eq!(uv(ClipConvention::VULKAN), DVec4::new(0.0, 1.0, 0.25, 1.0));
        // OpenGL: v from the bottom row, depth through the window transform.
        assert_eq!(uv(ClipConvention::OPENGL), DVec4::new(0.0, 1.0, 0.625, 1.0));
        for c in ALL {
            // Homogeneous: scaling the clip point scales its lookup.
            assert_eq!(c.uv_from_clip() * (corner * 4.0), uv(c) * 4.0);
        }
    }

    #[test]
    fn depth_rows_hold_the_crop_range_in_the_conventions_range() {
        // A centred row at ±h·W is the range's ends, in the right order.
        let (w, h) = (DVec4::W, 0.5);
        for clip in ALL.into_iter().chain([ClipConvention::OPENGL.reversed()]) {
            // At the point (0, 0, 0, 1): W = 1 and the centred row is zc.
            let at = |zc: f64| clip.depth_row(DVec4::new(0.0, 0.0, 0.0, zc), w, h, 1.0 / h).w;
            let (lo, hi) = if clip.reversed_z { (at(h), at(-h)) } else { (at(-h), at(h)) };
            assert_eq!((lo, hi), (clip.depth_min(), 1.0), "{clip:?}");
        }
    }
}
