//! Typed errors for invalid input. Every public entry point returns one of
//! these instead of panicking or producing a silently wrong body.

use std::fmt;

/// Why an input was rejected.
#[derive(Clone, Debug, PartialEq)]
pub enum GeomError {
    /// A coordinate or parameter is NaN or infinite.
    NonFinite {
        /// The input holding the value.
        what: &'static str,
    },
    /// The eight corners of a frustum do not bound a convex solid with the
    /// frustum's face structure (coincident corners, flat, twisted, non-convex).
    DegenerateFrustum {
        /// The frustum (view, spot light).
        what: &'static str,
        /// Which property of its corners fails.
        reason: &'static str,
    },
    /// A box whose `min` exceeds its `max` on some axis.
    InvertedBox {
        /// 0, 1 or 2 for x, y, z.
        axis: usize,
    },
    /// A direction (directional light, camera forward/up) of zero length.
    ZeroDirection {
        /// The direction's input.
        what: &'static str,
    },
    /// A camera description that cannot produce a frustum.
    InvalidCamera {
        /// Which camera parameter is out of range.
        reason: &'static str,
    },
    /// The body would need more vertices, faces or planes than the fixed
    /// capacity. Cannot happen for frustum/box/light inputs; guards the
    /// general polytope API.
    CapacityExceeded {
        /// The capacity exceeded (vertices, faces, planes).
        what: &'static str,
    },
    /// A polytope operation that is not defined for the polytope's
    /// current representation.
    Unsupported {
        /// What is not defined.
        reason: &'static str,
    },
}

impl fmt::Display for GeomError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GeomError::NonFinite { what } => write!(f, "{what} is not finite (NaN or infinity)"),
            GeomError::DegenerateFrustum { what, reason } => {
                write!(f, "{what} is not a valid frustum: {reason}")
            }
            GeomError::InvertedBox { axis } => {
                write!(f, "scene box has min > max on axis {}", ["x", "y", "z"][*axis])
            }
            GeomError::ZeroDirection { what } => write!(f, "{what} has zero length"),
            GeomError::InvalidCamera { reason } => write!(f, "invalid camera: {reason}"),
            GeomError::CapacityExceeded { what } => write!(f, "capacity exceeded: {what}"),
            GeomError::Unsupported { reason } => write!(f, "unsupported operation: {reason}"),
        }
    }
}

impl std::error::Error for GeomError {}

/// Rejects NaN and infinities in a point or vector.
pub(crate) fn check_finite(v: glam::DVec3, what: &'static str) -> Result<(), GeomError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(GeomError::NonFinite { what })
    }
}
