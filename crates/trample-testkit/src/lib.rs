//! # trample-testkit — what the workspace's tests share
//!
//! A dev-dependency of the workspace's crates, never published:
//!
//! - [`scenes`]: the test scenes several tests and examples run (the
//!   rolling ball, the busy scene, the LOD scene), written once as scene
//!   files in `scenes/`, parsed and built here.
//! - [`adapter`]: the `TRAMPLE_TEST_ADAPTER` check that pins a GPU test to
//!   one driver (CI runs the GPU tests on llvmpipe through GL and on
//!   lavapipe through Vulkan).
//! - `gpu` (feature `gpu`): a wgpu device for the GPU path's tests and
//!   examples, so that `trample-gpu` never depends on the renderer, not
//!   even for its tests. Off for the core's tests, which must not build
//!   wgpu.
//!
//! Tests use it through `[dev-dependencies]`; the core's tests make a
//! dev-dependency cycle (trample → trample-testkit → trample), which Cargo
//! allows: the integration tests and the kit link the same `trample`.

pub mod adapter;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod scenes;
