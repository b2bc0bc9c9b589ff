//! Predicted perspective aliasing of a map, to compare parameterisations
//! before choosing one.
//!
//! The renderer's aliasing at a receiver point `p` (screen pixels per
//! texel, as a square root of areas) is
//!
//! `e(p) = √(a_C(p, n) / a_M(p, n))`,
//!
//! where `a_X(p, n)` is how much the projection `X` — the camera `C`, the
//! map `M` — magnifies areas on the receiver's plane through `p` with
//! normal `n` (`project::image_area_scale`); the constant factors of screen
//! and map resolution are common to every map of one light and dropped.
//! This is the quantity LiSPSM's `n_opt` balances between the near and far
//! ends of the view [LISPSM04], without its restriction to the view axis
//! and with the receiver's orientation to the light and to the eye in it.
//!
//! Where receivers are is not known to the fit, only that the visible ones
//! lie in `V_i ∩ S`. Along one camera ray a warp that favours the near end
//! (every LiSPSM, TSM and PSM map does) compares worst with the uniform map
//! at the ray's far end, so the samples take the receiver there: the point
//! where each of nine rays of the split's camera (the corners, edge
//! midpoints and centre of the image) leaves the split's depth range or the
//! bounding box of `H`, whichever comes first. That is the scene box's own
//! boundary (a ground, a wall: the receiver's normal is that face's) or the
//! split's far end (a receiver of unknown orientation, taken facing the
//! light), never empty air in front of the camera: samples at the near
//! plane, where a camera inside the scene box sees nothing, let a warp
//! through that is better only there and worse on every surface actually
//! seen. A receiver nearer than a ray's far end favours the warp, so the
//! choice errs toward the uniform map, never toward a worse warp.
//!
//! A face turned away from the light gives no sample, as in the view's
//! prediction (`view_aliasing`): it is in its own shadow, where no aliasing
//! shows. Looking up over a city, six of the nine rays left the body's box
//! through its top, seen from below; on that air the LiSPSM warp looked
//! better, and on the strip of ground below it rendered 1.59× the uniform
//! map's aliasing. Where the rays meet the split's receivers in one image
//! row only (a far slice of a view over a ground: the rows below pass under
//! it, the row above over it), they meet them at about one depth, and the
//! faces' points at the split's near and far planes in the same columns
//! join them for the predicted maximum ([`crossings`]): on those three
//! points alone, at the slice's near end, TSM passed and rendered 1.9× the
//! uniform map's aliasing. Where fewer than `MIN_SAMPLES` remain (a thin slice of
//! a steep view, whose body lies between the rays; a board seen from
//! straight above), rays through the body's own part in the split add
//! theirs ([`Part`]). Where even those leave fewer (looking up from beyond
//! a board's edge, the ground a strip between the rays, the part mostly
//! air), rays through the faces of the box that the camera sees from inside
//! it, clipped to the split's frustum, add theirs ([`faces`]). A warp with
//! no sample at all to judge it is not kept: unjudged, a split's TSM map
//! aliased up to 80× the uniform map's (`tests/sweep.rs`, view slices).
//!
//! Where the engine passes receiver boxes ([`crate::FocusSettings::receivers`]),
//! the samples are where the rays first meet one in the split instead (its
//! far end where a ray is still inside one there), and a ray that meets
//! none has no sample. Where it names the scene's ground
//! ([`crate::FocusSettings::ground`]), they are where the rays meet that
//! face of the scene box (none past its edge), with each of the three
//! image columns' two ends on it in the split for the maximum
//! ([`Samples::add_ground_columns`]); the fallbacks take their rays through
//! the ground alone.

mod crossings;
mod faces;
mod part;

use crate::ground::GroundRect;
use crate::project::post_perspective;
use crate::project::{crop_estimate, image_area_scale, light_factor, GRAZING_COS};
use crate::receiver_rays::{box_receiver, clip_ray};
use crate::split_view::SplitView;
use crossings::{crossing, one_row, Face, FaceHit};
use faces::{face_rays, lit_faces, FACE_RAYS};
use glam::{DMat4, DVec3, DVec4};
use part::Part;
use shadowfocus_geom::{unit_direction, Body};

