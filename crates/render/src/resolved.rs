//! Which pixels a shadow map resolves: the ground truth is the same at the pixel's point and at
//! every texel centre its shadow lookup reads.
//!
//! A lookup at a receiver point p compares a few texel centres of the map (one without PCF, the
//! 2×2 around p with the sampler's bilinear PCF, (2r+2)² with a kernel). The texel at centre c
//! holds the depth of the nearest surface on the map's ray through c, and the receiver-plane bias
//! compares it with the receiver's own plane at that ray. So what the map says at c is what the
//! ground truth says at q(c), the point where the ray through c meets p's tangent plane lifted by
//! the surface offset (where the main pass makes its lookup and the truth starts its rays); the
//! filtered result is a weighted mean of those answers. Where some q(c) is lit and p is not (or
//! the other way round), a shadow edge lies within the lookup's footprint, and the rendered
//! value may differ from the point-sampled truth however fine the map: that is filtering, not
//! an error. Where every q(c) agrees with p, a correct map and bias must give p's answer, so a
//! mismatch there is a lost caster, a wrong bias or a broken depth order.
//!
//! NOTE: the screen-space test ("off edges": one truth value over the (2r+1)² pixels around p) does
//! not see this when the screen samples the receiver more coarsely than the map in some direction
//! (a far, grazing ground): a shadow thinner than the pixel spacing but wider than a texel falls
//! between pixel centres, every truth sample around p is lit, and the lookup still reads it.

use glam::{DMat4, DVec3, DVec4};

use crate::frame::RenderOutput;
use crate::ground_truth::{GroundTruth, Visibility};
use crate::types::{Pcf, RenderSettings, ShadowMapSpec};

/// Texel centres read by one lookup at most: a kernel of radius 16 (`RenderSettings::validate`
/// caps the radius) reads 34² of them.
fn footprint(st: [f64; 2], pcf: Pcf, mut visit: impl FnMut([f64; 2]) -> bool) -> bool {
    match pcf {
        Pcf::Off => visit([st[0].floor() + 0.5, st[1].floor() + 0.5]),
        Pcf::Hardware2x2 | Pcf::Kernel { .. } => {
            let r = match pcf {
                Pcf::Kernel { radius } => radius as i64,
                _ => 0,
            };
            let base = [(st[0] - 0.5).floor() + 0.5, (st[1] - 0.5).floor() + 0.5];
            for dy in -r..=r + 1 {
                for dx in -r..=r + 1 {
                    if !visit([base[0] + dx as f64, base[1] + dy as f64]) {
                        return false;
                    }
                }
            }
            true
        }
    }
}

/// Where the map's ray through texel centre `c` (texel coordinates, rows top to bottom) meets the
/// plane through `p` with normal `n`; `None` when the ray is parallel to it or the map singular.
fn plane_point(world_from_clip: &DMat4, res: f64, c: [f64; 2], p: DVec3, n: DVec3) -> Option<DVec3> {
    let x = 2.0 * c[0] / res - 1.0;
    let y = 1.0 - 2.0 * c[1] / res;
    // Two homogeneous points of the ray (depths 0 and 1 of the map); either may be at infinity.
    let a = *world_from_clip * DVec4::new(x, y, 0.0, 1.0);
    let b = *world_from_clip * DVec4::new(x, y, 1.0, 1.0);
    let plane = n.extend(-n.dot(p));
    let (pa, pb) = (plane.dot(a), plane.dot(b));
    // The point a·pb − b·pa lies on the plane (homogeneous line–plane intersection).
    let q = a * pb - b * pa;
    if !(q.w.abs() > 0.0) {
        return None;
    }
    let q = q.truncate() / q.w;
    q.is_finite().then_some(q)
}

