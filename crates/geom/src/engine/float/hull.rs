//! The start of the fast path: `hull(V ∪ {l})` from the exact beneath–beyond
//! signs, closed by a plane that holds `S` for a directional light.

use super::planes::{line_crossing, FloatPlane};
use super::{bits, two_or_more, CertifiedClipper, Step, CAP_V, FOLD_CACHE, MAX_FAST_PLANES, NONE};
use crate::input::aabb::Aabb;
use crate::input::frustum::{corner_bits, Apex, Frustum, HullOutline, Origin};
use glam::DVec3;

impl CertifiedClipper {
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
        self.planes.len = 0;
        self.verts.len = 0;
        self.planes.axis = 0;
        self.cuts = 0;
        self.cleared = 0;
        self.exact_vertices = 0;
        self.closed_by_scene_face = None;
        self.dim = 3;
        self.flat = 0;
        self.planes.fold_keys = [(NONE, NONE); FOLD_CACHE];
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
            self.planes.items[p] = match origin {
                Origin::Face(f) => FloatPlane::of_face(view, f as usize, through),
                Origin::Horizon(..) => FloatPlane::new(view.hull_plane(apex, origin), through),
            };
            self.planes.partners[p] = 0;
            horizon |= u64::from(matches!(origin, Origin::Horizon(..))) << p;
            for c in bits(u64::from(through)) {
                planes_of[c] |= 1 << p;
            }
        }
        self.planes.len = hull.len();
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
    pub(super) fn reset_to_merged_hull(&mut self, view: &Frustum, apex: Apex, hull: &HullOutline, scene: &Aabb) -> Step {
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
            self.planes.items[np] = match origin {
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
            self.planes.partners[np] = 0;
            np += 1;
        }
        self.planes.len = np;
        // Incidences from the planes' defining points; per kept corner, its
        // planes that contain the light's direction.
        let (mut planes_of, mut along) = ([0u64; 8], [0u64; 8]);
        for p in 0..np {
            let bit = 1u64 << p;
            for c in bits(u64::from(self.planes.items[p].through) & u64::from(kept)) {
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
    pub(super) fn cast_shadows(&mut self, toward: DVec3, scene: &Aabb, corners: &[DVec3; 8], rays: &[u64; 8]) -> Step {
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
    pub(super) fn push_input_vertex(&mut self, i: usize, on: u64) {
        let v = self.verts.len;
        self.verts.pos[v] = self.points[i];
        self.verts.rad[v] = DVec3::ZERO;
        self.verts.on[v] = on;
        self.verts.is_point[v] = 1 << i;
        self.verts.len += 1;
    }

    /// An axis plane that holds S and every frustum corner strictly inside,
    /// facing the light on the axis the light crosses most steeply; appended
    /// to the planes, its index returned.
    pub(super) fn closing_plane(&mut self, toward: DVec3, scene: &Aabb, corners: &[DVec3; 8]) -> Option<usize> {
        let k = self.planes.len;
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
        self.planes.items[k] = FloatPlane::axis(axis as u8, upper, value);
        self.planes.axis |= 1 << k;
        self.planes.partners[k] = 0;
        self.planes.len += 1;
        Some(k)
    }

    /// Appends the vertex where the ray from corner `c` toward the light
    /// meets the closing plane `cap`, on the planes `on`.
    #[inline(always)]
    pub(super) fn push_shadow(&mut self, c: usize, on: u64, cap: usize, toward: DVec3) -> Option<u8> {
        if self.verts.len >= CAP_V {
            return None;
        }
        // On the ray from the corner toward the light (both exact).
        let (pos, rad) = line_crossing(self.points[c], toward, false, &self.planes.items[cap])?;
        let v = self.verts.len;
        self.verts.pos[v] = pos;
        self.verts.rad[v] = rad;
        self.verts.on[v] = on;
        self.verts.is_point[v] = 0;
        self.verts.len += 1;
        Some(v as u8)
    }
}
