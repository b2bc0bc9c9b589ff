//! The focus body `H = hull(V ∪ {l}) ∩ S ∩ L` and its rounded output form.

use crate::certified::{CertifiedClipper, Step};
use crate::error::{check_finite, GeomError};
use crate::frustum::{Apex, Frustum, HullOutline, PlaneSet};
use crate::limits::{MAX_FACES, MAX_FACE_INDICES, MAX_VERTICES};
use crate::polytope::Polytope;
use glam::{DVec3, DVec4};

/// A closed axis-aligned box; zero thickness on any axis is allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    pub fn new(min: DVec3, max: DVec3) -> Result<Aabb, GeomError> {
        let b = Aabb { min, max };
        b.validate()?;
        Ok(b)
    }

    pub(crate) fn validate(&self) -> Result<(), GeomError> {
        check_finite(self.min, "scene box min")?;
        check_finite(self.max, "scene box max")?;
        for axis in 0..3 {
            if self.min[axis] > self.max[axis] {
                return Err(GeomError::InvertedBox { axis });
            }
        }
        Ok(())
    }

    /// The smallest box containing the points (exact: no arithmetic).
    pub fn around(points: &[DVec3]) -> Option<Aabb> {
        let first = *points.first()?;
        let (mut min, mut max) = (first, first);
        for p in points {
            min = min.min(*p);
            max = max.max(*p);
        }
        Some(Aabb { min, max })
    }

    /// Whether `p` lies in the closed box (exact comparisons).
    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }
}

/// A light. A directional light is the point at infinity it comes from.
// NOTE: a spot light carries its validated frustum by value, so that a
// `Light` is `Copy` and nothing is allocated per frame; the other variants
// pay its size.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light travelling along `direction` (from the light into the scene).
    Directional { direction: DVec3 },
    /// An omnidirectional point light.
    Point { position: DVec3 },
    /// A spot light: its apex and the frustum it lights.
    Spot { position: DVec3, frustum: Frustum },
}

impl Light {
    pub fn directional(direction: DVec3) -> Result<Light, GeomError> {
        let l = Light::Directional { direction };
        l.validate()?;
        Ok(l)
    }

    pub fn point(position: DVec3) -> Result<Light, GeomError> {
        let l = Light::Point { position };
        l.validate()?;
        Ok(l)
    }

    pub fn spot(position: DVec3, frustum: Frustum) -> Result<Light, GeomError> {
        let l = Light::Spot { position, frustum };
        l.validate()?;
        Ok(l)
    }

    /// Checks a light built from its fields: finite numbers, a nonzero
    /// direction (a spot light's frustum is valid by construction).
    pub fn validate(&self) -> Result<(), GeomError> {
        match *self {
            Light::Directional { direction } => {
                check_finite(direction, "light direction")?;
                if direction == DVec3::ZERO {
                    return Err(GeomError::ZeroDirection { what: "light direction" });
                }
                Ok(())
            }
            Light::Point { position } | Light::Spot { position, .. } => check_finite(position, "light position"),
        }
    }

    /// The unit vector along a directional light's travel direction, for
    /// any finite nonzero direction however long or short (see
    /// [`unit_direction`]); `None` for point and spot lights.
    pub fn unit_direction(&self) -> Option<DVec3> {
        match *self {
            Light::Directional { direction } => Some(unit_direction(direction)),
            _ => None,
        }
    }

    /// The light as a homogeneous point (at infinity for directional lights).
    pub fn apex(&self) -> Apex {
        match *self {
            Light::Directional { direction } => Apex::Infinite(-direction),
            Light::Point { position } | Light::Spot { position, .. } => Apex::Finite(position),
        }
    }
}

