//! Structured fuzz inputs shared by the targets.
//!
//! Raw `f64` bit patterns alone almost never make a valid frustum, so every
//! number is drawn from a mix: arbitrary bits (NaN, infinities, subnormals,
//! huge values), small integers, dyadic values `m·2^e`, and a table of
//! special values. Frusta come as arbitrary corners, as cameras, or as exact
//! dyadic pyramids (always valid unless their parameters are bad), so the
//! fuzzer spends its time inside the engine rather than in input checks.

use arbitrary::Arbitrary;
use shadowfocus_geom::{Aabb, Camera, DVec3, Frustum, GeomError, Light, Plane};

/// A number: arbitrary bits, or something more likely to be meaningful.
#[derive(Arbitrary, Clone, Copy, Debug)]
pub enum Num {
    Bits(u64),
    Int(i16),
    Dyadic(i32, i8),
    Special(u8),
}

const SPECIAL: [f64; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    -f64::MAX,
    f64::MIN_POSITIVE,
    5e-324,
    1e12,
    -1e12,
    1e-12,
    f64::EPSILON,
];

impl Num {
    pub fn get(self) -> f64 {
        match self {
            Num::Bits(b) => f64::from_bits(b),
            Num::Int(i) => i as f64,
            Num::Dyadic(m, e) => m as f64 * 2f64.powi(e as i32 % 80),
            Num::Special(k) => SPECIAL[k as usize % SPECIAL.len()],
        }
    }
}

pub type V3 = [Num; 3];

pub fn v3(v: &V3) -> DVec3 {
    DVec3::new(v[0].get(), v[1].get(), v[2].get())
}

/// A frustum description.
#[derive(Arbitrary, Clone, Debug)]
pub enum FrustumIn {
    Corners(Box<[V3; 8]>),
    Camera {
        eye: V3,
        forward: V3,
        up: V3,
        fovy_deg: Num,
        aspect: Num,
        near: Num,
        far: Num,
    },
    /// An exact pyramid frustum: apex `eye`, depths `2^near_exp` and
    /// `2^near_exp · 2^(far_exp+1)`, half-extents `a/16`, `b/16` per unit
    /// depth, axes permuted and flipped by `map`; optionally one corner
    /// moved by a small offset (creased or broken sides).
    Dyadic {
        eye: [i32; 3],
        near_exp: i8,
        far_exp: u8,
        a: u8,
        b: u8,
        map: u8,
        jitter: Option<(u8, [i8; 3], i8)>,
    },
}

impl FrustumIn {
    pub fn build(&self) -> Result<Frustum, GeomError> {
        match self {
            FrustumIn::Corners(c) => Frustum::from_corners(c.map(|p| v3(&p))),
            FrustumIn::Camera { eye, forward, up, fovy_deg, aspect, near, far } => Frustum::from_camera(&Camera {
                eye: v3(eye),
                forward: v3(forward),
                up: v3(up),
                fovy: fovy_deg.get().to_radians(),
                aspect: aspect.get(),
                near: near.get(),
                far: far.get(),
            }),
            FrustumIn::Dyadic { .. } => Frustum::from_corners(self.dyadic_corners().expect("dyadic variant")),
        }
    }

    /// The apex of a dyadic frustum.
    pub fn apex(&self) -> Option<DVec3> {
        match self {
            FrustumIn::Dyadic { eye, .. } => Some(DVec3::new(eye[0] as f64, eye[1] as f64, eye[2] as f64)),
            FrustumIn::Camera { eye, .. } => Some(v3(eye)),
            FrustumIn::Corners(_) => None,
        }
    }

