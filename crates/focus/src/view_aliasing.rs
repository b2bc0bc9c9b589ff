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
//! Where the receivers are is what the fit does not know, unless the
//! engine passes their boxes ([`crate::ReceiverBoxes`]): then each camera
//! ray's receiver is where it first meets a box. Without them, only the
//! scene box is known. Taking receivers anywhere in `V ∩ S` (facing the
//! camera, as the logarithmic bound does) puts them in the air at the near
//! plane, where a camera inside the box sees nothing, and the prediction
//! there is the near plane's, 9–300× what any pixel measures on the
//! built-in scenes. So the receivers are taken where the camera rays leave
//! the scene box: its floor seen from above is the ground, its walls the
//! walls. Casters (and a terrain above the box's floor) stand in front of
//! those faces; they are the part the prediction misses.

use crate::project::{image_area_scale, post_perspective};
use crate::receiver_rays::{Hit, ReceiverModel};
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
/// maps were fitted for, its full depth range) in the scene box `scene`,
/// with the receiver boxes `receivers` where the engine knows them (empty:
/// none known); `None` for a map with nothing to render, or one that
/// serves none of the receiver samples.
///
/// The receivers are where each of `RECEIVER_RAYS²` camera rays, spread
/// evenly over the image, first meets a receiver box (the face it enters
/// through, or leaves through from inside), or without boxes where it
/// leaves the scene box (a ground, a wall: that face's normal), where that
/// face turns toward the light: a camera inside
/// the scene box sees its surfaces, not the air in front of its near plane,
/// and a receiver turned away from the light is in its own shadow, where no
/// aliasing shows (the renderer measures over the receivers that face the
/// light too). A ray that reaches the far plane inside the box has no
/// receiver the fit knows of (the sky above a terrain, fog). A sample
/// counts for the map of the split that holds its depth (and, for a cube
/// face, that serves its direction). Without receiver boxes, casters inside
/// the scene box, and a terrain above its floor, are receivers nearer than
/// its faces, which the prediction does not see.
pub fn predict_aliasing(map: &ShadowMap, camera: &Camera, scene: &Aabb, receivers: &[Aabb]) -> Option<ViewAliasing> {
    if map.fit.state != MapState::Active {
        return None;
    }
    let basis = camera.basis().ok()?;
    let camera_clip = post_perspective(camera, &basis, 0.0);
    let mut out = None;
    each_receiver(camera, &basis, &map.light, ReceiverModel::new(scene, receivers), &map.split_range, |_, p, n, z| {
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
    model: ReceiverModel,
) -> [Option<ViewAliasing>; MAX_SPLITS] {
    let mut out = [None; MAX_SPLITS];
    let camera_clip = post_perspective(camera, basis, 0.0);
    each_receiver(camera, basis, light, model, depths, |split, p, n, z| {
        let Some(e) = split_map(maps, split, p).and_then(|map| aliasing_in(map, &camera_clip, p, n)) else { return };
        out[split] = Some(out[split].map_or(ViewAliasing::one(e, z), |v: ViewAliasing| v.with(e, z)));
    });
    out
}

/// The view depth of the nearest receiver sample (see [`predict_aliasing`])
/// in the camera's depth range; `None` without any.
pub(crate) fn nearest_receiver(camera: &Camera, basis: &CameraBasis, light: &Light, model: ReceiverModel) -> Option<f64> {
    let mut lo: Option<f64> = None;
    each_receiver(camera, basis, light, model, &[camera.near, camera.far], |_, _, _, z| lo = Some(lo.map_or(z, |l| l.min(z))));
    lo
}

/// Calls `f(split, p, n, z)` for each receiver sample that faces `light`
/// (point `p`, unit normal `n`, view depth `z`) in the depth range
/// `depths[0]..=depths[m]`, `split` the index of the range
/// `[depths[i], depths[i + 1]]` holding `z`.
///
/// The samples are the receivers of `RECEIVER_RAYS²` rays spread evenly
/// over the image, and, in each column of rays, the points where a face
/// the rays meet crosses a plane of `depths` (reported for the splits on
/// both sides): a split's worst receiver on a face is mostly at one of its
/// ends, which evenly spread rays miss where a split holds few rows of the
/// image (far splits over a ground seen near the horizon).
fn each_receiver(
    camera: &Camera,
    basis: &CameraBasis,
    light: &Light,
    model: ReceiverModel,
    depths: &[f64],
    mut f: impl FnMut(usize, DVec3, DVec3, f64),
) {
    let Some(m) = depths.len().checked_sub(1).filter(|&m| m > 0) else { return };
    let ty = (0.5 * camera.fovy).tan();
    let tx = ty * camera.aspect;
    let g = |k: usize| 2.0 * k as f64 / (RECEIVER_RAYS - 1) as f64 - 1.0;
    for i in 0..RECEIVER_RAYS {
        let ray = |gy: f64| basis.forward + basis.right * (g(i) * tx) + basis.up * (gy * ty);
        // The ray is clipped to the camera's whole range: a ray whose
        // receiver lies beyond the planes has none in them.
        let hit = |gy: f64| model.hit(camera.eye, ray(gy), camera.near, camera.far);
        // The face's normal toward the camera: a receiver there that faces
        // away from the light is in its own shadow, where no aliasing
        // shows.
        let mut sample = |split: usize, gy: f64, h: Hit| {
            let d = ray(gy);
            let n = DVec3::AXES[h.axis] * -d[h.axis].signum();
            let p = camera.eye + d * h.z;
            if n.dot(toward_light(light, p)) > 0.0 {
                f(split, p, n, h.z);
            }
        };
        let mut column = [None; RECEIVER_RAYS];
        for (j, c) in column.iter_mut().enumerate() {
            *c = hit(g(j));
            if let Some(h) = *c {
                if h.z >= depths[0] && h.z <= depths[m] {
                    sample(depths[1..m].partition_point(|&c| c < h.z), g(j), h);
                }
            }
        }
        // Along a column, `1/z` on a plane is affine in the image row: the
        // rows where a face crosses each plane follow from two rays on it
        // (interpolated between them, or extrapolated beyond them up to
        // the next ray where that meets another face or nothing), and a ray
        // there confirms the face.
        for j in 0..RECEIVER_RAYS - 1 {
            let same = |a: usize, b: usize| matches!((column[a], column[b]), (Some(x), Some(y)) if x.face == y.face);
            let line = if same(j, j + 1) {
                Some((j, j + 1))
            } else if j > 0 && same(j - 1, j) {
                Some((j - 1, j))
            } else if j + 2 < RECEIVER_RAYS && same(j + 1, j + 2) {
                Some((j + 1, j + 2))
            } else {
                None
            };
            let Some((a, b)) = line else { continue };
            let (ha, hb) = (column[a].unwrap(), column[b].unwrap());
            let (wa, wb) = (1.0 / ha.z, 1.0 / hb.z);
            for (k, &zk) in depths.iter().enumerate() {
                let gy = g(a) + (g(b) - g(a)) * (1.0 / zk - wa) / (wb - wa);
                if !(gy > g(j) && gy < g(j + 1)) {
                    continue;
                }
                // NOTE: `h.z` is `zk` up to rounding, either way: the sample
                // goes to the splits on both sides of the plane whatever the
                // last bit, so that a split predicts the same alone
                // (`predict_aliasing`) as among the others.
                let Some(h) = hit(gy).filter(|h| h.face == ha.face) else { continue };
                for split in [k.wrapping_sub(1), k] {
                    if split < m {
                        sample(split, gy, h);
                    }
                }
            }
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