/// `d / |d|` for any finite nonzero `d`, also where `|d|²` overflows
/// (|d| above ~1e154) or underflows (below ~1e-154), which `normalize`
/// turns into zero, infinity or NaN.
///
/// `d` is first multiplied by the power of two `2^-e` that brings its
/// largest component into `[1, 2)` (exact: only the exponents change, except
/// for components below 2⁻¹⁰²² of the largest, which round as a unit vector
/// would round them anyway), then normalised. The zero vector and
/// non-finite input give NaN components (validated lights never have them).
pub fn unit_direction(d: DVec3) -> DVec3 {
    let m = d.abs().max_element();
    if !(m > 0.0 && m.is_finite()) {
        return DVec3::splat(f64::NAN);
    }
    let bits = m.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    // floor(log2 m), exactly, for normal and subnormal m: in [-1074, 1023].
    let e = if biased == 0 { -1074 + (63 - (bits & ((1u64 << 52) - 1)).leading_zeros() as i32) } else { biased - 1023 };
    // 2^-e in two factors, each a normal power of two (|k| ≤ 537).
    let pow2 = |k: i32| f64::from_bits(((k + 1023) as u64) << 52);
    let (a, b) = (-e / 2, -e - (-e / 2));
    (d * pow2(a) * pow2(b)).normalize()
}

/// Dimension of a focus body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dimension {
    Empty,
    Point,
    Segment,
    Polygon,
    Solid,
}

impl Dimension {
    /// −1 for empty, else the affine dimension.
    pub fn as_i32(self) -> i32 {
        match self {
            Dimension::Empty => -1,
            Dimension::Point => 0,
            Dimension::Segment => 1,
            Dimension::Polygon => 2,
            Dimension::Solid => 3,
        }
    }

    fn from_i8(d: i8) -> Dimension {
        match d {
            0 => Dimension::Point,
            1 => Dimension::Segment,
            2 => Dimension::Polygon,
            3 => Dimension::Solid,
            _ => Dimension::Empty,
        }
    }
}

/// What a focus-body computation did and skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FocusStats {
    /// `S` was not clipped because `hull(V ∪ {l}) ⊆ S` (V and l inside S).
    pub scene_clip_skipped: bool,
    /// `L` was not clipped (no spot light).
    pub light_clip_skipped: bool,
    /// Halfspaces offered to the clipper.
    pub planes_offered: u16,
    /// Halfspaces that actually cut.
    pub planes_cut: u16,
    /// Faces of `S` and `L` the certified path did not clip because the
    /// body's bounding box lies strictly inside them.
    pub planes_cleared: u16,
    /// Stopped early because the body became empty.
    pub early_exit: bool,
    /// Big-integer evaluations: on the exact engine, predicates and
    /// coordinates the floating-point filters could not settle; on the float
    /// path, vertices placed from their planes' exact intersection (where
    /// the float estimate's proven error was above the output tolerance).
    pub exact_evaluations: u32,
    /// The certified floating-point path answered; the exact engine was
    /// not needed.
    pub float_path: bool,
    /// The float path answered a spot light only on its second try, with
    /// `L` clipped before `S` (the first, `S` before `L`, left a sign
    /// unproven).
    pub light_clipped_first: bool,
}

/// A focus body with rounded vertices: a fixed-capacity value, reusable
/// across frames without allocation.
#[derive(Clone)]
pub struct Body {
    pub(crate) dim: i8,
    pub(crate) verts: [DVec3; MAX_VERTICES],
    pub(crate) n_verts: usize,
    pub(crate) idx: [u16; MAX_FACE_INDICES],
    pub(crate) face_start: [u16; MAX_FACES + 1],
    pub(crate) face_planes: [DVec4; MAX_FACES],
    pub(crate) n_faces: usize,
    pub(crate) stats: FocusStats,
    /// Scratch space for the exact engine and the fast path, allocated on
    /// first use and kept, so that reusing a `Body` allocates nothing.
    work: Option<Box<Polytope>>,
    fast: Option<Box<CertifiedClipper>>,
    plan: Option<Box<Plan>>,
    /// The inputs of the last computation, valid when `inputs_valid`.
    inputs: Inputs,
    inputs_valid: bool,
}

/// What [`Body::exact`] rebuilds the inputs from: corners rather than
/// validated frusta.
///
/// NOTE: a validated frustum carries its face structure and normals (about
/// 900 bytes, as does every `Light` value, whatever its kind); copying two
/// of them per body was a visible share of a frame. The corners are all that
/// defines them, and validating the same corners again gives the same
/// frustum.
#[derive(Clone, Copy)]
struct Inputs {
    view: [DVec3; 8],
    light: LightInput,
    /// A spot light's frustum corners (unused for other lights).
    spot_corners: [DVec3; 8],
    scene: Aabb,
}

#[derive(Clone, Copy)]
enum LightInput {
    Directional(DVec3),
    Point(DVec3),
    Spot(DVec3),
}

