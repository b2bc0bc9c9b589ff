//! Clipping by the faces of `S` and `L`: proven signs, certified crossings,
//! flat results.

use super::planes::{coord, coord_mut, line_crossing, line_proxy, FloatPlane, SideBound};
use super::{bits, decide, two_or_more, CertifiedClipper, Fold, Step, VertexSet, CAP_V, FOLD_CACHE, LIGHT_FRUSTUM_SHIFT, NONE};
use crate::arith::floor::{BOUND_SLACK as SLACK, UNIT_ROUNDOFF as U};
use crate::arith::number::abs_cross;
use crate::arith::plane::Plane;
use crate::input::aabb::Aabb;
use crate::input::frustum::{corner_bits, creased_pair, Frustum};
use crate::predicates::side::point_side;
use glam::{DMat3, DVec3};

impl CertifiedClipper {
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
    pub(super) fn bounds(&self) -> (DVec3, DVec3) {
        // NOTE: each exact coordinate lies within its `rad` of `pos`; one pad
        // for all, 4·max rad + 4u·max |pos|, leaves at least 3·max rad +
        // 4u·max |pos| beyond that, more than the roundings of the pad and of
        // the sums (each under u of its magnitude).
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let (mut r_max, mut x_max) = (DVec3::ZERO, DVec3::ZERO);
        for v in 0..self.verts.len {
            let (x, r) = (self.verts.pos[v], self.verts.rad[v]);
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
    pub(super) fn next_slot(&mut self) -> Option<&mut FloatPlane> {
        self.planes.items.get_mut(self.planes.len)
    }

    /// Clips by the plane the caller staged in slot `n_planes` (see
    /// [`CertifiedClipper::next_slot`]).
    ///
    /// NOTE: staged in place rather than passed by value: a plane is ~250
    /// bytes, and two copies of it per clip were a visible share of a cut.
    pub(super) fn clip(&mut self) -> Step {
        let k = self.planes.len;
        let plane = &self.planes.items[k];
        let (through, axis, upper, value) = (plane.through, plane.axis, plane.upper, plane.value);
        // NOTE: the planes clipped by are faces of S and of L, whose values
        // and defining points are in `magnitude` already (`reset_to_hull`).
        debug_assert!(plane.src.magnitude() <= self.magnitude);
        let mut partners = 0;
        if two_or_more(through as u64) {
            for (i, p) in self.planes.items[..k].iter().enumerate() {
                if two_or_more((p.through & through) as u64) && matches!(p.src, Plane::Points(_)) {
                    partners |= 1 << i;
                }
            }
        }
        self.planes.partners[k] = partners;
        // The vertices strictly inside and strictly outside, as vertex sets.
        let (mut inside, mut outside): (VertexSet, VertexSet) = (0, 0);
        if axis < 3 {
            // An axis plane has no input points and no fold partners: its
            // sign is a comparison, exact where the coordinate is.
            self.planes.axis |= 1 << k;
            let a = axis as usize;
            let flip = if upper { 1.0 } else { -1.0 };
            for v in 0..self.verts.len {
                let s = (coord(&self.verts.pos[v], a) - value) * flip;
                let Some(s) = decide(s, coord(&self.verts.rad[v], a) * SLACK + 2.0 * U * s.abs()) else { return Step::Uncertain };
                self.verts.sign[v] = s;
                inside |= u64::from(s < 0) << v;
                outside |= u64::from(s > 0) << v;
            }
        } else {
            let bound = self.planes.items[k].side_bound();
            for v in 0..self.verts.len {
                let Some(s) = self.sign_at(v, k, &bound) else { return Step::Uncertain };
                self.verts.sign[v] = s;
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
            let touching = self.verts.sign[..self.verts.len].iter().filter(|&&s| s == 0).count();
            if touching == self.verts.len {
                if self.dim == 3 {
                    return Step::Uncertain;
                }
                self.flat |= bit;
            } else if self.dim < 3 && touching > self.dim as usize {
                return Step::Uncertain;
            }
            if touching < 3 || touching == self.verts.len {
                for v in 0..self.verts.len {
                    if self.verts.sign[v] == 0 {
                        self.verts.on[v] |= bit;
                    }
                }
            }
            self.planes.len += 1;
            return Step::Nonempty;
        }
        if inside == 0 {
            // Entirely outside (empty), or touching from outside: what is
            // left is the body's face on the plane (flat).
            return if self.verts.sign[..self.verts.len].contains(&0) { self.flatten(k) } else { Step::Empty };
        }
        self.planes.len += 1;
        self.cuts += 1;
        if self.cut(k, inside, outside) {
            Step::Nonempty
        } else {
            Step::Uncertain
        }
    }

    /// Copies vertex slot `from` into slot `to`.
    pub(super) fn move_vertex(&mut self, from: usize, to: usize) {
        self.verts.pos[to] = self.verts.pos[from];
        self.verts.rad[to] = self.verts.rad[from];
        self.verts.on[to] = self.verts.on[from];
        self.verts.is_point[to] = self.verts.is_point[from];
    }

    /// Keeps only the vertices on plane `k` (signs in `self.verts.sign`, none
    /// inside): the body's face on `k`, a polygon, an edge or a vertex.
    ///
    /// NOTE: every sign is exact, so these are all of the face's vertices;
    /// three or more vertices of a solid on one supporting plane are a
    /// polygon (extreme points, never collinear), and a flat body's face on
    /// a plane that does not hold all of it has one dimension fewer.
    pub(super) fn flatten(&mut self, k: usize) -> Step {
        let bit = 1u64 << k;
        let mut n = 0;
        for v in 0..self.verts.len {
            if self.verts.sign[v] == 0 {
                self.move_vertex(v, n);
                self.verts.on[n] |= bit;
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
        self.verts.len = n;
        self.dim = dim;
        self.flat = self.verts.on[..n].iter().fold(u64::MAX, |all, &on| all & on);
        self.planes.len += 1;
        Step::Nonempty
    }

    /// Exact sign of vertex `v` against plane `k`, if provable.
    pub(super) fn sign_at(&mut self, v: usize, k: usize, bound: &SideBound) -> Option<i8> {
        let plane = &self.planes.items[k];
        if self.verts.is_point[v] & plane.through != 0 {
            return Some(0);
        }
        let (x, r) = (self.verts.pos[v], self.verts.rad[v]);
        // A point on several planes that share a line with k: any of them
        // may decide (the point can lie close to one line and far from another).
        for i in bits(self.verts.on[v] & self.planes.partners[k]) {
            if let Some(fold) = self.fold(i, k) {
                let (s, e) = fold.proxy.side(x, r);
                if let Some(s) = decide(s, e) {
                    return Some(s * fold.sign as i8);
                }
            }
        }
        let plane = &self.planes.items[k];
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
    pub(super) fn fold(&mut self, i: usize, k: usize) -> Option<&Fold> {
        let key = (i as u8, k as u8);
        let slot = match self.planes.fold_keys.iter().position(|&e| e == key) {
            Some(slot) => slot,
            None => {
                let f = self.make_fold(i, k, self.planes.items[i].through & self.planes.items[k].through);
                let slot = self.planes.fold_keys.iter().position(|e| e.0 == NONE).unwrap_or(k % FOLD_CACHE);
                self.planes.fold_keys[slot] = key;
                self.planes.fold_proxies[slot] = f;
                slot
            }
        };
        self.planes.fold_proxies[slot].as_ref()
    }

    pub(super) fn make_fold(&self, i: usize, k: usize, common: u32) -> Option<Fold> {
        let mut ids = bits(common as u64);
        let (a, c) = (self.points[ids.next()?], self.points[ids.next()?]);
        let Plane::Points(defining) = self.planes.items[i].src else { return None };
        if a == c {
            return None;
        }
        // A defining point of plane i off the common line.
        let y = *defining.iter().find(|&&p| p != a && p != c)?;
        let proxy = line_proxy(&self.planes.items[i], a, c);
        let (s, err) = proxy.side(y, DVec3::ZERO);
        let proxy_y = decide(s, err).filter(|&s| s != 0)?;
        // NOTE: across a crease `y` lies within rounding of plane k, where
        // only exact arithmetic decides; the frustum's fold test already did.
        let (ti, tk) = (self.planes.items[i].through, self.planes.items[k].through);
        let creased = creased_pair(ti, tk) || creased_pair(ti >> LIGHT_FRUSTUM_SHIFT, tk >> LIGHT_FRUSTUM_SHIFT);
        let k_y = if creased { -1 } else { point_side(&self.planes.items[k].src, y) };
        debug_assert_eq!(k_y, point_side(&self.planes.items[k].src, y));
        if k_y == 0 {
            return None;
        }
        Some(Fold { proxy, sign: (k_y * proxy_y) as f64 })
    }

    /// Side values of the two ends of edge `u`–`w` against plane `k`, on
    /// one scale (the fold proxy when the edge lies in a folding plane).
    pub(super) fn edge_sides(&mut self, u: usize, w: usize, k: usize) -> [(f64, f64); 2] {
        let ((xu, ru), (xw, rw)) = ((self.verts.pos[u], self.verts.rad[u]), (self.verts.pos[w], self.verts.rad[w]));
        let common = self.verts.on[u] & self.verts.on[w] & self.planes.partners[k];
        if common != 0 {
            if let Some(f) = self.fold(common.trailing_zeros() as usize, k) {
                let side = |x, r| {
                    let (s, e) = f.proxy.side(x, r);
                    (s * f.sign, e)
                };
                return [side(xu, ru), side(xw, rw)];
            }
        }
        let p = &self.planes.items[k];
        [p.side(xu, ru), p.side(xw, rw)]
    }

    /// Makes the vertex where edge `u` (inside) – `w` (outside) crosses
    /// plane `k`; false when its error cannot be bounded.
    pub(super) fn crossing(&mut self, u: usize, w: usize, k: usize, out: usize) -> bool {
        let common = self.verts.on[u] & self.verts.on[w];
        let on = common | 1 << k;
        self.verts.on[out] = on;
        // Exact incidences: if every plane through the vertex passes through
        // one input point, the vertex is that point.
        // NOTE: an axis plane (a face of S) passes through no input point, so
        // a cut by one skips the loop.
        let through_k = self.planes.items[k].through;
        let pts = if through_k == 0 { 0 } else { bits(common).fold(through_k, |pts, i| pts & self.planes.items[i].through) };
        if pts != 0 {
            self.verts.pos[out] = self.points[pts.trailing_zeros() as usize];
            self.verts.rad[out] = DVec3::ZERO;
            self.verts.is_point[out] = pts;
            return true;
        }
        // Both ends exact input points (an edge of the hull as built): the
        // edge is the segment between them, no need to find the line's
        // defining points through the planes.
        if self.verts.is_point[u] != 0 && self.verts.is_point[w] != 0 {
            if let Some((x, rad)) = line_crossing(self.verts.pos[u], self.verts.pos[w] - self.verts.pos[u], true, &self.planes.items[k]) {
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
        let guess = self.verts.pos[from] + (self.verts.pos[to] - self.verts.pos[from]) * t;
        // The edge lies on two planes of `common`; with `k` they define the
        // vertex.
        let mut edge = bits(common);
        let (Some(i), Some(j)) = (edge.next(), edge.next()) else { return false };
        let mut planes = [&self.planes.items[i], &self.planes.items[j], &self.planes.items[k]];
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
    pub(super) fn place(&mut self, out: usize, on: u64, mut x: DVec3, mut rad: DVec3) -> bool {
        for i in bits(on & self.planes.axis) {
            let p = &self.planes.items[i];
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
    pub(super) fn store(&mut self, out: usize, x: DVec3, rad: DVec3) {
        self.verts.pos[out] = x;
        self.verts.rad[out] = rad;
        self.verts.is_point[out] = 0;
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
    pub(super) fn structured_crossing(&self, common: u64, k: usize) -> Option<(DVec3, DVec3)> {
        let kp = &self.planes.items[k];
        let axis = kp.axis as usize;
        if kp.axis < 3 {
            let mut first_axis = None;
            for i in bits(common & self.planes.axis) {
                let p = &self.planes.items[i];
                if p.axis as usize != axis {
                    match first_axis {
                        None => first_axis = Some(i),
                        Some(f) if self.planes.items[f].axis != p.axis => {
                            // Three axis planes: an exact point.
                            let mut x = DVec3::ZERO;
                            for q in [kp, &self.planes.items[f], p] {
                                *coord_mut(&mut x, q.axis as usize) = q.value;
                            }
                            return Some((x, DVec3::ZERO));
                        }
                        Some(_) => {}
                    }
                }
            }
            let general = common & !self.planes.axis;
            if let (Some(f), true) = (first_axis, general != 0) {
                return self.crossing_on_plane(general.trailing_zeros() as usize, [k, f]);
            }
        }
        // An input line: two planes of `common` sharing two input points, or
        // one point and the light's direction.
        for i in bits(common) {
            for j in bits(common & (u64::MAX << i << 1)) {
                let mut shared = bits((self.planes.items[i].through & self.planes.items[j].through) as u64);
                let Some(a) = shared.next() else { continue };
                let a_point = self.points[a];
                let (d, rounded) = match (shared.next(), self.planes.items[i].src, self.planes.items[j].src) {
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
    pub(super) fn crossing_on_plane(&self, g: usize, fixed: [usize; 2]) -> Option<(DVec3, DVec3)> {
        let p = &self.planes.items[g];
        let [k1, k2] = fixed.map(|f| (self.planes.items[f].axis as usize).min(2));
        let j = (3 - k1 - k2).min(2);
        let (n, en, anchor) = (p.n.to_array(), p.en.to_array(), p.anchor.to_array());
        let mut x = [0.0; 3];
        x[k1] = self.planes.items[fixed[0]].value;
        x[k2] = self.planes.items[fixed[1]].value;
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
    pub(super) fn certify_vertex(guess: DVec3, planes: [&FloatPlane; 3]) -> Option<(DVec3, DVec3)> {
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
    pub(super) fn cut(&mut self, k: usize, inside: VertexSet, outside: VertexSet) -> bool {
        let old_n = self.verts.len;
        let bit = 1u64 << k;
        let mut on_k = 0;
        // NOTE: 2 ≤ old_n ≤ 64 (a vertex on each side), so the shift is in range.
        for v in bits(u64::MAX >> (64 - old_n) & !(inside | outside)) {
            self.verts.on[v] |= bit;
            on_k += 1;
        }
        let mut n_new = old_n;
        // An outside vertex's inside neighbours: those sharing two of its
        // planes (one, in a polygon, whose flat planes are left out).
        // NOTE: tested pair by pair: a body has few vertices, and per-plane
        // vertex sets cost a loop over every inside vertex's planes.
        for w in bits(outside) {
            let on_w = self.verts.on[w] & !self.flat;
            let mut near = match self.dim {
                3 => {
                    let mut near = 0;
                    for u in bits(inside) {
                        near |= (two_or_more(self.verts.on[u] & on_w) as u64) << u;
                    }
                    near
                }
                2 => {
                    let mut near = 0;
                    for u in bits(inside) {
                        near |= ((self.verts.on[u] & on_w != 0) as u64) << u;
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
        self.verts.len = n;
        true
    }

    /// The certified sign of `det[n_a, n_b, n_c]` for three planes' exact
    /// normals.
    pub(super) fn normals_det_sign(a: &FloatPlane, b: &FloatPlane, c: &FloatPlane) -> Option<i8> {
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
}
