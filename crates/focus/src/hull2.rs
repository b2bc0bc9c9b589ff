//! The convex hull of a body's image in the map plane, and the rectangle
//! of least area around it: the orientation that lets a map's square fill
//! with the body ("no wasted map").
//!
//! Turns are decided with the exact orientation predicate (`robust`'s
//! adaptive `orient2d` [SHE97]) on the rounded image points, so the hull is the
//! exact hull of those points; the rounding of the points themselves only
//! steers the orientation, and the crop that follows makes the map
//! conservative whatever the orientation is.

use glam::DVec2;
use robust::{orient2d, Coord};
use shadowfocus_geom::MAX_VERTICES;

fn coord(p: DVec2) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

/// `> 0` when `o → a → b` turns left, exactly for the given points.
fn turn(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    orient2d(coord(o), coord(a), coord(b))
}

/// Writes the convex hull of `pts` (sorted in place) counter-clockwise into
/// `hull` and returns its vertex count (the monotone chain of [AND79]; collinear
/// points are dropped). `hull` needs room for `2 · pts.len()` points (the
/// second chain starts where the first ended).
pub(crate) fn convex_hull(pts: &mut [DVec2], hull: &mut [DVec2]) -> usize {
    let n = pts.len();
    if n < 3 {
        hull[..n].copy_from_slice(pts);
        return n;
    }
    pts.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut k = 0;
    for pass in 0..2 {
        let start = k;
        for i in 0..n {
            let p = if pass == 0 { pts[i] } else { pts[n - 1 - i] };
            while k >= start + 2 && turn(hull[k - 2], hull[k - 1], p) <= 0.0 {
                k -= 1;
            }
            hull[k] = p;
            k += 1;
        }
        // The chain's last point starts the other chain.
        k -= 1;
    }
    k
}

/// Twice the signed area of a polygon.
fn area2(poly: &[DVec2]) -> f64 {
    let n = poly.len();
    (0..n).map(|i| poly[i].perp_dot(poly[(i + 1) % n])).sum()
}

/// Area of the convex hull of `pts` (sorted in place).
pub(crate) fn hull_area(pts: &mut [DVec2]) -> f64 {
    let mut hull = [DVec2::ZERO; 2 * MAX_VERTICES];
    let k = convex_hull(pts, &mut hull);
    0.5 * area2(&hull[..k]).abs()
}

/// Unit direction `e` of the rectangle of least area containing `pts`
/// (sorted in place): one of its sides is parallel to `e` (a classic
/// result: some side of the least-area rectangle contains a hull edge, so
/// the hull's edge directions are the only candidates). `None` for fewer
/// than two distinct points.
///
/// Of two edge directions with areas within a relative 2⁻²⁰ the first in
/// hull order is kept, so that the choice does not flicker on rounding.
pub(crate) fn min_area_direction(pts: &mut [DVec2]) -> Option<DVec2> {
    let mut hull = [DVec2::ZERO; 2 * MAX_VERTICES];
    let k = convex_hull(pts, &mut hull);
    let hull = &hull[..k];
    if k < 2 {
        return None;
    }
    let mut best: Option<(f64, DVec2)> = None;
    for i in 0..k {
        let Some(e) = (hull[(i + 1) % k] - hull[i]).try_normalize() else { continue };
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in hull {
            let q = DVec2::new(e.dot(*p), e.perp_dot(*p));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let d = hi - lo;
        let area = d.x * d.y;
        if best.is_none_or(|(a, _)| area < a * (1.0 - 1.0 / (1u64 << 20) as f64)) {
            best = Some((area, e));
        }
    }
    best.map(|(_, e)| e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_inner_and_edge_points() {
        let mut pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.5, 0.0), // on an edge: dropped
            DVec2::new(1.0, 1.0),
            DVec2::new(0.3, 0.6), // inside
            DVec2::new(0.0, 1.0),
        ];
        let mut hull = [DVec2::ZERO; 12];
        let k = convex_hull(&mut pts, &mut hull);
        assert_eq!(k, 4);
        assert!(area2(&hull[..k]) > 0.0, "counter-clockwise");
        assert_eq!(hull_area(&mut pts), 1.0);
    }

    #[test]
    fn least_area_rectangle_of_a_rotated_strip() {
        // A 10 × 1 rectangle turned by 0.4 rad: the least-area direction is
        // its long side (or the short one: both give the same rectangle).
        let (c, s) = (0.4f64.cos(), 0.4f64.sin());
        let rot = |x: f64, y: f64| DVec2::new(c * x - s * y, s * x + c * y);
        let mut pts = [rot(0.0, 0.0), rot(10.0, 0.0), rot(10.0, 1.0), rot(0.0, 1.0), rot(5.0, 0.5)];
        let e = min_area_direction(&mut pts).unwrap();
        let along = e.dot(DVec2::new(c, s)).abs();
        assert!((along - 1.0).abs() < 1e-12 || along < 1e-12, "{e}");
    }

    #[test]
    fn degenerate_inputs() {
        let mut one = [DVec2::new(1.0, 2.0)];
        assert_eq!(min_area_direction(&mut one), None);
        let mut seg = [DVec2::new(0.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(1.0, 1.0)];
        let e = min_area_direction(&mut seg).unwrap();
        assert!((e.x.abs() - e.y.abs()).abs() < 1e-12);
        assert_eq!(hull_area(&mut seg), 0.0);
    }
}
