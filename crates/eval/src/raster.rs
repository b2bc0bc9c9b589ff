//! The same plots as [`crate::svg`], rasterised to PNG for viewers that do
//! not show SVG. Everything is drawn here — lines, discs and text in a
//! built-in 5×7 pixel font (upper case, digits, the punctuation the plots
//! use) — so no font files or system libraries are needed.

use crate::plot::{Layout, Point, MARGIN, SIZE};
use shadowfocus_raster::{font, png};

const WHITE: [u8; 3] = [255, 255, 255];
const BLACK: [u8; 3] = [0, 0, 0];
const GRID: [u8; 3] = [0xdd, 0xdd, 0xdd];
const FRAME: [u8; 3] = [0x44, 0x44, 0x44];

/// An RGB image.
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

#[derive(Clone, Copy)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

impl Canvas {
    pub fn new(width: u32, height: u32) -> Canvas {
        Canvas { width, height, rgb: WHITE.repeat((width * height) as usize) }
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * self.width + x) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Sets a pixel; coordinates outside the canvas are ignored.
    fn set(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && x < self.width as i64 && y < self.height as i64 {
            let i = 3 * (y as usize * self.width as usize + x as usize);
            self.rgb[i..i + 3].copy_from_slice(&c);
        }
    }

    /// A one-pixel line; with `dash = Some((on, off))` a dashed one.
    pub fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: [u8; 3], dash: Option<(u32, u32)>) {
        let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0) as u32;
        for i in 0..=steps {
            if let Some((on, off)) = dash {
                if i % (on + off) >= on {
                    continue;
                }
            }
            let t = i as f64 / steps as f64;
            self.set((x0 + t * (x1 - x0)).round() as i64, (y0 + t * (y1 - y0)).round() as i64, c);
        }
    }

    pub fn rect(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), c: [u8; 3]) {
        self.line((x0, y0), (x1, y0), c, None);
        self.line((x1, y0), (x1, y1), c, None);
        self.line((x1, y1), (x0, y1), c, None);
        self.line((x0, y1), (x0, y0), c, None);
    }

    pub fn disc(&mut self, (cx, cy): (f64, f64), r: f64, c: [u8; 3]) {
        let (x0, x1) = ((cx - r).floor() as i64, (cx + r).ceil() as i64);
        let (y0, y1) = ((cy - r).floor() as i64, (cy + r).ceil() as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (dx, dy) = (x as f64 - cx, y as f64 - cy);
                if dx * dx + dy * dy <= r * r {
                    self.set(x, y, c);
                }
            }
        }
    }

    /// Width in pixels of `text` at `scale`.
    pub fn text_width(text: &str, scale: u32) -> f64 {
        font::text_width(text, scale) as f64
    }

    /// Text with its baseline-ish bottom at `y`; `vertical` writes it
    /// bottom-to-top (a y-axis label), anchored on `(x, y)` the same way.
    pub fn text(&mut self, (x, y): (f64, f64), text: &str, scale: u32, c: [u8; 3], anchor: Anchor, vertical: bool) {
        let w = Canvas::text_width(text, scale);
        let start = match anchor {
            Anchor::Start => 0.0,
            Anchor::Middle => -w / 2.0,
            Anchor::End => -w,
        };
        let (start, top) = (start.round() as i64, 7 * scale as i64);
        font::rasterize(text, scale, |u, v| {
            // (u, v): along the text, and down from its top.
            let (u, v) = (start + u, v - top);
            let (px, py) = if vertical { (x as i64 + v, y as i64 - u) } else { (x as i64 + u, y as i64 + v) };
            self.set(px, py, c);
        });
    }

    /// PNG bytes (8-bit RGB).
    pub fn encode_png(&self) -> Result<Vec<u8>, String> {
        png::encode(self.width, self.height, png::Layout::Rgb, &self.rgb)
    }
}

