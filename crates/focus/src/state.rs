//! What a stable fit carries from one frame to the next.

use crate::MAX_MAPS;

/// The state a stable fit keeps between frames, held by the caller: plain
/// data, no allocation, one per light (and per view of it).
///
/// A stable map changes its texel grid only in steps: a stable spot map
/// (a spot light's, or a point light's cube face) takes its extent from a
/// ladder of quarter octaves, and a stable LiSPSM or TSM map takes its warp
/// direction, strength, centre and extents from lattices (see
/// [`WarpHold`]). Near a step's boundary a stateless fit would switch steps,
/// and so the whole texel grid, from frame to frame. With a state,
/// [`crate::fit_prepared_with_state`] keeps each map's steps from the
/// previous frame while they still hold its body and stay near the
/// tightest ones (hysteresis).
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
    /// Per map slot, the lattice steps of its last stable warped map.
    pub(crate) warps: [WarpHold; MAX_MAPS],
}

/// A stable LiSPSM or TSM map's parameters as lattice steps, to hold from
/// one frame to the next: plain integers, so that a state crosses a
/// foreign boundary (the C ABI's `SfWarpHold`) unchanged. Any values are
/// safe: the fit checks each held step against this frame's body and the
/// tightest steps, and chooses afresh where one does not hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct WarpHold {
    /// The warp direction in the light's world-fixed image frame, in
    /// sixteenths of a turn (0…15); any other value: nothing held.
    pub direction: i16,
    /// The warp's distance `n` before the body, `n = 2^(strength/4)`
    /// world units.
    pub strength: i16,
    /// The map's half extents across and along the warp, `2^(k/4)` in the
    /// warped image's units.
    pub extent: [i16; 2],
    /// The warp's centre in the image frame, in multiples of `n/4`.
    pub apex: [i64; 2],
}

impl WarpHold {
    /// Nothing held.
    pub const NONE: WarpHold = WarpHold { direction: -1, strength: 0, extent: [0; 2], apex: [0; 2] };

    /// Whether a warp is held.
    pub fn is_held(&self) -> bool {
        (0..16).contains(&self.direction)
    }
}

impl Default for WarpHold {
    fn default() -> Self {
        WarpHold::NONE
    }
}

impl Default for FitState {
    fn default() -> Self {
        FitState { steps: [-1; MAX_MAPS], warps: [WarpHold::NONE; MAX_MAPS] }
    }
}

impl FitState {
    /// A state with nothing held: the next fit is the stateless one.
    pub fn new() -> FitState {
        FitState::default()
    }

    /// The held spot-map steps as plain integers, to carry a state across a
    /// foreign boundary (the C ABI's `SfFitState`).
    pub fn to_steps(&self) -> [i16; MAX_MAPS] {
        self.steps
    }

    /// The held warps, per map slot (see [`WarpHold`]).
    pub fn to_warps(&self) -> [WarpHold; MAX_MAPS] {
        self.warps
    }

    /// A state from [`FitState::to_steps`]'s integers, holding no warp.
    /// Any values are safe: the fit checks every held step and ignores one
    /// that would not hold the body or that is negative.
    pub fn from_steps(steps: [i16; MAX_MAPS]) -> FitState {
        FitState { steps, ..FitState::default() }
    }

    /// A state from [`FitState::to_steps`] and [`FitState::to_warps`].
    pub fn from_parts(steps: [i16; MAX_MAPS], warps: [WarpHold; MAX_MAPS]) -> FitState {
        FitState { steps, warps }
    }
}

/// One map slot's share of a [`FitState`]: what its fit may hold, or what
/// it chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Held {
    /// A stable spot map's extent step (−1: none).
    pub step: i16,
    /// A stable warped map's steps.
    pub warp: WarpHold,
}

impl Held {
    pub(crate) const NONE: Held = Held { step: -1, warp: WarpHold::NONE };
}

impl FitState {
    /// Map slot `i`'s share.
    pub(crate) fn slot(&self, i: usize) -> Held {
        Held { step: self.steps[i], warp: self.warps[i] }
    }

    /// The state of the chosen steps, `None` beyond the maps given.
    pub(crate) fn from_slots(slots: impl Iterator<Item = Held>) -> FitState {
        let mut s = FitState::default();
        for (i, h) in slots.take(MAX_MAPS).enumerate() {
            (s.steps[i], s.warps[i]) = (h.step, h.warp);
        }
        s
    }
}
