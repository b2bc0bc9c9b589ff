//! One frame: splits, bodies, maps, plan.

use crate::budget::share_texels;
use crate::cone::{cone_axis, turn_into_cone, CONE_MARGIN};
use crate::error::FocusError;
use crate::frame::{perpendicular_hint, tangent_frame};
use crate::methods::{fit_body, light_point, Fitted, SplitView};
use crate::placement::{self, Planes};
use crate::project::{f32_matrix, texel_size};
use crate::receiver_rays::ReceiverModel;
use crate::receivers::fit_receivers;
use crate::result::{CubeFace, FocusResult, MapFit, MapState, Notes, ShadowMap, Skipped};
use crate::settings::{FocusSettings, Footprint, Ground, Method, PointMode, SplitScheme};
use crate::state::{FitState, Held};
use crate::view::PreparedView;
use crate::view_aliasing::{receiver_aliasing, ReceiverRays};
use glam::DVec3;
use shadowfocus_geom::{Aabb, Body, Camera, Focuser, Frustum, Light, MAX_VERTICES, ROUNDING_ULPS};

/// Fits the shadow maps of one frame into `out` (no allocation).
///
/// For each split `[C_i, C_{i+1}]` of the view depth range, the split's
/// sub-frustum is built from `camera` with that near and far, its focus body
/// `H_i = hull(V_i ∪ l) ∩ S ∩ L` is computed exactly, and the configured
/// method fits a map to it (six maps for an omnidirectional point light).
/// `out` then holds the maps, the split planes and the plan.
///
/// For several lights seen by one camera, [`PreparedView`] and
/// [`fit_prepared`] give the same maps with the camera's work done once.
pub fn fit(camera: &Camera, light: &Light, scene: &Aabb, settings: &FocusSettings, out: &mut FocusResult) -> Result<(), FocusError> {
    out.clear();
    let mut view = PreparedView::unprepared(camera, settings);
    view.prepare(camera, settings)?;
    fit_prepared(&view, light, scene, out)
}

/// [`fit`] for a view prepared by [`PreparedView::new`] or
/// [`PreparedView::prepare`]: the same maps, bit for bit, as `fit` with that
/// view's camera and settings, without building and validating the split
/// frusta again (no allocation).
///
/// ```
/// use glam::DVec3;
/// use shadowfocus_focus::{fit_prepared, FocusResult, FocusSettings, PreparedView};
/// use shadowfocus_geom::{Aabb, Camera, Light};
///
/// let camera = Camera { eye: DVec3::new(0.0, 2.0, 10.0), forward: DVec3::NEG_Z, up: DVec3::Y, fovy: 1.0, aspect: 1.5, near: 0.5, far: 100.0 };
/// let scene = Aabb::new(DVec3::new(-50.0, 0.0, -100.0), DVec3::new(50.0, 20.0, 20.0))?;
/// let lights = [Light::directional(DVec3::new(0.3, -1.0, 0.2))?, Light::point(DVec3::new(10.0, 15.0, -20.0))?];
/// let settings = FocusSettings::default();
///
/// // Once: a view and one result per light.
/// let mut view = PreparedView::new(&camera, &settings)?;
/// let mut results = [FocusResult::new(), FocusResult::new()];
/// // Every frame: the camera's work once, then each light.
/// view.prepare(&camera, &settings)?;
/// for (light, out) in lights.iter().zip(&mut results) {
///     fit_prepared(&view, light, &scene, out)?;
/// }
/// assert!(results.iter().all(|r| r.maps().iter().any(|m| m.is_active())));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fit_prepared(view: &PreparedView, light: &Light, scene: &Aabb, out: &mut FocusResult) -> Result<(), FocusError> {
    out.hold(&FitState::default());
    fit_held(view, light, scene, out)
}

