//! The GPU path of `trample simulate` (`--backend gpu`, or `auto` on a
//! hardware adapter): `trample_gpu::GpuSimulation` steps the scene, the
//! state comes back once at the end for the summary and the dumps.
//!
//! Errors the device reports (validation, out of memory, device lost) are
//! caught instead of panicking and end the GPU run with a message; the
//! caller then falls back to the CPU path under `auto`.

use crate::summary::Recorder;
use anyhow::{Result, anyhow};
use indicatif::ProgressBar;
use std::sync::{Arc, Mutex};
use trample::Simulation;
use trample_gpu::GpuSimulation;
use trample_render::headless::Gpu;

/// Fault injection for tests (`RELIABILITY.md`): with
/// `TRAMPLE_FAULT_GPU_LOST_AFTER=N` the device is destroyed before frame N,
/// as a driver reset or an unplugged GPU would lose it.
fn fault_device_lost_after() -> Option<u64> {
    std::env::var("TRAMPLE_FAULT_GPU_LOST_AFTER")
        .ok()?
        .parse()
        .ok()
}

/// Steps `sim` on `gpu` for `frames` frames in profiling mode
/// (`GpuSimulation::set_profiling`), so `summary.json`'s `stages_ms` are
/// per-stage GPU times: from timestamp queries, read back once per step,
/// where the device has them (`backend::choose` asks for them), else each
/// stage submitted and waited for on its own (`stage_timing` says which);
/// `step_ms` is the whole step with the CPU's share (poses, recording) and,
/// the GPU's work being waited for, the GPU's. The per-frame counters (DBG,
/// PBG, generations) are read back, 32 bytes a frame, for the progress bar
/// and the summary (the blade buffers are not).
///
/// # Errors
/// When the GPU path does not support the scene, or the device reports an
/// error (out of memory, device lost): the message says which.
pub fn simulate_on_gpu(
    gpu: &Gpu,
    sim: Simulation,
    frames: u64,
    bar: &ProgressBar,
) -> Result<(Simulation, Recorder)> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    GpuSimulation::supports(device, &sim).map_err(|e| anyhow!("GPU path: {e}"))?;
    let failure: Arc<Mutex<Option<String>>> = Arc::default();
    let sink = failure.clone();
    device.on_uncaptured_error(Arc::new(move |e| {
        let mut slot = sink.lock().unwrap_or_else(|p| p.into_inner());
        slot.get_or_insert_with(|| e.to_string());
    }));
    let lost = failure.clone();
    device.set_device_lost_callback(move |reason, msg| {
        // A lost device is the cause of the errors reported before it was
        // noticed (wgpu notices at the next wait: with timestamp profiling
        // that is the read-back, whose mapping fails first), so it wins.
        let mut slot = lost.lock().unwrap_or_else(|p| p.into_inner());
        *slot = Some(format!("device lost ({reason:?}): {msg}"));
    });
    let check = || -> Result<()> {
        match failure.lock().unwrap_or_else(|p| p.into_inner()).take() {
            Some(msg) => Err(anyhow!("GPU error: {msg}")),
            None => Ok(()),
        }
    };
    let mut g = GpuSimulation::new(device, queue, sim)?;
    g.set_profiling(true);
    check()?;
    let mut rec = Recorder::default();
    let dt = g.sim.params.dt_s;
    let lose_after = fault_device_lost_after();
    for i in 0..frames {
        if lose_after == Some(i) {
            device.destroy();
        }
        let counters = g
            .step(device, queue, dt)
            .and_then(|_| g.read_counters(device, queue))
            .map_err(|e| {
                // The device's own words (device lost, out of memory) say
                // more than the failed call that noticed it.
                match failure.lock().unwrap_or_else(|p| p.into_inner()).take() {
                    Some(msg) => anyhow!("GPU error: {msg} ({e})"),
                    None => anyhow!("GPU error: {e}"),
                }
            })?;
        check()?;
        counters.apply_to(&mut g.sim.timings);
        let t = g.sim.timings.clone();
        bar.set_message(format!("DBG {} PBG {}", t.dbg_blades, t.pbg_blades));
        rec.steps.push(t);
        bar.inc(1);
    }
    g.sync_to_cpu(device, queue)?;
    check()?;
    if let Some(last) = rec.steps.last() {
        let lod = g.sim.timings.lod;
        g.sim.timings = last.clone();
        g.sim.timings.lod = lod;
    }
    Ok((g.sim, rec))
}