/// Camera rays of the samples: the image's corners, edge midpoints and
/// centre, and as many through the body's part ([`Part`]).
const RAYS: usize = 9;

/// Fewest samples the light reaches at more than a graze that a warp is
/// judged on before the rays through the body's part ([`Part`]) are added:
/// on one or two receivers it is judged on where they happen to be. A
/// camera looking straight down at a board sees it all at one depth; the
/// image's rays found its centre and one edge, where PSM predicted less
/// than the uniform map and rendered 1.7× more.
const MIN_SAMPLES: usize = 3;

/// Most samples from the image's and the part's rays: one point on each
/// image ray, or fewer than `MIN_SAMPLES` of those and one on each ray
/// through the body's part.
const RAY_SAMPLES: usize = RAYS + MIN_SAMPLES - 1;

/// Most samples where a face crosses a split plane ([`crossings`]): the
/// three rays of one image row, at the split's two planes.
const CROSSINGS: usize = 6;

/// Most samples: those, and room for one face's rays ([`faces`]) where they
/// leave fewer than `MIN_SAMPLES` the light reaches at more than a graze.
const MAX_SAMPLES: usize = RAY_SAMPLES + CROSSINGS + FACE_RAYS;

/// Receiver samples of one split.
#[derive(Clone)]
pub(crate) struct Samples {
    pts: [DVec3; MAX_SAMPLES],
    /// The unit light ray at each sample, and the light's factor on the
    /// receiver there ([`light_factor`] of the receiver's normal: that of
    /// the box face the camera ray leaves or, for a receiver box, meets;
    /// facing the light where the ray reaches the far plane first).
    ray: [DVec3; MAX_SAMPLES],
    light: [f64; MAX_SAMPLES],
    /// Each sample's weight in the typical ratio ([`Predicted::ratio_product`]).
    weight: [f64; MAX_SAMPLES],
    /// Whether the sample is a face's crossing with a split plane
    /// ([`crossings`]): it marks an end of the receivers' depth, where a
    /// ray's sample stands for a ninth of the image, so it counts in the
    /// maximum only, not in the mean or the typical ratio.
    end: [bool; MAX_SAMPLES],
    /// The camera's area magnification `a_C` at each sample, on the
    /// receiver's plane.
    camera: [f64; MAX_SAMPLES],
    /// The camera's clip matrix (its area scale is all that is used).
    clip_from_world: DMat4,
    /// The reference map's aliasing at each sample, once [`Samples::judge`]
    /// has run.
    reference: [f64; MAX_SAMPLES],
    len: usize,
    /// The light as a homogeneous point (`w = 0`: toward a directional
    /// light).
    light_point: DVec4,
}

/// A map's predicted aliasing over the samples, up to a factor common to
/// the maps of one light and one split (comparable between those only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Predicted {
    pub max: f64,
    pub mean: f64,
    /// Product over the samples of (e / e_reference)^w, at most 1 where
    /// their weighted geometric mean is: whether the map is better than the
    /// reference on a typical sample, however the samples' magnitudes
    /// differ. The weight `w` is 1 but where the light grazes a receiver,
    /// where it fades to 0 as [`light_factor`] fades the receiver out: a
    /// wall lit by 10⁻¹⁷ after rounding votes as little as its aliasing
    /// weighs, and a sun in the camera's vertical plane fits the same on
    /// either side of it.
    pub ratio_product: f64,
    /// The sum of the weights the product runs over.
    pub weight: f64,
}

impl Predicted {
    /// Whether `self` is at least as good as the reference `other` in the
    /// worst sample, in the mean sample and on the typical sample: the
    /// rendered maximum, the bulk of the distribution (its p95) and the
    /// receivers that are not the worst each get a say.
    ///
    /// NOTE: the receivers' orientation is part of `e` (their normal where
    /// the ray meets the scene box): a warp's gain at the nearest receivers
    /// then does not hide its loss on a far ground the light grazes, which
    /// carries the view's worst aliasing under a low sun.
    pub fn no_worse_than(&self, other: &Predicted) -> bool {
        self.no_worse_than_by(other, 1.0)
    }

