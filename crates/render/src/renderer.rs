//! The headless renderer: shadow pass, G-buffer pass, eye-space blur, composite, read-back.

use std::collections::HashMap;
use std::time::Instant;

use glam::Mat4;
use wgpu::util::DeviceExt;

use crate::error::RenderError;
use crate::gpu::{AdapterSummary, BackendChoice, Gpu};
use crate::ground_truth::Visibility;
use crate::image::Image;
use crate::metrics::{self, RenderMetrics};
use crate::scene::{Scene, Vertex};
use crate::timer::{PhaseTimer, MAIN_PHASE, SHADOW_PHASE};
use crate::types::{validate_maps, CameraSpec, DepthMode, DepthTest, LightSpec, Pcf, RenderSettings, ShadowMapSpec, MAX_MAPS};
use crate::uniforms::{self, BlurUniform, CompositeUniform, FrameUniform, MapInfo, ShadowUniform};

/// One frame to render.
#[derive(Clone, Debug)]
pub struct RenderRequest<'a> {
    pub scene: &'a Scene,
    pub camera: CameraSpec,
    pub light: LightSpec,
    pub maps: &'a [ShadowMapSpec],
    /// Per map (in `maps` order), the fraction of the map's area that its focus body's projection
    /// covers (`shadowfocus_focus::ShadowMap::utilisation`), when the caller knows it: reported in
    /// the metrics. Empty when unknown; otherwise one value per map.
    pub utilisation: &'a [f64],
    pub settings: RenderSettings,
}

impl<'a> RenderRequest<'a> {
    /// The scene's own camera and light with default settings.
    pub fn new(scene: &'a Scene, maps: &'a [ShadowMapSpec]) -> RenderRequest<'a> {
        RenderRequest { scene, camera: scene.camera, light: scene.light, maps, utilisation: &[], settings: RenderSettings::default() }
    }

    pub fn aspect(&self) -> f64 {
        self.settings.width as f64 / self.settings.height as f64
    }

    pub fn validate(&self) -> Result<(), RenderError> {
        self.settings.validate()?;
        self.camera.validate()?;
        self.light.validate()?;
        validate_maps(self.maps, self.scene.objects.len())?;
        if !self.utilisation.is_empty() && self.utilisation.len() != self.maps.len() {
            return Err(RenderError::invalid("map utilisation", format!("{} values for {} maps", self.utilisation.len(), self.maps.len())));
        }
        if let Some(u) = self.utilisation.iter().find(|u| !(0.0..=1.0).contains(*u)) {
            return Err(RenderError::invalid("map utilisation", format!("{u} is not within [0, 1]")));
        }
        Ok(())
    }
}

/// A shadow map as read back: `resolution²` depths, rows top to bottom; NaN where no caster
/// was drawn. Depths are the rasterised values before bias (or the linear depth in linear mode).
#[derive(Clone, Debug)]
pub struct DepthMap {
    pub resolution: u32,
    pub depth: Vec<f32>,
    /// True for `DepthTest::Greater` maps in projective mode, which are stored as 1 − z so that
    /// every layer is compared with "less" (GL allows one comparison sampler per texture).
    pub reversed: bool,
}

/// Everything a render produced, per pixel (rows top to bottom) and summarised.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    pub width: u32,
    pub height: u32,
    /// The lit image.
    pub color: Image,
    /// xyz = world position; w = 1 receiver, 2 other geometry, 0 background.
    pub world: Vec<[f32; 4]>,
    /// Camera-facing unit normal (xyz).
    pub normal: Vec<[f32; 4]>,
    /// Screen pixels per shadow texel; < 0 where no map covers the pixel, NaN on background.
    pub aliasing: Vec<f32>,
    /// Index of the map each pixel used; −1 none (or background).
    pub split: Vec<i32>,
    /// Final shadow term in [0, 1] (after the optional blur); 1 = lit.
    pub shadow: Vec<f32>,
    /// Ray-cast ground truth, when requested.
    pub truth: Option<Vec<Visibility>>,
    /// The shadow maps, when `save_shadow_maps` was set.
    pub shadow_maps: Vec<DepthMap>,
    /// The camera and light the frame was rendered with.
    pub camera: CameraSpec,
    pub light: LightSpec,
    pub metrics: RenderMetrics,
}

