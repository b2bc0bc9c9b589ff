//! Shadow-map focusing: from a camera, a light and the scene's bounding box
//! to the matrices an engine renders its shadow maps with.
//!
//! Every map is fitted to the exact focus body of
//! [`shadowfocus_geom`], `H = hull(V ∪ {l}) ∩ S ∩ L` — the part of the
//! scene that can cast a shadow into the view — with one of four
//! parameterisations ([`Method`]): the focused uniform map, perspective
//! shadow maps (PSM, including inverted lights and the virtual camera
//! shift), light-space perspective shadow maps (LiSPSM) and trapezoidal
//! shadow maps (TSM), optionally per parallel split of the view depth range
//! (PSSM) and texel-snapped with quantised extents (`stable`; LiSPSM and
//! TSM with their warps on world-fixed lattices).
//!
//! # Conventions
//!
//! [`MapFit::clip_from_world`] (a [`ShadowMap`]'s `fit`) maps world points
//! to clip space in the convention of [`FocusSettings::clip`]
//! ([`ClipConvention`]: presets for wgpu, Direct3D, Metal, Vulkan and
//! OpenGL, each also with reversed-Z): after dividing by `w`, `x, y ∈ [−1, 1]`
//! and depth `z ∈ [0, 1]` (or `[−1, 1]`). Render the map with the
//! comparison [`MapFit::depth_test`] — less, or greater with reversed-Z; an
//! inverted PSM light takes the other one ([`MapFit::inverted`]) — and
//! sample it with the same comparison through [`MapFit::uv_from_world`]
//! (texture coordinates in the API's layout, depth as the depth buffer
//! stores it). Every vertex of the map's body lies inside the clip volume
//! `w > 0, −w ≤ x, y ≤ w` and `0 ≤ z ≤ w` (resp. `−w ≤ z ≤ w`), in f64 and
//! also with [`MapFit::clip_from_world_f32`] evaluated in f32. Engines that
//! keep view and projection apart use [`ShadowMap::light_view`] and
//! [`ShadowMap::light_projection`]; those that cull in their own BVH use
//! [`caster_planes`]. With [`FocusSettings::depth_clamp`] the depth range
//! holds only each map's receivers, and the map is rendered with depth
//! clamping ([`MapFit::depth_clamp`]). Split ranges are view depths along the
//! camera's forward axis; [`FocusResult::split_clip_depths`] gives the same
//! planes as depths of the right-handed camera projection in the same
//! convention (by default glam's `dcamera::rh::proj::directx::perspective`:
//! `z_clip/w_clip = f/(f − n)·(1 − n/z)` at view depth `z`).
//!
//! # Cost
//!
//! [`fit`] allocates nothing: [`FocusResult`] holds a fixed number of maps
//! ([`MAX_MAPS`]) and is refilled every frame. Invalid input gives a
//! [`FocusError`]; an empty body gives a map in state [`MapState::Empty`]
//! with a zero matrix, never NaN.
//!
//! About a fifth of a one-map fit is the camera's: building and exactly
//! validating the split frusta. With several shadowed lights per camera (or
//! a camera that did not move), do it once with [`PreparedView::prepare`]
//! and fit each light with [`fit_prepared`]: the same maps, bit for bit.
//!
//! # One frame
//!
//! ```
//! use shadowfocus_focus::{cull_casters, fit, FocusResult, FocusSettings, Method, SplitScheme, SplitSettings};
//! use shadowfocus_geom::{Aabb, Camera, Light};
//! use glam::DVec3;
//!
//! let camera = Camera {
//!     eye: DVec3::new(0.0, 2.0, 10.0),
//!     forward: DVec3::new(0.0, -0.1, -1.0),
//!     up: DVec3::Y,
//!     fovy: 60f64.to_radians(),
//!     aspect: 16.0 / 9.0,
//!     near: 0.5,
//!     far: 200.0,
//! };
//! let sun = Light::directional(DVec3::new(0.4, -1.0, 0.3))?;
//! let scene = Aabb::new(DVec3::new(-100.0, 0.0, -200.0), DVec3::new(100.0, 30.0, 20.0))?;
//! let settings = FocusSettings {
//!     method: Method::Lispsm,
//!     splits: SplitSettings { count: 4, scheme: SplitScheme::Practical { lambda: 0.5 }, delta_bias: 0.0 },
//!     resolution: 2048,
//!     ..FocusSettings::default()
//! };
//!
//! let mut frame = FocusResult::new(); // once
//! fit(&camera, &sun, &scene, &settings, &mut frame)?; // every frame
//!
//! let casters = [Aabb::new(DVec3::new(-1.0, 0.0, -5.0), DVec3::new(1.0, 3.0, -3.0))?];
//! let mut visible = [0u32; 1];
//! for map in frame.maps().iter().filter(|m| m.is_active()) {
//!     let _upload: [f32; 16] = map.fit.clip_from_world_f32.to_cols_array();
//!     let n = cull_casters(map, &casters, &mut visible)?;
//!     // render casters visible[..n] into the map with map.fit.depth_test …
//!     # let _ = n;
//! }
//! assert_eq!(frame.split_depths().len(), 5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![deny(missing_docs)]

mod budget;
mod camera;
pub mod clip;
mod cone;
mod cull;
mod error;
mod fit;
mod frame;
mod ground;
mod hull2;
mod light_frame;
mod methods;
mod placement;
mod predict;
mod project;
mod receiver_boxes;
mod receiver_rays;
mod receivers;
mod result;
#[cfg(feature = "serde")]
mod serde_float;
mod settings;
mod split_view;
mod splits;
mod state;
mod view;
mod view_aliasing;
mod visible_depth;
mod visible_receivers;

pub use camera::{camera_from_corners, RecoveredCamera};
pub use clip::{ClipConvention, DepthRange, UvOrigin};
pub use cull::{caster_planes, cull_casters, CasterRegion, MAX_REGION_PLANES};
pub use error::FocusError;
pub use fit::{fit, fit_frustum, fit_map, fit_prepared, fit_prepared_with_state};
pub use frame::S0 as ORIENTATION_BLEND_SIN;
pub use receiver_boxes::{ReceiverBoxes, MAX_RECEIVER_BOXES};
pub use result::{CubeFace, DepthTest, FocusResult, MapFit, MapState, Notes, ShadowMap, Skipped};
pub use settings::{
    BoxFace, DepthHintCoverage, FocusSettings, Footprint, Ground, LightNear, LispsmSettings, MapOrientation, MapSizes, Method, PointMode,
    PsmSettings, SplitScheme, SplitSettings, TexelBudget, TsmSettings, WarpDirection,
};
pub use splits::{clip_depth, split_depths};
pub use state::{FitState, WarpHold};
pub use view::PreparedView;
pub use view_aliasing::{predict_aliasing, ViewAliasing};
pub use visible_depth::visible_depth_after_motion;
pub use visible_receivers::VisibleReceivers;

/// Most parallel splits.
pub const MAX_SPLITS: usize = 8;
/// Most maps of one frame: every split of an omnidirectional light.
pub const MAX_MAPS: usize = 6 * MAX_SPLITS;
