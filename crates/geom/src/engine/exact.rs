//! Bounded convex polytopes with exactly defined vertices, clipped by
//! halfspaces with exact decisions.
//!
//! Every vertex is the intersection of three of the polytope's planes and is
//! kept as filtered homogeneous coordinates, never rounded: a later side test
//! is a filtered degree-4 determinant in plane coefficients, evaluated again
//! in exact arithmetic when the filter cannot decide. All combinatorial
//! decisions (which vertices survive, whether the result is flat or empty)
//! are therefore exact for the input numbers.
//!
//! Representation by dimension:
//! - solid: faces as vertex cycles, counter-clockwise seen from outside, one
//!   plane per face (faces are maximal: a cutting plane can never coincide
//!   with an existing face plane, so no two faces are coplanar);
//! - polygon: one vertex cycle, its supporting plane, and the plane through
//!   each edge;
//! - segment: two vertices and two planes through the line;
//! - point: one vertex.

use crate::arith::number::{Exact, Filtered, Ring};
use crate::arith::plane::{fold, intersect3, line_plane, side_value, Line, Plane};
use crate::error::GeomError;
use crate::input::aabb::Aabb;
use crate::limits::{MAX_FACES, MAX_FACE_INDICES, MAX_PLANES, MAX_VERTICES};
use crate::predicates::side::point_side;
use glam::DVec3;

const NONE: u16 = u16::MAX;

/// Largest proven rounding error of an output coordinate, in ulps of the
/// inputs' largest magnitude.
pub const ROUNDING_ULPS: f64 = 16.0;

/// How a vertex is known exactly. The cheapest exact description is
/// chosen when the vertex is made: an input point where the three planes
/// share one by definition, else a line–plane intersection where two of the
/// planes share an input line, else the meeting point of three planes.
#[derive(Clone, Copy, Debug)]
enum VertexDef {
    Point(DVec3),
    OnLine { line: Line, plane: u8 },
    Planes,
}

#[derive(Clone, Copy, Debug)]
struct Vertex {
    /// Three independent planes through the vertex.
    planes: [u8; 3],
    def: VertexDef,
    /// Filtered homogeneous coordinates (X, Y, Z, W).
    hom: [Filtered; 4],
    /// Exact sign of W (never zero for a vertex).
    w_sign: i8,
}

#[derive(Clone, Copy, Debug, Default)]
struct Face {
    plane: u8,
    start: u16,
    len: u16,
}

/// A bounded convex polytope (possibly flat or empty) with exact vertices.
#[derive(Clone)]
pub struct Polytope {
    planes: [Plane; MAX_PLANES],
    coef: [[Filtered; 4]; MAX_PLANES],
    n_planes: usize,
    verts: [Vertex; MAX_VERTICES],
    n_verts: usize,
    dim: i8,
    faces: [Face; MAX_FACES],
    n_faces: usize,
    idx: [u16; MAX_FACE_INDICES],
    /// Polygon: plane through edge `verts[i] → verts[i+1]`; segment: the two
    /// planes through the line in slots 0 and 1.
    edge_planes: [u8; MAX_VERTICES],
    /// Polygon: the supporting plane (its normal orients the cycle).
    support: u8,
    magnitude: f64,
    exact_evaluations: u32,
}

const DUMMY_VERTEX: Vertex = Vertex { planes: [0; 3], def: VertexDef::Planes, hom: [Filtered { v: 0.0, e: 0.0 }; 4], w_sign: 1 };
const DUMMY_PLANE: Plane = Plane::Axis { axis: 0, upper: true, value: 0.0 };

impl Polytope {
    pub(crate) fn empty_with_capacity() -> Polytope {
        Polytope {
            planes: [DUMMY_PLANE; MAX_PLANES],
            coef: [[Filtered { v: 0.0, e: 0.0 }; 4]; MAX_PLANES],
            n_planes: 0,
            verts: [DUMMY_VERTEX; MAX_VERTICES],
            n_verts: 0,
            dim: -1,
            faces: [Face::default(); MAX_FACES],
            n_faces: 0,
            idx: [0; MAX_FACE_INDICES],
            edge_planes: [0; MAX_VERTICES],
            support: 0,
            magnitude: 0.0,
            exact_evaluations: 0,
        }
    }

    /// The closed box (a flat box gives a polygon, segment or point).
    ///
    /// The box is checked first (its fields are public, so it need not come
    /// from [`Aabb::new`]): a NaN or infinite coordinate, or `min > max` on
    /// some axis, is an error.
    pub fn from_aabb(b: &Aabb) -> Result<Polytope, GeomError> {
        b.validate()?;
        let mut p = Polytope::empty_with_capacity();
        p.reset_to_valid_aabb(b);
        Ok(p)
    }

