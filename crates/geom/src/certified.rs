//! The fast path: clipping in plain `f64`, every decision certified.
//!
//! The body starts as `hull(V ∪ {l})` (its vertices are exact input points,
//! its faces given by the exact beneath–beyond signs) and is clipped by the
//! faces of the scene box `S` and of a spot light's frustum `L`.
//!
//! A vertex is kept as a rounded point with a per-coordinate bound on its
//! distance from the exact vertex; a side value comes with a bound on its
//! distance from the exact side value, and its sign is taken only when the
//! value is further from zero than the bound. A sign that no bound proves
//! (an exact zero the construction does not explain, or a value too close
//! to zero) abandons the fast path, and the caller runs the exact engine
//! ([`crate::polytope::Polytope`]) instead. So the fast path never decides
//! anything the exact engine would decide differently: it only skips the
//! exact engine's work when floating point provably suffices.
//!
//! Zeros that the construction explains are exact, not filtered:
//! - a vertex that is an input point (a frustum corner, the light) lies on
//!   every plane defined through that point;
//! - a coordinate fixed by a face of `S` (an axis plane) is exact, so its
//!   sign against any axis plane is a comparison of two floats;
//! - a vertex whose coordinates are all exact is tested with the exact
//!   orientation predicate.
//!
//! Two planes defined through a common pair of points meet in that line,
//! often at a tiny angle (the two triangles of a creased frustum side). A
//! vertex on one of them is then tested against the other through a
//! well-conditioned proxy: on plane `i`, plane `k` vanishes on the shared
//! line and nowhere else, so its sign is that of any plane through the line
//! transverse to `i`, times a constant sign fixed by one input point.
//!
//! Degenerate vertices (on more than three planes) are allowed: the clipper
//! keeps, per vertex, the set of planes it lies on, and clips through
//! on-plane vertices without creating new ones.
//!
//! A light in the plane of frustum faces merges each such face with the
//! light into one face of the hull (`reset_to_merged_hull`): exact
//! beneath–beyond signs decide which corners remain vertices.
//!
//! A vertex whose proven bound is above the output tolerance at the end
//! (planes meeting at a small angle) is placed from the exact intersection
//! of three of its planes (big integers), its combinatorics being proven
//! already; only such vertices pay for exact arithmetic.
//!
//! Flat results are exact coincidences too: a plane that leaves nothing
//! strictly inside leaves the body's face on it (its vertices, whose zero
//! signs are exact), a polygon, a segment or a point, which later planes
//! clip like a solid with one dimension fewer.

use crate::body::{Aabb, Body};
use crate::fixed::{meet, Meeting};
use crate::frustum::{corner_bits, creased_pair, Apex, Frustum, HullOutline, Origin};
use crate::limits::{MAX_FACE_INDICES, MAX_VERTICES};
use crate::number::{abs_cross, Exact};
use crate::plane::{intersect3, Plane};
use crate::polytope::{point_side, ROUNDING_ULPS};
use glam::{DMat3, DVec3, DVec4};

/// Unit roundoff.
const U: f64 = f64::EPSILON * 0.5;
/// NOTE: bounds are themselves rounded; every bound is a sum of products of
/// non-negative terms, low by at most a few ulps, which this factor covers.
const SLACK: f64 = 1.0 + 1.0 / (1u64 << 40) as f64;
/// Side values this small are never certified: it keeps underflow (where
/// relative error bounds fail) out of the way.
const FLOOR: f64 = 1e-280;

/// Hull of a frustum with a point (≤ 24) + closing plane + box (6) + light
/// frustum (≤ 12).
const MAX_FAST_PLANES: usize = 48;
/// Vertex slots of the fast path.
///
/// NOTE: vertex sets are `u64` bit sets. A body that would need more slots
/// (over 64 vertices at once: possible only with many planes of `L`) goes to
/// the exact engine; `u128` sets cost several instructions per variable
/// shift, on every cut and every face, for bodies that never need them.
const CAP_V: usize = 64;
const _: () = assert!(CAP_V <= 64 && CAP_V <= MAX_VERTICES);
/// A set of vertex slots.
type VertexSet = u64;
const NONE: u8 = u8::MAX;
/// Plane pairs whose fold proxy is remembered per body.
const FOLD_CACHE: usize = 8;
/// Input points: frustum corners 0–7, light 8, light frustum corners 9–16.
const N_POINTS: usize = 17;
const LIGHT_FRUSTUM_SHIFT: u32 = 9;

#[derive(Clone, Copy, Debug)]
struct FloatPlane {
    src: Plane,
    /// `x[axis] ≤ value` (or `≥`) when `axis < 3`; a general plane otherwise.
    axis: u8,
    upper: bool,
    value: f64,
    /// `n · (x − anchor) + offset ≤ 0` inside, with `|ñ − n| ≤ en` per component.
    n: DVec3,
    en: DVec3,
    anchor: DVec3,
    offset: f64,
    /// Input points the plane passes through by definition.
    through: u32,
}

impl FloatPlane {
    // NOTE: inlined so that callers build the ~250-byte plane in its slot
    // instead of copying it out of a temporary.
    #[inline(always)]
    fn new(src: Plane, through: u32) -> FloatPlane {
        let general = |n: DVec3, en: DVec3, anchor: DVec3, offset: f64| FloatPlane::general(src, n, en, anchor, offset, through);
        match src {
            Plane::Axis { axis, upper, value } => FloatPlane { through, ..FloatPlane::axis(axis, upper, value) },
            Plane::Points([p, q, r]) => {
                let (a, b) = (q - p, r - p);
                FloatPlane::through_points(src, p, a.cross(b), abs_cross(a, b), through)
            }
            // NOTE: as in `through_points`, with an exact direction: 3u.
            Plane::PointsDirection { p, q, direction } => {
                let a = q - p;
                general(a.cross(direction), abs_cross(a, direction) * (3.0 * U * SLACK), p, 0.0)
            }
            Plane::Coefficients { normal, offset } => general(normal, DVec3::ZERO, DVec3::ZERO, offset),
        }
    }

    /// The plane `src` = `Plane::Points([p, q, r])` from its cross product
    /// `(q − p) × (r − p)` and the same with absolute values (computed here,
    /// or stored by the frustum that validated the face).
    ///
    /// NOTE: a cross-product component is ã·b̃ − ã′·b̃′ over rounded
    /// differences: each product is off by 2u (its two differences) plus u
    /// (its rounding), the subtraction by u of the result, so
    /// |ñ − n| ≤ 4u·(|ã·b̃| + |ã′·b̃′|).
    #[inline(always)]
    fn through_points(src: Plane, p: DVec3, cross: DVec3, abs_cross: DVec3, through: u32) -> FloatPlane {
        FloatPlane::general(src, cross, abs_cross * (4.0 * U * SLACK), p, 0.0, through)
    }

    /// The plane of face `f` of a validated frustum, from the cross product
    /// its validation computed.
    #[inline(always)]
    fn of_face(frustum: &Frustum, f: usize, through: u32) -> FloatPlane {
        let (n, abs_n) = frustum.face_normal(f);
        let p = frustum.corners()[frustum.face(f)[0] as usize];
        FloatPlane::through_points(frustum.face_plane(f), p, n, abs_n, through)
    }

    /// `x[axis] ≤ value` (`upper`) or `≥ value`: exact, through no input point.
    fn axis(axis: u8, upper: bool, value: f64) -> FloatPlane {
        let mut n = DVec3::ZERO;
        *coord_mut(&mut n, axis as usize) = if upper { 1.0 } else { -1.0 };
        FloatPlane { axis, upper, value, ..FloatPlane::general(Plane::Axis { axis, upper, value }, n, DVec3::ZERO, DVec3::ZERO, 0.0, 0) }
    }

    /// `n · (x − anchor) + offset` with `|ñ − n| ≤ en`.
    #[inline(always)]
    fn general(src: Plane, n: DVec3, en: DVec3, anchor: DVec3, offset: f64, through: u32) -> FloatPlane {
        FloatPlane { src, axis: 3, upper: false, value: 0.0, n, en, anchor, offset, through }
    }

    /// Side value at a point known within `r`, and a bound on its error.
    #[inline]
    fn side(&self, x: DVec3, r: DVec3) -> (f64, f64) {
        if self.axis < 3 {
            let k = self.axis as usize;
            let d = coord(&x, k) - self.value;
            let s = if self.upper { d } else { -d };
            // NOTE: with an exact coordinate (r = 0) the rounded difference
            // has the exact sign, zero included: the bound is 2u·|s| < |s|.
            return (s, coord(&r, k) * SLACK + 2.0 * U * s.abs());
        }
        self.general_side(x, r, &self.side_bound())
    }

    /// The coefficients of a general plane's side bound.
    ///
    /// NOTE: |s̃ − s| ≤ 6u(|ñ|·|w̃| + |offset|) (the dot product, the
    /// difference w̃ = x̃ − anchor and the offset's addition) + en·|w̃|
    /// (the normal's error) + (|ñ| + en)·r (the point's error). Computed
    /// where a plane is tested rather than stored with it: most planes
    /// (the hull's, in a body without a spot light) are never tested.
    #[inline]
    fn side_bound(&self) -> SideBound {
        let na = self.n.abs();
        SideBound { w: na * (6.0 * U) + self.en, r: na + self.en, offset: 6.0 * U * self.offset.abs() }
    }

