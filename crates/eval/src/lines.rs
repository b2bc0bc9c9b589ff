//! Line plots in panels, rasterised to PNG with [`crate::raster`]'s canvas
//! and font: one panel per value of a parameter (a sweep's elevations), one
//! curve per series (a method) in every panel, the same axes and colours in
//! all of them, a shared legend on the right. The style of the LiSPSM
//! papers' plots of aliasing against light direction.

use crate::plot::PALETTE;
use crate::raster::{Anchor, Canvas};

const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [0xdd, 0xdd, 0xdd];
const FRAME: [u8; 3] = [0x44, 0x44, 0x44];
const GUIDE: [u8; 3] = [0x88, 0x88, 0x88];

/// One curve: points in order of x; points with a non-finite y (or, on a
/// log axis, y ≤ 0) are left out and break the line.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

#[derive(Clone, Debug)]
pub struct Panel {
    pub title: String,
    pub series: Vec<Series>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    Linear,
    Log,
}

/// What the panels share.
#[derive(Clone, Debug)]
pub struct Axes {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// x range and the ticks labelled on it.
    pub x_range: (f64, f64),
    pub x_ticks: Vec<f64>,
    pub y_scale: Scale,
    /// A dashed horizontal line at this y in every panel (a threshold), with its label in the legend.
    pub guide: Option<(f64, String)>,
}

const PANEL: (f64, f64) = (340.0, 300.0);
/// Inside one panel: left, right, top, bottom.
const PAD: (f64, f64, f64, f64) = (56.0, 12.0, 30.0, 40.0);
const TOP: f64 = 40.0;
const LEGEND: f64 = 150.0;

/// The y range all panels share: data values (and the guide) padded a little;
/// on a log axis whole decades.
fn y_range(axes: &Axes, panels: &[Panel]) -> (f64, f64) {
    let ok = |y: f64| y.is_finite() && (axes.y_scale == Scale::Linear || y > 0.0);
    let mut ys: Vec<f64> =
        panels.iter().flat_map(|p| p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1))).filter(|&y| ok(y)).collect();
    if let Some((g, _)) = &axes.guide {
        if ok(*g) {
            ys.push(*g);
        }
    }
    let lo = ys.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    match axes.y_scale {
        Scale::Log => {
            if !lo.is_finite() {
                return (1.0, 10.0);
            }
            let (a, b) = (lo.log10().floor(), hi.log10().ceil());
            (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
        }
        Scale::Linear => {
            if !lo.is_finite() {
                return (0.0, 1.0);
            }
            let lo = lo.min(0.0);
            let hi = if hi > lo { hi } else { lo + 1.0 };
            let step = nice_step((hi - lo) / 5.0);
            (lo, (hi / step).ceil() * step)
        }
    }
}

/// 1, 2 or 5 times a power of ten, at least `raw`.
fn nice_step(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * p).find(|&s| s >= raw).unwrap_or(10.0 * p)
}

/// Short tick label: no trailing zeros, exponent form only far from 1.
fn tick_label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&v.abs()) {
        return format!("{v:e}");
    }
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The series names in order of first appearance over all panels.
pub fn series_names(panels: &[Panel]) -> Vec<&str> {
    let mut names: Vec<&str> = Vec::new();
    for s in panels.iter().flat_map(|p| &p.series) {
        if !names.contains(&s.name.as_str()) {
            names.push(&s.name);
        }
    }
    names
}

/// Where a panel's data lands on the canvas.
struct Frame {
    x0: f64,
    y0: f64,
    x_range: (f64, f64),
    y_range: (f64, f64),
    log: bool,
}

impl Frame {
    fn px(&self, x: f64) -> f64 {
        let w = PANEL.0 - PAD.0 - PAD.1;
        self.x0 + PAD.0 + (x - self.x_range.0) / (self.x_range.1 - self.x_range.0) * w
    }

    fn py(&self, y: f64) -> f64 {
        let h = PANEL.1 - PAD.2 - PAD.3;
        let t = if self.log {
            (y.log10() - self.y_range.0.log10()) / (self.y_range.1.log10() - self.y_range.0.log10())
        } else {
            (y - self.y_range.0) / (self.y_range.1 - self.y_range.0)
        };
        self.y0 + PANEL.1 - PAD.3 - t.clamp(-0.02, 1.02) * h
    }
}

