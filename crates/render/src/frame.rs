//! One frame: what is asked for ([`RenderRequest`]) and what comes back ([`RenderOutput`]).

use crate::error::RenderError;
use crate::ground_truth::Visibility;
use crate::image::Image;
use crate::scene::Scene;
use crate::stats::RenderMetrics;
use crate::types::{validate_maps, CameraSpec, CubeFaceSpec, DepthMode, DepthTest, LightSpec, RenderSettings, ShadowMapSpec};

/// One frame to render.
#[derive(Clone, Debug)]
pub struct RenderRequest<'a> {
    pub scene: &'a Scene,
    pub camera: CameraSpec,
    pub light: LightSpec,
    pub maps: &'a [ShadowMapSpec],
    /// Per map (in `maps` order), the fraction of the map's area that its focus body's projection
    /// covers (`shadowfocus_focus::ShadowMap::utilisation`), when the caller knows it: reported in
    /// the metrics. Empty when unknown; otherwise one value per map.
    pub utilisation: &'a [f64],
    pub settings: RenderSettings,
}

impl<'a> RenderRequest<'a> {
    /// The scene's own camera and light with default settings.
    pub fn new(scene: &'a Scene, maps: &'a [ShadowMapSpec]) -> RenderRequest<'a> {
        RenderRequest { scene, camera: scene.camera, light: scene.light, maps, utilisation: &[], settings: RenderSettings::default() }
    }

    pub fn aspect(&self) -> f64 {
        self.settings.width as f64 / self.settings.height as f64
    }

    /// The comparison the shadow depth buffer is rendered with: `Greater` (a reversed buffer,
    /// cleared to 0, far at 0) when every map of the frame is a "greater" map in projective mode —
    /// a reversed-Z convention, PSM's inverted light in the default one — and `Less` otherwise.
    /// A map whose own test differs from the buffer's is stored as 1 − z ([`DepthMap::reversed`]),
    /// because GL allows one comparison sampler per texture.
    pub fn shadow_buffer_test(&self) -> DepthTest {
        let projective = matches!(self.settings.depth, DepthMode::Projective { .. });
        if projective && !self.maps.is_empty() && self.maps.iter().all(|m| m.depth_test == DepthTest::Greater) {
            DepthTest::Greater
        } else {
            DepthTest::Less
        }
    }

    /// Map `m`'s side in texels: its own, or the settings' `shadow_resolution`.
    pub fn map_resolution(&self, m: &ShadowMapSpec) -> u32 {
        m.resolution_or(self.settings.shadow_resolution)
    }

    /// The side of the texture array the maps share: the largest map's (the settings'
    /// `shadow_resolution` for a frame without maps).
    pub fn array_resolution(&self) -> u32 {
        self.maps.iter().map(|m| self.map_resolution(m)).max().unwrap_or(self.settings.shadow_resolution)
    }

    /// The texels the maps hold together, `Σ side²`.
    pub fn map_texels(&self) -> f64 {
        self.maps.iter().map(|m| (self.map_resolution(m) as f64).powi(2)).sum()
    }

    /// Whether map `m` is stored as 1 − z: its depth test is not the buffer's.
    pub(crate) fn stores_flipped(&self, m: &ShadowMapSpec) -> bool {
        matches!(self.settings.depth, DepthMode::Projective { .. }) && m.depth_test != self.shadow_buffer_test()
    }

    pub fn validate(&self) -> Result<(), RenderError> {
        self.settings.validate()?;
        self.camera.validate()?;
        self.light.validate()?;
        validate_maps(self.maps, self.scene.objects.len())?;
        if !self.utilisation.is_empty() && self.utilisation.len() != self.maps.len() {
            return Err(RenderError::invalid("map utilisation", format!("{} values for {} maps", self.utilisation.len(), self.maps.len())));
        }
        if let Some(u) = self.utilisation.iter().find(|u| !(0.0..=1.0).contains(*u)) {
            return Err(RenderError::invalid("map utilisation", format!("{u} is not within [0, 1]")));
        }
        Ok(())
    }
}

/// A shadow map as read back: `resolution²` depths (its own side), rows top to bottom; NaN where no caster
/// was drawn. Depths are the rasterised values before bias (or the linear depth in linear mode).
#[derive(Clone, Debug)]
pub struct DepthMap {
    pub resolution: u32,
    pub depth: Vec<f32>,
    /// True for maps stored as 1 − z of their own matrix's depth: in projective mode, the maps
    /// whose depth test is not the buffer's ([`RenderRequest::shadow_buffer_test`]).
    pub reversed: bool,
    /// The map's matrix, depth test and split, as rendered (from its [`ShadowMapSpec`]).
    pub world_to_clip: glam::Mat4,
    pub depth_test: DepthTest,
    pub split: [f32; 2],
    /// The cube face, for a point light's face map: it answers only for its own cone.
    pub face: Option<CubeFaceSpec>,
    /// Whether `depth` holds linear light depths ([`DepthMode::Linear`]) instead of z.
    pub linear: bool,
}

/// The receiver pixels of one slice of the view, reduced on the GPU: their world positions'
/// bounds and their greatest view depth (f32, from the main pass's f32 positions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReceiverSlice {
    pub min: [f32; 3],
    pub max: [f32; 3],
    pub far: f32,
}

/// The receiver slices of a frame per facing axis: `[axis][slice]`.
pub type ReceiverSlices = [[Option<ReceiverSlice>; crate::types::RECEIVER_SLICES]; 3];

/// Everything a render produced, per pixel (rows top to bottom) and summarised.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    pub width: u32,
    pub height: u32,
    /// The lit image.
    pub color: Image,
    /// xyz = world position; w = 1 receiver, 2 other geometry, 0 background.
    pub world: Vec<[f32; 4]>,
    /// Camera-facing unit normal (xyz).
    pub normal: Vec<[f32; 4]>,
    /// Screen pixels per shadow texel; < 0 where no map covers the pixel, NaN on background.
    pub aliasing: Vec<f32>,
    /// Index of the map each pixel used; −1 none (or background).
    pub split: Vec<i32>,
    /// Final shadow term in [0, 1] (after the optional blur); 1 = lit.
    pub shadow: Vec<f32>,
    /// Ray-cast ground truth, when requested.
    pub truth: Option<Vec<Visibility>>,
    /// The shadow maps, when `save_shadow_maps` was set.
    pub shadow_maps: Vec<DepthMap>,
    /// The least and greatest view depth of the pixels that see geometry, reduced on the GPU
    /// (f32, from the main pass's f32 positions); `None` where the adapter has no compute
    /// shaders or no pixel sees geometry.
    pub visible_depth: Option<[f32; 2]>,
    /// The receiver pixels (`world`'s w = 1) reduced on the GPU into the slices of the view that
    /// [`crate::RenderSettings::receiver_slices`] asked for, apart for each world axis (x, y, z)
    /// their normal lies closest to (`[axis][slice]`), each slice's `None` where no receiver pixel
    /// falls in it; `None` where they were not asked for or the adapter has no compute shaders.
    pub receiver_slices: Option<ReceiverSlices>,
    /// The scene's surface offset (`Scene::surface_offset`): the main pass looked each pixel's
    /// point up lifted off its surface by this much.
    pub surface_offset: f64,
    /// The camera and light the frame was rendered with.
    pub camera: CameraSpec,
    pub light: LightSpec,
    pub metrics: RenderMetrics,
}