    /// [`FloatPlane::side`] of a general plane, its bound's coefficients
    /// given (for testing many points against one plane).
    #[inline]
    fn general_side(&self, x: DVec3, r: DVec3, b: &SideBound) -> (f64, f64) {
        let w = x - self.anchor;
        let s = self.n.dot(w) + self.offset;
        let e = (b.w.dot(w.abs()) + b.r.dot(r) + b.offset) * SLACK + FLOOR;
        (s, e)
    }

    /// Rounded unit normal and offset for output.
    fn approximate(&self) -> DVec4 {
        if self.axis < 3 {
            let s = if self.upper { 1.0 } else { -1.0 };
            return self.n.extend(-s * self.value);
        }
        // NOTE: one division for the four coefficients: the output plane is
        // a rounded one, and a product by the reciprocal is one rounding more
        // (an ulp), against four divisions' latency per face.
        let len = self.n.length();
        let inv = 1.0 / len;
        if len > 0.0 && len.is_finite() && inv.is_finite() && self.en.max_element() <= len * 2f64.powi(-40) {
            return (self.n * inv).extend((self.offset - self.n.dot(self.anchor)) * inv);
        }
        self.src.approximate()
    }
}

/// A general plane's side bound `e = w·|x − anchor| + r·rad + offset`
/// (see [`FloatPlane::side_bound`]).
struct SideBound {
    w: DVec3,
    r: DVec3,
    offset: f64,
}

/// A plane through the line `a`–`c` of plane `p`, perpendicular to `p`:
/// with `p` it defines that line well even where another plane through the
/// line meets `p` at a tiny angle.
fn line_proxy(p: &FloatPlane, a: DVec3, c: DVec3) -> FloatPlane {
    // NOTE: m = (c − a) × n_p; its error comes from the rounded difference,
    // from n_p's error, and from the cross product's own rounding.
    let e = c - a;
    let en = abs_cross(e, p.en) * SLACK + abs_cross(e, p.n) * (5.0 * U);
    FloatPlane::general(Plane::Coefficients { normal: DVec3::ZERO, offset: 0.0 }, e.cross(p.n), en, a, 0.0, 0)
}

/// Coordinate `axis` (0, 1 or 2) of `p`, and its place.
///
/// NOTE: glam's `p[axis]` is a three-way match on every access, and in the
/// per-vertex loops that was ~2 % of a body; as an array index it is one
/// load (the `min` lets the bounds check go).
#[inline(always)]
fn coord(p: &DVec3, axis: usize) -> f64 {
    p.as_ref()[axis.min(2)]
}

#[inline(always)]
fn coord_mut(p: &mut DVec3, axis: usize) -> &mut f64 {
    &mut p.as_mut()[axis.min(2)]
}

/// Where the line `a + t·d` meets a plane: `a` exact, `d` exact or the
/// rounded difference of two exact points (`d_rounded`).
fn line_crossing(a: DVec3, d: DVec3, d_rounded: bool, p: &FloatPlane) -> Option<(DVec3, DVec3)> {
    if p.axis < 3 {
        let axis = p.axis as usize;
        if coord(&d, axis) == 0.0 {
            return None;
        }
        // NOTE: t = (value − a_k)/d_k carries at most three roundings (the
        // two differences and the quotient), so |t̃ − t| ≤ 3u|t| (plus second
        // order); x_m = a_m + t·d_m adds two more of |t·d_m| and one of |x_m|.
        let t = (p.value - coord(&a, axis)) / coord(&d, axis);
        let td = d * t;
        let mut x = a + td;
        *coord_mut(&mut x, axis) = p.value;
        let mut rad = exact_where_still((td.abs() * (6.0 * U) + x.abs() * (2.0 * U)) * SLACK + DVec3::splat(1e-300), d);
        *coord_mut(&mut rad, axis) = 0.0;
        // NOTE: `a` is finite, so a finite `x` has a finite `td`, and then
        // `rad` is finite too.
        return x.is_finite().then_some((x, rad));
    }
    // NOTE: t = −P(a)/(n·d). P(a) is known within e_q (the side bound at an
    // exact point); n·d within e_δ = en·|d| + 4u·|n|·|d| (+2u|n|·|d| when d
    // is a rounded difference). Then |t̃ − t| ≤ (e_q + |t̃|·e_δ)/(|δ̃| − e_δ)
    // + 2u|t̃|, and x = a + t·d adds |d|·|t̃ − t| and the final roundings.
    let (q, eq) = p.side(a, DVec3::ZERO);
    let delta = p.n.dot(d);
    let (na, da) = (p.n.abs(), d.abs());
    let ed = (p.en.dot(da) + na.dot(da) * if d_rounded { 6.0 * U } else { 4.0 * U }) * SLACK;
    if !(delta.abs() > 2.0 * ed) {
        return None;
    }
    let t = -q / delta;
    let et = (eq + t.abs() * ed) / (delta.abs() - ed) + 2.0 * U * t.abs();
    let td = d * t;
    let x = a + td;
    let rad = exact_where_still((da * et * (1.0 + 4.0 * U) + td.abs() * (4.0 * U) + x.abs() * (2.0 * U)) * SLACK + DVec3::splat(1e-300), d);
    (x.is_finite() && rad.is_finite()).then_some((x, rad))
}

/// Zero radius on the axes the line does not move along.
///
/// NOTE: a zero component of `d` is exact (a rounded difference is zero only
/// when the two coordinates are equal), so there `x = a + t·0 = a` exactly.
fn exact_where_still(rad: DVec3, d: DVec3) -> DVec3 {
    DVec3::select(d.cmpeq(DVec3::ZERO), DVec3::ZERO, rad)
}

/// Indices of the set bits of a plane or input-point mask, lowest first.
fn bits(mask: u64) -> Bits {
    Bits(mask)
}

struct Bits(u64);

impl Iterator for Bits {
    type Item = usize;

    #[inline]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

/// Whether a plane mask has two or more bits set (two common planes: an
/// edge).
#[inline]
fn two_or_more(mask: u64) -> bool {
    mask & mask.wrapping_sub(1) != 0
}

/// A sign proven by `(value, bound)`; `bound == 0` means the value is exact.
#[inline]
fn decide(s: f64, e: f64) -> Option<i8> {
    if !s.is_finite() {
        None
    } else if s > e {
        Some(1)
    } else if s < -e {
        Some(-1)
    } else if e == 0.0 {
        Some(0)
    } else {
        None
    }
}

/// How a clip ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// The body is not empty (cut or not; solid or flat).
    Nonempty,
    Empty,
    /// A decision floating point could not prove: run the exact engine.
    Uncertain,
}

/// The proxy for testing points of plane `i` against plane `k` when both
/// pass through two common input points (see the module notes).
#[derive(Clone, Copy)]
struct Fold {
    /// A plane through the common line, transverse to plane `i`.
    proxy: FloatPlane,
    /// `sign(k) = sign × sign(proxy)` on plane `i`.
    sign: f64,
}

/// Scratch space of the fast path, reused across frames.
#[derive(Clone)]
pub(crate) struct CertifiedClipper {
    planes: [FloatPlane; MAX_FAST_PLANES],
    /// Per plane: the earlier planes sharing a line of input points with it.
    partners: [u64; MAX_FAST_PLANES],
    n_planes: usize,
    points: [DVec3; N_POINTS],
    pos: [DVec3; CAP_V],
    rad: [DVec3; CAP_V],
    /// Planes each vertex lies on exactly.
    on: [u64; CAP_V],
    /// Input points each vertex is exactly equal to.
    is_point: [u32; CAP_V],
    n_verts: usize,
    magnitude: f64,
    sign: [i8; CAP_V],
    /// `write`'s scratch: per plane, the vertices on it (a vertex set).
    plane_members: [VertexSet; MAX_FAST_PLANES],
    /// `write`'s scratch: per vertex, the vertices it shares an edge with.
    neighbours: [VertexSet; CAP_V],
    /// `write`'s scratch: per vertex `a`, the vertices `b` such that a face
    /// written so far runs along the edge from `a` to `b`.
    directed: [VertexSet; CAP_V],
    /// Plane pairs `(i, k)` whose fold proxy is in `fold_proxies` (same
    /// slot), failures included (`None`).
    ///
    /// NOTE: the keys live apart from the proxies so that a new body resets
    /// 16 bytes, not eight ~250-byte proxies.
    fold_keys: [(u8, u8); FOLD_CACHE],
    fold_proxies: [Option<Fold>; FOLD_CACHE],
    /// Planes that are axis planes (faces of S, a closing plane).
    axis_planes: u64,
    /// Planes that cut.
    pub cuts: u16,
    /// Planes of S and L not clipped: the body's bounding box clears them.
    pub cleared: u16,
    /// The face of S (axis, upper) that closes a directional light's hull.
    closed_by_scene_face: Option<(u8, bool)>,
    /// Dimension of the body: 3 while solid; 2, 1, 0 once a plane has left
    /// only a polygon, a segment or a point of it.
    dim: i8,
    /// Planes that contain the whole body (none while it is solid).
    ///
    /// NOTE: in a flat body every vertex lies on these, so they say nothing
    /// about adjacency: two vertices of a polygon are adjacent exactly when
    /// they share another plane (each other plane supports the polygon in an
    /// edge or a vertex).
    flat: u64,
    /// The plane that left a polygon: its outward normal orients the cycle.
    support: usize,
    /// Vertices `write` placed exactly (see `exact_vertex`).
    pub exact_vertices: u16,
}

