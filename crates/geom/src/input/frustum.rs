//! Frusta as exact convex hulls of their eight corners, and their hull with
//! a light (a finite point, or a point at infinity for directional lights).

use crate::arith::plane::Plane;
use crate::error::{check_finite, GeomError};
use crate::input::camera::{Camera, CameraBasis};
use crate::predicates::orient::{
    in_safe_range, orient, orient_checked, orient_direction_past_static_filter, orient_past_static_filter, FaceFilter,
};
use glam::DVec3;

/// Faces of the canonical corner order (near −r−u, +r−u, +r+u, −r+u, then
/// far likewise), counter-clockwise seen from outside for a right-handed
/// frame (right = forward × up).
const QUADS: [[u8; 4]; 6] = [
    [0, 1, 2, 3], // near
    [4, 7, 6, 5], // far
    [0, 4, 5, 1], // bottom (−up)
    [3, 2, 6, 7], // top (+up)
    [0, 3, 7, 4], // left (−right)
    [1, 5, 6, 2], // right (+right)
];

/// Most faces of a frustum hull: six quads, each possibly creased in two.
pub(crate) const MAX_FRUSTUM_FACES: usize = 12;

/// A validated frustum: eight corners whose convex hull is a solid with the
/// frustum's face structure. Faces whose four corners are not exactly
/// coplanar (the usual case after rounding) are split along the diagonal
/// that keeps the hull convex, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
// NOTE: serialized as its eight corners and rebuilt with `from_corners`
// on the way in, so a deserialized frustum is checked like any other.
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "[DVec3; 8]", into = "[DVec3; 8]"))]
pub struct Frustum {
    corners: [DVec3; 8],
    /// Face polygons as corner indices, CCW from outside; `faces_len[i]` is 3 or 4.
    faces: [[u8; 4]; MAX_FRUSTUM_FACES],
    faces_len: [u8; MAX_FRUSTUM_FACES],
    n_faces: u8,
    /// Some corner lies in the plane of a face it does not belong to (a
    /// face and a neighbouring triangle coplanar): the face list is then not
    /// the hull's face structure — the hull merges those faces, and a corner
    /// may lie inside a face — although every face is a valid halfspace.
    coplanar_faces: bool,
    /// Every corner is in the safe range of the static filters.
    in_range: bool,
    /// The face holding each directed edge `a → b` (`u8::MAX`: none).
    edge_face: [[u8; 8]; 8],
    /// Per face, `(q − p) × (r − p)` over its first three corners and the
    /// same with absolute values: the static filter's data, computed once
    /// here and reused by every later test against the face (the light's
    /// side in [`Frustum::hull_with`], the float path's face planes).
    normals: [DVec3; MAX_FRUSTUM_FACES],
    abs_normals: [DVec3; MAX_FRUSTUM_FACES],
}

/// A light as a homogeneous point: finite, or at infinity in a direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Apex {
    /// A finite point.
    Finite(DVec3),
    /// The point at infinity reached by travelling along this direction.
    Infinite(DVec3),
}

impl Apex {
    /// The position, or the direction of a point at infinity.
    fn coordinates(self) -> DVec3 {
        match self {
            Apex::Finite(v) | Apex::Infinite(v) => v,
        }
    }

    /// The apex's bit in [`HullOutline::through`]: a point at infinity is
    /// no input point, so planes through it record none.
    pub(crate) fn through_bit(self) -> u32 {
        match self {
            Apex::Finite(_) => APEX_BIT,
            Apex::Infinite(_) => 0,
        }
    }
}

/// Bit of the hull apex in [`HullOutline::through`] (bits 0–7 are corners).
pub(crate) const APEX_BIT: u32 = 1 << 8;

/// Where a plane of a frustum hull comes from (see [`HullOutline`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Origin {
    /// Face `i` of the frustum.
    Face(u8),
    /// The horizon edge `a → b` (as oriented in a face that sees the apex)
    /// joined to the apex.
    Horizon(u8, u8),
}

