//! The `shadowfocus` command line and what its tests share: the subcommands
//! ([`cli`]) over the library ([`focus`], [`geom`], re-exported from the
//! `shadowfocus` crate) and the validation renderer ([`render`]).

pub use shadowfocus::{focus, geom};
pub use shadowfocus_render as render;

pub mod cli;

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
