//! RGBA8 images: PNG output, labels, heatmaps, depth views and contact sheets.

use std::path::Path;

use crate::error::RenderError;
use shadowfocus_raster::{font, png};

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Image {
    pub fn new(width: u32, height: u32, fill: [u8; 4]) -> Image {
        let mut rgba = Vec::with_capacity(width as usize * height as usize * 4);
        for _ in 0..width as usize * height as usize {
            rgba.extend_from_slice(&fill);
        }
        Image { width, height, rgba }
    }

    pub fn get(&self, x: u32, y: u32) -> [u8; 4] {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2], self.rgba[i + 3]]
    }

    pub fn put(&mut self, x: i64, y: i64, c: [u8; 4]) {
        if x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height {
            let i = (y as usize * self.width as usize + x as usize) * 4;
            self.rgba[i..i + 4].copy_from_slice(&c);
        }
    }

    pub fn fill_rect(&mut self, x: i64, y: i64, w: u32, h: u32, c: [u8; 4]) {
        for yy in y..y + h as i64 {
            for xx in x..x + w as i64 {
                self.put(xx, yy, c);
            }
        }
    }

    /// Draws `text` with its top-left corner at (x, y).
    pub fn text(&mut self, x: i64, y: i64, text: &str, scale: u32, c: [u8; 4]) {
        font::rasterize(text, scale, |u, v| self.put(x + u, y + v, c));
    }

    /// Copies `src` with its top-left corner at (x, y), clipped.
    pub fn blit(&mut self, src: &Image, x: i64, y: i64) {
        for sy in 0..src.height {
            for sx in 0..src.width {
                self.put(x + sx as i64, y + sy as i64, src.get(sx, sy));
            }
        }
    }

    /// Box-filtered downscale by an integer factor (≥ 1).
    pub fn downscale(&self, factor: u32) -> Image {
        let f = factor.max(1);
        let (w, h) = ((self.width / f).max(1), (self.height / f).max(1));
        let mut out = Image::new(w, h, [0, 0, 0, 255]);
        for y in 0..h {
            for x in 0..w {
                let mut acc = [0u32; 4];
                let mut n = 0;
                for dy in 0..f {
                    for dx in 0..f {
                        let (sx, sy) = (x * f + dx, y * f + dy);
                        if sx < self.width && sy < self.height {
                            let p = self.get(sx, sy);
                            for k in 0..4 {
                                acc[k] += p[k] as u32;
                            }
                            n += 1;
                        }
                    }
                }
                let n = n.max(1);
                out.put(x as i64, y as i64, [(acc[0] / n) as u8, (acc[1] / n) as u8, (acc[2] / n) as u8, (acc[3] / n) as u8]);
            }
        }
        out
    }

    pub fn save_png(&self, path: &Path) -> Result<(), RenderError> {
        let bytes = png::encode(self.width, self.height, png::Layout::Rgba, &self.rgba)
            .map_err(|reason| RenderError::Png { path: path.to_path_buf(), reason })?;
        std::fs::write(path, bytes).map_err(|source| RenderError::Io { path: path.to_path_buf(), source })
    }

    /// The `w × h` region at `(x, y)` magnified `scale` times (nearest pixel).
    pub fn zoom(&self, x: u32, y: u32, w: u32, h: u32, scale: u32) -> Image {
        let mut out = Image::new(w * scale, h * scale, [0, 0, 0, 255]);
        for j in 0..h * scale {
            for i in 0..w * scale {
                let (sx, sy) = (x + i / scale, y + j / scale);
                if sx < self.width && sy < self.height {
                    out.put(i as i64, j as i64, self.get(sx, sy));
                }
            }
        }
        out
    }

    /// Writes `frames` (all of one size) as an animated PNG, `delay_ms` per frame, looped.
    pub fn save_animation(frames: &[Image], delay_ms: u16, path: &Path) -> Result<(), RenderError> {
        let png_error = |reason| RenderError::Png { path: path.to_path_buf(), reason };
        let first = frames.first().ok_or_else(|| png_error("no frames".to_string()))?;
        let pixels: Vec<&[u8]> = frames.iter().map(|f| f.rgba.as_slice()).collect();
        let bytes = png::encode_animated(first.width, first.height, &pixels, delay_ms).map_err(png_error)?;
        std::fs::write(path, bytes).map_err(|source| RenderError::Io { path: path.to_path_buf(), source })
    }

    pub fn load_png(path: &Path) -> Result<Image, RenderError> {
        let bytes = std::fs::read(path).map_err(|source| RenderError::Io { path: path.to_path_buf(), source })?;
        let (width, height, rgba) = png::decode_rgba(&bytes).map_err(|reason| RenderError::Png { path: path.to_path_buf(), reason })?;
        Ok(Image { width, height, rgba })
    }
}