    /// [`Predicted::no_worse_than`] with `factor` allowed: the maximum and
    /// the mean at most `factor` times the reference's, the typical ratio
    /// (the product's geometric mean) at most `factor`.
    pub fn no_worse_than_by(&self, other: &Predicted, factor: f64) -> bool {
        self.max <= factor * other.max && self.mean <= factor * other.mean && self.ratio_product <= factor.powf(self.weight)
    }
}

impl Samples {
    /// Samples of the split of `sv` inside the bounding box of `body`, or
    /// on the receiver boxes of its settings where they give any, for the
    /// light at the homogeneous point `light_point`.
    pub fn new(sv: &SplitView, body: &Body, light_point: DVec4) -> Samples {
        let mut s = Samples {
            pts: [DVec3::ZERO; MAX_SAMPLES],
            ray: [DVec3::Z; MAX_SAMPLES],
            light: [1.0; MAX_SAMPLES],
            weight: [1.0; MAX_SAMPLES],
            end: [false; MAX_SAMPLES],
            camera: [0.0; MAX_SAMPLES],
            clip_from_world: post_perspective(sv.camera, &sv.basis, 0.0),
            reference: [1.0; MAX_SAMPLES],
            len: 0,
            light_point,
        };
        let (lo, hi) = bounds(body.vertices());
        match sv.ground {
            Some(g) => s.add_ground_columns(sv, g),
            None => s.add_image_rays(sv, lo, hi),
        }
        if s.firmly_lit() < MIN_SAMPLES {
            for d in Part::of(sv, body).rays(sv).iter().flatten() {
                if s.len < RAY_SAMPLES {
                    s.add_ray(sv, *d, lo, hi);
                }
            }
        }
        if s.firmly_lit() < MIN_SAMPLES && sv.settings.receivers.as_slice().is_empty() {
            let (faces, lit) = match sv.ground {
                Some(g) => ([g.face_index(); 6], 1),
                None => lit_faces(lo, hi, light_point),
            };
            let (lo, hi) = sv.ground.map_or((lo, hi), |g| (g.lo, g.hi));
            for &face in &faces[..lit] {
                if s.firmly_lit() >= MIN_SAMPLES {
                    break;
                }
                for d in face_rays(sv, lo, hi, face).iter().flatten() {
                    s.add_ray(sv, *d, lo, hi);
                }
            }
        }
        s
    }

    /// The samples of the nine image rays on the box `[lo, hi]` (the
    /// body's) or the receiver boxes, and where they meet receivers in one
    /// image row only, the faces' crossings with the split's planes.
    fn add_image_rays(&mut self, sv: &SplitView, lo: DVec3, hi: DVec3) {
        let s = self;
        let cam = sv.camera;
        let b = &sv.basis;
        let ty = (0.5 * cam.fovy).tan();
        let tx = ty * cam.aspect;
        let mut hits = [None; RAYS];
        for (i, hit) in hits.iter_mut().enumerate() {
            let (gx, gy) = ((i % 3) as f64 - 1.0, (i / 3) as f64 - 1.0);
            // The ray eye + z·d, z the view depth (d·forward = 1).
            let column = b.forward + b.right * (gx * tx);
            *hit = s.add_ray(sv, column + b.up * (gy * ty), lo, hi).map(|face| FaceHit { row: gy, column, face });
        }
        if one_row(&hits) {
            for h in hits.iter().flatten() {
                for z in [cam.near, cam.far] {
                    if let Some(p) = crossing(sv, h, z) {
                        s.add(p, Some(h.face.normal), true);
                    }
                }
            }
        }
    }

