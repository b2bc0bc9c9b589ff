//! Typed errors: every invalid input is reported, never a panic or NaN.

use shadowfocus_geom::GeomError;
use std::fmt;

/// Why a fit was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum FocusError {
    /// The geometry core rejected an input (camera, light, scene box, frustum).
    Geom(GeomError),
    /// A setting is out of its documented range.
    InvalidSettings {
        /// The setting's field path, e.g. `splits.count`.
        what: &'static str,
        /// Its documented range.
        reason: &'static str,
    },
    /// Eight corners that do not describe a symmetric perspective frustum.
    InvalidCorners {
        /// Which property of the corners fails.
        reason: &'static str,
    },
    /// No single projection from the light sees the whole body (a spot
    /// light whose position is not the apex of its frustum).
    NoSingleProjection {
        /// Why no projection exists.
        reason: &'static str,
    },
    /// The output buffer is smaller than the fit needs.
    Capacity {
        /// The buffer that is too small.
        what: &'static str,
    },
}

impl fmt::Display for FocusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FocusError::Geom(e) => write!(f, "{e}"),
            FocusError::InvalidSettings { what, reason } => write!(f, "invalid setting {what}: {reason}"),
            FocusError::InvalidCorners { reason } => write!(f, "corners do not form a perspective frustum: {reason}"),
            FocusError::NoSingleProjection { reason } => write!(f, "no single shadow map can see the focus body: {reason}"),
            FocusError::Capacity { what } => write!(f, "capacity exceeded: {what}"),
        }
    }
}

impl std::error::Error for FocusError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            FocusError::Geom(e) => Some(e),
            _ => None,
        }
    }
}

impl From<GeomError> for FocusError {
    fn from(e: GeomError) -> Self {
        FocusError::Geom(e)
    }
}
