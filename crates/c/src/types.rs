//! The C-visible types: inputs, settings, one fitted map, and the enums
//! whose values C passes as plain integers.
//!
//! NOTE: an enum-typed field that C fills is declared in Rust as a
//! `c_int` alias (`SfMethodInt`, …) and printed in the header as the C
//! enum (cbindgen.toml renames the alias's references and drops the alias
//! itself). Rust reads the integer and validates it: an out-of-range value
//! from C is an error, never an invalid Rust enum. A C enum with these
//! values has the size and alignment of `int`.

// NOTE: the enum values are named as C spells them (SF_OK, ...).
#![allow(non_camel_case_types)]

use std::ffi::c_int;

/// Status of every call that can fail: 0 on success, a negative code otherwise
/// (the message is in `sf_last_error`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfStatus {
    /// Success.
    SF_OK = 0,
    /// A required pointer argument was NULL.
    SF_ERR_NULL_POINTER = -1,
    /// An input is out of range: NaN or infinity, near >= far, a zero
    /// direction, an inverted box, a bad enum value, a setting outside its range.
    SF_ERR_INVALID_INPUT = -2,
    /// An output buffer holds fewer entries than needed; `*count` says how many.
    SF_ERR_BUFFER_TOO_SMALL = -3,
    /// No single projection from the light can see the focus body.
    SF_ERR_NO_SINGLE_PROJECTION = -4,
    /// A bug: an internal limit or a caught panic. The context stays usable.
    SF_ERR_INTERNAL = -5,
}

/// The kind of light.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfLightKind {
    /// A light at infinity travelling along `direction` (the sun).
    SF_LIGHT_DIRECTIONAL = 0,
    /// An omnidirectional light at `position`.
    SF_LIGHT_POINT = 1,
    /// A spot light at `position` lighting the frustum given by `direction`,
    /// `up`, `fovy_rad`, `aspect`, `near_dist` and `far_dist`.
    SF_LIGHT_SPOT = 2,
}

/// The shadow-map parameterisation.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfMethod {
    /// The focused standard map.
    SF_METHOD_UNIFORM = 0,
    /// Perspective shadow maps.
    SF_METHOD_PSM = 1,
    /// Light-space perspective shadow maps.
    SF_METHOD_LISPSM = 2,
    /// Trapezoidal shadow maps.
    SF_METHOD_TSM = 3,
    /// Per map, the one of the four with the least predicted aliasing (an
    /// active map's `method` says which, never this value).
    SF_METHOD_AUTO = 4,
}

/// How the view depth range is cut into parallel splits.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfSplitScheme {
    /// Evenly spaced split planes.
    SF_SPLIT_UNIFORM = 0,
    /// Logarithmically spaced split planes.
    SF_SPLIT_LOG = 1,
    /// `lambda` times the logarithmic plus `1 - lambda` times the uniform planes.
    SF_SPLIT_PRACTICAL = 2,
    /// The first split ends at the view depth `first_split`, the others
    /// follow geometrically to far (engine-style cascades).
    SF_SPLIT_GEOMETRIC = 3,
    /// Per light, planes that even out the splits' predicted aliasing
    /// (several fits per frame; refused with `stable`).
    SF_SPLIT_OPTIMAL = 4,
}

/// Which vector orients the LiSPSM warp.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfWarpDirection {
    /// The view direction projected perpendicular to the light.
    SF_WARP_VIEW_PROJECTED = 0,
    /// Eye to the centroid of the body, projected likewise.
    SF_WARP_MIDDLE_VECTOR = 1,
}

/// How each map's image is turned about its projection axis.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfOrientation {
    /// The least-area rectangle around the body's image fills the map.
    SF_ORIENTATION_LEAST_AREA = 0,
    /// The map's up follows the projected view direction, continuously.
    SF_ORIENTATION_VIEW_ALIGNED = 1,
}

/// The side lengths a map of a texel budget may take.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfMapSizes {
    /// Powers of two.
    SF_SIZES_POWER_OF_TWO = 0,
    /// Any whole number of texels.
    SF_SIZES_ANY = 1,
}

