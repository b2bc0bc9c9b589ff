//! Edge crawl: how far shadow edges move on screen between frames beyond
//! what the camera's motion explains.
//!
//! The edge pixels of a frame (a pixel whose lit/shadowed answer differs
//! from one of its four neighbours') are kept as world points; in the next
//! frame each is projected to where the camera's motion takes it, and its
//! distance to the nearest edge pixel of that frame is measured (capped at
//! [`CRAWL_REACH_PX`]). Edges that stay on the world move exactly as the
//! projection says, up to the resampling of the pixel grid; the same
//! measure on the ray-traced truth is that resampling's share, so the
//! rendered figure's excess over it is the crawl.

use super::screen::Screen;
use glam::DVec3;
use shadowfocus_render::RenderOutput;

/// Largest displacement counted, pixels: an edge farther away than this
/// has vanished rather than moved.
pub const CRAWL_REACH_PX: i64 = 6;

/// One frame's edges under one answer (rendered or true).
struct Edges {
    mask: Vec<bool>,
    points: Vec<DVec3>,
}

impl Edges {
    fn new(out: &RenderOutput, lit: impl Fn(usize) -> bool) -> Edges {
        let (w, h) = (out.width as usize, out.height as usize);
        let geometry = |i: usize| out.world[i][3] != 0.0;
        let mut mask = vec![false; w * h];
        let mut points = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                if !geometry(i) {
                    continue;
                }
                let neighbours = [(x > 0).then(|| i - 1), (x + 1 < w).then(|| i + 1), (y > 0).then(|| i - w), (y + 1 < h).then(|| i + w)];
                if neighbours.into_iter().flatten().any(|j| geometry(j) && lit(j) != lit(i)) {
                    mask[i] = true;
                    let p = out.world[i];
                    points.push(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
                }
            }
        }
        Edges { mask, points }
    }

    /// Distance in pixels from (x, y) to the nearest edge pixel's centre,
    /// capped at the reach.
    fn distance(&self, out: &RenderOutput, x: f64, y: f64) -> f64 {
        let (w, h) = (out.width as i64, out.height as i64);
        let (cx, cy) = (x as i64, y as i64);
        let mut best = CRAWL_REACH_PX as f64;
        for py in (cy - CRAWL_REACH_PX).max(0)..=(cy + CRAWL_REACH_PX).min(h - 1) {
            for px in (cx - CRAWL_REACH_PX).max(0)..=(cx + CRAWL_REACH_PX).min(w - 1) {
                if self.mask[(py * w + px) as usize] {
                    best = best.min((px as f64 + 0.5 - x).hypot(py as f64 + 0.5 - y));
                }
            }
        }
        best
    }
}

/// Mean displacement of the last frame's edges in this frame.
#[derive(Default)]
struct Track {
    last: Option<Edges>,
    sum: f64,
    count: u64,
}

impl Track {
    fn frame(&mut self, out: &RenderOutput, screen: &Screen, edges: Edges) {
        if let Some(last) = &self.last {
            for &p in &last.points {
                if let (Some(_), Some((x, y))) = (screen.sees(out, p), screen.project(p)) {
                    self.sum += edges.distance(out, x, y);
                    self.count += 1;
                }
            }
        }
        self.last = Some(edges);
    }

    fn mean(&self) -> f64 {
        if self.count == 0 {
            f64::NAN
        } else {
            self.sum / self.count as f64
        }
    }
}

/// Edge displacement of the rendered shadows and of the ray-traced truth.
#[derive(Default)]
pub struct Crawl {
    rendered: Track,
    truth: Track,
}

impl Crawl {
    pub fn frame(&mut self, out: &RenderOutput, screen: &Screen) {
        self.rendered.frame(out, screen, Edges::new(out, |i| out.shadow[i] >= 0.5));
        if let Some(t) = &out.truth {
            self.truth.frame(out, screen, Edges::new(out, |i| t[i].is_lit()));
        }
    }

    /// Mean displacement of rendered edges, pixels.
    pub fn rendered_px(&self) -> f64 {
        self.rendered.mean()
    }

    /// The same for the true edges: what resampling alone gives.
    pub fn truth_px(&self) -> f64 {
        self.truth.mean()
    }
}