/// A fixed-capacity list of halfspaces.
#[derive(Clone, Copy, Debug)]
pub struct PlaneSet {
    planes: [Plane; 2 * MAX_FRUSTUM_FACES],
    len: usize,
}

impl PlaneSet {
    pub(crate) fn new() -> Self {
        PlaneSet { planes: [Plane::Axis { axis: 0, upper: true, value: 0.0 }; 2 * MAX_FRUSTUM_FACES], len: 0 }
    }
    fn clear(&mut self) {
        self.len = 0;
    }
    fn push(&mut self, p: Plane) {
        // Capacity: kept faces + horizon edges ≤ 12 + 12 for a frustum hull.
        self.planes[self.len] = p;
        self.len += 1;
    }
    /// The planes, in insertion order.
    pub fn as_slice(&self) -> &[Plane] {
        &self.planes[..self.len]
    }
}

/// The hull's planes by origin, in [`PlaneSet`] order, without the planes
/// themselves: what the float path builds its own planes from, and what
/// [`Frustum::hull_planes_into`] turns into a [`PlaneSet`] when the exact
/// engine needs one.
///
/// NOTE: most frames never need the `Plane` values (the float path answers),
/// so they are not written until then.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HullOutline {
    origin: [Origin; 2 * MAX_FRUSTUM_FACES],
    /// Per plane, the frustum corners (bits 0–7) and the finite hull apex
    /// ([`APEX_BIT`]) it passes through by construction: exact incidences
    /// known without arithmetic.
    through: [u32; 2 * MAX_FRUSTUM_FACES],
    len: usize,
    /// Faces the apex lies strictly beyond, and faces whose plane holds it
    /// (the hull's faces are then not all distinct planes of the frustum's).
    pub(crate) sees: u16,
    pub(crate) coplanar: u16,
}

impl HullOutline {
    pub(crate) fn new() -> HullOutline {
        HullOutline { origin: [Origin::Face(0); 2 * MAX_FRUSTUM_FACES], through: [0; 2 * MAX_FRUSTUM_FACES], len: 0, sees: 0, coplanar: 0 }
    }

    pub(crate) fn len(&self) -> usize {
        self.len
    }

    pub(crate) fn origins(&self) -> &[Origin] {
        &self.origin[..self.len]
    }

    pub(crate) fn through(&self) -> &[u32] {
        &self.through[..self.len]
    }

    fn push(&mut self, through: u32, origin: Origin) {
        // Capacity: kept faces + horizon edges ≤ 12 + 12 for a frustum hull.
        self.origin[self.len] = origin;
        self.through[self.len] = through;
        self.len += 1;
    }
}

/// Whether two corner masks (as in [`HullOutline::through`]) are the two
/// triangles of one creased quad.
///
/// Two proper parts of a quad that share two corners and together hold all
/// four have three corners each (3 + 3 = 4 + 2), and the only faces with
/// three corners of one quad are the triangles of its crease.
///
/// NOTE: a validated frustum creases a quad only where its exact fold test
/// is nonzero, which puts each triangle's third corner strictly inside the
/// other triangle's plane: a sign known without arithmetic.
#[inline]
pub(crate) fn creased_pair(a: u32, b: u32) -> bool {
    let (all, common) = (a | b, a & b);
    a != all && b != all && common & common.wrapping_sub(1) != 0 && QUAD_MASKS.contains(&all)
}

/// The corner masks of [`QUADS`].
const QUAD_MASKS: [u32; 6] = {
    let mut masks = [0; 6];
    let mut q = 0;
    while q < 6 {
        let mut k = 0;
        while k < 4 {
            masks[q] |= 1 << QUADS[q][k];
            k += 1;
        }
        q += 1;
    }
    masks
};