    /// Resets `self` to a box without touching the heap; the box is checked
    /// as in [`Polytope::from_aabb`], and on an error `self` is unchanged.
    pub fn reset_to_aabb(&mut self, b: &Aabb) -> Result<(), GeomError> {
        b.validate()?;
        self.reset_to_valid_aabb(b);
        Ok(())
    }

    /// [`Polytope::reset_to_aabb`] for a box already validated.
    pub(crate) fn reset_to_valid_aabb(&mut self, b: &Aabb) {
        debug_assert!(b.validate().is_ok());
        self.n_planes = 0;
        self.n_verts = 0;
        self.n_faces = 0;
        self.magnitude = 0.0;
        self.exact_evaluations = 0;
        // A zero-thickness axis is first opened to the next float up and then
        // closed by an exact clip, which yields the flat face without a
        // special case.
        let mut hi = b.max;
        let mut flat = [false; 3];
        for k in 0..3 {
            if b.min[k] == b.max[k] {
                flat[k] = true;
                hi[k] = if b.min[k] < f64::MAX { b.min[k].next_up() } else { b.min[k] };
            }
        }
        let mut lo = b.min;
        for k in 0..3 {
            if flat[k] && hi[k] == lo[k] {
                // min == f64::MAX: open downwards instead.
                lo[k] = lo[k].next_down();
            }
        }
        for k in 0..3u8 {
            self.push_plane(Plane::Axis { axis: k, upper: false, value: lo[k as usize] });
            self.push_plane(Plane::Axis { axis: k, upper: true, value: hi[k as usize] });
        }
        for i in 0..8u8 {
            let pl = [i & 1, 2 + ((i >> 1) & 1), 4 + ((i >> 2) & 1)];
            self.verts[i as usize] = self.make_vertex(pl).expect("axis planes meet in one point");
        }
        self.n_verts = 8;
        // Faces CCW from outside; corner index bits are (x, y, z) at max.
        const BOX_FACES: [(u8, [u16; 4]); 6] =
            [(0, [0, 4, 6, 2]), (1, [1, 3, 7, 5]), (2, [0, 1, 5, 4]), (3, [2, 6, 7, 3]), (4, [0, 2, 3, 1]), (5, [4, 5, 7, 6])];
        for (f, (plane, cycle)) in BOX_FACES.iter().enumerate() {
            self.faces[f] = Face { plane: *plane, start: 4 * f as u16, len: 4 };
            self.idx[4 * f..4 * f + 4].copy_from_slice(cycle);
        }
        self.n_faces = 6;
        self.dim = 3;
        for k in 0..3 {
            if flat[k] {
                let closing = if hi[k] == b.max[k] {
                    Plane::Axis { axis: k as u8, upper: false, value: b.max[k] }
                } else {
                    Plane::Axis { axis: k as u8, upper: true, value: b.min[k] }
                };
                self.clip(&closing).expect("a box has room for three more planes");
            }
        }
    }

    fn push_plane(&mut self, p: Plane) -> usize {
        let i = self.n_planes;
        self.planes[i] = p;
        self.coef[i] = p.coefficients::<Filtered>();
        self.magnitude = self.magnitude.max(p.magnitude());
        self.n_planes += 1;
        i
    }

    fn make_vertex(&mut self, planes: [u8; 3]) -> Result<Vertex, GeomError> {
        let pl = planes.map(|i| self.planes[i as usize]);
        if let Some(x) = common_point(&pl) {
            let one = Filtered { v: 1.0, e: 0.0 };
            let hom = [Filtered { v: x.x, e: 0.0 }, Filtered { v: x.y, e: 0.0 }, Filtered { v: x.z, e: 0.0 }, one];
            return Ok(Vertex { planes, def: VertexDef::Point(x), hom, w_sign: 1 });
        }
        for (i, j, k) in [(0, 1, 2), (0, 2, 1), (1, 2, 0)] {
            if let Some(line) = pl[i].shared_line(&pl[j]) {
                let def = VertexDef::OnLine { line, plane: planes[k] };
                let hom = line_plane(&line, &pl[k], &self.coef[planes[k] as usize]);
                if let Some(v) = self.finish_vertex(planes, def, hom) {
                    return Ok(v);
                }
            }
        }
        let [a, b, c] = planes.map(|i| i as usize);
        let hom = intersect3(&self.coef[a], &self.coef[b], &self.coef[c]);
        self.finish_vertex(planes, VertexDef::Planes, hom).ok_or(GeomError::Unsupported { reason: "internal: vertex planes are dependent" })
    }

