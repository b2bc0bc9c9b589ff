//! Command-line front end: JSON-lines I/O and the render commands around
//! the library crates.

pub mod bench;
pub mod body;
pub mod case;
pub mod fit;
pub mod render;
