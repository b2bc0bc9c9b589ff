//! Exact geometric predicates: every sign is the sign of the exact value for
//! the `f64` inputs, found by the cheapest stage that can prove it.

pub(crate) mod orient;
pub(crate) mod side;
