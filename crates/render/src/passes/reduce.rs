//! The visible depth range on the GPU: a compute pass over the G-buffer's world positions into
//! two atomic words (the least and greatest view depth of any pixel that sees geometry), read
//! back as eight bytes. Adapters without compute shaders (some GL ES devices) have no such pass;
//! the caller then reduces the read-back positions on the CPU.

use wgpu::util::DeviceExt;

/// Threads per workgroup side (`@workgroup_size(8, 8)` in `reduce.wgsl`).
const GROUP: u32 = 8;

/// The pipeline, built once per renderer.
pub(crate) struct DepthReduce {
    bgl: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// One frame's reduction: its result buffer (two u32 words, f32 bits).
pub(crate) struct Reduced {
    pub range: wgpu::Buffer,
}

impl DepthReduce {
    pub fn new(device: &wgpu::Device) -> DepthReduce {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("reduce"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/reduce.wgsl").into()),
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
        let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("reduce"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Uint,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(
                    1,
                    wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None },
                ),
                entry(
                    2,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("reduce"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("reduce"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        DepthReduce { bgl, pipeline }
    }

    /// Records the reduction of `world` (`w × h`) for the camera at `eye` looking along the unit
    /// `forward`.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        world: &wgpu::Texture,
        (w, h): (u32, u32),
        eye: [f32; 3],
        forward: [f32; 3],
    ) -> Reduced {
        let mut view = [0u8; 48];
        let words: [u32; 12] = [
            eye[0].to_bits(),
            eye[1].to_bits(),
            eye[2].to_bits(),
            0,
            forward[0].to_bits(),
            forward[1].to_bits(),
            forward[2].to_bits(),
            0,
            w,
            h,
            0,
            0,
        ];
        view.copy_from_slice(bytemuck::cast_slice(&words));
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("reduce view"),
            contents: &view,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Least starts at the greatest bit pattern, greatest at 0.
        let range = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("visible depth"),
            contents: bytemuck::cast_slice(&[u32::MAX, 0u32]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let texture_view = world.create_view(&wgpu::TextureViewDescriptor::default());
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("reduce"),
            layout: &self.bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&texture_view) },
                wgpu::BindGroupEntry { binding: 1, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: range.as_entire_binding() },
            ],
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("reduce"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(GROUP), h.div_ceil(GROUP), 1);
        drop(pass);
        Reduced { range }
    }
}

/// The range from the read-back words; `None` where no pixel saw geometry.
pub(crate) fn decode(bytes: &[u8]) -> Option<[f32; 2]> {
    let w: Vec<u32> = bytemuck::pod_collect_to_vec::<u8, u32>(bytes);
    let (lo, hi) = (f32::from_bits(*w.first()?), f32::from_bits(*w.get(1)?));
    (lo <= hi).then_some([lo, hi])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_decode_to_the_range_or_nothing() {
        let b = |a: f32, z: f32| bytemuck::cast_slice::<u32, u8>(&[a.to_bits(), z.to_bits()]).to_vec();
        assert_eq!(decode(&b(0.5, 120.25)), Some([0.5, 120.25]));
        // Untouched words (no pixel saw geometry): u32::MAX is a NaN pattern, 0 is 0.0.
        assert_eq!(decode(bytemuck::cast_slice::<u32, u8>(&[u32::MAX, 0u32])), None);
    }
}