/// [`fit_prepared`] for stable maps that hold still over a camera path:
/// `state` carries each stable spot map's extent step and each stable
/// warped map's lattice steps from the previous frame, and is updated with
/// this frame's (see [`FitState`]). Other maps,
/// and fits without `stable`, are [`fit_prepared`]'s bit for bit. On an
/// error `state` is cleared, so the next frame starts afresh.
pub fn fit_prepared_with_state(
    view: &PreparedView,
    light: &Light,
    scene: &Aabb,
    state: &mut FitState,
    out: &mut FocusResult,
) -> Result<(), FocusError> {
    out.hold(state);
    let fitted = fit_held(view, light, scene, out);
    *state = if fitted.is_ok() { out.chosen() } else { FitState::default() };
    fitted
}

/// The fit, holding the steps already set in `out`.
fn fit_held(view: &PreparedView, light: &Light, scene: &Aabb, out: &mut FocusResult) -> Result<(), FocusError> {
    out.clear();
    if let Some(e) = &view.failed {
        return Err(e.clone());
    }
    let scene = Aabb::new(scene.min, scene.max)?;
    light.validate()?;
    check_ground(view.settings.ground, &scene)?;
    let optimal = view.settings.splits.scheme == SplitScheme::Optimal && view.splits > 1;
    // The receivers the prediction samples, found once for every use below.
    let rays = (optimal || view.settings.texel_budget.is_some()).then(|| {
        let model = ReceiverModel::new(&scene, &view.settings.receivers, view.settings.ground);
        ReceiverRays::new(&view.whole, [view.camera.near, view.camera.far], &view.basis, light, model)
    });
    match &rays {
        Some(rays) if optimal => {
            let mut planes = view.placement_start();
            let rounds = match view.settings.method {
                Method::Auto => placement::AUTO_PLACEMENT_ROUNDS,
                _ => placement::PLACEMENT_ROUNDS,
            };
            placement::place(&mut planes, rays.nearest(), view.splits, rounds, |planes| {
                out.clear();
                fit_splits(out, view, planes, light, &scene)?;
                Ok(receiver_aliasing(out.maps(), out.split_depths(), rays).map(|a| a.map(|a| a.max)))
            })?;
        }
        _ => fit_splits(out, view, &view.depths, light, &scene)?,
    }
    if view.settings.depth_clamp || view.settings.footprint != Footprint::Body {
        fit_receivers(out, view, &scene)?;
    }
    if let (Some(rays), Some(budget)) = (&rays, view.settings.texel_budget) {
        share_texels(out, view, rays, budget)?;
    }
    plan(out, &view.settings, light, &scene);
    Ok(())
}

/// A ground level must lie in the scene box: one outside it is a ground
/// the scene does not have (often an axis mixed up).
fn check_ground(ground: Option<Ground>, scene: &Aabb) -> Result<(), FocusError> {
    match ground {
        Some(Ground { face, level: Some(l) }) if !(l >= scene.min[face.axis()] && l <= scene.max[face.axis()]) => {
            Err(FocusError::InvalidSettings { what: "ground.level", reason: "must lie in the scene box along the ground face's axis" })
        }
        _ => Ok(()),
    }
}

/// Every split's maps for the planes `depths`: the view's own frusta where
/// the planes are the view's, frusta cut anew where they are not.
fn fit_splits(out: &mut FocusResult, view: &PreparedView, placed: &Planes, light: &Light, scene: &Aabb) -> Result<(), FocusError> {
    let depths = &view.covered(placed);
    out.set_splits(depths, view.splits, view.settings.clip);
    let ground = ReceiverModel::new(scene, &view.settings.receivers, view.settings.ground).ground();
    for i in 0..view.splits {
        let range = [depths[i], depths[i + 1]];
        let mut cut = None;
        let Some(frustum) = view.frustum_in(i, range, &mut cut)? else {
            empty_split(out, &view.settings, light, i, range)?;
            continue;
        };
        let sub = Camera { near: range[0], far: range[1], ..view.camera };
        fit_split(out, &SplitView { camera: &sub, basis: view.basis, settings: &view.settings, ground }, frustum, light, scene, i)?;
    }
    Ok(())
}

