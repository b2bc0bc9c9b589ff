//! The shadow pass: one depth layer per map, each drawn with only that map's casters, through a
//! dynamic offset into one buffer of per-map uniforms.

use std::ops::Range;

use wgpu::util::DeviceExt;

use super::{cleared, layer_view, mat, strided, tex2d, Geometry, DEPTH_FMT, UNIFORM_STRIDE, VIZ_FMT};
use crate::frame::RenderRequest;
use crate::scene::Scene;
use crate::timer::{PhaseTimer, SHADOW_PHASE};
use crate::types::DepthTest;
use crate::uniforms::ShadowUniform;

pub(crate) struct ShadowPass {
    /// The depth layers, one per map.
    pub depth: wgpu::Texture,
    /// The rasterised depths as colour, for read-back (`save_shadow_maps`).
    pub viz: Option<wgpu::Texture>,
    /// Per map, the index ranges of its casters.
    pub ranges: Vec<Vec<Range<u32>>>,
    bind_group: wgpu::BindGroup,
    layer_views: Vec<wgpu::TextureView>,
    viz_views: Vec<wgpu::TextureView>,
    /// The farthest depth: 1, or 0 in a reversed buffer.
    clear: f32,
    /// Per map, its side in texels: it is drawn into its layer's top-left `side²` texels (the
    /// rest stays cleared: no caster).
    sides: Vec<f32>,
}

impl ShadowPass {
    /// `lin_a`, `lin_b`: the linear-depth parameters of `shadow.wgsl` (`lin_b.w` is set per map).
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        req: &RenderRequest,
        layers: u32,
        lin_a: [f32; 4],
        lin_b: [f32; 4],
    ) -> ShadowPass {
        let s = &req.settings;
        let res = req.array_resolution();
        let depth = tex2d(
            device,
            "shadow maps",
            res,
            res,
            layers,
            DEPTH_FMT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let viz = s.save_shadow_maps.then(|| {
            tex2d(device, "shadow viz", res, res, layers, VIZ_FMT, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC)
        });
        let uniforms: Vec<ShadowUniform> = req
            .maps
            .iter()
            .map(|m| {
                let flip = if req.stores_flipped(m) { 1.0 } else { 0.0 };
                ShadowUniform { world_to_clip: mat(m.world_to_clip), lin_a, lin_b: [lin_b[0], lin_b[1], lin_b[2], flip] }
            })
            .collect();
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shadow uniforms"),
            contents: &strided(&uniforms, 1),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<ShadowUniform>() as u64),
                }),
            }],
        });
        let ranges = req.maps.iter().map(|m| caster_ranges(req.scene, &m.casters)).collect();
        let n = req.maps.len() as u32;
        let layer_views = (0..n).map(|i| layer_view(&depth, i)).collect();
        let viz_views = viz.as_ref().map(|v| (0..n).map(|i| layer_view(v, i)).collect()).unwrap_or_default();
        let clear = if req.shadow_buffer_test() == DepthTest::Greater { 0.0 } else { 1.0 };
        let sides = req.maps.iter().map(|m| req.map_resolution(m) as f32).collect();
        ShadowPass { depth, viz, ranges, bind_group, layer_views, viz_views, clear, sides }
    }

    /// The depth layers as the array the main pass samples.
    pub fn array_view(&self) -> wgpu::TextureView {
        self.depth.create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() })
    }

    pub fn encode(&self, enc: &mut wgpu::CommandEncoder, pipeline: &wgpu::RenderPipeline, geometry: &Geometry, timer: Option<&PhaseTimer>) {
        let count = self.layer_views.len();
        for (i, layer) in self.layer_views.iter().enumerate() {
            // All-ones bits: a NaN, read back as "no caster here".
            let viz = self.viz_views.get(i).and_then(|v| cleared(v, wgpu::Color { r: u32::MAX as f64, g: 0.0, b: 0.0, a: 0.0 }));
            let color_atts = [viz];
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow layer"),
                color_attachments: if self.viz_views.is_empty() { &[] } else { &color_atts },
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: layer,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(self.clear), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.and_then(|t| t.writes(SHADOW_PHASE, i, count)),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_viewport(0.0, 0.0, self.sides[i], self.sides[i], 0.0, 1.0);
            pass.set_bind_group(0, &self.bind_group, &[(i as u64 * UNIFORM_STRIDE) as u32]);
            geometry.bind(&mut pass);
            for r in &self.ranges[i] {
                pass.draw_indexed(r.clone(), 0, 0..1);
            }
        }
    }
}

/// Contiguous index ranges drawing `casters` (sorted, deduplicated): neighbouring objects whose
/// ranges touch become one draw call, so culled sets of thousands of objects stay cheap.
pub(crate) fn caster_ranges(scene: &Scene, casters: &[u32]) -> Vec<std::ops::Range<u32>> {
    let mut ids: Vec<u32> = casters.to_vec();
    ids.sort_unstable();
    ids.dedup();
    let mut objs: Vec<(u32, u32)> = ids
        .iter()
        .map(|&i| {
            let o = &scene.objects[i as usize];
            (o.first_index, o.first_index + o.index_count)
        })
        .collect();
    objs.sort_unstable();
    let mut out: Vec<std::ops::Range<u32>> = Vec::new();
    for (a, b) in objs {
        match out.last_mut() {
            Some(r) if r.end >= a => r.end = r.end.max(b),
            _ => out.push(a..b),
        }
    }
    out.retain(|r| r.end > r.start);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caster_ranges_merge_neighbouring_objects() {
        let scene = crate::scenes::builtin_scene("inverted").unwrap();
        let o = &scene.objects;
        let all = caster_ranges(&scene, &scene.all_objects());
        assert_eq!(all, vec![0..scene.indices.len() as u32]);
        let r = caster_ranges(&scene, &[2, 0, 0, 1, 5]);
        assert_eq!(r, vec![o[0].first_index..o[2].first_index + o[2].index_count, o[5].first_index..o[5].first_index + o[5].index_count]);
        assert!(caster_ranges(&scene, &[]).is_empty());
    }
}
