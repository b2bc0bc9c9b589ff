//! An independent exact reference for the focus body, written to be
//! obviously right rather than fast.
//!
//! It shares nothing with the body engine but the input types: no filters,
//! no incremental clipping, no beneath–beyond. Every f64 input is an
//! integer multiple of `2^e` for the smallest exponent `e` among them, so
//! after scaling by `2^-e` all inputs are big integers and every quantity
//! below is a polynomial in them, computed without rounding:
//!
//! 1. the halfspaces of `M`: for a point light, every plane through three
//!    of the nine points that has all nine on one side; for a directional
//!    light (`M = V + {−t·d}`), every such plane of the eight corners that
//!    the ray `−d` does not leave, and every plane through two corners and
//!    parallel to `d` with all corners on one side. These include every
//!    facet plane, and each is a valid halfspace of `M`, so their
//!    intersection is `M`;
//! 2. the six halfspaces of `S`, and those of `L` for a spot light;
//! 3. the vertices of `H`: every intersection point of three planes with
//!    independent normals that satisfies all halfspaces (H is bounded, so
//!    these are exactly its extreme points), kept in homogeneous integer
//!    coordinates `(X, W)`, `W > 0`.
//!
//! The cost is cubic in the number of planes (a few milliseconds per body),
//! which is fine for a test oracle and for the stress report.

use glam::DVec3;
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};
use shadowfocus_geom::{Aabb, Light};

type Vec3 = [BigInt; 3];

/// `n · x ≤ c`.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Halfspace {
    n: Vec3,
    c: BigInt,
}

/// A vertex `X / W` in scaled integer units, `W > 0`.
#[derive(Clone, Debug)]
struct Homogeneous {
    x: Vec3,
    w: BigInt,
}

/// The exact body: its vertices as exact rationals (world units) and the
/// halfspaces it was cut from.
#[derive(Clone, Debug)]
pub struct ExactBody {
    /// −1 empty, 0 point, 1 segment, 2 polygon, 3 solid.
    pub dimension: i32,
    pub vertices: Vec<[BigRational; 3]>,
    halfspaces: Vec<Halfspace>,
    scale: Scale,
}

impl ExactBody {
    /// Whether the f64 point `p` lies in the closed body, decided exactly.
    pub fn contains(&self, p: DVec3) -> bool {
        if !p.is_finite() {
            return false;
        }
        // p = Q · 2^e; in the body's units of 2^E that is Q / 2^(E − e) when
        // p has finer bits than any input, else the integer Q · 2^(e − E).
        let e = p.to_array().iter().filter(|v| **v != 0.0).map(|v| split_f64(*v).1).min().unwrap_or(self.scale.exponent);
        let q = if e >= self.scale.exponent {
            Homogeneous { x: self.scale.point(p), w: BigInt::from(1) }
        } else {
            let fine = Scale { exponent: e };
            Homogeneous { x: fine.point(p), w: BigInt::from(1) << (self.scale.exponent - e) as usize }
        };
        self.halfspaces.iter().all(|h| satisfies(h, &q))
    }
}

/// Why the oracle cannot take a case.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum OracleError {
    /// A coordinate is NaN or infinite.
    NotFinite,
}

impl std::fmt::Display for OracleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OracleError::NotFinite => write!(f, "the exact oracle takes finite coordinates only"),
        }
    }
}

impl std::error::Error for OracleError {}

/// `x = m · 2^e` with an integer `m` (0 for zero).
fn split_f64(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let sign = if bits >> 63 == 1 { -1 } else { 1 };
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 { (frac, -1074) } else { (frac | (1i64 << 52), exp - 1075) };
    (sign * m, e)
}

/// Converts every input to an integer multiple of a common power of two.
#[derive(Clone, Copy, Debug)]
struct Scale {
    exponent: i32,
}

impl Scale {
    fn new(values: &[f64]) -> Scale {
        let exponent = values.iter().filter(|v| **v != 0.0).map(|v| split_f64(*v).1).min().unwrap_or(0);
        Scale { exponent }
    }

    fn int(&self, x: f64) -> BigInt {
        let (m, e) = split_f64(x);
        BigInt::from(m) << ((e - self.exponent) as usize)
    }