    /// The samples on the ground `g` of the nine image rays, and in each of
    /// their three columns the two ends of the ground the column sees in the
    /// split ([`GroundRect::column_span`]: the ground's edge, the split's planes,
    /// the image's border), which count in the predicted maximum only, as
    /// the faces' crossings do: a split's worst ground receiver lies at one
    /// of them, and the rays miss both wherever the split holds a strip of
    /// ground a few rows high. Over the light sweep, four splits with the
    /// near ends left out were within 5 % of the best method in 241 of 252
    /// configurations instead of 245, 23 instead of 11 higher at p95 than
    /// without a ground.
    fn add_ground_columns(&mut self, sv: &SplitView, g: GroundRect) {
        let cam = sv.camera;
        let b = &sv.basis;
        let ty = (0.5 * cam.fovy).tan();
        let tx = ty * cam.aspect;
        for gx in [-1.0, 0.0, 1.0] {
            let column = b.forward + b.right * (gx * tx);
            for gy in [-1.0, 0.0, 1.0] {
                self.add_ray(sv, column + b.up * (gy * ty), g.lo, g.hi);
            }
            for end in g.column_span(cam.eye, column, b.up, ty, cam.near, cam.far).iter().flatten() {
                self.add(end.p, Some(g.normal()), true);
            }
        }
    }

    /// The sample on the camera ray `eye + z·d` (`d·forward = 1`), if it
    /// has one: where it leaves the split or the box `[lo, hi]` (the body's),
    /// or where it first meets one of the engine's receiver boxes (the
    /// split's far end, of unknown orientation, where it is inside one
    /// there; nothing where it meets none, or where the face it meets is
    /// turned away from the light). Where the sample is on a face and
    /// firmly lit, that face.
    fn add_ray(&mut self, sv: &SplitView, d: DVec3, lo: DVec3, hi: DVec3) -> Option<Face> {
        let (cam, receivers) = (sv.camera, &sv.settings.receivers);
        if let Some(g) = sv.ground {
            // On the ground, or nothing: the sky over its edge.
            let z = g.hit(cam.eye, d, cam.near, cam.far)?;
            self.add(cam.eye + d * z, Some(g.normal()), false);
            return None;
        }
        let (z, axis, (lo, hi)) = if receivers.is_empty() {
            clip_ray(cam.eye, d, cam.near, cam.far, lo, hi).map(|exit| (exit.depth, exit.axis, (lo, hi)))
        } else {
            let b = receivers.as_slice();
            box_receiver(receivers, cam.eye, d, cam.near, cam.far).map(|(k, z, axis)| (z, axis, (b[k].min, b[k].max)))
        }?;
        // The face the ray leaves or meets along axis k is seen from the
        // side its ray comes from: its normal toward the camera is −sign(d_k).
        let normal = axis.map(|k| DVec3::AXES[k] * -d[k].signum());
        let (p, len) = (cam.eye + d * z, self.len);
        self.add(p, normal, false);
        let (k, normal) = (axis?, normal?);
        (self.len > len && self.weight[len] == 1.0).then_some(Face { axis: k, at: p[k], normal, lo, hi })
    }

    /// How many samples the light reaches at more than a graze (a cosine of
    /// at least `GRAZING_COS`, below which [`light_factor`] fades a receiver
    /// out of the prediction). A wall lit by 10⁻¹⁷ after rounding is a
    /// sample that all but vanishes from the prediction; it must not decide
    /// whether the part's rays are added, or a sun in the camera's vertical
    /// plane would fit differently on either side of it. A face's crossing
    /// with a split plane is not counted: it has no say in the typical
    /// sample that the part's rays are there to widen.
    ///
    /// NOTE: the weight is 1 exactly where that cosine is at least
    /// `GRAZING_COS` (a cosine below it divides by it to at most the double
    /// below 1).
    fn firmly_lit(&self) -> usize {
        (0..self.len).filter(|&i| self.weight[i] == 1.0 && !self.end[i]).count()
    }

    /// The direction from `p` toward the light (of any length).
    fn toward_light(&self, p: DVec3) -> DVec3 {
        self.light_point.truncate() - p * self.light_point.w
    }

    /// Adds the receiver at `p` with its normal `face` toward the camera,
    /// where there is room and it faces the light (a sample on the far
    /// plane, of unknown orientation, is taken facing it), with what its
    /// prediction needs of the light and the camera; `end` marks a face's
    /// crossing with a split plane.
    fn add(&mut self, p: DVec3, face: Option<DVec3>, end: bool) {
        let toward = self.toward_light(p);
        let lit = face.is_none_or(|n| n.dot(toward) > 0.0);
        if !(lit && self.len < MAX_SAMPLES) {
            return;
        }
        let k = self.len;
        let ray = unit_direction(-toward);
        let n = face.unwrap_or(ray);
        let c = n.dot(ray).abs();
        (self.pts[k], self.ray[k], self.light[k]) = (p, ray, light_factor(c));
        (self.weight[k], self.end[k]) = ((c / GRAZING_COS).min(1.0), end);
        self.camera[k] = image_area_scale(&self.clip_from_world, p, n);
        self.len += 1;
    }

