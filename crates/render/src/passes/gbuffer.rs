//! The main pass: the scene into the G-buffer (world position, normal, albedo, and an auxiliary
//! target with aliasing, view depth, shadow term and the map each pixel used), each pixel's
//! shadow looked up in the map that serves its view depth.

use wgpu::util::DeviceExt;

use super::{cleared, mat, tex2d, view, Geometry, ALBEDO_FMT, AUX_FMT, COLOR_FMT, DEPTH_FMT, NORMAL_FMT, VIS_FMT, WORLD_FMT};
use crate::error::RenderError;
use crate::frame::RenderRequest;
use crate::timer::{PhaseTimer, MAIN_PHASE};
use crate::types::{Pcf, MAX_MAPS};
use crate::uniforms::{FrameUniform, MapInfo};

/// Constant term of the per-map depth bias, in the map's depth units ([0, 1]): four steps of
/// `Depth32Float` at 1 (2⁻²⁴ each), which bounds the storage rounding of the caster's depth and the
/// rasteriser's interpolation error relative to its triangle's depths (at most 1). The rounding of
/// the receiver's own depth is bounded per fragment (`depth_rounding` in `scene.wgsl`).
const RECEIVER_PLANE_CONSTANT: f32 = 4.0 / 16_777_216.0;

/// The slope term is capped at this tan θ (θ = 87°, the receiver's tilt to the light ray):
/// a plane nearly containing the light ray has an unbounded depth slope per texel, and an
/// unbounded bias would let it receive no shadow at all. Such surfaces get almost no light
/// (cos θ < 0.05) and are sampled by the map along a line. Beyond the cap they shadow
/// themselves in part, which the mismatch counts where the screen samples them coarsely
/// enough to pass as adequately sampled (a far wall under a high sun: the robot war's
/// 0.2 % at 480×270, sun 65°, azimuth 270°). Without the cap the leaks cost more: the mean
/// mismatch over the light sweep (`shadowfocus sweep --methods uniform,auto4,lispsm4 --size
/// 320x180`) falls in the robot war (0.48 → 0.18 %) and rises in five other scenes (the
/// forest 0.47 → 0.55 %).
const RECEIVER_PLANE_MAX_TAN: f32 = 19.08;

/// The frame's screen targets.
pub(crate) struct Targets {
    pub world: wgpu::Texture,
    pub normal: wgpu::Texture,
    pub albedo: wgpu::Texture,
    pub aux: wgpu::Texture,
    pub depth: wgpu::Texture,
    /// Ping-pong targets of the blur.
    pub vis: [wgpu::Texture; 2],
    pub color: wgpu::Texture,
}

impl Targets {
    fn new(device: &wgpu::Device, w: u32, h: u32) -> Targets {
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        Targets {
            world: tex2d(device, "world", w, h, 1, WORLD_FMT, rt),
            normal: tex2d(device, "normal", w, h, 1, NORMAL_FMT, rt),
            albedo: tex2d(device, "albedo", w, h, 1, ALBEDO_FMT, rt),
            aux: tex2d(device, "aux", w, h, 1, AUX_FMT, rt),
            depth: tex2d(device, "depth", w, h, 1, DEPTH_FMT, wgpu::TextureUsages::RENDER_ATTACHMENT),
            vis: [tex2d(device, "vis a", w, h, 1, VIS_FMT, rt), tex2d(device, "vis b", w, h, 1, VIS_FMT, rt)],
            color: tex2d(device, "color", w, h, 1, COLOR_FMT, rt),
        }
    }
}

/// How the main pass compares depths: the linear-depth parameters and whether the receiver-plane
/// bias is on.
#[derive(Clone, Copy)]
pub(crate) struct DepthLookup {
    pub lin_a: [f32; 4],
    pub lin_b: [f32; 4],
    pub receiver_plane: bool,
    /// The shadow buffer is reversed ("greater").
    pub greater: bool,
}

pub(crate) struct GBufferPass {
    pub targets: Targets,
    bind_group: wgpu::BindGroup,
    views: [wgpu::TextureView; 5],
}

