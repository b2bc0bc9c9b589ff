//! A map's predicted aliasing along the view, in absolute terms: what the
//! renderer measures per pixel, for receivers facing the camera.
//!
//! At a point `p` on a receiver with unit normal `t`, the screen pixels per
//! texel are `e(p) = √(a_C(p, t) / a_M(p, t)) · √(W·H) / T`, where `a_C`
//! and `a_M` are how much the camera's and the map's clip matrices magnify
//! areas on the receiver's plane into their `[−1, 1]²` images
//! (`project::image_area_scale`), and a `W×H` image and a `T×T` map turn
//! those into pixels (`W·H/4` per unit area) and texels (`T²/4`). The
//! prediction keeps the dimensionless first factor; [`ViewAliasing::in_pixels`]
//! applies the second.
//!
//! The receiver is taken facing the camera (`t` along the camera ray), as
//! the logarithmic bound of the renderer (`bound.rs`) takes it: the angle
//! terms are then 1, and a real receiver the light grazes aliases more by
//! exactly its own angle term. The points are where receivers can be: on
//! each of nine camera rays (the image's corners, edge midpoints and
//! centre), the part inside the split's depth range and the bounding box of
//! the map's body `H_i` (a visible receiver lies in `V_i ∩ S`, and every
//! point of `R_i` lies in `H_i`), sampled at `DEPTH_SAMPLES` depths spaced
//! evenly in log depth from its near end to its far end.
//!
//! NOTE: along one ray, with `t` fixed, `a_C ∝ 1/z²` and
//! `a_M = |L(p)·t| / w_M(p)³` with `L` and `w_M` affine in `p` (the quotient
//! rule applied to the map's rows), so `e² ∝ w_M³ / (z² |L·t|)`: a uniform
//! map's maximum is at the near end, a warp's may lie inside, which the
//! inner samples catch. Nine rays and five depths are a prediction, not a
//! bound: a receiver between the rays can alias more.

use crate::predict::clip_ray;
use crate::project::{image_area_scale, post_perspective};
use crate::result::{CubeFace, MapState, ShadowMap};
use crate::MAX_SPLITS;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Camera, CameraBasis, Light};

/// Depths sampled on each camera ray, from the segment's near end to its
/// far end.
pub(crate) const DEPTH_SAMPLES: usize = 5;

/// A map's predicted aliasing over its split for receivers facing the
/// camera (see [`predict_aliasing`]), dimensionless: multiply by
/// `√(W·H) / T` ([`ViewAliasing::in_pixels`]) for screen pixels per texel
/// of a `W×H` image and a `T×T` map.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViewAliasing {
    /// The largest value at the near end of the receivers' depth range in
    /// the split (over the nine rays).
    pub near: f64,
    /// The largest value at the far end.
    pub far: f64,
    /// The largest value over every sample of the split.
    pub max: f64,
}

impl ViewAliasing {
    /// In screen pixels per texel, for a `width × height` image and a map of
    /// `texels` per side.
    pub fn in_pixels(self, width: f64, height: f64, texels: f64) -> ViewAliasing {
        let k = (width * height).sqrt() / texels;
        ViewAliasing { near: self.near * k, far: self.far * k, max: self.max * k }
    }

    /// The larger of two predictions, side by side (a split's maps).
    pub(crate) fn worst(self, other: ViewAliasing) -> ViewAliasing {
        ViewAliasing { near: self.near.max(other.near), far: self.far.max(other.far), max: self.max.max(other.max) }
    }
}

/// The predicted aliasing of `map` for the view of `camera` (the camera the
/// map was fitted for, with the full depth range: the split's comes from
/// the map), for receivers facing the camera; `None` for a map with nothing
/// to render, or where no camera ray meets its body's box in the split.
///
/// This is the renderer's measured quantity (`metrics.json`'s `aliasing`)
/// up to the receivers' angle terms, computed from the matrices alone, so it
/// can choose between parameterisations and place splits before anything is
/// rendered. For a cube face only the points the face serves
/// ([`CubeFace::toward`]) count.
pub fn predict_aliasing(map: &ShadowMap, camera: &Camera) -> Option<ViewAliasing> {
    let basis = camera.basis().ok()?;
    map_aliasing(map, camera, &basis)
}

/// [`predict_aliasing`] with the camera's basis given.
pub(crate) fn map_aliasing(map: &ShadowMap, camera: &Camera, basis: &CameraBasis) -> Option<ViewAliasing> {
    if map.fit.state != MapState::Active || map.body().is_empty() {
        return None;
    }
    let (lo, hi) = bounds(map.body().vertices());
    let face = match (map.face, &map.light) {
        (Some(f), Light::Spot { position, .. }) => Some((f, *position)),
        _ => None,
    };
    let split = Camera { near: map.split_range[0], far: map.split_range[1], ..*camera };
    rays_aliasing(&map.fit.clip_from_world, &split, basis, (lo, hi), face)
}

