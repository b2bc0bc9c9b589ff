//! Inputs of a frame: camera, light, shadow maps and render settings.

use glam::{DMat4, DVec3, DVec4, Mat4};
use serde::{Deserialize, Serialize};

use crate::error::{check_finite, RenderError};

/// Axis-aligned box in world space (f64; exact images of the f32 vertex data).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub min: DVec3,
    pub max: DVec3,
}

impl Bounds {
    /// The empty box: the identity of [`Bounds::grow`].
    pub const EMPTY: Bounds = Bounds { min: DVec3::splat(f64::INFINITY), max: DVec3::splat(f64::NEG_INFINITY) };

    pub fn grow(&mut self, p: DVec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn union(&self, o: &Bounds) -> Bounds {
        Bounds { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }

    /// Corners in the order x fastest, then y, then z.
    pub fn corners(&self) -> [DVec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            DVec3::new(a.x, a.y, a.z),
            DVec3::new(b.x, a.y, a.z),
            DVec3::new(a.x, b.y, a.z),
            DVec3::new(b.x, b.y, a.z),
            DVec3::new(a.x, a.y, b.z),
            DVec3::new(b.x, a.y, b.z),
            DVec3::new(a.x, b.y, b.z),
            DVec3::new(b.x, b.y, b.z),
        ]
    }
}

/// Orthonormal camera frame: right = forward × up, up = right × forward.
fn orthonormal_frame(what: &str, forward: DVec3, up: DVec3) -> Result<(DVec3, DVec3, DVec3), RenderError> {
    let f = forward.normalize_or_zero();
    if f == DVec3::ZERO {
        return Err(RenderError::invalid(what, "forward/direction is the zero vector"));
    }
    let r = f.cross(up).normalize_or_zero();
    if r == DVec3::ZERO {
        return Err(RenderError::invalid(what, "up is zero or parallel to the forward direction"));
    }
    Ok((f, r, r.cross(f)))
}

/// A pinhole camera. The aspect ratio comes from the image size of each render.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraSpec {
    pub eye: DVec3,
    /// Viewing direction (need not be unit length).
    pub forward: DVec3,
    pub up: DVec3,
    /// Full vertical field of view, radians.
    pub fovy: f64,
    pub near: f64,
    pub far: f64,
}

impl CameraSpec {
    pub fn validate(&self) -> Result<(), RenderError> {
        let v = [self.eye, self.forward, self.up];
        for (name, x) in ["camera eye", "camera forward", "camera up"].iter().zip(v) {
            check_finite(name, &x.to_array())?;
        }
        check_finite("camera fovy/near/far", &[self.fovy, self.near, self.far])?;
        if !(self.fovy > 0.0 && self.fovy < std::f64::consts::PI) {
            return Err(RenderError::invalid("camera fovy", format!("{} rad is not in (0, π)", self.fovy)));
        }
        if !(self.near > 0.0 && self.near < self.far) {
            return Err(RenderError::invalid("camera near/far", format!("need 0 < near < far, got near {} far {}", self.near, self.far)));
        }
        orthonormal_frame("camera", self.forward, self.up).map(|_| ())
    }

    /// (forward, right, up), orthonormal; the same convention as `shadowfocus_geom::Camera::basis`.
    pub fn basis(&self) -> Result<(DVec3, DVec3, DVec3), RenderError> {
        orthonormal_frame("camera", self.forward, self.up)
    }

    /// Distance along the unit forward axis: the depth that shadow-map splits are measured in.
    pub fn view_depth(&self, p: DVec3) -> f64 {
        (p - self.eye).dot(self.forward.normalize())
    }

    pub fn view_matrix(&self) -> Result<DMat4, RenderError> {
        let (f, _, u) = self.basis()?;
        Ok(glam::dcamera::rh::view::look_to_mat4(self.eye, f, u))
    }

