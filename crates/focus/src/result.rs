//! What a fit returns: per map the matrices an engine uploads, and a plan
//! saying what the frame skipped and where it fell back.

use crate::clip::ClipConvention;
use crate::settings::{Footprint, Method};
use crate::state::{FitState, Held};
use crate::{MAX_MAPS, MAX_SPLITS};
use glam::{DMat4, Mat4};
use shadowfocus_geom::{Body, Focuser, Light};

/// The depth comparison a map must be rendered and sampled with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DepthTest {
    /// Keep the smallest depth (the caster nearest the light).
    Less,
    /// Keep the largest depth: the map's depth decreases toward the light,
    /// as with reversed-Z, or for PSM's inverted lights (behind the camera)
    /// without it.
    Greater,
}

impl DepthTest {
    /// The name used in reports and JSON.
    pub fn name(self) -> &'static str {
        match self {
            DepthTest::Less => "less",
            DepthTest::Greater => "greater",
        }
    }
}

/// Whether a map has anything to render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapState {
    /// The map covers its (non-empty) body.
    Active,
    /// The body is empty: nothing can shadow this split. The matrix is the
    /// zero matrix (every vertex lands at `w = 0` and is clipped), texel
    /// sizes are infinite; render nothing.
    Empty,
}

/// One face of an omnidirectional point light's cube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CubeFace {
    /// Looking along +x.
    PosX,
    /// Looking along −x.
    NegX,
    /// Looking along +y.
    PosY,
    /// Looking along −y.
    NegY,
    /// Looking along +z.
    PosZ,
    /// Looking along −z.
    NegZ,
}

impl CubeFace {
    /// The six faces, in the order the fit emits them.
    pub const ALL: [CubeFace; 6] = [CubeFace::PosX, CubeFace::NegX, CubeFace::PosY, CubeFace::NegY, CubeFace::PosZ, CubeFace::NegZ];

    /// The face of direction `d` from the light: its largest coordinate in
    /// magnitude (the first on ties) and that coordinate's sign. This is the
    /// face whose map answers for a receiver at `light + d`, as a cube map
    /// chooses: each face holds the casters of its own 90° cone (widened by
    /// 2⁻²⁰, so that the faces overlap), while its fitted image may reach
    /// past the cone — a receiver there, looked up in that face, would miss
    /// casters the face does not hold.
    pub fn toward(d: glam::DVec3) -> CubeFace {
        let a = d.abs();
        let k = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        CubeFace::ALL[2 * k + usize::from(d[k] < 0.0)]
    }

    /// The direction the face looks along and its up vector.
    pub fn axes(self) -> (glam::DVec3, glam::DVec3) {
        use glam::DVec3 as V;
        match self {
            CubeFace::PosX => (V::X, V::NEG_Y),
            CubeFace::NegX => (V::NEG_X, V::NEG_Y),
            CubeFace::PosY => (V::Y, V::Z),
            CubeFace::NegY => (V::NEG_Y, V::NEG_Z),
            CubeFace::PosZ => (V::Z, V::NEG_Y),
            CubeFace::NegZ => (V::NEG_Z, V::NEG_Y),
        }
    }

    /// The name used in reports and JSON.
    pub fn name(self) -> &'static str {
        ["+x", "-x", "+y", "-y", "+z", "-z"][self as usize]
    }
}

