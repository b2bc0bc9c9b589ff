//! Flicker at fixed world points.
//!
//! The probes are visible receiver pixels of the first frame. Each frame
//! looks every probe's world point up in its own shadow maps
//! ([`RenderOutput::lit_at`], the main pass's nearest-texel test on the
//! CPU), wherever the frame sees the point. The light and the scene do not
//! move, so the true answer at a fixed point never changes: a point-frame
//! flickers when its answer differs from the one the point had in the last
//! frame that saw it. A map that moves by whole texels between frames keeps
//! every answer; one that moves by fractions of a texel changes answers
//! along shadow edges ("crawl") and inside thin shadows.
//!
//! Probes whose first-frame truth is the same over the 5×5 pixels around
//! them are "off edges"; the others are "near edges", where crawl shows.

use super::screen::Screen;
use glam::DVec3;
use shadowfocus_render::{RenderOutput, Visibility};

/// A fixed world point and its answer in the last frame that saw it.
struct Probe {
    p: DVec3,
    n: DVec3,
    near_edge: bool,
    last: Option<bool>,
}

/// Point-frames compared and changed, off and near edges.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlickerCounts {
    pub compared: u64,
    pub flickered: u64,
    pub compared_near_edges: u64,
    pub flickered_near_edges: u64,
}

impl FlickerCounts {
    pub fn rate(&self) -> f64 {
        ratio(self.flickered, self.compared)
    }

    pub fn rate_near_edges(&self) -> f64 {
        ratio(self.flickered_near_edges, self.compared_near_edges)
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 {
        f64::NAN
    } else {
        a as f64 / b as f64
    }
}

pub struct Flicker {
    probes: Vec<Probe>,
    pub counts: FlickerCounts,
}

impl Flicker {
    /// Every `stride`-th receiver pixel of the first frame as a probe, but
    /// those whose truth is back-facing or outside a spot's pyramid: no
    /// shadow shows there, whatever the map answers (the mismatch count
    /// leaves them out for the same reason). On the chessboard's spot orbit
    /// a wall in the light's own plane (the light grazes it at 90°) held
    /// such probes, and the map's answers there flipped frame to frame.
    pub fn new(first: &RenderOutput, truth: &[Visibility], stride: usize) -> Flicker {
        let (w, h) = (first.width as i64, first.height as i64);
        let lit = |x: i64, y: i64| truth[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize].is_lit();
        let mut probes = Vec::new();
        for (i, px) in first.world.iter().enumerate().step_by(stride.max(1)) {
            if px[3] != 1.0 || !truth[i].shows_shadow() {
                continue;
            }
            let (x, y) = (i as i64 % w, i as i64 / w);
            let centre = lit(x, y);
            let near_edge = (-2..=2).any(|dy| (-2..=2).any(|dx| lit(x + dx, y + dy) != centre));
            let n = first.normal[i];
            probes.push(Probe {
                p: DVec3::new(px[0] as f64, px[1] as f64, px[2] as f64),
                n: DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64),
                near_edge,
                last: None,
            });
        }
        Flicker { probes, counts: FlickerCounts::default() }
    }

    /// Looks every probe up in `out`; returns how many the frame saw.
    pub fn frame(&mut self, out: &RenderOutput, screen: &Screen) -> usize {
        let mut seen = 0;
        for pr in &mut self.probes {
            let now = screen.sees(out, pr.p).and_then(|_| out.lit_at(pr.p, pr.n));
            let Some(now) = now else {
                pr.last = None;
                continue;
            };
            seen += 1;
            if let Some(before) = pr.last {
                let c = &mut self.counts;
                let changed = u64::from(before != now);
                if pr.near_edge {
                    (c.compared_near_edges, c.flickered_near_edges) = (c.compared_near_edges + 1, c.flickered_near_edges + changed);
                } else {
                    (c.compared, c.flickered) = (c.compared + 1, c.flickered + changed);
                }
            }
            pr.last = Some(now);
        }
        seen
    }
}
