//! What the renderer and the evaluation harness both draw with: a 5×7 bitmap font and PNG
//! encoding, so that neither needs font files or system libraries.

pub mod font;
pub mod png;