/// Renders one request with a freshly opened adapter chosen by `SHADOWFOCUS_BACKEND`.
/// For many frames keep a [`Renderer`] instead (opening an adapter takes tens of milliseconds).
pub fn render_scene(req: &RenderRequest) -> Result<RenderOutput, RenderError> {
    Renderer::from_env()?.render(req)
}

/// Uniform offsets must be multiples of this on every backend.
const UNIFORM_STRIDE: u64 = 256;

// NOTE: 32-bit float colour targets are not renderable through wgpu's GL backend on Mesa (it
// looks for a colour-buffer-float extension that a core profile does not list), so f32 data are
// written as bit patterns into 32-bit integer targets, which every backend can render to.
const WORLD_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
const NORMAL_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const ALBEDO_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const AUX_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Uint;
const VIS_FMT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
const VIZ_FMT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;
const COLOR_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FMT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Constant term of the per-map depth bias, in the map's depth units ([0, 1]): four steps of
/// `Depth32Float` at 1 (2⁻²⁴ each), which bounds the storage rounding of the caster's depth and the
/// rasteriser's interpolation error relative to its triangle's depths (at most 1). The rounding of
/// the receiver's own depth is bounded per fragment (`depth_rounding` in `scene.wgsl`).
const RECEIVER_PLANE_CONSTANT: f32 = 4.0 / 16_777_216.0;

/// The slope term is capped at this tan θ (θ = 87°, the receiver's tilt to the light ray):
/// a plane nearly containing the light ray has an unbounded depth slope per texel, and an
/// unbounded bias would let it receive no shadow at all. Such surfaces get almost no light
/// (cos θ < 0.05) and are sampled by the map along a line, never adequately.
const RECEIVER_PLANE_MAX_TAN: f32 = 19.08;

#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct ShadowPipelineKey {
    viz: bool,
    linear: bool,
    constant: i32,
    slope_bits: u32,
    clamp: bool,
}

/// An open device with compiled pipelines; reuse it across frames.
pub struct Renderer {
    gpu: Gpu,
    shadow_module: wgpu::ShaderModule,
    shadow_layout: wgpu::PipelineLayout,
    shadow_bgl: wgpu::BindGroupLayout,
    shadow_pipelines: HashMap<ShadowPipelineKey, wgpu::RenderPipeline>,
    scene_bgl: wgpu::BindGroupLayout,
    scene_pipeline: wgpu::RenderPipeline,
    blur_bgl: wgpu::BindGroupLayout,
    blur_pipeline: wgpu::RenderPipeline,
    composite_bgl: wgpu::BindGroupLayout,
    composite_pipeline: wgpu::RenderPipeline,
    /// Bilinear and nearest "less-equal" comparison samplers.
    samplers: [wgpu::Sampler; 2],
}

fn uniform_entry(binding: u32, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: dynamic, min_binding_size: None },
        count: None,
    }
}

fn float_texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    texture_entry(binding, wgpu::TextureSampleType::Float { filterable: false })
}

fn uint_texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    texture_entry(binding, wgpu::TextureSampleType::Uint)
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled: false },
        count: None,
    }
}

fn comparison_sampler(device: &wgpu::Device, compare: wgpu::CompareFunction, filter: wgpu::FilterMode) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("shadow comparison"),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: filter,
        min_filter: filter,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        lod_min_clamp: 0.0,
        lod_max_clamp: 0.0,
        compare: Some(compare),
        anisotropy_clamp: 1,
        border_color: None,
    })
}

fn target(format: wgpu::TextureFormat) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })
}

fn fullscreen_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    bgl: &wgpu::BindGroupLayout,
    entry: &str,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(bgl)],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        vertex: wgpu::VertexState { module, entry_point: Some("vs"), compilation_options: Default::default(), buffers: &[] },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &[target(format)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

const VERTEX_ATTRS: [wgpu::VertexAttribute; 2] = [
    wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x3, offset: 0, shader_location: 0 },
    wgpu::VertexAttribute { format: wgpu::VertexFormat::Unorm8x4, offset: 12, shader_location: 1 },
];

fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRS,
    }
}

fn shadow_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRS[..1],
    }
}

fn mat(m: Mat4) -> [f32; 16] {
    m.to_cols_array()
}

