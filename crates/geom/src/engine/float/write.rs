//! Writing the clipped body out: rounded vertices within the output
//! tolerance (or placed exactly), faces as proven counter-clockwise cycles.

use super::{bits, decide, two_or_more, CertifiedClipper, VertexSet, CAP_V, MAX_FAST_PLANES};
use crate::arith::fixed::{meet, Meeting};
use crate::arith::floor::{BOUND_SLACK as SLACK, UNDERFLOW_FLOOR as FLOOR, UNIT_ROUNDOFF as U};
use crate::arith::number::{abs_cross, Exact};
use crate::arith::plane::intersect3;
use crate::body::Body;
use crate::engine::exact::ROUNDING_ULPS;
use crate::limits::MAX_FACE_INDICES;
use glam::DVec3;

impl CertifiedClipper {
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
        // per plane; see BENCHMARKS.md for the per-body counts).
        let np = self.planes.len;
        let members = &mut self.scratch.plane_members[..np];
        members.fill(0);
        let mut count = [0u8; MAX_FAST_PLANES];
        for v in 0..self.verts.len {
            for p in bits(self.verts.on[v]) {
                members[p] |= 1 << v;
                count[p] += 1;
            }
        }
        // NOTE: two vertices of a solid span an edge exactly when they share
        // two planes (see `cut`); found once per vertex here, each face's
        // chaining is then one set operation per step.
        for v in 0..self.verts.len {
            let (mut once, mut twice): (VertexSet, VertexSet) = (0, 0);
            for p in bits(self.verts.on[v]) {
                twice |= once & self.scratch.plane_members[p];
                once |= self.scratch.plane_members[p];
            }
            self.scratch.neighbours[v] = twice & !(1 << v);
        }
        out.clear();
        let (mut ni, mut nf) = (0, 0);
        self.scratch.directed[..self.verts.len].fill(0);
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
                let mut on_p = bits(self.scratch.plane_members[p]);
                for slot in &mut out.idx[ni..ni + 3] {
                    *slot = on_p.next().unwrap_or(0) as u16;
                }
            } else if self.face_cycle(self.scratch.plane_members[p], m, &mut out.idx[ni..ni + m]).is_none() {
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
            out.face_planes[nf] = self.planes.items[p].approximate();
            if !self.record_edges(&out.idx[ni - m..ni]) {
                return false;
            }
            nf += 1;
        }
        // Euler's formula for a closed convex surface: every edge is in two
        // faces, V − E + F = 2.
        if ni % 2 != 0 || self.verts.len + nf != ni / 2 + 2 {
            out.clear();
            return false;
        }
        for v in 0..self.verts.len {
            let Some(x) = self.output_vertex(v) else {
                out.clear();
                return false;
            };
            out.verts[v] = x;
        }
        out.dim = 3;
        out.n_verts = self.verts.len;
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
    pub(super) fn output_vertex(&mut self, v: usize) -> Option<DVec3> {
        let (x, r) = (self.verts.pos[v], self.verts.rad[v]);
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
    pub(super) fn exact_vertex(&self, v: usize) -> Option<DVec3> {
        let mut on = [0usize; MAX_FAST_PLANES];
        let mut n = 0;
        for p in bits(self.verts.on[v]) {
            on[n] = p;
            n += 1;
        }
        let src = |i: usize| &self.planes.items[on[i]].src;
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
    pub(super) fn write_flat(&mut self, out: &mut Body) -> bool {
        out.clear();
        let n = self.verts.len;
        if self.dim == 2 {
            if !(3..=MAX_FACE_INDICES).contains(&n) {
                return false;
            }
            // Adjacent vertices share a plane besides the flat ones.
            let edges = !self.flat;
            let members = &mut self.scratch.plane_members[..self.planes.len];
            members.fill(0);
            for v in 0..n {
                for p in bits(self.verts.on[v] & edges) {
                    members[p] |= 1 << v;
                }
            }
            for v in 0..n {
                let near = bits(self.verts.on[v] & edges).fold(0, |near, p| near | self.scratch.plane_members[p]);
                self.scratch.neighbours[v] = near & !(1 << v);
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
            out.face_planes[0] = self.planes.items[self.support].approximate();
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
    pub(super) fn area_orientation(&self, p: usize, cycle: &[u16]) -> Option<bool> {
        // NOTE: fan terms of a convex polygon all point one way, so `A` has no
        // cancellation. A difference d = x_k − x_0 is off by the two radii and
        // its rounding; a cross product of perturbed vectors by
        // |δa|×|b| + |a|×|δb| + |δa|×|δb|, its own rounding by 2u of |a|×|b|,
        // and the running sum by (terms)·u of the same. The plane's own normal
        // is not used: it may be known less well than the polygon.
        let (x0, r0) = (self.verts.pos[cycle[0] as usize], self.verts.rad[cycle[0] as usize]);
        let edge = |v: usize| {
            let d = self.verts.pos[v] - x0;
            (d, self.verts.rad[v] + r0 + d.abs() * U)
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
        (0..self.verts.len).filter(|&v| self.verts.on[v] & 1 << p == 0).find_map(|y| {
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
    pub(super) fn face_cycle(&self, face: VertexSet, m: usize, cycle: &mut [u16]) -> Option<()> {
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
            let near = self.scratch.neighbours[first] & face;
            let (a, rest) = (near.trailing_zeros() as usize, near & near.wrapping_sub(1));
            let opposite = face & !near & !(1 << first);
            if !two_or_more(near)
                || two_or_more(rest)
                || self.scratch.neighbours[opposite.trailing_zeros() as usize & (CAP_V - 1)] & face != near
            {
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
            let near = self.scratch.neighbours[cur] & face & !(1 << prev);
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
        if self.scratch.neighbours[cur] & 1 << first == 0 {
            return None;
        }
        Some(())
    }

    /// Whether a face's chained cycle must be reversed, read off a face
    /// already written across one of its edges: consistently oriented faces
    /// run along a shared edge in opposite directions. `None` when no
    /// written face shares an edge.
    pub(super) fn reversed_by_neighbour(&self, cycle: &[u16]) -> Option<bool> {
        let slot = |v: u16| v as usize & (CAP_V - 1);
        let mut a = slot(cycle[cycle.len() - 1]);
        for &b in cycle {
            let b = slot(b);
            if self.scratch.directed[a] & 1 << b != 0 {
                return Some(true);
            }
            if self.scratch.directed[b] & 1 << a != 0 {
                return Some(false);
            }
            a = b;
        }
        None
    }

    /// Records a written face's directed edges; false when a face written
    /// before runs along one of them the same way (the faces are then not
    /// consistently oriented: broken incidences).
    pub(super) fn record_edges(&mut self, cycle: &[u16]) -> bool {
        let slot = |v: u16| v as usize & (CAP_V - 1);
        let mut a = slot(cycle[cycle.len() - 1]);
        let mut repeated = 0;
        for &b in cycle {
            let b = slot(b);
            repeated |= self.scratch.directed[a] & 1 << b;
            self.scratch.directed[a] |= 1 << b;
            a = b;
        }
        repeated == 0
    }

    /// Whether the chained cycle of plane `p`'s face must be reversed to run
    /// counter-clockwise from outside, proven from the planes' normals or the
    /// face's area vector.
    /// `others`: the planes that can hold an edge (all but `p` for a solid's
    /// face, all but the flat planes for a polygon).
    pub(super) fn reversed_by_geometry(&self, p: usize, others: u64, cycle: &[u16]) -> Option<bool> {
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
                let (to_a, to_b) = (self.verts.on[v] & self.verts.on[a] & others, self.verts.on[v] & self.verts.on[b] & others);
                bits(to_a).find_map(|i| {
                    bits(to_b).find_map(|j| Self::normals_det_sign(&self.planes.items[p], &self.planes.items[i], &self.planes.items[j]))
                })
            })
            .or_else(|| self.area_orientation(p, &cycle[..m]).map(|ccw| if ccw { -1 } else { 1 }))?;
        Some(decided > 0)
    }
}