/// The face of the scene box that is the ground of an open scene
/// (`SfSettings::ground`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfGround {
    /// No ground: every face of the scene box stands for receivers.
    SF_GROUND_NONE = 0,
    /// The side of least x.
    SF_GROUND_MIN_X = 1,
    /// The side of greatest x.
    SF_GROUND_MAX_X = 2,
    /// The side of least y: the ground of a y-up world.
    SF_GROUND_MIN_Y = 3,
    /// The side of greatest y.
    SF_GROUND_MAX_Y = 4,
    /// The side of least z: the ground of a z-up world.
    SF_GROUND_MIN_Z = 5,
    /// The side of greatest z.
    SF_GROUND_MAX_Z = 6,
}

/// How a point light is covered.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SfPointMode {
    /// One perspective map, six cube faces when the light is in the view.
    SF_POINT_SINGLE = 0,
    /// Always six cube faces.
    SF_POINT_CUBE = 1,
}

/// An `SfLightKind` value as C stores it.
pub type SfLightKindInt = c_int;
/// An `SfMethod` value as C stores it.
pub type SfMethodInt = c_int;
/// An `SfSplitScheme` value as C stores it.
pub type SfSplitSchemeInt = c_int;
/// An `SfWarpDirection` value as C stores it.
pub type SfWarpDirectionInt = c_int;
/// An `SfOrientation` value as C stores it.
pub type SfOrientationInt = c_int;
/// An `SfPointMode` value as C stores it.
pub type SfPointModeInt = c_int;
/// An `SfMapSizes` value as C stores it.
pub type SfMapSizesInt = c_int;
/// An `SfGround` value as C stores it.
pub type SfGroundInt = c_int;

/// Most parallel splits.
pub const SF_MAX_SPLITS: u32 = 8;

/// Most receiver boxes kept (`SfSettings::receivers`); more are merged.
pub const SF_MAX_RECEIVER_BOXES: u32 = 16;
/// Most maps one fit can produce (every split of a point light as a cube).
pub const SF_MAX_MAPS: u32 = 48;
/// Most vertices of a focus body.
pub const SF_MAX_BODY_VERTICES: u32 = 128;
/// Most caster planes of one map (what `sf_caster_planes` may write).
pub const SF_MAX_CASTER_PLANES: u32 = 198;

/// Note: PSM fell back to the uniform map in some map.
pub const SF_NOTE_PSM_FELL_BACK: u32 = 1 << 0;
/// Note: a point light inside the view was covered by six cube faces.
pub const SF_NOTE_POINT_AS_CUBE: u32 = 1 << 1;
/// Note: casters within `light_near` of a point light are not mapped.
pub const SF_NOTE_LIGHT_NEAR: u32 = 1 << 2;
/// Note: the map uses the reversed (greater) depth test.
pub const SF_NOTE_INVERTED: u32 = 1 << 3;
/// Note: `stable` was requested where it does not apply, and ignored.
pub const SF_NOTE_STABLE_IGNORED: u32 = 1 << 4;
/// Note: the f32 matrix cannot keep the body inside the clip volume; rebase.
pub const SF_NOTE_F32_IMPRECISE: u32 = 1 << 5;
/// Note: the warp was weakened or replaced by the uniform map (predicted aliasing).
pub const SF_NOTE_WARP_LIMITED: u32 = 1 << 6;

/// Skipped: no clip by the light frustum.
pub const SF_SKIPPED_LIGHT_CLIP: u32 = 1 << 0;
/// Skipped: no clip by the scene box.
pub const SF_SKIPPED_SCENE_CLIP: u32 = 1 << 1;
/// Skipped: PSM needed no virtual shift.
pub const SF_SKIPPED_PSM_SHIFT: u32 = 1 << 2;
/// Skipped: some maps have an empty body.
pub const SF_SKIPPED_EMPTY_MAPS: u32 = 1 << 3;
/// Skipped: the warp vanished (the map is exactly the uniform one).
pub const SF_SKIPPED_WARP: u32 = 1 << 4;

/// A perspective camera. `forward` and `up` need not be unit length; `up`
/// must not be parallel to `forward`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SfCamera {
    /// Eye position, world units.
    pub eye: [f64; 3],
    /// View direction.
    pub forward: [f64; 3],
    /// Up hint.
    pub up: [f64; 3],
    /// Full vertical field of view in radians, in (0, pi).
    pub fovy_rad: f64,
    /// Width over height, > 0.
    pub aspect: f64,
    /// Near plane distance along `forward`, > 0.
    pub near_dist: f64,
    /// Far plane distance along `forward`, > `near_dist`.
    pub far_dist: f64,
}