    /// Reversed-z perspective projection: view depth `near` maps to z = 1, `far` to z = 0.
    ///
    /// Derivation: with view-space depth d = −z_view, we want z_ndc = a + b/d with
    /// z_ndc(near) = 1 and z_ndc(far) = 0, so b = near·far/(far − near), a = −near/(far − near).
    /// As a matrix row (clip w = d): z_clip = a·d + b = −a·z_view + b.
    /// NOTE: reversed z puts the floating-point density of a Depth32Float buffer where
    /// perspective depth is coarsest (far away), so the 800 m scenes need no near/far tuning.
    pub fn projection_matrix(&self, aspect: f64) -> DMat4 {
        let t = 1.0 / (0.5 * self.fovy).tan();
        let (n, f) = (self.near, self.far);
        let a = -n / (f - n);
        let b = n * f / (f - n);
        DMat4::from_cols(
            DVec4::new(t / aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, t, 0.0, 0.0),
            DVec4::new(0.0, 0.0, -a, -1.0),
            DVec4::new(0.0, 0.0, b, 0.0),
        )
    }

    /// The 8 frustum corners for an aspect ratio: near face first, then far face, each in the order
    /// (−r−u), (+r−u), (+r+u), (−r+u) — the order `shadowfocus_geom::Frustum::from_corners` takes.
    pub fn corners(&self, aspect: f64) -> Result<[DVec3; 8], RenderError> {
        let (f, r, u) = self.basis()?;
        let th = (0.5 * self.fovy).tan();
        let mut out = [DVec3::ZERO; 8];
        for (k, d) in [self.near, self.far].into_iter().enumerate() {
            let (hu, hr) = (d * th, d * th * aspect);
            let c = self.eye + f * d;
            out[4 * k] = c - r * hr - u * hu;
            out[4 * k + 1] = c + r * hr - u * hu;
            out[4 * k + 2] = c + r * hr + u * hu;
            out[4 * k + 3] = c - r * hr + u * hu;
        }
        Ok(out)
    }
}

/// The light of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LightSpec {
    /// A light at infinity; `direction` is the travel direction (light → scene).
    Directional { direction: DVec3 },
    /// An omnidirectional point light.
    Point { position: DVec3 },
    /// A spot light whose lit region is a square pyramid (the frustum L of the focus body):
    /// apex `position`, axis `direction`, full opening angle `fovy`, clipped to [near, far].
    Spot { position: DVec3, direction: DVec3, up: DVec3, fovy: f64, near: f64, far: f64 },
}

impl LightSpec {
    pub fn validate(&self) -> Result<(), RenderError> {
        match *self {
            LightSpec::Directional { direction } => {
                check_finite("light direction", &direction.to_array())?;
                if direction.length_squared() == 0.0 {
                    return Err(RenderError::invalid("light direction", "is the zero vector"));
                }
            }
            LightSpec::Point { position } => check_finite("light position", &position.to_array())?,
            LightSpec::Spot { position, direction, up, fovy, near, far } => {
                check_finite("spot light position", &position.to_array())?;
                check_finite("spot light direction/up", &[direction.to_array(), up.to_array()].concat())?;
                check_finite("spot light fovy/near/far", &[fovy, near, far])?;
                if !(fovy > 0.0 && fovy < std::f64::consts::PI) {
                    return Err(RenderError::invalid("spot light fovy", format!("{fovy} rad is not in (0, π)")));
                }
                if !(near > 0.0 && near < far) {
                    return Err(RenderError::invalid("spot light near/far", format!("need 0 < near < far, got {near}, {far}")));
                }
                orthonormal_frame("spot light", direction, up)?;
            }
        }
        Ok(())
    }

    /// Position of a point or spot light; `None` for a directional light.
    pub fn position(&self) -> Option<DVec3> {
        match *self {
            LightSpec::Directional { .. } => None,
            LightSpec::Point { position } | LightSpec::Spot { position, .. } => Some(position),
        }
    }

    /// Unit vector from `p` toward the light and the distance to it (∞ for a directional light).
    pub fn toward_light(&self, p: DVec3) -> (DVec3, f64) {
        match *self {
            LightSpec::Directional { direction } => (-direction.normalize(), f64::INFINITY),
            LightSpec::Point { position } | LightSpec::Spot { position, .. } => {
                let v = position - p;
                let d = v.length();
                (v / d, d)
            }
        }
    }