/// [`fit`] for a view given as a frustum: the maps of
/// [`PreparedView::prepare_frustum`] and [`fit_prepared`], whose bodies are
/// computed from `view` itself (for corner input, pass the camera
/// [`crate::camera_from_corners`] recovers: it chooses the
/// parameterisation and the split depths, never the body).
///
/// NOTE: the view is built on the stack (about 7 KiB) for each call; an
/// engine fitting every frame keeps a [`PreparedView`] instead.
pub fn fit_frustum(
    view: &Frustum,
    camera: &Camera,
    light: &Light,
    scene: &Aabb,
    settings: &FocusSettings,
    out: &mut FocusResult,
) -> Result<(), FocusError> {
    out.clear();
    let mut pv = PreparedView::unprepared(camera, settings);
    pv.prepare_frustum(view, camera, settings)?;
    fit_prepared(&pv, light, scene, out)
}

/// A split emptied by δ_bias: no depth, hence no body and no map.
fn empty_split(out: &mut FocusResult, settings: &FocusSettings, light: &Light, split: usize, range: [f64; 2]) -> Result<(), FocusError> {
    let (map, _) = push(out)?;
    map.split = split;
    map.face = None;
    map.split_range = range;
    set_light(&mut map.light, light);
    map.fit = MapFit::empty(settings.method, settings.clip);
    map.body_valid = false;
    Ok(())
}

/// The maps of one split whose frustum is `view`.
fn fit_split(out: &mut FocusResult, sv: &SplitView, view: &Frustum, light: &Light, scene: &Aabb, split: usize) -> Result<(), FocusError> {
    match *light {
        Light::Point { position } => point_maps(out, sv, view, position, scene, split),
        _ => {
            let (map, focuser) = push(out)?;
            begin(map, sv, split, None, light);
            focuser.focus_into(&mut map.body, view, light, scene)?;
            map.body_valid = true;
            if !finish(map, sv) {
                return Err(FocusError::NoSingleProjection {
                    reason: "the light's apex is not outside the body (a spot position inconsistent with its frustum?)",
                });
            }
            Ok(())
        }
    }
}

fn push(out: &mut FocusResult) -> Result<(&mut ShadowMap, &mut Focuser), FocusError> {
    out.push().ok_or(FocusError::Capacity { what: "shadow maps" })
}

fn begin(map: &mut ShadowMap, sv: &SplitView, split: usize, face: Option<CubeFace>, light: &Light) {
    map.split = split;
    map.face = face;
    map.split_range = [sv.camera.near, sv.camera.far];
    set_light(&mut map.light, light);
    map.fit = MapFit::empty(sv.settings.method, sv.settings.clip);
    // Nothing is left out near a directional or spot light (a spot's own
    // near plane is part of L); `point_maps` sets a point light's r.
    map.light_near = 0.0;
    map.notes = Notes(0);
    map.skipped = Skipped(0);
}

/// `*dst = *src`, writing only the fields of `src`'s kind.
///
/// NOTE: a plain assignment copies a whole `Light`, the size of a spot
/// light's validated frustum (~900 bytes), even for a directional light.
fn set_light(dst: &mut Light, src: &Light) {
    match *src {
        Light::Directional { direction } => *dst = Light::Directional { direction },
        Light::Point { position } => *dst = Light::Point { position },
        Light::Spot { .. } => *dst = *src,
    }
}

/// Fits the map's (already computed) body; `false` if no single projection
/// from the map's light can see it.
fn finish(map: &mut ShadowMap, sv: &SplitView) -> bool {
    if map.body.is_empty() {
        map.set_empty();
        return true;
    }
    let Some(f) = fit_body(sv, &map.light, &map.body, &map.hold) else { return false };
    store(map, sv, &f);
    true
}

fn store(map: &mut ShadowMap, sv: &SplitView, f: &Fitted) {
    map.fit = map_fit(sv, &map.light, f);
    let mut notes = Notes(0);
    for (set, note) in
        [(f.psm_fell_back, Notes::PSM_FELL_BACK), (f.stable_ignored, Notes::STABLE_IGNORED), (f.warp_limited, Notes::WARP_LIMITED)]
    {
        if set {
            notes.insert(note);
        }
    }
    map.notes = notes;
    map.chosen = f.held;
    let warped = matches!(sv.settings.method, Method::Lispsm | Method::Tsm);
    map.skipped = if f.warp_vanished && warped { Skipped::WARP } else { Skipped(0) };
}

