//! Headless wgpu shadow renderer for validating shadow-map focusing.
//!
//! A frame is a [`Scene`] (triangles grouped into objects), a [`CameraSpec`], a [`LightSpec`] and
//! a list of [`ShadowMapSpec`]s (matrix, depth test, split range, casters) produced elsewhere.
//! The renderer draws the maps into a `Depth32Float` array, shades the scene with per-pixel
//! split selection and PCF, and reads back per-pixel world position, aliasing and the chosen
//! split. [`RenderMetrics`] compare every pixel with a CPU ray cast toward the light, and the
//! measured aliasing with the least maximum any parameterisation of the same texels reaches
//! ([`bound`]).
//!
//! ```no_run
//! use shadowfocus_render::*;
//! let scene = builtin_scene("inverted")?;
//! let map = testfit::scene_box_map(&scene, &scene.camera, &scene.light, 16.0 / 9.0)?; // or from the focusing crate
//! let maps = [map];
//! let out = render_scene(&RenderRequest::new(&scene, &maps))?;
//! write_outputs(std::path::Path::new("out/inverted"), &out, None)?;
//! # Ok::<(), RenderError>(())
//! ```

pub mod bound;
mod error;
mod frame;
mod gltf_scene;
mod gpu;
mod ground_truth;
mod image;
mod lookup;
mod metrics;
mod output;
mod passes;
mod renderer;
mod resolved;
mod scene;
mod scenes;
mod stats;
pub mod testfit;
mod timer;
mod types;
mod uniforms;

pub use error::RenderError;
pub use frame::{DepthMap, ReceiverSlice, ReceiverSlices, RenderOutput, RenderRequest};
pub use gltf_scene::{default_camera, default_light, load_gltf, load_scene, GltfReport};
pub use gpu::{AdapterSummary, BackendChoice, BACKEND_ENV};
pub use ground_truth::{GroundTruth, Visibility};
pub use image::{aliasing_color, aliasing_heatmap, contact_sheet, depth_image, mismatch_image, Image, PixelMatch, HEAT_UNLIT_VALUE};
pub use metrics::pixel_matches;
pub use output::{aliasing_image, caption, metrics_json, mismatch_view, shadow_map_images, write_outputs};
pub use renderer::{render_scene, Renderer};
pub use scene::{Scene, SceneObject, Vertex};
pub use scenes::{builtin_scene, BUILTIN_SCENES};
pub use stats::{AliasingStats, CasterStats, CoverageStats, MismatchStats, RenderMetrics, ADEQUATE_ALIASING};
pub use types::{
    Bounds, CameraSpec, CubeFaceSpec, DepthMode, DepthTest, EyeBlur, LightSpec, Pcf, RenderSettings, ShadowMapSpec, MAX_MAPS,
    RECEIVER_SLICES,
};