    /// World → clip matrix of a spot light's pyramid (z ∈ [0, 1]); `None` for other lights.
    pub fn spot_matrix(&self) -> Option<DMat4> {
        match *self {
            LightSpec::Spot { position, direction, up, fovy, near, far } => {
                let (f, _, u) = orthonormal_frame("spot light", direction, up).ok()?;
                Some(
                    glam::dcamera::rh::proj::directx::perspective(fovy, 1.0, near, far)
                        * glam::dcamera::rh::view::look_to_mat4(position, f, u),
                )
            }
            _ => None,
        }
    }

    /// Whether `p` lies in the lit pyramid of a spot light (always true for other lights).
    pub fn in_spot(&self, p: DVec3) -> bool {
        match self.spot_matrix() {
            None => true,
            Some(m) => {
                let c = m * p.extend(1.0);
                c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
            }
        }
    }

    /// Corners of a spot light's pyramid (near face, then far face; (−r−u), (+r−u), (+r+u), (−r+u)),
    /// ready for `shadowfocus_geom::Frustum::from_corners`; `None` for other lights.
    pub fn spot_frustum_corners(&self) -> Option<[DVec3; 8]> {
        match *self {
            LightSpec::Spot { position, direction, up, fovy, near, far } => {
                CameraSpec { eye: position, forward: direction, up, fovy, near, far }.corners(1.0).ok()
            }
            _ => None,
        }
    }
}

/// Which depth comparison a shadow map is rendered and sampled with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DepthTest {
    /// Smaller z is nearer the light (the usual case).
    #[default]
    Less,
    /// Larger z is nearer the light (inverted perspective shadow maps: light behind the viewer).
    Greater,
}

/// One shadow map (one layer of the shadow texture array).
#[derive(Clone, Debug, PartialEq)]
pub struct ShadowMapSpec {
    /// World → clip. After the divide by w (which must be > 0 on what the map covers),
    /// x, y ∈ [−1, 1] and z ∈ [0, 1] (wgpu convention); +y is the top row of the map.
    pub world_to_clip: Mat4,
    pub depth_test: DepthTest,
    /// View-depth range [start, end] (along the camera's unit forward axis) this map serves.
    pub split: [f32; 2],
    /// Indices into `Scene::objects` drawn into this map.
    pub casters: Vec<u32>,
    /// For one face of a point light's cube: which receivers the map answers for.
    pub face: Option<CubeFaceSpec>,
    /// The map's side in texels, when it has its own (a share of a texel budget); `None`:
    /// `RenderSettings::shadow_resolution`. Maps share one texture array as wide as the
    /// largest; a smaller map is drawn into, and looked up in, that layer's top-left corner.
    pub resolution: Option<u32>,
}

impl ShadowMapSpec {
    /// The map's side in texels: its own, or `default` (the frame's `shadow_resolution`).
    pub fn resolution_or(&self, default: u32) -> u32 {
        self.resolution.unwrap_or(default)
    }
}

/// One face of a point light's cube of maps. A face's map holds the casters of the receivers in
/// its own 90° cone only, while its fitted image may reach past the cone into its neighbours'; a
/// receiver is therefore looked up in the face of its direction from the light, as a cube map
/// chooses, and never in another face whose image happens to hold it too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubeFaceSpec {
    /// The light's position.
    pub light: DVec3,
    /// The face: 0 = +x, 1 = −x, 2 = +y, 3 = −y, 4 = +z, 5 = −z.
    pub index: u32,
}

impl CubeFaceSpec {
    /// The face of direction `d`: its largest coordinate in magnitude (the first on ties) and
    /// that coordinate's sign.
    pub fn index_toward(d: DVec3) -> u32 {
        let a = d.abs();
        let k = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        2 * k as u32 + u32::from(d[k] < 0.0)
    }

    /// Whether the face answers for the receiver `p`.
    pub fn holds(&self, p: DVec3) -> bool {
        CubeFaceSpec::index_toward(p - self.light) == self.index
    }
}

