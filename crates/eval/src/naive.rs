//! The usual engine pipeline, for comparison: a floating-point convex hull
//! of the frustum corners and the light (a directional light extruded a
//! finite distance), then clipping by the scene box with an absolute
//! epsilon. Nothing here is exact; that is the point.

use glam::DVec3;
use parry3d_f64::transformation::try_convex_hull;
use shadowfocus_geom::Aabb;

/// Absolute tolerance of the clip, in world units (typical engine value).
pub const CLIP_EPSILON: f64 = 1e-6;

/// The naive pipeline's light.
#[derive(Clone, Copy, Debug)]
pub enum NaiveLight {
    Point(DVec3),
    /// Travel direction; extruded by twice the extent of view and scene.
    Directional(DVec3),
}

/// What the naive pipeline produced.
#[derive(Clone, Debug)]
pub enum NaiveBody {
    /// Hull vertices and outward-oriented triangles (as parry returns them).
    Hull { vertices: Vec<DVec3>, triangles: Vec<[u32; 3]> },
    /// Fewer than four vertices or no triangles: not a solid.
    Degenerate { vertices: usize },
    /// The hull routine returned an error or panicked.
    Failed(String),
}

fn hull(points: &[DVec3]) -> NaiveBody {
    // NOTE: parry's hull may panic on hostile input; an engine would crash,
    // here the panic is counted.
    let r = std::panic::catch_unwind(|| try_convex_hull(points));
    match r {
        Ok(Ok((v, t))) if v.len() >= 4 && t.len() >= 4 => NaiveBody::Hull { vertices: v, triangles: t },
        Ok(Ok((v, _))) => NaiveBody::Degenerate { vertices: v.len() },
        Ok(Err(e)) => NaiveBody::Failed(format!("{e:?}")),
        Err(_) => NaiveBody::Failed("panic".into()),
    }
}

fn inside_eps(b: &Aabb, p: DVec3) -> bool {
    p.cmpge(b.min - DVec3::splat(CLIP_EPSILON)).all() && p.cmple(b.max + DVec3::splat(CLIP_EPSILON)).all()
}

/// Outward face planes `(n, d)` with `n·p + d ≤ 0` inside, from the
/// triangles (unnormalised cross products, as engines compute them),
/// oriented away from the vertices' centroid.
fn planes(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(DVec3, f64)> {
    let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len().max(1) as f64;
    triangles
        .iter()
        .map(|t| {
            let (a, b, c) = (vertices[t[0] as usize], vertices[t[1] as usize], vertices[t[2] as usize]);
            let n = (b - a).cross(c - a);
            let s = if n.dot(centroid - a) > 0.0 { -1.0 } else { 1.0 };
            (n * s, -s * n.dot(a))
        })
        .collect()
}

/// `hull(V ∪ l) ∩ S`, the naive way.
pub fn naive_body(view: &[DVec3; 8], light: NaiveLight, scene: &Aabb) -> NaiveBody {
    let mut pts: Vec<DVec3> = view.to_vec();
    match light {
        NaiveLight::Point(p) => pts.push(p),
        NaiveLight::Directional(d) => {
            let mut lo = scene.min;
            let mut hi = scene.max;
            for c in view {
                lo = lo.min(*c);
                hi = hi.max(*c);
            }
            let k = 2.0 * (hi - lo).length() / d.length();
            pts.extend(view.iter().map(|c| *c - d * k));
        }
    }
    let (hv, ht) = match hull(&pts) {
        NaiveBody::Hull { vertices, triangles } => (vertices, triangles),
        other => return other,
    };
    // Clip by S: keep hull vertices in S (±ε), add hull-edge crossings of
    // S's planes that land in S (±ε), and S's corners inside the hull (±ε).
    let mut out: Vec<DVec3> = hv.iter().copied().filter(|p| inside_eps(scene, *p)).collect();
    for t in &ht {
        for k in 0..3 {
            let (a, b) = (hv[t[k] as usize], hv[t[(k + 1) % 3] as usize]);
            for axis in 0..3 {
                for bound in [scene.min[axis], scene.max[axis]] {
                    let (da, db) = (a[axis] - bound, b[axis] - bound);
                    if (da < -CLIP_EPSILON && db > CLIP_EPSILON) || (da > CLIP_EPSILON && db < -CLIP_EPSILON) {
                        let p = a + (b - a) * (da / (da - db));
                        if inside_eps(scene, p) {
                            out.push(p);
                        }
                    }
                }
            }
        }
    }
    let pl = planes(&hv, &ht);
    let in_hull = |c: DVec3| pl.iter().all(|(n, d)| n.dot(c) + d <= CLIP_EPSILON * n.length());
    let corner = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { scene.min.x } else { scene.max.x },
            if i & 2 == 0 { scene.min.y } else { scene.max.y },
            if i & 4 == 0 { scene.min.z } else { scene.max.z },
        )
    };
    for i in 0..8 {
        if in_hull(corner(i)) {
            out.push(corner(i));
        }
        // S's edges crossing the hull's face planes (edges i → i + 2^axis).
        for axis in 0..3 {
            if i & (1 << axis) != 0 {
                continue;
            }
            let (a, b) = (corner(i), corner(i | (1 << axis)));
            for (n, d) in &pl {
                let (da, db) = (n.dot(a) + d, n.dot(b) + d);
                if (da < 0.0) != (db < 0.0) && da != db {
                    let p = a + (b - a) * (da / (da - db));
                    if in_hull(p) {
                        out.push(p);
                    }
                }
            }
        }
    }
    if out.len() < 4 {
        return NaiveBody::Degenerate { vertices: out.len() };
    }
    hull(&out)
}