/// A light. Directional lights use `direction` (where the light travels);
/// point lights `position`; spot lights every field, their frustum built
/// like a camera at `position` looking along `direction`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SfLight {
    /// An `SfLightKind` value.
    pub kind: SfLightKindInt,
    /// Position (point and spot lights).
    pub position: [f64; 3],
    /// Where the light travels (directional), or the spot's axis.
    pub direction: [f64; 3],
    /// The spot frustum's up hint.
    pub up: [f64; 3],
    /// The spot frustum's full vertical field of view, radians.
    pub fovy_rad: f64,
    /// The spot frustum's width over height.
    pub aspect: f64,
    /// The spot frustum's near distance, > 0.
    pub near_dist: f64,
    /// The spot frustum's far distance, > `near_dist`.
    pub far_dist: f64,
}

/// What a stable fit carries from one frame to the next (see
/// `sf_fit_light_held`): plain data, held by the caller, one per light.
/// Initialise it with `sf_fit_state_init`; its contents are hints that the
/// fit checks, so a state from another light or an earlier run never makes
/// a map lose its body.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SfFitState {
    /// Per map slot, a stable spot map's extent step held (-1: none).
    pub steps: [i16; 48],
    /// Per map slot, a stable LiSPSM or TSM map's lattice steps held.
    pub warps: [SfWarpHold; 48],
}

/// A stable LiSPSM or TSM map's lattice steps (the library's `WarpHold`):
/// integers, any values safe.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SfWarpHold {
    /// Warp direction in sixteenths of a turn (0..15); negative: none held.
    pub direction: i16,
    /// Warp distance `n = 2^(strength/4)` world units.
    pub strength: i16,
    /// Half extents across and along the warp, `2^(k/4)`.
    pub extent: [i16; 2],
    /// The warp's centre, in multiples of `n/4`.
    pub apex: [i64; 2],
}

/// An axis-aligned box; `min <= max` on every axis (zero thickness allowed).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SfAabb {
    /// Smallest corner.
    pub min: [f64; 3],
    /// Largest corner.
    pub max: [f64; 3],
}

