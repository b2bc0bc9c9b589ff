//! The receiver boxes an engine may pass: where the surfaces that receive
//! shadows are, as boxes (a terrain tile, a building, a floor).
//!
//! They serve two purposes, neither of which can lose a caster:
//!
//! - **Footprint.** Receivers lie in the boxes, so the visible lit
//!   receivers `R_i = V_i ∩ S ∩ L` lie in `R_i ∩ B`, `B` the boxes' bounds:
//!   maps fitted to their receivers ([`crate::Footprint::Receivers`],
//!   [`crate::FocusSettings::depth_clamp`]) fit to that. The body `H_i`,
//!   the depth range it sets and the caster culling do not change: casters
//!   need not be receivers.
//! - **Prediction.** The predicted aliasing ([`crate::predict_aliasing`]),
//!   which [`crate::SplitScheme::Optimal`] places its planes by, takes the
//!   receiver on each camera ray where the ray first meets a box, not where
//!   it leaves the scene box: a ground slab's top, not the box's floor
//!   below it; nothing for a ray into the sky.
//!
//! A box is a solid's bounds: a ray from outside meets the face it enters
//! through; from inside (a camera standing in a terrain tile's box), the
//! face it leaves through. Boxes around the points a depth pre-pass saw
//! ([`ReceiverBoxes::seen`], [`crate::VisibleReceivers`]) are not solids:
//! a point seen along a ray may lie anywhere in the boxes it passes
//! through, so the prediction takes it at the farthest, where the ray
//! leaves the last of them. That is the scene box's rule (a receiver
//! nearer than the ray's far end favours the warp, so the choice errs
//! toward the uniform map); taken where a ray first met such a box, the
//! slices of a terrain seen from eye height, each as wide as the view,
//! stopped the rays to farther ones early, and over the forest's light
//! sweep TSM's four splits rendered up to 2.5× the uniform map's maximum.

use crate::error::FocusError;
use glam::DVec3;
use shadowfocus_geom::Aabb;

/// Most boxes kept; more are merged into this many (see
/// [`ReceiverBoxes::new`]).
pub const MAX_RECEIVER_BOXES: usize = 16;

/// Up to [`MAX_RECEIVER_BOXES`] receiver boxes, checked (finite, `min ≤
/// max`); empty by default: no hint, receivers anywhere in the scene box.
#[derive(Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "Repr", into = "Repr"))]
pub struct ReceiverBoxes {
    boxes: [Aabb; MAX_RECEIVER_BOXES],
    len: usize,
    /// Boxes around seen points, not solids (see the module docs).
    seen: bool,
}

impl std::fmt::Debug for ReceiverBoxes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.seen {
            f.write_str("seen ")?;
        }
        f.debug_list().entries(self.as_slice()).finish()
    }
}

impl Default for ReceiverBoxes {
    fn default() -> Self {
        ReceiverBoxes::NONE
    }
}

impl ReceiverBoxes {
    /// No hint.
    pub const NONE: ReceiverBoxes =
        ReceiverBoxes { boxes: [Aabb { min: DVec3::ZERO, max: DVec3::ZERO }; MAX_RECEIVER_BOXES], len: 0, seen: false };

    /// The boxes, checked. More than [`MAX_RECEIVER_BOXES`] are merged: each
    /// goes to one of that many slabs along the axis its centres spread most
    /// on, and a slab's boxes become their bounds. Merging only grows boxes,
    /// so the bounds (all the footprint uses) stay the same and every
    /// receiver stays inside a box; the prediction coarsens. No allocation.
    pub fn new(boxes: &[Aabb]) -> Result<ReceiverBoxes, FocusError> {
        ReceiverBoxes::from_boxes(boxes.iter().copied())
    }

    /// [`ReceiverBoxes::new`] from an iterator it may read more than once (a C
    /// array converted on the fly).
    pub fn from_boxes<I: Iterator<Item = Aabb> + Clone>(boxes: I) -> Result<ReceiverBoxes, FocusError> {
        let mut out = ReceiverBoxes::NONE;
        let Some((bounds, count)) = checked_bounds(boxes.clone())? else { return Ok(out) };
        if count <= MAX_RECEIVER_BOXES {
            for b in boxes {
                out.boxes[out.len] = b;
                out.len += 1;
            }
            return Ok(out);
        }
        // The centres' spread per axis decides the slab axis.
        let (lo, hi) = boxes.clone().fold((bounds.max, bounds.min), |(lo, hi), b| {
            let c = 0.5 * (b.min + b.max);
            (lo.min(c), hi.max(c))
        });
        let spread = hi - lo;
        let axis = if spread.x >= spread.y && spread.x >= spread.z {
            0
        } else if spread.y >= spread.z {
            1
        } else {
            2
        };
        let mut slabs: [Option<Aabb>; MAX_RECEIVER_BOXES] = [None; MAX_RECEIVER_BOXES];
        for b in boxes {
            let c = 0.5 * (b.min[axis] + b.max[axis]);
            let t = if spread[axis] > 0.0 { (c - lo[axis]) / spread[axis] } else { 0.0 };
            let k = ((t * MAX_RECEIVER_BOXES as f64) as usize).min(MAX_RECEIVER_BOXES - 1);
            slabs[k] = Some(slabs[k].map_or(b, |s| union(&s, &b)));
        }
        for s in slabs.into_iter().flatten() {
            out.boxes[out.len] = s;
            out.len += 1;
        }
        Ok(out)
    }

