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
//! applies the second. On a receiver the light grazes by more than 85° the
//! prediction fades out with the receiver's light (`project::light_factor`):
//! there every map's aliasing grows without bound while the shadow's
//! contrast vanishes.
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
//! those faces; they are the part the prediction misses. Outdoors the walls
//! are where the geometry ends: where the engine names the scene's ground
//! ([`crate::FocusSettings::ground`]) the receivers are on that ground alone
//! (`crate::ground`), with the ends of each ray column's part of it.

use crate::project::{image_area_scale, light_factor, post_perspective};
use crate::receiver_boxes::ReceiverBoxes;
use crate::receiver_rays::{Hit, ReceiverModel};
use crate::result::{CubeFace, MapState, ShadowMap};
use crate::settings::Ground;
use crate::MAX_SPLITS;
use glam::{DMat4, DVec3};
use shadowfocus_geom::{unit_direction, Aabb, Camera, CameraBasis, Light};

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
/// with the receiver boxes `receivers` where the engine knows them
/// ([`ReceiverBoxes::NONE`]: none known), else on the `ground` where the scene is open
/// ([`crate::FocusSettings::ground`]; a level outside the scene box is
/// taken at the box's nearest face); `None` for a map with nothing
/// to render, or one that serves none of the receiver samples.
///
/// The receivers are where each of `RECEIVER_RAYS²` camera rays, spread
/// evenly over the image, first meets a receiver box (the face it enters
/// through, or leaves through from inside; for boxes of seen points,
/// [`ReceiverBoxes::seen`], the face it leaves the last one through), or without boxes where it
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
pub fn predict_aliasing(
    map: &ShadowMap,
    camera: &Camera,
    scene: &Aabb,
    receivers: &ReceiverBoxes,
    ground: Option<Ground>,
) -> Option<ViewAliasing> {
    if map.fit.state != MapState::Active {
        return None;
    }
    let basis = camera.basis().ok()?;
    let mut out = None;
    let model = ReceiverModel::new(scene, receivers, ground);
    let rays = ReceiverRays::new(camera, [camera.near, camera.far], &basis, &map.light, model);
    rays.each(&map.split_range, |_, s| {
        if let Some(e) = aliasing_in(map, s) {
            let z = s.z;
            out = Some(out.map_or(ViewAliasing::one(e, z), |v: ViewAliasing| v.with(e, z)));
        }
    });
    out
}

/// Each split's predicted aliasing ([`predict_aliasing`]) of the maps
/// `maps` fitted for the planes `depths`, `None` for a split no sample
/// lands in.
pub(crate) fn receiver_aliasing(maps: &[ShadowMap], depths: &[f64], rays: &ReceiverRays) -> [Option<ViewAliasing>; MAX_SPLITS] {
    let mut out = [None; MAX_SPLITS];
    rays.each(depths, |split, s| {
        let Some(e) = split_map(maps, split, s.p).and_then(|(_, map)| aliasing_in(map, s)) else { return };
        out[split] = Some(out[split].map_or(ViewAliasing::one(e, s.z), |v: ViewAliasing| v.with(e, s.z)));
    });
    out
}

/// Each map's predicted maximum aliasing ([`predict_aliasing`]) among the
/// maps `maps` fitted for the planes `depths`, in `out` (in `maps` order);
/// 0 for a map no sample lands in. A sample a map cannot see (infinite
/// aliasing: none of its sides would show it) is left out.
pub(crate) fn map_aliasing(maps: &[ShadowMap], depths: &[f64], rays: &ReceiverRays, out: &mut [f64]) {
    out.fill(0.0);
    rays.each(depths, |split, s| {
        let Some((k, map)) = split_map(maps, split, s.p) else { return };
        if let Some(e) = aliasing_in(map, s).filter(|e| e.is_finite()) {
            out[k] = out[k].max(e);
        }
    });
}

