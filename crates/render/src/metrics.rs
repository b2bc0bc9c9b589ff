//! Per-frame measurements: aliasing, agreement with ground truth, split coverage, casters, time.

use glam::DVec3;

use crate::frame::{RenderOutput, RenderRequest};
use crate::gpu::AdapterSummary;
use crate::ground_truth::Visibility;
use crate::image::PixelMatch;
use crate::resolved::resolved_mask;
use crate::stats::{AliasingStats, CasterStats, CoverageStats, MismatchStats, RenderMetrics, Timings, ADEQUATE_ALIASING};

fn pixel_pos(w: &[f32; 4]) -> DVec3 {
    DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64)
}

/// The aliasing of every pixel the statistics count (a visible receiver
/// that faces the light, inside a spot's cone, served by a map), with the
/// map that serves it and the factor `√(cos θ / cos φ)` that takes the
/// angle terms out of it (θ, φ: the light's and the eye's angles of
/// incidence; every map projects along the light's rays).
fn counted_aliasing<'a>(req: &'a RenderRequest, out: &'a RenderOutput) -> impl Iterator<Item = (i32, f64, f64)> + 'a {
    out.world.iter().enumerate().filter_map(|(i, w)| {
        let e = out.aliasing[i];
        // NaN (background) and −1 (uncovered) both fail `e >= 0`.
        if w[3] != 1.0 || e.is_nan() || e < 0.0 {
            return None;
        }
        let p = pixel_pos(w);
        let n = DVec3::new(out.normal[i][0] as f64, out.normal[i][1] as f64, out.normal[i][2] as f64);
        let (l, _) = req.light.toward_light(p);
        let angles = angle_factor(n, l, (req.camera.eye - p).normalize());
        (n.dot(l) > 0.0 && req.light.in_spot(p)).then_some((out.split[i], e as f64, angles))
    })
}

/// `√(cos θ / cos φ)` for a receiver with normal `n`, `l` and `v` the unit
/// directions toward the light and the eye: a receiver's aliasing is that of
/// one facing both times `√(cos φ / cos θ)` (its image on the screen, in
/// pixels, shrinks with cos φ, its image in the map, in texels, with
/// cos θ), so this factor takes the angles out.
fn angle_factor(n: DVec3, l: DVec3, v: DVec3) -> f64 {
    (n.dot(l).abs() / n.dot(v).abs()).sqrt()
}

/// Per map, the largest aliasing among the pixels it serves (NaN for a map
/// that serves none).
pub(crate) fn map_aliasing_max(req: &RenderRequest, out: &RenderOutput) -> Vec<f64> {
    let mut max = vec![f64::NAN; req.maps.len()];
    for (map, e, _) in counted_aliasing(req, out) {
        if let Some(m) = usize::try_from(map).ok().and_then(|k| max.get_mut(k)) {
            *m = if m.is_nan() { e } else { m.max(e) };
        }
    }
    max
}

