//! A wgpu device for the GPU path's tests and examples (feature `gpu`;
//! STYLE rule 3: the libraries never create a device, tests bring their
//! own). The backends come from `WGPU_BACKEND` (CI runs the GPU tests with
//! `gl`, Mesa llvmpipe, and with `vulkan`, lavapipe); the device asks for
//! every limit the adapter offers (the GPU path binds whole blade buffers,
//! above wgpu's default binding size on some adapters) and for those of the
//! optional features the adapter has (e.g. `trample_gpu::TIMESTAMP_FEATURES`
//! for per-stage GPU times).
//!
//! `trample_render::headless::create_device_with` asks wgpu for a device
//! the same way; it is not reused because the GPU path's tests must not
//! depend on the renderer (issue 18), and the GPU library itself creates no
//! device (STYLE rule 3: tests, tools and hosts bring their own).

use crate::adapter::check_adapter_name;

/// A device, its queue and the adapter they came from.
pub struct TestGpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter: [`TestGpu::adapter_name`] names it.
    pub adapter: wgpu::Adapter,
}

impl TestGpu {
    /// "name (backend, device type)", e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Gl, Cpu)`.
    #[must_use]
    pub fn adapter_name(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }
}

/// Why no device could be made.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// No adapter on the backends `WGPU_BACKEND` allows.
    #[error(
        "no GPU adapter on backends {backends} (WGPU_BACKEND=gl for llvmpipe, =vulkan for lavapipe): {why}"
    )]
    NoAdapter {
        /// The backends tried.
        backends: String,
        /// wgpu's reason.
        why: String,
    },
    /// The adapter refused the device.
    #[error("the adapter refused the device: {0}")]
    Device(String),
}

/// Creates a device on the adapter `WGPU_BACKEND` allows (a real GPU
/// preferred, else a software one), with every limit the adapter offers
/// and those of `optional` it has (`device.features()` says which).
/// [`test_gpu`] also checks the adapter against `TRAMPLE_TEST_ADAPTER`.
///
/// # Errors
/// [`DeviceError::NoAdapter`] names the backends tried;
/// [`DeviceError::Device`] when the adapter refuses the device.
pub fn create_device(optional: wgpu::Features) -> Result<TestGpu, DeviceError> {
    create_device_as(|adapter| (adapter.features() & optional, adapter.limits()))
}

/// As [`create_device`], with the features and limits `ask` chooses for
/// the adapter (e.g. exactly what a library publishes, as a host would).
///
/// # Errors
/// As [`create_device`].
pub fn create_device_as(
    ask: impl FnOnce(&wgpu::Adapter) -> (wgpu::Features, wgpu::Limits),
) -> Result<TestGpu, DeviceError> {
    let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    let backends = desc.backends;
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))
    .map_err(|e| DeviceError::NoAdapter {
        backends: format!("{backends:?}"),
        why: e.to_string(),
    })?;
    let (required_features, required_limits) = ask(&adapter);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("trample-testkit"),
        required_features,
        required_limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }))
    .map_err(|e| DeviceError::Device(e.to_string()))?;
    Ok(TestGpu {
        device,
        queue,
        adapter,
    })
}

/// The device for a GPU test: [`create_device`]`(optional)`, on the adapter
/// `TRAMPLE_TEST_ADAPTER` asks for.
///
/// # Panics
/// When there is no adapter (a GPU test without one fails, it does not
/// skip), when the adapter refuses the device, or when the adapter is not
/// the one `TRAMPLE_TEST_ADAPTER` names.
#[must_use]
pub fn test_gpu(optional: wgpu::Features) -> TestGpu {
    let gpu = create_device(optional).unwrap_or_else(|e| panic!("GPU test: {e}"));
    check_adapter_name(&gpu.adapter_name());
    gpu
}

/// The device for a GPU test that stands for a host's: exactly `features`
/// and `limits` (nothing more the adapter offers), on the adapter
/// `TRAMPLE_TEST_ADAPTER` asks for.
///
/// # Panics
/// As [`test_gpu`].
#[must_use]
pub fn test_gpu_exact(features: wgpu::Features, limits: wgpu::Limits) -> TestGpu {
    let gpu = create_device_as(|_| (features, limits)).unwrap_or_else(|e| panic!("GPU test: {e}"));
    check_adapter_name(&gpu.adapter_name());
    gpu
}