    /// The prediction for `reference` (the map others are compared
    /// against), and which samples it sees; `None` without samples.
    pub fn judge(&mut self, reference: &DMat4) -> Option<Predicted> {
        let mut k = 0;
        for i in 0..self.len {
            let e = self.aliasing(reference, i);
            if e.is_finite() && e > 0.0 {
                (self.pts[k], self.ray[k], self.light[k]) = (self.pts[i], self.ray[i], self.light[i]);
                (self.weight[k], self.end[k]) = (self.weight[i], self.end[i]);
                (self.camera[k], self.reference[k]) = (self.camera[i], e);
                k += 1;
            }
        }
        self.len = k;
        self.predict(reference)
    }

    /// Aliasing of `m` at sample `i` (as `e` above, up to the common factor).
    fn aliasing(&self, m: &DMat4, i: usize) -> f64 {
        (self.camera[i] / image_area_scale(m, self.pts[i], self.ray[i])).sqrt() * self.light[i]
    }

    /// [`Samples::predict`] for `m` cropped to the points `pts` by its
    /// estimated crop (`project::crop_estimate`: the same texel sizes as the
    /// certified crop to a few ulps), how candidate maps are judged before
    /// the one kept is cropped; `None` where the estimate fails.
    pub fn predict_estimated(&self, m: &DMat4, pts: &[DVec3]) -> Option<Predicted> {
        crop_estimate(m, pts).and_then(|e| self.predict(&e))
    }

    /// The prediction for the clip matrix `m` of the light given to
    /// [`Samples::judge`] over the samples it kept; one that `m` does not
    /// see makes the prediction fail every comparison.
    pub fn predict(&self, m: &DMat4) -> Option<Predicted> {
        let (mut max, mut sum, mut count, mut product, mut weight) = (0.0f64, 0.0, 0usize, 1.0, 0.0);
        for i in 0..self.len {
            let e = self.aliasing(m, i);
            max = max.max(e);
            if self.end[i] {
                // NOTE: 0·e is 0 for a finite e and NaN for a NaN or
                // infinite one, which the sum then carries (below).
                sum += 0.0 * e;
                continue;
            }
            (sum, count) = (sum + e, count + 1);
            let (r, w) = (e / self.reference[i], self.weight[i]);
            product *= if w == 1.0 { r } else { r.powf(w) };
            weight += w;
        }
        // NOTE: a NaN e (a sample the map cannot see) makes the maximum
        // ignore it but the sum and the product NaN, and NaN compares false:
        // refused. An overflow of the product (nine ratios beyond 1e34
        // each) refuses the map too, and an underflow to 0 accepts only a
        // map whose typical ratio is far below 1 anyway. Crossings alone (no
        // ray's sample left) give a NaN mean: refused too.
        (self.len > 0).then(|| Predicted { max, mean: sum / count as f64, ratio_product: product, weight })
    }
}

/// The bounding box of `pts`, rounded outward by a few ulps of its
/// largest coordinate.
///
/// NOTE: the body's vertices include the view's far corners, and the
/// image's corner rays pass through them: on the box's edge at the far
/// plane, where rounding alone decided whether the ray left through the far
/// plane (a receiver facing the light) or through a side face (one the
/// light may graze, whose vote vanishes). Rounded outward, the box holds
/// every vertex strictly, and such a ray leaves through the far plane
/// whichever way its own rounding falls.
fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in pts {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let pad = lo.abs().max(hi.abs()).max_element() * (8.0 * f64::EPSILON);
    if !pad.is_finite() {
        // No points (an empty box, which no ray meets).
        return (lo, hi);
    }
    (lo - DVec3::splat(pad), hi + DVec3::splat(pad))
}