/// Shadow-map filtering in the main pass.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Pcf {
    /// One nearest-texel comparison: a binary, unfiltered shadow test.
    Off,
    /// The sampler's bilinear comparison (2×2 texels).
    Hardware2x2,
    /// (2r+1)² bilinear comparisons one texel apart: a (2r+2)² texel footprint.
    Kernel { radius: u32 },
}

/// Eye-space, depth-dependent blur of the shadow term [SCH05 §4.3].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EyeBlur {
    /// Kernel radius in world units at the surface: a constant eye-space size, so its
    /// on-screen radius shrinks as 1/depth — near shadows are blurred more than far ones.
    pub world_radius: f32,
    /// Cap on the on-screen radius, pixels.
    pub max_radius_px: f32,
    /// Separable (horizontal + vertical) iterations.
    pub iterations: u32,
}

/// How depth is stored in the shadow maps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum DepthMode {
    /// The map's own projective z. With `receiver_plane` (the default) each map gets its own bias,
    /// chosen per fragment in the main pass from the map's texel footprint and depth derivative on
    /// the receiver's plane (receiver-plane depth bias: see `shadow_lookup` in `scene.wgsl` for the
    /// derivation), plus a constant term of a few steps of the depth format. `constant` and
    /// `slope_scale` add wgpu's `DepthBiasState` to the casters on top of that (`constant` in units
    /// of the smallest resolvable depth step, `slope_scale` × max depth slope per texel); they are 0
    /// by default. Both point away from the light, for `DepthTest::Greater` maps too.
    Projective { constant: i32, slope_scale: f32, receiver_plane: bool },
    /// Linear light depth [SCH05 §4.2]: distance along the light direction (directional)
    /// or from the light (point, spot), normalised over the scene bounds, written per fragment and
    /// compared with "less" whatever the map's projective depth test. Bias = `constant` +
    /// `slope_scale` × max(|∂d/∂x|, |∂d/∂y|) per shadow-map texel, in normalised depth units.
    Linear { constant: f32, slope_scale: f32 },
}

/// Everything about a render that is not the scene, camera, light or maps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Side of every shadow-map layer, texels.
    pub shadow_resolution: u32,
    pub depth: DepthMode,
    pub pcf: Pcf,
    /// Blend band at the far end of each split, as a fraction of the split's depth length
    /// (0 = hard switch between maps).
    pub blend_band: f32,
    pub blur: Option<EyeBlur>,
    /// Rasterise casters in front of a map's near plane at depth 0 instead of clipping them
    /// ("pancaking"; needs `DEPTH_CLIP_CONTROL`, ignored where the adapter lacks it). Off by
    /// default: a map must then contain every caster that matters, and a focusing error that
    /// cuts one off shows up as a mismatch instead of being hidden.
    pub depth_clamp: bool,
    /// Also read the shadow maps back (rendered a second time into a float colour target,
    /// since depth textures cannot be copied to buffers on GL).
    pub save_shadow_maps: bool,
    /// Ray-cast ground truth and mismatch metrics.
    pub ground_truth: bool,
    /// A pixel is "off edges" when the ground truth is the same over the (2r+1)² pixels around it.
    pub edge_radius: u32,
    /// Run the GPU passes this many times and report the fastest (≥ 1).
    pub timing_repeats: u32,
    /// The view depths between [`RECEIVER_SLICES`] slices of the view, ascending: reduce the
    /// receiver pixels' world positions into each slice's bounds and greatest depth on the GPU,
    /// apart for each world axis their normal lies closest to
    /// ([`crate::RenderOutput::receiver_slices`]; slice `k` holds the depths in
    /// `[planes[k − 1], planes[k])`). `None`: no such reduction.
    pub receiver_slices: Option<[f32; RECEIVER_SLICES - 1]>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 360,
            shadow_resolution: 1024,
            depth: DepthMode::Projective { constant: 0, slope_scale: 0.0, receiver_plane: true },
            pcf: Pcf::Hardware2x2,
            blend_band: 0.0,
            blur: None,
            depth_clamp: false,
            save_shadow_maps: true,
            ground_truth: true,
            edge_radius: 2,
            timing_repeats: 1,
            receiver_slices: None,
        }
    }
}