fn coord(p: DVec3) -> robust::Coord3D<f64> {
    robust::Coord3D { x: p.x, y: p.y, z: p.z }
}

impl NaiveBody {
    /// Whether `p` lies strictly outside the hull, decided exactly
    /// (Shewchuk's orient3d) against the hull's own triangles, so that only
    /// the pipeline's errors count, not the test's.
    pub fn excludes(&self, p: DVec3) -> bool {
        let NaiveBody::Hull { vertices, triangles } = self else { return true };
        let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
        triangles.iter().any(|t| {
            let (a, b, c) = (coord(vertices[t[0] as usize]), coord(vertices[t[1] as usize]), coord(vertices[t[2] as usize]));
            let sp = robust::orient3d(a, b, c, coord(p));
            let sc = robust::orient3d(a, b, c, coord(centroid));
            // Outside: strictly on the other side of a face than the interior.
            sp != 0.0 && sc != 0.0 && (sp > 0.0) != (sc > 0.0)
        })
    }

    /// Largest distance of `p` outside the hull's face planes (0 inside).
    pub fn distance_outside(&self, p: DVec3) -> f64 {
        let NaiveBody::Hull { vertices, triangles } = self else { return f64::INFINITY };
        planes(vertices, triangles)
            .iter()
            .map(|(n, d)| {
                // NOTE: a zero or NaN normal (a sliver triangle) says nothing
                // about containment; `len > 0.0` is false for NaN too.
                let len = n.length();
                if len > 0.0 {
                    ((n.dot(p) + d) / len).max(0.0)
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    }

    pub fn is_solid(&self) -> bool {
        matches!(self, NaiveBody::Hull { .. })
    }

    pub fn kind(&self) -> &'static str {
        match self {
            NaiveBody::Hull { .. } => "solid",
            NaiveBody::Degenerate { .. } => "degenerate",
            NaiveBody::Failed(_) => "failed",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_view() -> [DVec3; 8] {
        // A box-shaped "frustum" 0..1.
        let mut c = [DVec3::ZERO; 8];
        for (i, p) in c.iter_mut().enumerate() {
            *p = DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
        }
        c
    }

    #[test]
    fn ordinary_case_keeps_every_corner() {
        let s = Aabb::new(DVec3::splat(-10.0), DVec3::splat(10.0)).unwrap();
        let b = naive_body(&cube_view(), NaiveLight::Point(DVec3::new(5.0, 5.0, 5.0)), &s);
        assert!(b.is_solid());
        for c in cube_view() {
            assert!(!b.excludes(c), "{c}");
        }
        assert!(b.excludes(DVec3::splat(9.0)));
        assert!(!b.excludes(DVec3::new(5.0, 5.0, 5.0)));
    }

    #[test]
    fn clipping_by_the_box_cuts_the_light_off() {
        let s = Aabb::new(DVec3::splat(-1.0), DVec3::splat(2.0)).unwrap();
        let b = naive_body(&cube_view(), NaiveLight::Point(DVec3::new(5.0, 0.5, 0.5)), &s);
        assert!(b.is_solid());
        assert!(b.excludes(DVec3::new(4.0, 0.5, 0.5)));
        assert!(!b.excludes(DVec3::new(2.0, 0.5, 0.5)));
    }
}
