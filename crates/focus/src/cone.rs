//! The axis of a shadow frustum: the direction `a` maximising
//! `min_i a·u_i` over unit directions `u_i` (the centre of the smallest cone
//! containing them).
//!
//! By LP duality, `max_{|a|=1} min_i a·u_i = min_{x ∈ conv(u)} |x|` when
//! positive, attained at `a = x*/|x*|` with `x*` the point of the convex
//! hull of the `u_i` nearest the origin. That point is found with Gilbert–
//! Johnson–Keerthi iterations (support point, then the nearest point of a
//! simplex of at most four points). It moves continuously with the
//! directions — in particular a vertex appearing or vanishing on the body
//! does not make it jump — and it gives the largest possible margin
//! `min a·u_i`, which is what keeps `w > 0` robust for wide cones (PSM's
//! light just beyond the far face). `None` when the origin is (nearly) in
//! the hull: no open half-space holds all directions.

use glam::DVec3;

/// Half-angle margin of cube faces and truncation frusta: the field of view
/// is widened by 2⁻²⁰ (relative) so that the rounded frusta still overlap;
/// a rounding allowance, far above the rounding of `tan` and of the corners.
pub(crate) const CONE_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// Per subset of the four simplex vertices (bit `i`: vertex `i`), its
/// vertices in increasing order and how many there are.
const SUBSETS: [([usize; 4], usize); 16] = {
    let mut table = [([0; 4], 0); 16];
    let mut mask = 0;
    while mask < 16 {
        let (mut i, mut k) = (0, 0);
        while i < 4 {
            if mask & (1 << i) != 0 {
                table[mask].0[k] = i;
                k += 1;
            }
            i += 1;
        }
        table[mask].1 = k;
        mask += 1;
    }
    table
};

/// Nearest point to the origin of the simplex `w[..n]` (n ≤ 4) among its
/// faces through the newest vertex `w[n − 1]`; keeps in `w` only the
/// vertices of the smallest face containing it.
///
/// NOTE: GJK adds a support point only when it brings the hull closer to the
/// origin, and then the nearest point of the new simplex lies on a face
/// through it; the other faces (half of all) need not be tried. Should
/// rounding make another face nearer, the iteration simply goes on: the
/// axis is checked against every direction afterwards (`travel_axis`).
fn nearest_on_simplex(w: &mut [DVec3; 4], n: &mut usize) -> DVec3 {
    let pts = *w;
    let count = *n;
    let mut best = (f64::INFINITY, DVec3::ZERO, 0u8);
    // Every subset holding the newest vertex (≤ 8): its affine hull's
    // nearest point, kept if its barycentric coordinates are all positive.
    for mask in (1u8 << (count - 1))..(1 << count) {
        let (idx, k) = SUBSETS[mask as usize];
        let p0 = pts[idx[0]];
        let cand = match k {
            1 => Some(p0),
            2 => {
                let e = pts[idx[1]] - p0;
                let t = -p0.dot(e) / e.length_squared();
                (t > 0.0 && t < 1.0).then(|| p0 + e * t)
            }
            3 => {
                let (e1, e2) = (pts[idx[1]] - p0, pts[idx[2]] - p0);
                let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
                let (b1, b2) = (-p0.dot(e1), -p0.dot(e2));
                let det = a11 * a22 - a12 * a12;
                if det > 0.0 {
                    let s = (b1 * a22 - b2 * a12) / det;
                    let t = (a11 * b2 - a12 * b1) / det;
                    (s > 0.0 && t > 0.0 && s + t < 1.0).then(|| p0 + e1 * s + e2 * t)
                } else {
                    None
                }
            }
            _ => {
                // Tetrahedron: the origin inside means distance 0.
                let (e1, e2, e3) = (pts[idx[1]] - p0, pts[idx[2]] - p0, pts[idx[3]] - p0);
                let det = e1.dot(e2.cross(e3));
                if det != 0.0 {
                    let r = -p0;
                    let s = r.dot(e2.cross(e3)) / det;
                    let t = e1.dot(r.cross(e3)) / det;
                    let u = e1.dot(e2.cross(r)) / det;
                    (s > 0.0 && t > 0.0 && u > 0.0 && s + t + u < 1.0).then_some(DVec3::ZERO)
                } else {
                    None
                }
            }
        };
        if let Some(c) = cand {
            let d = c.length_squared();
            if d < best.0 {
                best = (d, c, mask);
            }
        }
    }
    let (kept, k) = SUBSETS[best.2 as usize];
    for (slot, &i) in w.iter_mut().zip(&kept[..k]) {
        *slot = pts[i];
    }
    *n = k;
    best.1
}