impl Default for Body {
    fn default() -> Self {
        Body::new()
    }
}

impl std::fmt::Debug for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Body")
            .field("dimension", &self.dimension())
            .field("vertices", &self.vertices())
            .field("faces", &self.faces().collect::<Vec<_>>())
            .field("volume", &self.volume())
            .finish()
    }
}

impl Body {
    /// An empty body.
    pub fn new() -> Body {
        Body {
            dim: -1,
            verts: [DVec3::ZERO; MAX_VERTICES],
            n_verts: 0,
            idx: [0; MAX_FACE_INDICES],
            face_start: [0; MAX_FACES + 1],
            face_planes: [DVec4::ZERO; MAX_FACES],
            n_faces: 0,
            stats: FocusStats::default(),
            work: None,
            fast: None,
            plan: None,
            inputs: Inputs {
                view: [DVec3::ZERO; 8],
                light: LightInput::Point(DVec3::ZERO),
                spot_corners: [DVec3::ZERO; 8],
                scene: Aabb { min: DVec3::ZERO, max: DVec3::ZERO },
            },
            inputs_valid: false,
        }
    }

    pub(crate) fn clear(&mut self) {
        self.dim = -1;
        self.n_verts = 0;
        self.n_faces = 0;
    }

    pub fn dimension(&self) -> Dimension {
        Dimension::from_i8(self.dim)
    }

    pub fn is_empty(&self) -> bool {
        self.dim < 0
    }

    /// Rounded vertices; every exact vertex is within a few ulps (of the
    /// inputs' magnitude) of its rounded counterpart.
    pub fn vertices(&self) -> &[DVec3] {
        &self.verts[..self.n_verts]
    }

    pub fn face_count(&self) -> usize {
        self.n_faces
    }

    /// Face `i` as vertex indices, counter-clockwise seen from outside (for
    /// a polygon: seen from the side its face plane's normal points to);
    /// `None` for `i ≥ face_count()`.
    #[inline]
    pub fn face(&self, i: usize) -> Option<&[u16]> {
        (i < self.n_faces).then(|| self.face_unchecked(i))
    }

    /// Face `i < n_faces`.
    #[inline]
    fn face_unchecked(&self, i: usize) -> &[u16] {
        &self.idx[self.face_start[i] as usize..self.face_start[i + 1] as usize]
    }

    pub fn faces(&self) -> impl Iterator<Item = &[u16]> + '_ {
        (0..self.n_faces).map(move |i| self.face_unchecked(i))
    }

    /// Per face: unit outward normal (xyz) and offset (w); inside is
    /// `n · p + w ≤ 0`. Rounded from the exact plane.
    pub fn face_planes(&self) -> &[DVec4] {
        &self.face_planes[..self.n_faces]
    }

    pub fn stats(&self) -> &FocusStats {
        &self.stats
    }

    /// The exact (unrounded) body behind the rounded one, for exact
    /// containment queries; `None` before the first successful computation.
    ///
    /// NOTE: this runs the exact engine again on the last inputs (and
    /// allocates): it is a verification tool, not part of a frame.
    pub fn exact(&self) -> Option<Box<Polytope>> {
        if !self.inputs_valid {
            return None;
        }
        let Inputs { view, light, spot_corners, scene } = self.inputs;
        let view = Frustum::from_corners(view).ok()?;
        let light = match light {
            LightInput::Directional(direction) => Light::Directional { direction },
            LightInput::Point(position) => Light::Point { position },
            LightInput::Spot(position) => Light::Spot { position, frustum: Frustum::from_corners(spot_corners).ok()? },
        };
        let mut work = Box::new(Polytope::from_aabb(&scene).ok()?);
        let mut plan = Box::new(Plan::new());
        match plan_into(&mut plan, &view, &light, &scene).ok()? {
            true => clip_exactly(&mut work, &mut plan, &view, &light).ok()?,
            false => work.make_empty(),
        }
        Some(work)
    }

    fn remember_inputs(&mut self, view: &Frustum, light: &Light, scene: &Aabb) {
        let inputs = &mut self.inputs;
        inputs.view = *view.corners();
        inputs.scene = *scene;
        inputs.light = match light {
            Light::Directional { direction } => LightInput::Directional(*direction),
            Light::Point { position } => LightInput::Point(*position),
            Light::Spot { position, frustum } => {
                inputs.spot_corners = *frustum.corners();
                LightInput::Spot(*position)
            }
        };
        self.inputs_valid = true;
    }

    /// The smallest box around the rounded vertices, `None` when empty.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::around(self.vertices())
    }

    /// Volume from the rounded vertices (0 unless solid).
    ///
    /// NOTE: computed on request (a few hundred flops) rather than with
    /// every body: fitting a shadow map never needs it.
    pub fn volume(&self) -> f64 {
        if self.dim != 3 || self.n_verts == 0 {
            return 0.0;
        }
        // NOTE: volume = Σ area_f · height_f / 3 with heights measured from a
        // vertex r of the body. For a convex body every height is ≥ 0, so the
        // sum has no cancellation; areas come from cross products of edges
        // local to each face. (Fanning signed tetrahedra from r instead cancels
        // catastrophically when the body has a vertex very far away.)
        let r = self.verts[0];
        let mut sum = 0.0;
        for (f, face) in self.faces().enumerate() {
            let n = self.face_planes[f].truncate();
            let q = self.verts[face[0] as usize];
            let mut area2 = glam::DVec3::ZERO;
            for k in 1..face.len() - 1 {
                let b = self.verts[face[k] as usize] - q;
                let c = self.verts[face[k + 1] as usize] - q;
                area2 += b.cross(c);
            }
            let height = n.dot(q - r);
            if height > 0.0 {
                // NOTE: past the f64 range the cross products overflow; an
                // overflowed area is +∞, never NaN (∞ − ∞).
                let area = area2.length();
                sum += 0.5 * if area.is_nan() { f64::INFINITY } else { area } * height;
            }
        }
        sum / 3.0
    }
}

