//! Adapter and device selection for headless rendering.

use std::future::Future;
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Wake, Waker};

use serde::Serialize;

use crate::error::RenderError;

/// Environment variable that forces a backend: `gl`, `vulkan` or `auto`.
pub const BACKEND_ENV: &str = "SHADOWFOCUS_BACKEND";

/// Which wgpu backend to open.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BackendChoice {
    /// A hardware GPU if any, else Vulkan on the CPU (lavapipe), else GL on the CPU (llvmpipe).
    Auto,
    Gl,
    Vulkan,
}

impl BackendChoice {
    pub fn parse(s: &str) -> Result<BackendChoice, RenderError> {
        match s.trim().to_ascii_lowercase().as_str() {
            "" | "auto" => Ok(BackendChoice::Auto),
            "gl" | "gles" | "opengl" => Ok(BackendChoice::Gl),
            "vulkan" | "vk" => Ok(BackendChoice::Vulkan),
            other => Err(RenderError::invalid(BACKEND_ENV, format!("'{other}' is not one of gl, vulkan, auto"))),
        }
    }

    /// Reads [`BACKEND_ENV`]; unset means `Auto`.
    pub fn from_env() -> Result<BackendChoice, RenderError> {
        match std::env::var(BACKEND_ENV) {
            Ok(v) => BackendChoice::parse(&v),
            Err(std::env::VarError::NotPresent) => Ok(BackendChoice::Auto),
            Err(e) => Err(RenderError::invalid(BACKEND_ENV, e.to_string())),
        }
    }

    fn backends(self) -> wgpu::Backends {
        match self {
            BackendChoice::Auto => wgpu::Backends::VULKAN | wgpu::Backends::GL,
            BackendChoice::Gl => wgpu::Backends::GL,
            BackendChoice::Vulkan => wgpu::Backends::VULKAN,
        }
    }
}

/// What was opened, for reports.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    /// Whether casters in front of a map's near plane can be clamped instead of clipped.
    pub depth_clamp: bool,
    /// Whether the GPU times its passes itself (timestamp queries).
    pub timestamps: bool,
    /// Whether the adapter runs compute shaders (the visible depth range is then reduced on
    /// the GPU).
    pub compute: bool,
}

/// An open device plus an error sink: wgpu errors become `RenderError`s instead of panics.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
    pub limits: wgpu::Limits,
    errors: Arc<Mutex<Vec<String>>>,
    _instance: wgpu::Instance,
    _adapter: wgpu::Adapter,
}

/// Rank for automatic choice: hardware first, then Vulkan on the CPU (faster than GL there).
fn rank(info: &wgpu::AdapterInfo) -> u32 {
    let hw = match info.device_type {
        wgpu::DeviceType::DiscreteGpu => 40,
        wgpu::DeviceType::IntegratedGpu => 30,
        wgpu::DeviceType::VirtualGpu => 20,
        wgpu::DeviceType::Other => 10,
        wgpu::DeviceType::Cpu => 0,
    };
    hw + if info.backend == wgpu::Backend::Vulkan { 2 } else { 1 }
}

const NO_ADAPTER_HINT: &str = "Headless rendering needs Mesa on a machine without a GPU: \
`apt-get install libegl1 libgl1-mesa-dri` gives the GL backend (llvmpipe), \
`apt-get install mesa-vulkan-drivers libvulkan1` the Vulkan one (lavapipe). \
With a GPU, install its Vulkan driver. Force a backend with SHADOWFOCUS_BACKEND=gl|vulkan|auto.";

impl Gpu {
    /// Opens the best adapter for `choice`.
    pub fn open(choice: BackendChoice) -> Result<Gpu, RenderError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = choice.backends();
        let instance = wgpu::Instance::new(desc);
        let mut adapters = block_on(instance.enumerate_adapters(choice.backends()));
        adapters.sort_by_key(|a| std::cmp::Reverse(rank(&a.get_info())));
        let tried = match choice {
            BackendChoice::Auto => "backends tried: vulkan, gl",
            BackendChoice::Gl => "backend tried: gl",
            BackendChoice::Vulkan => "backend tried: vulkan",
        }
        .to_string();
        let adapter = adapters
            .into_iter()
            .next()
            .ok_or_else(|| RenderError::NoAdapter { tried: tried.clone(), hint: NO_ADAPTER_HINT.to_string() })?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        // The G-buffer writes 48 bytes per pixel in four targets; WebGPU's default budget is 32,
        // but native adapters (GL, Vulkan) report their real, larger budget.
        if limits.max_color_attachments < 4 || limits.max_color_attachment_bytes_per_sample < 48 {
            return Err(RenderError::Unsupported {
                adapter: info.name.clone(),
                reason: format!(
                    "needs 4 colour targets and 48 bytes per sample, has {} and {}",
                    limits.max_color_attachments, limits.max_color_attachment_bytes_per_sample
                ),
            });
        }
        let depth_clamp = adapter.features().contains(wgpu::Features::DEPTH_CLIP_CONTROL);
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let compute = adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS);
        let mut features = wgpu::Features::empty();
        features.set(wgpu::Features::DEPTH_CLIP_CONTROL, depth_clamp);
        features.set(wgpu::Features::TIMESTAMP_QUERY, timestamps);
        let (device, queue) = block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("shadowfocus"),
            required_features: features,
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::Gpu(format!("request_device on '{}': {e}", info.name)))?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend).to_lowercase(),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            depth_clamp,
            timestamps,
            compute,
        };
        Ok(Gpu { device, queue, summary, limits, errors, _instance: instance, _adapter: adapter })
    }

    /// Returns and clears the errors wgpu reported since the last call.
    pub fn take_errors(&self) -> Result<(), RenderError> {
        let mut v = self.errors.lock().map_err(|_| RenderError::Gpu("error sink poisoned".into()))?;
        if v.is_empty() {
            Ok(())
        } else {
            let msg = v.join("; ");
            v.clear();
            Err(RenderError::Gpu(msg))
        }
    }

    pub fn wait(&self) -> Result<(), RenderError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| RenderError::Gpu(format!("poll: {e}")))
    }
}

struct ThreadWaker(std::thread::Thread);

impl Wake for ThreadWaker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

/// Minimal executor: native wgpu futures complete without an event loop.
pub(crate) fn block_on<F: Future>(fut: F) -> F::Output {
    let mut fut = std::pin::pin!(fut);
    let waker = Waker::from(Arc::new(ThreadWaker(std::thread::current())));
    let mut cx = Context::from_waker(&waker);
    loop {
        match fut.as_mut().poll(&mut cx) {
            Poll::Ready(v) => return v,
            Poll::Pending => std::thread::park(),
        }
    }
}