const DUMMY_PLANE: FloatPlane = FloatPlane {
    src: Plane::Axis { axis: 0, upper: true, value: 0.0 },
    axis: 0,
    upper: true,
    value: 0.0,
    n: DVec3::ZERO,
    en: DVec3::ZERO,
    anchor: DVec3::ZERO,
    offset: 0.0,
    through: 0,
};

impl CertifiedClipper {
    pub(crate) fn new() -> CertifiedClipper {
        CertifiedClipper {
            planes: [DUMMY_PLANE; MAX_FAST_PLANES],
            partners: [0; MAX_FAST_PLANES],
            n_planes: 0,
            points: [DVec3::ZERO; N_POINTS],
            pos: [DVec3::ZERO; CAP_V],
            rad: [DVec3::ZERO; CAP_V],
            on: [0; CAP_V],
            is_point: [0; CAP_V],
            n_verts: 0,
            magnitude: 0.0,
            sign: [0; CAP_V],
            plane_members: [0; MAX_FAST_PLANES],
            neighbours: [0; CAP_V],
            directed: [0; CAP_V],
            fold_keys: [(NONE, NONE); FOLD_CACHE],
            fold_proxies: [None; FOLD_CACHE],
            axis_planes: 0,
            cuts: 0,
            cleared: 0,
            closed_by_scene_face: None,
            dim: 3,
            flat: 0,
            support: 0,
            exact_vertices: 0,
        }
    }

    /// Starts from `hull(V ∪ {l})` itself, built from the exact beneath–
    /// beyond signs behind `hull`: its vertices are frustum corners and the
    /// light, all exact input points. A directional light's unbounded hull is
    /// closed by a plane that holds the scene box and the frustum (the face
    /// of S the light enters through, when it can), which cuts nothing of
    /// `H`. `Uncertain` when some face plane contains the light (the faces
    /// are then not all distinct planes).
    pub(crate) fn reset_to_hull(
        &mut self,
        view: &Frustum,
        apex: Apex,
        hull: &HullOutline,
        scene: &Aabb,
        light_frustum: Option<&[DVec3; 8]>,
    ) -> Step {
        self.n_planes = 0;
        self.n_verts = 0;
        self.axis_planes = 0;
        self.cuts = 0;
        self.cleared = 0;
        self.exact_vertices = 0;
        self.closed_by_scene_face = None;
        self.dim = 3;
        self.flat = 0;
        self.fold_keys = [(NONE, NONE); FOLD_CACHE];
        // NOTE: beneath–beyond takes the frustum's faces as the hull's; when
        // a corner lies in another face's plane the frustum's own faces merge
        // (with corners inside them), so such frusta go to the exact engine.
        // (A light in a face's plane is built below.)
        if !view.faces_are_hull_faces() || hull.len() + 1 > MAX_FAST_PLANES {
            return Step::Uncertain;
        }
        let corners = view.corners();
        self.points[..8].copy_from_slice(corners);
        // The largest input magnitude, per axis first: over S, the corners
        // and the light (and its frustum), the input points that exist.
        let mut magnitude = corners.iter().fold(scene.min.abs().max(scene.max.abs()), |m, c| m.max(c.abs()));
        self.points[8] = match apex {
            Apex::Finite(l) => {
                magnitude = magnitude.max(l.abs());
                l
            }
            Apex::Infinite(_) => DVec3::NAN,
        };
        match light_frustum {
            Some(c) => {
                self.points[9..].copy_from_slice(c);
                magnitude = c.iter().fold(magnitude, |m, c| m.max(c.abs()));
            }
            None => self.points[9..].fill(DVec3::NAN),
        }
        self.magnitude = magnitude.max_element();
        if hull.coplanar != 0 {
            return self.reset_to_merged_hull(view, apex, hull, scene);
        }
        // Per input point (frustum corners 0–7, light 8): the planes defined
        // through it, all exact incidences.
        let mut planes_of = [0u64; 9];
        let mut horizon = 0u64;
        for (p, (&through, &origin)) in hull.through().iter().zip(hull.origins()).enumerate() {
            self.planes[p] = match origin {
                Origin::Face(f) => FloatPlane::of_face(view, f as usize, through),
                Origin::Horizon(..) => FloatPlane::new(view.hull_plane(apex, origin), through),
            };
            self.partners[p] = 0;
            horizon |= u64::from(matches!(origin, Origin::Horizon(..))) << p;
            for c in bits(u64::from(through)) {
                planes_of[c] |= 1 << p;
            }
        }
        self.n_planes = hull.len();
        // The vertices: the input points on some plane (a corner whose faces
        // all see the light is inside the hull), exact.
        for (c, &on) in planes_of.iter().enumerate() {
            if on != 0 {
                self.push_input_vertex(c, on);
            }
        }
        let Apex::Infinite(toward) = apex else { return Step::Nonempty };
        // A light at infinity: each corner on the horizon lies on two horizon
        // planes, which its ray toward the light follows.
        let mut rays = [0u64; 8];
        for (ray, &on) in rays.iter_mut().zip(&planes_of[..8]) {
            *ray = on & horizon;
            if *ray != 0 && (!two_or_more(*ray) || two_or_more(*ray & (*ray - 1))) {
                return Step::Uncertain;
            }
        }
        self.cast_shadows(toward, scene, corners, &rays)
    }

    /// `hull(V ∪ {l})` when the light lies in the plane of some frustum
    /// faces (exact signs in `hull.sees` and `hull.coplanar`).
    ///
    /// Beneath–beyond with the light on a face's plane: that face and the
    /// light make one facet on the face's plane, and no horizon facet rises
    /// on its edges (it would lie in that plane). A corner stays a vertex
    /// exactly when the light lies strictly beneath some face through it:
    /// a corner whose faces all see the light or hold it lies inside a merged
    /// facet or on one of its edges (between the light and another corner).
    /// The light itself is a vertex when some face sees it; when none does,
    /// it lies on V's boundary and the hull is V (every corner a vertex, the
    /// light one only if it is a corner).
    ///
    /// For a light at infinity a ray from a kept corner is an edge exactly
    /// when two of the hull's planes through the corner contain the
    /// direction (horizon planes, and faces holding the light): then its
    /// shadow on the closing plane is a vertex on those planes.
    fn reset_to_merged_hull(&mut self, view: &Frustum, apex: Apex, hull: &HullOutline, scene: &Aabb) -> Step {
        let (sees, coplanar) = (hull.sees, hull.coplanar);
        let light_in_view = sees == 0;
        let n_faces = view.face_count();
        let beneath = !(sees | coplanar) & ((1u16 << n_faces) - 1);
        let apex_bit = apex.through_bit();
        let mut kept = if light_in_view { 0xff } else { 0u32 };
        for i in bits(beneath as u64) {
            kept |= corner_bits(view.face(i));
        }
        // Planes, in the order the outline lists them, less the horizon
        // planes raised toward a face that holds the light.
        // `with_light`: the planes through the light (or, at infinity,
        // containing its direction).
        let (mut np, mut with_light) = (0, 0u64);
        for (&through, &origin) in hull.through().iter().zip(hull.origins()) {
            self.planes[np] = match origin {
                Origin::Face(f) => {
                    let holds_light = coplanar & 1 << f != 0;
                    with_light |= u64::from(holds_light) << np;
                    FloatPlane::of_face(view, f as usize, through | if holds_light { apex_bit } else { 0 })
                }
                Origin::Horizon(a, b) => match view.face_with_edge(b, a) {
                    Some(g) if beneath & 1 << g != 0 => {
                        with_light |= 1 << np;
                        FloatPlane::new(view.hull_plane(apex, origin), through)
                    }
                    _ => continue,
                },
            };
            self.partners[np] = 0;
            np += 1;
        }
        self.n_planes = np;
        // Incidences from the planes' defining points; per kept corner, its
        // planes that contain the light's direction.
        let (mut planes_of, mut along) = ([0u64; 8], [0u64; 8]);
        for p in 0..np {
            let bit = 1u64 << p;
            for c in bits(u64::from(self.planes[p].through) & u64::from(kept)) {
                planes_of[c] |= bit;
                along[c] |= bit & with_light;
            }
        }
        // Vertices: the kept corners, then the light (or the shadows).
        for c in bits(kept as u64) {
            self.push_input_vertex(c, planes_of[c]);
        }
        let toward = match apex {
            Apex::Finite(_) => {
                if !light_in_view {
                    self.push_input_vertex(8, with_light);
                }
                return Step::Nonempty;
            }
            Apex::Infinite(toward) => toward,
        };
        let rays = along.map(|planes| if two_or_more(planes) { planes } else { 0 });
        self.cast_shadows(toward, scene, view.corners(), &rays)
    }

