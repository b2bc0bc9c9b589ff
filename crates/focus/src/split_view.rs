//! The camera of one split, as every method and the aliasing prediction
//! read it.

use crate::settings::FocusSettings;
use shadowfocus_geom::{Camera, CameraBasis};

/// The camera of one split and what every method reads from it.
pub(crate) struct SplitView<'a> {
    pub camera: &'a Camera,
    pub basis: CameraBasis,
    pub settings: &'a FocusSettings,
}
