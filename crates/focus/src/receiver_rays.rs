//! Camera rays against boxes: where a ray crosses a box (slab clipping),
//! and where it finds its receiver — where it leaves the scene box, where
//! it meets the scene box's ground, where it first meets one of the
//! engine's receiver boxes, or where it leaves the last box of seen points.

use crate::ground::GroundRect;
use crate::receiver_boxes::ReceiverBoxes;
use crate::settings::Ground;
use glam::DVec3;
use shadowfocus_geom::Aabb;

/// Where a ray leaves a box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Exit {
    /// The view depth where the ray enters the box (or `near`).
    pub entry: f64,
    /// The axis of the box face it enters through; `None` where it is
    /// inside at `near` already.
    pub entry_axis: Option<usize>,
    /// The view depth of the exit point.
    pub depth: f64,
    /// The axis of the box face it leaves through; `None` where the ray
    /// reaches `far` first.
    pub axis: Option<usize>,
}

/// Where `eye + z·d`, `z ∈ [near, far]`, leaves the box `[lo, hi]` (slab
/// clipping); `None` where it never is inside.
pub(crate) fn clip_ray(eye: DVec3, d: DVec3, near: f64, far: f64, lo: DVec3, hi: DVec3) -> Option<Exit> {
    let (mut z0, mut z1) = (near, far);
    let (mut entry_axis, mut axis) = (None, None);
    for k in 0..3 {
        let (e, dk) = (eye[k], d[k]);
        if dk == 0.0 {
            if e < lo[k] || e > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - e) / dk, (hi[k] - e) / dk);
        if a.min(b) > z0 {
            z0 = a.min(b);
            entry_axis = Some(k);
        }
        if a.max(b) < z1 {
            z1 = a.max(b);
            axis = Some(k);
        }
    }
    (z0 <= z1 && z0 > 0.0).then_some(Exit { entry: z0, entry_axis, depth: z1, axis })
}

/// Where the camera rays find their receivers: where they leave the scene
/// box, where they meet its ground, or where they first meet a receiver
/// box.
#[derive(Clone, Copy)]
pub(crate) enum ReceiverModel<'a> {
    SceneBox(&'a Aabb),
    Ground(GroundRect),
    Boxes(&'a ReceiverBoxes),
}

impl<'a> ReceiverModel<'a> {
    /// The receiver boxes where there are any, else the scene box's ground
    /// where `ground` names one, else the scene box.
    pub fn new(scene: &'a Aabb, receivers: &'a ReceiverBoxes, ground: Option<Ground>) -> ReceiverModel<'a> {
        match ground {
            _ if !receivers.is_empty() => ReceiverModel::Boxes(receivers),
            Some(g) => ReceiverModel::Ground(GroundRect::of(g, scene)),
            None => ReceiverModel::SceneBox(scene),
        }
    }

    /// The ground, in that model.
    pub fn ground(self) -> Option<GroundRect> {
        match self {
            ReceiverModel::Ground(g) => Some(g),
            _ => None,
        }
    }

    /// The receiver on the ray `eye + z·d` (`d · forward = 1`) in
    /// `[near, far]`; `None` where it has none.
    pub fn hit(self, eye: DVec3, d: DVec3, near: f64, far: f64) -> Option<Hit> {
        let face = |b: usize, axis: usize| Hit::face_id(b, axis, d);
        match self {
            ReceiverModel::SceneBox(b) => {
                let exit = clip_ray(eye, d, near, far, b.min, b.max)?;
                let axis = exit.axis?;
                Some(Hit { z: exit.depth, axis, face: face(0, axis) })
            }
            ReceiverModel::Ground(g) => {
                let z = g.hit(eye, d, near, far)?;
                Some(Hit { z, axis: g.axis, face: face(0, g.axis) })
            }
            ReceiverModel::Boxes(boxes) => {
                let (k, z, axis) = box_receiver(boxes, eye, d, near, far)?;
                let axis = axis?;
                Some(Hit { z, axis, face: face(k, axis) })
            }
        }
    }
}

