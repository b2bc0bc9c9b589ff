//! The visible depth range on the GPU: a compute pass over the G-buffer's world positions into
//! two atomic words (the least and greatest view depth of any pixel that sees geometry), read
//! back as eight bytes; where asked for, in the same pass, the receiver pixels' bounds and
//! greatest view depth per slice of the view and axis their normal faces (seven words a
//! slice). Adapters without compute
//! shaders (some GL ES devices) have no such pass; the caller then reduces the read-back
//! positions on the CPU.

use wgpu::util::DeviceExt;

use crate::frame::{ReceiverSlice, ReceiverSlices};
use crate::types::RECEIVER_SLICES;

/// Threads per workgroup side (`@workgroup_size(8, 8)` in `reduce.wgsl`).
const GROUP: u32 = 8;

/// The pipeline, built once per renderer.
pub(crate) struct DepthReduce {
    bgl: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

/// Words per slice (`SLICE_WORDS` in `reduce.wgsl`): min x, y, z, max x, y, z, greatest depth.
const SLICE_WORDS: usize = 7;

/// Words of the slices, of every facing axis (`slices` in `reduce.wgsl`).
const WORDS: usize = 3 * RECEIVER_SLICES * SLICE_WORDS;

/// Bytes of the slices' words.
pub(crate) const SLICES_BYTES: u32 = (WORDS * 4) as u32;

/// One frame's reduction: its result buffers (two u32 words, f32 bits; the slices' ordered
/// words, read back only where they were asked for).
pub(crate) struct Reduced {
    pub range: wgpu::Buffer,
    pub slices: Option<wgpu::Buffer>,
}

impl DepthReduce {
    pub fn new(device: &wgpu::Device) -> DepthReduce {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("reduce"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/reduce.wgsl").into()),
        });
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
        let storage = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
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
                entry(2, storage),
                entry(3, storage),
                entry(
                    4,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
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
    /// `forward`, and of its receiver pixels into the slices between `planes` where given, by the
    /// axis their `normals` face.
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        (world, normals): (&wgpu::Texture, &wgpu::Texture),
        (w, h): (u32, u32),
        eye: [f32; 3],
        forward: [f32; 3],
        planes: Option<&[f32; RECEIVER_SLICES - 1]>,
    ) -> Reduced {
        let mut words = [0u32; 28];
        words[..3].copy_from_slice(&eye.map(f32::to_bits));
        words[4..7].copy_from_slice(&forward.map(f32::to_bits));
        words[8..11].copy_from_slice(&[w, h, planes.is_some() as u32]);
        if let Some(p) = planes {
            words[12..12 + p.len()].copy_from_slice(&p.map(f32::to_bits));
        }
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("reduce view"),
            contents: bytemuck::cast_slice(&words),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // Least starts at the greatest bit pattern, greatest at 0.
        let range = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("visible depth"),
            contents: bytemuck::cast_slice(&[u32::MAX, 0u32]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        // Each slice's least words start at the greatest pattern, its greatest at 0.
        let empty: [u32; WORDS] = std::array::from_fn(|i| if i % SLICE_WORDS < 3 { u32::MAX } else { 0 });
        let slices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("receiver slices"),
            contents: bytemuck::cast_slice(&empty),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let texture_view = world.create_view(&wgpu::TextureViewDescriptor::default());
        let normal_view = normals.create_view(&wgpu::TextureViewDescriptor::default());
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("reduce"),
            layout: &self.bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&texture_view) },
                wgpu::BindGroupEntry { binding: 1, resource: uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: range.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: slices.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&normal_view) },
            ],
        });
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("reduce"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(w.div_ceil(GROUP), h.div_ceil(GROUP), 1);
        drop(pass);
        Reduced { range, slices: planes.is_some().then_some(slices) }
    }
}