/// Diverging colour map for aliasing: log2(e) ∈ [−3, 3] → blue (oversampled) … white (e = 1) … red
/// (undersampled), passing through yellow for e ≈ 2–4.
pub fn aliasing_color(e: f32) -> [u8; 4] {
    let t = (e.max(1e-30).log2() / 3.0).clamp(-1.0, 1.0);
    let lerp = |a: [f32; 3], b: [f32; 3], s: f32| -> [u8; 4] {
        let c = |k: usize| ((a[k] + (b[k] - a[k]) * s) * 255.0).round().clamp(0.0, 255.0) as u8;
        [c(0), c(1), c(2), 255]
    };
    const BLUE: [f32; 3] = [0.10, 0.25, 0.85];
    const WHITE: [f32; 3] = [0.95, 0.95, 0.95];
    const YELLOW: [f32; 3] = [1.0, 0.85, 0.15];
    const RED: [f32; 3] = [0.80, 0.05, 0.05];
    if t < 0.0 {
        lerp(WHITE, BLUE, -t)
    } else if t < 0.5 {
        lerp(WHITE, YELLOW, t * 2.0)
    } else {
        lerp(YELLOW, RED, (t - 0.5) * 2.0)
    }
}

/// Background of heatmaps and uncovered geometry.
pub const HEAT_BACKGROUND: [u8; 4] = [40, 40, 48, 255];
pub const HEAT_UNCOVERED: [u8; 4] = [220, 0, 220, 255];
pub const HEAT_UNLIT: [u8; 4] = [90, 90, 96, 255];
/// Value of `e` that [`aliasing_heatmap`] draws as "outside the light".
pub const HEAT_UNLIT_VALUE: f32 = -2.0;
const LEGEND_H: u32 = 34;

/// Aliasing heatmap: `e` per pixel (−1 = geometry no map covers, [`HEAT_UNLIT_VALUE`] = outside
/// the light, NaN = background), with a legend strip labelled in screen pixels per shadow texel.
/// Pixels whose `receiver` flag is false (not counted in the statistics) are drawn faded.
pub fn aliasing_heatmap(width: u32, height: u32, e: &[f32], receiver: Option<&[bool]>, title: &str) -> Image {
    let mut img = Image::new(width, height + LEGEND_H, [255, 255, 255, 255]);
    for y in 0..height {
        for x in 0..width {
            let v = e[(y * width + x) as usize];
            let c = if v.is_nan() {
                HEAT_BACKGROUND
            } else if v <= HEAT_UNLIT_VALUE {
                HEAT_UNLIT
            } else if v < 0.0 {
                HEAT_UNCOVERED
            } else {
                aliasing_color(v)
            };
            let counted = receiver.map(|r| r[(y * width + x) as usize]).unwrap_or(true);
            let c = if counted || v.is_nan() {
                c
            } else {
                let fade = |k: usize| ((c[k] as u32 + 2 * 150) / 3) as u8;
                [fade(0), fade(1), fade(2), 255]
            };
            img.put(x as i64, y as i64, c);
        }
    }
    // Legend: a colour bar over log2(e) ∈ [−3, 3] with ticks at powers of two.
    let y0 = height as i64 + 4;
    let bar_x = 8i64;
    let bar_w = (width as i64 - 16).max(60);
    for i in 0..bar_w {
        let t = -3.0 + 6.0 * i as f32 / (bar_w - 1).max(1) as f32;
        img.fill_rect(bar_x + i, y0, 1, 8, aliasing_color(t.exp2()));
    }
    let labels = ["1/8", "1/4", "1/2", "1", "2", "4", "8"];
    for (k, l) in labels.iter().enumerate() {
        let x = bar_x + (bar_w - 1) * k as i64 / 6;
        img.fill_rect(x, y0 + 8, 1, 3, [0, 0, 0, 255]);
        let w = font::text_width(l, 1) as i64;
        img.text((x - w / 2).clamp(0, width as i64 - w), y0 + 12, l, 1, [0, 0, 0, 255]);
    }
    let caption = format!("{title}  screen px per texel (>1 undersampled)  magenta: uncovered  faded: not a receiver");
    img.text(bar_x, y0 + 21, &caption, 1, [0, 0, 0, 255]);
    img
}

/// Mismatch image colours.
pub const FALSE_SHADOW: [u8; 4] = [230, 30, 30, 255];
pub const FALSE_SHADOW_EDGE: [u8; 4] = [250, 160, 120, 255];
pub const FALSE_LIGHT: [u8; 4] = [30, 90, 250, 255];
pub const FALSE_LIGHT_EDGE: [u8; 4] = [130, 200, 250, 255];

/// Per-pixel comparison result used by [`mismatch_image`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelMatch {
    Background,
    Agree,
    /// Rendered shadowed, truly lit (acne, over-wide shadows); `edge` = near a true shadow edge.
    FalseShadow {
        edge: bool,
    },
    /// Rendered lit, truly shadowed (light leaks, lost casters).
    FalseLight {
        edge: bool,
    },
}

