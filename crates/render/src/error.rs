//! One error type for everything the renderer can refuse or fail at.

use std::path::PathBuf;

/// Why a render, a scene load or an output write did not happen.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A number that must be finite was NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite { what: String },
    /// An input that is well-formed but unusable (zero size, near ≥ far, too many maps, ...).
    #[error("invalid input: {what}: {reason}")]
    Invalid { what: String, reason: String },
    /// A built-in scene name that does not exist.
    #[error("unknown scene '{name}'; built-in scenes: {known}")]
    UnknownScene { name: String, known: String },
    /// No usable graphics adapter could be opened.
    #[error("no usable graphics adapter ({tried}). {hint}")]
    NoAdapter { tried: String, hint: String },
    /// The adapter lacks something this renderer needs.
    #[error("adapter '{adapter}' cannot run this renderer: {reason}")]
    Unsupported { adapter: String, reason: String },
    /// wgpu reported a validation, out-of-memory or device error.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// A glTF file could not be read or is not usable.
    #[error("glTF '{path}': {reason}")]
    Gltf { path: PathBuf, reason: String },
    /// Reading or writing a file failed.
    #[error("I/O on '{path}': {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// PNG encoding failed.
    #[error("PNG '{path}': {reason}")]
    Png { path: PathBuf, reason: String },
    /// The ground-truth mesh could not be built.
    #[error("ground truth: {0}")]
    GroundTruth(String),
}

impl RenderError {
    pub(crate) fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        RenderError::Invalid { what: what.into(), reason: reason.into() }
    }
}

/// Fails with [`RenderError::NonFinite`] unless every value is finite.
pub(crate) fn check_finite(what: &str, values: &[f64]) -> Result<(), RenderError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(RenderError::NonFinite { what: what.to_string() })
    }
}