    fn finish_vertex(&mut self, planes: [u8; 3], def: VertexDef, hom: [Filtered; 4]) -> Option<Vertex> {
        let mut v = Vertex { planes, def, hom, w_sign: 0 };
        v.w_sign = match hom[3].sign() {
            Some(s) => s,
            None => {
                self.exact_evaluations += 1;
                self.exact_hom(&v)[3].sign()
            }
        };
        (v.w_sign != 0).then_some(v)
    }

    fn exact_hom(&self, v: &Vertex) -> [Exact; 4] {
        match v.def {
            VertexDef::Point(x) => [Exact::lit(x.x), Exact::lit(x.y), Exact::lit(x.z), Exact::lit(1.0)],
            VertexDef::OnLine { line, plane } => {
                let pl = &self.planes[plane as usize];
                line_plane(&line, pl, &pl.coefficients::<Exact>())
            }
            VertexDef::Planes => {
                let [a, b, c] = v.planes.map(|i| self.planes[i as usize].coefficients::<Exact>());
                intersect3(&a, &b, &c)
            }
        }
    }

    /// Whether plane `p` passes through vertex `v` by definition.
    fn on_by_definition(&self, v: &Vertex, p: usize) -> bool {
        if v.planes.contains(&(p as u8)) {
            return true;
        }
        let plane = &self.planes[p];
        match v.def {
            VertexDef::Point(x) => plane.passes_through(x) == Some(true),
            VertexDef::OnLine { line, .. } => plane.contains_line(&line),
            VertexDef::Planes => false,
        }
    }

    /// Exact side of vertex `v` w.r.t. plane `p`: −1 inside, 0 on, +1 outside.
    fn side(&mut self, v: usize, p: usize) -> i8 {
        // NOTE: the filter goes first: a proven non-zero sign is final, and
        // the definitional checks below only matter for values near zero.
        if let Some(s) = side_value(&self.coef[p], &self.verts[v].hom).sign() {
            if s != 0 {
                return s * self.verts[v].w_sign;
            }
        }
        let vert = self.verts[v];
        if self.on_by_definition(&vert, p) {
            return 0;
        }
        if let VertexDef::Point(x) = vert.def {
            return point_side(&self.planes[p], x);
        }
        // A vertex on plane P tested against a plane Q sharing a line with P
        // (a creased frustum side, neighbouring silhouette planes): decide
        // through the well-conditioned fold factorisation instead.
        for &on in &vert.planes {
            let on = on as usize;
            let Some(line) = self.planes[on].shared_line(&self.planes[p]) else { continue };
            let (s, perp) = fold::<Filtered>(&line, &self.coef[on], &self.coef[p]);
            let s = match s.sign() {
                Some(s) => s,
                None => self.fold_sign(&line, on, p),
            };
            if s == 0 {
                return 0; // Q is P's plane, which holds the vertex.
            }
            if let Some(t) = side_value(&perp, &vert.hom).sign() {
                return s * t * vert.w_sign;
            }
        }
        self.exact_evaluations += 1;
        let h = self.exact_hom(&vert);
        side_value(&self.planes[p].coefficients::<Exact>(), &h).sign() * vert.w_sign
    }

    /// Exact sign of `n_Q · (u × n_P)` for planes `P = on`, `Q = p` sharing
    /// `line`, when the direct evaluation is too close to call (nearly
    /// coplanar planes).
    ///
    /// With `b` a defining point of `P` off the line, `Q(b) = μ·m·(b − a)`
    /// (see [`fold`]), so `sign μ = sign Q(b) · sign(m · (b − a))`: an
    /// orientation test of input points (adaptive, no big integers) and a
    /// well-conditioned product.
    fn fold_sign(&mut self, line: &Line, on: usize, p: usize) -> i8 {
        let (pts, n) = self.planes[on].points();
        for &b in &pts[..n] {
            let lies_on_line = match *line {
                Line::TwoPoints(a, c) => b == a || b == c,
                Line::PointDirection(a, _) => b == a,
            };
            if lies_on_line {
                continue;
            }
            let (_, perp) = fold::<Filtered>(line, &self.coef[on], &self.coef[p]);
            let hb = [Filtered::lit(b.x), Filtered::lit(b.y), Filtered::lit(b.z), Filtered::lit(1.0)];
            if let Some(t) = side_value(&perp, &hb).sign() {
                if t != 0 {
                    return point_side(&self.planes[p], b) * t;
                }
            }
        }
        self.exact_evaluations += 1;
        fold::<Exact>(line, &self.planes[on].coefficients(), &self.planes[p].coefficients()).0.sign()
    }