    /// Closes the hull of a light at infinity: appends the closing plane,
    /// and for each corner whose ray toward the light is an edge (`rays[c]`:
    /// the hull's planes along it, or none) the ray's shadow on that plane.
    fn cast_shadows(&mut self, toward: DVec3, scene: &Aabb, corners: &[DVec3; 8], rays: &[u64; 8]) -> Step {
        let Some(cap) = self.closing_plane(toward, scene, corners) else { return Step::Uncertain };
        let mut shadows = 0;
        for (c, &planes) in rays.iter().enumerate() {
            if planes == 0 {
                continue;
            }
            if self.push_shadow(c, planes | 1 << cap, cap, toward).is_none() {
                return Step::Uncertain;
            }
            shadows += 1;
        }
        // The closing plane's face is the horizon's shadow: at least a triangle.
        if shadows < 3 {
            return Step::Uncertain;
        }
        Step::Nonempty
    }

    /// Appends input point `i` as an exact vertex on the planes `on` (the
    /// hull's first vertices: at most nine, so always room).
    fn push_input_vertex(&mut self, i: usize, on: u64) {
        let v = self.n_verts;
        self.pos[v] = self.points[i];
        self.rad[v] = DVec3::ZERO;
        self.on[v] = on;
        self.is_point[v] = 1 << i;
        self.n_verts += 1;
    }

    /// An axis plane that holds S and every frustum corner strictly inside,
    /// facing the light on the axis the light crosses most steeply; appended
    /// to the planes, its index returned.
    fn closing_plane(&mut self, toward: DVec3, scene: &Aabb, corners: &[DVec3; 8]) -> Option<usize> {
        let k = self.n_planes;
        if k >= MAX_FAST_PLANES {
            return None;
        }
        let axis = toward.abs().max_position();
        let upper = toward[axis] > 0.0;
        let face = if upper { scene.max[axis] } else { scene.min[axis] };
        let beyond = |value: f64, c: f64| if upper { c < value } else { c > value };
        let value = if corners.iter().all(|c| beyond(face, c[axis])) {
            // The face of S the light comes through: it bounds H anyway (so
            // the scene clip can skip it), and no shadow is made only to be
            // cut away.
            self.closed_by_scene_face = Some((axis as u8, upper));
            face
        } else {
            // NOTE: the extreme coordinate of S and the corners is an input
            // value, so exact; padding it by 1/64 of the spread keeps the
            // plane away from every corner, and any float beyond it is
            // strictly beyond.
            let (mut lo, mut hi) = (scene.min[axis], scene.max[axis]);
            for c in corners {
                lo = lo.min(c[axis]);
                hi = hi.max(c[axis]);
            }
            let pad = (hi - lo) * (1.0 / 64.0);
            let (value, extreme) = if upper { (hi + pad, hi) } else { (lo - pad, lo) };
            if !(value.is_finite() && beyond(value, extreme)) {
                return None;
            }
            value
        };
        // An axis plane gives the shadow vertices an exact coordinate and
        // cheap crossings with the scene's faces.
        self.planes[k] = FloatPlane::axis(axis as u8, upper, value);
        self.axis_planes |= 1 << k;
        self.partners[k] = 0;
        self.n_planes += 1;
        Some(k)
    }

    /// Appends the vertex where the ray from corner `c` toward the light
    /// meets the closing plane `cap`, on the planes `on`.
    #[inline(always)]
    fn push_shadow(&mut self, c: usize, on: u64, cap: usize, toward: DVec3) -> Option<u8> {
        if self.n_verts >= CAP_V {
            return None;
        }
        // On the ray from the corner toward the light (both exact).
        let (pos, rad) = line_crossing(self.points[c], toward, false, &self.planes[cap])?;
        let v = self.n_verts;
        self.pos[v] = pos;
        self.rad[v] = rad;
        self.on[v] = on;
        self.is_point[v] = 0;
        self.n_verts += 1;
        Some(v as u8)
    }

    /// Clips by the six faces of a box.
    ///
    /// A face whose plane clears the body's bounding box is not clipped: it
    /// neither cuts nor touches, so clipping would only prove every vertex
    /// inside, one by one.
    pub(crate) fn clip_box(&mut self, b: &Aabb) -> Step {
        let (lo, hi) = self.bounds();
        for axis in 0..3u8 {
            let a = axis as usize;
            for upper in [false, true] {
                let value = if upper { b.max[a] } else { b.min[a] };
                if self.closed_by_scene_face == Some((axis, upper)) {
                    continue;
                }
                if if upper { value > hi[a] } else { value < lo[a] } {
                    self.cleared += 1;
                    continue;
                }
                let Some(slot) = self.next_slot() else { return Step::Uncertain };
                *slot = FloatPlane::axis(axis, upper, value);
                let step = self.clip();
                if step != Step::Nonempty {
                    return step;
                }
            }
        }
        Step::Nonempty
    }

    /// Per-axis bounds on the vertices' exact positions (`lo ≤ x ≤ hi`), so
    /// that a plane strictly beyond them has every vertex strictly inside.
    fn bounds(&self) -> (DVec3, DVec3) {
        // NOTE: each exact coordinate lies within its `rad` of `pos`; one pad
        // for all, 4·max rad + 4u·max |pos|, leaves at least 3·max rad +
        // 4u·max |pos| beyond that, more than the roundings of the pad and of
        // the sums (each under u of its magnitude).
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let (mut r_max, mut x_max) = (DVec3::ZERO, DVec3::ZERO);
        for v in 0..self.n_verts {
            let (x, r) = (self.pos[v], self.rad[v]);
            lo = lo.min(x);
            hi = hi.max(x);
            r_max = r_max.max(r);
            x_max = x_max.max(x.abs());
        }
        let pad = r_max * 4.0 + x_max * (4.0 * U);
        (lo - pad, hi + pad)
    }

    /// Clips by the faces of a spot light's frustum (its corners are input
    /// points 9–16), each built from the normal the frustum's validation
    /// computed.
    ///
    /// As in `clip_box`, a plane the body's bounding box lies strictly
    /// inside of is not clipped.
    pub(crate) fn clip_frustum(&mut self, frustum: &Frustum) -> Step {
        let (lo, hi) = self.bounds();
        // NOTE: the box as a point known within a radius: the radius is
        // rounded up past both half-extents, so the side test's bound covers
        // every point of the box.
        let centre = (lo + hi) * 0.5;
        let radius = (hi - centre).max(centre - lo) * (1.0 + 4.0 * U);
        for f in 0..frustum.face_count() {
            let through = corner_bits(frustum.face(f)) << LIGHT_FRUSTUM_SHIFT;
            // Staged in the next free slot: a cleared plane is overwritten
            // by the next one.
            let Some(slot) = self.next_slot() else { return Step::Uncertain };
            *slot = FloatPlane::of_face(frustum, f, through);
            let (s, e) = slot.side(centre, radius);
            if decide(s, e) == Some(-1) {
                self.cleared += 1;
                continue;
            }
            let step = self.clip();
            if step != Step::Nonempty {
                return step;
            }
        }
        Step::Nonempty
    }

    /// The free slot where [`CertifiedClipper::clip`] takes its plane;
    /// `None` when every slot is used.
    fn next_slot(&mut self) -> Option<&mut FloatPlane> {
        self.planes.get_mut(self.n_planes)
    }

    /// Clips by the plane the caller staged in slot `n_planes` (see
    /// [`CertifiedClipper::next_slot`]).
    ///
    /// NOTE: staged in place rather than passed by value: a plane is ~250
    /// bytes, and two copies of it per clip were a visible share of a cut.
    fn clip(&mut self) -> Step {
        let k = self.n_planes;
        let plane = &self.planes[k];
        let (through, axis, upper, value) = (plane.through, plane.axis, plane.upper, plane.value);
        // NOTE: the planes clipped by are faces of S and of L, whose values
        // and defining points are in `magnitude` already (`reset_to_hull`).
        debug_assert!(plane.src.magnitude() <= self.magnitude);
        let mut partners = 0;
        if two_or_more(through as u64) {
            for (i, p) in self.planes[..k].iter().enumerate() {
                if two_or_more((p.through & through) as u64) && matches!(p.src, Plane::Points(_)) {
                    partners |= 1 << i;
                }
            }
        }
        self.partners[k] = partners;
        // The vertices strictly inside and strictly outside, as vertex sets.
        let (mut inside, mut outside): (VertexSet, VertexSet) = (0, 0);
        if axis < 3 {
            // An axis plane has no input points and no fold partners: its
            // sign is a comparison, exact where the coordinate is.
            self.axis_planes |= 1 << k;
            let a = axis as usize;
            let flip = if upper { 1.0 } else { -1.0 };
            for v in 0..self.n_verts {
                let s = (coord(&self.pos[v], a) - value) * flip;
                let Some(s) = decide(s, coord(&self.rad[v], a) * SLACK + 2.0 * U * s.abs()) else { return Step::Uncertain };
                self.sign[v] = s;
                inside |= u64::from(s < 0) << v;
                outside |= u64::from(s > 0) << v;
            }
        } else {
            let bound = self.planes[k].side_bound();
            for v in 0..self.n_verts {
                let Some(s) = self.sign_at(v, k, &bound) else { return Step::Uncertain };
                self.sign[v] = s;
                inside |= u64::from(s < 0) << v;
                outside |= u64::from(s > 0) << v;
            }
        }
        let bit = 1u64 << k;
        if outside == 0 {
            // Not cut; remember which vertices the plane touches.
            // NOTE: a supporting plane through three vertices of a solid
            // (never collinear: all are extreme points) is the plane of a face
            // already there. Its incidences are left out so that two vertices
            // share two planes exactly when they span an edge (see `cut`). A
            // flat body's supporting plane holds an edge, a vertex, or all of
            // it (then it joins the flat planes).
            let touching = self.sign[..self.n_verts].iter().filter(|&&s| s == 0).count();
            if touching == self.n_verts {
                if self.dim == 3 {
                    return Step::Uncertain;
                }
                self.flat |= bit;
            } else if self.dim < 3 && touching > self.dim as usize {
                return Step::Uncertain;
            }
            if touching < 3 || touching == self.n_verts {
                for v in 0..self.n_verts {
                    if self.sign[v] == 0 {
                        self.on[v] |= bit;
                    }
                }
            }
            self.n_planes += 1;
            return Step::Nonempty;
        }
        if inside == 0 {
            // Entirely outside (empty), or touching from outside: what is
            // left is the body's face on the plane (flat).
            return if self.sign[..self.n_verts].contains(&0) { self.flatten(k) } else { Step::Empty };
        }
        self.n_planes += 1;
        self.cuts += 1;
        if self.cut(k, inside, outside) {
            Step::Nonempty
        } else {
            Step::Uncertain
        }
    }