pub(crate) fn aliasing_stats(req: &RenderRequest, out: &RenderOutput) -> AliasingStats {
    let mut v: Vec<f64> = counted_aliasing(req, out).map(|(_, e, _)| e).collect();
    let angle_free_max = counted_aliasing(req, out).map(|(_, e, g)| e * g).fold(f64::NAN, f64::max);
    let s = &req.settings;
    let texels = req.map_texels();
    let c = &req.camera;
    let bound = crate::bound::min_max_aliasing(s.width, s.height, c.fovy, c.near, c.far, texels).unwrap_or(f64::NAN);
    if v.is_empty() {
        let nan = f64::NAN;
        return AliasingStats { max: nan, p95: nan, mean: nan, pixels: 0, bound, ratio: nan, angle_free_max: nan, angle_free_ratio: nan };
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let k = ((v.len() as f64 * 0.95).ceil() as usize).clamp(1, v.len()) - 1;
    let (_, p95, _) = v.select_nth_unstable_by(k, |a, b| a.total_cmp(b));
    let p95 = *p95;
    let max = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    AliasingStats {
        max,
        p95,
        mean,
        pixels: v.len() as u64,
        bound,
        ratio: max / bound,
        angle_free_max,
        angle_free_ratio: angle_free_max / bound,
    }
}

/// Classifies each pixel against the ground truth (which must be present).
///
/// Back-facing and outside-spot pixels count as agreeing: the renderer and the ground truth take
/// those decisions from the same normal and the same pyramid, so only the shadow test is judged.
pub fn pixel_matches(out: &RenderOutput, truth: &[Visibility], edge_radius: u32) -> Vec<PixelMatch> {
    let (w, h) = (out.width as i64, out.height as i64);
    let r = edge_radius as i64;
    let lit: Vec<bool> = truth.iter().map(|t| t.is_lit()).collect();
    let bg: Vec<bool> = truth.iter().map(|t| *t == Visibility::Background).collect();
    let mut res = Vec::with_capacity(truth.len());
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if truth[i] == Visibility::Background {
                res.push(PixelMatch::Background);
                continue;
            }
            if !truth[i].shows_shadow() {
                res.push(PixelMatch::Agree);
                continue;
            }
            let rendered_lit = out.shadow[i] >= 0.5;
            if rendered_lit == lit[i] {
                res.push(PixelMatch::Agree);
                continue;
            }
            // Edge: any neighbour with another truth value, background, or off-screen.
            let mut edge = false;
            'n: for dy in -r..=r {
                for dx in -r..=r {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx < 0 || yy < 0 || xx >= w || yy >= h {
                        edge = true;
                        break 'n;
                    }
                    let j = (yy * w + xx) as usize;
                    if bg[j] || lit[j] != lit[i] {
                        edge = true;
                        break 'n;
                    }
                }
            }
            res.push(if rendered_lit { PixelMatch::FalseLight { edge } } else { PixelMatch::FalseShadow { edge } });
        }
    }
    res
}

/// Pixels that are off edges (same ground truth over the neighbourhood), for the denominator.
fn off_edge_mask(out: &RenderOutput, truth: &[Visibility], r: u32) -> Vec<bool> {
    let (w, h) = (out.width as i64, out.height as i64);
    let r = r as i64;
    let lit: Vec<bool> = truth.iter().map(|t| t.is_lit()).collect();
    let mut mask = vec![false; truth.len()];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if truth[i] == Visibility::Background {
                continue;
            }
            let mut ok = true;
            'n: for dy in -r..=r {
                for dx in -r..=r {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx < 0 || yy < 0 || xx >= w || yy >= h {
                        ok = false;
                        break 'n;
                    }
                    let j = (yy * w + xx) as usize;
                    if truth[j] == Visibility::Background || lit[j] != lit[i] {
                        ok = false;
                        break 'n;
                    }
                }
            }
            mask[i] = ok;
        }
    }
    mask
}

