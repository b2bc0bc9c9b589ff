//! What one frame's measurements report (the computation is in `metrics`).

use serde::Serialize;

use crate::gpu::AdapterSummary;
use crate::types::{DepthTest, RenderSettings};

/// Screen pixels per shadow texel over the visible receiver pixels that a map covers and that
/// face the light (elsewhere the shadow term is not visible).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct AliasingStats {
    pub max: f64,
    pub p95: f64,
    pub mean: f64,
    pub pixels: u64,
    /// The least maximum aliasing any parameterisation of the frame's texels (every map's)
    /// reaches over the camera's `[near, far]` at this image size ([`crate::bound`]).
    pub bound: f64,
    /// `max / bound`: how far the frame is from the ideal parameterisation.
    pub ratio: f64,
    /// The maximum with the angle terms taken out: each pixel's aliasing times
    /// `√(cos θ / cos φ)`, θ and φ the light's and the eye's angles of incidence on the
    /// receiver (the map's and the camera's projection rays), which the bound sets to 1.
    pub angle_free_max: f64,
    /// `angle_free_max / bound`: what is left of `ratio` without the angle terms (the split
    /// count, where the receivers are); `ratio / angle_free_ratio` is what the angles cost.
    pub angle_free_ratio: f64,
}

/// Rendered lit/shadowed against the ray-cast ground truth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct MismatchStats {
    /// Mismatched pixels / visible geometry pixels.
    pub rate: f64,
    /// The same, over pixels whose (2r+1)² neighbourhood has one ground-truth value.
    pub rate_off_edges: f64,
    pub pixels: u64,
    pub mismatched: u64,
    pub off_edge_pixels: u64,
    pub off_edge_mismatched: u64,
    /// Rendered shadowed but truly lit.
    pub false_shadow: u64,
    /// Rendered lit but truly shadowed.
    pub false_light: u64,
    /// The mismatch rate over the pixels the map can resolve: off edges, with aliasing at most
    /// [`ADEQUATE_ALIASING`] screen pixels per texel, and with the ground truth at every texel
    /// centre the shadow lookup reads (on the receiver's plane) equal to the pixel's own. A map can
    /// only get shadows wrong there through a wrong bias, a lost caster or a broken depth order,
    /// not through undersampling or filtering.
    pub rate_adequate: f64,
    pub adequate_pixels: u64,
    pub adequate_mismatched: u64,
}

/// Largest aliasing (screen pixels per shadow-map texel) at which a pixel counts as adequately
/// sampled in [`MismatchStats::rate_adequate`].
pub const ADEQUATE_ALIASING: f32 = 2.0;

/// Whether every visible pixel (inside a spot light's pyramid) got a shadow map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct CoverageStats {
    pub required: u64,
    pub covered: u64,
    pub uncovered: u64,
    pub complete: bool,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CasterStats {
    /// Objects drawn into each map.
    pub per_map: Vec<u32>,
    /// Draw calls per map after merging adjacent index ranges.
    pub draw_calls: Vec<u32>,
    /// Objects drawn into at least one map.
    pub drawn: u32,
    /// Objects in the scene.
    pub total: u32,
}

#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Timings {
    pub shadow_ms: f64,
    pub main_ms: f64,
    pub shadow_gpu_ms: Option<f64>,
    pub main_gpu_ms: Option<f64>,
    pub readback_ms: f64,
    pub ground_truth_ms: f64,
}

/// Everything `metrics.json` reports about one frame.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RenderMetrics {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub shadow_resolution: u32,
    pub maps: usize,
    pub adapter: AdapterSummary,
    /// Whether casters in front of a map were clamped rather than clipped.
    pub depth_clamp: bool,
    /// The shadow depth buffer's comparison: `greater` for a reversed buffer (cleared to 0).
    pub shadow_buffer_test: DepthTest,
    /// Shadow + main passes, GPU work until idle (fastest of `timing_repeats`).
    pub render_ms: f64,
    pub shadow_pass_ms: f64,
    pub main_pass_ms: f64,
    /// The same phases timed by the GPU itself (timestamp queries, fastest
    /// of `timing_repeats`), where the adapter has them: no submission or
    /// fence wait in them.
    pub shadow_gpu_ms: Option<f64>,
    pub main_gpu_ms: Option<f64>,
    pub readback_ms: f64,
    pub ground_truth_ms: f64,
    pub aliasing: AliasingStats,
    pub mismatch: Option<MismatchStats>,
    pub coverage: CoverageStats,
    pub casters: CasterStats,
    /// Visible pixels served by each map.
    pub split_pixels: Vec<u64>,
    /// Per map, the largest aliasing among the pixels `aliasing` counts that
    /// it serves (null for a map that serves none).
    pub map_aliasing_max: Vec<f64>,
    /// Per map, the fraction of its area its focus body's projection covers, as given in the
    /// request (empty when not given), and their least and mean values (null when not given).
    pub map_utilisation: Vec<f64>,
    pub utilisation_min: Option<f64>,
    pub utilisation_mean: Option<f64>,
    pub settings: RenderSettings,
}