/// The panels side by side, a shared y range, a legend of the series.
pub fn panels_canvas(axes: &Axes, panels: &[Panel]) -> Canvas {
    let n = panels.len().max(1);
    let (w, h) = (PANEL.0 * n as f64 + LEGEND, PANEL.1 + TOP);
    let mut c = Canvas::new(w as u32, h as u32);
    c.text((w / 2.0, 24.0), &axes.title, 2, BLACK, Anchor::Middle, false);
    let yr = y_range(axes, panels);
    let names = series_names(panels);
    let colour = |name: &str| PALETTE[names.iter().position(|q| *q == name).unwrap_or(0) % PALETTE.len()];
    let log = axes.y_scale == Scale::Log;
    let y_ticks: Vec<f64> = if log {
        let (a, b) = (yr.0.log10().round() as i32, yr.1.log10().round() as i32);
        (a..=b).map(|d| 10f64.powi(d)).collect()
    } else {
        let step = nice_step((yr.1 - yr.0) / 5.0);
        let k = ((yr.1 - yr.0) / step).round() as i32;
        (0..=k).map(|i| yr.0 + i as f64 * step).collect()
    };
    for (k, panel) in panels.iter().enumerate() {
        let f = Frame { x0: PANEL.0 * k as f64, y0: TOP, x_range: axes.x_range, y_range: yr, log };
        let (l, r, t, b) = (f.x0 + PAD.0, f.x0 + PANEL.0 - PAD.1, f.y0 + PAD.2, f.y0 + PANEL.1 - PAD.3);
        for &x in &axes.x_ticks {
            let px = f.px(x);
            c.line((px, t), (px, b), GRID, None);
            c.text((px, b + 14.0), &tick_label(x), 1, BLACK, Anchor::Middle, false);
        }
        for &y in &y_ticks {
            let py = f.py(y);
            c.line((l, py), (r, py), GRID, None);
            c.text((l - 5.0, py + 4.0), &tick_label(y), 1, BLACK, Anchor::End, false);
        }
        if let Some((g, _)) = &axes.guide {
            if g.is_finite() && (!log || *g > 0.0) {
                let py = f.py(*g);
                c.line((l, py), (r, py), GUIDE, Some((5, 4)));
            }
        }
        c.rect((l, t), (r, b), FRAME);
        c.text(((l + r) / 2.0, t - 8.0), &panel.title, 1, BLACK, Anchor::Middle, false);
        c.text(((l + r) / 2.0, b + 32.0), &axes.x_label, 1, BLACK, Anchor::Middle, false);
        if k == 0 {
            c.text((f.x0 + 12.0, (t + b) / 2.0), &axes.y_label, 1, BLACK, Anchor::Middle, true);
        }
        for s in &panel.series {
            let col = colour(&s.name);
            let ok = |y: f64| y.is_finite() && (!log || y > 0.0);
            let mut prev: Option<(f64, f64)> = None;
            for &(x, y) in &s.points {
                if !ok(y) || !x.is_finite() {
                    prev = None;
                    continue;
                }
                let p = (f.px(x), f.py(y));
                if let Some(q) = prev {
                    // Two pixels wide.
                    c.line(q, p, col, None);
                    c.line((q.0, q.1 + 1.0), (p.0, p.1 + 1.0), col, None);
                }
                c.disc(p, 2.5, col);
                prev = Some(p);
            }
        }
    }
    let lx = PANEL.0 * n as f64 + 10.0;
    for (i, name) in names.iter().enumerate() {
        let y = TOP + PAD.2 + 14.0 + 18.0 * i as f64;
        c.line((lx, y - 4.0), (lx + 16.0, y - 4.0), colour(name), None);
        c.line((lx, y - 3.0), (lx + 16.0, y - 3.0), colour(name), None);
        c.disc((lx + 8.0, y - 3.5), 2.5, colour(name));
        c.text((lx + 22.0, y), name, 1, BLACK, Anchor::Start, false);
    }
    if let Some((_, label)) = &axes.guide {
        let y = TOP + PAD.2 + 14.0 + 18.0 * names.len() as f64;
        c.line((lx, y - 4.0), (lx + 16.0, y - 4.0), GUIDE, Some((5, 4)));
        c.text((lx + 22.0, y), label, 1, BLACK, Anchor::Start, false);
    }
    c
}

/// [`panels_canvas`] encoded as PNG.
pub fn panels_png(axes: &Axes, panels: &[Panel]) -> Result<Vec<u8>, String> {
    panels_canvas(axes, panels).encode_png()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes(scale: Scale) -> Axes {
        Axes {
            title: "t".into(),
            x_label: "azimuth".into(),
            y_label: "y".into(),
            x_range: (0.0, 360.0),
            x_ticks: vec![0.0, 90.0, 180.0, 270.0, 360.0],
            y_scale: scale,
            guide: Some((0.5, "limit".into())),
        }
    }

    fn panels() -> Vec<Panel> {
        let s =
            |name: &str, k: f64| Series { name: name.into(), points: (0..12).map(|i| (30.0 * i as f64, k * (1.0 + i as f64))).collect() };
        vec![
            Panel { title: "el 10".into(), series: vec![s("a", 1.0), s("b", 3.0)] },
            Panel {
                title: "el 35".into(),
                series: vec![s("b", 2.0), Series { name: "c".into(), points: vec![(0.0, f64::NAN), (30.0, 0.0), (60.0, 4.0)] }],
            },
        ]
    }

    #[test]
    fn ranges_cover_the_data_and_the_guide() {
        let p = panels();
        assert_eq!(y_range(&axes(Scale::Log), &p), (0.1, 100.0), "0.5 (the guide) to 36, zero left out");
        let (lo, hi) = y_range(&axes(Scale::Linear), &p);
        assert!(lo == 0.0 && (36.0..=40.0).contains(&hi), "{lo} {hi}");
        assert_eq!(series_names(&p), vec!["a", "b", "c"]);
        assert_eq!((nice_step(0.7), nice_step(3.0), nice_step(12.0)), (1.0, 5.0, 20.0));
        assert_eq!((tick_label(0.5), tick_label(100.0), tick_label(1e-6)), ("0.5".into(), "100".into(), "1e-6".into()));
    }

    #[test]
    fn curves_are_drawn_in_their_series_colour_in_every_panel() {
        let p = panels();
        let c = panels_canvas(&axes(Scale::Log), &p);
        assert_eq!(c.width as f64, 2.0 * PANEL.0 + LEGEND);
        let yr = y_range(&axes(Scale::Log), &p);
        for (k, panel) in p.iter().enumerate() {
            let f = Frame { x0: PANEL.0 * k as f64, y0: TOP, x_range: (0.0, 360.0), y_range: yr, log: true };
            for s in &panel.series {
                let col = PALETTE[series_names(&p).iter().position(|n| *n == s.name).unwrap()];
                for &(x, y) in s.points.iter().filter(|q| q.1 > 0.0) {
                    assert_eq!(c.pixel(f.px(x).round() as u32, f.py(y).round() as u32), col, "{} at ({x}, {y})", s.name);
                }
            }
        }
        let bytes = c.encode_png().unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
    }
}