    /// Boxes around the points a depth pre-pass saw (an engine's own
    /// reduction of its depth buffer, or [`crate::VisibleReceivers`]'s),
    /// checked and merged as [`ReceiverBoxes::new`] does: each camera ray's
    /// receiver is taken where it leaves the last box it passes through,
    /// not where it first meets one (see the module docs).
    /// No boxes are no hint, [`ReceiverBoxes::NONE`].
    pub fn seen(boxes: &[Aabb]) -> Result<ReceiverBoxes, FocusError> {
        Ok(ReceiverBoxes::new(boxes)?.into_seen())
    }

    /// The same boxes, marked as [`ReceiverBoxes::seen`]'s (none stay
    /// [`ReceiverBoxes::NONE`]).
    pub(crate) fn into_seen(self) -> ReceiverBoxes {
        ReceiverBoxes { seen: self.len > 0, ..self }
    }

    /// Whether the boxes hold seen points ([`ReceiverBoxes::seen`]) rather
    /// than solids.
    pub fn is_seen(&self) -> bool {
        self.seen
    }

    /// The boxes.
    pub fn as_slice(&self) -> &[Aabb] {
        &self.boxes[..self.len]
    }

    /// Whether there is no hint.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The bounds of every box; `None` without a hint.
    pub fn bounds(&self) -> Option<Aabb> {
        self.as_slice().iter().copied().reduce(|a, b| union(&a, &b))
    }
}

/// The bounds and number of `boxes`, each checked; `None` for none.
fn checked_bounds(boxes: impl Iterator<Item = Aabb>) -> Result<Option<(Aabb, usize)>, FocusError> {
    let mut out: Option<(Aabb, usize)> = None;
    for b in boxes {
        if Aabb::new(b.min, b.max).is_err() {
            return Err(FocusError::InvalidSettings { what: "receivers", reason: "every receiver box must be finite with min ≤ max" });
        }
        out = Some(out.map_or((b, 1), |(s, n)| (union(&s, &b), n + 1)));
    }
    Ok(out)
}

/// The bounding box of `a` and `b`.
pub(crate) fn union(a: &Aabb, b: &Aabb) -> Aabb {
    Aabb { min: a.min.min(b.min), max: a.max.max(b.max) }
}

/// The serialised form: a list of solids' boxes, or `{"seen": [...]}`.
#[cfg(feature = "serde")]
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
enum Repr {
    Solid(Vec<Aabb>),
    Seen { seen: Vec<Aabb> },
}

#[cfg(feature = "serde")]
impl TryFrom<Repr> for ReceiverBoxes {
    type Error = FocusError;
    fn try_from(r: Repr) -> Result<Self, FocusError> {
        match r {
            Repr::Solid(boxes) => ReceiverBoxes::new(&boxes),
            Repr::Seen { seen } => ReceiverBoxes::seen(&seen),
        }
    }
}

#[cfg(feature = "serde")]
impl From<ReceiverBoxes> for Repr {
    fn from(r: ReceiverBoxes) -> Repr {
        let boxes = r.as_slice().to_vec();
        if r.seen {
            Repr::Seen { seen: boxes }
        } else {
            Repr::Solid(boxes)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(c: DVec3, h: f64) -> Aabb {
        Aabb { min: c - DVec3::splat(h), max: c + DVec3::splat(h) }
    }

    #[test]
    fn bad_boxes_are_refused() {
        let nan = Aabb { min: DVec3::ZERO, max: DVec3::new(f64::NAN, 1.0, 1.0) };
        let inverted = Aabb { min: DVec3::ONE, max: DVec3::ZERO };
        for b in [nan, inverted] {
            let e = ReceiverBoxes::new(&[cube(DVec3::ZERO, 1.0), b]).unwrap_err();
            assert!(e.to_string().contains("receiver box"), "{e}");
        }
        assert!(ReceiverBoxes::new(&[]).unwrap().is_empty());
        assert_eq!(ReceiverBoxes::new(&[]).unwrap().bounds(), None);
    }

    #[test]
    fn many_boxes_merge_into_few_that_hold_them_all() {
        // 100 boxes along a diagonal: kept within the capacity, same bounds,
        // each input inside some kept box; a few boxes are kept as given.
        let many: Vec<Aabb> =
            (0..100).map(|k| cube(DVec3::new(k as f64 * 3.0, (k % 7) as f64, -(k as f64)), 0.5 + (k % 3) as f64)).collect();
        let r = ReceiverBoxes::new(&many).unwrap();
        assert!(r.as_slice().len() <= MAX_RECEIVER_BOXES && r.as_slice().len() > 1);
        let b = r.bounds().unwrap();
        let all = many.iter().copied().reduce(|a, b| union(&a, &b)).unwrap();
        assert_eq!((b.min, b.max), (all.min, all.max));
        for m in &many {
            assert!(r.as_slice().iter().any(|k| k.contains(m.min) && k.contains(m.max)), "{m:?} lost");
        }
        let few = &many[..5];
        assert_eq!(ReceiverBoxes::new(few).unwrap().as_slice(), few);
        // Boxes with one centre merge into one.
        let same: Vec<Aabb> = (1..40).map(|k| cube(DVec3::ONE, k as f64)).collect();
        assert_eq!(ReceiverBoxes::new(&same).unwrap().as_slice(), &[cube(DVec3::ONE, 39.0)]);
    }
}