/// The receivers of `RECEIVER_RAYS²` camera rays spread evenly over the
/// image, found once (they do not depend on the split planes) for every
/// prediction of one fit.
pub(crate) struct ReceiverRays<'a> {
    camera: &'a Camera,
    /// The view depths receivers are seen at (the engine's visible depth
    /// range, where it gives one): samples outside it are left out.
    visible: [f64; 2],
    light: &'a Light,
    model: ReceiverModel<'a>,
    /// The view direction, and the image's half extents at depth 1.
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    camera_clip: DMat4,
    /// Per column of rays, each row's receiver.
    hits: [[Option<Hit>; RECEIVER_RAYS]; RECEIVER_RAYS],
    /// The same rows' samples, where they face the light.
    samples: [[Option<Sample>; RECEIVER_RAYS]; RECEIVER_RAYS],
}

/// A receiver sample: point, view depth, the camera's area magnification
/// there on the receiver's face (`a_C`, the same for every map), the unit
/// light ray, and the light's factor on the receiver ([`light_factor`]).
#[derive(Clone, Copy)]
pub(crate) struct Sample {
    p: DVec3,
    z: f64,
    camera_area: f64,
    ray: DVec3,
    light: f64,
}

impl<'a> ReceiverRays<'a> {
    /// Each ray's receiver, the ray clipped to the camera's whole range: a
    /// ray whose receiver lies beyond the planes has none in them. Samples
    /// are taken in the `visible` depth range only.
    ///
    /// NOTE: the rays reach over the camera's whole range, not only the
    /// visible one, so that a face that enters the visible range at its near
    /// end has rays on it on both sides: its crossing with that end, the
    /// nearest and worst receiver of the first split, follows from them.
    /// Rays clipped at the visible near end miss it (a ray there loses its
    /// receiver to the last bit of rounding), and the first split is
    /// predicted too good.
    pub fn new(
        camera: &'a Camera,
        visible: [f64; 2],
        basis: &'a CameraBasis,
        light: &'a Light,
        model: ReceiverModel<'a>,
    ) -> ReceiverRays<'a> {
        let ty = (0.5 * camera.fovy).tan();
        let mut rays = ReceiverRays {
            camera,
            visible,
            light,
            model,
            forward: basis.forward,
            right: basis.right * (ty * camera.aspect),
            up: basis.up * ty,
            camera_clip: post_perspective(camera, basis, 0.0),
            hits: [[None; RECEIVER_RAYS]; RECEIVER_RAYS],
            samples: [[None; RECEIVER_RAYS]; RECEIVER_RAYS],
        };
        for i in 0..RECEIVER_RAYS {
            for j in 0..RECEIVER_RAYS {
                rays.hits[i][j] = rays.hit(i, ray_grid(j));
                rays.samples[i][j] = rays.hits[i][j].and_then(|h| rays.facing(i, ray_grid(j), h));
            }
        }
        rays
    }

    /// The ray of column `i` at image height `gy` (`d · forward = 1`).
    fn ray(&self, i: usize, gy: f64) -> DVec3 {
        self.forward + self.right * ray_grid(i) + self.up * gy
    }

    fn hit(&self, i: usize, gy: f64) -> Option<Hit> {
        self.model.hit(self.camera.eye, self.ray(i, gy), self.camera.near, self.camera.far)
    }

    /// The view depth of the nearest visible ray's receiver that faces the
    /// light; `None` without any.
    pub fn nearest(&self) -> Option<f64> {
        let [lo, hi] = self.visible;
        self.samples.iter().flatten().flatten().map(|s| s.z).filter(|&z| z >= lo && z <= hi).reduce(f64::min)
    }

    /// The receiver's sample (its face's normal toward the camera), where
    /// it faces the light: one turned away is in its own shadow, where no
    /// aliasing shows.
    fn facing(&self, i: usize, gy: f64, h: Hit) -> Option<Sample> {
        let d = self.ray(i, gy);
        let n = DVec3::AXES[h.axis] * -d[h.axis].signum();
        self.sample_at(self.camera.eye + d * h.z, h.z, n)
    }

    /// The sample at `p` (view depth `z`) on a receiver with the normal `n`
    /// toward the camera, where it faces the light.
    fn sample_at(&self, p: DVec3, z: f64, n: DVec3) -> Option<Sample> {
        let l = toward_light(self.light, p);
        (n.dot(l) > 0.0).then(|| {
            // NOTE: `unit_direction` normalises a light direction of any
            // magnitude (down to 2⁻¹⁰⁰⁰), as the fit's own light frame does.
            let ray = unit_direction(l);
            Sample { p, z, camera_area: image_area_scale(&self.camera_clip, p, n), ray, light: light_factor(n.dot(ray)) }
        })
    }

    /// Calls `f(split, sample)` for each receiver sample that faces the
    /// light in the depth range `depths[0]..=depths[m]` and in the visible
    /// range, `split` the index of the range `[depths[i], depths[i + 1]]`
    /// holding its depth.
    ///
    /// The samples are the receivers of `RECEIVER_RAYS²` rays spread evenly
    /// over the image, and, in each column of rays, the points where a face
    /// the rays meet crosses a plane of `depths` (reported for the splits on
    /// both sides), the outer two planes moved into the visible range: a
    /// split's worst receiver on a face is mostly at one of its ends, which
    /// evenly spread rays miss where a split holds few rows of the image (far
    /// splits over a ground seen near the horizon).
    pub fn each(&self, depths: &[f64], mut f: impl FnMut(usize, &Sample)) {
        let Some(m) = depths.len().checked_sub(1).filter(|&m| m > 0) else { return };
        let (lo, hi) = (depths[0].max(self.visible[0]), depths[m].min(self.visible[1]));
        let plane = |k: usize| match k {
            0 => lo,
            _ if k == m => hi,
            _ => depths[k],
        };
        for (i, column) in self.hits.iter().enumerate() {
            for s in self.samples[i].iter().flatten().filter(|s| s.z >= lo && s.z <= hi) {
                f(depths[1..m].partition_point(|&c| c < s.z), s);
            }
            // On a ground, the ends of the part the column sees in each
            // split: its edge (beyond which the rays pass over it) lies
            // between two rows, and where the split holds a strip of ground
            // narrower than the rows' spacing, so do its crossings with the
            // split's planes. A split alone (`predict_aliasing` of its map)
            // finds the same ends as among the others.
            if let Some(g) = self.model.ground() {
                let column = self.ray(i, 0.0);
                for split in 0..m {
                    let ends = g.column_span(self.camera.eye, column, self.up, 1.0, plane(split), plane(split + 1));
                    for end in ends.iter().flatten() {
                        if let Some(s) = self.sample_at(end.p, end.z, g.normal()) {
                            f(split, &s);
                        }
                    }
                }
            }
            // Along a column, `1/z` on a plane is affine in the image row:
            // the rows where a face crosses each plane follow from two rays
            // on it (interpolated between them, or extrapolated beyond them
            // up to the next ray where that meets another face or nothing),
            // and a ray there confirms the face.
            for j in 0..RECEIVER_RAYS - 1 {
                let Some((a, b)) = face_line(column, j) else { continue };
                let (wa, wb) = (1.0 / a.1.z, 1.0 / b.1.z);
                for k in 0..=m {
                    let zk = plane(k);
                    let gy = ray_grid(a.0) + (ray_grid(b.0) - ray_grid(a.0)) * (1.0 / zk - wa) / (wb - wa);
                    if !(gy > ray_grid(j) && gy < ray_grid(j + 1)) {
                        continue;
                    }
                    // NOTE: `h.z` is `zk` up to rounding, either way: the
                    // sample goes to the splits on both sides of the plane
                    // whatever the last bit, so that a split predicts the
                    // same alone (`predict_aliasing`) as among the others.
                    let Some(h) = self.hit(i, gy).filter(|h| h.face == a.1.face) else { continue };
                    let Some(s) = self.facing(i, gy, h) else { continue };
                    for split in [k.wrapping_sub(1), k] {
                        if split < m {
                            f(split, &s);
                        }
                    }
                }
            }
        }
    }
}

