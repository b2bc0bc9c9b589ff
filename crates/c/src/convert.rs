//! From the C structs to the library's validated inputs, and from a fitted
//! map back to `SfMap`.

use crate::error::Failure;
use crate::types::*;
use glam::DVec3;
use shadowfocus_focus::{
    BoxFace, ClipConvention, DepthHintCoverage, DepthRange, DepthTest, FitState, FocusSettings, Footprint, Ground, LightNear,
    LispsmSettings, MapOrientation, MapSizes, Method, PointMode, PsmSettings, ReceiverBoxes, ShadowMap, SplitScheme, SplitSettings,
    TexelBudget, TsmSettings, UvOrigin, WarpDirection, WarpHold,
};
use shadowfocus_geom::{Aabb, Camera, Frustum, Light};
use std::ffi::c_int;

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// The camera (validated later, by the fit).
pub fn camera(c: &SfCamera) -> Camera {
    Camera { eye: v3(c.eye), forward: v3(c.forward), up: v3(c.up), fovy: c.fovy_rad, aspect: c.aspect, near: c.near_dist, far: c.far_dist }
}

/// A checked box.
pub fn aabb(b: &SfAabb) -> Result<Aabb, shadowfocus_geom::GeomError> {
    Aabb::new(v3(b.min), v3(b.max))
}

/// A checked light.
pub fn light(l: &SfLight) -> Result<Light, Failure> {
    let checked = match l.kind {
        k if k == SfLightKind::SF_LIGHT_DIRECTIONAL as c_int => Light::directional(v3(l.direction)),
        k if k == SfLightKind::SF_LIGHT_POINT as c_int => Light::point(v3(l.position)),
        k if k == SfLightKind::SF_LIGHT_SPOT as c_int => return spot(l),
        k => return Err(bad_enum("light.kind", k, "SfLightKind")),
    };
    checked.map_err(|e| Failure::geom(&e, "light"))
}

fn spot(l: &SfLight) -> Result<Light, Failure> {
    let frame = Camera {
        eye: v3(l.position),
        forward: v3(l.direction),
        up: v3(l.up),
        fovy: l.fovy_rad,
        aspect: l.aspect,
        near: l.near_dist,
        far: l.far_dist,
    };
    let frustum = Frustum::from_camera(&frame).map_err(|e| Failure::geom(&e, "spot light frustum (a camera at the light)"))?;
    Light::spot(frame.eye, frustum).map_err(|e| Failure::geom(&e, "light"))
}

fn bad_enum(field: &str, value: c_int, type_name: &str) -> Failure {
    Failure::invalid(format!("{field}: {value} is not an {type_name} value"))
}

/// The enum value of `value`, one of `values` (C's integer is the index).
fn pick<T: Copy>(value: c_int, values: &[T], field: &str, type_name: &str) -> Result<T, Failure> {
    usize::try_from(value).ok().and_then(|i| values.get(i).copied()).ok_or_else(|| bad_enum(field, value, type_name))
}

/// The grounds in `SfGround` order: none, then the faces.
fn grounds() -> [Option<BoxFace>; 7] {
    std::array::from_fn(|i| i.checked_sub(1).map(|k| BoxFace::ALL[k]))
}

/// The ground: its face (`SfGround`) and, where `ground_at_level` is set,
/// its level.
fn ground(s: &SfSettings) -> Result<Option<Ground>, Failure> {
    let face = pick(s.ground, &grounds(), "settings.ground", "SfGround")?;
    match (face, s.ground_at_level != 0) {
        (None, true) => Err(Failure::invalid("settings.ground_at_level: a ground level needs a ground face (settings.ground)")),
        (face, at_level) => Ok(face.map(|face| Ground { face, level: at_level.then_some(s.ground_level) })),
    }
}

/// `Some(v)` unless `v` is exactly 0 ("not set"); NaN and negatives are
/// passed on for the settings check to reject.
fn optional(v: f64) -> Option<f64> {
    (v != 0.0).then_some(v)
}

