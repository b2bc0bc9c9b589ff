//! A map's predicted aliasing, in absolute terms: what the renderer
//! measures per pixel, from the matrices alone.
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
//! Where the receivers are is what the fit does not know: only the scene
//! box. Taking them anywhere in `V ∩ S` (facing the camera, as the
//! logarithmic bound does) puts them in the air at the near plane, where a
//! camera inside the box sees nothing, and the prediction there is the
//! near plane's, 9–300× what any pixel measures on the built-in scenes. So
//! the receivers are taken where the camera rays leave the scene box: its
//! floor seen from above is the ground, its walls the walls. Casters (and a
//! terrain above the box's floor) stand in front of those faces; they are
//! the part the prediction misses.

use crate::predict::clip_ray;
use crate::project::{image_area_scale, post_perspective};
use crate::result::{CubeFace, MapState, ShadowMap};
use crate::MAX_SPLITS;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{Aabb, Camera, CameraBasis, Light};

/// Camera rays per image side: the receivers are sampled on
/// `RECEIVER_RAYS²` rays spread evenly over the image.
pub(crate) const RECEIVER_RAYS: usize = 17;

/// A map's predicted aliasing at the receivers the scene box implies (see
/// [`predict_aliasing`]), dimensionless: multiply by `√(W·H) / T`
/// ([`ViewAliasing::in_pixels`]) for screen pixels per texel of a `W×H`
/// image and a `T×T` map.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ViewAliasing {
    /// At the nearest receiver sample of the split.
    pub near: f64,
    /// At the farthest.
    pub far: f64,
    /// The largest over the split's samples.
    pub max: f64,
    /// The view depths of the nearest and farthest samples.
    pub depths: [f64; 2],
}

impl ViewAliasing {
    /// In screen pixels per texel, for a `width × height` image and a map of
    /// `texels` per side.
    pub fn in_pixels(self, width: f64, height: f64, texels: f64) -> ViewAliasing {
        let k = (width * height).sqrt() / texels;
        ViewAliasing { near: self.near * k, far: self.far * k, max: self.max * k, ..self }
    }

    /// The prediction with one more sample, `e` at view depth `z`.
    fn with(self, e: f64, z: f64) -> ViewAliasing {
        let mut v = ViewAliasing { max: self.max.max(e), ..self };
        if z < v.depths[0] {
            (v.near, v.depths[0]) = (e, z);
        }
        if z > v.depths[1] {
            (v.far, v.depths[1]) = (e, z);
        }
        v
    }

    fn one(e: f64, z: f64) -> ViewAliasing {
        ViewAliasing { near: e, far: e, max: e, depths: [z, z] }
    }
}

/// The predicted aliasing of `map` for the view of `camera` (the camera the
/// maps were fitted for, its full depth range) in the scene box `scene`;
/// `None` for a map with nothing to render, or one that serves none of the
/// receiver samples.
///
/// The receivers are where each of `RECEIVER_RAYS²` camera rays, spread
/// evenly over the image, leaves the scene box (a ground, a wall: that
/// face's normal), where that face turns toward the light: a camera inside
/// the scene box sees its surfaces, not the air in front of its near plane,
/// and a receiver turned away from the light is in its own shadow, where no
/// aliasing shows (the renderer measures over the receivers that face the
/// light too). A ray that reaches the far plane inside the box has no
/// receiver the fit knows of (the sky above a terrain, fog). A sample
/// counts for the map of the split that holds its depth (and, for a cube
/// face, that serves its direction). Casters inside the box, and a terrain
/// above its floor, are receivers nearer than its faces, which the
/// prediction does not see.
pub fn predict_aliasing(map: &ShadowMap, camera: &Camera, scene: &Aabb) -> Option<ViewAliasing> {
    if map.fit.state != MapState::Active {
        return None;
    }
    let basis = camera.basis().ok()?;
    let camera_clip = post_perspective(camera, &basis, 0.0);
    let mut out = None;
    each_receiver(camera, &basis, &map.light, (scene.min, scene.max), &map.split_range, |_, p, n, z| {
        if let Some(e) = aliasing_in(map, &camera_clip, p, n) {
            out = Some(out.map_or(ViewAliasing::one(e, z), |v: ViewAliasing| v.with(e, z)));
        }
    });
    out
}

