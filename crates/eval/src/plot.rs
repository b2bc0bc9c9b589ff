//! What a log–log scatter plot shows, independent of how it is drawn: the
//! kept points, the decade ranges of both axes, the series (one colour
//! each, in order of first appearance) and the lower-left Pareto front.
//! [`crate::svg`] and [`crate::raster`] draw the same layout.

use crate::table::pareto_front;

/// One plotted point: position, series name (colour) and a label (shown on
/// hover in the SVG).
#[derive(Clone, Debug)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub series: String,
    pub label: String,
}

/// Series colours, RGB.
pub const PALETTE: [[u8; 3]; 8] = [
    [0x1f, 0x77, 0xb4],
    [0xd6, 0x27, 0x28],
    [0x2c, 0xa0, 0x2c],
    [0x94, 0x67, 0xbd],
    [0xff, 0x7f, 0x0e],
    [0x8c, 0x56, 0x4b],
    [0xe3, 0x77, 0xc2],
    [0x17, 0xbe, 0xcf],
];

/// Canvas size and margins (left, right, top, bottom), in pixels.
pub const SIZE: (f64, f64) = (760.0, 480.0);
pub const MARGIN: (f64, f64, f64, f64) = (70.0, 170.0, 40.0, 50.0);

/// Decades covering `[lo, hi]` (both positive).
fn decades(lo: f64, hi: f64) -> (f64, f64) {
    let a = lo.log10().floor();
    let b = hi.log10().ceil();
    (a, if b > a { b } else { a + 1.0 })
}

pub struct Layout<'a> {
    /// Points with positive, finite coordinates (the others cannot be
    /// placed on log axes and are left out).
    pub points: Vec<&'a Point>,
    /// Decade exponents spanned by each axis.
    pub x_decades: (i32, i32),
    pub y_decades: (i32, i32),
    pub series: Vec<&'a str>,
    /// The Pareto front, sorted by x.
    pub front: Vec<(f64, f64)>,
}

impl<'a> Layout<'a> {
    pub fn new(points: &'a [Point]) -> Layout<'a> {
        let points: Vec<&Point> = points.iter().filter(|p| p.x > 0.0 && p.y > 0.0 && p.x.is_finite() && p.y.is_finite()).collect();
        let range = |f: fn(&Point) -> f64| points.iter().map(|p| f(p)).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (x, y) = if points.is_empty() { ((1.0, 10.0), (1.0, 10.0)) } else { (range(|p| p.x), range(|p| p.y)) };
        let (x0, x1) = decades(x.0, x.1);
        let (y0, y1) = decades(y.0, y.1);
        let mut series: Vec<&str> = Vec::new();
        for p in &points {
            if !series.contains(&p.series.as_str()) {
                series.push(&p.series);
            }
        }
        let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.x, p.y)).collect();
        let mut front: Vec<(f64, f64)> = pareto_front(&xy).into_iter().map(|i| xy[i]).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        Layout { points, x_decades: (x0 as i32, x1 as i32), y_decades: (y0 as i32, y1 as i32), series, front }
    }

    /// Canvas x of a data x.
    pub fn px(&self, x: f64) -> f64 {
        let (w, (l, r, _, _)) = (SIZE.0, MARGIN);
        let (x0, x1) = (self.x_decades.0 as f64, self.x_decades.1 as f64);
        l + (x.log10() - x0) / (x1 - x0) * (w - l - r)
    }

    /// Canvas y of a data y.
    pub fn py(&self, y: f64) -> f64 {
        let (h, (_, _, t, b)) = (SIZE.1, MARGIN);
        let (y0, y1) = (self.y_decades.0 as f64, self.y_decades.1 as f64);
        h - b - (y.log10() - y0) / (y1 - y0) * (h - t - b)
    }

    pub fn colour(&self, series: &str) -> [u8; 3] {
        PALETTE[self.series.iter().position(|q| *q == series).unwrap_or(0) % PALETTE.len()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_spans_whole_decades_and_skips_unplaceable_points() {
        let p = |x, y, s: &str| Point { x, y, series: s.into(), label: String::new() };
        let pts = [p(2.0, 30.0, "a"), p(300.0, 0.5, "b"), p(0.0, 1.0, "a"), p(f64::NAN, 1.0, "c")];
        let l = Layout::new(&pts);
        assert_eq!(l.points.len(), 2);
        assert_eq!((l.x_decades, l.y_decades), ((0, 3), (-1, 2)));
        assert_eq!(l.series, vec!["a", "b"]);
        assert_eq!(l.front.len(), 2, "neither point dominates the other");
        assert_eq!(l.px(1.0), MARGIN.0);
        assert_eq!(l.py(0.1), SIZE.1 - MARGIN.3);
    }
}