    fn point(&self, p: DVec3) -> Vec3 {
        [self.int(p.x), self.int(p.y), self.int(p.z)]
    }

    /// `x / w` back in world units.
    fn rational(&self, x: &BigInt, w: &BigInt) -> BigRational {
        let (num, den) =
            if self.exponent >= 0 { (x << self.exponent as usize, w.clone()) } else { (x.clone(), w << (-self.exponent) as usize) };
        BigRational::new(num, den)
    }
}

fn sub(a: &Vec3, b: &Vec3) -> Vec3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [&a[1] * &b[2] - &a[2] * &b[1], &a[2] * &b[0] - &a[0] * &b[2], &a[0] * &b[1] - &a[1] * &b[0]]
}

fn dot(a: &Vec3, b: &Vec3) -> BigInt {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn is_zero(a: &Vec3) -> bool {
    a.iter().all(Zero::is_zero)
}

/// Adds the plane `n · x = n · p0` oriented so that every point lies
/// inside, if one orientation does that and the ray (if any) stays inside.
fn push_supporting(out: &mut Vec<Halfspace>, n: Vec3, p0: &Vec3, points: &[Vec3], ray: Option<&Vec3>) {
    let c = dot(&n, p0);
    let (mut below, mut above) = (true, true);
    for p in points {
        let s = dot(&n, p) - &c;
        below &= !s.is_positive();
        above &= !s.is_negative();
    }
    let along = ray.map_or_else(BigInt::zero, |r| dot(&n, r));
    if below && !along.is_positive() {
        push_unique(out, Halfspace { n: n.clone(), c: c.clone() });
    }
    if above && !along.is_negative() {
        push_unique(out, Halfspace { n: [-&n[0], -&n[1], -&n[2]], c: -c });
    }
}

/// Adds `h` in lowest terms unless it is already there.
fn push_unique(out: &mut Vec<Halfspace>, h: Halfspace) {
    let g = h.n.iter().chain(std::iter::once(&h.c)).fold(BigInt::zero(), |g, v| g.gcd(v));
    let h = if g > BigInt::from(1) { Halfspace { n: [&h.n[0] / &g, &h.n[1] / &g, &h.n[2] / &g], c: &h.c / &g } } else { h };
    if !out.contains(&h) {
        out.push(h);
    }
}

/// Halfspaces whose intersection is `hull(points) + {t·ray : t ≥ 0}`.
fn hull_halfspaces(points: &[Vec3], ray: Option<&Vec3>, out: &mut Vec<Halfspace>) {
    let k = points.len();
    for i in 0..k {
        for j in i + 1..k {
            let e = sub(&points[j], &points[i]);
            if let Some(r) = ray {
                let n = cross(&e, r);
                if !is_zero(&n) {
                    push_supporting(out, n, &points[i], points, ray);
                }
            }
            for m in j + 1..k {
                let n = cross(&e, &sub(&points[m], &points[i]));
                if !is_zero(&n) {
                    push_supporting(out, n, &points[i], points, ray);
                }
            }
        }
    }
}

fn box_halfspaces(s: &Scale, scene: &Aabb, out: &mut Vec<Halfspace>) {
    let (lo, hi) = (s.point(scene.min), s.point(scene.max));
    for axis in 0..3 {
        let mut n: Vec3 = [BigInt::zero(), BigInt::zero(), BigInt::zero()];
        n[axis] = BigInt::from(1);
        out.push(Halfspace { n: n.clone(), c: hi[axis].clone() });
        n[axis] = BigInt::from(-1);
        out.push(Halfspace { n, c: -&lo[axis] });
    }
}

fn det3(a: &Vec3, b: &Vec3, c: &Vec3) -> BigInt {
    dot(a, &cross(b, c))
}

/// The point on three planes, if their normals are independent.
fn three_planes(a: &Halfspace, b: &Halfspace, c: &Halfspace) -> Option<Homogeneous> {
    let w = det3(&a.n, &b.n, &c.n);
    if w.is_zero() {
        return None;
    }
    // Cramer's rule, written with the cross products of pairs of normals:
    // X = (c_a (n_b × n_c) + c_b (n_c × n_a) + c_c (n_a × n_b)).
    let (bc, ca, ab) = (cross(&b.n, &c.n), cross(&c.n, &a.n), cross(&a.n, &b.n));
    let mut x: Vec3 = std::array::from_fn(|i| &a.c * &bc[i] + &b.c * &ca[i] + &c.c * &ab[i]);
    let mut w = w;
    if w.is_negative() {
        x = [-&x[0], -&x[1], -&x[2]];
        w = -w;
    }
    Some(Homogeneous { x, w })
}

fn satisfies(h: &Halfspace, p: &Homogeneous) -> bool {
    dot(&h.n, &p.x) <= &h.c * &p.w
}

fn same_point(p: &Homogeneous, q: &Homogeneous) -> bool {
    (0..3).all(|i| &p.x[i] * &q.w == &q.x[i] * &p.w)
}

/// Affine dimension of a set of points (−1 when empty).
fn affine_dimension(v: &[Homogeneous]) -> i32 {
    let Some(first) = v.first() else { return -1 };
    // Differences scaled by W_i·W_0 stay integral and keep their direction.
    let diffs: Vec<Vec3> =
        v[1..].iter().map(|p| std::array::from_fn(|i| &p.x[i] * &first.w - &first.x[i] * &p.w)).filter(|d: &Vec3| !is_zero(d)).collect();
    let Some(a) = diffs.first() else { return 0 };
    let Some(normal) = diffs.iter().map(|b| cross(a, b)).find(|n| !is_zero(n)) else { return 1 };
    if diffs.iter().any(|c| !dot(&normal, c).is_zero()) {
        3
    } else {
        2
    }
}

/// The exact focus body `H = M ∩ S ∩ L` of f64 inputs.
pub fn exact_body(view: &[DVec3; 8], light: &Light, scene: &Aabb) -> Result<ExactBody, OracleError> {
    let mut values: Vec<f64> = view.iter().flat_map(|p| p.to_array()).collect();
    values.extend(scene.min.to_array());
    values.extend(scene.max.to_array());
    match light {
        Light::Directional { direction } => values.extend(direction.to_array()),
        Light::Point { position } => values.extend(position.to_array()),
        Light::Spot { position, frustum } => {
            values.extend(position.to_array());
            values.extend(frustum.corners().iter().flat_map(|p| p.to_array()));
        }
    }
    if values.iter().any(|v| !v.is_finite()) {
        return Err(OracleError::NotFinite);
    }
    let s = Scale::new(&values);
    let mut points: Vec<Vec3> = view.iter().map(|p| s.point(*p)).collect();
    let mut planes = Vec::new();
    match light {
        Light::Directional { direction } => {
            let ray = s.point(-*direction);
            hull_halfspaces(&points, Some(&ray), &mut planes);
        }
        Light::Point { position } | Light::Spot { position, .. } => {
            points.push(s.point(*position));
            hull_halfspaces(&points, None, &mut planes);
        }
    }
    box_halfspaces(&s, scene, &mut planes);
    if let Light::Spot { frustum, .. } = light {
        let corners: Vec<Vec3> = frustum.corners().iter().map(|p| s.point(*p)).collect();
        hull_halfspaces(&corners, None, &mut planes);
    }

    let mut vertices: Vec<Homogeneous> = Vec::new();
    let k = planes.len();
    for i in 0..k {
        for j in i + 1..k {
            for m in j + 1..k {
                let Some(p) = three_planes(&planes[i], &planes[j], &planes[m]) else { continue };
                if planes.iter().all(|h| satisfies(h, &p)) && !vertices.iter().any(|q| same_point(q, &p)) {
                    vertices.push(p);
                }
            }
        }
    }
    let dimension = affine_dimension(&vertices);
    let vertices = vertices.iter().map(|p| std::array::from_fn(|i| s.rational(&p.x[i], &p.w))).collect();
    Ok(ExactBody { dimension, vertices, halfspaces: planes, scale: s })
}

/// How a computed (rounded) body compares with the exact one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Agreement {
    pub dimension_matches: bool,
    pub vertex_counts_match: bool,
    /// Largest distance (max norm) from an exact vertex to the nearest
    /// computed vertex and from a computed vertex to the nearest exact one:
    /// the Hausdorff distance of the vertex sets, measured exactly.
    pub max_vertex_error: f64,
}