    /// Makes the polytope empty.
    pub fn make_empty(&mut self) {
        self.dim = -1;
        self.n_verts = 0;
        self.n_faces = 0;
    }

    /// Dimension of the polytope: −1 (empty) to 3 (solid).
    pub fn dimension(&self) -> i8 {
        self.dim
    }

    /// Whether the polytope has no point.
    pub fn is_empty(&self) -> bool {
        self.dim < 0
    }

    /// Number of side tests the filter could not decide so far.
    pub fn exact_evaluations(&self) -> u32 {
        self.exact_evaluations
    }

    /// Number of planes that cut the polytope so far (box planes included).
    pub fn plane_count(&self) -> usize {
        self.n_planes
    }

    /// Intersects with a closed halfspace. Returns whether the plane cut
    /// (changed) the polytope.
    pub fn clip(&mut self, plane: &Plane) -> Result<bool, GeomError> {
        if !plane.is_finite() {
            return Err(GeomError::NonFinite { what: "clipping plane" });
        }
        if self.dim < 0 {
            return Ok(false);
        }
        if self.n_planes >= MAX_PLANES {
            return Err(GeomError::CapacityExceeded { what: "planes" });
        }
        // Tentatively place the plane; it is kept only if it cuts.
        let p = self.n_planes;
        self.planes[p] = *plane;
        self.coef[p] = plane.coefficients::<Filtered>();
        let mut side = [0i8; MAX_VERTICES];
        let (mut pos, mut neg) = (0, 0);
        for (v, s) in side.iter_mut().enumerate().take(self.n_verts) {
            *s = self.side(v, p);
            pos += (*s > 0) as usize;
            neg += (*s < 0) as usize;
        }
        if pos == 0 {
            return Ok(false);
        }
        self.magnitude = self.magnitude.max(plane.magnitude());
        if neg == 0 {
            self.collapse_onto_plane(&side);
            return Ok(true);
        }
        self.n_planes += 1;
        match self.dim {
            3 => self.cut_solid(&side, p as u8)?,
            2 => self.cut_polygon(&side, p as u8)?,
            1 => self.cut_segment(&side, p as u8)?,
            _ => unreachable!("a point has no vertex on both sides"),
        }
        Ok(true)
    }

    /// Clips by every halfspace in turn, stopping early once empty.
    pub fn clip_all(&mut self, planes: &[Plane]) -> Result<(), GeomError> {
        for p in planes {
            if self.dim < 0 {
                break;
            }
            self.clip(p)?;
        }
        Ok(())
    }

    /// Intersects with a closed box.
    pub fn intersect_aabb(&mut self, b: &Aabb) -> Result<(), GeomError> {
        for k in 0..3u8 {
            self.clip(&Plane::Axis { axis: k, upper: false, value: b.min[k as usize] })?;
            self.clip(&Plane::Axis { axis: k, upper: true, value: b.max[k as usize] })?;
        }
        Ok(())
    }

    /// Intersects with another polytope (of any dimension).
    pub fn intersect(&mut self, other: &Polytope) -> Result<(), GeomError> {
        if other.dim > self.dim {
            // Clipping the lower-dimensional one is cheaper and exact either way.
            let mut o = other.clone();
            o.clip_all(&self.halfspaces_buf()?[..])?;
            *self = o;
            return Ok(());
        }
        let hs = other.halfspaces_buf()?;
        self.clip_all(&hs[..])
    }

    /// Whether the point lies in the closed polytope (exact).
    pub fn contains_point(&self, p: DVec3) -> bool {
        if self.dim < 0 || !p.is_finite() {
            return false;
        }
        let Ok(hs) = self.halfspaces_buf() else { return false };
        hs.iter().all(|h| point_side(h, p) <= 0)
    }

