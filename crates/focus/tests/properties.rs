//! Guarantees of every fit, as properties over random cameras, lights,
//! scenes and settings, checked against the exact body engine.

mod common;

use common::*;
use glam::{DVec3, DVec4};
use proptest::prelude::*;
use shadowfocus_focus::*;
use shadowfocus_geom::{focus_body, Aabb, Camera, Dimension, Frustum, Light};

fn split_camera(cam: &Camera, r: [f64; 2]) -> Camera {
    Camera { near: r[0], far: r[1], ..*cam }
}

/// Every map contains its body in the GPU's clip volume (f64 and f32, in
/// the settings' clip convention), the
/// body is the exact H_i of its split, the maps' x/y/w rows pass through the
/// light, and the splits cover [near, far] without gaps.
fn check_frame(cam: &Camera, light: &Light, scene: &Aabb, s: &FocusSettings, out: &FocusResult) -> Result<(), TestCaseError> {
    let d = out.split_depths();
    prop_assert_eq!(d.len(), s.splits.count + 1);
    prop_assert_eq!(d[0], cam.near);
    prop_assert_eq!(d[d.len() - 1], cam.far);
    prop_assert!(d.windows(2).all(|w| w[0] <= w[1]), "splits not monotone: {:?}", d);
    // Every active map has a size: the resolution, or its share of the
    // budget, which the active maps keep within (an allowed size each).
    let sizes: Vec<u32> = out.maps().iter().filter(|m| m.is_active()).map(|m| m.fit.resolution).collect();
    prop_assert!(out.maps().iter().all(|m| m.is_active() || m.fit.resolution == 0));
    match s.texel_budget {
        None => prop_assert!(sizes.iter().all(|&r| r == s.resolution), "{:?}", sizes),
        Some(b) => {
            prop_assert!(sizes.iter().map(|&r| u64::from(r).pow(2)).sum::<u64>() <= b.texels, "{:?} over {}", sizes, b.texels);
            prop_assert!(sizes.iter().all(|&r| (4..=s.resolution).contains(&r)), "{:?}", sizes);
            prop_assert!(b.sizes == MapSizes::Any || sizes.iter().all(|r| r.is_power_of_two()), "{:?}", sizes);
        }
    }
    // Camera clip depths in the convention's range, increasing away from
    // the eye (decreasing with reversed-Z).
    let z_min = s.clip.depth_min();
    for (i, w) in out.split_clip_depths().windows(2).enumerate() {
        let (a, b) = if s.clip.reversed_z { (w[1], w[0]) } else { (w[0], w[1]) };
        prop_assert!(a <= b && a >= z_min - 1e-12 && b <= 1.0 + 1e-12, "clip depths {i}: {:?}", w);
    }
    let mut splits_seen = vec![false; s.splits.count];
    for map in out.maps() {
        prop_assert!(map.fit.clip_from_world.is_finite() && map.fit.texel_size.iter().all(|t| !t.is_nan()));
        prop_assert_eq!(map.split_range, [d[map.split], d[map.split + 1]]);
        splits_seen[map.split] = true;
        if map.fit.state == MapState::Empty {
            prop_assert_eq!(map.fit.clip_from_world, glam::DMat4::ZERO);
            prop_assert!(map.body().is_empty());
            continue;
        }
        let body = map.body();
        prop_assert!(!body.is_empty());
        // f32 keeps its guarantee at these coordinates for directional
        // lights; a point light's map may lose it for vertices a few
        // `light_near` from the light (w there is below f32's resolution of
        // the world coordinates) — then the frame says so.
        if matches!(map.light, Light::Directional { .. }) && modest_coordinates(cam, scene) {
            prop_assert!(map.fit.f32_exact, "f32 guarantee lost at modest coordinates");
        }
        if !map.fit.f32_exact {
            prop_assert!(out.notes.contains(Notes::F32_IMPRECISE));
        }
        for p in body.vertices() {
            prop_assert!(inside_map_f64(&map.fit, *p), "vertex {p} outside map (f64) {:?}", map.fit.method);
            if map.fit.f32_exact {
                prop_assert!(inside_map_f32(&map.fit, *p), "vertex {p} outside map (f32) {:?}", map.fit.method);
            }
        }
        // Rays from the light map to one texel: x, y, w rows contain L.
        let lp = light_point(&map.light);
        for r in [0, 1, 3] {
            let row: DVec4 = map.fit.clip_from_world.row(r);
            // Against the row's largest entry too: a w row at infinity
            // ((≈0, ≈0, ≈0, w), an orthographic map) has xyz entries of
            // rounding size, which its own |row|·|L| does not bound.
            let scale = row.abs().dot(lp.abs()).max(row.abs().max_element() * lp.abs().max_element()).max(1e-300);
            prop_assert!(row.dot(lp).abs() <= 1e-9 * scale, "row {r} misses the light: {}", row.dot(lp) / scale);
        }
        // The body is H_i of the split, recomputed independently.
        let sub = split_camera(cam, map.split_range);
        let h = focus_body(&Frustum::from_camera(&sub).unwrap(), &map.light, scene).unwrap();
        prop_assert_eq!(h.vertices().len(), body.vertices().len());
        for p in h.vertices() {
            prop_assert!(inside_map_f64(&map.fit, *p));
        }
    }
    prop_assert!(splits_seen.iter().all(|x| *x), "a split has no map");

    // Visible points: every point of V_i ∩ S lies in split i's map(s).
    let b = cam.basis().unwrap();
    let t = (0.5 * cam.fovy).tan();
    for k in 0..64 {
        let fx = ((k * 37) % 64) as f64 / 63.0 * 2.0 - 1.0;
        let fy = ((k * 11) % 64) as f64 / 63.0 * 2.0 - 1.0;
        let fz = k as f64 / 63.0;
        // NOTE: near + (far − near)·1 can round above far; clamp into range.
        let z = (cam.near + (cam.far - cam.near) * fz).clamp(cam.near, cam.far);
        let p = cam.eye + b.forward * z + b.right * (fx * z * t * cam.aspect * 0.999) + b.up * (fy * z * t * 0.999);
        if !scene.contains(p) {
            continue;
        }
        let i = (0..s.splits.count).find(|&i| d[i] <= z && z <= d[i + 1] && d[i] < d[i + 1]).unwrap();
        // A point light's receiver is looked up in the cube face toward it.
        let own_face = |m: &ShadowMap| match (m.face, light) {
            (Some(f), Light::Point { position }) => CubeFace::toward(p - *position) == f,
            _ => true,
        };
        let covered = out.maps().iter().filter(|m| m.split == i && m.is_active() && own_face(m)).any(|m| inside_map_f64(&m.fit, p));
        // Within the split's r of a point light (the maps' light_near).
        let r = out.maps().iter().filter(|m| m.split == i).map(|m| m.light_near).fold(0.0, f64::max);
        let near_light = match light {
            Light::Point { position } => (p - *position).length() <= r,
            _ => false,
        };
        let in_spot = match light {
            Light::Spot { frustum, .. } => frustum.contains(p),
            _ => true,
        };
        prop_assert!(covered || near_light || !in_spot, "visible point {p} at depth {z} not in split {i}'s map");
    }

    // Point lights: every vertex of the untruncated H_i farther than the
    // split's r from the light is in some active map of the split.
    if let Light::Point { position: l } = *light {
        for i in 0..s.splits.count {
            if d[i] >= d[i + 1] {
                continue;
            }
            let sub = split_camera(cam, [d[i], d[i + 1]]);
            let h0 = focus_body(&Frustum::from_camera(&sub).unwrap(), light, scene).unwrap();
            let r = point_light_radius(out, i)?;
            let maps: Vec<&ShadowMap> = out.maps().iter().filter(|m| m.split == i && m.is_active()).collect();
            for v in h0.vertices() {
                if (*v - l).length() <= r {
                    continue;
                }
                prop_assert!(
                    maps.iter().any(|m| inside_map_f64(&m.fit, *v)),
                    "H vertex {v} of split {i} ({} from the light, r = {r}) in no map",
                    (*v - l).length()
                );
            }
        }
    }
    Ok(())
}

