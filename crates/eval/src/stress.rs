//! Numerical stress: families of cameras, lights and scenes pushed toward
//! the ranges where floating-point focusing breaks, each checked exactly.
//!
//! Per case:
//! - the body against [`crate::oracle`], an independent big-integer
//!   computation of the exact `H`: same dimension, same vertex count, and
//!   the distance between the vertex sets (relative to the case's magnitude);
//! - conservativeness of the body: every corner of `V` that lies in `S`
//!   (decided exactly: box membership of an f64 point is exact) must lie in
//!   the exact body `H` (the oracle's exact containment), and every corner and
//!   exact vertex within rounding of the reported (rounded) body's face planes;
//! - every fitted map must keep its body's vertices inside the clip volume
//!   `w > 0, −w ≤ x, y ≤ w, 0 ≤ z ≤ w`, evaluated in f64;
//! - the condition number of every world→clip matrix (nalgebra SVD);
//! - the naive f64 + ε pipeline of [`crate::naive`] on the same input:
//!   how many in-`S` corners of `V` it excludes (decided exactly), and
//!   whether it degenerates or fails.

use crate::naive::{naive_body, NaiveBody, NaiveLight};
use crate::oracle;
use glam::{DMat4, DVec3, DVec4};
use shadowfocus_focus::{fit, FocusResult, FocusSettings, Method, SplitSettings};
use shadowfocus_geom::{focus_body, Aabb, Camera, Frustum, Light};

/// One stress input.
#[derive(Clone, Debug)]
pub struct StressCase {
    pub family: &'static str,
    /// The swept parameter (far/near, offset, distance, γ, scale, …).
    pub param: f64,
    pub label: String,
    pub camera: Camera,
    pub light: Light,
    pub scene: Aabb,
}

/// What one case gave.
#[derive(Clone, Debug, Default)]
pub struct StressOutcome {
    pub family: &'static str,
    pub param: f64,
    pub label: String,
    /// The body engine's error, if any (typed; a panic is not caught).
    pub body_error: Option<String>,
    pub dimension: i32,
    pub vertices: usize,
    /// The oracle's dimension and vertex count, whether ours match, and the
    /// distance between the vertex sets relative to the magnitude.
    pub oracle_dimension: i32,
    pub oracle_vertices: usize,
    pub oracle_agrees: bool,
    pub oracle_error: f64,
    /// Corners of V inside S.
    pub corners_in_scene: usize,
    /// Of those, outside the exact body (must be 0).
    pub exact_violations: usize,
    /// Largest distance of such a corner or of an exact vertex outside the
    /// rounded body's face planes, relative to the case's magnitude (≈ a few
    /// ulps at most).
    pub rounded_excess: f64,
    /// Fitted maps checked / maps whose body left the clip volume / fits
    /// that returned an error.
    pub maps_checked: usize,
    pub maps_not_containing: usize,
    pub fit_errors: Vec<String>,
    /// Largest world→clip condition number over the checked maps.
    pub max_condition: f64,
    /// The naive pipeline: solid / degenerate / failed.
    pub naive_kind: &'static str,
    /// In-S corners of V the naive body excludes (exact test).
    pub naive_lost: usize,
    /// How far (relative to magnitude) the worst lost corner lies outside.
    pub naive_lost_excess: f64,
}

fn camera(eye: DVec3, forward: DVec3, near: f64, far: f64) -> Camera {
    Camera { eye, forward, up: DVec3::Y, fovy: 60f64.to_radians(), aspect: 16.0 / 9.0, near, far }
}

fn aabb(min: DVec3, max: DVec3) -> Aabb {
    Aabb { min, max }
}

fn base_forward() -> DVec3 {
    DVec3::new(0.0, -0.15, -1.0).normalize()
}

fn sun() -> Light {
    Light::Directional { direction: DVec3::new(0.4, -1.0, 0.3) }
}

fn push(out: &mut Vec<StressCase>, family: &'static str, param: f64, label: String, camera: Camera, light: Light, scene: Aabb) {
    out.push(StressCase { family, param, label, camera, light, scene });
}