    /// Copies vertex slot `from` into slot `to`.
    fn move_vertex(&mut self, from: usize, to: usize) {
        self.pos[to] = self.pos[from];
        self.rad[to] = self.rad[from];
        self.on[to] = self.on[from];
        self.is_point[to] = self.is_point[from];
    }

    /// Keeps only the vertices on plane `k` (signs in `self.sign`, none
    /// inside): the body's face on `k`, a polygon, an edge or a vertex.
    ///
    /// NOTE: every sign is exact, so these are all of the face's vertices;
    /// three or more vertices of a solid on one supporting plane are a
    /// polygon (extreme points, never collinear), and a flat body's face on
    /// a plane that does not hold all of it has one dimension fewer.
    fn flatten(&mut self, k: usize) -> Step {
        let bit = 1u64 << k;
        let mut n = 0;
        for v in 0..self.n_verts {
            if self.sign[v] == 0 {
                self.move_vertex(v, n);
                self.on[n] |= bit;
                n += 1;
            }
        }
        let dim = match n {
            1 => 0,
            2 => 1,
            _ => 2,
        };
        if dim >= self.dim {
            return Step::Uncertain;
        }
        if dim == 2 {
            self.support = k;
        }
        self.n_verts = n;
        self.dim = dim;
        self.flat = self.on[..n].iter().fold(u64::MAX, |all, &on| all & on);
        self.n_planes += 1;
        Step::Nonempty
    }

    /// Exact sign of vertex `v` against plane `k`, if provable.
    fn sign_at(&mut self, v: usize, k: usize, bound: &SideBound) -> Option<i8> {
        let plane = &self.planes[k];
        if self.is_point[v] & plane.through != 0 {
            return Some(0);
        }
        let (x, r) = (self.pos[v], self.rad[v]);
        // A point on several planes that share a line with k: any of them
        // may decide (the point can lie close to one line and far from another).
        for i in bits(self.on[v] & self.partners[k]) {
            if let Some(fold) = self.fold(i, k) {
                let (s, e) = fold.proxy.side(x, r);
                if let Some(s) = decide(s, e) {
                    return Some(s * fold.sign as i8);
                }
            }
        }
        let plane = &self.planes[k];
        let (s, e) = plane.general_side(x, r, bound);
        if let Some(s) = decide(s, e) {
            return Some(s);
        }
        if r == DVec3::ZERO {
            // An exactly known point: the exact predicate decides.
            return Some(point_side(&plane.src, x));
        }
        None
    }

    /// The fold proxy for points on plane `i` tested against plane `k`
    /// (planes sharing a line of input points), cached per body.
    /// `None` when the pair has no proxy.
    fn fold(&mut self, i: usize, k: usize) -> Option<&Fold> {
        let key = (i as u8, k as u8);
        let slot = match self.fold_keys.iter().position(|&e| e == key) {
            Some(slot) => slot,
            None => {
                let f = self.make_fold(i, k, self.planes[i].through & self.planes[k].through);
                let slot = self.fold_keys.iter().position(|e| e.0 == NONE).unwrap_or(k % FOLD_CACHE);
                self.fold_keys[slot] = key;
                self.fold_proxies[slot] = f;
                slot
            }
        };
        self.fold_proxies[slot].as_ref()
    }

    fn make_fold(&self, i: usize, k: usize, common: u32) -> Option<Fold> {
        let mut ids = bits(common as u64);
        let (a, c) = (self.points[ids.next()?], self.points[ids.next()?]);
        let Plane::Points(defining) = self.planes[i].src else { return None };
        if a == c {
            return None;
        }
        // A defining point of plane i off the common line.
        let y = *defining.iter().find(|&&p| p != a && p != c)?;
        let proxy = line_proxy(&self.planes[i], a, c);
        let (s, err) = proxy.side(y, DVec3::ZERO);
        let proxy_y = decide(s, err).filter(|&s| s != 0)?;
        // NOTE: across a crease `y` lies within rounding of plane k, where
        // only exact arithmetic decides; the frustum's fold test already did.
        let (ti, tk) = (self.planes[i].through, self.planes[k].through);
        let creased = creased_pair(ti, tk) || creased_pair(ti >> LIGHT_FRUSTUM_SHIFT, tk >> LIGHT_FRUSTUM_SHIFT);
        let k_y = if creased { -1 } else { point_side(&self.planes[k].src, y) };
        debug_assert_eq!(k_y, point_side(&self.planes[k].src, y));
        if k_y == 0 {
            return None;
        }
        Some(Fold { proxy, sign: (k_y * proxy_y) as f64 })
    }

    /// Side values of the two ends of edge `u`–`w` against plane `k`, on
    /// one scale (the fold proxy when the edge lies in a folding plane).
    fn edge_sides(&mut self, u: usize, w: usize, k: usize) -> [(f64, f64); 2] {
        let ((xu, ru), (xw, rw)) = ((self.pos[u], self.rad[u]), (self.pos[w], self.rad[w]));
        let common = self.on[u] & self.on[w] & self.partners[k];
        if common != 0 {
            if let Some(f) = self.fold(common.trailing_zeros() as usize, k) {
                let side = |x, r| {
                    let (s, e) = f.proxy.side(x, r);
                    (s * f.sign, e)
                };
                return [side(xu, ru), side(xw, rw)];
            }
        }
        let p = &self.planes[k];
        [p.side(xu, ru), p.side(xw, rw)]
    }

    /// Makes the vertex where edge `u` (inside) – `w` (outside) crosses
    /// plane `k`; false when its error cannot be bounded.
    fn crossing(&mut self, u: usize, w: usize, k: usize, out: usize) -> bool {
        let common = self.on[u] & self.on[w];
        let on = common | 1 << k;
        self.on[out] = on;
        // Exact incidences: if every plane through the vertex passes through
        // one input point, the vertex is that point.
        // NOTE: an axis plane (a face of S) passes through no input point, so
        // a cut by one skips the loop.
        let through_k = self.planes[k].through;
        let pts = if through_k == 0 { 0 } else { bits(common).fold(through_k, |pts, i| pts & self.planes[i].through) };
        if pts != 0 {
            self.pos[out] = self.points[pts.trailing_zeros() as usize];
            self.rad[out] = DVec3::ZERO;
            self.is_point[out] = pts;
            return true;
        }
        // Both ends exact input points (an edge of the hull as built): the
        // edge is the segment between them, no need to find the line's
        // defining points through the planes.
        if self.is_point[u] != 0 && self.is_point[w] != 0 {
            if let Some((x, rad)) = line_crossing(self.pos[u], self.pos[w] - self.pos[u], true, &self.planes[k]) {
                self.store(out, x, rad);
                return true;
            }
        }
        if let Some((x, rad)) = self.structured_crossing(common, k) {
            self.store(out, x, rad);
            return true;
        }
        // A first estimate by interpolation along the edge (the side values
        // need not be certified for this).
        // NOTE: a polygon's edge lies on its edge plane and on every flat
        // plane; one flat plane with the edge plane defines the line (two
        // flat planes may be one plane, as the two faces of a flat box).
        let flat_common = common & self.flat;
        let common = if self.dim == 2 && common & !self.flat != 0 && flat_common != 0 {
            (common & !self.flat) | flat_common & flat_common.wrapping_neg()
        } else {
            common
        };
        let [(su, _), (sw, _)] = self.edge_sides(u, w, k);
        let (a, b) = ((-su).max(0.0), sw.max(0.0));
        let t = if a + b > 0.0 { a / (a + b) } else { 0.5 };
        let (from, to, t) = if t <= 0.5 { (u, w, t) } else { (w, u, 1.0 - t) };
        let guess = self.pos[from] + (self.pos[to] - self.pos[from]) * t;
        // The edge lies on two planes of `common`; with `k` they define the
        // vertex.
        let mut edge = bits(common);
        let (Some(i), Some(j)) = (edge.next(), edge.next()) else { return false };
        let mut planes = [&self.planes[i], &self.planes[j], &self.planes[k]];
        let proxy;
        for (x, y) in [(0, 1), (0, 2), (1, 2)] {
            let mut shared = bits((planes[x].through & planes[y].through) as u64);
            if let (Some(a), Some(c)) = (shared.next(), shared.next()) {
                let (a, c) = (self.points[a], self.points[c]);
                if a != c {
                    proxy = line_proxy(planes[x], a, c);
                    planes[y] = &proxy;
                    break;
                }
            }
        }
        let Some((x, rad)) = Self::certify_vertex(guess, planes) else { return false };
        self.place(out, on, x, rad)
    }

