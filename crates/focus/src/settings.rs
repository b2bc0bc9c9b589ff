//! What to fit: method, splits, resolution and per-method parameters.

use crate::clip::ClipConvention;
use crate::error::FocusError;
use crate::receiver_boxes::ReceiverBoxes;
use crate::MAX_SPLITS;

/// The shadow-map parameterisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Method {
    /// Focused standard map: orthographic (directional) or perspective from
    /// the light, fitted tightly to `H`.
    Uniform,
    /// Perspective shadow map: a uniform map fitted in the camera's
    /// post-perspective space.
    Psm,
    /// Light-space perspective shadow map (extra perspective along the view
    /// direction projected into the light's image plane).
    Lispsm,
    /// Trapezoidal shadow map (trapezoid around the light-space hull, with the
    /// focus point on the 80 % line).
    Tsm,
    /// Per map, whichever of the four has the least predicted maximum
    /// aliasing over the split's receivers ([`crate::MapFit::method`] says
    /// which); for a single map, LiSPSM with its warp swept stronger than
    /// `n_opt` where that predicts less ([`crate::MapFit::warp_near`] says
    /// how strong). With `stable`, the stable uniform map.
    Auto,
}

impl Method {
    /// The name used in reports and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Method::Uniform => "uniform",
            Method::Psm => "psm",
            Method::Lispsm => "lispsm",
            Method::Tsm => "tsm",
            Method::Auto => "auto",
        }
    }
}

/// How the view depth range is cut into parallel splits [PSSM06 §3.3].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SplitScheme {
    /// `C_i = n + (f − n) i/m` (eq. 5).
    Uniform,
    /// `C_i = n (f/n)^(i/m)` (eq. 4).
    Log,
    /// `C_i = λ C_i^log + (1 − λ) C_i^uniform` — eq. 6 is λ = ½.
    Practical {
        /// The weight λ ∈ [0, 1] of the logarithmic planes.
        lambda: f64,
    },
    /// The first split ends at the view depth `first`, the others follow
    /// geometrically to `far`: `C_i = first (f/first)^((i−1)/(m−1))` for
    /// `1 ≤ i < m` — the cascades most engines ship (a first cascade of a
    /// fixed length in world units). `first` is clamped into `[near, far]`.
    Geometric {
        /// The far end of the first split, a view depth in world units.
        first: f64,
    },
    /// Planes placed per light so that the splits' predicted maximum
    /// aliasing ([`crate::predict_aliasing`]: at the receiver boxes where
    /// [`crate::FocusSettings::receivers`] gives them, else at the receivers
    /// the scene box implies) is as even as the maps allow: from the better
    /// of `Practical { λ = ½ }` and logarithmic planes over the receivers'
    /// depth range, each round refits every split and moves the planes in
    /// log depth toward equal aliasing, and the best planes are kept —
    /// never worse by the prediction than the practical ones. The default:
    /// it costs a few fits per frame, and the planes move with the view and
    /// the light, so stable maps refuse it (choose `Practical`, `Log` or
    /// `Geometric` with them).
    Optimal,
}

/// Texels shared among a fit's maps ([`FocusSettings::texel_budget`]): each
/// active map's size follows its predicted maximum aliasing
/// ([`crate::predict_aliasing`]), so that the maps' maxima come out as even
/// as the sizes allow: [`SplitScheme::Optimal`]'s rule, applied to sizes.
/// No map's side falls below half an equal share's (`√(texels / maps) / 2`),
/// so that a split whose receivers the prediction misses loses at most 2×.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TexelBudget {
    /// The most texels the active maps may hold together, `Σ size²`; at
    /// least `MapSizes::SMALLEST²` per active map.
    pub texels: u64,
    /// Which sizes a map may take.
    pub sizes: MapSizes,
}

/// The side lengths a budgeted map may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapSizes {
    /// Powers of two (what texture arrays and atlases with mip-like
    /// packing want).
    PowerOfTwo,
    /// Any whole number of texels.
    Any,
}

impl MapSizes {
    /// The smallest side a map takes: the least [`FocusSettings::resolution`].
    pub const SMALLEST: u32 = 4;
}