/// A fitted projection: what an engine uploads and renders one map with.
///
/// `clip_from_world` maps world points to the map's clip space in the
/// convention `clip` ([`crate::FocusSettings::clip`]): after the divide by
/// `w`, `x, y ∈ [−1, 1]` and depth `z` in the convention's range, `[0, 1]`
/// or `[−1, 1]`. Every vertex of the map's body lies in the clip volume
/// `w > 0, −w ≤ x, y ≤ w, z_min·w ≤ z ≤ w` (`z_min` =
/// [`ClipConvention::depth_min`]) — of its receivers only, where `footprint`
/// or `depth_clamp` says the map was fitted to them.
/// `clip_from_world_f32` is `clip_from_world · translate(f32_origin)` in
/// f32: applied in f32 arithmetic to a vertex's position relative to
/// [`crate::FocusSettings::f32_origin`], rounded to f32, it keeps the vertex
/// inside too — whenever `f32_exact` is true (false only when f32 cannot
/// resolve the body at that distance from the origin; then rebase). Columns
/// are glam's (column-major) order.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct MapFit {
    /// Whether there is anything to render.
    pub state: MapState,
    /// World to clip space in the convention `clip` (column-major).
    pub clip_from_world: DMat4,
    /// `clip_from_world · translate(f32_origin)` rounded to f32.
    pub clip_from_world_f32: Mat4,
    /// Whether the f32 guarantee above holds.
    pub f32_exact: bool,
    /// The comparison to render and sample the map with.
    pub depth_test: DepthTest,
    /// World size of one texel (square root of its footprint area on the
    /// plane perpendicular to the light ray) on the camera axis at the
    /// split's near and far depth; infinite where the map does not see that
    /// point.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float::pair"))]
    pub texel_size: [f64; 2],
    /// Texels per side of the square map: [`crate::FocusSettings::resolution`],
    /// or the map's share of a [`crate::TexelBudget`]; 0 for a map with
    /// nothing to render.
    #[cfg_attr(feature = "serde", serde(default))]
    pub resolution: u32,
    /// The method that produced the matrix (PSM may fall back to uniform).
    pub method: Method,
    /// Distance (in the map's image units) from the warp's projection centre
    /// to the body's near end: LiSPSM's `n_opt`, TSM's η; infinite when the
    /// map has no warp.
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_float"))]
    pub warp_near: f64,
    /// PSM's virtual camera shift along −forward (0 when none was needed).
    pub psm_shift: f64,
    /// The clip convention the matrices are written in.
    pub clip: ClipConvention,
    /// The depth range holds only the receivers (visible, lit points; see
    /// [`crate::FocusSettings::depth_clamp`]): render the map with depth
    /// clamping (wgpu `unclipped_depth`, Vulkan `depthClamp`, Direct3D
    /// `DepthClipEnable = false`), or casters toward the light are lost.
    pub depth_clamp: bool,
    /// What the image is fitted to ([`crate::FocusSettings::footprint`]).
    /// With [`crate::Footprint::Receivers`] the clip volume holds the
    /// receivers and every body point on a light ray through one; body
    /// vertices elsewhere fall outside `x, y ∈ [−1, 1]` (still inside the
    /// depth range unless `depth_clamp`).
    pub footprint: Footprint,
}

impl MapFit {
    /// The fit of an empty body: nothing to render, a zero matrix (never
    /// NaN), infinite texels.
    pub fn empty(method: Method, clip: ClipConvention) -> MapFit {
        MapFit {
            state: MapState::Empty,
            clip_from_world: DMat4::ZERO,
            clip_from_world_f32: Mat4::ZERO,
            f32_exact: true,
            depth_test: clip.normal_depth_test(),
            texel_size: [f64::INFINITY; 2],
            resolution: 0,
            method,
            warp_near: f64::INFINITY,
            psm_shift: 0.0,
            clip,
            depth_clamp: false,
            footprint: Footprint::Body,
        }
    }

    /// The matrix a shader looks the map up with: world point to
    /// `(u, v, depth, 1)·w`, so that after the divide `u, v ∈ [0, 1]` are
    /// the texture coordinates in the convention's layout and `depth` is
    /// what the depth buffer holds there, in `[0, 1]` (see
    /// [`ClipConvention::uv_from_clip`]); compare with `depth_test`.
    /// Every body vertex has `u, v, depth ∈ [0, 1]` up to the rounding of
    /// this one product (the containment guarantee is proven for
    /// `clip_from_world`, which this is an affine image of).
    pub fn uv_from_world(&self) -> DMat4 {
        self.clip.uv_from_clip() * self.clip_from_world
    }

    /// [`MapFit::uv_from_world`] for positions relative to the f32 origin,
    /// in f32: the lookup rows (halves and ones) applied to
    /// `clip_from_world_f32`.
    pub fn uv_from_world_f32(&self) -> Mat4 {
        self.clip.uv_from_clip().as_mat4() * self.clip_from_world_f32
    }

    /// Whether the light is inverted for this map (PSM with the light
    /// behind the camera): its depth test is the convention's other one.
    pub fn inverted(&self) -> bool {
        self.state == MapState::Active && self.depth_test != self.clip.normal_depth_test()
    }
}