    /// Stores vertex `out` (on the planes `on`), making the coordinates that
    /// axis planes through it fix exact.
    fn place(&mut self, out: usize, on: u64, mut x: DVec3, mut rad: DVec3) -> bool {
        for i in bits(on & self.axis_planes) {
            let p = &self.planes[i];
            *coord_mut(&mut x, p.axis as usize) = p.value;
            *coord_mut(&mut rad, p.axis as usize) = 0.0;
        }
        self.store(out, x, rad);
        rad.is_finite() && x.is_finite()
    }

    /// Stores vertex `out` as found by a structured crossing: finite, and
    /// exact on the axes of the axis planes through it already.
    ///
    /// NOTE: a line crossing sets the cut plane's coordinate, a crossing on
    /// a plane both axis planes' coordinates, and a line of input points
    /// lies on an axis plane only where both points have its coordinate (an
    /// exactly zero step along that axis): no coordinate is left to fix.
    fn store(&mut self, out: usize, x: DVec3, rad: DVec3) {
        self.pos[out] = x;
        self.rad[out] = rad;
        self.is_point[out] = 0;
    }

    /// Where an edge on the planes `common` crosses plane `k`, with an a
    /// priori error bound, when the edge lies on a line the inputs define:
    /// - `k` and two more axis planes: the vertex is exact;
    /// - `k` and one more axis plane, and a general plane: one coordinate
    ///   from the plane;
    /// - two planes sharing two input points `a`, `b` (or one input point and
    ///   the light's direction): the line `a + t·(b − a)` meets plane `k`.
    ///
    /// `None` when no such description applies.
    fn structured_crossing(&self, common: u64, k: usize) -> Option<(DVec3, DVec3)> {
        let kp = &self.planes[k];
        let axis = kp.axis as usize;
        if kp.axis < 3 {
            let mut first_axis = None;
            for i in bits(common & self.axis_planes) {
                let p = &self.planes[i];
                if p.axis as usize != axis {
                    match first_axis {
                        None => first_axis = Some(i),
                        Some(f) if self.planes[f].axis != p.axis => {
                            // Three axis planes: an exact point.
                            let mut x = DVec3::ZERO;
                            for q in [kp, &self.planes[f], p] {
                                *coord_mut(&mut x, q.axis as usize) = q.value;
                            }
                            return Some((x, DVec3::ZERO));
                        }
                        Some(_) => {}
                    }
                }
            }
            let general = common & !self.axis_planes;
            if let (Some(f), true) = (first_axis, general != 0) {
                return self.crossing_on_plane(general.trailing_zeros() as usize, [k, f]);
            }
        }
        // An input line: two planes of `common` sharing two input points, or
        // one point and the light's direction.
        for i in bits(common) {
            for j in bits(common & (u64::MAX << i << 1)) {
                let mut shared = bits((self.planes[i].through & self.planes[j].through) as u64);
                let Some(a) = shared.next() else { continue };
                let a_point = self.points[a];
                let (d, rounded) = match (shared.next(), self.planes[i].src, self.planes[j].src) {
                    (Some(b), ..) => (self.points[b] - a_point, true),
                    (None, Plane::PointsDirection { direction: u, .. }, Plane::PointsDirection { direction: v, .. }) if u == v => {
                        (u, false)
                    }
                    (None, ..) => continue,
                };
                return line_crossing(a_point, d, rounded, kp);
            }
        }
        None
    }

    /// The point on general plane `g` whose coordinates on the axes of the
    /// two axis planes `fixed` are their values.
    fn crossing_on_plane(&self, g: usize, fixed: [usize; 2]) -> Option<(DVec3, DVec3)> {
        let p = &self.planes[g];
        let [k1, k2] = fixed.map(|f| (self.planes[f].axis as usize).min(2));
        let j = (3 - k1 - k2).min(2);
        let (n, en, anchor) = (p.n.to_array(), p.en.to_array(), p.anchor.to_array());
        let mut x = [0.0; 3];
        x[k1] = self.planes[fixed[0]].value;
        x[k2] = self.planes[fixed[1]].value;
        // NOTE: n_j (x_j − a_j) = −q with q = Σ_{m≠j} n_m (x_m − a_m) + offset.
        // q's error: the normal's (en·|w|) and 5u of its terms' absolute sum;
        // dividing by ñ_j (within en_j) adds |q/n_j|·en_j over |ñ_j| − en_j.
        let (w1, w2) = (x[k1] - anchor[k1], x[k2] - anchor[k2]);
        let q = n[k1] * w1 + n[k2] * w2 + p.offset;
        let eq = en[k1] * w1.abs() + en[k2] * w2.abs() + 5.0 * U * ((n[k1] * w1).abs() + (n[k2] * w2).abs() + p.offset.abs());
        let (nj, enj) = (n[j].abs(), en[j]);
        if !(nj > 2.0 * enj) {
            return None;
        }
        let step = q / n[j];
        x[j] = anchor[j] - step;
        let mut rad = [0.0; 3];
        if q == 0.0 && eq == 0.0 {
            // q is exactly zero: the point is the anchor's coordinate, exact.
            return Some((DVec3::from_array(x), DVec3::ZERO));
        }
        rad[j] = ((eq + step.abs() * enj) / (nj - enj) + 2.0 * U * step.abs() + U * x[j].abs()) * SLACK + 1e-300;
        (x[j].is_finite() && rad[j].is_finite()).then(|| (DVec3::from_array(x), DVec3::from_array(rad)))
    }

    /// Improves an estimate of the point where three planes meet and proves
    /// a per-coordinate bound on its distance from the exact point.
    ///
    /// Derivation: write the planes as `N x = c` (exact `N`, `c`). For the
    /// estimate `x̃`, the exact residual `ρ = N x̃ − c` is the vector of its
    /// side values, each known within `e` (the side bound at an exactly
    /// known point). Then `x̃ − x* = N⁻¹ ρ`. With `M` any approximate inverse
    /// (here: of the rounded normals) and `R = I − M N`, `‖R‖ < 1` gives
    /// `N⁻¹ = (I − R)⁻¹ M`, hence
    /// `|x̃ − x*| ≤ y + ‖R‖/(1 − ‖R‖)·‖y‖∞` with `y = |M| (|ρ̃| + e)`, and
    /// `|R| ≤ |I − M Ñ| + |M| |E|` (E: the normals' error) plus rounding.
    /// The bound follows the actual residual, so errors do not accumulate
    /// from one clip to the next. One Newton step `x̃ − M ρ̃` first brings
    /// the estimate within rounding of the exact point.
    fn certify_vertex(guess: DVec3, planes: [&FloatPlane; 3]) -> Option<(DVec3, DVec3)> {
        let [p0, p1, p2] = planes;
        let n = DMat3::from_cols(p0.n, p1.n, p2.n).transpose();
        let det = n.determinant();
        if !(det.abs() > 0.0 && det.is_finite()) {
            return None;
        }
        let m = n.inverse();
        let residual = |x: DVec3| {
            let ((a, ea), (b, eb), (c, ec)) = (p0.side(x, DVec3::ZERO), p1.side(x, DVec3::ZERO), p2.side(x, DVec3::ZERO));
            (DVec3::new(a, b, c), DVec3::new(ea, eb, ec))
        };
        let (rho, _) = residual(guess);
        let x = guess - m * rho;
        let (rho, e) = residual(x);
        let abs = |a: DMat3| DMat3::from_cols(a.x_axis.abs(), a.y_axis.abs(), a.z_axis.abs());
        let (am, an) = (abs(m), abs(n));
        let en = DMat3::from_cols(p0.en, p1.en, p2.en).transpose();
        let r = abs(DMat3::IDENTITY - m * n) * (1.0 + 4.0 * U) + am * an * (4.0 * U) + am * en;
        let r_norm = (r.x_axis + r.y_axis + r.z_axis).max_element() * SLACK;
        if !(r_norm < 0.5) {
            return None;
        }
        let y = am * (rho.abs() + e) * SLACK;
        let rad = (y + DVec3::splat(y.max_element() * r_norm / (1.0 - r_norm))) * SLACK;
        (x.is_finite() && rad.is_finite()).then_some((x, rad))
    }