/// Parallel splits of the view frustum.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SplitSettings {
    /// Number of splits, `1..=MAX_SPLITS`; 1 is a single map.
    pub count: usize,
    /// How the split planes are placed (default [`SplitScheme::Optimal`]).
    pub scheme: SplitScheme,
    /// Non-negative shift of the inner split planes (δ_bias of eq. 7); the
    /// outer planes stay at the camera's near and far.
    pub delta_bias: f64,
}

impl Default for SplitSettings {
    fn default() -> Self {
        SplitSettings { count: 1, scheme: SplitScheme::Optimal, delta_bias: 0.0 }
    }
}

/// Which vector orients the LiSPSM warp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum WarpDirection {
    /// The view direction projected perpendicular to the light.
    ViewProjected,
    /// The "middle vector": eye → centroid of `H`, projected likewise.
    MiddleVector,
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// Light-space perspective shadow maps \[LISPSM04\].
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LispsmSettings {
    /// A visible far distance (e.g. from occlusion culling). Only tightens
    /// `Δz` in `n_opt`; `H` is still computed from the full view frustum.
    pub visible_far: Option<f64>,
    /// The vector the warp is oriented by.
    pub warp: WarpDirection,
}

impl Default for LispsmSettings {
    fn default() -> Self {
        LispsmSettings { visible_far: None, warp: WarpDirection::ViewProjected }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Default)]
/// Perspective shadow maps \[PSM02\].
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PsmSettings {
    /// A tightened near distance (minimum visible depth read back by the
    /// engine). PSM then fits to the view frustum `[near, far]` with this
    /// near: every visible receiver lies in it, and every caster that can
    /// shadow one lies on a segment from it to the light, so `H` computed
    /// from the tightened frustum is still conservative for what is seen.
    pub near: Option<f64>,
    /// A tightened far distance, same contract.
    pub far: Option<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
/// Trapezoidal shadow maps \[TSM04\].
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TsmSettings {
    /// Distance δ of the focus point beyond the near plane, as a fraction of
    /// the split's depth range; the focus point is mapped to the 80 % line.
    pub focus: f64,
}

impl Default for TsmSettings {
    fn default() -> Self {
        TsmSettings { focus: 0.25 }
    }
}

/// How a map's image is turned about its projection axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapOrientation {
    /// Uniform and PSM maps are turned so that the least-area rectangle
    /// around the body's image fills the map; warped maps put their warp
    /// exactly along the image of the view direction. The most texels on
    /// the body; the orientation can jump where two rectangles tie.
    LeastArea,
    /// Every map's image up follows the (projected) view direction, blended
    /// continuously into a second reference near the view axis (see the
    /// module docs of the orientation frame): maps change continuously with
    /// the light and the camera, at the price of unused texels where the
    /// body's image lies across the frame.
    ViewAligned,
}

/// How a point light is covered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PointMode {
    /// One perspective map from the light toward the view; six cube faces
    /// when the light lies in the view frustum (no single map can see it)
    /// or one map would be wider than a cube face (a tangent above `√2`).
    Single,
    /// Six cube faces, each focused on its part of `H`.
    Cube,
}

/// The distance `r` from a point light within which casters may be left
/// out of its maps (a perspective map cannot contain its own centre).
///
/// The guarantee, per split: every point of the split's focus body `H_i`
/// farther than `r` from the light lies in some active map of the split;
/// each map reports its `r` in [`crate::ShadowMap::light_near`]. A single
/// map cuts `H_i` with a plane at `r / √(1 + t_x² + t_y²)` along its axis
/// (`t_x`, `t_y` the tangents of its half-angles, so that every point cut
/// off lies within `r`), and gives way to six cube faces, each cut at
/// `r/√3`, where its cone is wider than a cube face's (`t_x² + t_y² > 2`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LightNear {
    /// `r = fraction · R`, with `R` the light's reach over the split: the
    /// largest max-norm distance from the light to a corner of the split's
    /// frustum or, if smaller, of the scene box (an upper bound of the
    /// distance from the light to any point of `H_i`, in the max norm). `r`
    /// then follows the scene's scale; `fraction` lies in `(0, 1)`.
    Auto {
        /// `r` over the light's reach.
        fraction: f64,
    },
    /// A fixed `r` in world units (e.g. the light's own radius); finite and
    /// positive.
    Fixed(f64),
}