/// Computes `H = hull(V ∪ {l}) ∩ S ∩ L` (see [`focus_body_into`]).
pub fn focus_body(view: &Frustum, light: &Light, scene: &Aabb) -> Result<Body, GeomError> {
    let mut b = Body::new();
    focus_body_into(&mut b, view, light, scene)?;
    Ok(b)
}

/// What the clipper is given: a box known to contain H, the halfspaces of
/// `hull(V ∪ {l})`, and those of a spot light's frustum.
#[derive(Clone)]
struct Plan {
    start: Aabb,
    scene_clip_skipped: bool,
    /// `hull(V ∪ {l})` by plane origins; its planes go into `hull` only for
    /// the exact engine (see [`clip_exactly`]).
    outline: HullOutline,
    hull: PlaneSet,
    /// A spot light's frustum planes, filled like `hull`.
    light_planes: PlaneSet,
}

impl Plan {
    fn new() -> Plan {
        Plan {
            start: Aabb { min: DVec3::ZERO, max: DVec3::ZERO },
            scene_clip_skipped: false,
            outline: HullOutline::new(),
            hull: PlaneSet::new(),
            light_planes: PlaneSet::new(),
        }
    }
}

/// Fills `plan`; `false` when H is certainly empty before any clipping.
///
/// NOTE: written in place: the plane sets are a few kilobytes each, and
/// returning them by value cost more than building them.
fn plan_into(plan: &mut Plan, view: &Frustum, light: &Light, scene: &Aabb) -> Result<bool, GeomError> {
    let Some((start, scene_clip_skipped)) = start_box(view, light, scene) else { return Ok(false) };
    view.hull_outline_into(light.apex(), &mut plan.outline)?;
    plan.start = start;
    // NOTE: a directional light's hull reaches past S whatever V does; a
    // point light's hull lies in S when V and the light do (convexity).
    plan.scene_clip_skipped = scene_clip_skipped && !matches!(light, Light::Directional { .. });
    Ok(true)
}

/// The exact engine: every decision exact, vertices kept unrounded.
fn clip_exactly(work: &mut Polytope, plan: &mut Plan, view: &Frustum, light: &Light) -> Result<(), GeomError> {
    view.hull_planes_into(light.apex(), &plan.outline, &mut plan.hull);
    work.reset_to_valid_aabb(&plan.start);
    work.clip_all(plan.hull.as_slice())?;
    if let Light::Spot { frustum, .. } = light {
        frustum.planes_into(&mut plan.light_planes);
        work.clip_all(plan.light_planes.as_slice())?;
    }
    Ok(())
}