impl GBufferPass {
    /// `samplers`: the bilinear and the nearest comparison sampler, for a \"less\" and a reversed buffer.
    pub fn new(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        samplers: &[[wgpu::Sampler; 2]; 2],
        req: &RenderRequest,
        depth: DepthLookup,
        shadow_maps: &wgpu::TextureView,
    ) -> Result<GBufferPass, RenderError> {
        let s = &req.settings;
        let frame = frame_uniform(req, depth)?;
        let frame_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // The receiver-plane bias compares each texel with its own reference (bilinear weights in
        // the shader), through the nearest sampler.
        let samplers = &samplers[depth.greater as usize];
        let sampler = if s.pcf == Pcf::Off || depth.receiver_plane { &samplers[1] } else { &samplers[0] };
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(shadow_maps) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(sampler) },
            ],
        });
        let targets = Targets::new(device, s.width, s.height);
        let views = [view(&targets.world), view(&targets.normal), view(&targets.albedo), view(&targets.aux), view(&targets.depth)];
        Ok(GBufferPass { targets, bind_group, views })
    }

    pub fn encode(&self, enc: &mut wgpu::CommandEncoder, pipeline: &wgpu::RenderPipeline, geometry: &Geometry, timer: Option<&PhaseTimer>) {
        let zero = wgpu::Color { r: 0.0, g: 0.0, b: 0.0, a: 0.0 };
        let [world, normal, albedo, aux, depth] = &self.views;
        let atts = [cleared(world, zero), cleared(normal, zero), cleared(albedo, zero), cleared(aux, zero)];
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("g-buffer"),
            color_attachments: &atts,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: timer.and_then(|t| t.writes(MAIN_PHASE, 0, 2)),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        geometry.bind(&mut pass);
        pass.draw_indexed(0..geometry.index_count, 0, 0..1);
    }
}

/// The main pass's uniform block: camera, linear depth, lookup parameters and every map.
fn frame_uniform(req: &RenderRequest, depth: DepthLookup) -> Result<FrameUniform, RenderError> {
    let s = &req.settings;
    let view_proj = (req.camera.projection_matrix(req.aspect()) * req.camera.view_matrix()?).as_mat4();
    let (fwd, _, _) = req.camera.basis()?;
    let mut maps = [MapInfo { world_to_clip: [0.0; 16], split: [0.0; 4], face: [0.0, 0.0, 0.0, -1.0], size: [1.0; 4] }; MAX_MAPS];
    let array = req.array_resolution();
    for (i, m) in req.maps.iter().enumerate() {
        let side = req.map_resolution(m);
        maps[i] = MapInfo {
            world_to_clip: mat(m.world_to_clip),
            split: [m.split[0], m.split[1], if req.stores_flipped(m) { 1.0 } else { 0.0 }, if depth.greater { -1.0 } else { 1.0 }],
            face: match m.face {
                Some(c) => [c.light.x as f32, c.light.y as f32, c.light.z as f32, c.index as f32],
                None => [0.0, 0.0, 0.0, -1.0],
            },
            size: [side as f32, (side as f64 / array as f64) as f32, 0.0, 0.0],
        };
    }
    let (pcf_mode, pcf_radius) = match s.pcf {
        Pcf::Off => (0.0, 0.0),
        Pcf::Hardware2x2 => (1.0, 0.0),
        Pcf::Kernel { radius } => (2.0, radius as f32),
    };
    let eye = req.camera.eye;
    Ok(FrameUniform {
        view_proj: mat(view_proj),
        eye: [eye.x as f32, eye.y as f32, eye.z as f32, 1.0],
        forward: [fwd.x as f32, fwd.y as f32, fwd.z as f32, req.scene.surface_offset() as f32],
        cam: [req.camera.near as f32, req.camera.far as f32, s.width as f32, s.height as f32],
        lin_a: depth.lin_a,
        lin_b: depth.lin_b,
        params: [req.maps.len() as f32, 0.0, pcf_mode, pcf_radius],
        params2: [s.blend_band, if depth.receiver_plane { 1.0 } else { 0.0 }, RECEIVER_PLANE_CONSTANT, RECEIVER_PLANE_MAX_TAN],
        maps,
    })
}