impl LightNear {
    /// The default fraction of [`LightNear::Auto`]: 2⁻¹⁰, a depth range of
    /// about a thousand for a map that reaches across the split.
    pub const DEFAULT_FRACTION: f64 = 1.0 / 1024.0;

    /// `r` for a light whose reach over the split is `reach`.
    pub fn radius(self, reach: f64) -> f64 {
        match self {
            LightNear::Auto { fraction } => fraction * reach,
            LightNear::Fixed(r) => r,
        }
    }
}

impl Default for LightNear {
    fn default() -> Self {
        LightNear::Auto { fraction: LightNear::DEFAULT_FRACTION }
    }
}

/// Which part of each map's body its image (the `x`, `y` extent) is fitted
/// to. The depth range holds the whole body either way (or only the
/// receivers, with [`FocusSettings::depth_clamp`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Footprint {
    /// All of the body `H_i`: every body vertex lies in the map.
    Body,
    /// Only the receivers `R_i = V_i ∩ S ∩ L` (the visible part of `H_i`),
    /// with `margin_texels` texels more on each side for the lookup
    /// filter's reach (at least the PCF kernel's radius plus one for
    /// bilinear taps). Every receiver lies in the map, and every point of
    /// `H_i` on a light ray through a receiver: the casters that can shadow
    /// it. `0 ≤ margin_texels ≤ resolution / 8`.
    Receivers {
        /// Texels added on each side of the receivers' image.
        margin_texels: f64,
    },
}

impl Footprint {
    /// The margin of a 2×2 bilinear lookup with a one-texel kernel.
    pub const DEFAULT_MARGIN_TEXELS: f64 = 2.0;
    /// The receivers with [`Footprint::DEFAULT_MARGIN_TEXELS`].
    pub const RECEIVERS: Footprint = Footprint::Receivers { margin_texels: Footprint::DEFAULT_MARGIN_TEXELS };
}

/// A face of an axis-aligned box: its side of least (`Min`) or greatest
/// (`Max`) coordinate along one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum BoxFace {
    /// The side of least x.
    MinX,
    /// The side of greatest x.
    MaxX,
    /// The side of least y: the ground of a y-up world.
    MinY,
    /// The side of greatest y.
    MaxY,
    /// The side of least z: the ground of a z-up world.
    MinZ,
    /// The side of greatest z.
    MaxZ,
}

impl BoxFace {
    /// The faces, in the order of [`BoxFace::index`].
    pub const ALL: [BoxFace; 6] = [BoxFace::MinX, BoxFace::MaxX, BoxFace::MinY, BoxFace::MaxY, BoxFace::MinZ, BoxFace::MaxZ];

    /// The axis the face is perpendicular to: 0, 1, 2 for x, y, z.
    pub const fn axis(self) -> usize {
        self.index() / 2
    }

    /// Whether it is the side of greatest coordinate.
    pub const fn is_max(self) -> bool {
        self.index() % 2 == 1
    }

    /// `2 · axis + is_max`.
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// The ground of an open scene ([`FocusSettings::ground`]): a plane facing
/// into the scene box from its face `face`, on the face itself or, at
/// `level`, inside the box.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Ground {
    /// The face the ground is parallel to, on the scene's open side of it:
    /// `MinY` in a y-up world.
    pub face: BoxFace,
    /// The ground's coordinate along the face's axis where it lies above
    /// the box's face: the top of a slab the world stands on. It must lie
    /// in the scene box. None: on the face. A camera below the ground sees
    /// none of it: the prediction then has no receivers and keeps no warp,
    /// so a level for an uneven terrain (whose valleys the camera may
    /// stand in) is worse than receiver boxes that follow it.
    #[cfg_attr(feature = "serde", serde(default))]
    pub level: Option<f64>,
}

impl Ground {
    /// The ground on the face `face` of the scene box.
    pub const fn face(face: BoxFace) -> Ground {
        Ground { face, level: None }
    }