/// The fast path (see [`crate::certified`]): `Uncertain` sends the case to
/// the exact engine. `light_first` clips a spot light's `L` before `S`.
fn clip_certified(fast: &mut CertifiedClipper, plan: &Plan, view: &Frustum, light: &Light, scene: &Aabb, light_first: bool) -> Step {
    let light_frustum = match light {
        Light::Spot { frustum, .. } => Some(frustum.corners()),
        _ => None,
    };
    let mut step = fast.reset_to_hull(view, light.apex(), &plan.outline, scene, light_frustum);
    let clip_scene = |fast: &mut CertifiedClipper, step: Step| {
        if step == Step::Nonempty && !plan.scene_clip_skipped {
            fast.clip_box(scene)
        } else {
            step
        }
    };
    if !light_first {
        step = clip_scene(fast, step);
    }
    if let (Step::Nonempty, Light::Spot { frustum, .. }) = (step, light) {
        step = fast.clip_frustum(frustum);
    }
    if light_first {
        step = clip_scene(fast, step);
    }
    step
}

/// The fast path's answer, written into `out`; `false` when it could not
/// prove one (see [`CertifiedClipper::write`]).
#[allow(clippy::too_many_arguments)]
fn answer_certified(
    fast: &mut CertifiedClipper,
    out: &mut Body,
    plan: &Plan,
    view: &Frustum,
    light: &Light,
    scene: &Aabb,
    light_first: bool,
    stats: &mut FocusStats,
) -> bool {
    let answered = match clip_certified(fast, plan, view, light, scene, light_first) {
        Step::Empty => {
            out.clear();
            stats.early_exit = true;
            true
        }
        Step::Nonempty => fast.write(out),
        Step::Uncertain => false,
    };
    stats.planes_cut = fast.cuts;
    stats.planes_cleared = fast.cleared;
    answered
}

/// Computes the focus body into a reusable `Body`, without allocating once
/// `out` has been used before.
///
/// Every case first runs a floating-point clipper whose every sign is
/// proven by an error bound, and whose output coordinates are proven within
/// [`crate::ROUNDING_ULPS`] of the exact ones (a vertex whose bound is
/// looser is placed from its planes' exact intersection); when a bound
/// cannot prove a decision (coincidences the construction does not explain,
/// such as a frustum corner in another face's plane, or near-degenerate
/// input) the case is computed again by the exact engine (a spot light is
/// first tried once more on the float path, with `L` clipped before `S`).
/// Both give the same exact body; [`FocusStats::float_path`] says which one
/// answered.
///
/// Work skipped when a case does not need it:
/// - `L` is clipped only for spot lights;
/// - for point and spot lights with `V ⊆ S` and `l ∈ S`, `hull(V ∪ {l}) ⊆ S`
///   by convexity, so `S` is not clipped (the exact engine starts from the
///   smaller box around `V ∪ {l}` instead);
/// - clipping stops as soon as the body is empty.
pub fn focus_body_into(out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
    compute(out, view, light, scene, true, true)
}

/// [`focus_body_into`] without the scene-clip skip, to measure what it
/// saves; the same body.
#[doc(hidden)]
pub fn focus_body_into_without_skip(out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
    compute(out, view, light, scene, true, false)
}

/// [`focus_body_into`] without the floating-point path: every case runs the
/// exact engine. The answer is the same; this is the reference the fast
/// path is tested against, and a baseline for benchmarks.
pub fn focus_body_exact_into(out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
    compute(out, view, light, scene, false, true)
}

fn compute(out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb, float_path: bool, skip: bool) -> Result<(), GeomError> {
    scene.validate()?;
    light.validate()?;
    out.inputs_valid = false;
    let mut stats = FocusStats { light_clip_skipped: !matches!(light, Light::Spot { .. }), ..FocusStats::default() };
    let mut plan = out.plan.take().unwrap_or_else(|| Box::new(Plan::new()));
    let nonempty = plan_into(&mut plan, view, light, scene);
    let result = match nonempty {
        Ok(true) => compute_planned(out, &mut plan, view, light, scene, float_path, skip, stats),
        Ok(false) => {
            // The box around what can cast into V misses S: H is empty.
            out.clear();
            stats.early_exit = true;
            stats.float_path = float_path;
            out.stats = stats;
            out.remember_inputs(view, light, scene);
            Ok(())
        }
        Err(e) => {
            out.clear();
            Err(e)
        }
    };
    out.plan = Some(plan);
    result
}