/// What to fit. Fill it with `sf_settings_default`, then change fields.
/// Optional distances are "not set" when 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SfSettings {
    /// An `SfMethod` value (default uniform).
    pub method: SfMethodInt,
    /// Number of parallel splits, 1 to `SF_MAX_SPLITS` (default 1).
    pub splits: u32,
    /// An `SfSplitScheme` value (default optimal; stable maps with more than one split need another).
    pub split_scheme: SfSplitSchemeInt,
    /// Weight of the logarithmic planes in the practical scheme, in [0, 1] (default 0.5).
    pub lambda: f64,
    /// The far end of the first split for the geometric scheme, a view
    /// depth in world units; must be set (> 0) with that scheme (default 0,
    /// not set).
    pub first_split: f64,
    /// Non-negative shift of the inner split planes (default 0).
    pub delta_bias: f64,
    /// Map resolution in texels (square maps), >= 4 (default 2048).
    pub resolution: u32,
    /// Nonzero: stable maps with the uniform (or auto) method, texel-snapped
    /// with quantised extents and depth ranges (directional lights: camera-
    /// rotation invariant; spot lights: in the spot's frame; point lights:
    /// six cube faces); ignored with the other methods, with a note.
    pub stable: c_int,
    /// Nonzero: clip depth in [0, 1] (wgpu, Vulkan, Direct3D, Metal); 0: in
    /// [-1, 1] (OpenGL). Default 1.
    pub depth_zero_to_one: c_int,
    /// Nonzero: reversed-Z, depth 1 nearest the light (the maps then use
    /// the greater test, inverted PSM lights the less one). Default 0.
    pub reversed_z: c_int,
    /// Nonzero: the first texel row is the image's top (wgpu, Vulkan,
    /// Direct3D, Metal); 0: its bottom (OpenGL). Default 1.
    pub uv_origin_top_left: c_int,
    /// Nonzero: clip +y points down the rendered image (Vulkan). Default 0.
    /// With the three fields above: OpenGL is (0, 0, 0, 0), Vulkan
    /// (1, 0, 1, 1), wgpu, Direct3D and Metal (1, 0, 1, 0).
    pub clip_y_down: c_int,
    /// LiSPSM: a visible far distance that tightens the warp (0: none).
    pub lispsm_visible_far: f64,
    /// LiSPSM: an `SfWarpDirection` value (default view projected).
    pub lispsm_warp: SfWarpDirectionInt,
    /// PSM: a tightened near distance (0: none).
    pub psm_near: f64,
    /// PSM: a tightened far distance (0: none).
    pub psm_far: f64,
    /// TSM: the focus point's distance past the near plane, a fraction of the split in (0, 1] (default 0.25).
    pub tsm_focus: f64,
    /// An `SfPointMode` value (default single).
    pub point_mode: SfPointModeInt,
    /// Point lights: leave out casters within this fraction of the light's
    /// reach, in (0, 1) (default 1/1024); used when `light_near_fixed` is 0.
    pub light_near_fraction: f64,
    /// Point lights: leave out casters within this world distance (0: use the fraction).
    pub light_near_fixed: f64,
    /// An `SfOrientation` value (default least area).
    pub orientation: SfOrientationInt,
    /// Nonzero: weaken or drop warps predicted to alias more than the uniform map (default 1).
    pub warp_guard: c_int,
    /// Origin of the positions `clip_from_world_f32` is applied to (default 0, 0, 0).
    pub f32_origin: [f64; 3],
    /// Nonzero: fit each map's depth range to its receivers (the visible,
    /// lit part of its body) and render with depth clamping; maps so fitted
    /// have `depth_clamp` set. Default 0.
    pub depth_clamp: c_int,
    /// Nonzero: fit each map's image to its receivers only, grown by
    /// `receiver_margin_texels` on each side for the lookup filter; maps so
    /// fitted have `receiver_footprint` set. Default 0.
    pub receiver_footprint: c_int,
    /// Texels added around the receivers' image, in [0, resolution / 8]
    /// (default 2: a bilinear 2×2 lookup and a one-texel kernel).
    pub receiver_margin_texels: f64,
    /// The view depths [min, max] of the samples this frame shades (from
    /// the depth pre-pass, sample-distribution shadow maps): the fit covers
    /// only that slab of the view. Both 0: not set (default).
    pub visible_depth_min: f64,
    /// See `visible_depth_min`.
    pub visible_depth_max: f64,
    /// Nonzero: with a visible depth range, the first split still reaches
    /// back to `near` and the last out to `far` (the planes placed over the
    /// range), so that a receiver outside the range — one that came into
    /// view after a range a frame old was measured — still has a map.
    /// Default 0: only the range is covered.
    pub visible_depth_covers_view: c_int,
    /// Boxes around the surfaces that receive shadows, when the engine
    /// knows them (a terrain's tiles, a level's floors): every shaded
    /// receiver must lie in one, casters need not. Maps fitted to their
    /// receivers fit to the boxes' bounds, and the optimal split placement
    /// predicts aliasing on the boxes. More than `SF_MAX_RECEIVER_BOXES`
    /// are merged into that many. Read during the call only; NULL with
    /// `receiver_count` 0: none (default).
    pub receivers: *const SfAabb,
    /// Number of boxes at `receivers`.
    pub receiver_count: u32,
    /// Nonzero: the boxes at `receivers` are around the points a depth
    /// pre-pass saw (`sf_visible_receivers`, or the engine's own reduction),
    /// not solids: the prediction takes a camera ray's receiver where it
    /// leaves the last box it passes through, the farthest a seen point can
    /// be. Default 0: solids, a ray's receiver where it first meets one.
    pub receivers_seen: c_int,
    /// An `SfGround` value: the face of the scene box that is the ground
    /// of an open scene (a ground and what stands on it, under the sky;
    /// `SF_GROUND_MIN_Y` in a y-up world). The predicted aliasing that
    /// `SF_METHOD_AUTO`, the warp guard and the optimal split placement use
    /// then takes its receivers on that face only, not on the box's walls,
    /// where the geometry ends; what a map covers does not change. Receiver
    /// boxes take precedence. Default `SF_GROUND_NONE`.
    pub ground: SfGroundInt,
    /// Nonzero: the ground lies at `ground_level` on its face's axis, above
    /// the face (the top of a slab the world stands on); it must lie in the
    /// scene box. Default 0: on the face.
    pub ground_at_level: c_int,
    /// See `ground_at_level`.
    pub ground_level: f64,
    /// Texels shared among the active maps by their predicted aliasing
    /// (sum of size squared at most this), each map at most `resolution`
    /// wide and its size in `SfMap::resolution`; 0: every map is
    /// `resolution` wide (default). Refused with `stable`.
    pub texel_budget: u64,
    /// An `SfMapSizes` value: the sizes a budgeted map may take (default
    /// powers of two).
    pub budget_sizes: SfMapSizesInt,
}