/// Compares computed vertices with the exact body.
pub fn compare(exact: &ExactBody, dimension: i32, vertices: &[DVec3]) -> Agreement {
    let ours: Vec<[BigRational; 3]> = vertices
        .iter()
        .filter_map(|v| Some([BigRational::from_float(v.x)?, BigRational::from_float(v.y)?, BigRational::from_float(v.z)?]))
        .collect();
    let distance = |a: &[BigRational; 3], b: &[BigRational; 3]| {
        (0..3).map(|i| (&a[i] - &b[i]).abs().to_f64().unwrap_or(f64::INFINITY)).fold(0.0, f64::max)
    };
    let nearest = |p: &[BigRational; 3], set: &[[BigRational; 3]]| set.iter().map(|q| distance(p, q)).fold(f64::INFINITY, f64::min);
    let mut err: f64 = 0.0;
    if ours.len() != vertices.len() {
        err = f64::INFINITY;
    }
    for p in &exact.vertices {
        err = err.max(nearest(p, &ours));
    }
    for p in &ours {
        err = err.max(nearest(p, &exact.vertices));
    }
    if exact.vertices.is_empty() && ours.is_empty() {
        err = 0.0;
    }
    Agreement {
        dimension_matches: exact.dimension == dimension,
        vertex_counts_match: exact.vertices.len() == vertices.len(),
        max_vertex_error: err,
    }
}