/// Linear-depth parameters (mode, a, b) for the shaders, normalised over the scene bounds.
///
/// Directional: d(p) = (l̂·p − min)/(max − min) over the box corners. Point/spot:
/// d(p) = |p − light| / max corner distance. NOTE: the box is centred near the origin in every
/// scene here, so the affine form's constant term is O(1) and the f32 evaluation loses no
/// more than a few ulps of [0, 1].
fn linear_params(light: &LightSpec, scene: &Scene) -> ([f32; 4], f32) {
    let corners = scene.bounds.corners();
    match *light {
        LightSpec::Directional { direction } => {
            let l = direction.normalize();
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for c in corners {
                lo = lo.min(l.dot(c));
                hi = hi.max(l.dot(c));
            }
            let span = (hi - lo).max(1e-30);
            let a = l / span;
            ([a.x as f32, a.y as f32, a.z as f32, (-lo / span) as f32], 1.0)
        }
        LightSpec::Point { position } | LightSpec::Spot { position, .. } => {
            let far = corners.iter().map(|c| (*c - position).length()).fold(0.0, f64::max).max(1e-30);
            ([position.x as f32, position.y as f32, position.z as f32, (1.0 / far) as f32], 2.0)
        }
    }
}

struct Targets {
    world: wgpu::Texture,
    normal: wgpu::Texture,
    albedo: wgpu::Texture,
    aux: wgpu::Texture,
    depth: wgpu::Texture,
    vis: [wgpu::Texture; 2],
    color: wgpu::Texture,
}

fn tex2d(
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

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor::default())
}