/// The range from the read-back words; `None` where no pixel saw geometry.
pub(crate) fn decode(bytes: &[u8]) -> Option<[f32; 2]> {
    let w: Vec<u32> = bytemuck::pod_collect_to_vec::<u8, u32>(bytes);
    let (lo, hi) = (f32::from_bits(*w.first()?), f32::from_bits(*w.get(1)?));
    (lo <= hi).then_some([lo, hi])
}

/// The f32 of an `ordered` word (`reduce.wgsl`).
fn unordered(k: u32) -> f32 {
    f32::from_bits(if k >> 31 == 1 { k & 0x7fff_ffff } else { !k })
}

/// The slices from their read-back words, per facing axis; a slice's `None` where no receiver
/// pixel fell in it.
pub(crate) fn decode_slices(bytes: &[u8]) -> ReceiverSlices {
    let w: Vec<u32> = bytemuck::pod_collect_to_vec::<u8, u32>(bytes);
    std::array::from_fn(|axis| std::array::from_fn(|k| slice(&w, axis * RECEIVER_SLICES + k)))
}

/// Slice `i`'s words, decoded.
fn slice(w: &[u32], i: usize) -> Option<ReceiverSlice> {
    let s = w.get(i * SLICE_WORDS..(i + 1) * SLICE_WORDS)?;
    // NOTE: untouched, a slice's least word is u32::MAX and its greatest 0; any pixel leaves
    // least ≤ greatest, in the words' order as in the floats'.
    (s[0] <= s[3]).then(|| ReceiverSlice {
        min: [s[0], s[1], s[2]].map(unordered),
        max: [s[3], s[4], s[5]].map(unordered),
        far: unordered(s[6]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ordered` of `reduce.wgsl`, for the tests.
    fn ordered(x: f32) -> u32 {
        let b = x.to_bits();
        if b >> 31 == 1 {
            !b
        } else {
            b | 0x8000_0000
        }
    }

    #[test]
    fn ordered_words_keep_the_floats_order_and_come_back() {
        let xs = [f32::NEG_INFINITY, -3.5e30, -1.0, -1e-40, -0.0, 0.0, 1e-40, 0.25, 1.0, 7.0e12, f32::INFINITY];
        for (a, b) in xs.iter().zip(&xs[1..]) {
            assert!(ordered(*a) < ordered(*b), "{a} {b}");
        }
        for x in xs {
            assert_eq!(unordered(ordered(x)).to_bits(), x.to_bits());
        }
    }

    #[test]
    fn slices_decode_to_their_bounds_or_nothing() {
        let mut w = [0u32; WORDS];
        for i in 0..3 * RECEIVER_SLICES {
            w[i * SLICE_WORDS..i * SLICE_WORDS + 3].fill(u32::MAX);
        }
        let filled = [-2.0f32, 0.5, -7.25, 3.0, 0.5, -1.0, 41.5].map(ordered);
        let i = RECEIVER_SLICES + 5;
        w[i * SLICE_WORDS..(i + 1) * SLICE_WORDS].copy_from_slice(&filled);
        let s = decode_slices(bytemuck::cast_slice(&w));
        assert_eq!(s.iter().flatten().filter(|s| s.is_some()).count(), 1);
        assert_eq!(s[1][5], Some(ReceiverSlice { min: [-2.0, 0.5, -7.25], max: [3.0, 0.5, -1.0], far: 41.5 }));
    }

    #[test]
    fn words_decode_to_the_range_or_nothing() {
        let b = |a: f32, z: f32| bytemuck::cast_slice::<u32, u8>(&[a.to_bits(), z.to_bits()]).to_vec();
        assert_eq!(decode(&b(0.5, 120.25)), Some([0.5, 120.25]));
        // Untouched words (no pixel saw geometry): u32::MAX is a NaN pattern, 0 is 0.0.
        assert_eq!(decode(bytemuck::cast_slice::<u32, u8>(&[u32::MAX, 0u32])), None);
    }
}