/// Per quad of [`QUADS`], the four corners not on it.
const QUAD_OTHERS: [[u8; 4]; 6] = {
    let mut others = [[0; 4]; 6];
    let mut q = 0;
    while q < 6 {
        let (mut c, mut n) = (0, 0);
        while c < 8 {
            if QUAD_MASKS[q] & 1 << c == 0 {
                others[q][n] = c as u8;
                n += 1;
            }
            c += 1;
        }
        q += 1;
    }
    others
};

pub(crate) fn corner_bits(idx: &[u8]) -> u32 {
    idx.iter().fold(0, |m, &i| m | 1 << i)
}

impl Frustum {
    /// Validates eight corners in the documented order (near then far,
    /// each −r−u, +r−u, +r+u, −r+u). Either handedness is accepted.
    pub fn from_corners(corners: [DVec3; 8]) -> Result<Frustum, GeomError> {
        Self::with_name(corners, "frustum")
    }

    /// The frustum of a camera (see [`Camera::corners`] for the formula).
    pub fn from_camera(camera: &Camera) -> Result<Frustum, GeomError> {
        Self::with_name(camera.corners()?, "camera frustum")
    }

    /// [`Frustum::from_camera`] with the camera's basis already computed
    /// (see [`Camera::corners_in`]): the same frustum, without recomputing
    /// the basis for every split of one view.
    pub fn from_camera_in(camera: &Camera, basis: &CameraBasis) -> Result<Frustum, GeomError> {
        Self::with_name(camera.corners_in(basis)?, "camera frustum")
    }

    pub(crate) fn with_name(corners: [DVec3; 8], what: &'static str) -> Result<Frustum, GeomError> {
        for c in &corners {
            check_finite(*c, "frustum corner")?;
        }
        // Every orientation below is among corners: test their range once.
        let in_range = corners.iter().all(|c| in_safe_range(*c));
        let orient = |p: DVec3, q: DVec3, r: DVec3, x: DVec3| orient_checked(p, q, r, x, in_range);
        // Handedness: the far corners must lie inside the near face.
        let [c0, c1, c2, _, c4, c5, c6, c7] = corners;
        let mut hand = 0;
        for far in [c4, c5, c6, c7] {
            hand = orient(c0, c1, c2, far);
            if hand != 0 {
                break;
            }
        }
        if hand == 0 {
            return Err(GeomError::DegenerateFrustum { what, reason: "all corners are coplanar" });
        }
        let mut f = Frustum {
            corners,
            faces: [[0; 4]; MAX_FRUSTUM_FACES],
            faces_len: [0; MAX_FRUSTUM_FACES],
            n_faces: 0,
            coplanar_faces: false,
            in_range,
            edge_face: [[u8::MAX; 8]; 8],
            normals: [DVec3::ZERO; MAX_FRUSTUM_FACES],
            abs_normals: [DVec3::ZERO; MAX_FRUSTUM_FACES],
        };
        // Per face: the corners off the quad it comes from.
        let mut off_quad = [[0u8; 4]; MAX_FRUSTUM_FACES];
        for (quad, others) in QUADS.iter().zip(QUAD_OTHERS) {
            // A left-handed corner order mirrors every face: reverse the cycles.
            let [a, b, c, d] = if hand < 0 { *quad } else { [quad[0], quad[3], quad[2], quad[1]] };
            let p = |i: u8| corners[i as usize];
            let first = f.n_faces as usize;
            // Fold along the diagonal that keeps the surface convex: if d is
            // on the inner side of plane(a, b, c) the edge a–c is convex.
            match orient(p(a), p(b), p(c), p(d)) {
                0 => f.push_face(&[a, b, c, d]),
                s if s < 0 => {
                    f.push_face(&[a, b, c]);
                    f.push_face(&[a, c, d]);
                }
                _ => {
                    f.push_face(&[a, b, d]);
                    f.push_face(&[b, c, d]);
                }
            }
            off_quad[first..f.n_faces as usize].fill(others);
        }
        // Convexity: every face plane has all corners on its closed inner
        // side and at least one strictly inside (no flat or twisted hull).
        // The fourth corner of a creased quad is on the inner side of both
        // triangles by the fold decision above, so it is not tested again.
        for i in 0..f.n_faces as usize {
            let face = f.face(i);
            let (a, b, c) = (corners[face[0] as usize], corners[face[1] as usize], corners[face[2] as usize]);
            let plane = FaceFilter::new(a, b, c);
            (f.normals[i], f.abs_normals[i]) = (plane.normal, plane.abs_normal);
            let mut strictly_inside = false;
            for k in off_quad[i] {
                let x = corners[k as usize];
                let filtered = if in_range { plane.side(x) } else { None };
                let s = filtered.unwrap_or_else(|| orient_past_static_filter(a, b, c, x, in_range));
                if s > 0 {
                    return Err(GeomError::DegenerateFrustum {
                        what,
                        reason: "corners are not in convex position (twisted or non-convex frustum)",
                    });
                }
                strictly_inside |= s < 0;
                f.coplanar_faces |= s == 0;
            }
            if !strictly_inside {
                return Err(GeomError::DegenerateFrustum { what, reason: "a face is degenerate (coincident or collinear corners)" });
            }
        }
        Ok(f)
    }