    fn dyadic_corners(&self) -> Option<[DVec3; 8]> {
        let FrustumIn::Dyadic { eye, near_exp, far_exp, a, b, map, jitter } = self else { return None };
        let eye = DVec3::new(eye[0] as f64, eye[1] as f64, eye[2] as f64);
        let near = 2f64.powi(*near_exp as i32 % 40);
        let far = near * 2f64.powi((*far_exp as i32 % 30) + 1);
        let (a, b) = (*a as f64 / 16.0, *b as f64 / 16.0);
        const PERMS: [[usize; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        let perm = PERMS[(*map as usize) % 6];
        let flip = [map & 8 != 0, map & 16 != 0, map & 32 != 0];
        let apply = |p: DVec3| {
            let mut q = DVec3::ZERO;
            for i in 0..3 {
                q[i] = if flip[i] { -p[perm[i]] } else { p[perm[i]] };
            }
            q
        };
        let mut c = [DVec3::ZERO; 8];
        for (k, t) in [near, far].into_iter().enumerate() {
            for (i, (sx, sy)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
                c[4 * k + i] = eye + apply(DVec3::new(sx * a * t, sy * b * t, -t));
            }
        }
        if let Some((i, d, e)) = jitter {
            let s = 2f64.powi(*e as i32 % 60);
            c[*i as usize % 8] += DVec3::new(d[0] as f64, d[1] as f64, d[2] as f64) * s;
        }
        Some(c)
    }
}

/// A light description; the `Raw*` forms bypass the checked constructors.
#[derive(Arbitrary, Clone, Debug)]
pub enum LightIn {
    Directional(V3),
    /// Along a difference of two view corners (edges, diagonals).
    AlongCorners(u8, u8, bool),
    Point(V3),
    AtCorner(u8),
    AtApex,
    Spot {
        position: V3,
        frustum: FrustumIn,
    },
    /// A spot light whose frustum's apex is the light position.
    SpotAtApex(FrustumIn),
    RawDirectional(V3),
    RawPoint(V3),
}

impl LightIn {
    pub fn build(&self, view: &Frustum, view_in: &FrustumIn) -> Result<Light, GeomError> {
        let c = view.corners();
        match self {
            LightIn::Directional(d) => Light::directional(v3(d)),
            LightIn::AlongCorners(i, j, s) => {
                let d = c[*i as usize % 8] - c[*j as usize % 8];
                Light::directional(if *s { d } else { -d })
            }
            LightIn::Point(p) => Light::point(v3(p)),
            LightIn::AtCorner(i) => Light::point(c[*i as usize % 8]),
            LightIn::AtApex => Light::point(view_in.apex().unwrap_or(c[0])),
            LightIn::Spot { position, frustum } => Light::spot(v3(position), frustum.build()?),
            LightIn::SpotAtApex(f) => {
                let frustum = f.build()?;
                Light::spot(f.apex().unwrap_or(frustum.corners()[0]), frustum)
            }
            LightIn::RawDirectional(d) => Ok(Light::Directional { direction: v3(d) }),
            LightIn::RawPoint(p) => Ok(Light::Point { position: v3(p) }),
        }
    }
}

/// A scene box description; `Raw` bypasses `Aabb::new`.
#[derive(Arbitrary, Clone, Debug)]
pub enum SceneIn {
    New {
        min: V3,
        max: V3,
    },
    Raw {
        min: V3,
        max: V3,
    },
    /// The box around two corners of V (touching V, often flat).
    Corners(u8, u8),
    /// The box around V, grown by `pad` times its size, flattened on the
    /// axes set in `flat` (through V's centre).
    AroundView {
        pad: Num,
        flat: u8,
    },
}

impl SceneIn {
    pub fn build(&self, view: &Frustum) -> Result<Aabb, GeomError> {
        let c = view.corners();
        match self {
            SceneIn::New { min, max } => Aabb::new(v3(min), v3(max)),
            SceneIn::Raw { min, max } => Ok(Aabb { min: v3(min), max: v3(max) }),
            SceneIn::Corners(i, j) => Ok(Aabb::around(&[c[*i as usize % 8], c[*j as usize % 8]]).expect("two points")),
            SceneIn::AroundView { pad, flat } => {
                let b = Aabb::around(c).expect("eight points");
                let e = (b.max - b.min) * pad.get();
                let (mut min, mut max) = (b.min - e, b.max + e);
                let mid = (b.min + b.max) * 0.5;
                for k in 0..3 {
                    if flat & (1 << k) != 0 {
                        min[k] = mid[k];
                        max[k] = mid[k];
                    }
                }
                Aabb::new(min, max)
            }
        }
    }
}

/// A halfspace description.
#[derive(Arbitrary, Clone, Debug)]
pub enum PlaneIn {
    Coefficients { normal: V3, offset: Num },
    Points([V3; 3]),
    PointsDirection { p: V3, q: V3, direction: V3 },
    Axis { axis: u8, upper: bool, value: Num },
}

impl PlaneIn {
    pub fn build(&self) -> Plane {
        match self {
            PlaneIn::Coefficients { normal, offset } => Plane::Coefficients { normal: v3(normal), offset: offset.get() },
            PlaneIn::Points(p) => Plane::Points(p.map(|x| v3(&x))),
            PlaneIn::PointsDirection { p, q, direction } => Plane::PointsDirection { p: v3(p), q: v3(q), direction: v3(direction) },
            // Axis values ≥ 3 are not finite planes; they must be rejected.
            PlaneIn::Axis { axis, upper, value } => Plane::Axis { axis: axis % 4, upper: *upper, value: value.get() },
        }
    }
}

/// Largest magnitude among finite positional inputs.
pub fn magnitude(points: &[DVec3]) -> f64 {
    points.iter().filter(|p| p.is_finite()).map(|p| p.abs().max_element()).fold(0.0, f64::max)
}

/// What the JSON-lines targets check of a command's output for UTF-8
/// `input`: one JSON result with an `id` per non-blank input line, `check`
/// on every result that is not an error, and as many error lines as the
/// command reported failures.
pub fn check_result_lines(input: &str, output: Vec<u8>, failed: usize, check: impl Fn(&serde_json::Value, &str)) {
    let expected = input.lines().filter(|l| !l.trim().is_empty()).count();
    let out = String::from_utf8(output).expect("output is UTF-8");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), expected, "one result per case line");
    let mut errors = 0;
    for l in &lines {
        let v: serde_json::Value = serde_json::from_str(l).expect("each result is JSON");
        assert!(v.get("id").is_some(), "result without id: {l}");
        if v.get("error").is_some() {
            errors += 1;
        } else {
            check(&v, l);
        }
    }
    assert_eq!(errors, failed, "the failure count matches the error lines");
}
