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
//! ```
//! use shadowfocus_geom::{focus_body, Aabb, Camera, Dimension, Frustum, Light};
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
//! # Ok::<(), shadowfocus_geom::GeomError>(())
//! ```

mod body;
mod camera;
mod certified;
mod error;
mod fixed;
mod frustum;
mod limits;
mod number;
mod plane;
mod polytope;
mod wide;

pub use body::{
    focus_body, focus_body_exact_into, focus_body_into, focus_body_into_without_skip, unit_direction, Aabb, Body, Dimension, FocusStats,
    Light,
};
pub use camera::{Camera, CameraBasis};
pub use error::GeomError;
pub use frustum::{Apex, Frustum, PlaneSet};
pub use limits::{MAX_FACES, MAX_FACE_INDICES, MAX_PLANES, MAX_VERTICES};
pub use plane::Plane;
pub use polytope::{Polytope, ROUNDING_ULPS};

pub use glam::{DVec3, DVec4};