    fn push_face(&mut self, idx: &[u8]) {
        let i = self.n_faces as usize;
        let mut prev = idx[idx.len() - 1];
        for &a in idx {
            self.edge_face[prev as usize][a as usize] = i as u8;
            prev = a;
        }
        self.faces[i][..idx.len()].copy_from_slice(idx);
        self.faces_len[i] = idx.len() as u8;
        self.n_faces += 1;
    }

    /// Whether the faces are exactly the hull's faces: no corner lies in the
    /// plane of a face it is not part of.
    pub(crate) fn faces_are_hull_faces(&self) -> bool {
        !self.coplanar_faces
    }

    /// Face `i` as corner indices, counter-clockwise from outside.
    pub(crate) fn face(&self, i: usize) -> &[u8] {
        &self.faces[i][..self.faces_len[i] as usize]
    }

    /// The eight corners: near face, then far face.
    pub fn corners(&self) -> &[DVec3; 8] {
        &self.corners
    }

    /// Number of faces of the exact hull (6 when every side is planar, up to 12).
    pub fn face_count(&self) -> usize {
        self.n_faces as usize
    }

    /// Face `i`'s static filter (valid for tests when `in_range`).
    fn face_filter(&self, i: usize) -> FaceFilter {
        FaceFilter { p: self.corners[self.faces[i][0] as usize], normal: self.normals[i], abs_normal: self.abs_normals[i] }
    }

    /// The cross product `(q − p) × (r − p)` behind face `i`'s plane (as
    /// `Plane::Points([p, q, r])`), and the same with absolute values: what
    /// the float path builds the plane from.
    pub(crate) fn face_normal(&self, i: usize) -> (DVec3, DVec3) {
        (self.normals[i], self.abs_normals[i])
    }

    #[inline(always)]
    pub(crate) fn face_plane(&self, i: usize) -> Plane {
        let f = self.face(i);
        Plane::Points([self.corners[f[0] as usize], self.corners[f[1] as usize], self.corners[f[2] as usize]])
    }

    /// The halfspaces whose intersection is the frustum.
    pub fn planes(&self) -> PlaneSet {
        let mut out = PlaneSet::new();
        self.planes_into(&mut out);
        out
    }

    /// [`Frustum::planes`] written into `out` (no copy of the set).
    pub(crate) fn planes_into(&self, out: &mut PlaneSet) {
        out.clear();
        for i in 0..self.face_count() {
            out.push(self.face_plane(i));
        }
    }

