//! Unit tests of the C ABI (the crate builds no rlib, so they live here).

mod alloc;
mod common;
mod errors;
mod header;
mod round_trip;