    /// Cuts by plane `k`: `inside` and `outside` are the vertices strictly
    /// on either side (both nonempty), the others lie on `k`.
    ///
    /// NOTE: the body keeps no face cycles while clipping. Two vertices span
    /// an edge exactly when they lie on two common planes: two distinct
    /// supporting planes meet the body in a face of dimension ≤ 1, and two
    /// vertices in it are its endpoints (planes that merely repeat a face
    /// are not recorded, see `clip`). So the cut edges are the pairs of an
    /// inside and an outside vertex sharing two planes, and faces are
    /// assembled once, in `write`.
    fn cut(&mut self, k: usize, inside: VertexSet, outside: VertexSet) -> bool {
        let old_n = self.n_verts;
        let bit = 1u64 << k;
        let mut on_k = 0;
        // NOTE: 2 ≤ old_n ≤ 64 (a vertex on each side), so the shift is in range.
        for v in bits(u64::MAX >> (64 - old_n) & !(inside | outside)) {
            self.on[v] |= bit;
            on_k += 1;
        }
        let mut n_new = old_n;
        // An outside vertex's inside neighbours: those sharing two of its
        // planes (one, in a polygon, whose flat planes are left out).
        // NOTE: tested pair by pair: a body has few vertices, and per-plane
        // vertex sets cost a loop over every inside vertex's planes.
        for w in bits(outside) {
            let on_w = self.on[w] & !self.flat;
            let mut near = match self.dim {
                3 => {
                    let mut near = 0;
                    for u in bits(inside) {
                        near |= (two_or_more(self.on[u] & on_w) as u64) << u;
                    }
                    near
                }
                2 => {
                    let mut near = 0;
                    for u in bits(inside) {
                        near |= ((self.on[u] & on_w != 0) as u64) << u;
                    }
                    near
                }
                // A segment's other end.
                _ => inside,
            };
            while near != 0 {
                let u = near.trailing_zeros() as usize;
                near &= near - 1;
                if n_new >= CAP_V || !self.crossing(u, w, k, n_new) {
                    return false;
                }
                n_new += 1;
            }
        }
        // The cap of a solid is a polygon: at least three vertices on k; a
        // polygon's is a chord (two), a segment's a point.
        let cap = on_k + n_new - old_n;
        let dim = self.dim as usize;
        if cap < dim || (dim < 3 && cap != dim) {
            return false;
        }
        // Drop the vertices outside: each outside slot, lowest first, takes
        // the last vertex kept.
        // NOTE: filling holes from the end moves one vertex per hole, where
        // shifting everything down moved every vertex after the first hole.
        let kept = |v: usize| v >= old_n || outside & 1 << v == 0;
        let mut n = n_new;
        for w in bits(outside) {
            while n > w && !kept(n - 1) {
                n -= 1;
            }
            if n <= w {
                break;
            }
            n -= 1;
            self.move_vertex(n, w);
        }
        self.n_verts = n;
        true
    }

    /// The certified sign of `det[n_a, n_b, n_c]` for three planes' exact
    /// normals.
    fn normals_det_sign(a: &FloatPlane, b: &FloatPlane, c: &FloatPlane) -> Option<i8> {
        // NOTE: the exact normals lie within `en` of the rounded ones, so the
        // exact determinant differs from the rounded normals' by at most
        // perm(|ñ| + en) − perm(|ñ|) (multilinearity); each permanent and the
        // determinant itself carry under 6u of perm(|ñ| + en) in rounding.
        let perm = |x: DVec3, y: DVec3, z: DVec3| x.dot(abs_cross(y, z));
        let det = a.n.dot(b.n.cross(c.n));
        let nominal = perm(a.n.abs(), b.n.abs(), c.n.abs());
        let widened = perm(a.n.abs() + a.en, b.n.abs() + b.en, c.n.abs() + c.en);
        let bound = ((widened - nominal) + 20.0 * U * widened) * SLACK;
        decide(det, bound).filter(|&s| s != 0)
    }

    /// Writes the body into `out`; false (and `out` left empty) when a
    /// vertex is neither within the output tolerance nor placed exactly, the
    /// faces do not chain into a closed surface, or a face's orientation is
    /// not proven.
    pub(crate) fn write(&mut self, out: &mut Body) -> bool {
        if self.dim < 3 {
            return self.write_flat(out);
        }
        // Each plane's vertices as a vertex set; planes with three or more
        // carry a face.
        // NOTE: the sizes are counted here rather than taken by `count_ones`
        // (no `popcnt` in the baseline instruction set: a dozen instructions
        // per plane, ~1 % of a body).
        let np = self.n_planes;
        let members = &mut self.plane_members[..np];
        members.fill(0);
        let mut count = [0u8; MAX_FAST_PLANES];
        for v in 0..self.n_verts {
            for p in bits(self.on[v]) {
                members[p] |= 1 << v;
                count[p] += 1;
            }
        }
        // NOTE: two vertices of a solid span an edge exactly when they share
        // two planes (see `cut`); found once per vertex here, each face's
        // chaining is then one set operation per step.
        for v in 0..self.n_verts {
            let (mut once, mut twice): (VertexSet, VertexSet) = (0, 0);
            for p in bits(self.on[v]) {
                twice |= once & self.plane_members[p];
                once |= self.plane_members[p];
            }
            self.neighbours[v] = twice & !(1 << v);
        }
        out.clear();
        let (mut ni, mut nf) = (0, 0);
        self.directed[..self.n_verts].fill(0);
        for p in 0..np {
            let m = count[p] as usize;
            if m < 3 {
                continue;
            }
            if ni + m > MAX_FACE_INDICES {
                return false;
            }
            if m == 3 {
                // NOTE: three vertices of a face are a triangle in either
                // order; the orientation is decided below like any face's, and
                // Euler's formula still checks the whole surface.
                let mut on_p = bits(self.plane_members[p]);
                for slot in &mut out.idx[ni..ni + 3] {
                    *slot = on_p.next().unwrap_or(0) as u16;
                }
            } else if self.face_cycle(self.plane_members[p], m, &mut out.idx[ni..ni + m]).is_none() {
                return false;
            }
            let cycle = &out.idx[ni..ni + m];
            let neighbour = self.reversed_by_neighbour(cycle);
            let Some(reverse) = neighbour.or_else(|| self.reversed_by_geometry(p, !(1 << p), cycle)) else { return false };
            if reverse {
                out.idx[ni + 1..ni + m].reverse();
            }
            out.face_start[nf] = ni as u16;
            ni += m;
            out.face_start[nf + 1] = ni as u16;
            out.face_planes[nf] = self.planes[p].approximate();
            if !self.record_edges(&out.idx[ni - m..ni]) {
                return false;
            }
            nf += 1;
        }
        // Euler's formula for a closed convex surface: every edge is in two
        // faces, V − E + F = 2.
        if ni % 2 != 0 || self.n_verts + nf != ni / 2 + 2 {
            out.clear();
            return false;
        }
        for v in 0..self.n_verts {
            let Some(x) = self.output_vertex(v) else {
                out.clear();
                return false;
            };
            out.verts[v] = x;
        }
        out.dim = 3;
        out.n_verts = self.n_verts;
        out.face_start[nf] = ni as u16;
        out.n_faces = nf;
        true
    }

    /// Vertex `v` as written: its rounded position when the proven error is
    /// within the output tolerance, else placed exactly (see
    /// `exact_vertex`); `None` when it is not finite or cannot be placed.
    ///
    /// NOTE: checked as the vertex is written, after the faces: chaining and
    /// orienting them read positions only through their proven radii.
    #[inline]
    fn output_vertex(&mut self, v: usize) -> Option<DVec3> {
        let (x, r) = (self.pos[v], self.rad[v]);
        let allowed = x.abs().max(DVec3::splat(self.magnitude)) * (ROUNDING_ULPS * f64::EPSILON);
        // Adding +0 turns −0 into +0.
        if x.is_finite() && r.cmple(allowed).all() {
            return Some(x + DVec3::ZERO);
        }
        if !x.is_finite() {
            return None;
        }
        let exact = self.exact_vertex(v)?;
        self.exact_vertices += 1;
        Some(exact + DVec3::ZERO)
    }