    /// The halfspaces whose intersection is `hull(frustum ∪ {apex})`; for an
    /// apex at infinity, the frustum swept toward it without end.
    ///
    /// Beneath–beyond: faces that do not see the apex stay; each horizon
    /// edge `a → b` (as oriented in a face that sees the apex) spans a new
    /// facet `(a, b, apex)` with the same outward orientation. Faces whose
    /// plane contains the apex count as not seeing it, so coplanar cases keep
    /// their plane (the new facet through a neighbouring horizon edge then
    /// coincides with it and is redundant, never wrong).
    ///
    /// A non-finite apex, or a point at infinity in the zero direction, is
    /// an error: the hull is not defined.
    pub fn hull_with(&self, apex: Apex) -> Result<PlaneSet, GeomError> {
        let mut out = PlaneSet::new();
        self.hull_into(apex, &mut out)?;
        Ok(out)
    }

    /// [`Frustum::hull_with`] written into `out` (no copy of the set).
    pub(crate) fn hull_into(&self, apex: Apex, out: &mut PlaneSet) -> Result<(), GeomError> {
        let mut outline = HullOutline::new();
        self.hull_outline_into(apex, &mut outline)?;
        self.hull_planes_into(apex, &outline, out);
        Ok(())
    }

    /// The planes of an outline made by [`Frustum::hull_outline_into`] for
    /// the same apex.
    pub(crate) fn hull_planes_into(&self, apex: Apex, outline: &HullOutline, out: &mut PlaneSet) {
        out.clear();
        for &origin in outline.origins() {
            out.push(self.hull_plane(apex, origin));
        }
    }

    /// The plane of the hull with `apex` that comes from `origin`.
    #[inline(always)]
    pub(crate) fn hull_plane(&self, apex: Apex, origin: Origin) -> Plane {
        match origin {
            Origin::Face(i) => self.face_plane(i as usize),
            Origin::Horizon(a, b) => {
                let (pa, pb) = (self.corners[a as usize], self.corners[b as usize]);
                match apex {
                    Apex::Finite(l) => Plane::Points([pa, pb, l]),
                    Apex::Infinite(direction) => Plane::PointsDirection { p: pa, q: pb, direction },
                }
            }
        }
    }

    /// Beneath–beyond as in [`Frustum::hull_with`], recording where each
    /// plane comes from.
    pub(crate) fn hull_outline_into(&self, apex: Apex, out: &mut HullOutline) -> Result<(), GeomError> {
        out.len = 0;
        match apex {
            Apex::Finite(l) => check_finite(l, "hull apex")?,
            Apex::Infinite(d) => {
                check_finite(d, "hull apex direction")?;
                if d == DVec3::ZERO {
                    return Err(GeomError::ZeroDirection { what: "hull apex direction" });
                }
            }
        }
        let n = self.face_count();
        let in_range = self.in_range && in_safe_range(apex.coordinates());
        let (mut sees, mut coplanar) = (0u16, 0u16);
        for i in 0..n {
            let filter = self.face_filter(i);
            let triangle = || {
                let f = self.face(i);
                [self.corners[f[0] as usize], self.corners[f[1] as usize], self.corners[f[2] as usize]]
            };
            let side = match apex {
                Apex::Finite(l) => match in_range.then(|| filter.side(l)).flatten() {
                    Some(s) => s,
                    None => {
                        let [a, b, c] = triangle();
                        orient_past_static_filter(a, b, c, l, in_range)
                    }
                },
                Apex::Infinite(dir) => match in_range.then(|| filter.side_of_direction(dir)).flatten() {
                    Some(s) => s,
                    None => {
                        let [a, b, c] = triangle();
                        orient_direction_past_static_filter(a, b, c, dir)
                    }
                },
            };
            sees |= u16::from(side > 0) << i;
            coplanar |= u16::from(side == 0) << i;
        }
        (out.sees, out.coplanar) = (sees, coplanar);
        let apex_bit = apex.through_bit();
        for i in 0..n {
            if sees & 1 << i == 0 {
                out.push(corner_bits(self.face(i)), Origin::Face(i as u8));
                continue;
            }
            let f = self.face(i);
            for k in 0..f.len() {
                // NOTE: the next index without `%`, a division per edge.
                let (a, b) = (f[k], f[if k + 1 == f.len() { 0 } else { k + 1 }]);
                if let Some(j) = self.face_with_edge(b, a) {
                    if sees & 1 << j == 0 {
                        out.push(corner_bits(&[a, b]) | apex_bit, Origin::Horizon(a, b));
                    }
                }
            }
        }
        Ok(())
    }

