//! Failures as C sees them: a status code and a message.

use crate::types::SfStatus;
use shadowfocus_focus::FocusError;
use shadowfocus_geom::GeomError;

/// A failed call: the code it returns and the message `sf_last_error` gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The status returned to C.
    pub status: SfStatus,
    /// What went wrong, without a trailing NUL.
    pub message: String,
}

impl Failure {
    /// A failure with `status` and `message`.
    pub fn new(status: SfStatus, message: impl Into<String>) -> Failure {
        Failure { status, message: message.into() }
    }

    /// A NULL pointer passed for the argument `what`.
    pub fn null(what: &str) -> Failure {
        Failure::new(SfStatus::SF_ERR_NULL_POINTER, format!("{what} is NULL"))
    }

    /// An input out of range.
    pub fn invalid(message: impl Into<String>) -> Failure {
        Failure::new(SfStatus::SF_ERR_INVALID_INPUT, message)
    }

    /// An output buffer of `capacity` entries where `needed` are needed.
    pub fn too_small(what: &str, capacity: usize, needed: usize) -> Failure {
        Failure::new(SfStatus::SF_ERR_BUFFER_TOO_SMALL, format!("{what} holds {capacity} entries, {needed} needed"))
    }

    /// A geometry error, its message prefixed with `context` when not empty.
    pub fn geom(e: &GeomError, context: &str) -> Failure {
        Failure::new(geom_status(e), with_context(context, e))
    }

    /// A fitting error.
    pub fn focus(e: &FocusError) -> Failure {
        Failure::new(focus_status(e), e.to_string())
    }
}

impl From<FocusError> for Failure {
    fn from(e: FocusError) -> Failure {
        Failure::focus(&e)
    }
}

fn with_context(context: &str, e: &impl std::fmt::Display) -> String {
    if context.is_empty() {
        e.to_string()
    } else {
        format!("{context}: {e}")
    }
}

/// The status of a geometry error. Capacity and unsupported-operation
/// errors cannot come from the inputs this API builds: they are bugs.
pub fn geom_status(e: &GeomError) -> SfStatus {
    match e {
        GeomError::NonFinite { .. }
        | GeomError::DegenerateFrustum { .. }
        | GeomError::InvertedBox { .. }
        | GeomError::ZeroDirection { .. }
        | GeomError::InvalidCamera { .. } => SfStatus::SF_ERR_INVALID_INPUT,
        GeomError::CapacityExceeded { .. } | GeomError::Unsupported { .. } => SfStatus::SF_ERR_INTERNAL,
    }
}

/// The status of a fitting error.
pub fn focus_status(e: &FocusError) -> SfStatus {
    match e {
        FocusError::Geom(g) => geom_status(g),
        FocusError::InvalidSettings { .. } | FocusError::InvalidCorners { .. } => SfStatus::SF_ERR_INVALID_INPUT,
        FocusError::NoSingleProjection { .. } => SfStatus::SF_ERR_NO_SINGLE_PROJECTION,
        FocusError::Capacity { .. } => SfStatus::SF_ERR_BUFFER_TOO_SMALL,
    }
}
