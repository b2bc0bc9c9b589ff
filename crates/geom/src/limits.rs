//! The fixed capacities of every body and polytope: no allocation per frame.

/// Most planes a polytope can be bounded by.
pub const MAX_PLANES: usize = 64;
/// Most vertices a polytope can have.
pub const MAX_VERTICES: usize = 128;
/// Most faces a polytope can have.
pub const MAX_FACES: usize = MAX_PLANES;
/// Most face–vertex incidences (sum of face sizes).
pub const MAX_FACE_INDICES: usize = 3 * MAX_VERTICES + 64;