/// An exact vertex rounded to f64 coordinates (for plotting and for
/// evaluating f64 face planes on it).
pub fn to_f64(p: &[BigRational; 3]) -> DVec3 {
    DVec3::new(p[0].to_f64().unwrap_or(f64::NAN), p[1].to_f64().unwrap_or(f64::NAN), p[2].to_f64().unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadowfocus_geom::Frustum;

    /// The unit cube written as a frustum's eight corners (near face z = 1,
    /// far face z = 0), a valid solid.
    fn cube() -> [DVec3; 8] {
        let q = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        [q(0., 0., 1.), q(1., 0., 1.), q(1., 1., 1.), q(0., 1., 1.), q(0., 0., 0.), q(1., 0., 0.), q(1., 1., 0.), q(0., 1., 0.)]
    }

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb { min: DVec3::from_array(min), max: DVec3::from_array(max) }
    }

    fn f(v: DVec3) -> [f64; 3] {
        v.to_array()
    }

    #[test]
    fn cube_with_a_point_light_above_is_a_cube_and_a_pyramid() {
        let light = Light::Point { position: DVec3::new(0.5, 0.5, 3.0) };
        let h = exact_body(&cube(), &light, &aabb([-1.0; 3], [2.0, 2.0, 10.0])).unwrap();
        assert_eq!(h.dimension, 3);
        assert_eq!(h.vertices.len(), 9);
        assert!(h.vertices.iter().any(|v| f(to_f64(v)) == [0.5, 0.5, 3.0]));
    }

    #[test]
    fn scene_slices_the_pyramid_at_a_third() {
        // Cut at z = 2: the pyramid from z = 1 to 3 shrinks to half width.
        let light = Light::Point { position: DVec3::new(0.5, 0.5, 3.0) };
        let h = exact_body(&cube(), &light, &aabb([-1.0; 3], [2.0, 2.0, 2.0])).unwrap();
        assert_eq!(h.vertices.len(), 12);
        let mut top: Vec<[f64; 3]> = h.vertices.iter().map(to_f64).filter(|v| v.z == 2.0).map(f).collect();
        top.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(top, vec![[0.25, 0.25, 2.0], [0.25, 0.75, 2.0], [0.75, 0.25, 2.0], [0.75, 0.75, 2.0]]);
    }

    #[test]
    fn directional_light_is_an_infinite_extrusion_cut_by_the_scene() {
        // Light travelling down −z: M is the cube's column above it.
        let light = Light::Directional { direction: DVec3::new(0.0, 0.0, -1.0) };
        let h = exact_body(&cube(), &light, &aabb([-5.0; 3], [5.0, 5.0, 1e12])).unwrap();
        assert_eq!(h.dimension, 3);
        assert_eq!(h.vertices.len(), 8);
        assert!(h.vertices.iter().map(to_f64).filter(|v| v.z == 1e12).count() == 4);
        // Light travelling up: nothing above the cube.
        let up = Light::Directional { direction: DVec3::new(0.0, 0.0, 1.0) };
        let h = exact_body(&cube(), &up, &aabb([-5.0; 3], [5.0, 5.0, 1e12])).unwrap();
        assert!(h.vertices.iter().map(to_f64).all(|v| v.z >= -5.0 && v.z <= 1.0));
    }

    #[test]
    fn flat_and_empty_results_have_their_dimension() {
        let light = Light::Point { position: DVec3::new(0.5, 0.5, 3.0) };
        let flat = exact_body(&cube(), &light, &aabb([-1.0, -1.0, 1.0], [2.0, 2.0, 1.0])).unwrap();
        assert_eq!((flat.dimension, flat.vertices.len()), (2, 4));
        let edge = exact_body(&cube(), &light, &aabb([1.0, 1.0, -1.0], [2.0, 2.0, 1.0])).unwrap();
        assert_eq!(edge.dimension, 1);
        let apex = exact_body(&cube(), &light, &aabb([0.5, 0.5, 3.0], [0.5, 0.5, 3.0])).unwrap();
        assert_eq!((apex.dimension, apex.vertices.len()), (0, 1));
        let empty = exact_body(&cube(), &light, &aabb([0.5, 0.5, 3.0].map(|x: f64| x.next_up()), [4.0; 3])).unwrap();
        assert_eq!((empty.dimension, empty.vertices.len()), (-1, 0));
    }

    #[test]
    fn spot_frustum_cuts_the_body() {
        // A spot frustum equal to the cube's lower half.
        let mut lower = cube();
        for p in &mut lower[..4] {
            p.z = 0.5;
        }
        let spot = Light::Spot { position: DVec3::new(0.5, 0.5, 3.0), frustum: Frustum::from_corners(lower).unwrap() };
        let h = exact_body(&cube(), &spot, &aabb([-1.0; 3], [2.0; 3])).unwrap();
        assert_eq!(h.vertices.len(), 8);
        assert!(h.vertices.iter().map(to_f64).all(|v| v.z <= 0.5));
    }

    #[test]
    fn containment_is_exact() {
        let light = Light::Point { position: DVec3::new(0.5, 0.5, 3.0) };
        let h = exact_body(&cube(), &light, &aabb([-1.0; 3], [2.0, 2.0, 10.0])).unwrap();
        assert!(h.contains(DVec3::new(0.5, 0.5, 3.0)));
        assert!(!h.contains(DVec3::new(0.5, 0.5, 3.0f64.next_up())));
        // The slanted face through the edge x = 0, z = 1 and the apex is
        // x = (z − 1)/4: (0.25, 0.5, 2) is on it, one ulp off is outside.
        assert!(h.contains(DVec3::new(0.25, 0.5, 2.0)));
        assert!(!h.contains(DVec3::new(0.25f64.next_down(), 0.5, 2.0)));
        assert!(h.contains(DVec3::new(1e-300, 1e-300, 1e-300)));
        assert!(!h.contains(DVec3::new(-1e-300, 0.5, 0.5)));
    }

    #[test]
    fn comparison_detects_a_moved_vertex() {
        let light = Light::Point { position: DVec3::new(0.5, 0.5, 3.0) };
        let h = exact_body(&cube(), &light, &aabb([-1.0; 3], [2.0, 2.0, 10.0])).unwrap();
        let mut v: Vec<DVec3> = h.vertices.iter().map(to_f64).collect();
        assert_eq!(compare(&h, 3, &v).max_vertex_error, 0.0);
        v[3].x = v[3].x.next_up();
        let a = compare(&h, 3, &v);
        assert!(a.max_vertex_error > 0.0 && a.max_vertex_error < 1e-15);
        assert!(!compare(&h, 2, &v[..8]).vertex_counts_match);
    }

    #[test]
    fn non_finite_input_is_an_error() {
        let light = Light::Point { position: DVec3::new(f64::NAN, 0.5, 3.0) };
        assert_eq!(exact_body(&cube(), &light, &aabb([-1.0; 3], [2.0; 3])).unwrap_err(), OracleError::NotFinite);
    }
}
