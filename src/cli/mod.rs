//! Command-line front end: JSON-lines I/O around the library crates.

pub mod body;
pub mod case;