fn layer_view(t: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
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

/// Number of texture layers for `maps` maps.
///
/// NOTE: on GL, wgpu picks the texture target at creation: one layer becomes TEXTURE_2D and a
/// square texture with a multiple of 6 layers becomes a cube map, neither of which can be
/// sampled as a 2D array. Allocating at least 2 layers and skipping multiples of 6 keeps
/// the target TEXTURE_2D_ARRAY everywhere.
fn layer_count(maps: usize) -> u32 {
    let mut n = maps.max(2) as u32;
    if n.is_multiple_of(6) {
        n += 1;
    }
    n
}

impl Renderer {
    pub fn new(choice: BackendChoice) -> Result<Renderer, RenderError> {
        let gpu = Gpu::open(choice)?;
        let device = &gpu.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let shadow_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow.wgsl"),
            source: wgpu::ShaderSource::Wgsl(uniforms::SHADOW_WGSL.into()),
        });
        let scene_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(uniforms::scene_wgsl().into()),
        });
        let post_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("post.wgsl"),
            source: wgpu::ShaderSource::Wgsl(uniforms::POST_WGSL.into()),
        });

        let shadow_bgl =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("shadow"), entries: &[uniform_entry(0, true)] });
        let shadow_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow"),
            bind_group_layouts: &[Some(&shadow_bgl)],
            immediate_size: 0,
        });

        let mut scene_entries = vec![
            uniform_entry(0, false),
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
                count: None,
            },
        ];
        scene_entries.push(wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            count: None,
        });
        let scene_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("scene"), entries: &scene_entries });
        let scene_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&scene_bgl)],
            immediate_size: 0,
        });
        let scene_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("g-buffer"),
            layout: Some(&scene_layout),
            vertex: wgpu::VertexState {
                module: &scene_module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout())],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FMT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &scene_module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[target(WORLD_FMT), target(NORMAL_FMT), target(ALBEDO_FMT), target(AUX_FMT)],
            }),
            multiview_mask: None,
            cache: None,
        });

        let blur_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blur"),
            entries: &[uniform_entry(0, true), uint_texture_entry(1), float_texture_entry(2)],
        });
        let blur_pipeline = fullscreen_pipeline(device, "blur", &post_module, &blur_bgl, "fs_blur", VIS_FMT);
        let composite_bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("composite"),
            entries: &[
                uniform_entry(0, false),
                uint_texture_entry(1),
                float_texture_entry(2),
                float_texture_entry(3),
                uint_texture_entry(4),
                float_texture_entry(5),
            ],
        });
        let composite_pipeline = fullscreen_pipeline(device, "composite", &post_module, &composite_bgl, "fs_composite", COLOR_FMT);
        let samplers = [
            comparison_sampler(device, wgpu::CompareFunction::LessEqual, wgpu::FilterMode::Linear),
            comparison_sampler(device, wgpu::CompareFunction::LessEqual, wgpu::FilterMode::Nearest),
        ];
        if let Some(e) = crate::gpu::block_on(scope.pop()) {
            return Err(RenderError::Gpu(format!("creating pipelines: {e}")));
        }
        gpu.take_errors()?;
        Ok(Renderer {
            gpu,
            shadow_module,
            shadow_layout,
            shadow_bgl,
            shadow_pipelines: HashMap::new(),
            scene_bgl,
            scene_pipeline,
            blur_bgl,
            blur_pipeline,
            composite_bgl,
            composite_pipeline,
            samplers,
        })
    }

    /// Opens the adapter chosen by `SHADOWFOCUS_BACKEND` (gl, vulkan, auto; unset = auto).
    pub fn from_env() -> Result<Renderer, RenderError> {
        Renderer::new(BackendChoice::from_env()?)
    }

    pub fn adapter(&self) -> &AdapterSummary {
        &self.gpu.summary
    }

    fn shadow_pipeline(&mut self, key: ShadowPipelineKey) -> &wgpu::RenderPipeline {
        let device = &self.gpu.device;
        let (module, layout) = (&self.shadow_module, &self.shadow_layout);
        self.shadow_pipelines.entry(key).or_insert_with(|| {
            // "Greater" maps are stored as 1 − z (see shadow.wgsl), so every layer uses "less" and a
            // bias that points away from the light.
            let bias = if key.linear {
                wgpu::DepthBiasState::default()
            } else {
                // NOTE: GL has no depth-bias clamp; 0 means "unclamped" on every backend.
                wgpu::DepthBiasState { constant: key.constant, slope_scale: f32::from_bits(key.slope_bits), clamp: 0.0 }
            };
            let compare = wgpu::CompareFunction::Less;
            let entry = match (key.linear, key.viz) {
                (false, false) => None,
                (false, true) => Some("fs_viz"),
                (true, false) => Some("fs_linear"),
                (true, true) => Some("fs_linear_viz"),
            };
            let viz_targets = [target(VIZ_FMT)];
            let targets: &[Option<wgpu::ColorTargetState>] = if key.viz { &viz_targets } else { &[] };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("shadow"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[Some(shadow_vertex_layout())],
                },
                primitive: wgpu::PrimitiveState { unclipped_depth: key.clamp, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FMT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(compare),
                    stencil: Default::default(),
                    bias,
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: entry.map(|e| wgpu::FragmentState {
                    module,
                    entry_point: Some(e),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// Renders a frame, reads it back and measures it.
    pub fn render(&mut self, req: &RenderRequest) -> Result<RenderOutput, RenderError> {
        req.validate()?;
        let s = req.settings;
        let (w, h, res) = (s.width, s.height, s.shadow_resolution);
        let lim = &self.gpu.limits;
        if w > lim.max_texture_dimension_2d || h > lim.max_texture_dimension_2d || res > lim.max_texture_dimension_2d {
            return Err(RenderError::Unsupported {
                adapter: self.gpu.summary.name.clone(),
                reason: format!("textures are limited to {} texels per side", lim.max_texture_dimension_2d),
            });
        }
        let layers = layer_count(req.maps.len());
        if layers > lim.max_texture_array_layers {
            return Err(RenderError::Unsupported {
                adapter: self.gpu.summary.name.clone(),
                reason: format!("{layers} shadow layers, the adapter allows {}", lim.max_texture_array_layers),
            });
        }
        let scope = self.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let result = self.render_inner(req, layers);
        let scoped = crate::gpu::block_on(scope.pop());
        self.gpu.take_errors()?;
        if let Some(e) = scoped {
            return Err(RenderError::Gpu(e.to_string()));
        }
        result
    }

    fn render_inner(&mut self, req: &RenderRequest, layers: u32) -> Result<RenderOutput, RenderError> {
        let s = req.settings;
        let scene = req.scene;
        let (w, h, res) = (s.width, s.height, s.shadow_resolution);
        let clamp = s.depth_clamp && self.gpu.summary.depth_clamp;
        let (linear, lin_const, lin_slope, bias_c, bias_s, receiver_plane) = match s.depth {
            DepthMode::Projective { constant, slope_scale, receiver_plane } => (false, 0.0, 0.0, constant, slope_scale, receiver_plane),
            DepthMode::Linear { constant, slope_scale } => (true, constant, slope_scale, 0, 0.0, false),
        };
        let (lin_a, lin_mode) = linear_params(&req.light, scene);
        let lin_b = [if linear { lin_mode } else { 0.0 }, lin_const, lin_slope, 0.0];

        // The shadow pipeline first: building it borrows self mutably.
        let key = ShadowPipelineKey { viz: s.save_shadow_maps, linear, constant: bias_c, slope_bits: bias_s.to_bits(), clamp };
        self.shadow_pipeline(key);
        let device = &self.gpu.device;
        let queue = &self.gpu.queue;

        // Geometry, with the receiver flag in the colour's alpha (1 = receiver).
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
        let vbuf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vertices"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let ibuf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("indices"),
            contents: bytemuck::cast_slice(&scene.indices),
            usage: wgpu::BufferUsages::INDEX,
        });

        // Shadow maps.
        let shadow_tex = tex2d(
            device,
            "shadow maps",
            res,
            res,
            layers,
            DEPTH_FMT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let viz_tex = s.save_shadow_maps.then(|| {
            tex2d(device, "shadow viz", res, res, layers, VIZ_FMT, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC)
        });
        let mut shadow_uniforms = vec![0u8; (UNIFORM_STRIDE as usize) * req.maps.len().max(1)];
        for (i, m) in req.maps.iter().enumerate() {
            let flip = if m.depth_test == DepthTest::Greater { 1.0 } else { 0.0 };
            let u = ShadowUniform { world_to_clip: mat(m.world_to_clip), lin_a, lin_b: [lin_b[0], lin_b[1], lin_b[2], flip] };
            let off = i * UNIFORM_STRIDE as usize;
            shadow_uniforms[off..off + std::mem::size_of::<ShadowUniform>()].copy_from_slice(bytemuck::bytes_of(&u));
        }
        let shadow_ubuf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("shadow uniforms"),
            contents: &shadow_uniforms,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let shadow_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow"),
            layout: &self.shadow_bgl,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &shadow_ubuf,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<ShadowUniform>() as u64),
                }),
            }],
        });
        let ranges: Vec<Vec<std::ops::Range<u32>>> = req.maps.iter().map(|m| caster_ranges(scene, &m.casters)).collect();

        // Frame uniform.
        let aspect = req.aspect();
        let view_proj = (req.camera.projection_matrix(aspect) * req.camera.view_matrix()?).as_mat4();
        let (fwd, _, _) = req.camera.basis()?;
        let mut maps = [MapInfo { world_to_clip: [0.0; 16], split: [0.0; 4] }; MAX_MAPS];
        for (i, m) in req.maps.iter().enumerate() {
            maps[i] = MapInfo {
                world_to_clip: mat(m.world_to_clip),
                split: [m.split[0], m.split[1], if m.depth_test == DepthTest::Greater { 1.0 } else { 0.0 }, 0.0],
            };
        }
        let (pcf_mode, pcf_radius) = match s.pcf {
            Pcf::Off => (0.0, 0.0),
            Pcf::Hardware2x2 => (1.0, 0.0),
            Pcf::Kernel { radius } => (2.0, radius as f32),
        };
        let frame = FrameUniform {
            view_proj: mat(view_proj),
            eye: [req.camera.eye.x as f32, req.camera.eye.y as f32, req.camera.eye.z as f32, 1.0],
            forward: [fwd.x as f32, fwd.y as f32, fwd.z as f32, 0.0],
            cam: [req.camera.near as f32, req.camera.far as f32, w as f32, h as f32],
            lin_a,
            lin_b,
            params: [req.maps.len() as f32, res as f32, pcf_mode, pcf_radius],
            params2: [s.blend_band, if receiver_plane { 1.0 } else { 0.0 }, RECEIVER_PLANE_CONSTANT, RECEIVER_PLANE_MAX_TAN],
            maps,
        };
        let frame_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });

        // Screen targets.
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let t = Targets {
            world: tex2d(device, "world", w, h, 1, WORLD_FMT, rt),
            normal: tex2d(device, "normal", w, h, 1, NORMAL_FMT, rt),
            albedo: tex2d(device, "albedo", w, h, 1, ALBEDO_FMT, rt),
            aux: tex2d(device, "aux", w, h, 1, AUX_FMT, rt),
            depth: tex2d(device, "depth", w, h, 1, DEPTH_FMT, wgpu::TextureUsages::RENDER_ATTACHMENT),
            vis: [tex2d(device, "vis a", w, h, 1, VIS_FMT, rt), tex2d(device, "vis b", w, h, 1, VIS_FMT, rt)],
            color: tex2d(device, "color", w, h, 1, COLOR_FMT, rt),
        };
        let shadow_array_view = shadow_tex
            .create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() });
        let mut scene_entries = vec![
            wgpu::BindGroupEntry { binding: 0, resource: frame_buf.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&shadow_array_view) },
        ];
        // The receiver-plane bias compares each texel with its own reference (bilinear weights in
        // the shader), through the nearest sampler.
        let sampler = if s.pcf == Pcf::Off || receiver_plane { &self.samplers[1] } else { &self.samplers[0] };
        scene_entries.push(wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(sampler) });
        let scene_bg =
            device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("scene"), layout: &self.scene_bgl, entries: &scene_entries });

        // Blur: uniforms for (horizontal from aux), (horizontal), (vertical).
        let focal_px = 0.5 * h as f64 / (0.5 * req.camera.fovy).tan();
        let blur = s.blur.filter(|b| b.iterations > 0 && b.world_radius > 0.0 && b.max_radius_px > 0.0);
        let mut blur_bytes = vec![0u8; 3 * UNIFORM_STRIDE as usize];
        if let Some(b) = blur {
            let variants = [([1.0, 0.0], 1.0), ([1.0, 0.0], 0.0), ([0.0, 1.0], 0.0)];
            for (k, (dir, from_aux)) in variants.iter().enumerate() {
                let u = BlurUniform { a: [dir[0], dir[1], focal_px as f32, b.world_radius], b: [b.max_radius_px, *from_aux, 0.0, 0.0] };
                let off = k * UNIFORM_STRIDE as usize;
                blur_bytes[off..off + std::mem::size_of::<BlurUniform>()].copy_from_slice(bytemuck::bytes_of(&u));
            }
        }
        let blur_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("blur"),
            contents: &blur_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let aux_view = view(&t.aux);
        let vis_views = [view(&t.vis[0]), view(&t.vis[1])];
        let blur_bg = |src: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("blur"),
                layout: &self.blur_bgl,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &blur_buf,
                            offset: 0,
                            size: wgpu::BufferSize::new(std::mem::size_of::<BlurUniform>() as u64),
                        }),
                    },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&aux_view) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(src) },
                ],
            })
        };
        // Reading vis b writing vis a, and the reverse.
        let blur_bg_read = [blur_bg(&vis_views[0]), blur_bg(&vis_views[1])];

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
        let world_view = view(&t.world);
        let normal_view = view(&t.normal);
        let albedo_view = view(&t.albedo);
        // After n iterations of (H: → a, V: a → b) the result is in b.
        let comp_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: &self.composite_bgl,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: comp_buf.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&world_view) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&normal_view) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&albedo_view) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&aux_view) },
                wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(&vis_views[1]) },
            ],
        });
        let color_view = view(&t.color);
        let depth_view = view(&t.depth);

        let shadow_layer_views: Vec<wgpu::TextureView> = (0..req.maps.len() as u32).map(|i| layer_view(&shadow_tex, i)).collect();
        let viz_layer_views: Vec<wgpu::TextureView> =
            viz_tex.as_ref().map(|v| (0..req.maps.len() as u32).map(|i| layer_view(v, i)).collect()).unwrap_or_default();

        let mut best_shadow = f64::INFINITY;
        let mut best_main = f64::INFINITY;
        let timer = PhaseTimer::new(&self.gpu);
        let mut best_gpu: [Option<f64>; 2] = [None, None];
        for _ in 0..s.timing_repeats {
            // Shadow pass.
            let t0 = Instant::now();
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("shadow") });
            for i in 0..req.maps.len() {
                let clear = 1.0;
                let pipeline = &self.shadow_pipelines[&key];
                let color_att = viz_layer_views.get(i).map(|v| wgpu::RenderPassColorAttachment {
                    view: v,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        // All-ones bits: a NaN, read back as "no caster here".
                        load: wgpu::LoadOp::Clear(wgpu::Color { r: u32::MAX as f64, g: 0.0, b: 0.0, a: 0.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                });
                let color_atts = [color_att];
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("shadow layer"),
                    color_attachments: if s.save_shadow_maps { &color_atts } else { &[] },
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &shadow_layer_views[i],
                        depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timer.as_ref().and_then(|t| t.writes(SHADOW_PHASE, i, req.maps.len())),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &shadow_bg, &[(i as u64 * UNIFORM_STRIDE) as u32]);
                pass.set_vertex_buffer(0, vbuf.slice(..));
                pass.set_index_buffer(ibuf.slice(..), wgpu::IndexFormat::Uint32);
                for r in &ranges[i] {
                    pass.draw_indexed(r.clone(), 0, 0..1);
                }
            }
            queue.submit([enc.finish()]);
            self.gpu.wait()?;
            best_shadow = best_shadow.min(t0.elapsed().as_secs_f64() * 1e3);

            // G-buffer, blur, composite.
            let t1 = Instant::now();
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("main") });
            {
                fn clear_att(v: &wgpu::TextureView, c: wgpu::Color) -> Option<wgpu::RenderPassColorAttachment<'_>> {
                    Some(wgpu::RenderPassColorAttachment {
                        view: v,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Clear(c), store: wgpu::StoreOp::Store },
                    })
                }
                let zero = wgpu::Color { r: 0.0, g: 0.0, b: 0.0, a: 0.0 };
                let atts = [
                    clear_att(&world_view, zero),
                    clear_att(&normal_view, zero),
                    clear_att(&albedo_view, zero),
                    clear_att(&aux_view, zero),
                ];
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("g-buffer"),
                    color_attachments: &atts,
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &depth_view,
                        depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(0.0), store: wgpu::StoreOp::Store }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timer.as_ref().and_then(|t| t.writes(MAIN_PHASE, 0, 2)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.scene_pipeline);
                pass.set_bind_group(0, &scene_bg, &[]);
                pass.set_vertex_buffer(0, vbuf.slice(..));
                pass.set_index_buffer(ibuf.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..scene.indices.len() as u32, 0, 0..1);
            }
            if let Some(b) = blur {
                for it in 0..b.iterations {
                    // Horizontal: (aux or b) → a; vertical: a → b.
                    let h_off = if it == 0 { 0 } else { UNIFORM_STRIDE as u32 };
                    for (dst, bg, off) in
                        [(&vis_views[0], &blur_bg_read[1], h_off), (&vis_views[1], &blur_bg_read[0], 2 * UNIFORM_STRIDE as u32)]
                    {
                        let att = [Some(wgpu::RenderPassColorAttachment {
                            view: dst,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::WHITE), store: wgpu::StoreOp::Store },
                        })];
                        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some("blur"),
                            color_attachments: &att,
                            depth_stencil_attachment: None,
                            timestamp_writes: None,
                            occlusion_query_set: None,
                            multiview_mask: None,
                        });
                        pass.set_pipeline(&self.blur_pipeline);
                        pass.set_bind_group(0, bg, &[off]);
                        pass.draw(0..3, 0..1);
                    }
                }
            }
            {
                let att = [Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
                })];
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("composite"),
                    color_attachments: &att,
                    depth_stencil_attachment: None,
                    timestamp_writes: timer.as_ref().and_then(|t| t.writes(MAIN_PHASE, 1, 2)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.composite_pipeline);
                pass.set_bind_group(0, &comp_bg, &[]);
                pass.draw(0..3, 0..1);
            }
            queue.submit([enc.finish()]);
            self.gpu.wait()?;
            best_main = best_main.min(t1.elapsed().as_secs_f64() * 1e3);
            if let Some(t) = &timer {
                for (best, ms) in best_gpu.iter_mut().zip(t.read(&self.gpu)?) {
                    *best = match (*best, ms) {
                        (Some(b), Some(m)) => Some(b.min(m)),
                        (b, m) => b.or(m),
                    };
                }
            }
        }

        // Read-back.
        let t2 = Instant::now();
        let mut rb = Readback::default();
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("read-back") });
        let i_world = rb.add(device, &mut enc, &t.world, 0, w, h, 16);
        let i_normal = rb.add(device, &mut enc, &t.normal, 0, w, h, 8);
        let i_aux = rb.add(device, &mut enc, &t.aux, 0, w, h, 16);
        let i_vis = blur.map(|_| rb.add(device, &mut enc, &t.vis[1], 0, w, h, 2));
        let i_color = rb.add(device, &mut enc, &t.color, 0, w, h, 4);
        let i_maps: Vec<usize> = match &viz_tex {
            Some(v) => (0..req.maps.len() as u32).map(|l| rb.add(device, &mut enc, v, l, res, res, 4)).collect(),
            None => Vec::new(),
        };
        queue.submit([enc.finish()]);
        let data = rb.finish(&self.gpu)?;
        let readback_ms = t2.elapsed().as_secs_f64() * 1e3;

        let f32s = |b: &[u8]| -> Vec<f32> { bytemuck::pod_collect_to_vec::<u8, f32>(b) };
        let world_f = f32s(&data[i_world]);
        let aux_f = f32s(&data[i_aux]);
        let normal_h: Vec<u16> = bytemuck::pod_collect_to_vec::<u8, u16>(&data[i_normal]);
        let n = (w * h) as usize;
        let mut world = Vec::with_capacity(n);
        let mut normal = Vec::with_capacity(n);
        let mut aliasing = Vec::with_capacity(n);
        let mut split = Vec::with_capacity(n);
        let mut shadow = Vec::with_capacity(n);
        let vis_f: Option<Vec<f32>> =
            i_vis.map(|i| bytemuck::pod_collect_to_vec::<u8, u16>(&data[i]).into_iter().map(half_to_f32).collect());
        for p in 0..n {
            let wv = [world_f[4 * p], world_f[4 * p + 1], world_f[4 * p + 2], world_f[4 * p + 3]];
            world.push(wv);
            normal.push([half_to_f32(normal_h[4 * p]), half_to_f32(normal_h[4 * p + 1]), half_to_f32(normal_h[4 * p + 2]), 0.0]);
            let bg = wv[3] == 0.0;
            aliasing.push(if bg { f32::NAN } else { aux_f[4 * p] });
            split.push(if bg { -1 } else { aux_f[4 * p + 3] as i32 });
            shadow.push(match &vis_f {
                Some(v) if !bg => v[p],
                _ => aux_f[4 * p + 2],
            });
        }
        let color = Image { width: w, height: h, rgba: data[i_color].clone() };
        let shadow_maps: Vec<DepthMap> = i_maps
            .iter()
            .enumerate()
            .map(|(k, &i)| DepthMap {
                resolution: res,
                depth: f32s(&data[i]),
                reversed: req.maps[k].depth_test == DepthTest::Greater && !linear,
            })
            .collect();

        let t3 = Instant::now();
        let truth = if s.ground_truth {
            let gt = scene.ground_truth()?;
            Some(gt.classify_image(&world, &normal, &req.light))
        } else {
            None
        };
        let ground_truth_ms = t3.elapsed().as_secs_f64() * 1e3;

        let mut out = RenderOutput {
            width: w,
            height: h,
            color,
            world,
            normal,
            aliasing,
            split,
            shadow,
            truth,
            shadow_maps,
            camera: req.camera,
            light: req.light,
            metrics: RenderMetrics::default(),
        };
        let draw_calls: Vec<u32> = ranges.iter().map(|r| r.len() as u32).collect();
        out.metrics = metrics::compute(
            req,
            &out,
            &self.gpu.summary,
            clamp,
            &draw_calls,
            metrics::Timings {
                shadow_ms: best_shadow,
                main_ms: best_main,
                shadow_gpu_ms: best_gpu[0],
                main_gpu_ms: best_gpu[1],
                readback_ms,
                ground_truth_ms,
            },
        );
        Ok(out)
    }
}

/// Texture → buffer copies with 256-byte row alignment (and plain buffer
/// copies), mapped together.
#[derive(Default)]
pub(crate) struct Readback {
    items: Vec<(wgpu::Buffer, u32, u32, u32)>, // buffer, padded row bytes, row bytes, rows
}

impl Readback {
    #[allow(clippy::too_many_arguments)]
    fn add(
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

    #[test]
    fn layer_counts_avoid_gl_special_targets() {
        for n in 0..=MAX_MAPS {
            let l = layer_count(n);
            assert!(l >= 2 && l as usize >= n && !l.is_multiple_of(6), "{n} maps → {l} layers");
        }
    }
}