/// How far the image `(x/w, y/w)` of `y` can lie from the image of the
/// same light ray under the matrix with the `x`, `y`, `w` rows moved exactly
/// through the light `l`: writing `row = row' + δ e` with `row'·l = 0` and
/// `e·l = 1` (`e = (0, 0, 0, 1/l_w)`, or `(l/|l|², 0)` at infinity), the
/// image moves by at most `(|δx| + |ξ||δw|)·|e·y|/w` in `x`, likewise in `y`.
fn ray_drift(m: &glam::DMat4, l: DVec4, y: DVec3) -> f64 {
    let q = *m * y.extend(1.0);
    let delta = |r: usize| {
        let row = m.row(r);
        row.dot(l).abs() + 4.0 * f64::EPSILON * row.abs().dot(l.abs())
    };
    let e_y = if l.w != 0.0 { 1.0 / l.w.abs() } else { l.truncate().length() * y.length() / l.truncate().length_squared() };
    let (dx, dy, dw) = (delta(0), delta(1), delta(3));
    ((dx + (q.x / q.w).abs() * dw).max(dy + (q.y / q.w).abs() * dw)) * e_y / q.w
}

/// An engine's f32 test of a box against caster planes, with the margin
/// `CasterRegion::planes` documents: the box's corners and the planes
/// rounded to f32, outside a plane by more than `2⁻²⁰ (|n|·|c| + |n|·e + |w|)`.
fn outside_in_f32(planes: &[DVec4], b: &Aabb) -> bool {
    let (lo, hi) = (b.min.as_vec3(), b.max.as_vec3());
    let (c, e) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    planes.iter().any(|p| {
        let (n, w) = (p.truncate().as_vec3(), p.w as f32);
        let s = n.dot(c) - n.abs().dot(e) + w;
        s > (n.abs().dot(c.abs()) + n.abs().dot(e) + w.abs()) * (1.0 / (1u32 << 20) as f32)
    })
}

/// 128 cases per property in the test suite; `PROPTEST_CASES` overrides it
/// for longer runs.
/// Receiver hints as fractions of the scene box per axis: none, or up to
/// three boxes whose sides fall on the box's own faces, its middle, beyond
/// it or inside it, flat slabs (a floor) among them.
fn receiver_hint_strategy() -> impl Strategy<Value = Vec<[[f64; 2]; 3]>> {
    let f = prop_oneof![Just(0.0), Just(1.0), Just(0.5), Just(-0.25), Just(1.25), 0.0..1.0f64];
    let side = (f.clone(), f).prop_map(|(a, b): (f64, f64)| [a.min(b), a.max(b)]);
    prop_oneof![Just(Vec::new()), prop::collection::vec([side.clone(), side.clone(), side], 1..=3)]
}