/// The ray grid's image coordinate `k` of `RECEIVER_RAYS`, in `[−1, 1]`.
fn ray_grid(k: usize) -> f64 {
    2.0 * k as f64 / (RECEIVER_RAYS - 1) as f64 - 1.0
}

/// Two rows of `column` on one face that bound the gap between rows `j` and
/// `j + 1` or extend into it: the gap's own ends, or the two rows before it
/// or after it.
fn face_line(column: &[Option<Hit>; RECEIVER_RAYS], j: usize) -> Option<((usize, Hit), (usize, Hit))> {
    let same = |a: usize, b: usize| match (column[a], column[b]) {
        (Some(x), Some(y)) if x.face == y.face => Some(((a, x), (b, y))),
        _ => None,
    };
    same(j, j + 1)
        .or_else(|| j.checked_sub(1).and_then(|i| same(i, j)))
        .or_else(|| (j + 2 < RECEIVER_RAYS).then(|| same(j + 1, j + 2)).flatten())
}

/// The aliasing of `map` at the sample `s` (dimensionless); infinite where
/// the map cannot see it (NaN from `w ≤ 0`: never a smaller prediction);
/// `None` for a cube face that does not serve it.
fn aliasing_in(map: &ShadowMap, s: &Sample) -> Option<f64> {
    if let (Some(f), Light::Spot { position, .. }) = (map.face, &map.light) {
        if CubeFace::toward(s.p - *position) != f {
            return None;
        }
    }
    let e = (s.camera_area / image_area_scale(&map.fit.clip_from_world, s.p, s.ray)).sqrt() * s.light;
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
/// face toward it), with its index in `maps`.
fn split_map(maps: &[ShadowMap], split: usize, p: DVec3) -> Option<(usize, &ShadowMap)> {
    maps.iter().enumerate().filter(|(_, map)| map.split == split && map.fit.state == MapState::Active).find(|(_, map)| {
        match (map.face, &map.light) {
            (Some(f), Light::Spot { position, .. }) => CubeFace::toward(p - *position) == f,
            _ => true,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fit given the visible depth range `[z0, far]` of a camera above a
    /// floor: the floor's crossing with `z0` is the nearest receiver sample,
    /// wherever `z0` falls. Rays clipped at `z0` itself lost that crossing
    /// for 132 of these 199 (the ray to it lands a rounding error short of
    /// the range), and the first split was predicted too good.
    #[test]
    fn the_visible_near_end_is_sampled_where_a_face_crosses_it() {
        let scene = Aabb::new(DVec3::new(-1e3, 0.0, -1e3), DVec3::new(1e3, 50.0, 1e3)).unwrap();
        let camera = Camera {
            eye: DVec3::new(0.3, 1.7, -2.0),
            forward: DVec3::new(0.05, -0.3, 1.0),
            up: DVec3::Y,
            fovy: 1.0,
            aspect: 16.0 / 9.0,
            near: 0.1,
            far: 400.0,
        };
        let basis = camera.basis().unwrap();
        let light = Light::directional(DVec3::new(0.3, -1.0, 0.2)).unwrap();
        let model = ReceiverModel::new(&scene, &ReceiverBoxes::NONE, None);
        let whole = ReceiverRays::new(&camera, [camera.near, camera.far], &basis, &light, model);
        let floor = whole.nearest().unwrap();
        let mut checked = 0;
        for k in 1..200 {
            let z0 = floor * (300.0 / floor).powf(k as f64 / 200.0);
            let rays = ReceiverRays::new(&camera, [z0, camera.far], &basis, &light, model);
            let mut nearest = f64::INFINITY;
            rays.each(&[z0, camera.far], |_, s| nearest = nearest.min(s.z));
            assert!((nearest / z0 - 1.0).abs() < 1e-9, "z0 {z0}: nearest sample {nearest}");
            assert!(rays.nearest().is_none_or(|z| z >= z0));
            checked += 1;
        }
        assert_eq!(checked, 199);
    }
}
