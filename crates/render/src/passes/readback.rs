//! Read-back: the frame's targets (and the shadow maps, when kept) copied into mappable buffers
//! with 256-byte row alignment, mapped together, and decoded per pixel.

use super::gbuffer::Targets;
use super::reduce::{decode, decode_slices, Reduced, SLICES_BYTES};
use super::shadow::ShadowPass;
use crate::error::RenderError;
use crate::frame::{DepthMap, RenderOutput, RenderRequest};
use crate::gpu::Gpu;
use crate::image::Image;
use crate::stats::RenderMetrics;
use crate::types::DepthMode;

/// Reads the frame back into a [`RenderOutput`] (no ground truth, default metrics: the
/// renderer adds both). `blurred`: the shadow term comes from the blur's last target.
pub(crate) fn read_frame(
    gpu: &Gpu,
    req: &RenderRequest,
    t: &Targets,
    shadow: &ShadowPass,
    blurred: bool,
    reduced: Option<&Reduced>,
) -> Result<RenderOutput, RenderError> {
    let device = &gpu.device;
    let (w, h) = (req.settings.width, req.settings.height);
    let mut rb = Readback::default();
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("read-back") });
    let i_world = rb.add(device, &mut enc, &t.world, 0, w, h, 16);
    let i_normal = rb.add(device, &mut enc, &t.normal, 0, w, h, 8);
    let i_aux = rb.add(device, &mut enc, &t.aux, 0, w, h, 16);
    let i_vis = blurred.then(|| rb.add(device, &mut enc, &t.vis[1], 0, w, h, 2));
    let i_color = rb.add(device, &mut enc, &t.color, 0, w, h, 4);
    let i_range = reduced.map(|r| rb.add_buffer(device, &mut enc, &r.range, 8));
    let i_slices = reduced.and_then(|r| r.slices.as_ref()).map(|b| rb.add_buffer(device, &mut enc, b, SLICES_BYTES));
    let i_maps: Vec<usize> = match &shadow.viz {
        Some(v) => req
            .maps
            .iter()
            .zip(0..)
            .map(|(m, l)| {
                let res = req.map_resolution(m);
                rb.add(device, &mut enc, v, l, res, res, 4)
            })
            .collect(),
        None => Vec::new(),
    };
    gpu.queue.submit([enc.finish()]);
    let data = rb.finish(gpu)?;

    let f32s = |b: &[u8]| -> Vec<f32> { bytemuck::pod_collect_to_vec::<u8, f32>(b) };
    let world_f = f32s(&data[i_world]);
    let aux_f = f32s(&data[i_aux]);
    let normal_h: Vec<u16> = bytemuck::pod_collect_to_vec::<u8, u16>(&data[i_normal]);
    let n = (w * h) as usize;
    let mut px = RenderOutput {
        width: w,
        height: h,
        color: Image { width: w, height: h, rgba: data[i_color].clone() },
        world: Vec::with_capacity(n),
        normal: Vec::with_capacity(n),
        aliasing: Vec::with_capacity(n),
        split: Vec::with_capacity(n),
        shadow: Vec::with_capacity(n),
        truth: None,
        shadow_maps: Vec::new(),
        visible_depth: i_range.and_then(|i| decode(&data[i])),
        receiver_slices: i_slices.map(|i| decode_slices(&data[i])),
        surface_offset: req.scene.surface_offset(),
        camera: req.camera,
        light: req.light,
        metrics: RenderMetrics::default(),
    };
    let vis_f: Option<Vec<f32>> = i_vis.map(|i| bytemuck::pod_collect_to_vec::<u8, u16>(&data[i]).into_iter().map(half_to_f32).collect());
    for p in 0..n {
        let wv = [world_f[4 * p], world_f[4 * p + 1], world_f[4 * p + 2], world_f[4 * p + 3]];
        px.world.push(wv);
        px.normal.push([half_to_f32(normal_h[4 * p]), half_to_f32(normal_h[4 * p + 1]), half_to_f32(normal_h[4 * p + 2]), 0.0]);
        let bg = wv[3] == 0.0;
        px.aliasing.push(if bg { f32::NAN } else { aux_f[4 * p] });
        px.split.push(if bg { -1 } else { aux_f[4 * p + 3] as i32 });
        px.shadow.push(match &vis_f {
            Some(v) if !bg => v[p],
            _ => aux_f[4 * p + 2],
        });
    }
    px.shadow_maps = i_maps
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let m = &req.maps[k];
            DepthMap {
                resolution: req.map_resolution(m),
                depth: f32s(&data[i]),
                reversed: req.stores_flipped(m),
                world_to_clip: m.world_to_clip,
                depth_test: m.depth_test,
                split: m.split,
                face: m.face,
                linear: matches!(req.settings.depth, DepthMode::Linear { .. }),
            }
        })
        .collect();
    Ok(px)
}