    /// Vertex `v` from the exact intersection of three of its planes, each
    /// coordinate within 3u relative (correctly rounded where big integers
    /// answer); `None` when no three of them meet in a point.
    ///
    /// NOTE: for a vertex whose proven error exceeds the output tolerance
    /// (planes meeting at small angles make the float estimate's bound
    /// loose, typically by a factor of 1.1–3). Every plane recorded on a
    /// vertex passes through it exactly, so any three independent ones give
    /// it; the signs that placed it were proven already, so only its
    /// coordinates need exact arithmetic, not the whole body. That is done
    /// in fixed-width integers on the stack ([`crate::fixed`]) when the
    /// planes' values fit, else with big integers (which allocate).
    #[cold]
    fn exact_vertex(&self, v: usize) -> Option<DVec3> {
        let mut on = [0usize; MAX_FAST_PLANES];
        let mut n = 0;
        for p in bits(self.on[v]) {
            on[n] = p;
            n += 1;
        }
        let src = |i: usize| &self.planes[on[i]].src;
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let x = match meet([src(i), src(j), src(k)]) {
                        Meeting::Point(x) => x,
                        Meeting::Dependent => continue,
                        Meeting::Unfit => {
                            let h = intersect3(
                                &src(i).coefficients::<Exact>(),
                                &src(j).coefficients::<Exact>(),
                                &src(k).coefficients::<Exact>(),
                            );
                            if h[3].sign() == 0 {
                                continue;
                            }
                            DVec3::from_array(std::array::from_fn(|c| Exact::ratio_to_f64(&h[c], &h[3]) + 0.0))
                        }
                    };
                    return x.is_finite().then_some(x);
                }
            }
        }
        None
    }

    /// Writes a flat body: a point, a segment, or a polygon whose cycle runs
    /// counter-clockwise seen from the side its face plane's normal (the
    /// outward normal of the plane that left it) points to. False when a
    /// vertex cannot be written (see `output_vertex`), the cycle does not
    /// close or its orientation is not proven.
    fn write_flat(&mut self, out: &mut Body) -> bool {
        out.clear();
        let n = self.n_verts;
        if self.dim == 2 {
            if !(3..=MAX_FACE_INDICES).contains(&n) {
                return false;
            }
            // Adjacent vertices share a plane besides the flat ones.
            let edges = !self.flat;
            let members = &mut self.plane_members[..self.n_planes];
            members.fill(0);
            for v in 0..n {
                for p in bits(self.on[v] & edges) {
                    members[p] |= 1 << v;
                }
            }
            for v in 0..n {
                let near = bits(self.on[v] & edges).fold(0, |near, p| near | self.plane_members[p]);
                self.neighbours[v] = near & !(1 << v);
            }
            let all: VertexSet = u64::MAX >> (64 - n);
            if self.face_cycle(all, n, &mut out.idx[..n]).is_none() {
                return false;
            }
            let Some(reverse) = self.reversed_by_geometry(self.support, edges, &out.idx[..n]) else { return false };
            if reverse {
                out.idx[1..n].reverse();
            }
            // The vertices in cycle order, as the exact engine lists them.
            for i in 0..n {
                let Some(x) = self.output_vertex(out.idx[i] as usize) else {
                    out.clear();
                    return false;
                };
                out.verts[i] = x;
                out.idx[i] = i as u16;
            }
            out.face_start[0] = 0;
            out.face_start[1] = n as u16;
            out.face_planes[0] = self.planes[self.support].approximate();
            out.n_faces = 1;
        } else {
            for v in 0..n {
                let Some(x) = self.output_vertex(v) else {
                    out.clear();
                    return false;
                };
                out.verts[v] = x;
            }
        }
        out.n_verts = n;
        out.dim = self.dim;
        true
    }

    /// Whether the convex polygon `cycle` of plane `p` runs counter-clockwise
    /// seen from outside, from its area vector `A` (a fan from its first
    /// vertex): `A` must point away from the body's vertices off the plane.
    /// `None` when the bounds cannot prove it.
    fn area_orientation(&self, p: usize, cycle: &[u16]) -> Option<bool> {
        // NOTE: fan terms of a convex polygon all point one way, so `A` has no
        // cancellation. A difference d = x_k − x_0 is off by the two radii and
        // its rounding; a cross product of perturbed vectors by
        // |δa|×|b| + |a|×|δb| + |δa|×|δb|, its own rounding by 2u of |a|×|b|,
        // and the running sum by (terms)·u of the same. The plane's own normal
        // is not used: it may be known less well than the polygon.
        let (x0, r0) = (self.pos[cycle[0] as usize], self.rad[cycle[0] as usize]);
        let edge = |v: usize| {
            let d = self.pos[v] - x0;
            (d, self.rad[v] + r0 + d.abs() * U)
        };
        let rounding = (cycle.len() as f64 + 2.0) * U;
        let (mut area, mut err) = (DVec3::ZERO, DVec3::ZERO);
        let (mut a, mut ea) = edge(cycle[1] as usize);
        for &v in &cycle[2..] {
            let (b, eb) = edge(v as usize);
            area += a.cross(b);
            err += abs_cross(ea, b) + abs_cross(a, eb) + abs_cross(ea, eb) + abs_cross(a, b) * rounding;
            (a, ea) = (b, eb);
        }
        // Against the vertices off the plane, until one proves the side (a
        // vertex may lie very close to the plane without being on it).
        (0..self.n_verts).filter(|&v| self.on[v] & 1 << p == 0).find_map(|y| {
            let (d, ed) = edge(y);
            let value = area.dot(d);
            let bound = (err.dot(d.abs() + ed) + area.abs().dot(ed) + 3.0 * U * area.abs().dot(d.abs())) * SLACK + FLOOR;
            decide(value, bound).filter(|&s| s != 0).map(|s| s < 0)
        })
    }

    /// Writes the `m` vertices of `face` (a vertex set) into `cycle`,
    /// chained through its edges in either direction; `None` when the chain
    /// does not close. Needs `neighbours`: within a solid's face, a vertex's
    /// neighbours are its two ends of the face's edges; in a polygon, the
    /// vertices sharing an edge plane with it.
    fn face_cycle(&self, face: VertexSet, m: usize, cycle: &mut [u16]) -> Option<()> {
        // NOTE: each edge of a face lies on a different other plane, so a
        // face has fewer vertices than there are planes; more means the
        // incidences are broken.
        if m >= MAX_FAST_PLANES {
            return None;
        }
        let first = face.trailing_zeros() as usize;
        if m == 4 {
            // A quadrilateral: the first vertex's two neighbours, and the
            // vertex opposite, which must neighbour both.
            let near = self.neighbours[first] & face;
            let (a, rest) = (near.trailing_zeros() as usize, near & near.wrapping_sub(1));
            let opposite = face & !near & !(1 << first);
            if !two_or_more(near) || two_or_more(rest) || self.neighbours[opposite.trailing_zeros() as usize & (CAP_V - 1)] & face != near {
                return None;
            }
            cycle[..4].copy_from_slice(&[first, a, opposite.trailing_zeros() as usize, rest.trailing_zeros() as usize].map(|v| v as u16));
            return Some(());
        }
        // Each step takes the lowest neighbour in the face that is not the
        // vertex it came from.
        let (mut prev, mut cur) = (first, first);
        let mut placed: VertexSet = 1 << first;
        cycle[0] = first as u16;
        for slot in cycle.iter_mut().take(m).skip(1) {
            let near = self.neighbours[cur] & face & !(1 << prev);
            if near == 0 {
                return None;
            }
            let next = near.trailing_zeros() as usize;
            if placed & 1 << next != 0 {
                return None;
            }
            placed |= 1 << next;
            *slot = next as u16;
            (prev, cur) = (cur, next);
        }
        if self.neighbours[cur] & 1 << first == 0 {
            return None;
        }
        Some(())
    }

    /// Whether a face's chained cycle must be reversed, read off a face
    /// already written across one of its edges: consistently oriented faces
    /// run along a shared edge in opposite directions. `None` when no
    /// written face shares an edge.
    fn reversed_by_neighbour(&self, cycle: &[u16]) -> Option<bool> {
        let slot = |v: u16| v as usize & (CAP_V - 1);
        let mut a = slot(cycle[cycle.len() - 1]);
        for &b in cycle {
            let b = slot(b);
            if self.directed[a] & 1 << b != 0 {
                return Some(true);
            }
            if self.directed[b] & 1 << a != 0 {
                return Some(false);
            }
            a = b;
        }
        None
    }

    /// Records a written face's directed edges; false when a face written
    /// before runs along one of them the same way (the faces are then not
    /// consistently oriented: broken incidences).
    fn record_edges(&mut self, cycle: &[u16]) -> bool {
        let slot = |v: u16| v as usize & (CAP_V - 1);
        let mut a = slot(cycle[cycle.len() - 1]);
        let mut repeated = 0;
        for &b in cycle {
            let b = slot(b);
            repeated |= self.directed[a] & 1 << b;
            self.directed[a] |= 1 << b;
            a = b;
        }
        repeated == 0
    }

    /// Whether the chained cycle of plane `p`'s face must be reversed to run
    /// counter-clockwise from outside, proven from the planes' normals or the
    /// face's area vector.
    /// `others`: the planes that can hold an edge (all but `p` for a solid's
    /// face, all but the flat planes for a polygon).
    fn reversed_by_geometry(&self, p: usize, others: u64, cycle: &[u16]) -> Option<bool> {
        let m = cycle.len();
        // NOTE: at a vertex v with neighbours a (next) and b (previous), the
        // edge v → a runs along planes p and i, into the inner side of j (the
        // plane of edge v → b), and likewise with i and j swapped. Writing
        // both directions as ±(n_p × n_i), ±(n_p × n_j) with those signs,
        // (t_a × t_b) · n_p = −det[n_p, n_i, n_j]·|n_p|²: the cycle runs
        // counter-clockwise from outside exactly when the determinant is
        // negative. It is near zero where i nearly repeats p (the two
        // triangles of a creased frustum side), so the first vertex whose
        // determinant's sign is proven decides.
        // Where every such determinant is too close to zero (nearly dependent
        // planes, or a plane whose normal is barely known: three nearly
        // collinear defining points) the polygon's area vector decides.
        let decided = (0..m)
            .find_map(|s| {
                let (next, prev) = (if s + 1 == m { 0 } else { s + 1 }, if s == 0 { m - 1 } else { s - 1 });
                let (v, a, b) = (cycle[s] as usize, cycle[next] as usize, cycle[prev] as usize);
                let (to_a, to_b) = (self.on[v] & self.on[a] & others, self.on[v] & self.on[b] & others);
                bits(to_a).find_map(|i| bits(to_b).find_map(|j| Self::normals_det_sign(&self.planes[p], &self.planes[i], &self.planes[j])))
            })
            .or_else(|| self.area_orientation(p, &cycle[..m]).map(|ccw| if ccw { -1 } else { 1 }))?;
        Some(decided > 0)
    }
}
