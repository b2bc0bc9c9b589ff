//! The passes of one frame, in the order the renderer records them:
//!
//! 1. [`shadow`]: one depth layer per shadow map, casters only;
//! 2. [`gbuffer`]: world position, normal, albedo, shadow term, aliasing and the map each pixel
//!    used, into integer and float targets;
//! 3. [`post`]: the eye-space blur of the shadow term [SCH05 §4.3] and the lit composite;
//! 4. [`reduce`]: the visible depth range and the receivers' slices, where the adapter has
//!    compute shaders;
//! 5. [`readback`]: the targets back into memory, decoded per pixel.
//!
//! Each pass creates what it needs for one frame in `new` and records itself into a command
//! encoder in `encode`; [`crate::Renderer`] owns the pipelines and only sequences the passes.

pub(crate) mod gbuffer;
pub(crate) mod post;
pub(crate) mod readback;
pub(crate) mod reduce;
pub(crate) mod shadow;

use wgpu::util::DeviceExt;

use crate::scene::Scene;

/// Uniform offsets must be multiples of this on every backend.
pub(crate) const UNIFORM_STRIDE: u64 = 256;

// NOTE: 32-bit float colour targets are not renderable through wgpu's GL backend on Mesa (it
// looks for a colour-buffer-float extension that a core profile does not list), so f32 data are
// written as bit patterns into 32-bit integer targets, which every backend can render to.
pub(crate) const WORLD_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
pub(crate) const NORMAL_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
pub(crate) const ALBEDO_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub(crate) const AUX_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
pub(crate) const VIS_FMT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
pub(crate) const VIZ_FMT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
pub(crate) const COLOR_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub(crate) const DEPTH_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub(crate) fn tex2d(
    device: &wgpu::Device,
    label: &str,
    w: u32,
    h: u32,
    layers: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: layers },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

pub(crate) fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor::default())
}

pub(crate) fn layer_view(t: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

pub(crate) fn mat(m: glam::Mat4) -> [f32; 16] {
    m.to_cols_array()
}

/// `items` laid out `UNIFORM_STRIDE` apart (at least `slots` of them), for dynamic offsets.
pub(crate) fn strided<T: bytemuck::Pod>(items: &[T], slots: usize) -> Vec<u8> {
    let mut bytes = vec![0u8; UNIFORM_STRIDE as usize * slots.max(items.len()).max(1)];
    for (i, u) in items.iter().enumerate() {
        let off = i * UNIFORM_STRIDE as usize;
        bytes[off..off + std::mem::size_of::<T>()].copy_from_slice(bytemuck::bytes_of(u));
    }
    bytes
}

/// A colour attachment cleared to `clear` and stored.
pub(crate) fn cleared(view: &wgpu::TextureView, clear: wgpu::Color) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store },
    })
}

/// The scene's vertices (the receiver flag in the colour's alpha: 255 = receiver) and indices.
pub(crate) struct Geometry {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

impl Geometry {
    pub fn upload(device: &wgpu::Device, scene: &Scene) -> Geometry {
        let mut verts = scene.vertices.clone();
        for v in verts.iter_mut() {
            v.color[3] = 0;
        }
        for o in &scene.objects {
            if o.receiver {
                for &i in &scene.indices[o.first_index as usize..(o.first_index + o.index_count) as usize] {
                    verts[i as usize].color[3] = 255;
                }
            }
        }
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vertices"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("indices"),
            contents: bytemuck::cast_slice(&scene.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Geometry { vertices, indices, index_count: scene.indices.len() as u32 }
    }

    pub fn bind<'a>(&'a self, pass: &mut wgpu::RenderPass<'a>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
    }
}
