//! Test device: the renderer's `headless::create_device_with` (honours
//! `WGPU_BACKEND`; CI runs these tests with `gl`, llvmpipe, and with
//! `vulkan`, lavapipe), with the timestamp features where the adapter has
//! them. No adapter is a test failure, not a skip. `TRAMPLE_TEST_ADAPTER`
//! (CI sets it) lists, comma-separated, words the adapter's name must
//! contain (e.g. `llvmpipe,Vulkan`), so that a run meant for one driver
//! cannot pass on another.

#![allow(dead_code)]

use trample_gpu::wgpu;
use trample_render::headless::Gpu;

/// The device for the GPU tests, with [`trample_gpu::TIMESTAMP_FEATURES`]
/// where the adapter offers them.
pub fn gpu() -> Gpu {
    gpu_with(trample_gpu::TIMESTAMP_FEATURES)
}

/// As [`gpu`], with no optional feature (the profiling mode then measures
/// wall time).
pub fn gpu_without_timestamps() -> Gpu {
    gpu_with(wgpu::Features::empty())
}

fn gpu_with(features: wgpu::Features) -> Gpu {
    let gpu = trample_render::headless::create_device_with(features).unwrap_or_else(|e| {
        panic!(
            "no GPU adapter for the GPU tests (WGPU_BACKEND=gl for llvmpipe, =vulkan for lavapipe): {e}"
        )
    });
    let name = gpu.adapter_name();
    if let Ok(wanted) = std::env::var("TRAMPLE_TEST_ADAPTER") {
        for word in wanted.split(',').map(str::trim).filter(|w| !w.is_empty()) {
            assert!(
                name.contains(word),
                "adapter {name} is not the one TRAMPLE_TEST_ADAPTER={wanted} asks for"
            );
        }
    }
    gpu
}