    pub(crate) fn face_with_edge(&self, a: u8, b: u8) -> Option<usize> {
        let f = self.edge_face[a as usize][b as usize];
        (f != u8::MAX).then_some(f as usize)
    }

    /// Whether `x` lies in the closed frustum (exact).
    pub fn contains(&self, x: DVec3) -> bool {
        (0..self.face_count()).all(|i| {
            let f = self.face(i);
            orient(self.corners[f[0] as usize], self.corners[f[1] as usize], self.corners[f[2] as usize], x) <= 0
        })
    }
}

#[cfg(feature = "serde")]
impl TryFrom<[DVec3; 8]> for Frustum {
    type Error = GeomError;
    fn try_from(corners: [DVec3; 8]) -> Result<Frustum, GeomError> {
        Frustum::from_corners(corners)
    }
}

#[cfg(feature = "serde")]
impl From<Frustum> for [DVec3; 8] {
    fn from(f: Frustum) -> [DVec3; 8] {
        f.corners
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arith::number::{cross, diff, dot, Exact};

    #[test]
    fn orient_agrees_with_big_integers_across_its_stages() {
        // Camera frusta of many poses and scales: their side quads are
        // coplanar up to rounding (the wide-integer stage), the other
        // corners far off them (the static filter), and the tiny or huge
        // scales leave the safe range (dynamic filter, big integers).
        let exact =
            |p: DVec3, q: DVec3, r: DVec3, x: DVec3| dot(&cross(&diff::<Exact>(q, p), &diff::<Exact>(r, p)), &diff::<Exact>(x, p)).sign();
        let mut zeros = 0;
        for k in 0..400 {
            let t = k as f64 * 0.37;
            let scale = [1e-250, 1e-3, 1.0, 1e5, 1e250][k % 5];
            let cam = Camera {
                eye: DVec3::new(t.sin() * 30.0, 2.0 + t.cos(), 10.0 - t) * scale,
                forward: DVec3::new(t.cos(), -0.3 + 0.1 * t.sin(), -1.0),
                up: DVec3::Y,
                fovy: 0.3 + (k % 7) as f64 * 0.3,
                aspect: 1.0 + (k % 3) as f64 * 0.4,
                near: 0.1 * scale,
                far: (50.0 + k as f64) * scale,
            };
            let c = cam.corners().unwrap();
            for quad in QUADS {
                for x in 0..8 {
                    let [a, b, d, _] = quad.map(|i| c[i as usize]);
                    let want = exact(a, b, d, c[x]);
                    assert_eq!(orient(a, b, d, c[x]), want, "pose {k}, quad {quad:?}, corner {x}");
                    zeros += usize::from(want == 0);
                }
            }
        }
        assert!(zeros > 400, "exact zeros seen: {zeros}");
    }

    fn unit_frustum() -> [DVec3; 8] {
        let mut c = [DVec3::ZERO; 8];
        for (k, (t, s)) in [(-1.0, 1.0), (-2.0, 2.0)].into_iter().enumerate() {
            let sq = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            for (i, (x, y)) in sq.into_iter().enumerate() {
                c[4 * k + i] = DVec3::new(x * s, y * s, t);
            }
        }
        c
    }

    #[test]
    fn planar_frustum_has_six_faces_and_contains_its_centre() {
        let f = Frustum::from_corners(unit_frustum()).unwrap();
        assert_eq!(f.face_count(), 6);
        assert!(f.contains(DVec3::new(0.0, 0.0, -1.5)));
        assert!(!f.contains(DVec3::new(0.0, 0.0, -0.5)));
        assert!(!f.contains(DVec3::new(3.0, 0.0, -1.5)));
    }

    #[test]
    fn mirrored_corner_order_is_accepted() {
        let mut c = unit_frustum();
        for p in &mut c {
            p.x = -p.x;
        }
        let f = Frustum::from_corners(c).unwrap();
        assert!(f.contains(DVec3::new(0.0, 0.0, -1.5)));
        assert!(!f.contains(DVec3::new(0.0, 0.0, -2.5)));
    }

    #[test]
    fn creased_side_is_split_into_two_triangles() {
        let mut c = unit_frustum();
        c[6].x += 1e-9; // far +r+u corner pushed out of the side planes
        let f = Frustum::from_corners(c).unwrap();
        assert!(f.face_count() > 6);
        for x in c {
            assert!(f.contains(x));
        }
    }

    /// The sign `creased_pair` promises, checked exactly: on camera frusta
    /// (whose rounded side quads crease either way) and on both handedness.
    #[test]
    fn a_creased_pair_holds_each_third_corner_strictly_inside_the_other_plane() {
        use proptest::prelude::Rng;
        use proptest::test_runner::{RngAlgorithm, TestRng};
        let mut rng = TestRng::deterministic_rng(RngAlgorithm::ChaCha);
        let (mut pairs, mut other_pairs) = (0, 0);
        for _ in 0..300 {
            let mut v = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            let cam = Camera {
                eye: DVec3::new(v() * 100.0, v() * 100.0, v() * 100.0),
                forward: DVec3::new(v(), v(), v()),
                up: DVec3::new(v(), v(), v()),
                fovy: 1.0 + v() * 0.5,
                aspect: 1.5 + v() * 0.5,
                near: 0.5 + v() * 0.25,
                far: 300.0 + v() * 200.0,
            };
            let Ok(f) = Frustum::from_camera(&cam) else { continue };
            let mut mirrored = *f.corners();
            mirrored.iter_mut().for_each(|c| c.x = -c.x);
            for f in [f, Frustum::from_corners(mirrored).unwrap()] {
                for i in 0..f.face_count() {
                    for k in 0..f.face_count() {
                        let (a, b) = (corner_bits(f.face(i)), corner_bits(f.face(k)));
                        if i == k || !creased_pair(a, b) {
                            other_pairs += (i != k) as usize;
                            continue;
                        }
                        pairs += 1;
                        let third = f.face(i).iter().find(|&&c| b & 1 << c == 0).unwrap();
                        let t = f.face(k);
                        let c = f.corners();
                        assert_eq!(orient(c[t[0] as usize], c[t[1] as usize], c[t[2] as usize], c[*third as usize]), -1);
                    }
                }
            }
        }
        // Both kinds occur: the test is not vacuous.
        assert!(pairs > 500 && other_pairs > 5000, "{pairs} creased pairs, {other_pairs} others");
    }

    #[test]
    fn bad_frusta_are_rejected() {
        let mut c = unit_frustum();
        c.swap(4, 6); // twisted
        assert!(Frustum::from_corners(c).is_err());
        let mut flat = unit_frustum();
        for p in &mut flat {
            p.z = 0.0;
        }
        assert!(Frustum::from_corners(flat).is_err());
        let mut nan = unit_frustum();
        nan[3].y = f64::NAN;
        assert!(matches!(Frustum::from_corners(nan), Err(GeomError::NonFinite { .. })));
        let mut pinched = unit_frustum();
        pinched[1] = pinched[0];
        assert!(Frustum::from_corners(pinched).is_err());
    }
}