/// Largest number of shadow maps per frame.
pub const MAX_MAPS: usize = 16;

/// Slices of the view the receiver pixels are reduced into
/// ([`RenderSettings::receiver_slices`]): as many as the focus library's visible receiver boxes.
pub const RECEIVER_SLICES: usize = 16;

impl RenderSettings {
    pub fn validate(&self) -> Result<(), RenderError> {
        if self.width == 0 || self.height == 0 || self.width > 8192 || self.height > 8192 {
            return Err(RenderError::invalid("image size", format!("{}x{} is not within 1..=8192", self.width, self.height)));
        }
        if !(1..=16384).contains(&self.shadow_resolution) {
            return Err(RenderError::invalid("shadow resolution", format!("{} is not within 1..=16384", self.shadow_resolution)));
        }
        check_finite("blend band", &[self.blend_band as f64])?;
        if !(0.0..=1.0).contains(&self.blend_band) {
            return Err(RenderError::invalid("blend band", format!("{} is not within [0, 1]", self.blend_band)));
        }
        match self.depth {
            DepthMode::Projective { slope_scale, .. } => check_finite("slope-scaled bias", &[slope_scale as f64])?,
            DepthMode::Linear { constant, slope_scale } => check_finite("linear depth bias", &[constant as f64, slope_scale as f64])?,
        }
        if let Pcf::Kernel { radius } = self.pcf {
            if radius > 8 {
                return Err(RenderError::invalid("PCF kernel radius", format!("{radius} > 8")));
            }
        }
        if let Some(b) = self.blur {
            check_finite("blur", &[b.world_radius as f64, b.max_radius_px as f64])?;
            if b.world_radius < 0.0 || b.max_radius_px < 0.0 || b.iterations > 64 {
                return Err(RenderError::invalid("blur", "radii must be ≥ 0 and iterations ≤ 64"));
            }
        }
        if self.timing_repeats == 0 || self.timing_repeats > 100 {
            return Err(RenderError::invalid("timing repeats", "must be within 1..=100"));
        }
        if self.edge_radius > 16 {
            return Err(RenderError::invalid("edge radius", "must be ≤ 16"));
        }
        if let Some(planes) = &self.receiver_slices {
            check_finite("receiver slice planes", &planes.map(f64::from))?;
            if planes.windows(2).any(|p| p[0] > p[1]) {
                return Err(RenderError::invalid("receiver slice planes", "must ascend"));
            }
        }
        Ok(())
    }
}

/// Validates the maps against the scene: count, finite matrices, sane split ranges, caster indices.
pub(crate) fn validate_maps(maps: &[ShadowMapSpec], object_count: usize) -> Result<(), RenderError> {
    if maps.len() > MAX_MAPS {
        return Err(RenderError::invalid("shadow maps", format!("{} maps, at most {MAX_MAPS}", maps.len())));
    }
    for (i, m) in maps.iter().enumerate() {
        let vals: Vec<f64> = m.world_to_clip.to_cols_array().iter().map(|&v| v as f64).collect();
        check_finite(&format!("shadow map {i} matrix"), &vals)?;
        check_finite(&format!("shadow map {i} split"), &[m.split[0] as f64, m.split[1] as f64])?;
        if m.split[0] > m.split[1] {
            return Err(RenderError::invalid(format!("shadow map {i} split"), format!("start {} > end {}", m.split[0], m.split[1])));
        }
        if let Some(r) = m.resolution.filter(|r| !(1..=16384).contains(r)) {
            return Err(RenderError::invalid(format!("shadow map {i} resolution"), format!("{r} is not within 1..=16384")));
        }
        if let Some(&bad) = m.casters.iter().find(|&&c| c as usize >= object_count) {
            return Err(RenderError::invalid(
                format!("shadow map {i} casters"),
                format!("object index {bad} but the scene has {object_count} objects"),
            ));
        }
    }
    Ok(())
}
