//! The ground of an open scene ([`crate::FocusSettings::ground`]): the one
//! face of the scene box, or the plane parallel to it at a level inside the
//! box, that stands for receivers in the predicted aliasing.
//!
//! Outdoors, the scene box is where the geometry ends: its floor is the
//! ground, its walls and top are the sky beyond the last building. Taken as
//! receivers, those walls misled every prediction that saw them. Over a
//! city, the box's side wall 630–860 m out, lit at 86°, predicted the two far
//! splits at 1.2 screen pixels per texel where the renderer measured 0.17
//! and 0.10 on the ground and the buildings there; the optimal planes evened
//! the near splits against it. Across a 700 m board, the far wall at the
//! board's edge predicted PSM 5.6× the aliasing it rendered on the board.
//!
//! A camera ray's receiver is then where it meets the ground (inside the
//! box's extent on the other two axes, seen from the open side); a ray over
//! it has none. Where the world stands on a slab (a board 6 m thick, a
//! ground block 2 m deep) the box's floor lies below the receivers, and for
//! an eye 1.7 m up a floor 2 m lower more than doubles every receiver's
//! distance below it: the level puts the ground where the slab's top is.
//!
//! Along one column of the image the ground a ray meets is a segment whose
//! ends (the ground's edge, the split's planes, the image's border) are
//! where a split's worst ground receiver lies, between the rays wherever
//! the ground is a strip of few rows: [`GroundRect::column_span`] finds them
//! in closed form.

use crate::settings::Ground;
use glam::DVec3;
use shadowfocus_geom::Aabb;

/// The ground in a box: the plane `x_axis = at` and its rectangle `[lo, hi]`
/// on the other two axes (`lo`, `hi` the box cut at the ground: its face on
/// the ground's side is the ground); `up` is `+1` where the open side (the
/// box's inside) lies toward greater coordinates along `axis`, else `−1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GroundRect {
    pub axis: usize,
    pub at: f64,
    pub up: f64,
    pub lo: DVec3,
    pub hi: DVec3,
}

/// A point of the ground seen along a camera ray: the ray's image height
/// `s` in the column (the ray is `column + s·up`, see
/// [`GroundRect::column_span`]), its view depth and the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct GroundPoint {
    pub s: f64,
    pub z: f64,
    pub p: DVec3,
}

impl GroundRect {
    /// The ground `g` in the box `b`: on the face `g.face`, or at
    /// `g.level`, taken into the box (the nearest of its faces, where it
    /// lies outside).
    pub fn of(g: Ground, b: &Aabb) -> GroundRect {
        let axis = g.face.axis();
        let (mut lo, mut hi) = (b.min, b.max);
        let level = |face: f64| g.level.map_or(face, |l| l.clamp(b.min[axis], b.max[axis]));
        let (at, up) = if g.face.is_max() {
            hi[axis] = level(b.max[axis]);
            (hi[axis], -1.0)
        } else {
            lo[axis] = level(b.min[axis]);
            (lo[axis], 1.0)
        };
        GroundRect { axis, at, up, lo, hi }
    }

    /// The face's number in `2 · axis + is_max` order ([`BoxFace::index`]).
    pub fn face_index(&self) -> usize {
        2 * self.axis + usize::from(self.up < 0.0)
    }

    /// The unit normal on the ground's open side.
    pub fn normal(&self) -> DVec3 {
        DVec3::AXES[self.axis] * self.up
    }

    /// The view depth where the ray `eye + z·d` (`d·forward = 1`) meets the
    /// ground in `[near, far]`, within its rectangle and from the open side;
    /// `None` where it does not.
    pub fn hit(&self, eye: DVec3, d: DVec3, near: f64, far: f64) -> Option<f64> {
        let (height, descent) = ((eye[self.axis] - self.at) * self.up, -d[self.axis] * self.up);
        if !(height > 0.0 && descent > 0.0) {
            return None;
        }
        let z = height / descent;
        let p = eye + d * z;
        let inside = self.others().all(|a| p[a] >= self.lo[a] && p[a] <= self.hi[a]);
        (z >= near && z <= far && inside).then_some(z)
    }

