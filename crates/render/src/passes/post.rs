//! Screen-space passes after the G-buffer: the eye-space blur of the shadow term [SCH05 §4.3]
//! (separable, ping-ponging between two targets) and the lit composite.

use glam::Mat4;
use wgpu::util::DeviceExt;

use super::gbuffer::Targets;
use super::{cleared, mat, strided, view, UNIFORM_STRIDE};
use crate::frame::RenderRequest;
use crate::timer::{PhaseTimer, MAIN_PHASE};
use crate::types::{EyeBlur, LightSpec};
use crate::uniforms::{BlurUniform, CompositeUniform};

pub(crate) struct PostPass {
    /// The blur, when it does anything.
    pub blur: Option<EyeBlur>,
    /// Reading vis b writing vis a, and the reverse.
    blur_reads: [wgpu::BindGroup; 2],
    vis: [wgpu::TextureView; 2],
    composite: wgpu::BindGroup,
    color: wgpu::TextureView,
}

impl PostPass {
    pub fn new(
        device: &wgpu::Device,
        blur_layout: &wgpu::BindGroupLayout,
        composite_layout: &wgpu::BindGroupLayout,
        req: &RenderRequest,
        t: &Targets,
    ) -> PostPass {
        let s = &req.settings;
        let focal_px = 0.5 * s.height as f64 / (0.5 * req.camera.fovy).tan();
        let blur = s.blur.filter(|b| b.iterations > 0 && b.world_radius > 0.0 && b.max_radius_px > 0.0);
        // Uniforms for (horizontal from aux), (horizontal), (vertical).
        let variants: Vec<BlurUniform> = match blur {
            Some(b) => [([1.0, 0.0], 1.0), ([1.0, 0.0], 0.0), ([0.0, 1.0], 0.0)]
                .iter()
                .map(|(dir, from_aux)| BlurUniform {
                    a: [dir[0], dir[1], focal_px as f32, b.world_radius],
                    b: [b.max_radius_px, *from_aux, 0.0, 0.0],
                })
                .collect(),
            None => Vec::new(),
        };
        let blur_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("blur"),
            contents: &strided(&variants, 3),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let aux = view(&t.aux);
        let vis = [view(&t.vis[0]), view(&t.vis[1])];
        let blur_reading = |src: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("blur"),
                layout: blur_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &blur_buf,
                            offset: 0,
                            size: wgpu::BufferSize::new(std::mem::size_of::<BlurUniform>() as u64),
                        }),
                    },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&aux) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(src) },
                ],
            })
        };
        let blur_reads = [blur_reading(&vis[0]), blur_reading(&vis[1])];

        let spot = req.light.spot_matrix().map(|m| m.as_mat4()).unwrap_or(Mat4::IDENTITY);
        let (lvec, lkind) = match req.light {
            LightSpec::Directional { direction } => (direction, 0.0),
            LightSpec::Point { position } => (position, 1.0),
            LightSpec::Spot { position, .. } => (position, 2.0),
        };
        let comp = CompositeUniform {
            spot: mat(spot),
            light: [lvec.x as f32, lvec.y as f32, lvec.z as f32, lkind],
            flags: [if blur.is_some() { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
        };
        let comp_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("composite"),
            contents: bytemuck::bytes_of(&comp),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // After n iterations of (H: → a, V: a → b) the result is in b.
        let composite = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: composite_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: comp_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view(&t.world)) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&view(&t.normal)) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&view(&t.albedo)) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&aux) },
                wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(&vis[1]) },
            ],
        });
        PostPass { blur, blur_reads, vis, composite, color: view(&t.color) }
    }

    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        blur_pipeline: &wgpu::RenderPipeline,
        composite_pipeline: &wgpu::RenderPipeline,
        timer: Option<&PhaseTimer>,
    ) {
        if let Some(b) = self.blur {
            for it in 0..b.iterations {
                // Horizontal: (aux or b) → a; vertical: a → b.
                let h_off = if it == 0 { 0 } else { UNIFORM_STRIDE as u32 };
                for (dst, bg, off) in
                    [(&self.vis[0], &self.blur_reads[1], h_off), (&self.vis[1], &self.blur_reads[0], 2 * UNIFORM_STRIDE as u32)]
                {
                    let att = [cleared(dst, wgpu::Color::WHITE)];
                    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                        label: Some("blur"),
                        color_attachments: &att,
                        depth_stencil_attachment: None,
                        timestamp_writes: None,
                        occlusion_query_set: None,
                        multiview_mask: None,
                    });
                    pass.set_pipeline(blur_pipeline);
                    pass.set_bind_group(0, bg, &[off]);
                    pass.draw(0..3, 0..1);
                }
            }
        }
        let att = [cleared(&self.color, wgpu::Color::BLACK)];
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("composite"),
            color_attachments: &att,
            depth_stencil_attachment: None,
            timestamp_writes: timer.and_then(|t| t.writes(MAIN_PHASE, 1, 2)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(composite_pipeline);
        pass.set_bind_group(0, &self.composite, &[]);
        pass.draw(0..3, 0..1);
    }
}
