//! What a focus body is computed from: the view frustum `V` (from a camera
//! or eight corners), the light and the scene box `S`, each validated when
//! built.

pub(crate) mod aabb;
pub(crate) mod camera;
pub(crate) mod frustum;
pub(crate) mod light;