/// Every stress case, deterministic.
pub fn stress_cases() -> Vec<StressCase> {
    let mut v = Vec::new();
    let eye = DVec3::new(0.0, 2.0, 10.0);
    let base_scene = aabb(DVec3::new(-100.0, 0.0, -200.0), DVec3::new(100.0, 30.0, 20.0));

    // far/near from 10 to 1e7: the scene grows with the far plane so S
    // still cuts V.
    for k in 1..=7 {
        let f = 10f64.powi(k);
        let s = aabb(DVec3::new(-f, 0.0, -f), DVec3::new(f, 0.15 * f, 20.0));
        push(&mut v, "far_over_near", f, format!("f/n = 1e{k}"), camera(eye, base_forward(), 1.0, f), sun(), s);
    }
    // World offset 0 … 1e8 (everything translated).
    for k in [None, Some(2), Some(4), Some(5), Some(6), Some(7), Some(8)] {
        let o = k.map_or(0.0, |k| 10f64.powi(k));
        let d = DVec3::new(1.0, 0.5, 1.0).normalize() * o;
        let s = aabb(base_scene.min + d, base_scene.max + d);
        push(&mut v, "world_offset", o, format!("offset {o:e}"), camera(eye + d, base_forward(), 0.5, 200.0), sun(), s);
    }
    // Point light at distance 1 … 1e15 from the eye.
    for k in 0..=15 {
        let d = 10f64.powi(k);
        let p = eye + DVec3::new(0.3, 1.0, 0.2).normalize() * d;
        push(
            &mut v,
            "light_distance",
            d,
            format!("point light 1e{k}"),
            camera(eye, base_forward(), 0.5, 200.0),
            Light::Point { position: p },
            base_scene,
        );
    }
    // γ, the angle between light and view direction: 0.1 … 1e-12 and 0,
    // light behind the viewer (same direction) and in front (opposite).
    let f = base_forward();
    let r = f.cross(DVec3::Y).normalize();
    for (family, sign) in [("gamma_behind", 1.0), ("gamma_front", -1.0)] {
        for k in [Some(1), Some(2), Some(4), Some(6), Some(8), Some(10), Some(12), None] {
            let g = k.map_or(0.0, |k| 10f64.powi(-k));
            let d = f * (sign * g.cos()) + r * g.sin();
            push(&mut v, family, g, format!("γ = {g:e}"), camera(eye, f, 0.5, 200.0), Light::Directional { direction: d }, base_scene);
        }
    }
    // Near-coplanar: an axis-aligned camera looking down −z, near plane at
    // z = −1, far plane at z = −100; scene faces on, and one ulp either
    // side of, V's faces; lights on and one ulp off a frustum plane.
    let cam = camera(DVec3::ZERO, DVec3::NEG_Z, 1.0, 100.0);
    let wide = aabb(DVec3::splat(-1000.0), DVec3::splat(1000.0));
    for (tag, z) in [("on", -1.0f64), ("ulp+", (-1.0f64).next_up()), ("ulp-", (-1.0f64).next_down())] {
        let s = aabb(DVec3::new(-1000.0, -1000.0, -1000.0), DVec3::new(1000.0, 1000.0, z));
        push(&mut v, "coplanar", z, format!("S max.z at near plane ({tag})"), cam, sun(), s);
    }
    for (tag, z) in [("on", -100.0f64), ("ulp+", (-100.0f64).next_up()), ("ulp-", (-100.0f64).next_down())] {
        let s = aabb(DVec3::new(-1000.0, -1000.0, z), DVec3::splat(1000.0));
        push(
            &mut v,
            "coplanar",
            z,
            format!("S min.z at far plane ({tag})"),
            cam,
            Light::Point { position: DVec3::new(0.0, 500.0, -50.0) },
            s,
        );
    }
    if let Ok(c) = cam.corners() {
        let top = c[6].y; // far top corner height
        for (tag, y) in [("on", top), ("ulp+", top.next_up()), ("ulp-", top.next_down())] {
            let s = aabb(DVec3::new(-1000.0, y, -1000.0), DVec3::splat(1000.0));
            push(&mut v, "coplanar", y, format!("S min.y at far top edge ({tag})"), cam, sun(), s);
        }
    }
    // Flat and point-sized results: a zero-thickness scene in the near
    // plane (a polygon), and a scene that is a single far corner of V.
    let flat = aabb(DVec3::new(-1000.0, -1000.0, -1.0), DVec3::new(1000.0, 1000.0, -1.0));
    push(&mut v, "coplanar", -1.0, "S flat in the near plane".into(), cam, sun(), flat);
    if let Ok(c) = cam.corners() {
        push(
            &mut v,
            "coplanar",
            c[6].z,
            "S = a far corner of V".into(),
            cam,
            Light::Point { position: DVec3::new(0.0, 500.0, -50.0) },
            aabb(c[6], c[6]),
        );
    }
    for (tag, z) in [("on", -1.0f64), ("ulp+", (-1.0f64).next_up()), ("ulp-", (-1.0f64).next_down())] {
        push(
            &mut v,
            "coplanar",
            z,
            format!("point light in near plane ({tag})"),
            cam,
            Light::Point { position: DVec3::new(0.0, 50.0, z) },
            wide,
        );
    }
    for (tag, dz) in [("on", 0.0), ("ulp", f64::EPSILON), ("-ulp", -f64::EPSILON)] {
        push(
            &mut v,
            "coplanar",
            dz,
            format!("light parallel to near plane ({tag})"),
            cam,
            Light::Directional { direction: DVec3::new(0.0, -1.0, dz) },
            wide,
        );
    }
    // Tiny (1e-6) to huge (1e9) scenes: the base scene scaled.
    for k in [-6, -3, 0, 3, 6, 9] {
        let s = 10f64.powi(k);
        let sc = aabb(base_scene.min * s, base_scene.max * s);
        push(&mut v, "scale", s, format!("scale 1e{k}"), camera(eye * s, base_forward(), 0.5 * s, 200.0 * s), sun(), sc);
    }
    v
}