/// Per pixel: whether the map it used resolves it (see the module docs). Only pixels for which
/// `candidate` holds are examined (the others come out `false`): the truth costs a ray per
/// texel centre.
pub(crate) fn resolved_mask(
    out: &RenderOutput,
    truth: &[Visibility],
    maps: &[ShadowMapSpec],
    settings: &RenderSettings,
    gt: &GroundTruth,
    candidate: &[bool],
) -> Vec<bool> {
    let matrices: Vec<(DMat4, DMat4)> = maps
        .iter()
        .map(|m| {
            let c = m.world_to_clip.as_dmat4();
            (c, c.inverse())
        })
        .collect();
    let lookup = Lookup { out, truth, maps, matrices: &matrices, settings, gt };
    let n = truth.len();
    let mut mask = vec![false; n];
    let threads = std::thread::available_parallelism().map(|t| t.get()).unwrap_or(1).clamp(1, 64);
    let chunk = n.div_ceil(threads).max(1);
    std::thread::scope(|s| {
        for (k, slot) in mask.chunks_mut(chunk).enumerate() {
            let start = k * chunk;
            let lookup = &lookup;
            s.spawn(move || {
                for (j, m) in slot.iter_mut().enumerate() {
                    let i = start + j;
                    if candidate[i] {
                        *m = lookup.pixel_resolved(i);
                    }
                }
            });
        }
    });
    mask
}

/// What a pixel's shadow lookup reads: the frame, its truth, the maps with their clip matrices
/// (and inverses), and the filters.
struct Lookup<'a> {
    out: &'a RenderOutput,
    truth: &'a [Visibility],
    maps: &'a [ShadowMapSpec],
    matrices: &'a [(DMat4, DMat4)],
    settings: &'a RenderSettings,
    gt: &'a GroundTruth,
}

impl Lookup<'_> {
    fn pixel_resolved(&self, i: usize) -> bool {
        let Lookup { out, truth, maps, matrices, settings, gt } = *self;
        let t = truth[i];
        if !matches!(t, Visibility::Lit | Visibility::Occluded) || out.split[i] < 0 {
            return false;
        }
        let map = out.split[i] as usize;
        let w = out.world[i];
        let p = DVec3::new(w[0] as f64, w[1] as f64, w[2] as f64);
        let nn = out.normal[i];
        let n = DVec3::new(nn[0] as f64, nn[1] as f64, nn[2] as f64).normalize_or_zero();
        if n == DVec3::ZERO {
            return false;
        }
        let agrees = |q: DVec3| gt.classify(q, n, &out.light) == t;
        // The main pass looks p up lifted off its surface by the surface offset (as the truth
        // casts its ray): its taps compare against the plane through the lifted point.
        let lifted = p + n * gt.surface_offset();
        let tap_agrees = |q: DVec3| gt.classify_lifted(q, n, &out.light) == t;
        let map_agrees = |k: usize| {
            let (Some((m, inv)), Some(spec)) = (matrices.get(k), maps.get(k)) else {
                return false;
            };
            let res = spec.resolution_or(settings.shadow_resolution) as f64;
            let c = *m * lifted.extend(1.0);
            if !(c.w > 0.0) {
                return false;
            }
            let st = [res * (0.5 + 0.5 * c.x / c.w), res * (0.5 - 0.5 * c.y / c.w)];
            footprint(st, settings.pcf, |centre| plane_point(inv, res, centre, lifted, n).is_some_and(tap_agrees))
        };
        let blended = blended_with(out, maps, matrices, settings, map, p);
        map_agrees(map) && blended.is_none_or(map_agrees) && blur_agrees(settings, p, n, agrees)
    }
}

/// The map a pixel in the blend band at the far end of its split fades into: the next one that
/// contains p, as in the main pass.
fn blended_with(
    out: &RenderOutput,
    maps: &[ShadowMapSpec],
    matrices: &[(DMat4, DMat4)],
    settings: &RenderSettings,
    map: usize,
    p: DVec3,
) -> Option<usize> {
    let band = settings.blend_band as f64;
    let [s0, s1] = maps.get(map)?.split.map(|v| v as f64);
    let len = (s1 - s0) * band;
    let depth = out.camera.view_depth(p);
    if !(band > 0.0 && len > 0.0 && depth > s1 - len) {
        return None;
    }
    (map + 1..maps.len()).find(|&j| {
        let c = matrices[j].0 * p.extend(1.0);
        c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w
    })
}