/// One shadow map: a split (or cube face) of one light, its focus body and
/// the projection fitted to it ([`MapFit`]).
#[derive(Clone, Debug)]
pub struct ShadowMap {
    /// Index of the split this map serves.
    pub split: usize,
    /// The cube face, for omnidirectional point lights. A receiver `p` is
    /// looked up in the face [`CubeFace::toward`]`(p − light)` only: another
    /// face's image may hold `p` too, but not the casters on its light ray.
    pub face: Option<CubeFace>,
    /// The split's view-depth range `[z0, z1]` along the camera's forward axis.
    pub split_range: [f64; 2],
    /// The fitted projection: its matrices, depth test and texel sizes.
    pub fit: MapFit,
    /// For point lights, the distance `r` from the light within which
    /// casters may be left out of this map (see [`crate::LightNear`]); 0
    /// where the map leaves nothing out (directional and spot lights).
    pub light_near: f64,
    /// The light this map projects from (a cube face's 90° spot for
    /// omnidirectional lights).
    pub light: Light,
    /// The focus body `H` (computed for this map, possibly stale when
    /// `body_valid` is false).
    pub(crate) body: Body,
    pub(crate) body_valid: bool,
    /// The stable steps held from the previous frame, and the steps this
    /// fit chose ([`Held::NONE`]: not a stable spot or warped map).
    pub(crate) hold: Held,
    pub(crate) chosen: Held,
    /// This map's share of the frame's notes and skipped work.
    pub(crate) notes: Notes,
    pub(crate) skipped: Skipped,
}

impl ShadowMap {
    pub(crate) fn new() -> ShadowMap {
        ShadowMap {
            split: 0,
            face: None,
            split_range: [0.0; 2],
            fit: MapFit::empty(Method::Uniform, ClipConvention::WGPU),
            light_near: 0.0,
            light: Light::Directional { direction: glam::DVec3::NEG_Y },
            body: Body::new(),
            body_valid: false,
            hold: Held::NONE,
            chosen: Held::NONE,
            notes: Notes(0),
            skipped: Skipped(0),
        }
    }

    /// The focus body `H` this map covers (empty for maps whose split or
    /// face has no depth range at all).
    pub fn body(&self) -> &Body {
        if self.body_valid {
            &self.body
        } else {
            empty_body()
        }
    }

    pub(crate) fn set_empty(&mut self) {
        self.fit = MapFit::empty(self.fit.method, self.fit.clip);
    }

    /// Where this map departed from the requested method, and why (the
    /// frame's [`FocusResult::notes`] are the union over its maps and the
    /// frame-wide ones).
    pub fn notes(&self) -> Notes {
        self.notes
    }

    /// Work this map did not need ([`Skipped::WARP`]: its warp vanished).
    pub fn skipped(&self) -> Skipped {
        self.skipped
    }

    /// Whether the map has a body to render ([`MapState::Active`]).
    pub fn is_active(&self) -> bool {
        self.fit.state == MapState::Active
    }

    /// The light's view, for engines that keep view and projection apart:
    /// a rigid, right-handed `view_from_world` looking down its `−z` along
    /// the map's axis, with `+y` toward the map's `+y`. A point or spot
    /// light's eye is at the light; a directional light's is behind the
    /// body (by its bounding box's diagonal), so that the body lies in front.
    /// `light_projection() · light_view()` is `clip_from_world` up to
    /// rounding; the containment guarantee is stated for `clip_from_world`.
    pub fn light_view(&self) -> DMat4 {
        crate::light_frame::view_from_world(&self.light, &self.fit.clip_from_world, self.body())
    }

    /// `clip_from_world · light_view()⁻¹`: the map's projection from the
    /// light's view space (zero for an empty map).
    pub fn light_projection(&self) -> DMat4 {
        self.light_view_and_projection().1
    }

    /// [`ShadowMap::light_view`] and [`ShadowMap::light_projection`]
    /// together, the view computed once.
    pub fn light_view_and_projection(&self) -> (DMat4, DMat4) {
        let view = self.light_view();
        (view, self.fit.clip_from_world * crate::light_frame::world_from_view(&view))
    }

