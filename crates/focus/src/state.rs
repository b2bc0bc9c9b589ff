//! What a stable fit carries from one frame to the next.

use crate::MAX_MAPS;

/// The state a stable fit keeps between frames, held by the caller: plain
/// data, no allocation, one per light (and per view of it).
///
/// A stable spot map (a spot light's, or a point light's cube face) takes
/// its extent from a ladder of quarter octaves, the tightest step that
/// holds its body. A body whose size hovers at a step's boundary would
/// switch steps, and so the whole texel grid, from frame to frame. With a
/// state, [`crate::fit_prepared_with_state`] keeps a map's step from the
/// previous frame while the body still fits it and it is at most one step
/// looser than the tightest (hysteresis).
///
/// The held steps are hints that the fit checks: a state from another
/// light, another view, or no earlier frame at all never makes a map lose
/// its body — at worst the first frame's maps are one step looser. Without
/// a state every fit stays a pure function of its inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FitState {
    /// Per map slot (in the order of [`crate::FocusResult::maps`]), the
    /// extent step of its last stable spot map; −1 for none.
    pub(crate) steps: [i16; MAX_MAPS],
}

impl Default for FitState {
    fn default() -> Self {
        FitState { steps: [-1; MAX_MAPS] }
    }
}

impl FitState {
    /// A state with nothing held: the next fit is the stateless one.
    pub fn new() -> FitState {
        FitState::default()
    }

    /// The held steps as plain integers, to carry a state across a foreign
    /// boundary (the C ABI's `SfFitState`).
    pub fn to_steps(&self) -> [i16; MAX_MAPS] {
        self.steps
    }

    /// A state from [`FitState::to_steps`]'s integers. Any values are
    /// safe: the fit checks every held step and ignores one that would not
    /// hold the body or that is negative.
    pub fn from_steps(steps: [i16; MAX_MAPS]) -> FitState {
        FitState { steps }
    }
}
