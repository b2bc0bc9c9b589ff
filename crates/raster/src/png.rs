//! PNG encoding and decoding of 8-bit images, with errors as text for the caller to wrap.

/// How the bytes of an image are laid out per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    Rgb,
    Rgba,
}

/// PNG bytes of a `width × height` image, rows top to bottom.
pub fn encode(width: u32, height: u32, layout: Layout, pixels: &[u8]) -> Result<Vec<u8>, String> {
    let channels = match layout {
        Layout::Rgb => 3,
        Layout::Rgba => 4,
    };
    if pixels.len() != (width as usize) * (height as usize) * channels {
        return Err(format!("{} bytes for a {width}×{height} image of {channels} channels", pixels.len()));
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(match layout {
            Layout::Rgb => png::ColorType::Rgb,
            Layout::Rgba => png::ColorType::Rgba,
        });
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        w.write_image_data(pixels).map_err(|e| e.to_string())?;
        w.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Animated PNG bytes of `frames` (each `width × height` RGBA, rows top to
/// bottom), shown `delay_ms` each and looped forever; viewers without APNG
/// support show the first frame.
pub fn encode_animated(width: u32, height: u32, frames: &[&[u8]], delay_ms: u16) -> Result<Vec<u8>, String> {
    let size = (width as usize) * (height as usize) * 4;
    if frames.is_empty() || frames.iter().any(|f| f.len() != size) {
        return Err(format!("an animation needs at least one frame of {size} bytes ({width}×{height} RGBA)"));
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_animated(frames.len() as u32, 0).map_err(|e| e.to_string())?;
        enc.set_frame_delay(delay_ms, 1000).map_err(|e| e.to_string())?;
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        for f in frames {
            w.write_image_data(f).map_err(|e| e.to_string())?;
        }
        w.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// An 8-bit PNG (grey, grey + alpha, RGB or RGBA; palettes expanded) as `(width, height, RGBA)`.
pub fn decode_rgba(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    buf.truncate(info.buffer_size());
    if info.bit_depth != png::BitDepth::Eight {
        return Err("only 8-bit images are supported".into());
    }
    let rgba = match info.color_type {
        png::ColorType::Rgba => buf,
        png::ColorType::Rgb => buf.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        png::ColorType::Grayscale => buf.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        png::ColorType::GrayscaleAlpha => buf.chunks_exact(2).flat_map(|p| [p[0], p[0], p[0], p[1]]).collect(),
        other => return Err(format!("unsupported colour type {other:?}")),
    };
    if rgba.len() != (info.width * info.height) as usize * 4 {
        return Err("only 8-bit images are supported".into());
    }
    Ok((info.width, info.height, rgba))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_and_rgba_round_trip_as_rgba() {
        let rgb = [10u8, 20, 30, 40, 50, 60];
        let (w, h, rgba) = decode_rgba(&encode(2, 1, Layout::Rgb, &rgb).unwrap()).unwrap();
        assert_eq!((w, h, rgba), (2, 1, vec![10, 20, 30, 255, 40, 50, 60, 255]));
        let px = [1u8, 2, 3, 4];
        assert_eq!(decode_rgba(&encode(1, 1, Layout::Rgba, &px).unwrap()).unwrap().2, px.to_vec());
    }

    #[test]
    fn animations_hold_every_frame() {
        let (a, b) = ([255u8, 0, 0, 255].repeat(6), [0u8, 0, 255, 255].repeat(6));
        let bytes = encode_animated(3, 2, &[&a, &b, &a], 100).unwrap();
        let mut dec = png::Decoder::new(std::io::Cursor::new(&bytes[..]));
        dec.set_transformations(png::Transformations::EXPAND);
        let mut reader = dec.read_info().unwrap();
        assert_eq!(reader.info().animation_control.map(|c| c.num_frames), Some(3));
        let mut buf = vec![0; reader.output_buffer_size()];
        for want in [&a, &b, &a] {
            reader.next_frame(&mut buf).unwrap();
            assert_eq!(&buf[..24], &want[..]);
        }
        assert!(encode_animated(3, 2, &[&a[..20]], 100).is_err());
        assert!(encode_animated(3, 2, &[], 100).is_err());
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(encode(2, 2, Layout::Rgb, &[0; 5]).is_err());
        assert!(decode_rgba(b"not a png").is_err());
    }
}