    /// The ground parallel to `face` at `level` along its axis.
    pub const fn at(face: BoxFace, level: f64) -> Ground {
        Ground { face, level: Some(level) }
    }
}

impl From<BoxFace> for Ground {
    fn from(face: BoxFace) -> Ground {
        Ground::face(face)
    }
}

/// What the splits cover when a visible depth range is given
/// ([`FocusSettings::visible_depth`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DepthHintCoverage {
    /// The hinted slab only: every split lies in it. Right for a range
    /// reduced from the frame's own depth pre-pass, which holds every
    /// shaded receiver.
    #[default]
    Hint,
    /// The whole view: the planes are placed over the hinted slab as with
    /// `Hint`, then the first split reaches back to the camera's `near` and
    /// the last out to its `far`. A receiver outside the hint — one that
    /// came into view after the range was measured (a disocclusion, or an
    /// object moving in, with a range a frame old) — still lies in a map, at
    /// the outer split's resolution, instead of in none. With one split the
    /// hint then changes nothing.
    View,
}

/// Everything a fit needs besides camera, light and scene.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FocusSettings {
    /// The parameterisation (default uniform).
    pub method: Method,
    /// Parallel splits of the view (default one).
    pub splits: SplitSettings,
    /// Shadow-map resolution in texels (square maps), ≥ 4: every map's
    /// side, or with a [`TexelBudget`] the largest side a map may take.
    pub resolution: u32,
    /// Stable maps: texel-snapped, their extent and depth range quantised,
    /// so that from frame to frame a map moves by whole texels or not at
    /// all. Directional lights: with the uniform method (or `Auto`, which
    /// then takes it) camera-rotation invariant; with LiSPSM or TSM the
    /// warp's direction, strength and centre on world-fixed lattices (held
    /// from frame to frame with a [`crate::FitState`]). Spot lights: in the
    /// spot's own frame, unwarped; point lights: six cube faces, each a
    /// stable spot. Ignored with PSM, whose grid moves with the camera, and
    /// said so in the plan.
    pub stable: bool,
    /// LiSPSM parameters.
    pub lispsm: LispsmSettings,
    /// PSM parameters.
    pub psm: PsmSettings,
    /// TSM parameters.
    pub tsm: TsmSettings,
    /// How point lights are covered.
    pub point: PointMode,
    /// Distance from a point light below which casters may be left out of
    /// its maps (see [`LightNear`]; by default a fraction of the light's
    /// reach, so it follows the scene's scale). Spot lights use their own
    /// frustum's near plane instead.
    pub light_near: LightNear,
    /// How each map's image is turned (default: least area).
    pub orientation: MapOrientation,
    /// LiSPSM, TSM and PSM are weakened or replaced by the uniform map where
    /// their predicted aliasing is worse than the uniform map's (on by
    /// default; off gives each method exactly as designed, continuous in its
    /// inputs).
    pub warp_guard: bool,
    /// Origin of the positions the f32 matrix is applied to:
    /// [`crate::MapFit::clip_from_world_f32`] maps `p − f32_origin` (rounded to
    /// f32) and its rounding margins are computed for those magnitudes.
    /// Zero means world positions; an engine that renders camera-relative
    /// (large worlds) passes its rebasing origin, e.g. the camera position.
    pub f32_origin: glam::DVec3,
    /// The clip convention of the API the maps are rendered with: depth
    /// range, reversed-Z and texture layout (default [`ClipConvention::WGPU`]).
    /// It decides each map's depth row, its depth test and its lookup
    /// matrix; which light rays a map covers does not depend on it.
    pub clip: ClipConvention,
    /// Fit each map's depth range to its receivers only (the visible, lit
    /// part `V_i ∩ S ∩ L` of its body) and render with depth clamping
    /// ("pancaking"): casters toward the light are clamped to the range's
    /// near end instead of widening it. Maps fitted so say
    /// [`crate::MapFit::depth_clamp`]. Off by default.
    pub depth_clamp: bool,
    /// What each map's image is fitted to: its whole body (default) or the
    /// receivers only ([`Footprint`]); maps fitted to the receivers say
    /// so in [`crate::MapFit::footprint`].
    pub footprint: Footprint,
    /// The view depths `[z_min, z_max]` of the samples the frame shades
    /// (read back from its depth pre-pass), when the engine knows them: the
    /// fit then covers only `[max(near, z_min), min(far, z_max)]`, its splits
    /// placed over that slab \[SDSM10\]. Every shaded receiver must lie in it,
    /// unless [`FocusSettings::visible_depth_coverage`] is
    /// [`DepthHintCoverage::View`] (see
    /// [`crate::visible_depth_after_motion`] for a range one frame old).
    /// With [`SplitScheme::Optimal`] (the default) the first plane starts no
    /// farther out than the logarithmic plane over the range; the practical
    /// scheme's uniform part lengthens the first split as the near end
    /// moves out.
    pub visible_depth: Option<[f64; 2]>,
    /// What the splits cover with a visible depth range: the hinted slab
    /// (default) or the whole view, the planes still placed over the slab
    /// ([`DepthHintCoverage`]). A range a frame old needs `View` for no
    /// pixel to be left without a map.
    #[cfg_attr(feature = "serde", serde(default))]
    pub visible_depth_coverage: DepthHintCoverage,
    /// Boxes around the surfaces that receive shadows, when the engine
    /// knows them (a terrain's tiles, a level's floors): maps fitted to
    /// their receivers ([`Footprint::Receivers`], `depth_clamp`) fit to the
    /// part inside the boxes' bounds, and the predicted aliasing
    /// ([`SplitScheme::Optimal`], [`crate::predict_aliasing`]) takes its
    /// receivers on the boxes. Every shaded receiver must lie in a box;
    /// casters need not. An engine that knows no boxes but renders a depth
    /// pre-pass passes boxes around what it saw ([`crate::VisibleReceivers`],
    /// [`ReceiverBoxes::seen`]). Empty by default.
    #[cfg_attr(feature = "serde", serde(default))]
    pub receivers: ReceiverBoxes,
    /// The ground of an open scene (a ground and what stands on it, under
    /// the sky; the scene box's `MinY` face in a y-up world, or a level
    /// above it where the world stands on a slab), when the engine knows
    /// it: the predicted aliasing (`Auto`'s choice, the warp guard,
    /// [`SplitScheme::Optimal`], [`crate::predict_aliasing`]) then takes its
    /// receivers on that ground only, and the box's other faces, where the
    /// scene's geometry ends, stand for nothing. It moves what the
    /// prediction looks at, never what a map covers. None by default: every
    /// face of the scene box stands for receivers (a room's walls).
    /// Receiver boxes, where given, take precedence.
    #[cfg_attr(feature = "serde", serde(default))]
    pub ground: Option<Ground>,
    /// Texels shared among the maps by their predicted aliasing, instead of
    /// `resolution²` each ([`TexelBudget`]); each map says its size in
    /// [`crate::MapFit::resolution`]. The sizes follow the view and the
    /// light, so stable maps refuse a budget. None by default.
    #[cfg_attr(feature = "serde", serde(default))]
    pub texel_budget: Option<TexelBudget>,
}