/// The prediction of the clip matrix `m` over the receivers of `camera`'s
/// depth range inside the box `[lo, hi]`, counting only points whose
/// direction from the light `face.1` picks the cube face `face.0`.
fn rays_aliasing(
    m: &DMat4,
    camera: &Camera,
    basis: &CameraBasis,
    (lo, hi): (DVec3, DVec3),
    face: Option<(CubeFace, DVec3)>,
) -> Option<ViewAliasing> {
    let camera_clip = post_perspective(camera, basis, 0.0);
    let ty = (0.5 * camera.fovy).tan();
    let tx = ty * camera.aspect;
    let mut out: Option<ViewAliasing> = None;
    for gy in [-1.0, 0.0, 1.0] {
        for gx in [-1.0, 0.0, 1.0] {
            // The ray eye + z·d, z the view depth (d·forward = 1).
            let d = basis.forward + basis.right * (gx * tx) + basis.up * (gy * ty);
            let Some(seg) = clip_ray(camera.eye, d, camera.near, camera.far, lo, hi) else { continue };
            let facing = -d / d.length();
            let mut ray = ViewAliasing { near: f64::NAN, far: f64::NAN, max: 0.0 };
            let mut seen = false;
            for k in 0..DEPTH_SAMPLES {
                let t = k as f64 / (DEPTH_SAMPLES - 1) as f64;
                // NOTE: entry·(exit/entry)^t keeps both ends exact (t = 0, 1).
                let z = if k + 1 == DEPTH_SAMPLES { seg.depth } else { seg.entry * (t * (seg.depth / seg.entry).ln()).exp() };
                let p = camera.eye + d * z;
                if face.is_some_and(|(f, l)| CubeFace::toward(p - l) != f) {
                    continue;
                }
                let e = (image_area_scale(&camera_clip, p, facing) / image_area_scale(m, p, facing)).sqrt();
                // NOTE: a point the map cannot see (w ≤ 0) gives NaN: it
                // makes the prediction infinite, never smaller.
                let e = if e.is_nan() { f64::INFINITY } else { e };
                if k == 0 {
                    ray.near = e;
                }
                if k + 1 == DEPTH_SAMPLES {
                    ray.far = e;
                }
                ray.max = ray.max.max(e);
                seen = true;
            }
            if seen {
                let ray = ViewAliasing { near: finite_or_zero(ray.near), far: finite_or_zero(ray.far), ..ray };
                out = Some(out.map_or(ray, |o| o.worst(ray)));
            }
        }
    }
    out
}

/// An end the face filter skipped counts as nothing (NaN), an unseen one
/// as infinite.
fn finite_or_zero(e: f64) -> f64 {
    if e.is_nan() {
        0.0
    } else {
        e
    }
}

fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in pts {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo, hi)
}

/// Camera rays per image side for [`receiver_aliasing`].
pub(crate) const RECEIVER_RAYS: usize = 9;

/// Each split's predicted maximum aliasing at the receivers the scene box
/// implies, `None` for a split no camera ray ends in. On each of
/// `RECEIVER_RAYS²` camera rays spread evenly over the image, the receiver
/// is taken where the ray leaves the scene box `[lo, hi]` (a ground, a
/// wall: that face's normal) or reaches the far plane (facing the camera),
/// and judged in the map of the split holding it that serves it.
///
/// NOTE: this is what split placement needs and [`predict_aliasing`] does
/// not give: a camera inside the scene box sees its surfaces, not the air
/// in front of the near plane, and a plane placed for air near the camera
/// (the logarithmic scheme's first split) spends a map on nothing.
pub(crate) fn receiver_aliasing(
    maps: &[ShadowMap],
    depths: &[f64],
    camera: &Camera,
    basis: &CameraBasis,
    (lo, hi): (DVec3, DVec3),
) -> [Option<f64>; MAX_SPLITS] {
    let mut out = [None; MAX_SPLITS];
    let Some(m) = depths.len().checked_sub(1).filter(|&m| m > 0) else { return out };
    let camera_clip = post_perspective(camera, basis, 0.0);
    let ty = (0.5 * camera.fovy).tan();
    let tx = ty * camera.aspect;
    let g = |k: usize| 2.0 * k as f64 / (RECEIVER_RAYS - 1) as f64 - 1.0;
    for j in 0..RECEIVER_RAYS {
        for i in 0..RECEIVER_RAYS {
            let d = basis.forward + basis.right * (g(i) * tx) + basis.up * (g(j) * ty);
            let Some(exit) = clip_ray(camera.eye, d, depths[0], depths[m], lo, hi) else { continue };
            let p = camera.eye + d * exit.depth;
            let n = exit.axis.map_or(-d / d.length(), |k| DVec3::AXES[k]);
            let split = depths[1..m].partition_point(|&c| c < exit.depth);
            let Some(map) = split_map(maps, split, p) else { continue };
            let e = (image_area_scale(&camera_clip, p, n) / image_area_scale(&map.fit.clip_from_world, p, n)).sqrt();
            // NOTE: a point the map cannot see (w ≤ 0) gives NaN: it makes
            // the prediction infinite, never smaller.
            let e = if e.is_nan() { f64::INFINITY } else { e };
            out[split] = Some(out[split].map_or(e, |x: f64| x.max(e)));
        }
    }
    out
}

/// The active map of `split` that serves the point `p` (for a cube, the
/// face toward it).
fn split_map(maps: &[ShadowMap], split: usize, p: DVec3) -> Option<&ShadowMap> {
    maps.iter().filter(|map| map.split == split && map.fit.state == MapState::Active).find(|map| match (map.face, &map.light) {
        (Some(f), Light::Spot { position, .. }) => CubeFace::toward(p - *position) == f,
        _ => true,
    })
}
