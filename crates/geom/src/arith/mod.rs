//! Arithmetic behind the predicates: the rounding floor, filtered and exact
//! number types, fixed-width integer stages, and plane formulas generic over
//! them.

pub(crate) mod fixed;
pub(crate) mod floor;
pub(crate) mod number;
pub(crate) mod plane;
pub(crate) mod wide;