/// `resolved(candidates)` says which of the candidate pixels (off edges, aliasing at most
/// [`ADEQUATE_ALIASING`]) the map resolves (see `resolved.rs`); they make the adequate set.
pub(crate) fn mismatch_stats(
    out: &RenderOutput,
    truth: &[Visibility],
    edge_radius: u32,
    resolved: impl FnOnce(&[bool]) -> Vec<bool>,
) -> MismatchStats {
    let m = pixel_matches(out, truth, edge_radius);
    let off = off_edge_mask(out, truth, edge_radius);
    // NOTE: NaN (background) and −1 (no map) fail both comparisons.
    let sampled = |i: usize| off[i] && out.aliasing[i] >= 0.0 && out.aliasing[i] <= ADEQUATE_ALIASING;
    let candidates: Vec<bool> = (0..m.len()).map(sampled).collect();
    let resolved = resolved(&candidates);
    let mut s = MismatchStats::default();
    for (i, pm) in m.iter().enumerate() {
        if *pm == PixelMatch::Background {
            continue;
        }
        s.pixels += 1;
        if off[i] {
            s.off_edge_pixels += 1;
        }
        let adequate = candidates[i] && resolved.get(i).copied().unwrap_or(false);
        if adequate {
            s.adequate_pixels += 1;
        }
        let bad = match pm {
            PixelMatch::FalseShadow { .. } => {
                s.false_shadow += 1;
                true
            }
            PixelMatch::FalseLight { .. } => {
                s.false_light += 1;
                true
            }
            _ => false,
        };
        if bad {
            s.mismatched += 1;
            if off[i] {
                s.off_edge_mismatched += 1;
            }
            if adequate {
                s.adequate_mismatched += 1;
            }
        }
    }
    s.rate = if s.pixels > 0 { s.mismatched as f64 / s.pixels as f64 } else { 0.0 };
    s.rate_off_edges = if s.off_edge_pixels > 0 { s.off_edge_mismatched as f64 / s.off_edge_pixels as f64 } else { 0.0 };
    s.rate_adequate = if s.adequate_pixels > 0 { s.adequate_mismatched as f64 / s.adequate_pixels as f64 } else { 0.0 };
    s
}

pub(crate) fn coverage_stats(req: &RenderRequest, out: &RenderOutput) -> (CoverageStats, Vec<u64>) {
    let mut c = CoverageStats::default();
    let mut per = vec![0u64; req.maps.len()];
    for (i, w) in out.world.iter().enumerate() {
        if w[3] == 0.0 {
            continue;
        }
        let s = out.split[i];
        if s >= 0 && (s as usize) < per.len() {
            per[s as usize] += 1;
        }
        if !req.light.in_spot(pixel_pos(w)) {
            continue;
        }
        c.required += 1;
        if s >= 0 {
            c.covered += 1;
        }
    }
    c.uncovered = c.required - c.covered;
    c.complete = c.uncovered == 0;
    (c, per)
}

pub(crate) fn compute(
    req: &RenderRequest,
    out: &RenderOutput,
    adapter: &AdapterSummary,
    depth_clamp: bool,
    draw_calls: &[u32],
    t: Timings,
) -> RenderMetrics {
    let (coverage, split_pixels) = coverage_stats(req, out);
    let mut union: Vec<u32> = req.maps.iter().flat_map(|m| m.casters.iter().copied()).collect();
    union.sort_unstable();
    union.dedup();
    let per_map = req
        .maps
        .iter()
        .map(|m| {
            let mut c = m.casters.clone();
            c.sort_unstable();
            c.dedup();
            c.len() as u32
        })
        .collect();
    RenderMetrics {
        scene: req.scene.name.clone(),
        width: out.width,
        height: out.height,
        shadow_resolution: req.settings.shadow_resolution,
        maps: req.maps.len(),
        adapter: adapter.clone(),
        depth_clamp,
        shadow_buffer_test: req.shadow_buffer_test(),
        render_ms: t.shadow_ms + t.main_ms,
        shadow_pass_ms: t.shadow_ms,
        main_pass_ms: t.main_ms,
        shadow_gpu_ms: t.shadow_gpu_ms,
        main_gpu_ms: t.main_gpu_ms,
        readback_ms: t.readback_ms,
        ground_truth_ms: t.ground_truth_ms,
        aliasing: aliasing_stats(req, out),
        mismatch: out.truth.as_ref().map(|tr| {
            mismatch_stats(out, tr, req.settings.edge_radius, |candidates| {
                // The truth was cast through this cached ground truth a moment ago.
                match req.scene.ground_truth() {
                    Ok(gt) => resolved_mask(out, tr, req.maps, &req.settings, &gt, candidates),
                    Err(_) => vec![false; candidates.len()],
                }
            })
        }),
        coverage,
        casters: CasterStats { per_map, draw_calls: draw_calls.to_vec(), drawn: union.len() as u32, total: req.scene.objects.len() as u32 },
        split_pixels,
        map_aliasing_max: map_aliasing_max(req, out),
        map_utilisation: req.utilisation.to_vec(),
        utilisation_min: utilisation_min(req.utilisation),
        utilisation_mean: utilisation_mean(req.utilisation),
        settings: req.settings,
    }
}