#[allow(clippy::too_many_arguments)]
fn compute_planned(
    out: &mut Body,
    plan: &mut Plan,
    view: &Frustum,
    light: &Light,
    scene: &Aabb,
    float_path: bool,
    skip: bool,
    mut stats: FocusStats,
) -> Result<(), GeomError> {
    plan.scene_clip_skipped &= skip;
    stats.scene_clip_skipped = plan.scene_clip_skipped;
    let light_faces = match light {
        Light::Spot { frustum, .. } => frustum.face_count(),
        _ => 0,
    };
    stats.planes_offered = (plan.outline.len() + light_faces) as u16;

    let mut answered = false;
    if float_path {
        let mut fast = out.fast.take().unwrap_or_else(|| Box::new(CertifiedClipper::new()));
        answered = answer_certified(&mut fast, out, plan, view, light, scene, false, &mut stats);
        // NOTE: S first is the faster order for most spot lights (S usually
        // cuts hull(V ∪ {l}) down before L's planes, all through the apex,
        // meet it). Where that order leaves a sign unproven, L first often
        // proves every one: a second float pass costs a few microseconds,
        // the exact engine a hundred or more.
        if !answered && matches!(light, Light::Spot { .. }) {
            answered = answer_certified(&mut fast, out, plan, view, light, scene, true, &mut stats);
            stats.light_clipped_first = answered;
        }
        if answered {
            stats.exact_evaluations = u32::from(fast.exact_vertices);
        }
        out.fast = Some(fast);
    }
    if answered {
        stats.float_path = true;
    } else {
        let mut work = out.work.take().unwrap_or_else(|| {
            let mut p = Box::new(Polytope::empty_with_capacity());
            p.reset_to_valid_aabb(&plan.start);
            p
        });
        if let Err(e) = clip_exactly(&mut work, plan, view, light) {
            out.work = Some(work);
            out.clear();
            return Err(e);
        }
        stats.early_exit |= work.is_empty();
        stats.planes_cut = work.plane_count().saturating_sub(6) as u16;
        stats.planes_cleared = 0;
        work.write_rounded(out);
        stats.exact_evaluations = work.exact_evaluations();
        out.work = Some(work);
    }
    out.stats = stats;
    out.remember_inputs(view, light, scene);
    Ok(())
}

/// An exact box containing H to start clipping from, and whether it makes
/// the clip by `S` unnecessary; `None` when H is certainly empty.
///
/// `hull(V ∪ {l})` lies in the box around V's corners and l. A directional
/// light sweeps V without end toward the light, so on each axis the box
/// extends to S's bound on the side the light comes from. The result is
/// intersected with S (and with the box around a spot light's frustum). All
/// bounds are input values, so the box is exact, and starting from it instead
/// of S avoids making vertices far outside hull(V ∪ {l}) that later clips
/// would only remove.
fn start_box(view: &Frustum, light: &Light, scene: &Aabb) -> Option<(Aabb, bool)> {
    let corners = view.corners();
    let mut b = Aabb::around(corners).expect("eight corners");
    match *light {
        Light::Directional { direction } => {
            for k in 0..3 {
                // The light lies at infinity along −direction.
                if direction[k] < 0.0 {
                    b.max[k] = b.max[k].max(scene.max[k]);
                } else if direction[k] > 0.0 {
                    b.min[k] = b.min[k].min(scene.min[k]);
                }
            }
        }
        Light::Point { position } | Light::Spot { position, .. } => {
            b.min = b.min.min(position);
            b.max = b.max.max(position);
        }
    }
    let inside_scene = b.min.cmpge(scene.min).all() && b.max.cmple(scene.max).all();
    let mut out = Aabb { min: b.min.max(scene.min), max: b.max.min(scene.max) };
    if let Light::Spot { frustum, .. } = light {
        let l = Aabb::around(frustum.corners()).expect("eight corners");
        out.min = out.min.max(l.min);
        out.max = out.max.min(l.max);
    }
    if out.min.cmple(out.max).all() {
        Some((out, inside_scene))
    } else {
        None
    }
}
