//! The two engines behind a focus body and the [`Focuser`] that runs them.
//!
//! Every case first runs the certified floating-point clipper
//! ([`float`]); whatever it cannot prove goes to the exact engine
//! ([`exact`]). Both start from the same [`plan`].

pub(crate) mod exact;
pub(crate) mod float;
pub(crate) mod plan;

use crate::body::{Body, FocusStats};
use crate::error::GeomError;
use crate::input::aabb::Aabb;
use crate::input::frustum::Frustum;
use crate::input::light::Light;
use exact::Polytope;
use float::{CertifiedClipper, Step};
use plan::{plan_into, Plan};

/// The work space of focus-body computations: the plan and both engines'
/// scratch memory, allocated on first use and kept, so that computing into
/// a reused [`Body`] with a reused `Focuser` allocates nothing.
///
/// One `Focuser` serves any number of bodies (the output is the [`Body`]
/// passed in, a plain value); keep one per thread.
#[derive(Clone, Default)]
pub struct Focuser {
    plan: Option<Box<Plan>>,
    float: Option<Box<CertifiedClipper>>,
    exact: Option<Box<Polytope>>,
}

impl std::fmt::Debug for Focuser {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Focuser").field("allocated", &self.plan.is_some()).finish()
    }
}

/// Which engines a computation may use.
#[derive(Clone, Copy)]
struct Route {
    /// Try the certified float path first.
    float_path: bool,
    /// Skip the clip by `S` where `hull(V ∪ {l}) ⊆ S`.
    skip: bool,
}

impl Focuser {
    /// A focuser that has allocated nothing yet.
    pub fn new() -> Focuser {
        Focuser::default()
    }

    /// Computes the focus body `H = hull(V ∪ {l}) ∩ S ∩ L` into `out`.
    ///
    /// Every case first runs a floating-point clipper whose every sign is
    /// proven by an error bound, and whose output coordinates are proven
    /// within [`crate::ROUNDING_ULPS`] of the exact ones (a vertex whose
    /// bound is looser is placed from its planes' exact intersection); when
    /// a bound cannot prove a decision (coincidences the construction does
    /// not explain, such as a frustum corner in another face's plane, or
    /// near-degenerate input) the case is computed again by the exact
    /// engine (a spot light is first tried once more on the float path,
    /// with `L` clipped before `S`). Both give the same exact body;
    /// [`FocusStats::float_path`] says which one answered.
    ///
    /// Work skipped when a case does not need it:
    /// - `L` is clipped only for spot lights;
    /// - for point and spot lights with `V ⊆ S` and `l ∈ S`,
    ///   `hull(V ∪ {l}) ⊆ S` by convexity, so `S` is not clipped (the exact
    ///   engine starts from the smaller box around `V ∪ {l}` instead);
    /// - clipping stops as soon as the body is empty.
    pub fn focus_into(&mut self, out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
        self.compute(out, view, light, scene, Route { float_path: true, skip: true })
    }

    /// [`Focuser::focus_into`] without the floating-point path: every case
    /// runs the exact engine. The answer is the same; this is the reference
    /// the fast path is tested against, and a baseline for benchmarks.
    pub fn focus_exact_into(&mut self, out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
        self.compute(out, view, light, scene, Route { float_path: false, skip: true })
    }

    /// [`Focuser::focus_into`] without the scene-clip skip, to measure what
    /// it saves; the same body.
    #[doc(hidden)]
    pub fn focus_into_without_skip(&mut self, out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb) -> Result<(), GeomError> {
        self.compute(out, view, light, scene, Route { float_path: true, skip: false })
    }

    fn compute(&mut self, out: &mut Body, view: &Frustum, light: &Light, scene: &Aabb, route: Route) -> Result<(), GeomError> {
        scene.validate()?;
        light.validate()?;
        out.inputs_valid = false;
        let mut stats = FocusStats { light_clip_skipped: !matches!(light, Light::Spot { .. }), ..FocusStats::default() };
        let plan = self.plan.get_or_insert_with(|| Box::new(Plan::new()));
        match plan_into(plan, view, light, scene) {
            Ok(true) => self.compute_planned(out, view, light, scene, route, stats),
            Ok(false) => {
                // The box around what can cast into V misses S: H is empty.
                out.clear();
                stats.early_exit = true;
                stats.float_path = route.float_path;
                out.stats = stats;
                out.record_inputs(view, light, scene);
                Ok(())
            }
            Err(e) => {
                out.clear();
                Err(e)
            }
        }
    }