/// The direction of `units` least aligned with `a`, and its dot product
/// with `a` (`(∞, 0)` when there is none).
pub(crate) fn least_aligned(units: &[DVec3], a: DVec3) -> (f64, DVec3) {
    let mut worst = (f64::INFINITY, DVec3::ZERO);
    for u in units {
        let d = a.dot(*u);
        if d < worst.0 {
            worst = (d, *u);
        }
    }
    worst
}

/// Turns `a` toward the direction of `units` least aligned with it, at
/// most `max_steps` times, until it has a positive dot product with every
/// one: a cheap search for a cone axis from a guess. `None` when the steps
/// run out or the sum cancels to zero.
pub(crate) fn turn_into_cone(units: &[DVec3], mut a: DVec3, max_steps: usize) -> Option<DVec3> {
    let mut worst = least_aligned(units, a);
    let mut steps = 0;
    while !(worst.0 > 0.0) {
        if steps == max_steps {
            return None;
        }
        a = (a + worst.1).normalize_or_zero();
        if a == DVec3::ZERO {
            return None;
        }
        worst = least_aligned(units, a);
        steps += 1;
    }
    Some(a)
}

/// The maximin axis of `dirs` (unit vectors), or `None`.
pub(crate) fn cone_axis(dirs: &[DVec3]) -> Option<DVec3> {
    let support = |v: DVec3| least_aligned(dirs, v).1;
    let mut w = [*dirs.first()?; 4];
    let mut n = 1;
    let mut v = w[0];
    for _ in 0..48 {
        let s = support(v);
        let vv = v.length_squared();
        // NOTE: GJK's stopping rule: the support point brings no relative
        // improvement; then v is the nearest hull point to rounding.
        if vv - v.dot(s) <= 1e-13 * vv || w[..n].contains(&s) {
            break;
        }
        w[n] = s;
        n += 1;
        v = nearest_on_simplex(&mut w, &mut n);
        if !(v.length_squared() > 1e-28) {
            return None;
        }
    }
    let a = v.normalize_or_zero();
    (a != DVec3::ZERO && a.is_finite()).then_some(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn margin(a: DVec3, d: &[DVec3]) -> f64 {
        d.iter().map(|u| a.dot(*u)).fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn symmetric_cone_axis() {
        let d: Vec<DVec3> = (0..8)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 8.0;
                DVec3::new(t.cos() * 0.5, t.sin() * 0.5, 1.0).normalize()
            })
            .collect();
        let a = cone_axis(&d).unwrap();
        assert!((a - DVec3::Z).length() < 1e-9, "{a}");
    }

    #[test]
    fn wide_cone_near_half_space() {
        // Directions spread over almost a hemisphere around −z, as seen from
        // a PSM light just beyond the far face: margin ~ 1e-3.
        let mut d = Vec::new();
        for x in [-1.0, -0.3, 0.4, 1.0] {
            for y in [-1.0, 0.2, 1.0] {
                d.push(DVec3::new(x - 0.9, y - 0.9, -0.002).normalize());
                d.push(DVec3::new(x - 0.9, y - 0.9, -2.0).normalize());
            }
        }
        let a = cone_axis(&d).unwrap();
        assert!(margin(a, &d) > 0.0, "{a} {}", margin(a, &d));
        // Better than the plain −z axis, which is already feasible.
        assert!(margin(a, &d) >= margin(DVec3::NEG_Z, &d) - 1e-12);
    }

    #[test]
    fn no_axis_when_surrounding() {
        let d = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z];
        assert!(cone_axis(&d).is_none());
        let d = [DVec3::X, DVec3::NEG_X];
        assert!(cone_axis(&d).is_none());
    }
}