fn map_fit(sv: &SplitView, light: &Light, f: &Fitted) -> MapFit {
    let lp = light_point(light);
    let res = sv.settings.resolution;
    let (eye, fwd) = (sv.camera.eye, sv.basis.forward);
    MapFit {
        state: MapState::Active,
        clip_from_world: f.m,
        clip_from_world_f32: f32_matrix(&f.m, sv.settings.f32_origin),
        f32_exact: f.f32_exact,
        depth_test: sv.settings.clip.depth_test(f.inverted),
        texel_size: [texel_size(&f.m, lp, eye + fwd * sv.camera.near, res), texel_size(&f.m, lp, eye + fwd * sv.camera.far, res)],
        resolution: res,
        method: f.method,
        warp_near: f.warp_near,
        psm_shift: f.psm_shift,
        clip: sv.settings.clip,
        depth_clamp: false,
        footprint: Footprint::Body,
    }
}

/// Fits one map to a body the caller computed (for engines with their own
/// bodies, and to time the fitting alone). `camera` is the split's camera
/// (its near and far are the split range); `settings.splits` is ignored. A
/// point light must not lie in the body (pass the spot that truncates it).
pub fn fit_map(camera: &Camera, light: &Light, body: &Body, settings: &FocusSettings) -> Result<MapFit, FocusError> {
    settings.validate()?;
    let no_box = "fit_map has no scene box to find the receivers in (fit, fit_prepared and fit_frustum have)";
    if settings.depth_clamp {
        return Err(FocusError::InvalidSettings { what: "depth_clamp", reason: no_box });
    }
    if settings.footprint != Footprint::Body {
        return Err(FocusError::InvalidSettings { what: "footprint", reason: no_box });
    }
    let basis = camera.basis()?;
    if body.is_empty() {
        return Ok(MapFit::empty(settings.method, settings.clip));
    }
    // NOTE: without a scene box, the body's bounds stand for it: its face
    // on the ground's side is the ground where the body reaches down to it.
    let ground = body.bounds().and_then(|b| ReceiverModel::new(&b, &settings.receivers, settings.ground).ground());
    let sv = SplitView { camera, basis, settings, ground };
    let f = fit_body(&sv, light, body, &Held::NONE)
        .ok_or(FocusError::NoSingleProjection { reason: "the light lies in the body or sees it over a half-space" })?;
    Ok(map_fit(&sv, light, &f))
}

/// The light's reach over a split: the largest max-norm distance from `l`
/// to a corner of the split's frustum, or of the scene box where that is
/// smaller. `H_i ⊆ hull(V_i ∪ l) ∩ S` lies within it (max norm).
fn light_reach(view: &Frustum, l: DVec3, scene: &Aabb) -> f64 {
    let from_l = |c: DVec3| (c - l).abs().max_element();
    let v = view.corners().iter().map(|c| from_l(*c)).fold(0.0, f64::max);
    let s = (0..8).map(|k| from_l(scene.corner(k))).fold(0.0, f64::max);
    v.min(s)
}

/// Largest absolute coordinate of the inputs of a split's body (the
/// magnitude its rounding bound is relative to).
fn input_magnitude(view: &Frustum, l: DVec3, scene: &Aabb) -> f64 {
    let m = view.corners().iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
    m.max(l.abs().max_element()).max(scene.min.abs().max_element()).max(scene.max.abs().max_element())
}

