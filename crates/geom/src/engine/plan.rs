//! What the engines are given: a box known to contain `H` to start from,
//! and the halfspaces of `hull(V ∪ {l})` and of a spot light's `L`.

use crate::error::GeomError;
use crate::input::aabb::Aabb;
use crate::input::frustum::{Frustum, HullOutline, PlaneSet};
use crate::input::light::Light;
use glam::DVec3;

/// What the clipper is given: a box known to contain H, the halfspaces of
/// `hull(V ∪ {l})`, and those of a spot light's frustum.
#[derive(Clone)]
pub(crate) struct Plan {
    pub(crate) start: Aabb,
    pub(crate) scene_clip_skipped: bool,
    /// `hull(V ∪ {l})` by plane origins; its planes go into `hull` only for
    /// the exact engine.
    pub(crate) outline: HullOutline,
    pub(crate) hull: PlaneSet,
    /// A spot light's frustum planes, filled like `hull`.
    pub(crate) light_planes: PlaneSet,
}

impl Plan {
    pub(crate) fn new() -> Plan {
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
pub(crate) fn plan_into(plan: &mut Plan, view: &Frustum, light: &Light, scene: &Aabb) -> Result<bool, GeomError> {
    let Some((start, scene_clip_skipped)) = start_box(view, light, scene) else { return Ok(false) };
    view.hull_outline_into(light.apex(), &mut plan.outline)?;
    plan.start = start;
    // NOTE: a directional light's hull reaches past S whatever V does; a
    // point light's hull lies in S when V and the light do (convexity).
    plan.scene_clip_skipped = scene_clip_skipped && !matches!(light, Light::Directional { .. });
    Ok(true)
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