    /// The ends of the ground that the rays `column + s·up`, `s ∈ [−s_max,
    /// s_max]` (the camera's image column at `column`, `up` its image up
    /// vector at depth 1), meet in `[near, far]`: nearest first, `None`
    /// where they meet none.
    ///
    /// Along the column the ground point is `eye + z(s)·(column + s·up)`
    /// with `z(s) = h / δ(s)`, `h` the eye's height above the ground and
    /// `δ(s) = −(column + s·up)·n` the ray's descent (`n` the ground's
    /// normal). Every condition on the point — depth in `[near, far]`,
    /// inside the rectangle — multiplied by `δ(s) > 0` is affine in `s`, so
    /// the rays that meet the ground form one interval of `s`, found by
    /// intersecting half-lines; its ends give the points.
    pub fn column_span(&self, eye: DVec3, column: DVec3, up: DVec3, s_max: f64, near: f64, far: f64) -> Option<[GroundPoint; 2]> {
        let k = self.axis;
        let h = (eye[k] - self.at) * self.up;
        if !(h > 0.0) {
            return None;
        }
        // δ(s) = δ0 − s·δ1.
        let (d0, d1) = (-column[k] * self.up, up[k] * self.up);
        let mut span = Span { lo: -s_max, hi: s_max };
        // z ≥ near: h − near·δ(s) ≥ 0; z ≤ far: far·δ(s) − h ≥ 0 (which
        // makes δ positive).
        span.keep(h - near * d0, near * d1);
        span.keep(far * d0 - h, -far * d1);
        for a in self.others() {
            // lo_a ≤ eye_a + z·(column_a + s·up_a) ≤ hi_a, times δ(s):
            // h·(column_a + s·up_a) − (lo_a − eye_a)·δ(s) ≥ 0, and the
            // same with hi_a turned around.
            let (lo, hi) = (self.lo[a] - eye[a], self.hi[a] - eye[a]);
            span.keep(h * column[a] - lo * d0, h * up[a] + lo * d1);
            span.keep(hi * d0 - h * column[a], -hi * d1 - h * up[a]);
        }
        if !(span.lo <= span.hi) {
            return None;
        }
        let point = |s: f64| {
            let d = column + up * s;
            let z = h / (-d[k] * self.up);
            GroundPoint { s, z, p: eye + d * z }
        };
        let (a, b) = (point(span.lo), point(span.hi));
        (a.z.is_finite() && b.z.is_finite()).then_some(if a.z <= b.z { [a, b] } else { [b, a] })
    }

    /// The two axes of the ground's rectangle.
    fn others(&self) -> impl Iterator<Item = usize> {
        [(self.axis + 1) % 3, (self.axis + 2) % 3].into_iter()
    }
}

