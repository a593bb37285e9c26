//! Test device: the renderer's `headless::create_device` (honours
//! `WGPU_BACKEND`; CI uses `gl`, llvmpipe). No adapter is a test failure, not
//! a skip.

#![allow(dead_code)]

pub fn gpu() -> trample_render::headless::Gpu {
    trample_render::headless::create_device().unwrap_or_else(|e| {
        panic!("no GPU adapter for the GPU tests (set WGPU_BACKEND=gl for llvmpipe): {e}")
    })
}
