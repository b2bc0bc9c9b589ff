//! Continuity: sweeping the light direction through the view direction,
//! the image plane and behind the camera changes every method's maps
//! continuously, without NaN — for the continuous parameterisation
//! (`MapOrientation::ViewAligned`, `warp_guard` off). The default
//! least-area orientation and the warp guard trade that for texels: the
//! rectangle of least area and the guard's choice can switch in one step.
//!
//! The measure is the map itself: normalised coordinates `(x/w, y/w,
//! depth)` of fixed points of the view frustum (depth in the "less"
//! orientation, so that PSM's switch to the greater test at the image plane
//! compares like with like). A step may change them by a bounded amount,
//! and refining the step around the largest changes must make the change
//! shrink — a jump would stay as large however fine the step.

mod common;

use common::*;
use glam::DVec3;
use shadowfocus_focus::*;
use shadowfocus_geom::{Aabb, Camera, Light};

struct Sweep {
    cam: Camera,
    scene: Aabb,
    g: DVec3,
    settings: FocusSettings,
    points: Vec<(usize, DVec3)>,
}

impl Sweep {
    fn new(cam: Camera, g: DVec3, settings: FocusSettings) -> Sweep {
        let corners = cam.corners().unwrap();
        let (mut lo, mut hi) = (corners[0], corners[0]);
        for c in corners {
            lo = lo.min(c);
            hi = hi.max(c);
        }
        let pad = (hi - lo) * 0.5;
        let scene = Aabb::new(lo - pad, hi + pad).unwrap();
        let mut s = Sweep { cam, scene, g, settings, points: Vec::new() };
        // Fixed points inside the view frustum, tagged with their split.
        let mut out = FocusResult::new();
        s.fit(0.3, &mut out);
        let d = out.split_depths().to_vec();
        let b = cam.basis().unwrap();
        let t = (0.5 * cam.fovy).tan();
        for k in 0..40 {
            let (fx, fy) = (((k * 7) % 11) as f64 / 10.0 * 1.6 - 0.8, ((k * 5) % 13) as f64 / 12.0 * 1.6 - 0.8);
            let z = cam.near + (cam.far - cam.near) * ((k as f64 + 0.5) / 40.0).powi(2);
            let p = cam.eye + b.forward * z + b.right * (fx * z * t * cam.aspect) + b.up * (fy * z * t);
            let i = (0..d.len() - 1).find(|&i| d[i] < z && z < d[i + 1]);
            if let Some(i) = i {
                s.points.push((i, p));
            }
        }
        s
    }

    fn light(&self, theta: f64) -> Light {
        let f = self.cam.basis().unwrap().forward;
        Light::directional(f * theta.cos() + self.g * theta.sin()).unwrap()
    }

    fn fit(&self, theta: f64, out: &mut FocusResult) {
        fit(&self.cam, &self.light(theta), &self.scene, &self.settings, out).unwrap();
    }

    /// Normalised coordinates of the fixed points at angle θ.
    fn state(&self, theta: f64, out: &mut FocusResult) -> Vec<DVec3> {
        self.fit(theta, out);
        self.points
            .iter()
            .map(|(i, p)| {
                let map = out.maps().iter().find(|m| m.split == *i).unwrap();
                assert!(map.is_active(), "split {i} empty at θ = {theta}");
                let q = ndc(map, *p);
                assert!(q.is_finite(), "NaN/inf at θ = {theta}: {q}");
                q
            })
            .collect()
    }

    fn change(&self, a: f64, b: f64, out: &mut FocusResult) -> f64 {
        let (sa, sb) = (self.state(a, out), self.state(b, out));
        sa.iter().zip(sb.iter()).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f64::max)
    }
}

/// Largest allowed change of a normalised map coordinate per 0.5° step.
/// The maps must turn by 180° about the light as it passes through the view
/// direction (the projected view direction flips); the blend of the image
/// orientation spreads that over the ±30° cone around the view axis
/// (≈ 3 rad of map rotation per rad of light), and the warps magnify it near
/// the eye. PSM is steepest where the transformed light sits just beyond
/// the far face's edge (its shadow frustum is then ~180° wide).
fn bound(method: Method) -> f64 {
    match method {
        Method::Uniform => 0.2,
        Method::Lispsm => 0.4,
        Method::Tsm => 1.0,
        Method::Psm => 1.6,
        Method::Auto => panic!("auto switches between the methods where their predictions cross: it is not continuous"),
    }
}

fn run(method: Method, splits: usize, g_is_up: bool) {
    let cam = Camera {
        eye: DVec3::new(1.0, 3.0, 5.0),
        forward: DVec3::new(0.2, -0.15, -1.0),
        up: DVec3::Y,
        fovy: 1.0,
        aspect: 1.5,
        near: 0.5,
        far: 60.0,
    };
    let b = cam.basis().unwrap();
    let settings = FocusSettings {
        method,
        splits: SplitSettings { count: splits, ..Default::default() },
        orientation: MapOrientation::ViewAligned,
        warp_guard: false,
        ..Default::default()
    };
    let sw = Sweep::new(cam, if g_is_up { b.up } else { b.right }, settings);
    let mut out = FocusResult::new();
    let n = 720;
    let step = std::f64::consts::TAU / n as f64;
    let mut prev = sw.state(0.0, &mut out);
    let mut changes = Vec::new();
    for k in 1..=n {
        let th = k as f64 * step;
        let cur = sw.state(th, &mut out);
        let c = prev.iter().zip(cur.iter()).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f64::max);
        changes.push((c, th - step));
        prev = cur;
    }
    changes.sort_by(|a, b| b.0.total_cmp(&a.0));
    let (worst, at) = changes[0];
    eprintln!(
        "{method:?} splits {splits} {}: largest change per 0.5° step {worst:.4} at θ = {at:.4}",
        if g_is_up { "view/up" } else { "view/right" }
    );
    assert!(worst < bound(method), "{method:?}: change {worst} per step at θ = {at}");
    // Refinement around the largest changes: a jump survives bisection.
    for &(c, a) in changes.iter().take(3) {
        let (mut lo, mut hi) = (a, a + step);
        let mut cc = c;
        for _ in 0..10 {
            let mid = 0.5 * (lo + hi);
            let (c1, c2) = (sw.change(lo, mid, &mut out), sw.change(mid, hi, &mut out));
            if c1 >= c2 {
                hi = mid;
                cc = c1;
            } else {
                lo = mid;
                cc = c2;
            }
        }
        assert!(cc <= 0.05 * c.max(1e-9) || cc < 1e-6, "{method:?}: jump of {cc} at θ ≈ {lo} (step change {c})");
    }
}

#[test]
fn uniform_sweeps() {
    for up in [true, false] {
        run(Method::Uniform, 1, up);
        run(Method::Uniform, 3, up);
    }
}

#[test]
fn psm_sweeps() {
    for up in [true, false] {
        run(Method::Psm, 1, up);
        run(Method::Psm, 3, up);
    }
}

#[test]
fn lispsm_sweeps() {
    for up in [true, false] {
        run(Method::Lispsm, 1, up);
        run(Method::Lispsm, 3, up);
    }
}

#[test]
fn tsm_sweeps() {
    for up in [true, false] {
        run(Method::Tsm, 1, up);
        run(Method::Tsm, 3, up);
    }
}
