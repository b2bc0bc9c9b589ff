//! The floating-point floor every error bound stands on, defined once.

/// Unit roundoff of round-to-nearest `f64` arithmetic: a rounded operation
/// is within a factor `1 ± u` of the exact one.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON * 0.5;

/// Unit roundoff of round-to-nearest `f32` arithmetic.
pub const UNIT_ROUNDOFF_F32: f64 = 1.0 / (1u64 << 24) as f64;

/// NOTE: an error bound is itself computed in floating point and may come
/// out slightly low: every operation on it is a sum or product of
/// non-negative terms, so it is low by a factor of at most `(1 − u)^depth`.
/// Bounds here have depth < 64; this slack covers depths up to ~2^12.
pub(crate) const BOUND_SLACK: f64 = 1.0 + 1.0 / (1u64 << 40) as f64;

/// Values this small are never certified by a relative bound: it keeps
/// subnormal underflow (where relative error bounds fail) out of the way.
pub(crate) const UNDERFLOW_FLOOR: f64 = 1e-280;