/// A point light: one perspective map toward the view, or six cube faces.
///
/// Guarantee (see [`crate::LightNear`]): every point of the split's body
/// `H_i` farther than `r` from the light lies in some active map of the
/// split, `r` being each map's `light_near` (0 where the map leaves nothing
/// out: a single map of a light outside the scene box).
fn point_maps(out: &mut FocusResult, sv: &SplitView, view: &Frustum, l: DVec3, scene: &Aabb, split: usize) -> Result<(), FocusError> {
    let r = sv.settings.light_near.radius(light_reach(view, l, scene));
    // NOTE: a stable map needs a frame fixed in the world; a single map's
    // axis follows the body, the cube's faces do not.
    if sv.settings.point == PointMode::Cube || sv.settings.stable_applies() {
        return cube_faces(out, sv, view, l, scene, split, r);
    }
    let light = Light::Point { position: l };
    let (map, focuser) = push(out)?;
    begin(map, sv, split, None, &light);
    focuser.focus_into(&mut map.body, view, &light, scene)?;
    map.body_valid = true;
    if map.body.is_empty() {
        map.set_empty();
        return Ok(());
    }
    if scene.contains(l) {
        // l ∈ hull(V ∪ l) ∩ S = H: no perspective map contains its own
        // centre. Cut H near the light along an axis that sees all of H's
        // other points, as a spot light, and map the rest.
        map.light_near = r;
        match truncation_frustum(sv, &map.body, l, r, input_magnitude(view, l, scene))? {
            Truncation::Frustum(fr) => {
                let spot = Light::spot(l, fr)?;
                map.light = spot;
                focuser.focus_into(&mut map.body, view, &spot, scene)?;
                if finish(map, sv) {
                    return Ok(());
                }
            }
            Truncation::AllNear => {
                map.set_empty();
                return Ok(());
            }
            Truncation::NoCone => {}
        }
    } else if finish(map, sv) && !wider_than_a_face(map, sv, l) {
        return Ok(());
    }
    // The light is inside the view frustum (or sees H over more than a
    // half-space, or over a cone wider than a cube face's): six faces.
    out.pop();
    out.notes.insert(Notes::POINT_AS_CUBE);
    cube_faces(out, sv, view, l, scene, split, r)
}

/// Whether the single map of a point light at `l` sees its body over a cone
/// wider than a cube face's: the narrowest cone from `l` around the body
/// (about its maximin axis, see [`cone_axis`]) has a vertex farther
/// than `√2`, the tangent of a face's corner, off its axis. Then six faces
/// sample it better: a light just outside the scene box, above a wide view,
/// would otherwise get one map spanning nearly a half-space, at hundreds of
/// screen pixels per texel. PSM keeps its map: it samples in the camera's
/// post-perspective space, where the light's cone is not what counts.
fn wider_than_a_face(map: &ShadowMap, sv: &SplitView, l: DVec3) -> bool {
    if !map.is_active() || sv.settings.method == Method::Psm {
        return false;
    }
    let mut buf = [DVec3::ZERO; MAX_VERTICES];
    let units = unit_directions(map.body.vertices(), l, &mut buf);
    // NOTE: tan² ≤ 2 as |u × a|² ≤ 2 (a·u)² with a·u > 0, without a division.
    let within = |a: DVec3| units.iter().all(|u| a.dot(*u) > 0.0 && u.cross(a).length_squared() <= 2.0 * a.dot(*u).powi(2));
    // Any axis holding every direction within a face's cone proves the
    // narrowest one does too; the map's own `w` axis usually does, and
    // saves the search.
    let own = map.fit.clip_from_world.row(3).truncate().normalize_or_zero();
    if own != DVec3::ZERO && within(own) {
        return false;
    }
    cone_axis(units).is_none_or(|a| !within(a))
}

/// Unit directions from `l` to the vertices other than `l` itself, in `buf`.
fn unit_directions<'a>(verts: &[DVec3], l: DVec3, buf: &'a mut [DVec3; MAX_VERTICES]) -> &'a [DVec3] {
    let mut n = 0;
    for p in verts.iter().filter(|p| **p != l) {
        buf[n] = (*p - l).normalize();
        n += 1;
    }
    &buf[..n]
}

// NOTE: returned once per point-light split, never stored: the size
// difference between variants costs nothing and boxing would allocate.
#[allow(clippy::large_enum_variant)]
enum Truncation {
    Frustum(Frustum),
    /// All of H lies within `r` of the light.
    AllNear,
    /// The directions from the light to H do not fit in an open half-space,
    /// or not in a cone as narrow as a cube face's (`t_x² + t_y² ≤ 2`), or
    /// rounding leaves a vertex's side of the light's plane unproven.
    NoCone,
}