/// One fitted shadow map.
///
/// `clip_from_world` maps world points to clip space (column-major) in the
/// settings' convention: after the divide by `w`, `x, y` in [-1, 1] and
/// depth `z` in [0, 1] (or [-1, 1] when `depth_zero_to_one` is 0). Every
/// vertex of the map's body satisfies `w > 0, -w <= x, y <= w` and `0 <= z
/// <= w` (resp. `-w <= z <= w`), and so does `clip_from_world_f32` applied
/// in float to the vertex minus `f32_origin` when `f32_exact` is nonzero.
/// Inactive maps have zero matrices.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SfMap {
    /// Nonzero when the map has a body to render; 0: render nothing.
    pub active: c_int,
    /// Nonzero: render and sample with the greater depth test (reversed-Z,
    /// or PSM's inverted lights without it); 0: less.
    pub depth_greater: c_int,
    /// The split's view-depth range along the camera's forward axis.
    pub split: [f64; 2],
    /// World to clip, column-major.
    pub clip_from_world: [f64; 16],
    /// `clip_from_world` times translate(`f32_origin`), rounded to float, column-major.
    pub clip_from_world_f32: [f32; 16],
    /// The lookup matrix: world point to (u, v, depth, 1) times w, with u, v
    /// the texture coordinates in the convention's layout and depth as the
    /// depth buffer stores it, in [0, 1]; compare with `depth_greater`.
    pub uv_from_world: [f64; 16],
    /// `uv_from_world` for positions relative to `f32_origin`, in float.
    pub uv_from_world_f32: [f32; 16],
    /// The light's rigid right-handed view (looking down -z along the map's
    /// axis; eye at a point or spot light, behind the body for the sun).
    pub light_view: [f64; 16],
    /// `clip_from_world` times the inverse of `light_view`.
    pub light_projection: [f64; 16],
    /// Nonzero: PSM's light is inverted for this map (its depth test is the
    /// convention's other one).
    pub inverted: c_int,
    /// World size of a texel at the split's near and far depth on the camera axis (infinite where unseen).
    pub texel_size: [f64; 2],
    /// The `SfMethod` that produced the matrix (PSM may fall back to uniform).
    pub method: SfMethodInt,
    /// Index of the split this map serves.
    pub split_index: u32,
    /// Cube face 0..5 (+x, -x, +y, -y, +z, -z) of a point light covered as a cube; -1 otherwise.
    /// Look a receiver p up in the face of p - light's largest coordinate in magnitude (the
    /// first on ties) and its sign, as a cube map chooses: a face's image may reach past its
    /// 90-degree cone into a neighbour's, but the casters there are in the neighbour's map.
    pub cube_face: c_int,
    /// Nonzero when the f32 guarantee holds.
    pub f32_exact: c_int,
    /// Distance from the warp's projection centre to the body (LiSPSM's n_opt, TSM's eta); infinite without warp.
    pub warp_near: f64,
    /// PSM's virtual camera shift (0 when none).
    pub psm_shift: f64,
    /// Point lights: casters closer than this to the light may be left out (0 otherwise).
    pub light_near: f64,
    /// `SF_NOTE_*` bits: where this map departed from the request.
    pub notes: u32,
    /// `SF_SKIPPED_*` bits: work this map did not need.
    pub skipped: u32,
    /// Number of vertices of the map's body (what `sf_body` writes).
    pub body_vertex_count: u32,
    /// Nonzero: the depth range holds only the receivers; render with depth
    /// clamping (wgpu unclipped_depth, Vulkan depthClamp, D3D
    /// DepthClipEnable = FALSE), or casters toward the light are lost.
    pub depth_clamp: c_int,
    /// Nonzero: the image holds the receivers (and every body point on a
    /// light ray through one), not the whole body.
    pub receiver_footprint: c_int,
    /// Texels per side of the square map: `resolution`, or its share of
    /// `texel_budget`; 0 for an inactive map.
    pub resolution: u32,
}