/// The settings, with every enum value checked (the ranges are checked by the fit).
///
/// # Safety
/// `s.receivers` is NULL or points to `s.receiver_count` boxes.
pub unsafe fn settings(s: &SfSettings) -> Result<FocusSettings, Failure> {
    // SAFETY: as the caller promises; NULL is refused unless the count is 0.
    let receivers = unsafe { receiver_boxes(s.receivers, s.receiver_count)? };
    let receivers = if s.receivers_seen != 0 { ReceiverBoxes::seen(receivers.as_slice())? } else { receivers };
    Ok(FocusSettings {
        method: method(s.method)?,
        splits: SplitSettings { count: s.splits as usize, scheme: scheme(s)?, delta_bias: s.delta_bias },
        resolution: s.resolution,
        stable: s.stable != 0,
        lispsm: LispsmSettings {
            visible_far: optional(s.lispsm_visible_far),
            warp: pick(
                s.lispsm_warp,
                &[WarpDirection::ViewProjected, WarpDirection::MiddleVector],
                "settings.lispsm_warp",
                "SfWarpDirection",
            )?,
        },
        psm: PsmSettings { near: optional(s.psm_near), far: optional(s.psm_far) },
        tsm: TsmSettings { focus: s.tsm_focus },
        point: pick(s.point_mode, &[PointMode::Single, PointMode::Cube], "settings.point_mode", "SfPointMode")?,
        light_near: match optional(s.light_near_fixed) {
            Some(r) => LightNear::Fixed(r),
            None => LightNear::Auto { fraction: s.light_near_fraction },
        },
        orientation: pick(
            s.orientation,
            &[MapOrientation::LeastArea, MapOrientation::ViewAligned],
            "settings.orientation",
            "SfOrientation",
        )?,
        warp_guard: s.warp_guard != 0,
        f32_origin: v3(s.f32_origin),
        clip: clip(s),
        depth_clamp: s.depth_clamp != 0,
        footprint: if s.receiver_footprint != 0 {
            Footprint::Receivers { margin_texels: s.receiver_margin_texels }
        } else {
            Footprint::Body
        },
        visible_depth: (s.visible_depth_min != 0.0 || s.visible_depth_max != 0.0).then_some([s.visible_depth_min, s.visible_depth_max]),
        visible_depth_coverage: if s.visible_depth_covers_view != 0 { DepthHintCoverage::View } else { DepthHintCoverage::Hint },
        receivers,
        ground: ground(s)?,
        texel_budget: match s.texel_budget {
            0 => None,
            texels => Some(TexelBudget {
                texels,
                sizes: pick(s.budget_sizes, &[MapSizes::PowerOfTwo, MapSizes::Any], "settings.budget_sizes", "SfMapSizes")?,
            }),
        },
    })
}

/// The receiver boxes at `p`, checked.
///
/// # Safety
/// `p` is NULL or points to `n` boxes.
unsafe fn receiver_boxes(p: *const SfAabb, n: u32) -> Result<ReceiverBoxes, Failure> {
    if n == 0 {
        return Ok(ReceiverBoxes::NONE);
    }
    if p.is_null() {
        return Err(Failure::null("settings.receivers"));
    }
    // SAFETY: non-NULL and `n` boxes long (caller).
    let boxes = unsafe { std::slice::from_raw_parts(p, n as usize) };
    Ok(ReceiverBoxes::from_boxes(boxes.iter().map(|b| Aabb { min: v3(b.min), max: v3(b.max) }))?)
}

const METHODS: [Method; 5] = [Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm, Method::Auto];

fn method(m: c_int) -> Result<Method, Failure> {
    pick(m, &METHODS, "settings.method", "SfMethod")
}

fn scheme(s: &SfSettings) -> Result<SplitScheme, Failure> {
    let schemes = [
        SplitScheme::Uniform,
        SplitScheme::Log,
        SplitScheme::Practical { lambda: s.lambda },
        SplitScheme::Geometric { first: s.first_split },
        SplitScheme::Optimal,
    ];
    pick(s.split_scheme, &schemes, "settings.split_scheme", "SfSplitScheme")
}

/// The clip convention of the settings (every combination is valid).
fn clip(s: &SfSettings) -> ClipConvention {
    ClipConvention {
        depth: if s.depth_zero_to_one != 0 { DepthRange::ZeroToOne } else { DepthRange::MinusOneToOne },
        reversed_z: s.reversed_z != 0,
        uv_origin: if s.uv_origin_top_left != 0 { UvOrigin::TopLeft } else { UvOrigin::BottomLeft },
        y_down: s.clip_y_down != 0,
    }
}

