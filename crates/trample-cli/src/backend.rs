//! `--backend auto|cpu|gpu` (issue 4): which path runs the simulation.
//!
//! `auto` takes the GPU path on a hardware adapter and the CPU path on a
//! software one (llvmpipe, lavapipe: slower than the CPU path with rayon,
//! PLATFORM.md) or when no adapter is found; `gpu` forces the GPU path,
//! also on a software adapter, and fails with a clear message without one.

use anyhow::{Result, bail};
use trample_render::headless::{Gpu, create_device_with};

/// The `--backend` flag (defaults: `cpu` for `simulate` and `collide`,
/// whose figures an adapter probe would skew; `auto` for `run`, which has a
/// device anyway; `cpu` for `view`, whose GPU path still reads the field
/// back every frame).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The GPU on a hardware adapter, else the CPU.
    Auto,
    /// The CPU reference path (rayon).
    Cpu,
    /// The GPU path (wgpu compute), also on a software adapter.
    Gpu,
}

/// The device to run on, or `None` for the CPU path. `auto` falls back to
/// the CPU with a message on stderr. The device has the timestamp queries
/// of `trample_gpu::TIMESTAMP_FEATURES` where the adapter offers them, for
/// the per-stage GPU times of `summary.json`.
///
/// # Errors
/// `gpu` without a usable adapter.
pub fn choose(backend: Backend) -> Result<Option<Gpu>> {
    match backend {
        Backend::Cpu => Ok(None),
        Backend::Gpu => match create_device_with(trample_gpu::TIMESTAMP_FEATURES) {
            Ok(gpu) => {
                eprintln!("trample: GPU path on {}", gpu.adapter_name());
                Ok(Some(gpu))
            }
            Err(e) => bail!(
                "--backend gpu: no usable GPU adapter ({e}); use --backend cpu, or WGPU_BACKEND=gl for Mesa llvmpipe"
            ),
        },
        Backend::Auto => match create_device_with(trample_gpu::TIMESTAMP_FEATURES) {
            Ok(gpu) if gpu.adapter.get_info().device_type == wgpu_device_type_cpu() => {
                eprintln!(
                    "trample: {} is a software adapter: CPU path (--backend gpu forces the GPU path)",
                    gpu.adapter_name()
                );
                Ok(None)
            }
            Ok(gpu) => {
                eprintln!("trample: GPU path on {}", gpu.adapter_name());
                Ok(Some(gpu))
            }
            Err(e) => {
                eprintln!("trample: no GPU adapter ({e}): CPU path");
                Ok(None)
            }
        },
    }
}

/// What far objects taking turns (`far_every` above 1) do on the GPU
/// path, for stderr when a GPU run has them; `None` at 1. Turns are the
/// CPU path's saving: they cut the blades' work, but split the step into
/// more sub-steps (each far pass sub-stepped for its own travel; the herd at
/// 16 runs about 12 a step instead of 1), and a GPU's step costs about a
/// chain of dispatches a sub-step however little each one does: on an
/// NVIDIA H200 the herd stepped in 22 ms at 16 against 4.8 ms every step
/// (BENCHMARKS.md, session 70).
/// Printed on stderr by [`note_far_turns`].
fn far_turns_note(far_every: u32) -> Option<String> {
    (far_every > 1).then(|| {
        format!(
            "trample: note: far objects take turns (far_every {far_every}), which splits a step into more \
             sub-steps; on the GPU path each sub-step costs a chain of dispatches however few blades it moves \
             (NVIDIA H200, the herd: 22 ms a step at 16 against 4.8 ms at 1): far_every 1 is usually faster there"
        )
    })
}

/// Prints the note of [`far_turns_note`] on stderr when a GPU run has far
/// turns (`far_every` above 1); nothing otherwise.
pub fn note_far_turns(far_every: u32) {
    if let Some(note) = far_turns_note(far_every) {
        eprintln!("{note}");
    }
}

fn wgpu_device_type_cpu() -> trample_gpu::wgpu::DeviceType {
    trample_gpu::wgpu::DeviceType::Cpu
}

/// For `run`, which has its render device already: whether to simulate on
/// it too. `auto`: only on a hardware adapter; `gpu`: always; `cpu`: never.
#[must_use]
pub fn simulate_on(backend: Backend, gpu: &Gpu) -> bool {
    let software = gpu.adapter.get_info().device_type == wgpu_device_type_cpu();
    match backend {
        Backend::Cpu => false,
        Backend::Gpu => true,
        Backend::Auto if software => {
            eprintln!(
                "trample: {} is a software adapter: simulating on the CPU path (--backend gpu forces the GPU path)",
                gpu.adapter_name()
            );
            false
        }
        Backend::Auto => true,
    }
}