/// A symmetric frustum from `l` containing every point of `body` (exact
/// points, not only the rounded vertices) at depth ≥ its near along its
/// axis, with its near chosen so that every point of the body before it
/// lies within `r` of `l`.
///
/// Every point `p` of the body is `l + Σ λ_i (v_i − l)`, `λ_i ≥ 0`, so it
/// lies in the cone of the vertices' directions: its lateral offsets are at
/// most `t_x`, `t_y` times its depth `t` along the axis, and
/// `|p − l| ≤ t √(1 + t_x² + t_y²)`. With near `r / √(1 + t_x² + t_y²)`
/// every point cut off lies within `r`. The tangents are bounded from the
/// rounded vertices with their proven error (`ROUNDING_ULPS` ulps of the
/// inputs' magnitude `mag`, per coordinate) and the rounding of the dot
/// products, then widened by `CONE_MARGIN`; the near is rounded down by the
/// same margin.
fn truncation_frustum(sv: &SplitView, body: &Body, l: DVec3, r: f64, mag: f64) -> Result<Truncation, FocusError> {
    let verts = body.vertices();
    // NOTE: normalised once here rather than in every pass of the search
    // below (three passes when the first guess holds, a sqrt and three
    // divisions per vertex each).
    let mut buf = [DVec3::ZERO; MAX_VERTICES];
    let units = unit_directions(verts, l, &mut buf);
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for u in units {
        lo = lo.min(*u);
        hi = hi.max(*u);
    }
    let guess = ((lo + hi) * 0.5).normalize_or_zero();
    let axis = if guess == DVec3::ZERO { None } else { turn_into_cone(units, guess, 64) };
    let Some(a) = axis else { return Ok(Truncation::NoCone) };
    let hint = perpendicular_hint(sv.basis.forward, sv.basis.right + sv.basis.up);
    let (right, up) = tangent_frame(a, sv.basis.forward, hint);
    // Error of u = v − l against the exact vertex: the vertex's proven
    // bound per coordinate (√3 of it in length) and the subtraction's
    // rounding, doubled for the rounding of this bound itself.
    let delta = 2.0 * 3f64.sqrt() * (ROUNDING_ULPS + 2.0) * f64::EPSILON * mag;
    let (mut tx, mut ty, mut far) = (0.0f64, 0.0f64, 0.0f64);
    for p in verts.iter().filter(|p| **p != l) {
        let u = *p - l;
        // Each dot product with a (nearly) unit vector: off by at most
        // δ (|a| ≤ 1 + ε) plus its own rounding (≤ 4ε Σ|u_j|).
        let err = delta * (1.0 + f64::EPSILON) + 4.0 * f64::EPSILON * u.abs().element_sum();
        let depth = a.dot(u) - err;
        if !(depth > 0.0) {
            return Ok(Truncation::NoCone);
        }
        tx = tx.max((right.dot(u).abs() + err) / depth);
        ty = ty.max((up.dot(u).abs() + err) / depth);
        far = far.max(depth + 2.0 * err);
    }
    far *= 1.0 + CONE_MARGIN;
    // Keep both half-angles positive and finite (a flat body seen edge-on).
    let t_max = tx.max(ty).max(1e-9);
    let (tx, ty) = ((tx.max(t_max * 1e-6)) * (1.0 + CONE_MARGIN), (ty.max(t_max * 1e-6)) * (1.0 + CONE_MARGIN));
    let k = (1.0 + tx * tx + ty * ty).sqrt();
    let near = r / k * (1.0 - CONE_MARGIN);
    if !(far > near) {
        return Ok(Truncation::AllNear);
    }
    // Wider than a cube face (tan² of both half-angles 1): the faces cut at
    // r/√3, nearer than this map would have to.
    if !(tx * tx + ty * ty <= 2.0) {
        return Ok(Truncation::NoCone);
    }
    let cam = Camera { eye: l, forward: a, up, fovy: 2.0 * ty.atan(), aspect: tx / ty, near, far };
    if !(cam.fovy < std::f64::consts::PI) {
        return Ok(Truncation::NoCone);
    }
    Ok(Truncation::Frustum(Frustum::from_camera(&cam)?))
}