    fn compute_planned(
        &mut self,
        out: &mut Body,
        view: &Frustum,
        light: &Light,
        scene: &Aabb,
        route: Route,
        mut stats: FocusStats,
    ) -> Result<(), GeomError> {
        let plan = self.plan.as_deref_mut().expect("planned");
        plan.scene_clip_skipped &= route.skip;
        stats.scene_clip_skipped = plan.scene_clip_skipped;
        let light_faces = match light {
            Light::Spot { frustum, .. } => frustum.face_count(),
            _ => 0,
        };
        stats.planes_offered = (plan.outline.len() + light_faces) as u16;

        let mut answered = false;
        if route.float_path {
            let fast = self.float.get_or_insert_with(|| Box::new(CertifiedClipper::new()));
            answered = answer_certified(fast, out, plan, view, light, scene, false, &mut stats);
            // NOTE: S first is the faster order for most spot lights (S usually
            // cuts hull(V ∪ {l}) down before L's planes, all through the apex,
            // meet it). Where that order leaves a sign unproven, L first often
            // proves every one: a second float pass costs a few microseconds,
            // the exact engine a hundred or more.
            if !answered && matches!(light, Light::Spot { .. }) {
                answered = answer_certified(fast, out, plan, view, light, scene, true, &mut stats);
                stats.light_clipped_first = answered;
            }
            if answered {
                stats.exact_evaluations = u32::from(fast.exact_vertices);
            }
        }
        if answered {
            stats.float_path = true;
        } else {
            let work = self.exact.get_or_insert_with(|| {
                let mut p = Box::new(Polytope::empty_with_capacity());
                p.reset_to_valid_aabb(&plan.start);
                p
            });
            if let Err(e) = clip_exactly(work, plan, view, light) {
                out.clear();
                return Err(e);
            }
            stats.early_exit |= work.is_empty();
            stats.planes_cut = work.plane_count().saturating_sub(6) as u16;
            stats.planes_cleared = 0;
            work.write_rounded(out);
            stats.exact_evaluations = work.exact_evaluations();
        }
        out.stats = stats;
        out.record_inputs(view, light, scene);
        Ok(())
    }
}

/// Computes `H = hull(V ∪ {l}) ∩ S ∩ L` into a new [`Body`] with a new
/// [`Focuser`] (see [`Focuser::focus_into`]). It allocates both: per frame,
/// keep a `Focuser` and a `Body` and call [`Focuser::focus_into`].
pub fn focus_body(view: &Frustum, light: &Light, scene: &Aabb) -> Result<Body, GeomError> {
    let mut body = Body::new();
    Focuser::new().focus_into(&mut body, view, light, scene)?;
    Ok(body)
}

impl Body {
    /// The exact (unrounded) body behind the rounded one, for exact
    /// containment queries; `None` before the first successful computation.
    ///
    /// NOTE: this runs the exact engine again on the last inputs (and
    /// allocates): it is a verification tool, not part of a frame.
    pub fn exact(&self) -> Option<Box<Polytope>> {
        if !self.inputs_valid {
            return None;
        }
        let (view, light, scene) = self.inputs.rebuild()?;
        let mut work = Box::new(Polytope::from_aabb(&scene).ok()?);
        let mut plan = Box::new(Plan::new());
        match plan_into(&mut plan, &view, &light, &scene).ok()? {
            true => clip_exactly(&mut work, &mut plan, &view, &light).ok()?,
            false => work.make_empty(),
        }
        Some(work)
    }
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

/// The fast path (see [`float`]): `Uncertain` sends the case to the exact
/// engine. `light_first` clips a spot light's `L` before `S`.
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