/// The eye-space blur mixes the shadow term of pixels up to its world radius away on screen: the
/// truth must also agree at that radius on p's tangent plane (eight directions).
fn blur_agrees(settings: &RenderSettings, p: DVec3, n: DVec3, agrees: impl Fn(DVec3) -> bool) -> bool {
    let Some(blur) = settings.blur else {
        return true;
    };
    let r = blur.world_radius as f64;
    let (t1, t2) = n.any_orthonormal_pair();
    (0..8).all(|k| {
        let a = k as f64 * std::f64::consts::FRAC_PI_4;
        agrees(p + r * (a.cos() * t1 + a.sin() * t2))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn centres(st: [f64; 2], pcf: Pcf) -> Vec<[f64; 2]> {
        let mut v = Vec::new();
        assert!(footprint(st, pcf, |c| {
            v.push(c);
            true
        }));
        v
    }

    #[test]
    fn footprints_are_the_texel_centres_each_filter_reads() {
        // Nearest: the texel the point lies in.
        assert_eq!(centres([3.2, 7.9], Pcf::Off), vec![[3.5, 7.5]]);
        // Bilinear: the 2×2 centres around the point.
        assert_eq!(centres([3.2, 7.9], Pcf::Hardware2x2), vec![[2.5, 7.5], [3.5, 7.5], [2.5, 8.5], [3.5, 8.5]]);
        // A radius-1 kernel: 3×3 bilinear lookups one texel apart read 4×4 centres.
        let k = centres([3.7, 7.2], Pcf::Kernel { radius: 1 });
        assert_eq!(k.len(), 16);
        assert_eq!((k[0], k[15]), ([2.5, 5.5], [5.5, 8.5]));
        // Every centre lies within the kernel's reach of the point.
        assert!(k.iter().all(|c| (c[0] - 3.7).abs() <= 2.0 && (c[1] - 7.2).abs() <= 2.0));
        // A refused centre stops the walk.
        let mut seen = 0;
        assert!(!footprint([3.2, 7.9], Pcf::Kernel { radius: 2 }, |_| {
            seen += 1;
            seen < 3
        }));
        assert_eq!(seen, 3);
    }

    #[test]
    fn a_texel_ray_meets_the_receiver_plane_where_the_map_projects_it() {
        // An orthographic map looking down −y over x, z ∈ [−4, 4] (x right, −z up in the map) and
        // a perspective one from (0, 10, 0); a tilted receiver plane through (1, 2, −0.5).
        let ortho = glam::dcamera::rh::proj::directx::orthographic(-4.0, 4.0, -4.0, 4.0, 0.0, 20.0)
            * glam::dcamera::rh::view::look_to_mat4(DVec3::new(0.0, 10.0, 0.0), DVec3::NEG_Y, DVec3::NEG_Z);
        let persp = glam::dcamera::rh::proj::directx::perspective(1.2, 1.0, 0.5, 30.0)
            * glam::dcamera::rh::view::look_to_mat4(DVec3::new(0.0, 10.0, 0.0), DVec3::NEG_Y, DVec3::NEG_Z);
        let (p, n) = (DVec3::new(1.0, 2.0, -0.5), DVec3::new(0.3, 1.0, -0.2).normalize());
        let res = 256.0;
        for m in [ortho, persp] {
            let inv = m.inverse();
            for c in [[10.5, 200.5], [128.5, 3.5], [250.5, 128.5]] {
                let q = plane_point(&inv, res, c, p, n).expect("the ray crosses the plane");
                assert!((q - p).dot(n).abs() < 1e-9, "on the plane");
                let k = m * q.extend(1.0);
                let st = [res * (0.5 + 0.5 * k.x / k.w), res * (0.5 - 0.5 * k.y / k.w)];
                assert!((st[0] - c[0]).abs() < 1e-6 && (st[1] - c[1]).abs() < 1e-6, "{st:?} against {c:?}");
            }
        }
        // A plane parallel to the map's rays (a vertical wall under an orthographic map) is met
        // nowhere or everywhere: no point.
        let wall = plane_point(&ortho.inverse(), res, [10.5, 20.5], p, DVec3::X);
        assert!(wall.is_none(), "{wall:?}");
    }
}