/// The C settings that give `FocusSettings::default()`.
pub fn default_settings() -> SfSettings {
    let d = FocusSettings::default();
    let (mut lambda, mut first_split) = (0.5, 0.0);
    let split_scheme = match d.splits.scheme {
        SplitScheme::Uniform => SfSplitScheme::SF_SPLIT_UNIFORM,
        SplitScheme::Log => SfSplitScheme::SF_SPLIT_LOG,
        SplitScheme::Practical { lambda: l } => {
            lambda = l;
            SfSplitScheme::SF_SPLIT_PRACTICAL
        }
        SplitScheme::Geometric { first } => {
            first_split = first;
            SfSplitScheme::SF_SPLIT_GEOMETRIC
        }
        SplitScheme::Optimal => SfSplitScheme::SF_SPLIT_OPTIMAL,
    };
    let (light_near_fraction, light_near_fixed) = match d.light_near {
        LightNear::Auto { fraction } => (fraction, 0.0),
        LightNear::Fixed(r) => (LightNear::DEFAULT_FRACTION, r),
    };
    SfSettings {
        method: method_index(d.method),
        splits: d.splits.count as u32,
        split_scheme: split_scheme as c_int,
        lambda,
        first_split,
        delta_bias: d.splits.delta_bias,
        resolution: d.resolution,
        stable: d.stable.into(),
        depth_zero_to_one: (d.clip.depth == DepthRange::ZeroToOne).into(),
        reversed_z: d.clip.reversed_z.into(),
        uv_origin_top_left: (d.clip.uv_origin == UvOrigin::TopLeft).into(),
        clip_y_down: d.clip.y_down.into(),
        lispsm_visible_far: d.lispsm.visible_far.unwrap_or(0.0),
        lispsm_warp: (d.lispsm.warp == WarpDirection::MiddleVector).into(),
        psm_near: d.psm.near.unwrap_or(0.0),
        psm_far: d.psm.far.unwrap_or(0.0),
        tsm_focus: d.tsm.focus,
        point_mode: (d.point == PointMode::Cube).into(),
        light_near_fraction,
        light_near_fixed,
        orientation: (d.orientation == MapOrientation::ViewAligned).into(),
        warp_guard: d.warp_guard.into(),
        f32_origin: d.f32_origin.to_array(),
        depth_clamp: d.depth_clamp.into(),
        receiver_footprint: (d.footprint != Footprint::Body).into(),
        receiver_margin_texels: match d.footprint {
            Footprint::Receivers { margin_texels } => margin_texels,
            Footprint::Body => Footprint::DEFAULT_MARGIN_TEXELS,
        },
        visible_depth_min: d.visible_depth.map_or(0.0, |r| r[0]),
        visible_depth_max: d.visible_depth.map_or(0.0, |r| r[1]),
        visible_depth_covers_view: (d.visible_depth_coverage == DepthHintCoverage::View).into(),
        receivers: std::ptr::null(),
        receiver_count: 0,
        receivers_seen: 0,
        ground: d.ground.map_or(0, |g| g.face.index() as c_int + 1),
        ground_at_level: d.ground.is_some_and(|g| g.level.is_some()).into(),
        ground_level: d.ground.and_then(|g| g.level).unwrap_or(0.0),
        texel_budget: d.texel_budget.map_or(0, |b| b.texels),
        budget_sizes: (d.texel_budget.is_some_and(|b| b.sizes == MapSizes::Any)).into(),
    }
}

fn method_index(m: Method) -> c_int {
    METHODS.iter().position(|x| *x == m).unwrap_or(0) as c_int
}

/// The C view of a fitted map.
// NOTE: the only place that reads a map's fitted fields.
pub fn map(m: &ShadowMap) -> SfMap {
    let f = &m.fit;
    let (view, projection) = m.light_view_and_projection();
    SfMap {
        active: m.is_active().into(),
        depth_greater: (f.depth_test == DepthTest::Greater).into(),
        split: m.split_range,
        clip_from_world: f.clip_from_world.to_cols_array(),
        clip_from_world_f32: f.clip_from_world_f32.to_cols_array(),
        uv_from_world: f.uv_from_world().to_cols_array(),
        uv_from_world_f32: f.uv_from_world_f32().to_cols_array(),
        light_view: view.to_cols_array(),
        light_projection: projection.to_cols_array(),
        inverted: f.inverted().into(),
        texel_size: f.texel_size,
        method: method_index(f.method),
        split_index: m.split as u32,
        cube_face: m.face.map_or(-1, |f| f as c_int),
        f32_exact: f.f32_exact.into(),
        warp_near: f.warp_near,
        psm_shift: f.psm_shift,
        light_near: m.light_near,
        notes: m.notes().0,
        skipped: m.skipped().0,
        body_vertex_count: m.body().vertices().len() as u32,
        depth_clamp: f.depth_clamp.into(),
        receiver_footprint: (f.footprint != Footprint::Body).into(),
        resolution: f.resolution,
    }
}

/// The library's state from a C `SfFitState`.
pub(crate) fn load_state(s: &SfFitState) -> FitState {
    let warps = s.warps.map(|w| WarpHold { direction: w.direction, strength: w.strength, extent: w.extent, apex: w.apex });
    FitState::from_parts(s.steps, warps)
}

/// Writes the library's state into a C `SfFitState`.
pub(crate) fn store_state(dst: &mut SfFitState, s: &FitState) {
    dst.steps = s.to_steps();
    dst.warps = s.to_warps().map(|w| SfWarpHold { direction: w.direction, strength: w.strength, extent: w.extent, apex: w.apex });
}
