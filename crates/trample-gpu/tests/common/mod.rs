//! Test device: the test kit's `gpu::test_gpu` (honours `WGPU_BACKEND`;
//! CI runs these tests with `gl`, llvmpipe, and with `vulkan`, lavapipe),
//! with the timestamp features where the adapter has them. No adapter is a
//! test failure, not a skip. `TRAMPLE_TEST_ADAPTER` (CI sets it) lists,
//! comma-separated, words the adapter's name must contain (e.g.
//! `llvmpipe,Vulkan`), so that a run meant for one driver cannot pass on
//! another.

#![allow(dead_code)]

use trample_gpu::wgpu;
pub use trample_testkit::gpu::TestGpu;

/// The device for the GPU tests, with [`trample_gpu::TIMESTAMP_FEATURES`]
/// where the adapter offers them.
pub fn gpu() -> TestGpu {
    trample_testkit::gpu::test_gpu(trample_gpu::TIMESTAMP_FEATURES)
}

/// As [`gpu`], with no optional feature (the profiling mode then measures
/// wall time).
pub fn gpu_without_timestamps() -> TestGpu {
    trample_testkit::gpu::test_gpu(wgpu::Features::empty())
}