impl Default for FocusSettings {
    fn default() -> Self {
        FocusSettings {
            method: Method::Uniform,
            splits: SplitSettings::default(),
            resolution: 2048,
            stable: false,
            lispsm: LispsmSettings::default(),
            psm: PsmSettings::default(),
            tsm: TsmSettings::default(),
            point: PointMode::Single,
            light_near: LightNear::default(),
            orientation: MapOrientation::LeastArea,
            warp_guard: true,
            f32_origin: glam::DVec3::ZERO,
            clip: ClipConvention::WGPU,
            depth_clamp: false,
            footprint: Footprint::Body,
            visible_depth: None,
            visible_depth_coverage: DepthHintCoverage::Hint,
            receivers: ReceiverBoxes::NONE,
            ground: None,
            texel_budget: None,
        }
    }
}

impl FocusSettings {
    /// Whether the stable maps apply: `stable` with the uniform method, or
    /// with `Auto`, which then takes the stable uniform map.
    pub(crate) fn stable_uniform(&self) -> bool {
        self.stable && matches!(self.method, Method::Uniform | Method::Auto)
    }

    /// Whether the stable warped maps apply: `stable` with LiSPSM or TSM
    /// (a directional light's; a spot light's stable map is its own).
    pub(crate) fn stable_warp(&self) -> bool {
        self.stable && matches!(self.method, Method::Lispsm | Method::Tsm)
    }

