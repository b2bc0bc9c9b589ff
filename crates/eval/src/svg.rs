//! Scatter plots with logarithmic axes, written as plain SVG (no fonts or
//! system libraries needed); the layout is [`crate::plot`]'s.

use crate::plot::{Layout, Point, MARGIN, SIZE};
use std::fmt::Write;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// A log–log scatter plot with the lower-left Pareto front drawn as a step
/// line. Points with non-positive or non-finite coordinates are left out.
pub fn scatter(title: &str, x_label: &str, y_label: &str, points: &[Point]) -> String {
    let lay = Layout::new(points);
    let ((w, h), (l, r, t, b)) = (SIZE, MARGIN);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<rect width="100%" height="100%" fill="white"/><text x="{}" y="22" text-anchor="middle" font-size="15">{}</text>"#,
        w / 2.0,
        escape(title)
    );
    if lay.points.is_empty() {
        s.push_str("<text x=\"50%\" y=\"50%\" text-anchor=\"middle\">no data</text></svg>\n");
        return s;
    }
    // Axes, decade grid lines and labels.
    let _ = writeln!(s, r##"<rect x="{l}" y="{t}" width="{}" height="{}" fill="none" stroke="#444"/>"##, w - l - r, h - t - b);
    for d in lay.x_decades.0..=lay.x_decades.1 {
        let x = lay.px(10f64.powi(d));
        let _ = writeln!(
            s,
            r##"<line x1="{x}" y1="{t}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" text-anchor="middle">1e{d}</text>"##,
            h - b,
            h - b + 16.0
        );
    }
    for d in lay.y_decades.0..=lay.y_decades.1 {
        let y = lay.py(10f64.powi(d));
        let _ = writeln!(
            s,
            r##"<line x1="{l}" y1="{y}" x2="{}" y2="{y}" stroke="#ddd"/><text x="{}" y="{}" text-anchor="end">1e{d}</text>"##,
            w - r,
            l - 6.0,
            y + 4.0
        );
    }
    let _ = writeln!(s, r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#, (l + w - r) / 2.0, h - 12.0, escape(x_label));
    let _ =
        writeln!(s, r#"<text transform="translate(18,{}) rotate(-90)" text-anchor="middle">{}</text>"#, (t + h - b) / 2.0, escape(y_label));
    for p in &lay.points {
        let _ = writeln!(
            s,
            r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{}" fill-opacity="0.75"><title>{}</title></circle>"#,
            lay.px(p.x),
            lay.py(p.y),
            hex(lay.colour(&p.series)),
            escape(&p.label)
        );
    }
    if let Some(first) = lay.front.first() {
        let mut d = format!("M{:.1},{:.1}", lay.px(first.0), lay.py(first.1));
        for w2 in lay.front.windows(2) {
            let _ = write!(d, " H{:.1} V{:.1}", lay.px(w2[1].0), lay.py(w2[1].1));
        }
        let _ = writeln!(s, r##"<path d="{d}" fill="none" stroke="#000" stroke-dasharray="4 3"/>"##);
    }
    for (i, name) in lay.series.iter().enumerate() {
        let y = t + 14.0 + 18.0 * i as f64;
        let _ = writeln!(
            s,
            r#"<circle cx="{}" cy="{}" r="4" fill="{}"/><text x="{}" y="{}">{}</text>"#,
            w - r + 14.0,
            y - 4.0,
            hex(lay.colour(name)),
            w - r + 24.0,
            y,
            escape(name)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" font-size="11">--- Pareto front</text>"#,
        w - r + 10.0,
        t + 14.0 + 18.0 * lay.series.len() as f64
    );
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