/// The boxes of `hint` in `scene`.
fn hint_boxes(scene: &Aabb, hint: &[[[f64; 2]; 3]]) -> Vec<Aabb> {
    let at = |k: usize, t: f64| scene.min[k] + (scene.max[k] - scene.min[k]) * t;
    hint.iter()
        .map(|h| Aabb {
            min: DVec3::new(at(0, h[0][0]), at(1, h[1][0]), at(2, h[2][0])),
            max: DVec3::new(at(0, h[0][1]), at(1, h[1][1]), at(2, h[2][1])),
        })
        .collect()
}

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(128);
    ProptestConfig { cases, max_shrink_iters: 200, ..ProptestConfig::default() }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn conservative_and_covering(((cam, scene, light), s) in framed_strategy()) {
        let mut out = FocusResult::new();
        fit(&cam, &light, &scene, &s, &mut out).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        check_frame(&cam, &light, &scene, &s, &out)?;
    }

    /// Two points of H on one light ray land on the same texel, and the one
    /// nearer the light has the smaller depth for `Less`, the larger for
    /// `Greater` (PSM's inverted lights included).
    #[test]
    fn depth_order(((cam, scene, light), s) in framed_strategy(), seed in any::<u64>()) {
        let mut out = FocusResult::new();
        fit(&cam, &light, &scene, &s, &mut out).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        for map in out.maps().iter().filter(|m| m.is_active()) {
            let body = map.body();
            if body.dimension() != Dimension::Solid {
                continue;
            }
            let scale = body.vertices().iter().map(|p| p.abs().max_element()).fold(0.0, f64::max);
            for p in body_points(body, 6, seed).into_iter().skip(body.vertices().len()) {
                // The chord of H along the light ray through p.
                let t = travel(&map.light, p);
                let (mut s0, mut s1) = (f64::NEG_INFINITY, f64::INFINITY);
                for pl in body.face_planes() {
                    let n = pl.truncate();
                    let (a, b) = (n.dot(t), n.dot(p) + pl.w);
                    if a > 0.0 { s1 = s1.min(-b / a); } else if a < 0.0 { s0 = s0.max(-b / a); }
                }
                if !(s0.is_finite() && s1.is_finite() && s1 - s0 > 1e-6 * scale) {
                    continue;
                }
                let (s_near, s_far) = (s0 + 0.01 * (s1 - s0), s1 - 0.01 * (s1 - s0));
                let near_light = p + t * s_near;
                let far_light = p + t * s_far;
                let (qa, qb) = (map.fit.clip_from_world * near_light.extend(1.0), map.fit.clip_from_world * far_light.extend(1.0));
                prop_assert!(qa.w > 0.0 && qb.w > 0.0);
                let (xa, ya, za) = (qa.x / qa.w, qa.y / qa.w, qa.z / qa.w);
                let (xb, yb, zb) = (qb.x / qb.w, qb.y / qb.w, qb.z / qb.w);
                // The points are rounded: compare at the resolution their
                // rounding leaves (coarse only far from the origin). So is the
                // ray's direction: `p − l` loses (|p| + |l|)·ε, which moves a
                // point |s| along it by |s|·(|p| + |l|)/|p − l| times that.
                let lp = light_point(&map.light);
                let dir_err = if lp.w == 0.0 { 0.0 } else { (p.abs().max_element() + lp.truncate().abs().max_element()) / (p - lp.truncate()).length() };
                let grow = |q: DVec3, s: f64| 1.0 + s.abs() * dir_err / q.abs().max_element().max(f64::MIN_POSITIVE);
                let m = &map.fit.clip_from_world;
                let res = ndc_sensitivity(m, near_light) * grow(near_light, s_near) + ndc_sensitivity(m, far_light) * grow(far_light, s_far);
                // And the map's rows pass through the light only to rounding:
                // with δ = row·L (bounded with its own rounding) each point's
                // image moves by at most (|δx| + |ξ||δw|)/w, times |l·y|/|l|²
                // for a light at infinity (see `ray_drift`).
                let drift = ray_drift(m, lp, near_light) + ray_drift(m, lp, far_light);
                let tol = 1e-7 + 2.0 * res.x.max(res.y) + drift;
                prop_assert!((xa - xb).abs() < tol && (ya - yb).abs() < tol, "not one texel: ({xa}, {ya}) vs ({xb}, {yb}), resolution {tol}");
                if (za - zb).abs() <= 2.0 * res.z {
                    continue;
                }
                match map.fit.depth_test {
                    DepthTest::Less => prop_assert!(za < zb, "less: {za} !< {zb} ({:?})", map.fit.method),
                    DepthTest::Greater => prop_assert!(za > zb, "greater: {za} !> {zb} ({:?})", map.fit.method),
                }
            }
        }
    }

    /// A clip convention changes only the depth row, and only as the
    /// `clip` module's table says: the x, y and w rows, the body and the
    /// method are the default convention's, bit for bit; the depth row is
    /// the default one mapped to the convention's range (to rounding); the
    /// depth test flips exactly with reversed-Z. The lookup matrix puts every
    /// body vertex at u, v, depth in [0, 1] with the convention's layout, and
    /// the light's view and projection multiply back to `clip_from_world`.
    #[test]
    fn conventions_change_only_the_depth_row(((cam, scene, light), s) in framed_strategy(), clip in clip_strategy()) {
        let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
        let base = FocusSettings { clip: ClipConvention::WGPU, ..s };
        fit(&cam, &light, &scene, &base, &mut a).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        fit(&cam, &light, &scene, &FocusSettings { clip, ..s }, &mut b).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert_eq!(a.maps().len(), b.maps().len());
        prop_assert_eq!(a.notes, b.notes);
        for (x, y) in a.maps().iter().zip(b.maps()) {
            prop_assert_eq!((x.fit.state, x.fit.method, x.split, x.face), (y.fit.state, y.fit.method, y.split, y.face));
            prop_assert_eq!(x.body().vertices(), y.body().vertices());
            prop_assert_eq!(y.fit.clip, clip);
            if !x.is_active() {
                prop_assert_eq!(y.fit.depth_test, clip.normal_depth_test());
                continue;
            }
            let (mx, my) = (&x.fit.clip_from_world, &y.fit.clip_from_world);
            for r in [0, 1, 3] {
                prop_assert_eq!(mx.row(r).to_array().map(f64::to_bits), my.row(r).to_array().map(f64::to_bits), "row {}", r);
            }
            // The default row D has 0 ≤ D ≤ W on the body; the convention's
            // row is D, W − D, 2D − W or W − 2D.
            let (d, w) = (mx.row(2), mx.row(3));
            let want = match (clip.depth, clip.reversed_z) {
                (DepthRange::ZeroToOne, false) => d,
                (DepthRange::ZeroToOne, true) => w - d,
                (DepthRange::MinusOneToOne, false) => d * 2.0 - w,
                (DepthRange::MinusOneToOne, true) => w - d * 2.0,
            };
            let got = my.row(2);
            let scale = d.abs().max(w.abs()).max_element();
            prop_assert!((got - want).abs().max_element() <= 1e-12 * scale, "depth row {got} vs {want}");
            let flipped = x.fit.depth_test != y.fit.depth_test;
            prop_assert_eq!(flipped, clip.reversed_z, "depth tests {:?} and {:?}", x.fit.depth_test, y.fit.depth_test);
            prop_assert_eq!(x.fit.inverted(), y.fit.inverted());
            // The lookup: u, v in [0, 1] with v = 0 at the first texel row.
            let uv = y.fit.uv_from_world();
            let top_first = (clip.uv_origin == UvOrigin::TopLeft) != clip.y_down;
            for p in y.body().vertices() {
                let (q, c) = (uv * p.extend(1.0), *my * p.extend(1.0));
                let (u, v, z) = (q.x / q.w, q.y / q.w, q.z / q.w);
                // Rounding of the products, relative to the magnitudes they cancel.
                let pa = p.extend(1.0).abs();
                let mag = |m: &glam::DMat4| (0..4).map(|i| m.row(i).abs().dot(pa)).fold(0.0, f64::max);
                let tol = 1e-9 + 1e-12 * mag(&uv).max(mag(my)) / q.w.abs().min(c.w.abs());
                prop_assert!(u >= -tol && u <= 1.0 + tol && v >= -tol && v <= 1.0 + tol && z >= -tol && z <= 1.0 + tol, "lookup ({u}, {v}, {z})");
                let y_clip = c.y / c.w;
                let v_want = if top_first { 0.5 - 0.5 * y_clip } else { 0.5 + 0.5 * y_clip };
                prop_assert!((v - v_want).abs() <= tol, "v {v} vs {v_want}");
            }
            // View and projection, apart: a rigid view, and their product.
            let view = y.light_view();
            let r = glam::DMat3::from_mat4(view);
            prop_assert!((r * r.transpose() - glam::DMat3::IDENTITY).to_cols_array().iter().all(|e| e.abs() < 1e-12) && r.determinant() > 0.0);
            let back = y.light_projection() * view;
            let scale = my.abs().to_cols_array().iter().fold(0.0f64, |m, v| m.max(*v)) * (1.0 + view.w_axis.truncate().abs().max_element());
            prop_assert!((back - *my).abs().to_cols_array().iter().all(|e| *e <= 1e-12 * scale), "projection · view != clip_from_world");
            // The body lies in front of the light's view.
            for p in y.body().vertices() {
                prop_assert!((view * p.extend(1.0)).z <= 1e-9 * scale, "body vertex {p} behind the light's view");
            }
        }
    }

    /// Depth clamping changes only the depth row, keeping its orientation
    /// (or empties a map without receivers), and the clamped range still
    /// holds every visible, lit point (the receivers) in the full clip
    /// volume; every body vertex keeps `x`, `y` and `w` inside.
    #[test]
    fn depth_clamp_holds_the_receivers(((cam, scene, light), s) in framed_strategy()) {
        let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
        fit(&cam, &light, &scene, &s, &mut a).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        fit(&cam, &light, &scene, &FocusSettings { depth_clamp: true, ..s }, &mut b).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert_eq!(a.maps().len(), b.maps().len());
        for (x, y) in a.maps().iter().zip(b.maps()) {
            prop_assert!(!x.fit.depth_clamp);
            // A map may only become empty (it has no receivers).
            prop_assert!(x.is_active() || !y.is_active());
            if !y.is_active() {
                continue;
            }
            prop_assert_eq!((x.fit.depth_test, x.fit.method), (y.fit.depth_test, y.fit.method));
            let (mx, my) = (&x.fit.clip_from_world, &y.fit.clip_from_world);
            for r in [0, 1, 3] {
                prop_assert_eq!(mx.row(r).to_array().map(f64::to_bits), my.row(r).to_array().map(f64::to_bits), "row {}", r);
            }
            let ndc_z = |m: &glam::DMat4, p: DVec3| { let q = *m * p.extend(1.0); q.z / q.w };
            let verts = y.body().vertices();
            for p in verts {
                let q = *my * p.extend(1.0);
                prop_assert!(q.w > 0.0 && q.x.abs() <= q.w && q.y.abs() <= q.w, "body vertex {p} outside x, y");
            }
            // The same depth order: the new depth is an increasing affine
            // function of the old one (compare the extreme vertices).
            if let (Some(lo), Some(hi)) = (
                verts.iter().min_by(|p, q| ndc_z(mx, **p).total_cmp(&ndc_z(mx, **q))),
                verts.iter().max_by(|p, q| ndc_z(mx, **p).total_cmp(&ndc_z(mx, **q))),
            ) {
                let (d_old, d_new) = (ndc_z(mx, *hi) - ndc_z(mx, *lo), ndc_z(my, *hi) - ndc_z(my, *lo));
                if d_old > 1e-6 {
                    prop_assert!(d_new > 0.0, "depth order reversed: {d_old} → {d_new}");
                }
            }
        }
        // Visible, lit points lie in their split's clamped maps, depth included.
        let d = b.split_depths();
        let basis = cam.basis().unwrap();
        let t = (0.5 * cam.fovy).tan();
        for k in 0..64 {
            let fx = ((k * 37) % 64) as f64 / 63.0 * 2.0 - 1.0;
            let fy = ((k * 11) % 64) as f64 / 63.0 * 2.0 - 1.0;
            let z = (cam.near + (cam.far - cam.near) * (k as f64 / 63.0)).clamp(cam.near, cam.far);
            let p = cam.eye + basis.forward * z + basis.right * (fx * z * t * cam.aspect * 0.999) + basis.up * (fy * z * t * 0.999);
            let lit = match light { Light::Spot { frustum, .. } => frustum.contains(p), _ => true };
            if !scene.contains(p) || !lit {
                continue;
            }
            let i = (0..s.splits.count).find(|&i| d[i] <= z && z <= d[i + 1] && d[i] < d[i + 1]).unwrap();
            let maps: Vec<&ShadowMap> = b.maps().iter().filter(|m| m.split == i && m.is_active()).collect();
            let near_light = match light { Light::Point { position } => maps.iter().any(|m| (p - position).length() <= m.light_near), _ => false };
            prop_assert!(near_light || maps.iter().any(|m| m.fit.depth_clamp && inside_map_f64(&m.fit, p)), "receiver {p} at depth {z} outside split {i}'s clamped maps");
        }
    }

    /// Maps fitted to their receivers hold every visible, lit point — inside
    /// the margin asked for — and every point of the scene on the light ray
    /// from such a point toward the light (the casters that can shadow it),
    /// depth included unless the depth is clamped too. Their depth and `w`
    /// rows are the body fit's own.
    #[test]
    fn receiver_footprint_holds_the_receivers_and_their_light_rays(((cam, scene, light), s) in framed_strategy(), margin in prop_oneof![Just(0.0), Just(2.0), Just(17.5)], clamp in any::<bool>(), hint in receiver_hint_strategy(), seen in any::<bool>()) {
        // With receiver boxes, the receivers promised are those inside a
        // box (the body fit gets them too: optimal planes follow them);
        // boxes of seen points promise the same, predicted otherwise.
        let boxes = hint_boxes(&scene, &hint);
        let receivers = if seen { ReceiverBoxes::seen(&boxes) } else { ReceiverBoxes::new(&boxes) };
        let receivers = receivers.map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let s = FocusSettings { stable: false, receivers, ..s };
        let r = FocusSettings { footprint: Footprint::Receivers { margin_texels: margin }, depth_clamp: clamp, ..s };
        let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
        fit(&cam, &light, &scene, &s, &mut a).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        fit(&cam, &light, &scene, &r, &mut b).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        prop_assert_eq!(a.maps().len(), b.maps().len());
        for (x, y) in a.maps().iter().zip(b.maps()) {
            prop_assert!(x.is_active() || !y.is_active());
            if !y.is_active() {
                continue;
            }
            prop_assert_eq!(y.fit.footprint, r.footprint);
            prop_assert_eq!(y.fit.depth_clamp, clamp);
            let rows = if clamp { vec![3] } else { vec![2, 3] };
            for k in rows {
                prop_assert_eq!(x.fit.clip_from_world.row(k).to_array().map(f64::to_bits), y.fit.clip_from_world.row(k).to_array().map(f64::to_bits), "row {}", k);
            }
        }
        let d = b.split_depths();
        let basis = cam.basis().unwrap();
        let t = (0.5 * cam.fovy).tan();
        let reach = (scene.max - scene.min).length();
        for k in 0..64 {
            let fx = ((k * 37) % 64) as f64 / 63.0 * 2.0 - 1.0;
            let fy = ((k * 11) % 64) as f64 / 63.0 * 2.0 - 1.0;
            let z = (cam.near + (cam.far - cam.near) * (k as f64 / 63.0)).clamp(cam.near, cam.far);
            let p = cam.eye + basis.forward * z + basis.right * (fx * z * t * cam.aspect * 0.999) + basis.up * (fy * z * t * 0.999);
            let lit = |q: DVec3| match light { Light::Spot { frustum, .. } => frustum.contains(q), _ => true };
            if !scene.contains(p) || !lit(p) || !(boxes.is_empty() || boxes.iter().any(|b| b.contains(p))) {
                continue;
            }
            let i = (0..s.splits.count).find(|&i| d[i] <= z && z <= d[i + 1] && d[i] < d[i + 1]).unwrap();
            let maps: Vec<&ShadowMap> = b.maps().iter().filter(|m| m.split == i && m.is_active()).collect();
            let near_light = |q: DVec3| match light { Light::Point { position } => maps.iter().any(|m| (q - position).length() <= m.light_near), _ => false };
            if near_light(p) {
                continue;
            }
            // The maps whose receivers p is among: p inside their image
            // shrunk by the margin, and for a point light's cube faces p in
            // the face's cone (the face `CubeFace::toward` picks; another
            // face's image may reach p, but it answers only for its cone).
            // NOTE: the margin is exact up to the image's rounding, a few ulps.
            let own_face = |m: &ShadowMap| match (m.face, light) {
                (Some(f), Light::Point { position }) => CubeFace::toward(p - position) == f,
                _ => true,
            };
            // The margin is in each map's own texels (a budget sizes them).
            let within_margin = |m: &ShadowMap| {
                let inner = 1.0 - 2.0 * margin / m.fit.resolution as f64;
                let c = m.fit.clip_from_world * p.extend(1.0);
                own_face(m) && inside_map_f64(&m.fit, p) && (c.x / c.w).abs().max((c.y / c.w).abs()) <= inner * (1.0 + 1e-9)
            };
            let holding: Vec<&&ShadowMap> = maps.iter().filter(|m| within_margin(m)).collect();
            prop_assert!(!holding.is_empty(), "receiver {p} at depth {z} outside split {i}'s maps, or within the {margin}-texel margin only");
            for m in holding {
                let lp = light_point(&m.light);
                for j in 1..8 {
                    let f = j as f64 / 8.0;
                    let q = match light {
                        Light::Directional { direction } => p - direction * (f * reach),
                        Light::Point { position } | Light::Spot { position, .. } => p + (position - p) * f,
                    };
                    if !scene.contains(q) || !lit(q) || near_light(q) {
                        continue;
                    }
                    let c = m.fit.clip_from_world * q.extend(1.0);
                    let drift = ray_drift(&m.fit.clip_from_world, lp, q) + ray_drift(&m.fit.clip_from_world, lp, p) + 1e-9;
                    prop_assert!(c.w > 0.0 && (c.x / c.w).abs() <= 1.0 + drift && (c.y / c.w).abs() <= 1.0 + drift, "{q} on the light ray from receiver {p} outside map x, y");
                    if !clamp {
                        let (zq, z_min) = (c.z / c.w, m.fit.clip.depth_min());
                        prop_assert!(zq >= z_min - 1e-9 && zq <= 1.0 + 1e-9, "{q} on the light ray from receiver {p} outside the depth range: {zq}");
                    }
                }
            }
        }
    }

    /// A visible depth range narrows the camera: the fit equals, bit for
    /// bit, the fit of the camera with that near and far (which
    /// `conservative_and_covering` checks), and its splits lie in it. Optimal
    /// placement alone also starts its first plane no farther out than the
    /// logarithmic plane over the range, so it never ends beyond it either.
    #[test]
    fn visible_depth_fits_the_narrowed_camera(((cam, scene, light), s) in framed_strategy(), a in 0.0..1.0f64, b in 0.0..1.0f64) {
        let (a, b) = (a.min(b), a.max(b));
        let z = |t: f64| cam.near + (cam.far - cam.near) * t;
        prop_assume!(z(a) < z(b));
        let hinted = FocusSettings { visible_depth: Some([z(a), z(b)]), visible_depth_coverage: DepthHintCoverage::Hint, ..s };
        let narrowed = Camera { near: z(a).max(cam.near), far: z(b).min(cam.far), ..cam };
        let (mut x, mut y) = (FocusResult::new(), FocusResult::new());
        let rx = fit(&cam, &light, &scene, &hinted, &mut x);
        let ry = fit(&narrowed, &light, &scene, &s, &mut y);
        prop_assert_eq!(rx.is_ok(), ry.is_ok(), "{:?} vs {:?}", rx, ry);
        if rx.is_err() {
            return Ok(());
        }
        prop_assert!(x.split_depths().iter().all(|d| (narrowed.near..=narrowed.far).contains(d)));
        if s.splits.scheme == SplitScheme::Optimal && s.splits.count > 1 {
            let log = narrowed.near * ((narrowed.far / narrowed.near).ln() / s.splits.count as f64).exp();
            prop_assert!(x.split_depths()[1] <= log, "{:?}: first plane beyond the logarithmic {}", x.split_depths(), log);
            return Ok(());
        }
        prop_assert_eq!(x.split_depths(), y.split_depths());
        prop_assert_eq!(x.maps().len(), y.maps().len());
        for (p, q) in x.maps().iter().zip(y.maps()) {
            prop_assert_eq!(p.fit.clip_from_world.to_cols_array().map(f64::to_bits), q.fit.clip_from_world.to_cols_array().map(f64::to_bits));
            prop_assert_eq!(p.body().vertices(), q.body().vertices());
        }
    }

    /// A visible depth range covering the whole view: the fit passes every
    /// check of `conservative_and_covering` for the whole camera (its
    /// outer splits reach `near` and `far`, and every visible point of each
    /// split's body is in its map), its inner planes are the hint-only
    /// fit's where the scheme places them from the range alone, and its
    /// inner splits' maps are that fit's, bit for bit.
    #[test]
    fn visible_depth_covering_the_view_places_over_the_range(((cam, scene, light), s) in framed_strategy(), a in 0.0..1.0f64, b in 0.0..1.0f64) {
        let (a, b) = (a.min(b), a.max(b));
        let z = |t: f64| cam.near + (cam.far - cam.near) * t;
        prop_assume!(z(a) < z(b));
        let range = Some([z(a), z(b)]);
        let covering = FocusSettings { visible_depth: range, visible_depth_coverage: DepthHintCoverage::View, ..s };
        let hinted = FocusSettings { visible_depth_coverage: DepthHintCoverage::Hint, ..covering };
        let (mut x, mut y) = (FocusResult::new(), FocusResult::new());
        fit(&cam, &light, &scene, &covering, &mut x).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        check_frame(&cam, &light, &scene, &covering, &x)?;
        fit(&cam, &light, &scene, &hinted, &mut y).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let (dx, dy, n) = (x.split_depths(), y.split_depths(), s.splits.count);
        prop_assert_eq!((dx[0], dx[n]), (cam.near, cam.far));
        // Optimal planes follow the outer splits' fits, and budgets their
        // predictions: the rest place and size from the range alone.
        if s.splits.scheme == SplitScheme::Optimal || s.texel_budget.is_some() {
            return Ok(());
        }
        prop_assert_eq!(&dx[1..n], &dy[1..n]);
        let inner = |r: &FocusResult| -> Vec<_> {
            r.maps().iter().filter(|m| m.split > 0 && m.split + 1 < n).map(|m| (m.split, m.face, m.fit.clip_from_world.to_cols_array().map(f64::to_bits))).collect()
        };
        prop_assert_eq!(inner(&x), inner(&y));
    }

    /// Optimal placement keeps the outer planes and never predicts worse
    /// than the practical planes it starts from: the largest
    /// `predict_aliasing` over its maps is at most the practical fit's. The
    /// maps themselves are checked with every other scheme's by
    /// `conservative_and_covering` (the generator mixes it in).
    #[test]
    fn optimal_planes_predict_no_worse_than_practical(((cam, scene, light), s) in framed_strategy(), count in 2..=6usize) {
        let s = FocusSettings { stable: false, splits: SplitSettings { count, scheme: SplitScheme::Practical { lambda: 0.5 }, delta_bias: 0.0 }, ..s };
        let optimal = FocusSettings { splits: SplitSettings { scheme: SplitScheme::Optimal, ..s.splits }, ..s };
        let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
        let (ra, rb) = (fit(&cam, &light, &scene, &s, &mut a), fit(&cam, &light, &scene, &optimal, &mut b));
        prop_assert_eq!(ra.is_ok(), rb.is_ok(), "{:?} vs {:?}", ra, rb);
        if ra.is_err() {
            return Ok(());
        }
        let (da, db) = (a.split_depths(), b.split_depths());
        prop_assert_eq!((da.len(), da[0], da[count]), (db.len(), db[0], db[count]));
        prop_assert!(db.windows(2).all(|w| w[0] <= w[1]), "{:?}", db);
        // NOTE: judged on the receivers the placement predicts on: the
        // scene box's faces, or its ground where the settings name one.
        let worst = |r: &FocusResult| r.maps().iter().filter_map(|m| predict_aliasing(m, &cam, &scene, &ReceiverBoxes::NONE, s.ground)).fold(0.0f64, |w, p| w.max(p.max));
        prop_assert!(worst(&b) <= worst(&a), "optimal {} > practical {}: {:?} vs {:?}", worst(&b), worst(&a), db, da);
    }

    /// Auto's every map is, bit for bit, the map one of the four methods
    /// fits for the same body (with `stable`, the stable uniform one), and
    /// says which, or a LiSPSM map whose warp is swept stronger than the
    /// one LiSPSM fits (its `warp_near` shorter).
    #[test]
    fn auto_picks_one_of_the_four_maps(((cam, scene, light), s) in framed_strategy()) {
        // Optimal placement gives each method its own planes: compare on
        // fixed ones.
        let scheme = if s.splits.scheme == SplitScheme::Optimal { SplitScheme::Log } else { s.splits.scheme };
        let s = FocusSettings { splits: SplitSettings { scheme, ..s.splits }, ..s };
        let auto = FocusSettings { method: Method::Auto, ..s };
        let mut a = FocusResult::new();
        fit(&cam, &light, &scene, &auto, &mut a).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let mut fits = Vec::new();
        let mut psm_unmatched = false;
        // Stable, Auto is the stable uniform map (a point light's on the
        // cube, which the other methods need not use).
        let methods: &[Method] = if s.stable { &[Method::Uniform] } else { &[Method::Uniform, Method::Psm, Method::Lispsm, Method::Tsm] };
        for &method in methods {
            let mut r = FocusResult::new();
            let mine = FocusSettings { method, ..s };
            // PSM narrows the visible range only when asked (psm.near/far), so its bodies are Auto's.
            fit(&cam, &light, &scene, &mine, &mut r).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            // NOTE: PSM keeps one map for a point light that the others
            // (and Auto) cover with six faces, a single map being wider
            // than a face; Auto's PSM faces then have no PSM fit to match.
            if method == Method::Psm && r.maps().len() != a.maps().len() {
                prop_assert!(a.notes.contains(Notes::POINT_AS_CUBE) && !r.notes.contains(Notes::POINT_AS_CUBE));
                psm_unmatched = true;
                continue;
            }
            prop_assert_eq!(r.maps().len(), a.maps().len());
            fits.push((method, r));
        }
        for (i, m) in a.maps().iter().enumerate().filter(|(_, m)| m.is_active()) {
            prop_assert!(m.fit.method != Method::Auto);
            if psm_unmatched && m.fit.method == Method::Psm {
                continue;
            }
            let bits = m.fit.clip_from_world.to_cols_array().map(f64::to_bits);
            let same = fits.iter().any(|(_, r)| {
                let c = &r.maps()[i].fit;
                c.clip_from_world.to_cols_array().map(f64::to_bits) == bits && c.method == m.fit.method
            });
            let lispsm = fits.iter().find(|(k, _)| *k == Method::Lispsm).map(|(_, r)| &r.maps()[i].fit);
            let swept = m.fit.method == Method::Lispsm
                && lispsm.is_some_and(|l| m.fit.warp_near > 0.0 && m.fit.warp_near < l.warp_near);
            prop_assert!(same || swept, "map {i} ({:?}, warp_near {}) is none of the four methods' maps", m.fit.method, m.fit.warp_near);
        }
    }

    /// Stable maps over a camera path (eight frames, the eye and the view
    /// direction moving a little each frame), fitted with and without a
    /// `FitState`: every frame passes `check_frame` (H in every map), and
    /// between two frames a stable map that keeps its texel grid (the same
    /// `w` row, image rows that differ by a multiple of it) moves by whole
    /// texels.
    #[test]
    fn stable_maps_move_by_whole_texels(((cam, scene, light), s) in framed_strategy(), method in prop_oneof![Just(Method::Uniform), Just(Method::Lispsm), Just(Method::Tsm)], step in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), turn in -0.02..0.02f64, held in any::<bool>()) {
        // Optimal placement and texel budgets refuse stable maps (their
        // planes and sizes move).
        let scheme = if s.splits.scheme == SplitScheme::Optimal { SplitScheme::Log } else { s.splits.scheme };
        let s = FocusSettings { stable: true, method, splits: SplitSettings { scheme, ..s.splits }, texel_budget: None, ..s };
        let res = s.resolution as f64;
        let scale = (scene.max - scene.min).length() * 1e-3;
        let mut prev: Option<(FocusResult, [WarpHold; MAX_MAPS])> = None;
        let mut state = FitState::default();
        for k in 0..8 {
            let t = k as f64;
            let rot = glam::DQuat::from_rotation_y(turn * t);
            let c = Camera { eye: cam.eye + DVec3::from(step) * (scale * t), forward: rot * cam.forward, up: rot * cam.up, ..cam };
            let mut out = FocusResult::new();
            let view = PreparedView::new(&c, &s).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            // NOTE: a state that holds nothing gives the stateless fit; it
            // tells which lattice steps a stable warp chose.
            if !held {
                state = FitState::default();
            }
            fit_prepared_with_state(&view, &light, &scene, &mut state, &mut out).map_err(|e| TestCaseError::fail(format!("{e}")))?;
            check_frame(&c, &light, &scene, &s, &out)?;
            let warps = state.to_warps();
            if let Some((p, prev_warps)) = &prev {
                prop_assert_eq!(p.maps().len(), out.maps().len());
                for (i, (a, b)) in p.maps().iter().zip(out.maps()).enumerate() {
                    if !(a.is_active() && b.is_active()) || a.notes().contains(Notes::STABLE_IGNORED) || b.notes().contains(Notes::STABLE_IGNORED) {
                        continue;
                    }
                    // A stable warp keeps its grid exactly while its lattice
                    // steps hold: then its rows must differ by whole texels.
                    // (Its rows alone cannot tell: with the warp's centre far
                    // out, a new extent can look like a multiple of `w`.)
                    let (wa, wb) = (prev_warps[i], warps[i]);
                    let warp_kept = wa.is_held() && wa == wb;
                    if (wa.is_held() || wb.is_held()) && !warp_kept {
                        continue;
                    }
                    let (ma, mb) = (&a.fit.clip_from_world, &b.fit.clip_from_world);
                    let w = ma.row(3);
                    if mb.row(3) != w {
                        prop_assert!(!warp_kept, "a kept warp changed its w row");
                        continue;
                    }
                    for r in [0, 1] {
                        // d = δ·w when the grid is kept; δ in texels is
                        // δ·res/2. NOTE: δ is read from the xyz parts (the
                        // directions, of the map's own scale) where w has
                        // them; the fourth entries carry the light's
                        // position, up to 1e8 here, and its rounding.
                        let (ra, rb) = (ma.row(r), mb.row(r));
                        let d = rb - ra;
                        let (dx, wx) = (d.truncate(), w.truncate());
                        let size = ra.truncate().length().max(rb.truncate().length());
                        let delta = if wx == DVec3::ZERO { d.w / w.w } else { dx.dot(wx) / wx.length_squared() };
                        if (dx - wx * delta).length() > 1e-9 * size {
                            prop_assert!(!warp_kept, "a kept warp's row {} is not a translation", r);
                            continue; // the extent or the frame changed: a new grid
                        }
                        let texels = delta * res / 2.0;
                        prop_assert!((texels - texels.round()).abs() <= 1e-6 * (1.0 + texels.abs()), "row {} moved by {} texels", r, texels);
                    }
                }
            }
            prev = Some((out, warps));
        }
    }

    /// One prepared view serves several lights with exactly the maps that
    /// separate `fit` calls give, or with the same error. The view is
    /// refilled in place from an earlier preparation for another camera and
    /// other settings, so nothing of that one may leak into the fits.
    #[test]
    fn prepared_view_fits_like_fit(cam in camera_strategy(), scene in scene_strategy(), lights in proptest::collection::vec(light_strategy(), 3), s in settings_strategy(), earlier in camera_strategy(), earlier_s in settings_strategy()) {
        let (mut a, mut b) = (FocusResult::new(), FocusResult::new());
        let mut view = match PreparedView::new(&earlier, &earlier_s) {
            Ok(v) => v,
            Err(_) => PreparedView::new(&earlier, &FocusSettings::default()).map_err(|e| TestCaseError::reject(format!("{e}")))?,
        };
        let prepared = view.prepare(&cam, &s);
        for light in &lights {
            let direct = fit(&cam, light, &scene, &s, &mut a);
            let from_view = fit_prepared(&view, light, &scene, &mut b);
            match (direct, from_view) {
                (Ok(()), Ok(())) => {}
                (Err(e), Err(f)) => {
                    prop_assert_eq!(e.to_string(), f.to_string());
                    if let Err(p) = &prepared {
                        prop_assert_eq!(p, &f);
                    }
                    continue;
                }
                (x, y) => return Err(TestCaseError::fail(format!("fit {x:?}, prepared {y:?}"))),
            }
            prop_assert_eq!(a.split_depths(), b.split_depths());
            if s.splits.scheme == SplitScheme::Optimal {
                // The view holds where the placement starts; each light
                // moves the inner planes.
                let (v, d) = (view.split_depths(), b.split_depths());
                prop_assert_eq!((v.len(), v[0], v[v.len() - 1]), (d.len(), d[0], d[d.len() - 1]));
            } else {
                prop_assert_eq!(view.split_depths(), b.split_depths());
            }
            prop_assert_eq!(a.split_clip_depths(), b.split_clip_depths());
            prop_assert_eq!((a.skipped, a.notes), (b.skipped, b.notes));
            prop_assert_eq!(a.maps().len(), b.maps().len());
            for (x, y) in a.maps().iter().zip(b.maps()) {
                prop_assert_eq!((x.fit.state, x.split, x.face, x.split_range, x.fit.depth_test, x.fit.method), (y.fit.state, y.split, y.face, y.split_range, y.fit.depth_test, y.fit.method));
                prop_assert_eq!(x.fit.clip_from_world.to_cols_array().map(f64::to_bits), y.fit.clip_from_world.to_cols_array().map(f64::to_bits));
                prop_assert_eq!(x.fit.clip_from_world_f32.to_cols_array().map(f32::to_bits), y.fit.clip_from_world_f32.to_cols_array().map(f32::to_bits));
                prop_assert_eq!(x.fit.texel_size.map(f64::to_bits), y.fit.texel_size.map(f64::to_bits));
                prop_assert_eq!(x.body().vertices(), y.body().vertices());
            }
        }
    }

    /// Caster culling never drops a box that meets the region that can
    /// shadow the map (H swept toward the light / hull(H ∪ l)), neither in
    /// f64 nor as an engine's f32 test of the caster planes with the
    /// documented margin.
    #[test]
    fn culling_is_conservative((cam, scene, light) in frame_strategy(), seed in any::<u64>(), sizes in proptest::collection::vec(0.0..3.0f64, 12)) {
        let s = FocusSettings::default();
        let mut out = FocusResult::new();
        fit(&cam, &light, &scene, &s, &mut out).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        for map in out.maps().iter().filter(|m| m.is_active()) {
            let region = CasterRegion::of_map(map);
            let pts = body_points(map.body(), 12, seed);
            for (k, p) in pts.iter().enumerate() {
                // A point of R: a point of H moved toward the light.
                let lp = light_point(&map.light);
                let q = if lp.w == 0.0 {
                    *p + lp.truncate() * (sizes[k % 12] * 40.0)
                } else {
                    *p + (lp.truncate() - *p) * (sizes[k % 12] / 3.0)
                };
                let e = DVec3::splat(sizes[(k + 5) % 12] * 0.5);
                // Boxes with q at a corner or inside.
                for b in [Aabb::new(q - e, q + e).unwrap(), Aabb::new(q, q + e).unwrap(), Aabb::new(q - e * 2.0, q).unwrap()] {
                    prop_assert!(region.may_shadow(&b), "box {:?} containing {q} of R was culled", b);
                    prop_assert!(!outside_in_f32(region.planes(), &b), "box {:?} containing {q} of R culled by the planes in f32", b);
                }
            }
        }
    }
}
