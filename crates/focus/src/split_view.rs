//! The camera of one split, as every method and the aliasing prediction
//! read it.

use crate::ground::GroundRect;
use crate::settings::FocusSettings;
use shadowfocus_geom::{Camera, CameraBasis};

/// The camera of one split and what every method reads from it.
pub(crate) struct SplitView<'a> {
    pub camera: &'a Camera,
    pub basis: CameraBasis,
    pub settings: &'a FocusSettings,
    /// The ground the prediction takes its receivers on
    /// ([`FocusSettings::ground`], resolved on the scene box), where the
    /// settings name one and give no receiver boxes.
    pub ground: Option<GroundRect>,
}
