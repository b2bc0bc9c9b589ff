//! Shadowfocus: exact, fast focusing of shadow maps.
//!
//! - [`geom`]: exact focus bodies `H = hull(V ∪ l) ∩ S ∩ L` and convex polytopes;
//! - [`focus`]: shadow-map matrices (uniform, PSM, LiSPSM, TSM, parallel splits);
//! - [`render`]: a thin headless wgpu renderer for validation scenes.

pub use shadowfocus_focus as focus;
pub use shadowfocus_geom as geom;
pub use shadowfocus_render as render;

pub mod cli;

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