    /// Whether `stable` applies at all: every method but PSM, whose texel
    /// grid lives in the camera's post-perspective space.
    pub(crate) fn stable_applies(&self) -> bool {
        self.stable_uniform() || self.stable_warp()
    }

    /// Checks every parameter against its documented range.
    pub fn validate(&self) -> Result<(), FocusError> {
        let bad = |what, reason| Err(FocusError::InvalidSettings { what, reason });
        if self.splits.count == 0 || self.splits.count > MAX_SPLITS {
            return bad("splits.count", "must be between 1 and 8");
        }
        if !(self.splits.delta_bias.is_finite() && self.splits.delta_bias >= 0.0) {
            return bad("splits.delta_bias", "must be finite and non-negative");
        }
        match self.splits.scheme {
            SplitScheme::Practical { lambda } if !(0.0..=1.0).contains(&lambda) => return bad("splits.lambda", "must lie in [0, 1]"),
            SplitScheme::Geometric { first } if !(first.is_finite() && first > 0.0) => {
                return bad("splits.first", "must be finite and positive")
            }
            SplitScheme::Optimal if self.stable && self.splits.count > 1 => {
                return bad(
                    "splits.scheme",
                    "optimal placement (the default) moves the split planes with the view and the light; stable maps need planes that hold still: choose Practical, Log, Uniform or Geometric",
                )
            }
            _ => {}
        }
        if self.resolution < MapSizes::SMALLEST {
            return bad("resolution", "must be at least 4 texels");
        }
        if let Some(b) = self.texel_budget {
            let least = u64::from(MapSizes::SMALLEST).pow(2);
            if b.texels < least {
                return bad("texel_budget.texels", "must be at least 16 (one map of 4 × 4 texels)");
            }
            if self.stable {
                return bad(
                    "texel_budget",
                    "a budget resizes the maps with the view and the light; stable maps need sizes that hold still: give each map `resolution` instead",
                );
            }
        }
        match self.light_near {
            LightNear::Auto { fraction } => {
                if !(fraction > 0.0 && fraction < 1.0) {
                    return bad("light_near", "Auto's fraction must lie in (0, 1)");
                }
            }
            LightNear::Fixed(r) => {
                if !(r.is_finite() && r > 0.0) {
                    return bad("light_near", "Fixed(r) must be finite and positive");
                }
            }
        }
        if let Footprint::Receivers { margin_texels } = self.footprint {
            if !(margin_texels >= 0.0 && margin_texels <= self.resolution as f64 / 8.0) {
                return bad("footprint.margin_texels", "must lie in [0, resolution / 8]");
            }
            if self.stable {
                return bad(
                    "footprint",
                    "stable maps keep a fixed, texel-snapped extent; fitting them to the receivers would move it every frame",
                );
            }
        }
        if let Some([lo, hi]) = self.visible_depth {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return bad("visible_depth", "must be finite with z_min < z_max");
            }
        }
        if let Some(Ground { level: Some(level), .. }) = self.ground {
            if !level.is_finite() {
                return bad("ground.level", "must be finite");
            }
        }
        if !self.f32_origin.is_finite() {
            return bad("f32_origin", "must be finite");
        }
        if !(self.tsm.focus.is_finite() && self.tsm.focus > 0.0 && self.tsm.focus <= 1.0) {
            return bad("tsm.focus", "must lie in (0, 1]");
        }
        for (v, what) in [(self.lispsm.visible_far, "lispsm.visible_far"), (self.psm.near, "psm.near"), (self.psm.far, "psm.far")] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return bad(what, "must be finite and positive");
                }
            }
        }
        Ok(())
    }
}