/// The lit image desaturated and darkened, with mismatches painted over it and a legend strip.
pub fn mismatch_image(color: &Image, matches: &[PixelMatch]) -> Image {
    let (w, h) = (color.width, color.height);
    let mut img = Image::new(w, h + 14, [255, 255, 255, 255]);
    for y in 0..h {
        for x in 0..w {
            let c = match matches[(y * w + x) as usize] {
                PixelMatch::Background => [20, 20, 24, 255],
                PixelMatch::Agree => {
                    let p = color.get(x, y);
                    let g = ((p[0] as u32 * 3 + p[1] as u32 * 6 + p[2] as u32) / 10 / 2 + 20) as u8;
                    [g, g, g, 255]
                }
                PixelMatch::FalseShadow { edge: false } => FALSE_SHADOW,
                PixelMatch::FalseShadow { edge: true } => FALSE_SHADOW_EDGE,
                PixelMatch::FalseLight { edge: false } => FALSE_LIGHT,
                PixelMatch::FalseLight { edge: true } => FALSE_LIGHT_EDGE,
            };
            img.put(x as i64, y as i64, c);
        }
    }
    let y0 = h as i64 + 3;
    let mut x = 4i64;
    for (c, label) in
        [(FALSE_SHADOW, "false shadow"), (FALSE_LIGHT, "light leak"), (FALSE_SHADOW_EDGE, "near edge"), (FALSE_LIGHT_EDGE, "near edge")]
    {
        img.fill_rect(x, y0, 8, 8, c);
        img.text(x + 11, y0 + 1, label, 1, [0, 0, 0, 255]);
        x += 11 + font::text_width(label, 1) as i64 + 10;
    }
    img
}

/// Grey-scale view of a stored depth map (smaller = nearer the light): depths stretched to the
/// full range, near the light dark; texels no caster covered (NaN) in dark blue.
pub fn depth_image(resolution: u32, depth: &[f32]) -> Image {
    let mut lo = f32::INFINITY;
    let mut hi = f32::NEG_INFINITY;
    for &d in depth {
        if d.is_finite() {
            lo = lo.min(d);
            hi = hi.max(d);
        }
    }
    let span = if hi > lo { hi - lo } else { 1.0 };
    let mut img = Image::new(resolution, resolution, [0, 0, 0, 255]);
    for y in 0..resolution {
        for x in 0..resolution {
            let d = depth[(y * resolution + x) as usize];
            let c = if !d.is_finite() {
                [20, 30, 70, 255]
            } else {
                let t = (d - lo) / span;
                let g = (40.0 + 215.0 * t.clamp(0.0, 1.0)) as u8;
                [g, g, g, 255]
            };
            img.put(x as i64, y as i64, c);
        }
    }
    img
}

/// Tiles images in a grid, each with its label underneath, on a white sheet.
pub fn contact_sheet(tiles: &[(&Image, &str)], columns: usize) -> Image {
    let columns = columns.clamp(1, tiles.len().max(1));
    let rows = tiles.len().div_ceil(columns);
    let tw = tiles.iter().map(|t| t.0.width).max().unwrap_or(1);
    let th = tiles.iter().map(|t| t.0.height).max().unwrap_or(1);
    let (pad, label_h) = (8u32, 14u32);
    let sheet_w = columns as u32 * (tw + pad) + pad;
    let sheet_h = rows as u32 * (th + label_h + pad) + pad;
    let mut sheet = Image::new(sheet_w, sheet_h.max(1), [255, 255, 255, 255]);
    for (k, (img, label)) in tiles.iter().enumerate() {
        let (c, r) = ((k % columns) as u32, (k / columns) as u32);
        let x = (pad + c * (tw + pad)) as i64;
        let y = (pad + r * (th + label_h + pad)) as i64;
        sheet.blit(img, x, y);
        // Trim labels that would run into the next tile.
        let max_chars = (tw / font::CELL_W) as usize;
        let text: String = label.chars().take(max_chars).collect();
        sheet.text(x, y + img.height as i64 + 3, &text, 1, [0, 0, 0, 255]);
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_is_monotone_in_redness_above_one() {
        let a = aliasing_color(1.0);
        let b = aliasing_color(8.0);
        let c = aliasing_color(1.0 / 8.0);
        assert!(a[0] > 200 && a[1] > 200 && a[2] > 200, "e = 1 should be near white: {a:?}");
        assert!(b[0] > 150 && b[1] < 60, "e = 8 should be red: {b:?}");
        assert!(c[2] > 150 && c[0] < 60, "e = 1/8 should be blue: {c:?}");
    }

    #[test]
    fn png_round_trip() {
        let mut img = Image::new(7, 5, [1, 2, 3, 255]);
        img.text(0, 0, "A", 1, [255, 0, 0, 255]);
        let dir = std::env::temp_dir().join(format!("sf-render-png-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("x.png");
        img.save_png(&p).unwrap();
        assert_eq!(Image::load_png(&p).unwrap(), img);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn contact_sheet_places_tiles_and_labels() {
        let a = Image::new(10, 6, [255, 0, 0, 255]);
        let b = Image::new(10, 6, [0, 255, 0, 255]);
        let s = contact_sheet(&[(&a, "A"), (&b, "B")], 2);
        assert_eq!(s.get(8, 8), [255, 0, 0, 255]);
        assert_eq!(s.get(8 + 10 + 8, 8), [0, 255, 0, 255]);
        let dark = s.rgba.chunks_exact(4).filter(|p| p[0] == 0 && p[1] == 0 && p[2] == 0).count();
        assert!(dark > 0, "labels were drawn");
    }
}