fn magnitude(c: &StressCase) -> f64 {
    let mut m =
        c.camera.eye.abs().max_element().max(c.camera.far).max(c.scene.min.abs().max_element()).max(c.scene.max.abs().max_element());
    if let Light::Point { position } = c.light {
        m = m.max(position.abs().max_element());
    }
    m
}

/// Condition number `σ_max/σ_min` of a 4×4 matrix (∞ when singular).
pub fn condition(m: &DMat4) -> f64 {
    let n = nalgebra::Matrix4::<f64>::from_column_slice(&m.to_cols_array());
    let sv = n.singular_values();
    let (lo, hi) = (sv.min(), sv.max());
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// Whether `v` lands in the clip volume of `m` (f64 evaluation).
pub fn in_clip_volume(m: &DMat4, v: DVec3) -> bool {
    let c = *m * DVec4::new(v.x, v.y, v.z, 1.0);
    c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
}

const FIT_METHODS: [(Method, usize); 5] =
    [(Method::Uniform, 1), (Method::Psm, 1), (Method::Lispsm, 1), (Method::Tsm, 1), (Method::Lispsm, 4)];

fn check_fits(c: &StressCase, o: &mut StressOutcome, result: &mut FocusResult) {
    for (method, splits) in FIT_METHODS {
        let settings =
            FocusSettings { method, splits: SplitSettings { count: splits, ..SplitSettings::default() }, ..FocusSettings::default() };
        if let Err(e) = fit(&c.camera, &c.light, &c.scene, &settings, result) {
            o.fit_errors.push(format!("{}x{splits}: {e}", method.name()));
            continue;
        }
        for m in result.maps().iter().filter(|m| m.is_active()) {
            o.maps_checked += 1;
            if !m.body().vertices().iter().all(|v| in_clip_volume(&m.fit.clip_from_world, *v)) {
                o.maps_not_containing += 1;
            }
            o.max_condition = o.max_condition.max(condition(&m.fit.clip_from_world));
        }
    }
}

fn naive_light(l: &Light) -> Option<NaiveLight> {
    match *l {
        Light::Directional { direction } => Some(NaiveLight::Directional(direction)),
        Light::Point { position } => Some(NaiveLight::Point(position)),
        Light::Spot { .. } => None,
    }
}

/// Runs one case through both pipelines.
pub fn run_case(c: &StressCase) -> StressOutcome {
    let mut o = StressOutcome { family: c.family, param: c.param, label: c.label.clone(), naive_kind: "n/a", ..Default::default() };
    let mag = magnitude(c);
    let frustum = match Frustum::from_camera(&c.camera) {
        Ok(f) => f,
        Err(e) => {
            o.body_error = Some(e.to_string());
            return o;
        }
    };
    let corners: Vec<DVec3> = frustum.corners().iter().copied().filter(|p| c.scene.contains(*p)).collect();
    o.corners_in_scene = corners.len();
    let exact = oracle::exact_body(frustum.corners(), &c.light, &c.scene);
    match (focus_body(&frustum, &c.light, &c.scene), exact) {
        (Err(e), _) => o.body_error = Some(e.to_string()),
        (_, Err(e)) => o.body_error = Some(format!("oracle: {e}")),
        (Ok(body), Ok(exact)) => {
            o.dimension = body.dimension().as_i32();
            o.vertices = body.vertices().len();
            o.oracle_dimension = exact.dimension;
            o.oracle_vertices = exact.vertices.len();
            let a = oracle::compare(&exact, o.dimension, body.vertices());
            o.oracle_agrees = a.dimension_matches && a.vertex_counts_match;
            o.oracle_error = a.max_vertex_error / mag;
            o.exact_violations = corners.iter().filter(|p| !exact.contains(**p)).count();
            let exact_vertices: Vec<DVec3> = exact.vertices.iter().map(oracle::to_f64).collect();
            for p in corners.iter().chain(&exact_vertices) {
                for pl in body.face_planes() {
                    let d = pl.truncate().dot(*p) + pl.w;
                    o.rounded_excess = o.rounded_excess.max(d / mag);
                }
            }
        }
    }
    let mut result = FocusResult::new();
    check_fits(c, &mut o, &mut result);
    if let Some(l) = naive_light(&c.light) {
        let nb = naive_body(frustum.corners(), l, &c.scene);
        o.naive_kind = nb.kind();
        if let NaiveBody::Hull { .. } = nb {
            for p in &corners {
                if nb.excludes(*p) {
                    o.naive_lost += 1;
                    o.naive_lost_excess = o.naive_lost_excess.max(nb.distance_outside(*p) / mag);
                }
            }
        }
    }
    o
}

/// Runs every case of [`stress_cases`].
pub fn run_all() -> Vec<StressOutcome> {
    stress_cases().iter().map(run_case).collect()
}

/// A naive loss larger than this (relative to the input magnitude) is not
/// rounding noise.
pub const GROSS_LOSS: f64 = 1e-9;

/// Whether the naive pipeline broke on a case where ours did not: lost an
/// in-S corner, degenerated on a solid body, or failed.
pub fn naive_broke(o: &StressOutcome) -> bool {
    let ours_ok = o.body_error.is_none() && o.exact_violations == 0;
    ours_ok && (o.naive_lost > 0 || (o.dimension == 3 && o.naive_kind != "solid" && o.naive_kind != "n/a"))
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.is_finite() {
        format!("{x:.1e}")
    } else {
        "∞".into()
    }
}

/// The markdown report section: one line per case.
pub fn report_markdown(outcomes: &[StressOutcome]) -> String {
    let mut s = String::from(
        "| family | case | dim | oracle dim / vertices | vertex error (rel.) | V∩S corners | violations (exact) | rounded excess (rel.) | maps ok / checked | max cond | fit errors | naive | naive lost | naive excess (rel.) |\n|---|---|---:|---:|---:|---:|---:|---:|---|---:|---|---|---:|---:|\n",
    );
    for o in outcomes {
        let dim = match &o.body_error {
            Some(e) => format!("error: {e}"),
            None => o.dimension.to_string(),
        };
        s.push_str(&format!(
            "| {} | {} | {} | {}{} / {} | {} | {} | {} | {} | {}/{} | {} | {} | {} | {} | {} |\n",
            o.family,
            o.label,
            dim,
            if o.oracle_agrees { "" } else { "**≠** " },
            o.oracle_dimension,
            o.oracle_vertices,
            sci(o.oracle_error),
            o.corners_in_scene,
            o.exact_violations,
            sci(o.rounded_excess),
            o.maps_checked - o.maps_not_containing,
            o.maps_checked,
            sci(o.max_condition),
            if o.fit_errors.is_empty() { "—".to_string() } else { o.fit_errors.join("; ") },
            o.naive_kind,
            o.naive_lost,
            sci(o.naive_lost_excess),
        ));
    }
    let total = outcomes.len();
    let agree = outcomes.iter().filter(|o| o.body_error.is_none() && o.oracle_agrees).count();
    let worst = outcomes.iter().map(|o| o.oracle_error).fold(0.0, f64::max);
    let viol: usize = outcomes.iter().map(|o| o.exact_violations).sum();
    let bad_maps: usize = outcomes.iter().map(|o| o.maps_not_containing).sum();
    let broke = outcomes.iter().filter(|o| naive_broke(o)).count();
    let degenerate = outcomes.iter().filter(|o| naive_broke(o) && o.naive_kind != "solid").count();
    let gross = outcomes.iter().filter(|o| naive_broke(o) && o.naive_lost_excess > GROSS_LOSS).count();
    s.push_str(&format!(
        "\n{total} cases: the body agrees with the big-integer oracle (dimension and vertex count) on {agree}, largest vertex error {} of the magnitude; {viol} conservativeness violations of the exact body, {bad_maps} fitted maps not containing their body. The naive f64 + ε pipeline broke on {broke} cases where ours did not: {degenerate} degenerate or failed hulls, {gross} with a view corner lost by more than {GROSS_LOSS:e} (relative), the rest excluding a corner by a rounding-level amount (still a lost caster if one touches it).\n",
        sci(worst)
    ));
    s
}