/// Where the ray `eye + z·d`, `z ∈ [near, far]`, finds its receiver among
/// `boxes`: where it first meets a solid's ([`first_box`]), or where it
/// leaves the last box of seen points ([`last_box`]).
pub(crate) fn box_receiver(boxes: &ReceiverBoxes, eye: DVec3, d: DVec3, near: f64, far: f64) -> Option<(usize, f64, Option<usize>)> {
    if boxes.is_seen() {
        last_box(boxes.as_slice(), eye, d, near, far)
    } else {
        first_box(boxes.as_slice(), eye, d, near, far)
    }
}

/// The farthest point of `boxes` on the ray `eye + z·d`, `z ∈ [near, far]`:
/// the index of the box the ray leaves last, and the depth and axis of
/// the face it leaves through (no axis where it is still inside at `far`).
fn last_box(boxes: &[Aabb], eye: DVec3, d: DVec3, near: f64, far: f64) -> Option<(usize, f64, Option<usize>)> {
    crossed(boxes, eye, d, near, far).map(|(k, x)| (k, x.depth, x.axis)).max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The nearest of `boxes` on the ray `eye + z·d`, `z ∈ [near, far]`: its
/// index, and the depth and axis of the face the ray enters it through, or
/// leaves it through where it starts inside (no axis where it is still
/// inside at `far`).
fn first_box(boxes: &[Aabb], eye: DVec3, d: DVec3, near: f64, far: f64) -> Option<(usize, f64, Option<usize>)> {
    crossed(boxes, eye, d, near, far)
        .map(|(k, x)| match x.entry_axis {
            Some(axis) => (k, x.entry, Some(axis)),
            None => (k, x.depth, x.axis),
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// The boxes the ray crosses in `[near, far]`, with where it crosses each.
fn crossed(boxes: &[Aabb], eye: DVec3, d: DVec3, near: f64, far: f64) -> impl Iterator<Item = (usize, Exit)> + '_ {
    boxes.iter().enumerate().filter_map(move |(k, b)| Some((k, clip_ray(eye, d, near, far, b.min, b.max)?)))
}

/// A camera ray's receiver: its view depth, the axis of the box face it
/// lies on, and which face of which box that is.
#[derive(Clone, Copy)]
pub(crate) struct Hit {
    pub z: f64,
    pub axis: usize,
    pub face: usize,
}

impl Hit {
    fn face_id(b: usize, axis: usize, d: DVec3) -> usize {
        (b * 3 + axis) * 2 + usize::from(d[axis] > 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_clipped_to_a_box() {
        let eye = DVec3::ZERO;
        let d = DVec3::new(0.0, -0.5, 1.0);
        let (lo, hi) = (DVec3::new(-10.0, -2.0, -10.0), DVec3::new(10.0, -1.0, 10.0));
        // The box y ∈ [−2, −1] is crossed between z = 2 and z = 4, left
        // through its face y = −2.
        assert_eq!(clip_ray(eye, d, 0.1, 100.0, lo, hi), Some(Exit { entry: 2.0, entry_axis: Some(1), depth: 4.0, axis: Some(1) }));
        // Far inside the box: the ray ends there, on no face.
        assert_eq!(clip_ray(eye, d, 0.1, 3.0, lo, hi), Some(Exit { entry: 2.0, entry_axis: Some(1), depth: 3.0, axis: None }));
        // From inside: no face entered.
        let inside = (DVec3::splat(-10.0), DVec3::splat(10.0));
        assert_eq!(
            clip_ray(eye, d, 0.1, 100.0, inside.0, inside.1),
            Some(Exit { entry: 0.1, entry_axis: None, depth: 10.0, axis: Some(2) })
        );
        // Beyond far: nothing.
        assert_eq!(clip_ray(eye, d, 0.1, 1.5, lo, hi), None);
        // Parallel to a slab and outside it.
        assert_eq!(clip_ray(eye, DVec3::Z, 0.1, 10.0, DVec3::new(1.0, -1.0, 0.0), DVec3::new(2.0, 1.0, 5.0)), None);
    }
}