/// Each split's predicted aliasing ([`predict_aliasing`]) of the maps
/// `maps` fitted for the planes `depths`, `None` for a split no sample
/// lands in.
pub(crate) fn receiver_aliasing(
    maps: &[ShadowMap],
    depths: &[f64],
    camera: &Camera,
    basis: &CameraBasis,
    light: &Light,
    scene: (DVec3, DVec3),
) -> [Option<ViewAliasing>; MAX_SPLITS] {
    let mut out = [None; MAX_SPLITS];
    let camera_clip = post_perspective(camera, basis, 0.0);
    each_receiver(camera, basis, light, scene, depths, |split, p, n, z| {
        let Some(e) = split_map(maps, split, p).and_then(|map| aliasing_in(map, &camera_clip, p, n)) else { return };
        out[split] = Some(out[split].map_or(ViewAliasing::one(e, z), |v: ViewAliasing| v.with(e, z)));
    });
    out
}

/// The view depth of the nearest receiver sample (see [`predict_aliasing`])
/// in the camera's depth range; `None` without any.
pub(crate) fn nearest_receiver(camera: &Camera, basis: &CameraBasis, light: &Light, scene: (DVec3, DVec3)) -> Option<f64> {
    let mut lo: Option<f64> = None;
    each_receiver(camera, basis, light, scene, &[camera.near, camera.far], |_, _, _, z| lo = Some(lo.map_or(z, |l| l.min(z))));
    lo
}

/// Calls `f(split, p, n, z)` for each receiver sample that faces `light`
/// (point `p`, unit normal `n`, view depth `z`) in the depth range
/// `depths[0]..=depths[m]`, `split` the index of the range
/// `[depths[i], depths[i + 1]]` holding `z`.
fn each_receiver(
    camera: &Camera,
    basis: &CameraBasis,
    light: &Light,
    (lo, hi): (DVec3, DVec3),
    depths: &[f64],
    mut f: impl FnMut(usize, DVec3, DVec3, f64),
) {
    let Some(m) = depths.len().checked_sub(1).filter(|&m| m > 0) else { return };
    let ty = (0.5 * camera.fovy).tan();
    let tx = ty * camera.aspect;
    let g = |k: usize| 2.0 * k as f64 / (RECEIVER_RAYS - 1) as f64 - 1.0;
    for j in 0..RECEIVER_RAYS {
        for i in 0..RECEIVER_RAYS {
            let d = basis.forward + basis.right * (g(i) * tx) + basis.up * (g(j) * ty);
            // The ray is clipped to the camera's whole range: a ray that
            // leaves the box beyond the planes has no receiver in them.
            let Some(exit) = clip_ray(camera.eye, d, camera.near, camera.far, lo, hi) else { continue };
            let z = exit.depth;
            if z < depths[0] || z > depths[m] {
                continue;
            }
            let Some(axis) = exit.axis else { continue };
            // The face's normal toward the camera: a receiver there that
            // faces away from the light is in its own shadow, where no
            // aliasing shows.
            let n = DVec3::AXES[axis] * -d[axis].signum();
            let p = camera.eye + d * z;
            if !(n.dot(toward_light(light, p)) > 0.0) {
                continue;
            }
            f(depths[1..m].partition_point(|&c| c < z), p, n, z);
        }
    }
}

/// The aliasing of `map` at `p` on a receiver with normal `n`
/// (dimensionless); infinite where the map cannot see `p` (NaN from `w ≤
/// 0`: never a smaller prediction); `None` for a cube face that does not
/// serve `p`.
fn aliasing_in(map: &ShadowMap, camera_clip: &DMat4, p: DVec3, n: DVec3) -> Option<f64> {
    if let (Some(f), Light::Spot { position, .. }) = (map.face, &map.light) {
        if CubeFace::toward(p - *position) != f {
            return None;
        }
    }
    let e = (image_area_scale(camera_clip, p, n) / image_area_scale(&map.fit.clip_from_world, p, n)).sqrt();
    Some(if e.is_nan() { f64::INFINITY } else { e })
}

/// The direction from `p` toward `light` (not normalised).
fn toward_light(light: &Light, p: DVec3) -> DVec3 {
    match *light {
        Light::Directional { direction } => -direction,
        Light::Point { position } | Light::Spot { position, .. } => position - p,
    }
}

/// The active map of `split` that serves the point `p` (for a cube, the
/// face toward it).
fn split_map(maps: &[ShadowMap], split: usize, p: DVec3) -> Option<&ShadowMap> {
    maps.iter().filter(|map| map.split == split && map.fit.state == MapState::Active).find(|map| match (map.face, &map.light) {
        (Some(f), Light::Spot { position, .. }) => CubeFace::toward(p - *position) == f,
        _ => true,
    })
}
