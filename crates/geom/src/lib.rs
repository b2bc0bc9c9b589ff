//! Exact focus bodies for shadow mapping.
//!
//! The focus body of Perspective Shadow Maps is
//! `H = hull(V ∪ {l}) ∩ S ∩ L`: the part of the scene box `S` (and of a spot
//! light's frustum `L`) that can cast a shadow into the view frustum `V`
//! when lit from `l` — a point, or a point at infinity for directional
//! lights. This crate computes `H` for the exact values of its `f64`
//! inputs: every side-of-plane, coplanarity, emptiness and flatness decision
//! is the exact one. A case first runs a floating-point clipper in which
//! every sign and every vertex carries a proven error bound; whatever that
//! cannot prove (coincidences it does not explain, near-degenerate input)
//! goes to an exact engine of filtered predicates with a big-integer
//! fallback and unrounded vertices. Output vertices are within
//! [`ROUNDING_ULPS`] of the exact ones.
//!
//! Layout: `input/` (what a body is computed from, validated), `arith/`
//! (the rounding floor, filtered and exact numbers, fixed-width integer
//! stages, plane formulas), `predicates/` (the exact sign cascades),
//! `engine/` (the plan, the certified float engine by phase, the exact
//! engine, and the [`Focuser`] that runs them) and `body.rs` (the plain
//! output). Each imports only parts before it in the order arith,
//! predicates, input, body, engine: no import circles.
//!
//! ```
//! use shadowfocus_geom::{focus_body, Aabb, Body, Camera, Dimension, Focuser, Frustum, Light};
//! use glam::DVec3;
//!
//! let view = Frustum::from_camera(&Camera {
//!     eye: DVec3::new(0.0, 2.0, 10.0),
//!     forward: DVec3::new(0.0, 0.0, -1.0),
//!     up: DVec3::Y,
//!     fovy: 60f64.to_radians(),
//!     aspect: 1.5,
//!     near: 0.5,
//!     far: 50.0,
//! })?;
//! let scene = Aabb::new(DVec3::new(-20.0, 0.0, -40.0), DVec3::new(20.0, 8.0, 5.0))?;
//! let sun = Light::directional(DVec3::new(0.3, -1.0, 0.2))?;
//! let body = focus_body(&view, &sun, &scene)?;
//! assert_eq!(body.dimension(), Dimension::Solid);
//! assert!(body.volume() > 0.0);
//!
//! // Per frame: one work space and one output, reused without allocating.
//! let (mut focuser, mut frame_body) = (Focuser::new(), Body::new());
//! focuser.focus_into(&mut frame_body, &view, &sun, &scene)?;
//! assert_eq!(frame_body.vertices(), body.vertices());
//! # Ok::<(), shadowfocus_geom::GeomError>(())
//! ```

#![deny(missing_docs)]

mod arith;
mod body;
mod engine;
mod error;
mod input;
mod limits;
mod predicates;

pub use arith::floor::{UNIT_ROUNDOFF, UNIT_ROUNDOFF_F32};
pub use arith::plane::Plane;
pub use body::{Body, Dimension, FocusStats};
pub use engine::exact::{Polytope, ROUNDING_ULPS};
pub use engine::{focus_body, Focuser};
pub use error::GeomError;
pub use input::aabb::Aabb;
pub use input::camera::{Camera, CameraBasis};
pub use input::frustum::{Apex, Frustum, PlaneSet};
pub use input::light::{unit_direction, Light};
pub use limits::{MAX_FACES, MAX_FACE_INDICES, MAX_PLANES, MAX_VERTICES};

pub use glam::{DVec3, DVec4};