    /// Whether `other` lies in the closed polytope `self` (exact).
    pub fn contains(&self, other: &Polytope) -> Result<bool, GeomError> {
        let mut o = other.clone();
        for h in self.halfspaces_buf()?.iter() {
            if o.clip(h)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Halfspaces whose intersection is exactly this polytope.
    fn halfspaces_buf(&self) -> Result<HalfspaceBuf, GeomError> {
        let mut out = HalfspaceBuf { planes: [DUMMY_PLANE; MAX_PLANES + 8], len: 0 };
        match self.dim {
            3 => {
                for f in &self.faces[..self.n_faces] {
                    out.push(self.planes[f.plane as usize]);
                }
            }
            2 => {
                let s = self.planes[self.support as usize];
                out.push(s);
                out.push(s.flipped());
                for i in 0..self.n_verts {
                    out.push(self.planes[self.edge_planes[i] as usize]);
                }
            }
            1 | 0 => {
                // A point is the intersection of its three defining planes,
                // each taken with both orientations. A segment is its two
                // line planes (both orientations) and each endpoint's
                // defining planes oriented toward the other endpoint.
                if self.n_planes >= MAX_PLANES {
                    return Err(GeomError::CapacityExceeded { what: "planes" });
                }
                if self.dim == 1 {
                    for k in 0..2 {
                        let line = self.planes[self.edge_planes[k] as usize];
                        out.push(line);
                        out.push(line.flipped());
                    }
                }
                let mut me = self.clone();
                for v in 0..self.n_verts {
                    for &pl in &self.verts[v].planes {
                        let plane = self.planes[pl as usize];
                        if self.dim == 0 {
                            out.push(plane);
                            out.push(plane.flipped());
                            continue;
                        }
                        let other = 1 - v;
                        let i = me.n_planes;
                        me.planes[i] = plane;
                        me.coef[i] = plane.coefficients::<Filtered>();
                        match me.side(other, i) {
                            0 => {
                                out.push(plane);
                                out.push(plane.flipped());
                            }
                            s if s < 0 => out.push(plane),
                            _ => out.push(plane.flipped()),
                        }
                    }
                }
            }
            _ => {
                // Empty: an impossible halfspace.
                out.push(Plane::Coefficients { normal: DVec3::ZERO, offset: 1.0 });
            }
        }
        Ok(out)
    }

    /// All vertices are on the plane or outside: keep the face on the plane.
    fn collapse_onto_plane(&mut self, side: &[i8]) {
        let mut on = [0u16; MAX_VERTICES];
        let mut n_on = 0;
        for v in 0..self.n_verts {
            if side[v] == 0 {
                on[n_on] = v as u16;
                n_on += 1;
            }
        }
        match n_on {
            0 => {
                self.dim = -1;
                self.n_verts = 0;
                self.n_faces = 0;
            }
            1 => {
                self.verts[0] = self.verts[on[0] as usize];
                self.n_verts = 1;
                self.n_faces = 0;
                self.dim = 0;
            }
            2 => {
                let (a, b) = (on[0], on[1]);
                let line = match self.dim {
                    3 => {
                        let f1 = self.face_with_edge(a, b).or_else(|| self.face_with_edge(b, a));
                        let f2 = self.face_with_edge(b, a).or_else(|| self.face_with_edge(a, b));
                        let (f1, f2) = (f1.expect("edge"), f2.expect("edge"));
                        [self.faces[f1].plane, self.faces[f2].plane]
                    }
                    2 => {
                        let i = if (a as usize + 1) % self.n_verts == b as usize { a } else { b };
                        [self.support, self.edge_planes[i as usize]]
                    }
                    _ => [self.edge_planes[0], self.edge_planes[1]],
                };
                self.verts[0] = self.verts[a as usize];
                self.verts[1] = self.verts[b as usize];
                self.edge_planes[0] = line[0];
                self.edge_planes[1] = line[1];
                self.n_verts = 2;
                self.n_faces = 0;
                self.dim = 1;
            }
            _ => {
                // Three or more vertices on a supporting plane of a solid: a
                // facet (vertices are extreme points, so never collinear).
                debug_assert_eq!(self.dim, 3);
                let f = (0..self.n_faces)
                    .find(|&f| self.face_slice(f).iter().all(|&v| side[v as usize] == 0))
                    .expect("a supporting plane through three vertices contains a facet");
                let face = self.faces[f];
                let mut cyc = [0u16; MAX_VERTICES];
                let n = face.len as usize;
                cyc[..n].copy_from_slice(self.face_slice(f));
                let mut planes = [0u8; MAX_VERTICES];
                for k in 0..n {
                    let (a, b) = (cyc[k], cyc[(k + 1) % n]);
                    let twin = self.face_with_edge(b, a).expect("closed surface");
                    planes[k] = self.faces[twin].plane;
                }
                let old = self.verts;
                for k in 0..n {
                    self.verts[k] = old[cyc[k] as usize];
                }
                self.edge_planes[..n].copy_from_slice(&planes[..n]);
                self.support = face.plane;
                self.n_verts = n;
                self.n_faces = 0;
                self.dim = 2;
            }
        }
    }

    fn face_slice(&self, f: usize) -> &[u16] {
        let face = self.faces[f];
        &self.idx[face.start as usize..(face.start + face.len) as usize]
    }

    fn face_with_edge(&self, a: u16, b: u16) -> Option<usize> {
        (0..self.n_faces).find(|&f| {
            let s = self.face_slice(f);
            (0..s.len()).any(|k| s[k] == a && s[(k + 1) % s.len()] == b)
        })
    }

    /// Cuts a solid by plane `p` that has vertices strictly on both sides.
    fn cut_solid(&mut self, side: &[i8; MAX_VERTICES], p: u8) -> Result<(), GeomError> {
        // 1. Edges crossing the plane strictly, as directed edges of faces.
        const MAX_CROSS: usize = 2 * MAX_FACES;
        let mut cross = [(0u16, 0u16, 0u8); MAX_CROSS];
        let mut n_cross = 0;
        for f in 0..self.n_faces {
            let s = self.face_slice(f);
            for k in 0..s.len() {
                let (a, b) = (s[k], s[(k + 1) % s.len()]);
                if side[a as usize] * side[b as usize] < 0 {
                    if n_cross == MAX_CROSS {
                        return Err(GeomError::CapacityExceeded { what: "crossing edges" });
                    }
                    cross[n_cross] = (a, b, self.faces[f].plane);
                    n_cross += 1;
                }
            }
        }
        // 2. One new vertex per undirected crossing edge: the meeting point
        //    of the two face planes along the edge and the cutting plane.
        let mut new_vertex = [NONE; MAX_CROSS];
        let first_new = self.n_verts;
        for i in 0..n_cross {
            if new_vertex[i] != NONE {
                continue;
            }
            let (a, b, fp) = cross[i];
            let j = (0..n_cross).find(|&j| cross[j].0 == b && cross[j].1 == a).expect("every edge has a twin");
            if self.n_verts == MAX_VERTICES {
                return Err(GeomError::CapacityExceeded { what: "vertices" });
            }
            let v = self.make_vertex([fp, cross[j].2, p])?;
            self.verts[self.n_verts] = v;
            new_vertex[i] = self.n_verts as u16;
            new_vertex[j] = self.n_verts as u16;
            self.n_verts += 1;
        }
        let on_plane = |v: u16| v as usize >= first_new || side[v as usize] == 0;
        // 3. Clip every face cycle; remember each face's chord along the plane.
        let mut faces = [Face::default(); MAX_FACES];
        let mut idx = [0u16; MAX_FACE_INDICES];
        let (mut nf, mut ni) = (0usize, 0usize);
        let mut chord_next = [NONE; MAX_VERTICES];
        let mut chord_start = NONE;
        let mut ci = 0;
        for f in 0..self.n_faces {
            let face = self.faces[f];
            let start = ni;
            let s = face.start as usize;
            let len = face.len as usize;
            for k in 0..len {
                let (a, b) = (self.idx[s + k], self.idx[s + (k + 1) % len]);
                if side[a as usize] <= 0 {
                    if ni == MAX_FACE_INDICES {
                        return Err(GeomError::CapacityExceeded { what: "face indices" });
                    }
                    idx[ni] = a;
                    ni += 1;
                }
                if side[a as usize] * side[b as usize] < 0 {
                    debug_assert!(cross[ci].0 == a && cross[ci].1 == b);
                    if ni == MAX_FACE_INDICES {
                        return Err(GeomError::CapacityExceeded { what: "face indices" });
                    }
                    idx[ni] = new_vertex[ci];
                    ni += 1;
                    ci += 1;
                }
            }
            let n = ni - start;
            if n < 3 {
                ni = start; // the face lay outside, or touched the plane only
                continue;
            }
            // The chord u → w along the cutting plane; the new face on the
            // plane runs along it the other way, w → u.
            for k in 0..n {
                let (u, w) = (idx[start + k], idx[start + (k + 1) % n]);
                if on_plane(u) && on_plane(w) {
                    chord_next[w as usize] = u;
                    chord_start = w;
                    break;
                }
            }
            faces[nf] = Face { plane: face.plane, start: start as u16, len: n as u16 };
            nf += 1;
        }
        // 4. The new face on the cutting plane, chained from the chords.
        if chord_start == NONE || nf == MAX_FACES {
            return Err(GeomError::CapacityExceeded { what: "faces" });
        }
        let start = ni;
        let mut v = chord_start;
        loop {
            if ni == MAX_FACE_INDICES || ni - start > self.n_verts {
                return Err(GeomError::Unsupported { reason: "internal: section polygon does not close" });
            }
            idx[ni] = v;
            ni += 1;
            v = chord_next[v as usize];
            if v == NONE {
                return Err(GeomError::Unsupported { reason: "internal: section polygon is open" });
            }
            if v == chord_start {
                break;
            }
        }
        faces[nf] = Face { plane: p, start: start as u16, len: (ni - start) as u16 };
        nf += 1;
        // 5. Drop the vertices outside and renumber.
        let mut remap = [NONE; MAX_VERTICES];
        let mut nv = 0;
        for v in 0..self.n_verts {
            if v >= first_new || side[v] <= 0 {
                self.verts[nv] = self.verts[v];
                remap[v] = nv as u16;
                nv += 1;
            }
        }
        self.n_verts = nv;
        for i in &mut idx[..ni] {
            *i = remap[*i as usize];
        }
        self.faces[..nf].copy_from_slice(&faces[..nf]);
        self.idx[..ni].copy_from_slice(&idx[..ni]);
        self.n_faces = nf;
        Ok(())
    }

    /// Cuts a polygon (Sutherland–Hodgman with exact sides).
    fn cut_polygon(&mut self, side: &[i8; MAX_VERTICES], p: u8) -> Result<(), GeomError> {
        let n = self.n_verts;
        let mut verts = [DUMMY_VERTEX; MAX_VERTICES];
        let mut planes = [0u8; MAX_VERTICES];
        let mut m = 0;
        for i in 0..n {
            let j = (i + 1) % n;
            let (sa, sb) = (side[i], side[j]);
            let e = self.edge_planes[i];
            if m + 2 > MAX_VERTICES {
                return Err(GeomError::CapacityExceeded { what: "vertices" });
            }
            if sa <= 0 {
                verts[m] = self.verts[i];
                // The edge leaves along `e` unless it heads outside, in which
                // case the boundary continues along the cutting plane.
                planes[m] = if sb > 0 && sa == 0 { p } else { e };
                m += 1;
            }
            if sa * sb < 0 {
                verts[m] = self.make_vertex([self.support, e, p])?;
                planes[m] = if sa < 0 { p } else { e };
                m += 1;
            }
        }
        self.verts[..m].copy_from_slice(&verts[..m]);
        self.edge_planes[..m].copy_from_slice(&planes[..m]);
        self.n_verts = m;
        Ok(())
    }

    fn cut_segment(&mut self, side: &[i8; MAX_VERTICES], p: u8) -> Result<(), GeomError> {
        let v = self.make_vertex([self.edge_planes[0], self.edge_planes[1], p])?;
        let outside = if side[0] > 0 { 0 } else { 1 };
        self.verts[outside] = v;
        Ok(())
    }

    /// Writes the rounded polytope into `out` (vertices, faces, planes).
    pub(crate) fn write_rounded(&mut self, out: &mut crate::body::Body) {
        out.clear();
        out.dim = self.dim;
        if self.dim < 0 {
            return;
        }
        for v in 0..self.n_verts {
            let x = self.rounded_vertex(v);
            out.verts[v] = x;
        }
        out.n_verts = self.n_verts;
        match self.dim {
            3 => {
                let mut ni = 0;
                for f in 0..self.n_faces {
                    let s = self.face_slice(f);
                    out.idx[ni..ni + s.len()].copy_from_slice(s);
                    out.face_start[f] = ni as u16;
                    ni += s.len();
                    out.face_planes[f] = self.planes[self.faces[f].plane as usize].approximate();
                }
                out.face_start[self.n_faces] = ni as u16;
                out.n_faces = self.n_faces;
            }
            2 => {
                for v in 0..self.n_verts {
                    out.idx[v] = v as u16;
                }
                out.face_start[0] = 0;
                out.face_start[1] = self.n_verts as u16;
                out.face_planes[0] = self.planes[self.support as usize].approximate();
                out.n_faces = 1;
            }
            _ => out.n_faces = 0,
        }
    }

    /// Filtered rounding of `X/W`; false when the proven error is too large.
    fn round_quotient(&self, h: &[Filtered; 4], out: &mut [f64; 3]) -> bool {
        let w = h[3];
        if !(w.v.abs() > 2.0 * w.e && w.v.is_finite() && w.e.is_finite()) {
            return false;
        }
        for k in 0..3 {
            let x = h[k].v / w.v;
            let err = (h[k].e + x.abs() * w.e) / (w.v.abs() - w.e) + 2.0 * f64::EPSILON * x.abs();
            if !self.within_tolerance(x, err) {
                return false;
            }
            out[k] = x;
        }
        true
    }

    /// Filtered rounding of a line–plane intersection as `a + u·t` with
    /// `t = −P(a) / (n·u)`: coordinates the line holds fixed (axis lines)
    /// stay exact, and the others carry the error of `t` alone.
    fn round_on_line(&self, line: &Line, plane: usize, out: &mut [f64; 3]) -> bool {
        let c = &self.coef[plane];
        let a = line.anchor();
        let u = line.direction::<Filtered>();
        let n = [c[0], c[1], c[2]];
        let nu = crate::arith::number::dot(&n, &u);
        let pa = self.planes[plane].eval_at::<Filtered>(a);
        if !(nu.v.abs() > 2.0 * nu.e && nu.v.is_finite() && pa.v.is_finite()) {
            return false;
        }
        let t = -pa.v / nu.v;
        let t_err = (pa.e + t.abs() * nu.e) / (nu.v.abs() - nu.e) + f64::EPSILON * t.abs();
        for k in 0..3 {
            if u[k].v == 0.0 && u[k].e == 0.0 {
                out[k] = a[k];
                continue;
            }
            let step = u[k].v * t;
            let x = a[k] + step;
            let err = u[k].v.abs() * t_err + t.abs() * u[k].e + f64::EPSILON * (step.abs() + x.abs());
            if !self.within_tolerance(x, err) {
                return false;
            }
            out[k] = x;
        }
        true
    }

    /// NOTE: a filtered coordinate is accepted when its proven error is at
    /// most [`ROUNDING_ULPS`] ulps of the inputs' largest magnitude (the
    /// proven bound is worst-case; actual errors are typically below one
    /// ulp); otherwise the exact coordinates are divided exactly, within one
    /// ulp.
    fn within_tolerance(&self, x: f64, err: f64) -> bool {
        x.is_finite() && err <= self.magnitude.max(x.abs()) * (ROUNDING_ULPS * f64::EPSILON)
    }

    /// Rounds vertex `v` to f64, within a few ulps of the inputs' magnitude.
    fn rounded_vertex(&mut self, v: usize) -> DVec3 {
        let vert = self.verts[v];
        let mut out = [0.0; 3];
        let ok = match vert.def {
            VertexDef::Point(x) => return x,
            VertexDef::OnLine { line, plane } => {
                self.round_quotient(&vert.hom, &mut out) || self.round_on_line(&line, plane as usize, &mut out)
            }
            VertexDef::Planes => self.round_quotient(&vert.hom, &mut out),
        };
        if !ok {
            self.exact_evaluations += 1;
            let e = self.exact_hom(&self.verts[v]);
            for k in 0..3 {
                out[k] = Exact::ratio_to_f64(&e[k], &e[3]);
            }
        }
        // Adding +0 turns a −0 from a negative W into +0.
        DVec3::from_array(out.map(|x| x + 0.0))
    }
}

struct HalfspaceBuf {
    planes: [Plane; MAX_PLANES + 8],
    len: usize,
}

impl HalfspaceBuf {
    fn push(&mut self, p: Plane) {
        if self.len < self.planes.len() {
            self.planes[self.len] = p;
            self.len += 1;
        }
    }
}

impl std::ops::Deref for HalfspaceBuf {
    type Target = [Plane];
    fn deref(&self) -> &[Plane] {
        &self.planes[..self.len]
    }
}

/// The input point three planes all pass through by definition, if any.
fn common_point(planes: &[Plane; 3]) -> Option<DVec3> {
    if let [Plane::Axis { axis: i, value: a, .. }, Plane::Axis { axis: j, value: b, .. }, Plane::Axis { axis: k, value: c, .. }] = *planes {
        let mut x = DVec3::ZERO;
        let (i, j, k) = (i as usize, j as usize, k as usize);
        if i == j || j == k || i == k {
            return None;
        }
        x[i] = a;
        x[j] = b;
        x[k] = c;
        return Some(x);
    }
    for pl in planes {
        let (pts, n) = pl.points();
        for &x in &pts[..n] {
            if planes.iter().all(|q| q.passes_through(x) == Some(true)) {
                return Some(x);
            }
        }
    }
    None
}
