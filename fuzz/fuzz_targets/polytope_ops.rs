//! Random sequences of polytope operations with arbitrary planes: never a
//! panic, and every step keeps the exact set invariants:
//! - a clip never grows the set; it reports a cut exactly when the set
//!   changed (the old set is then not inside the new one);
//! - a point inside after a clip was inside before;
//! - intersecting never raises the dimension, and `A ∩ B` lies in both;
//! - every polytope contains itself.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use shadowfocus_fuzz::{v3, FrustumIn, LightIn, PlaneIn, V3};
use shadowfocus_geom::{Aabb, Polytope};

#[derive(Arbitrary, Debug)]
enum Op {
    Clip(PlaneIn),
    ClipAll(Vec<PlaneIn>),
    IntersectAabb(V3, V3),
    /// Intersect with a box clipped by some planes.
    Intersect {
        min: V3,
        max: V3,
        planes: Vec<PlaneIn>,
    },
    /// Clip by the halfspaces of a frustum, or of its hull with a light.
    Frustum {
        frustum: FrustumIn,
        light: Option<LightIn>,
    },
    ContainsPoint(V3),
    Reset(V3, V3),
}

#[derive(Arbitrary, Debug)]
struct Input {
    min: V3,
    max: V3,
    ops: Vec<Op>,
}

/// A valid box, or `None` (boxes are validated before `from_aabb`).
fn boxed(min: &V3, max: &V3) -> Option<Aabb> {
    Aabb::new(v3(min), v3(max)).ok()
}

fn contains(a: &Polytope, b: &Polytope) -> Option<bool> {
    a.contains(b).ok()
}

fn clip_checked(p: &mut Polytope, plane: &PlaneIn) -> bool {
    let before = p.clone();
    match p.clip(&plane.build()) {
        Ok(cut) => {
            if let (Some(inside), Some(back)) = (contains(&before, p), contains(p, &before)) {
                assert!(inside, "a clip grew the polytope");
                assert_eq!(back, !cut, "clip reported cut = {cut}, but the set {} change", if back { "did not" } else { "did" });
            }
            assert!(p.dimension() <= before.dimension());
            true
        }
        Err(_) => {
            // Invalid planes are rejected before anything changes.
            if let (Some(a), Some(b)) = (contains(&before, p), contains(p, &before)) {
                assert!(a && b, "a rejected clip changed the polytope");
            }
            false
        }
    }
}

fuzz_target!(|input: Input| {
    let Some(start) = boxed(&input.min, &input.max) else { return };
    let mut p = Polytope::from_aabb(&start).expect("boxed() validates its box");
    for op in input.ops.iter().take(12) {
        match op {
            Op::Clip(plane) => {
                if !clip_checked(&mut p, plane) {
                    return;
                }
            }
            Op::ClipAll(planes) => {
                let planes: Vec<_> = planes.iter().take(8).map(PlaneIn::build).collect();
                let before = p.clone();
                if p.clip_all(&planes).is_err() {
                    return;
                }
                if let Some(inside) = contains(&before, &p) {
                    assert!(inside, "clip_all grew the polytope");
                }
            }
            Op::IntersectAabb(min, max) => {
                let b = Aabb { min: v3(min), max: v3(max) };
                let before = p.clone();
                if p.intersect_aabb(&b).is_err() {
                    return;
                }
                if let Some(inside) = contains(&before, &p) {
                    assert!(inside, "intersect_aabb grew the polytope");
                }
                if Aabb::new(b.min, b.max).is_ok() {
                    if let Some(inside) = contains(&Polytope::from_aabb(&b).expect("a validated box"), &p) {
                        assert!(inside, "P ∩ box is not inside the box");
                    }
                }
            }
            Op::Intersect { min, max, planes } => {
                let Some(b) = boxed(min, max) else { continue };
                let mut other = Polytope::from_aabb(&b).expect("boxed() validates its box");
                let planes: Vec<_> = planes.iter().take(8).map(PlaneIn::build).collect();
                if other.clip_all(&planes).is_err() {
                    continue;
                }
                let before = p.clone();
                if p.intersect(&other).is_err() {
                    return;
                }
                assert!(p.dimension() <= before.dimension().min(other.dimension()).max(-1));
                for (whole, what) in [(&before, "first"), (&other, "second")] {
                    if let Some(inside) = contains(whole, &p) {
                        assert!(inside, "A ∩ B is not inside the {what} operand");
                    }
                }
                // The other order gives the same set.
                let mut q = other.clone();
                if q.intersect(&before).is_ok() {
                    if let (Some(a), Some(b)) = (contains(&p, &q), contains(&q, &p)) {
                        assert!(a && b, "A ∩ B differs from B ∩ A");
                        assert_eq!(p.dimension(), q.dimension());
                    }
                }
            }
            Op::Frustum { frustum, light } => {
                let Ok(f) = frustum.build() else { continue };
                // Unchecked lights (NaN, zero direction) are allowed here:
                // `hull_with` is public and must cope with any apex.
                let planes = match light.as_ref().map(|l| l.build(&f, frustum)) {
                    None => f.planes().as_slice().to_vec(),
                    Some(Ok(l)) => f.hull_with(l.apex()).map(|h| h.as_slice().to_vec()).unwrap_or_default(),
                    Some(Err(_)) => continue,
                };
                let before = p.clone();
                if p.clip_all(&planes).is_err() {
                    return;
                }
                if let Some(inside) = contains(&before, &p) {
                    assert!(inside, "clipping by a frustum grew the polytope");
                }
                // F ⊆ hull(F ∪ l): a corner of F inside before stays inside.
                for c in f.corners() {
                    if before.contains_point(*c) {
                        assert!(p.contains_point(*c), "clipping by F or hull(F ∪ l) lost a corner of F");
                    }
                }
            }
            Op::ContainsPoint(x) => {
                let x = v3(x);
                let inside = p.contains_point(x);
                if !x.is_finite() {
                    assert!(!inside, "a non-finite point is inside");
                }
            }
            Op::Reset(min, max) => {
                if let Some(b) = boxed(min, max) {
                    p.reset_to_aabb(&b).expect("boxed() validates its box");
                    for c in [b.min, b.max] {
                        assert!(p.contains_point(c), "a box lost its corner");
                    }
                }
            }
        }
        if let Some(me) = contains(&p, &p) {
            assert!(me, "a polytope does not contain itself");
        }
    }
});
