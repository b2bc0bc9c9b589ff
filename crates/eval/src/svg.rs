//! Scatter plots with logarithmic axes, written as plain SVG (no fonts or
//! system libraries needed).

use crate::table::pareto_front;
use std::fmt::Write;

/// One plotted point: position, series name (colour) and a label shown on
/// hover.
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub series: String,
    pub label: String,
}

const PALETTE: [&str; 8] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Decades covering `[lo, hi]` (both positive).
fn decades(lo: f64, hi: f64) -> (f64, f64) {
    let a = lo.log10().floor();
    let b = hi.log10().ceil();
    (a, if b > a { b } else { a + 1.0 })
}

/// A log–log scatter plot with the lower-left Pareto front drawn as a step
/// line. Points with non-positive or non-finite coordinates are left out.
pub fn scatter(title: &str, x_label: &str, y_label: &str, points: &[Point]) -> String {
    let pts: Vec<&Point> = points.iter().filter(|p| p.x > 0.0 && p.y > 0.0 && p.x.is_finite() && p.y.is_finite()).collect();
    let (w, h, l, r, t, b) = (760.0, 480.0, 70.0, 170.0, 40.0, 50.0);
    let mut s = String::new();
    let _ = writeln!(s, r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#);
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/><text x="{}" y="22" text-anchor="middle" font-size="15">{}</text>"#, w / 2.0, escape(title));
    if pts.is_empty() {
        s.push_str("<text x=\"50%\" y=\"50%\" text-anchor=\"middle\">no data</text></svg>\n");
        return s;
    }
    let fold = |f: fn(&Point) -> f64| pts.iter().map(|p| f(p)).fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (x0, x1) = decades(fold(|p| p.x).0, fold(|p| p.x).1);
    let (y0, y1) = decades(fold(|p| p.y).0, fold(|p| p.y).1);
    let px = |x: f64| l + (x.log10() - x0) / (x1 - x0) * (w - l - r);
    let py = |y: f64| h - b - (y.log10() - y0) / (y1 - y0) * (h - t - b);
    // Axes, decade grid lines and labels.
    let _ = writeln!(s, r##"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="#444"/>"##, w - l - r, h - t - b);
    for d in (x0 as i32)..=(x1 as i32) {
        let x = px(10f64.powi(d));
        let _ = writeln!(s, r##"<line x1="{x}" y1="{t}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" text-anchor="middle">1e{d}</text>"##, h - b, h - b + 16.0);
    }
    for d in (y0 as i32)..=(y1 as i32) {
        let y = py(10f64.powi(d));
        let _ = writeln!(s, r##"<line x1="{l}" y1="{y}" x2="{}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">1e{d}</text>"##, w - r, l - 6.0, y + 4.0);
    }
    let _ = writeln!(s, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, (l + w - r) / 2.0, h - 12.0, escape(x_label));
    let _ = writeln!(s, r#"<text transform="translate(18,{}) rotate(-90)" text-anchor="middle">{}</text>"#, (t + h - b) / 2.0, escape(y_label));
    // Series in order of first appearance.
    let mut series: Vec<&str> = Vec::new();
    for p in &pts {
        if !series.contains(&p.series.as_str()) {
            series.push(&p.series);
        }
    }
    for p in &pts {
        let c = PALETTE[series.iter().position(|q| *q == p.series).unwrap_or(0) % PALETTE.len()];
        let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{c}" fill-opacity="0.75"><title>{}</title></circle>"#, px(p.x), py(p.y), escape(&p.label));
    }
    // Pareto front as a step line.
    let xy: Vec<(f64, f64)> = pts.iter().map(|p| (p.x, p.y)).collect();
    let mut front: Vec<(f64, f64)> = pareto_front(&xy).into_iter().map(|i| xy[i]).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    if !front.is_empty() {
        let mut d = format!("M{:.1},{:.1}", px(front[0].0), py(front[0].1));
        for w2 in front.windows(2) {
            let _ = write!(d, " H{:.1} V{:.1}", px(w2[1].0), py(w2[1].1));
        }
        let _ = writeln!(s, r##"<path d="{d}" fill="none" stroke="#000" stroke-dasharray="4 3"/>"##);
    }
    for (i, name) in series.iter().enumerate() {
        let y = t + 14.0 + 18.0 * i as f64;
        let _ = writeln!(s, r#"<circle cx="{}" cy="{}" r="4" fill="{}"/><text x="{}" y="{}">{}</text>"#, w - r + 14.0, y - 4.0, PALETTE[i % PALETTE.len()], w - r + 24.0, y, escape(name));
    }
    let _ = writeln!(s, r#"<text x="{}" y="{}" font-size="11">--- Pareto front</text>"#, w - r + 10.0, t + 14.0 + 18.0 * series.len() as f64);
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scatter_is_well_formed_and_skips_bad_points() {
        let p = |x, y, s: &str| Point { x, y, series: s.into(), label: format!("{x}<{y}") };
        let svg = scatter("t & u", "x", "y", &[p(1.0, 2.0, "a"), p(10.0, 0.5, "b"), p(-1.0, 1.0, "a"), p(f64::NAN, 1.0, "a")]);
        assert_eq!(svg.matches("<circle").count(), 2 + 2, "two points and two legend dots");
        assert!(svg.contains("t &amp; u") && svg.contains("1&lt;2"));
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("<path d=\"M"), "front drawn");
    }
}