    /// Fraction of the map's area `[−1, 1]²` that the projection of its
    /// body covers (0 for an empty map): how many of its texels the fit
    /// puts on `H`. Computed on demand (a 2D convex hull of the body's
    /// image, no allocation), so that fits that do not ask do not pay.
    pub fn utilisation(&self) -> f64 {
        if !self.is_active() {
            return 0.0;
        }
        crate::project::utilisation(&self.fit.clip_from_world, self.body().vertices())
    }
}

fn empty_body() -> &'static Body {
    static EMPTY: std::sync::OnceLock<Body> = std::sync::OnceLock::new();
    EMPTY.get_or_init(Body::new)
}

macro_rules! flags {
    ($(#[$m:meta])* $name:ident { $($(#[$fm:meta])* $flag:ident = $bit:expr, $label:expr;)* }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub struct $name(pub u32);
        impl $name {
            $($(#[$fm])* pub const $flag: $name = $name(1 << $bit);)*
            const ALL: &'static [($name, &'static str)] = &[$(($name::$flag, $label)),*];
            /// Whether every flag of `f` is set.
            pub fn contains(self, f: $name) -> bool { self.0 & f.0 == f.0 }
            /// Sets the flags of `f`.
            pub fn insert(&mut self, f: $name) { self.0 |= f.0; }
            /// Clears the flags of `f`.
            pub fn remove(&mut self, f: $name) { self.0 &= !f.0; }
            /// Whether no flag is set.
            pub fn is_empty(self) -> bool { self.0 == 0 }
            /// Names of the set flags, for reports.
            pub fn names(self) -> impl Iterator<Item = &'static str> {
                Self::ALL.iter().filter(move |(f, _)| self.contains(*f)).map(|(_, n)| *n)
            }
        }
    };
}

flags! {
    /// Work the frame did not need and did not do.
    Skipped {
        /// No clip by the light frustum `L` (directional or point light).
        LIGHT_CLIP = 0, "light_clip";
        /// No clip by the scene box: `hull(V ∪ l) ⊆ S` (V and l inside S).
        SCENE_CLIP = 1, "scene_clip";
        /// PSM: `H` lay beyond the near plane in every map, no virtual shift.
        PSM_SHIFT = 2, "psm_shift";
        /// Some splits (or cube faces) have an empty `H`: no map rendered.
        EMPTY_MAPS = 3, "empty_maps";
        /// LiSPSM/TSM: the warp vanished in some map (γ = 0, or TSM's focus
        /// beyond the 80 % line), which is then exactly the uniform map.
        WARP = 4, "warp";
    }
}

flags! {
    /// Where the fit departed from the requested method, and why.
    Notes {
        /// PSM could not put the transformed light outside `H` (a point
        /// light inside the scene), or its predicted aliasing was worse
        /// than the uniform map's: those maps are uniform.
        PSM_FELL_BACK = 0, "psm_fell_back_to_uniform";
        /// A point light inside the view frustum cannot be seen by one
        /// perspective map, or one would see its body over a cone wider
        /// than a cube face's: six cube faces were used.
        POINT_AS_CUBE = 1, "point_light_as_cube";
        /// A point light within `light_near` of the scene box: casters that
        /// close to the light are not mapped (a perspective map cannot
        /// contain its own centre).
        LIGHT_NEAR = 2, "light_near_truncated";
        /// Some map's light is inverted (PSM, light behind the camera): it
        /// uses the convention's other depth test (greater, or less with
        /// reversed-Z).
        INVERTED = 3, "inverted_light";
        /// `stable` was requested where it does not apply (PSM,
        /// or a map whose stable construction could not hold its body) and
        /// was ignored.
        STABLE_IGNORED = 4, "stable_ignored";
        /// Some map's f32 matrix cannot keep its body inside the clip volume:
        /// the positions' f32 rounding (relative to `f32_origin`) is
        /// comparable to the body. The f64 matrix is still exact; rebase.
        F32_IMPRECISE = 5, "f32_imprecise";
        /// Some map's warp was weakened (LiSPSM/TSM: a smaller ε; PSM: a
        /// longer virtual shift), or replaced by the uniform map, because
        /// it was predicted to alias more than the uniform map fitted to
        /// the same body.
        WARP_LIMITED = 6, "warp_limited";
    }
}