fn utilisation_min(u: &[f64]) -> Option<f64> {
    u.iter().copied().reduce(f64::min)
}

fn utilisation_mean(u: &[f64]) -> Option<f64> {
    (!u.is_empty()).then(|| u.iter().sum::<f64>() / u.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::types::{CameraSpec, LightSpec};

    /// A w×h frame whose left half is truly lit and right half truly occluded, rendered all lit.
    fn frame(w: u32, h: u32) -> (RenderOutput, Vec<Visibility>) {
        let n = (w * h) as usize;
        let truth: Vec<Visibility> = (0..n).map(|i| if (i as u32 % w) < w / 2 { Visibility::Lit } else { Visibility::Occluded }).collect();
        let cam = CameraSpec { eye: DVec3::ZERO, forward: DVec3::Z, up: DVec3::Y, fovy: 1.0, near: 0.1, far: 10.0 };
        let out = RenderOutput {
            width: w,
            height: h,
            color: Image::new(w, h, [0, 0, 0, 255]),
            world: vec![[0.0, 0.0, 1.0, 1.0]; n],
            normal: vec![[0.0, 0.0, -1.0, 0.0]; n],
            aliasing: vec![1.0; n],
            split: vec![0; n],
            shadow: vec![1.0; n],
            truth: Some(truth.clone()),
            shadow_maps: Vec::new(),
            visible_depth: None,
            receiver_slices: None,
            surface_offset: 0.0,
            camera: cam,
            light: LightSpec::Directional { direction: DVec3::Z },
            metrics: RenderMetrics::default(),
        };
        (out, truth)
    }

    #[test]
    fn mismatches_split_into_edge_and_off_edge() {
        let (out, truth) = frame(10, 6);
        let s = mismatch_stats(&out, &truth, 1, <[bool]>::to_vec);
        // Every right-half pixel is a false light; off-edge ones are the interior of the right
        // half: columns 6..=8 of rows 1..=4 (column 5 touches the lit half, 9 and rows 0, 5 the border).
        assert_eq!(s.pixels, 60);
        assert_eq!((s.mismatched, s.false_light, s.false_shadow), (30, 30, 0));
        assert_eq!(s.off_edge_mismatched, 3 * 4);
        // Off-edge pixels of both halves: columns 1..=3 and 6..=8, rows 1..=4.
        assert_eq!(s.off_edge_pixels, 2 * 3 * 4);
        assert!((s.rate - 0.5).abs() < 1e-12 && (s.rate_off_edges - 0.5).abs() < 1e-12);
        let m = pixel_matches(&out, &truth, 1);
        assert_eq!(m[0], PixelMatch::Agree);
        assert_eq!(m[5], PixelMatch::FalseLight { edge: true });
        assert_eq!(m[10 + 7], PixelMatch::FalseLight { edge: false });
    }

    #[test]
    fn adequate_pixels_are_off_edges_and_resolved_by_the_map() {
        let (mut out, truth) = frame(10, 6);
        // Aliasing per column: 0.5, 1, …, 5 screen pixels per texel; row 2 has no map (−1).
        for y in 0..6 {
            for x in 0..10 {
                out.aliasing[y * 10 + x] = if y == 2 { -1.0 } else { 0.5 * (x + 1) as f32 };
            }
        }
        let s = mismatch_stats(&out, &truth, 1, <[bool]>::to_vec);
        // Off edges: columns 1..=3 and 6..=8 of rows 1..=4; e ≤ 2 keeps columns 1..=3 (e = 1,
        // 1.5, 2: the bound is inclusive); row 2 is uncovered. All of them are truly lit and
        // rendered lit.
        assert_eq!(s.adequate_pixels, 3 * 3);
        assert_eq!(s.adequate_mismatched, 0);
        assert_eq!(s.rate_adequate, 0.0);
        // Finer maps on the right half: its off-edge pixels (all false lights) become adequate.
        for y in 0..6 {
            for x in 5..10 {
                out.aliasing[y * 10 + x] = if y == 2 { f32::NAN } else { 2.0 };
            }
        }
        let s = mismatch_stats(&out, &truth, 1, <[bool]>::to_vec);
        assert_eq!((s.adequate_pixels, s.adequate_mismatched), (2 * 3 * 3, 3 * 3));
        assert!((s.rate_adequate - 0.5).abs() < 1e-12);
        // Just above the bound nothing on the right counts.
        for y in [0, 1, 3, 4, 5] {
            for x in 5..10 {
                out.aliasing[y * 10 + x] = 2.0001;
            }
        }
        let s = mismatch_stats(&out, &truth, 1, <[bool]>::to_vec);
        assert_eq!((s.adequate_pixels, s.adequate_mismatched), (3 * 3, 0));
    }

    #[test]
    fn adequate_rate_reaches_metrics_json() {
        let (mut out, truth) = frame(10, 6);
        out.metrics.mismatch = Some(mismatch_stats(&out, &truth, 1, <[bool]>::to_vec));
        let j = crate::output::metrics_json(&out.metrics, None);
        let m = &j["mismatch"];
        assert_eq!(m["adequate_pixels"].as_u64(), Some(2 * 3 * 4));
        assert_eq!(m["adequate_mismatched"].as_u64(), Some(3 * 4));
        assert!((m["rate_adequate"].as_f64().unwrap() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_angle_factor_undoes_the_angles_of_incidence() {
        let (n, up) = (DVec3::Y, DVec3::Y);
        let at = |deg: f64| DVec3::new(deg.to_radians().sin(), deg.to_radians().cos(), 0.0);
        assert!((angle_factor(n, up, up) - 1.0).abs() < 1e-15);
        // Light at 60° (cos ½), eye head-on: a texel covers twice the
        // receiver, the aliasing is √2 times a facing receiver's; the factor
        // is √½.
        assert!((angle_factor(n, at(60.0), up) - 0.5f64.sqrt()).abs() < 1e-12);
        // Eye at 60°, light head-on: the other way.
        assert!((angle_factor(n, up, at(60.0)) - 2f64.sqrt()).abs() < 1e-12);
        // The normal's side does not matter.
        assert_eq!(angle_factor(-n, at(30.0), at(45.0)), angle_factor(n, at(30.0), at(45.0)));
    }

    #[test]
    fn utilisation_summaries() {
        assert_eq!(utilisation_min(&[]), None);
        assert_eq!(utilisation_mean(&[]), None);
        assert_eq!(utilisation_min(&[0.5, 0.25, 0.75]), Some(0.25));
        assert_eq!(utilisation_mean(&[0.5, 0.25, 0.75]), Some(0.5));
        let m = RenderMetrics {
            map_utilisation: vec![0.5, 0.25],
            utilisation_min: Some(0.25),
            utilisation_mean: Some(0.375),
            ..Default::default()
        };
        let j = crate::output::metrics_json(&m, None);
        assert_eq!(j["map_utilisation"], serde_json::json!([0.5, 0.25]));
        assert_eq!(j["utilisation_mean"].as_f64(), Some(0.375));
        assert_eq!(j["utilisation_min"].as_f64(), Some(0.25));
    }

    #[test]
    fn back_facing_pixels_are_not_judged() {
        let (out, mut truth) = frame(4, 4);
        for t in truth.iter_mut() {
            *t = Visibility::BackFacing;
        }
        let s = mismatch_stats(&out, &truth, 1, <[bool]>::to_vec);
        assert_eq!(s.mismatched, 0);
        assert_eq!(s.pixels, 16);
    }
}