/// Texture → buffer copies with 256-byte row alignment (and plain buffer
/// copies), mapped together.
#[derive(Default)]
pub(crate) struct Readback {
    items: Vec<(wgpu::Buffer, u32, u32, u32)>, // buffer, padded row bytes, row bytes, rows
}

impl Readback {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add(
        &mut self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        tex: &wgpu::Texture,
        layer: u32,
        w: u32,
        h: u32,
        bpp: u32,
    ) -> usize {
        let row = w * bpp;
        let padded = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: padded as u64 * h as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        enc.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: tex,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: Some(h) },
            },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        self.items.push((buf, padded, row, h));
        self.items.len() - 1
    }

    /// Copies the first `size` bytes of `src` (a `COPY_SRC` buffer).
    pub(crate) fn add_buffer(&mut self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder, src: &wgpu::Buffer, size: u32) -> usize {
        let buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("read-back"),
            size: size as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        enc.copy_buffer_to_buffer(src, 0, &buf, 0, size as u64);
        self.items.push((buf, size, size, 1));
        self.items.len() - 1
    }

    pub(crate) fn finish(self, gpu: &Gpu) -> Result<Vec<Vec<u8>>, RenderError> {
        type MapStatus = Option<Result<(), wgpu::BufferAsyncError>>;
        let status: std::sync::Arc<std::sync::Mutex<Vec<MapStatus>>> =
            std::sync::Arc::new(std::sync::Mutex::new(vec![None; self.items.len()]));
        for (k, (buf, ..)) in self.items.iter().enumerate() {
            let st = status.clone();
            buf.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                if let Ok(mut v) = st.lock() {
                    v[k] = Some(r);
                }
            });
        }
        gpu.wait()?;
        let st = status.lock().map_err(|_| RenderError::Gpu("map status poisoned".into()))?;
        let mut out = Vec::with_capacity(self.items.len());
        for (k, (buf, padded, row, rows)) in self.items.iter().enumerate() {
            match &st[k] {
                Some(Ok(())) => {}
                Some(Err(e)) => return Err(RenderError::Gpu(format!("mapping a read-back buffer: {e}"))),
                None => return Err(RenderError::Gpu("a read-back buffer was never mapped".into())),
            }
            let mapped = buf.get_mapped_range(..).map_err(|e| RenderError::Gpu(format!("read-back range: {e:?}")))?;
            let mut v = Vec::with_capacity((*row * *rows) as usize);
            for r in 0..*rows as usize {
                let start = r * *padded as usize;
                v.extend_from_slice(&mapped[start..start + *row as usize]);
            }
            drop(mapped);
            buf.unmap();
            out.push(v);
        }
        Ok(out)
    }
}

/// IEEE binary16 → f32 (for the Rgba16Float normal target).
pub(crate) fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0f32 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * (-24f32).exp2(),
        31 => {
            if frac == 0.0 {
                sign * f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => sign * (1.0 + frac / 1024.0) * ((exp - 15) as f32).exp2(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode() {
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0xbc00), -1.0);
        assert_eq!(half_to_f32(0x3800), 0.5);
        assert_eq!(half_to_f32(0x0000), 0.0);
        assert_eq!(half_to_f32(0x7bff), 65504.0);
        assert_eq!(half_to_f32(0x0001), (-24f32).exp2());
        assert!(half_to_f32(0x7e00).is_nan());
    }
}
