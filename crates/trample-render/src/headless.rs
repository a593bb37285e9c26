//! A device for tools and tests that render offscreen (no window): the one
//! place in this crate that creates a GPU device (STYLE rule 3).

use crate::error::RenderError;

/// A device, its queue and the adapter they came from.
pub struct Gpu {
    /// The device the renderer draws with.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter: [`Gpu::adapter_name`] names it, [`supported_msaa`] asks it.
    pub adapter: wgpu::Adapter,
}

impl Gpu {
    /// "name (backend, device type)", e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Gl, Cpu)`.
    #[must_use]
    pub fn adapter_name(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }

    /// The MSAA sample count to use for `wanted` samples: `wanted` if the
    /// adapter renders and resolves it for the colour and depth formats, else 1.
    #[must_use]
    pub fn msaa(&self, wanted: u32) -> u32 {
        supported_msaa(&self.adapter, wanted)
    }
}

/// `wanted` if `adapter` supports that many samples for [`crate::COLOR_FORMAT`]
/// (with resolve) and [`crate::DEPTH_FORMAT`], else 1.
#[must_use]
pub fn supported_msaa(adapter: &wgpu::Adapter, wanted: u32) -> u32 {
    use wgpu::TextureFormatFeatureFlags as F;
    let color = adapter
        .get_texture_format_features(crate::COLOR_FORMAT)
        .flags;
    let depth = adapter
        .get_texture_format_features(crate::DEPTH_FORMAT)
        .flags;
    if wanted > 1
        && color.sample_count_supported(wanted)
        && color.contains(F::MULTISAMPLE_RESOLVE)
        && depth.sample_count_supported(wanted)
    {
        wanted
    } else {
        1
    }
}

/// Creates a device with the backends of `WGPU_BACKEND` (default: all),
/// preferring a real GPU, falling back to a software one (Mesa llvmpipe
/// through GL, lavapipe through Vulkan).
///
/// # Errors
/// [`RenderError::NoAdapter`] names the backends tried; [`RenderError::Device`]
/// when the adapter refuses the device.
pub fn create_device() -> Result<Gpu, RenderError> {
    create_device_with(wgpu::Features::empty())
}

/// As [`create_device`], also enabling those of `optional` the adapter
/// offers (e.g. `trample_gpu::TIMESTAMP_FEATURES` for per-stage GPU
/// times); `device.features()` says which it got.
///
/// # Errors
/// As [`create_device`].
pub fn create_device_with(optional: wgpu::Features) -> Result<Gpu, RenderError> {
    let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    let backends = desc.backends;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))
    .map_err(|e| RenderError::NoAdapter {
        backends: format!("{backends:?}"),
        why: e.to_string(),
    })?;
    let limits = crate::required_limits(&adapter);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("trample"),
        required_features: adapter.features() & optional,
        required_limits: limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .map_err(|e| RenderError::Device(e.to_string()))?;
    Ok(Gpu {
        device,
        queue,
        adapter,
    })
}
