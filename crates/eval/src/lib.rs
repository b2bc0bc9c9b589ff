//! Evaluation harness for shadowfocus: the tables behind its performance
//! and accuracy claims.
//!
//! - [`table`], [`plot`], [`svg`], [`raster`]: rows of the run-time-against-error
//!   sweep, their CSV and markdown views, Pareto fronts and log–log plots
//!   (SVG and PNG).
//! - [`lines`]: line plots in panels (PNG), one curve per series: the light
//!   sweep's aliasing and mismatch against azimuth.
//! - [`stress`], [`naive`]: numerical stress families checked exactly,
//!   against a naive floating-point pipeline, and against [`oracle`], an
//!   independent big-integer reference for the body.
//! - [`fixtures`]: the body against the committed CGAL-exact fixtures, and
//!   the naive pipeline against the same oracle.
//!
//! The sweep itself (scenes, renderer) is driven by `shadowfocus bench`.

pub mod fixtures;
pub mod lines;
pub mod naive;
pub mod oracle;
pub mod plot;
pub mod raster;
pub mod stress;
pub mod svg;
pub mod table;