/// The result of [`crate::fit`]: allocated once, refilled every frame.
pub struct FocusResult {
    maps: Box<[ShadowMap]>,
    len: usize,
    split_depths: [f64; MAX_SPLITS + 1],
    split_clip: [f64; MAX_SPLITS + 1],
    splits: usize,
    /// Work the frame did not need.
    pub skipped: Skipped,
    /// Where the frame departed from the request, and why.
    pub notes: Notes,
    /// The body engines' work space, shared by every map.
    focuser: Focuser,
    scratch: Body,
    /// The stable steps held from a [`FitState`] for this fit (nothing
    /// held for a fit without one).
    held: FitState,
}

impl Default for FocusResult {
    fn default() -> Self {
        FocusResult::new()
    }
}

impl std::fmt::Debug for FocusResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FocusResult")
            .field("maps", &self.maps())
            .field("split_depths", &self.split_depths())
            .field("skipped", &self.skipped)
            .field("notes", &self.notes)
            .finish()
    }
}

impl FocusResult {
    /// Room for `MAX_MAPS` maps (8 splits × 6 cube faces). Allocates once.
    pub fn new() -> FocusResult {
        FocusResult {
            maps: (0..MAX_MAPS).map(|_| ShadowMap::new()).collect(),
            len: 0,
            split_depths: [0.0; MAX_SPLITS + 1],
            split_clip: [0.0; MAX_SPLITS + 1],
            splits: 0,
            skipped: Skipped::default(),
            notes: Notes::default(),
            focuser: Focuser::new(),
            scratch: Body::new(),
            held: FitState::default(),
        }
    }

    /// The maps of the last fit, in split order (cube faces within a split
    /// in [`CubeFace::ALL`] order). Empty maps are included, marked
    /// [`MapState::Empty`].
    pub fn maps(&self) -> &[ShadowMap] {
        &self.maps[..self.len]
    }

    /// Split plane depths `C_0 = near, …, C_m = far` along the camera's
    /// forward axis.
    pub fn split_depths(&self) -> &[f64] {
        &self.split_depths[..=self.splits]
    }

    /// The same planes as clip-space depths of the right-handed camera
    /// projection in the fit's clip convention ([`ClipConvention::camera_depth`];
    /// by default `z ∈ [0, 1]`, as glam's `dcamera::rh::proj::directx::perspective`)
    /// [PSSM06 eq. 8]. A fragment with clip depth between `clip[i]` and
    /// `clip[i + 1]` samples split `i` (the values decrease with reversed-Z).
    pub fn split_clip_depths(&self) -> &[f64] {
        &self.split_clip[..=self.splits]
    }

    /// Number of splits of the last fit.
    pub fn split_count(&self) -> usize {
        self.splits
    }

    pub(crate) fn clear(&mut self) {
        self.len = 0;
        self.splits = 0;
        self.skipped = Skipped::default();
        self.notes = Notes::default();
    }

    pub(crate) fn set_splits(&mut self, depths: &[f64; MAX_SPLITS + 1], m: usize, clip: ClipConvention) {
        self.splits = m;
        self.split_depths = *depths;
        for i in 0..=m {
            self.split_clip[i] = clip.camera_depth(depths[0], depths[m], depths[i]);
        }
    }

    /// The maps, the body engine and a scratch body (for the receivers).
    pub(crate) fn maps_and_work(&mut self) -> (&mut [ShadowMap], &mut Focuser, &mut Body) {
        (&mut self.maps[..self.len], &mut self.focuser, &mut self.scratch)
    }

    /// The next map slot, and the work space to compute its body with.
    /// The steps to hold in the next fit.
    pub(crate) fn hold(&mut self, state: &FitState) {
        self.held = *state;
    }

    /// The steps each map slot's fit chose (none beyond the maps and for
    /// maps that are not stable spot or warped maps).
    pub(crate) fn chosen(&self) -> FitState {
        FitState::from_slots(self.maps().iter().map(|m| if m.is_active() { m.chosen } else { Held::NONE }))
    }

    pub(crate) fn push(&mut self) -> Option<(&mut ShadowMap, &mut Focuser)> {
        if self.len >= self.maps.len() {
            return None;
        }
        self.len += 1;
        let map = &mut self.maps[self.len - 1];
        (map.hold, map.chosen) = (self.held.slot(self.len - 1), Held::NONE);
        Some((map, &mut self.focuser))
    }

    pub(crate) fn pop(&mut self) {
        self.len -= 1;
    }
}