/// An interval of `s`, cut by half-lines `a + b·s ≥ 0`.
struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    fn keep(&mut self, a: f64, b: f64) {
        if b > 0.0 {
            self.lo = self.lo.max(-a / b);
        } else if b < 0.0 {
            self.hi = self.hi.min(-a / b);
        } else if !(a >= 0.0) {
            (self.lo, self.hi) = (1.0, -1.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::BoxFace;

    fn board() -> GroundRect {
        let b = Aabb::new(DVec3::new(-10.0, 0.0, -10.0), DVec3::new(10.0, 5.0, 10.0)).unwrap();
        GroundRect::of(BoxFace::MinY.into(), &b)
    }

    #[test]
    fn a_ray_meets_the_ground_inside_its_rectangle_from_above() {
        let g = board();
        let eye = DVec3::new(0.0, 2.0, -10.0);
        // Down at slope 1/4: the ground at depth 8.
        assert_eq!(g.hit(eye, DVec3::new(0.0, -0.25, 1.0), 0.1, 100.0), Some(8.0));
        // At slope 1/20 it would meet it at depth 40, beyond the board's edge.
        assert_eq!(g.hit(eye, DVec3::new(0.0, -0.05, 1.0), 0.1, 100.0), None);
        // Beyond far, or up into the sky: none.
        assert_eq!(g.hit(eye, DVec3::new(0.0, -0.25, 1.0), 0.1, 7.0), None);
        assert_eq!(g.hit(eye, DVec3::new(0.0, 0.25, 1.0), 0.1, 100.0), None);
        // From below the ground (its underside): none.
        assert_eq!(g.hit(DVec3::new(0.0, -2.0, -10.0), DVec3::new(0.0, 0.25, 1.0), 0.1, 100.0), None);
        // A ceiling as the ground (a world upside down): seen from below.
        let b = Aabb::new(DVec3::new(-10.0, 0.0, -10.0), DVec3::new(10.0, 5.0, 10.0)).unwrap();
        let g = GroundRect::of(BoxFace::MaxY.into(), &b);
        assert_eq!(g.normal(), DVec3::NEG_Y);
        assert_eq!(g.hit(DVec3::new(0.0, 3.0, -10.0), DVec3::new(0.0, 0.25, 1.0), 0.1, 100.0), Some(8.0));
    }

    #[test]
    fn a_level_cuts_the_box_at_the_ground() {
        let b = Aabb::new(DVec3::new(-10.0, -2.0, -10.0), DVec3::new(10.0, 5.0, 10.0)).unwrap();
        // A slab's top at y = 0: the ground and the rectangle's floor there.
        let g = GroundRect::of(Ground::at(BoxFace::MinY, 0.0), &b);
        assert_eq!((g.axis, g.at, g.up, g.lo.y, g.hi.y), (1, 0.0, 1.0, 0.0, 5.0));
        let eye = DVec3::new(0.0, 2.0, -10.0);
        assert_eq!(g.hit(eye, DVec3::new(0.0, -0.25, 1.0), 0.1, 100.0), Some(8.0));
        // At the face itself, the face's ground; outside the box, the
        // nearest face.
        assert_eq!(GroundRect::of(Ground::at(BoxFace::MinY, -2.0), &b), GroundRect::of(BoxFace::MinY.into(), &b));
        assert_eq!(GroundRect::of(Ground::at(BoxFace::MinY, -7.0), &b).at, -2.0);
        assert_eq!(GroundRect::of(Ground::at(BoxFace::MinY, 9.0), &b).at, 5.0);
        // A ceiling at y = 4 cuts the box's top.
        let g = GroundRect::of(Ground::at(BoxFace::MaxY, 4.0), &b);
        assert_eq!((g.at, g.up, g.lo.y, g.hi.y), (4.0, -1.0, -2.0, 4.0));
    }

    #[test]
    fn a_column_meets_the_ground_between_its_edge_and_the_image_border() {
        let g = board();
        let eye = DVec3::new(0.0, 2.0, -10.0);
        // The column straight ahead, image heights s ∈ [−1, 1]: the ray
        // (0, s, 1) descends for s < 0; it meets the ground at depth −2/s,
        // inside the board up to depth 20 (z = 10, its far edge): s = −0.1.
        let [near, far] = g.column_span(eye, DVec3::Z, DVec3::Y, 1.0, 0.1, 100.0).unwrap();
        assert_eq!((near.s, near.z), (-1.0, 2.0));
        assert!((far.s + 0.1).abs() < 1e-15 && (far.z - 20.0).abs() < 1e-12, "{far:?}");
        assert!((far.p - DVec3::new(0.0, 0.0, 10.0)).length() < 1e-12);
        // The far plane at 12 cuts it first; the near plane at 4 the other end.
        let [near, far] = g.column_span(eye, DVec3::Z, DVec3::Y, 1.0, 4.0, 12.0).unwrap();
        assert!((near.z - 4.0).abs() < 1e-12 && (far.z - 12.0).abs() < 1e-12, "{near:?} {far:?}");
        // Every sample on a ray meets the ground where the ray does.
        for t in [0.0, 0.3, 0.7, 1.0] {
            let s = near.s + (far.s - near.s) * t;
            let z = g.hit(eye, DVec3::Z + DVec3::Y * s, 0.1, 100.0).unwrap();
            assert!((z - (-2.0 / s)).abs() < 1e-9);
        }
        // A column aimed off the board's side, or an image above the
        // horizon: none.
        assert_eq!(g.column_span(eye, DVec3::new(3.0, 0.0, 1.0), DVec3::Y, 0.05, 0.1, 100.0), None);
        assert_eq!(g.column_span(eye, DVec3::new(0.0, 0.5, 1.0), DVec3::Y, 0.25, 0.1, 100.0), None);
    }

    /// Over random boxes, faces, eyes and columns, the span holds exactly
    /// the image heights whose rays `hit` the ground: every ray inside it
    /// does (but within rounding of its ends), none outside it.
    #[test]
    fn the_column_span_is_where_the_rays_hit_the_ground() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut rnd = |lo: f64, hi: f64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        };
        let (mut spans, mut rays) = (0, 0);
        for case in 0..400 {
            let scale = 10f64.powf(rnd(-2.0, 3.0));
            let lo = DVec3::new(rnd(-1.0, 0.0), rnd(-1.0, 0.0), rnd(-1.0, 0.0)) * scale;
            let b = Aabb::new(lo, lo + DVec3::new(rnd(0.1, 2.0), rnd(0.1, 2.0), rnd(0.1, 2.0)) * scale).unwrap();
            // A third of the grounds at a level inside the box.
            let face = BoxFace::ALL[case % 6];
            let ground = match case % 3 {
                1 => Ground::at(face, rnd(b.min[face.axis()], b.max[face.axis()])),
                _ => face.into(),
            };
            let g = GroundRect::of(ground, &b);
            let mut eye = DVec3::new(rnd(-1.5, 1.5), rnd(-1.5, 1.5), rnd(-1.5, 1.5)) * scale;
            let mut column = DVec3::new(rnd(-1.0, 1.0), rnd(-1.0, 1.0), rnd(-1.0, 1.0));
            if case % 3 != 0 {
                // Above the ground, looking down at it.
                for a in g.others() {
                    eye[a] = rnd(b.min[a], b.max[a]);
                }
                eye[g.axis] = g.at + g.up * rnd(0.01, 1.0) * scale;
                column[g.axis] = -g.up * rnd(0.05, 1.0);
            }
            let up = DVec3::new(rnd(-1.0, 1.0), rnd(-1.0, 1.0), rnd(-1.0, 1.0));
            let (s_max, near, far) = (rnd(0.1, 1.5), 0.01 * scale, rnd(0.5, 5.0) * scale);
            let span = g.column_span(eye, column, up, s_max, near, far);
            spans += usize::from(span.is_some());
            for k in 0..=200 {
                let s = -s_max + 2.0 * s_max * k as f64 / 200.0;
                let hit = g.hit(eye, column + up * s, near, far);
                let inside = span.is_some_and(|[a, b]| s >= a.s.min(b.s) && s <= a.s.max(b.s));
                let near_end = span.is_some_and(|[a, b]| (s - a.s).abs().min((s - b.s).abs()) < 1e-9 * s_max);
                assert!(hit.is_some() == inside || near_end, "case {case}, s {s}: hit {hit:?}, span {span:?}");
                rays += usize::from(hit.is_some());
            }
            if let Some(ends) = span {
                for e in ends {
                    let on = (e.p[g.axis] - g.at).abs() <= 1e-9 * scale;
                    assert!(on && e.z >= near * (1.0 - 1e-9) && e.z <= far * (1.0 + 1e-9), "case {case}: end {e:?}");
                }
            }
        }
        assert!(spans > 100 && rays > 10_000, "only {spans} spans and {rays} rays on the ground");
    }
}
