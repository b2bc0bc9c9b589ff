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
//! ([`crate::engine::exact::Polytope`]) instead. So the fast path never decides
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

mod clip;
mod hull;
mod planes;
mod write;

#[cfg(test)]
mod tests;

use crate::arith::plane::Plane;
use crate::limits::MAX_VERTICES;
use glam::DVec3;
use planes::FloatPlane;

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
    planes: PlaneStore,
    /// The input points (see `N_POINTS`): view corners, the light, light frustum corners.
    points: [DVec3; N_POINTS],
    verts: VertexStore,
    magnitude: f64,
    scratch: WriteScratch,
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

/// The planes of the hull and the clips, with what is cached per plane pair.
#[derive(Clone)]
struct PlaneStore {
    items: [FloatPlane; MAX_FAST_PLANES],
    /// Per plane: the earlier planes sharing a line of input points with it.
    partners: [u64; MAX_FAST_PLANES],
    len: usize,
    /// Planes that are axis planes (faces of S, a closing plane).
    axis: u64,
    /// Plane pairs `(i, k)` whose fold proxy is in `fold_proxies` (same
    /// slot), failures included (`None`).
    ///
    /// NOTE: the keys live apart from the proxies so that a new body resets
    /// 16 bytes, not eight ~250-byte proxies.
    fold_keys: [(u8, u8); FOLD_CACHE],
    fold_proxies: [Option<Fold>; FOLD_CACHE],
}

/// The body's vertices: rounded positions, their rounding radii, and the
/// exact incidences the clips decided.
#[derive(Clone)]
struct VertexStore {
    pos: [DVec3; CAP_V],
    rad: [DVec3; CAP_V],
    /// Planes each vertex lies on exactly.
    on: [u64; CAP_V],
    /// Input points each vertex is exactly equal to.
    is_point: [u32; CAP_V],
    /// Each vertex's side of the plane being clipped with.
    sign: [i8; CAP_V],
    len: usize,
}

/// `write`'s scratch: the incidence graph it orders faces with.
#[derive(Clone)]
struct WriteScratch {
    /// Per plane, the vertices on it (a vertex set).
    plane_members: [VertexSet; MAX_FAST_PLANES],
    /// Per vertex, the vertices it shares an edge with.
    neighbours: [VertexSet; CAP_V],
    /// Per vertex `a`, the vertices `b` such that a face written so far runs
    /// along the edge from `a` to `b`.
    directed: [VertexSet; CAP_V],
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
            planes: PlaneStore {
                items: [DUMMY_PLANE; MAX_FAST_PLANES],
                partners: [0; MAX_FAST_PLANES],
                len: 0,
                axis: 0,
                fold_keys: [(NONE, NONE); FOLD_CACHE],
                fold_proxies: [None; FOLD_CACHE],
            },
            points: [DVec3::ZERO; N_POINTS],
            verts: VertexStore {
                pos: [DVec3::ZERO; CAP_V],
                rad: [DVec3::ZERO; CAP_V],
                on: [0; CAP_V],
                is_point: [0; CAP_V],
                sign: [0; CAP_V],
                len: 0,
            },
            magnitude: 0.0,
            scratch: WriteScratch { plane_members: [0; MAX_FAST_PLANES], neighbours: [0; CAP_V], directed: [0; CAP_V] },
            cuts: 0,
            cleared: 0,
            closed_by_scene_face: None,
            dim: 3,
            flat: 0,
            support: 0,
            exact_vertices: 0,
        }
    }
}