/// Six 90° faces (widened by `CONE_MARGIN` so they overlap), each a spot
/// light from `l` with near `r/√3` (rounded down) and far reaching the
/// scene box's farthest corner along the face axis; each focused on its own
/// body. A point farther than `r` from `l` is farther than `r/√3` along
/// the axis of its largest coordinate (max norm ≥ Euclidean / √3), so the
/// face of that axis holds it.
fn cube_faces(
    out: &mut FocusResult,
    sv: &SplitView,
    view: &Frustum,
    l: DVec3,
    scene: &Aabb,
    split: usize,
    r: f64,
) -> Result<(), FocusError> {
    let near = r * (1.0 / 3f64.sqrt()) * (1.0 - CONE_MARGIN);
    for face in CubeFace::ALL {
        let (axis, up) = face.axes();
        let far = (0..8).map(|k| axis.dot(scene.corner(k) - l)).fold(f64::NEG_INFINITY, f64::max) * (1.0 + CONE_MARGIN);
        let (map, focuser) = push(out)?;
        begin(map, sv, split, Some(face), &Light::Point { position: l });
        map.light_near = r;
        if !(far > near) {
            map.set_empty();
            map.body_valid = false;
            continue;
        }
        let cam = Camera { eye: l, forward: axis, up, fovy: 2.0 * (1.0 + CONE_MARGIN).atan(), aspect: 1.0, near, far };
        let face_frustum = Frustum::from_camera(&cam)?;
        let spot = Light::spot(l, face_frustum)?;
        map.light = spot;
        focuser.focus_into(&mut map.body, view, &spot, scene)?;
        map.body_valid = true;
        if finish(map, sv) {
            continue;
        }
        // The body's vertices are rounded within ROUNDING_ULPS of the
        // inputs' largest magnitude; a view frustum far larger than the
        // scene (a huge aspect or far) can then put some behind the light,
        // where no map from it sees them. The face's frustum cut by S,
        // `L_f ∩ S ⊇ H_f` (its body with the face itself as the view), is
        // computed at the face's own scale: fit the map to that instead.
        focuser.focus_into(&mut map.body, &face_frustum, &spot, scene)?;
        if !finish(map, sv) {
            return Err(FocusError::NoSingleProjection { reason: "a cube face cannot see its body, nor its frustum within the scene box" });
        }
    }
    Ok(())
}

/// Aggregates what the frame skipped and where it departed from the request.
fn plan(out: &mut FocusResult, settings: &FocusSettings, light: &Light, scene: &Aabb) {
    let mut skipped = Skipped::default();
    let mut notes = out.notes;
    let (mut light_clip, mut scene_clip, mut computed) = (true, true, false);
    let mut any_shift = false;
    for map in out.maps() {
        if map.body_valid {
            computed = true;
            light_clip &= map.body.stats().light_clip_skipped;
            scene_clip &= map.body.stats().scene_clip_skipped;
        }
        if map.fit.state == MapState::Empty {
            skipped.insert(Skipped::EMPTY_MAPS);
            continue;
        }
        any_shift |= map.fit.psm_shift > 0.0;
        notes.insert(map.notes);
        skipped.insert(map.skipped);
        if map.fit.inverted() {
            notes.insert(Notes::INVERTED);
        }
        if !map.fit.f32_exact {
            notes.insert(Notes::F32_IMPRECISE);
        }
    }
    if computed && light_clip {
        skipped.insert(Skipped::LIGHT_CLIP);
    }
    if computed && scene_clip {
        skipped.insert(Skipped::SCENE_CLIP);
    }
    if let Light::Point { position } = *light {
        // Some map leaves out casters within r > 0 of the light, and the
        // cube of half-size r around the light meets S.
        let r = out.maps().iter().map(|m| m.light_near).fold(0.0, f64::max);
        let rv = DVec3::splat(r);
        if r > 0.0 && (position + rv).cmpge(scene.min).all() && (position - rv).cmple(scene.max).all() {
            notes.insert(Notes::LIGHT_NEAR);
        }
    }
    if settings.method == Method::Psm && !any_shift {
        skipped.insert(Skipped::PSM_SHIFT);
    }
    out.skipped = skipped;
    out.notes = notes;
}
