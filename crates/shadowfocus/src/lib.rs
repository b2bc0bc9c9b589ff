//! Shadowfocus decides where a shadow map looks: each frame it fits the
//! light's projection to exactly the part of the world that can cast a
//! visible shadow, the focus body `H = hull(V ∪ l) ∩ S ∩ L` of the view `V`,
//! the light `l`, the scene box `S` and the light's frustum `L` \[PSM02\].
//!
//! - [`geom`] computes `H` exactly (certified floating point, an exact
//!   engine where floats cannot decide), with typed errors for bad input.
//! - [`focus`] fits shadow-map matrices to `H`: the focused uniform map,
//!   perspective shadow maps (PSM, inverted lights, the virtual shift),
//!   light-space perspective shadow maps (LiSPSM), trapezoidal maps (TSM),
//!   parallel splits, texel-snapped stable maps for every light (LiSPSM and TSM too), cube faces for point
//!   lights, in every graphics API's clip convention
//!   ([`focus::ClipConvention`]), and culls casters against each map.
//!
//! The guarantee: every vertex of a map's body lies inside the map's clip
//! volume, in f64 and with the f32 matrix evaluated in f32 — so no caster
//! that can shadow the view is cut off. Nothing allocates per frame once a
//! [`focus::FocusResult`] exists.
//!
//! This crate depends only on those two (and glam, robust, num-bigint): no
//! GPU, command line or JSON. The optional `serde` feature derives
//! `Serialize`/`Deserialize` for the input types, the settings and each
//! map's fitted projection.
//!
//! # One frame: [`focus::fit`]
//!
//! ```
//! use glam::DVec3;
//! use shadowfocus::focus::{fit, ClipConvention, FocusResult, FocusSettings, Method, SplitSettings};
//! use shadowfocus::geom::{Aabb, Camera, Light};
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
//!     splits: SplitSettings { count: 4, ..SplitSettings::default() },
//!     clip: ClipConvention::VULKAN.reversed(),
//!     ..FocusSettings::default()
//! };
//!
//! let mut frame = FocusResult::new(); // once
//! fit(&camera, &sun, &scene, &settings, &mut frame)?; // every frame
//! for map in frame.maps().iter().filter(|m| m.is_active()) {
//!     let _render_with: [f32; 16] = map.fit.clip_from_world_f32.to_cols_array();
//!     let _sample_with: [f32; 16] = map.fit.uv_from_world_f32().to_cols_array();
//!     // depth compare: map.fit.depth_test (greater here: reversed-Z)
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Several lights, one camera: [`focus::PreparedView`]
//!
//! ```
//! use glam::DVec3;
//! use shadowfocus::focus::{fit_prepared, FocusResult, FocusSettings, PreparedView};
//! use shadowfocus::geom::{Aabb, Camera, Light};
//!
//! let camera = Camera {
//!     eye: DVec3::new(0.0, 2.0, 10.0),
//!     forward: DVec3::NEG_Z,
//!     up: DVec3::Y,
//!     fovy: 1.0,
//!     aspect: 1.5,
//!     near: 0.5,
//!     far: 100.0,
//! };
//! let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0))?;
//! let lights = [Light::directional(DVec3::new(0.3, -1.0, 0.1))?, Light::point(DVec3::new(5.0, 8.0, -20.0))?];
//! let view = PreparedView::new(&camera, &FocusSettings::default())?; // per camera
//! let mut results = [FocusResult::new(), FocusResult::new()];
//! for (light, out) in lights.iter().zip(&mut results) {
//!     fit_prepared(&view, light, &scene, out)?; // per light
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # The casters each map needs: [`focus::cull_casters`]
//!
//! ```
//! use glam::DVec3;
//! use shadowfocus::focus::{cull_casters, fit, FocusResult, FocusSettings};
//! use shadowfocus::geom::{Aabb, Camera, Light};
//!
//! let camera = Camera { eye: DVec3::ZERO, forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.0, near: 0.5, far: 50.0 };
//! let sun = Light::directional(DVec3::new(0.2, -1.0, 0.0))?;
//! let scene = Aabb::new(DVec3::splat(-60.0), DVec3::splat(60.0))?;
//! let mut frame = FocusResult::new();
//! fit(&camera, &sun, &scene, &FocusSettings::default(), &mut frame)?;
//! let boxes = [
//!     Aabb::new(DVec3::new(-1.0, -1.0, -10.0), DVec3::new(1.0, 1.0, -8.0))?, // in view
//!     Aabb::new(DVec3::new(-1.0, -1.0, 20.0), DVec3::new(1.0, 1.0, 22.0))?,  // behind the eye, off the light's way
//! ];
//! let mut kept = [0u32; 2];
//! let n = cull_casters(&frame.maps()[0], &boxes, &mut kept)?;
//! assert_eq!(&kept[..n], &[0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # The focus body itself: [`geom::Focuser`]
//!
//! ```
//! use glam::DVec3;
//! use shadowfocus::geom::{Aabb, Body, Camera, Focuser, Frustum, Light};
//!
//! let camera = Camera { eye: DVec3::ZERO, forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.0, near: 1.0, far: 10.0 };
//! let view = Frustum::from_camera(&camera)?;
//! let scene = Aabb::new(DVec3::splat(-20.0), DVec3::splat(20.0))?;
//! let (mut focuser, mut body) = (Focuser::new(), Body::new()); // once
//! focuser.focus_into(&mut body, &view, &Light::directional(DVec3::NEG_Y)?, &scene)?; // every frame
//! assert!(!body.is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! An engine that has its view as eight corners (an off-centre or oblique
//! projection) fits with [`focus::fit_frustum`]; one with its own bodies
//! with [`focus::fit_map`]. `examples/engine_frame.rs` is a whole frame loop
//! to copy. Papers are cited by the keys of the repository's
//! `REFERENCES.md`.

#![deny(missing_docs)]

/// Exact focus bodies and the convex polytopes they are built from.
pub use shadowfocus_geom as geom;

/// Shadow-map matrices fitted to focus bodies, parallel splits and caster
/// culling.
pub use shadowfocus_focus as focus;