/// The plot of [`crate::svg::scatter`] as an image.
pub fn scatter_canvas(title: &str, x_label: &str, y_label: &str, points: &[Point]) -> Canvas {
    let lay = Layout::new(points);
    let ((w, h), (l, r, t, b)) = (SIZE, MARGIN);
    let mut c = Canvas::new(w as u32, h as u32);
    c.text((w / 2.0, 26.0), title, 2, BLACK, Anchor::Middle, false);
    if lay.points.is_empty() {
        c.text((w / 2.0, h / 2.0), "no data", 2, BLACK, Anchor::Middle, false);
        return c;
    }
    for d in lay.x_decades.0..=lay.x_decades.1 {
        let x = lay.px(10f64.powi(d));
        c.line((x, t), (x, h - b), GRID, None);
        c.text((x, h - b + 16.0), &format!("1e{d}"), 1, BLACK, Anchor::Middle, false);
    }
    for d in lay.y_decades.0..=lay.y_decades.1 {
        let y = lay.py(10f64.powi(d));
        c.line((l, y), (w - r, y), GRID, None);
        c.text((l - 6.0, y + 4.0), &format!("1e{d}"), 1, BLACK, Anchor::End, false);
    }
    c.rect((l, t), (w - r, h - b), FRAME);
    c.text(((l + w - r) / 2.0, h - 12.0), x_label, 1, BLACK, Anchor::Middle, false);
    c.text((22.0, (t + h - b) / 2.0), y_label, 1, BLACK, Anchor::Middle, true);
    // The front first: it runs through its points, which stay visible on top.
    for pair in lay.front.windows(2) {
        let (a, z) = ((lay.px(pair[0].0), lay.py(pair[0].1)), (lay.px(pair[1].0), lay.py(pair[1].1)));
        c.line(a, (z.0, a.1), BLACK, Some((4, 3)));
        c.line((z.0, a.1), z, BLACK, Some((4, 3)));
    }
    for p in &lay.points {
        c.disc((lay.px(p.x), lay.py(p.y)), 3.5, lay.colour(&p.series));
    }
    for (i, name) in lay.series.iter().enumerate() {
        let y = t + 14.0 + 18.0 * i as f64;
        c.disc((w - r + 14.0, y - 4.0), 4.0, lay.colour(name));
        c.text((w - r + 24.0, y), name, 1, BLACK, Anchor::Start, false);
    }
    let y = t + 14.0 + 18.0 * lay.series.len() as f64;
    c.line((w - r + 8.0, y - 4.0), (w - r + 20.0, y - 4.0), BLACK, Some((4, 3)));
    c.text((w - r + 24.0, y), "Pareto front", 1, BLACK, Anchor::Start, false);
    c
}

/// [`scatter_canvas`] encoded as PNG.
pub fn scatter_png(title: &str, x_label: &str, y_label: &str, points: &[Point]) -> Result<Vec<u8>, String> {
    scatter_canvas(title, x_label, y_label, points).encode_png()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_and_text_land_where_the_layout_puts_them() {
        let p = |x, y, s: &str| Point { x, y, series: s.into(), label: String::new() };
        let pts = [p(2.0, 3.0, "a"), p(50.0, 0.5, "b")];
        let c = scatter_canvas("t", "x", "y", &pts);
        let lay = Layout::new(&pts);
        for q in &pts {
            let (x, y) = (lay.px(q.x).round() as u32, lay.py(q.y).round() as u32);
            assert_eq!(c.pixel(x, y), lay.colour(&q.series));
        }
        // Title pixels are dark, a blank corner is white.
        assert!((0..c.width).any(|x| (10..30).any(|y| c.pixel(x, y) == BLACK)));
        assert_eq!(c.pixel(2, c.height - 2), WHITE);
    }

    #[test]
    fn png_decodes_back_to_the_canvas() {
        let c = scatter_canvas("round trip", "x", "y", &[Point { x: 1.5, y: 2.5, series: "s".into(), label: String::new() }]);
        let bytes = c.encode_png().unwrap();
        let (w, h, rgba) = png::decode_rgba(&bytes).unwrap();
        assert_eq!((w, h), (c.width, c.height));
        let rgb: Vec<u8> = rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        assert_eq!(rgb, c.rgb);
    }
}
