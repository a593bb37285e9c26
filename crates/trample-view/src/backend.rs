//! Which path steps the viewer's simulation: the CPU reference (rayon) or
//! the GPU path ([`GpuSimulation`], wgpu compute) on the viewer's own device.
//!
//! [`Backend`] holds the one running simulation either way, so every action
//! of the app (driving, parameters, camera, reset, restart) goes to
//! [`Backend::sim_mut`] and reaches whichever path runs: the GPU path reads
//! its parameters, camera and poses from its `sim` at each step.
//!
//! On the GPU path the renderer draws straight from the GPU buffers
//! (`Renderer::encode_gpu`, through [`Backend::gpu_mut`]); after each step
//! only its counters come back (48 bytes: DBG, PBG, levels, for the stats).
//! The field itself is read back ([`GpuSimulation::sync_to_cpu`]) when the
//! simulation returns to the CPU path, or on demand ([`Backend::sync_field`]).
//!
//! Every GPU call runs inside wgpu error scopes ([`guarded`]): a refused
//! scene, a validation error, running out of memory or a lost device ends
//! the GPU path with a message and the simulation goes on on the CPU from
//! the last state read back (the state it had when the GPU path took over,
//! if the device is lost). Nothing here panics on a GPU failure.

use trample::Simulation;
use trample::step::{BladeClass, SimError};
use trample_gpu::{GpuError, GpuSimulation};

/// Which path runs the simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendKind {
    /// The CPU reference path (rayon).
    #[default]
    Cpu,
    /// The GPU path (wgpu compute) on the viewer's device.
    Gpu,
}

impl BackendKind {
    /// Name shown in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Cpu => "CPU",
            Self::Gpu => "GPU",
        }
    }
}

/// What `trample view --backend` asks for when the window opens.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StartBackend {
    /// The CPU path.
    Cpu,
    /// The GPU path, also on a software adapter.
    Gpu,
    /// The GPU path on a hardware adapter, the CPU path on a software one
    /// (llvmpipe, lavapipe: slower than the CPU path, PLATFORM.md). The
    /// default, as for `trample run`.
    #[default]
    Auto,
}

impl StartBackend {
    /// The path to start on with `device` (`None`: no device).
    #[must_use]
    pub fn resolve(self, device: Option<&GpuDevice>) -> BackendKind {
        match (self, device) {
            (Self::Cpu, _) | (_, None) => BackendKind::Cpu,
            (Self::Gpu, Some(_)) => BackendKind::Gpu,
            (Self::Auto, Some(d)) if d.software => BackendKind::Cpu,
            (Self::Auto, Some(_)) => BackendKind::Gpu,
        }
    }
}

/// The device the viewer draws with, lent to the GPU path (wgpu handles
/// are shared references: cloning one does not make a new device).
#[derive(Clone, Debug)]
pub struct GpuDevice {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// "name (backend, device type)".
    pub adapter: String,
    /// A software adapter (Mesa llvmpipe or lavapipe).
    pub software: bool,
}

impl GpuDevice {
    /// The device and queue of `adapter`.
    #[must_use]
    pub fn new(device: wgpu::Device, queue: wgpu::Queue, adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        Self {
            device,
            queue,
            adapter: format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type),
            software: info.device_type == wgpu::DeviceType::Cpu,
        }
    }
}

/// How the last GPU step went, for the panel's stats.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuStepStats {
    /// Its stages were timed one by one ([`GpuSimulation::set_profiling`]);
    /// otherwise `sim.timings` has no stage times and `total_ms` is the
    /// recording time only.
    pub profiled: bool,
    /// Wall time of reading the step's counters back (48 bytes),
    /// milliseconds: without profiling, mostly the wait for the step.
    pub readback_ms: f64,
}

/// The running simulation, on the CPU or on the GPU.
pub enum Backend {
    /// Stepped by [`Simulation::step`].
    Cpu(Box<Simulation>),
    /// Stepped by [`GpuSimulation::step`]; its `sim` holds everything else.
    Gpu(Box<OnGpu>),
}

/// The GPU path's state.
pub struct OnGpu {
    gpu: GpuSimulation,
    device: GpuDevice,
    /// Each blade's class over the run before the GPU path took over: the
    /// GPU counts classes from its own start.
    class_before: Vec<BladeClass>,
    /// The last step.
    stats: GpuStepStats,
}

impl Backend {
    /// The path that runs.
    #[must_use]
    pub fn kind(&self) -> BackendKind {
        match self {
            Self::Cpu(_) => BackendKind::Cpu,
            Self::Gpu(_) => BackendKind::Gpu,
        }
    }

    /// The simulation: on the GPU path, its CPU side (parameters, bodies,
    /// camera, time) and the field as last read back.
    #[must_use]
    pub fn sim(&self) -> &Simulation {
        match self {
            Self::Cpu(sim) => sim,
            Self::Gpu(g) => &g.gpu.sim,
        }
    }

    /// The simulation, to edit: parameters, LOD distances, wind, camera and
    /// driving take effect at the next step on either path.
    pub fn sim_mut(&mut self) -> &mut Simulation {
        match self {
            Self::Cpu(sim) => sim,
            Self::Gpu(g) => &mut g.gpu.sim,
        }
    }

    /// The GPU adapter the simulation runs on, if on the GPU path.
    #[must_use]
    pub fn adapter(&self) -> Option<&str> {
        match self {
            Self::Cpu(_) => None,
            Self::Gpu(g) => Some(&g.device.adapter),
        }
    }

    /// On the GPU path: the GPU simulation, for a renderer drawing straight
    /// from its buffers.
    pub fn gpu_mut(&mut self) -> Option<&mut GpuSimulation> {
        match self {
            Self::Cpu(_) => None,
            Self::Gpu(g) => Some(&mut g.gpu),
        }
    }

    /// On the GPU path: reads the field back into [`Backend::sim`] (blade
    /// positions, classes, levels, slopes), which otherwise holds the field
    /// as it was when the GPU path took over. Nothing on the CPU path.
    ///
    /// # Errors
    /// The read-back failed (device lost).
    pub fn sync_field(&mut self) -> Result<(), String> {
        match self {
            Self::Cpu(_) => Ok(()),
            Self::Gpu(g) => g.read_back(),
        }
    }

    /// On the GPU path: how its last step went.
    #[must_use]
    pub fn gpu_stats(&self) -> Option<GpuStepStats> {
        match self {
            Self::Cpu(_) => None,
            Self::Gpu(g) => Some(g.stats),
        }
    }

    /// Moves the simulation onto the GPU path on `device`, field state and
    /// all (a copy of the simulation is uploaded). Nothing changes when
    /// already there.
    ///
    /// # Errors
    /// Why the GPU path refuses the scene ([`GpuSimulation::supports`]:
    /// a field too large for the device) or the
    /// upload failed; the simulation stays on the CPU.
    pub fn to_gpu(&mut self, device: &GpuDevice) -> Result<(), String> {
        let Self::Cpu(sim) = self else {
            return Ok(());
        };
        let on_gpu = OnGpu::new(device, sim)?;
        *self = Self::Gpu(Box::new(on_gpu));
        Ok(())
    }

    /// Moves the simulation back to the CPU path with the GPU's state.
    ///
    /// # Errors
    /// The read-back failed (device lost): the simulation is on the CPU
    /// anyway, from the last state read back.
    pub fn to_cpu(&mut self) -> Result<(), String> {
        let Self::Gpu(g) = self else {
            return Ok(());
        };
        let read = g.read_back();
        let sim = g.take_over();
        *self = Self::Cpu(Box::new(sim));
        read
    }

    /// Replaces the simulation (a field reset) on the same path: on the
    /// GPU path the GPU side is rebuilt from `sim` (new field, new shape).
    ///
    /// # Errors
    /// The GPU path refused the new simulation: it runs on the CPU.
    pub fn replace(&mut self, sim: Simulation) -> Result<(), String> {
        let device = match self {
            Self::Cpu(_) => None,
            Self::Gpu(g) => Some(g.device.clone()),
        };
        *self = Self::Cpu(Box::new(sim));
        match device {
            Some(d) => self.to_gpu(&d),
            None => Ok(()),
        }
    }

    /// One step of `dt` seconds on the path that runs. `profile`: on the GPU
    /// path, time each stage on its own (slower; see
    /// [`GpuSimulation::set_profiling`]).
    ///
    /// Returns `Ok(Some(message))` when the GPU path failed and the
    /// simulation fell back to the CPU (this step is not retaken).
    ///
    /// # Errors
    /// The CPU step refused its parameters (e.g. `dt`).
    pub fn step(&mut self, dt: f32, profile: bool) -> Result<Option<String>, SimError> {
        match self {
            Self::Cpu(sim) => sim.step(dt).map(|_| None),
            Self::Gpu(g) => match g.step(dt, profile) {
                Ok(()) => Ok(None),
                Err(e) => {
                    let sim = g.take_over();
                    *self = Self::Cpu(Box::new(sim));
                    Ok(Some(e))
                }
            },
        }
    }
}

impl OnGpu {
    fn new(device: &GpuDevice, sim: &Simulation) -> Result<Self, String> {
        let (d, q) = (&device.device, &device.queue);
        GpuSimulation::supports(d, sim).map_err(|e| e.to_string())?;
        let gpu = guarded(d, || GpuSimulation::new(d, q, sim.clone()))?;
        Ok(Self {
            gpu,
            device: device.clone(),
            class_before: sim.class.clone(),
            stats: GpuStepStats::default(),
        })
    }

    /// One GPU step, then its counters back into `sim.timings` for the
    /// stats; the field stays on the GPU (see the module docs).
    fn step(&mut self, dt: f32, profile: bool) -> Result<(), String> {
        let (d, q) = (&self.device.device, &self.device.queue);
        let gpu = &mut self.gpu;
        gpu.set_profiling(profile);
        let mut readback = std::time::Duration::ZERO;
        guarded(d, || {
            gpu.step(d, q, dt)?;
            let start = std::time::Instant::now();
            let read = gpu.sync_counters(d, q);
            readback = start.elapsed();
            read
        })?;
        self.stats = GpuStepStats {
            profiled: profile,
            readback_ms: readback.as_secs_f64() * 1e3,
        };
        Ok(())
    }

    /// The GPU state into `sim`.
    fn read_back(&mut self) -> Result<(), String> {
        let (d, q) = (&self.device.device, &self.device.queue);
        let gpu = &mut self.gpu;
        guarded(d, || gpu.sync_to_cpu(d, q))?;
        self.merge_classes();
        Ok(())
    }

    /// Whole-run classes: hit directly on either path wins, then reached by
    /// propagation on either.
    fn merge_classes(&mut self) {
        const DIRECT: BladeClass = BladeClass::Direct;
        for (now, &before) in self.gpu.sim.class.iter_mut().zip(&self.class_before) {
            *now = if *now == DIRECT || before == DIRECT {
                DIRECT
            } else {
                (*now).max(before)
            };
        }
    }

    /// The simulation as last read back, ready for the CPU path
    /// (`sync_to_cpu` rebuilt its sets of displaced blades).
    fn take_over(&mut self) -> Simulation {
        self.gpu.sim.clone()
    }
}

/// Runs `f` (GPU work on `device`) inside error scopes for validation,
/// out-of-memory and internal errors, so that a failure comes back as a
/// message instead of wgpu's default handler's panic. A panic inside `f`
/// (wgpu's own helpers `expect` a mapping that a lost device refuses,
/// e.g. `create_buffer_init`) is caught too and comes back as a message.
///
/// # Errors
/// `f`'s error or the first error a scope caught, in one line.
pub fn guarded<T>(
    device: &wgpu::Device,
    f: impl FnOnce() -> Result<T, GpuError>,
) -> Result<T, String> {
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    // After a panic the GPU side is dropped, never used again: nothing is
    // seen half-updated.
    let out = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(out) => out.map_err(|e| e.to_string()),
        Err(panic) => {
            let why = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("no message");
            Err(format!("wgpu panicked: {why}"))
        }
    };
    // Scopes pop in reverse order of their pushes.
    let caught = [internal.pop(), validation.pop(), oom.pop()]
        .into_iter()
        .find_map(pollster::block_on);
    let one_line = |s: String| s.replace('\n', " ");
    match (out, caught) {
        (Ok(v), None) => Ok(v),
        (Ok(_), Some(e)) => Err(one_line(format!("GPU error: {e}"))),
        (Err(e), None) => Err(one_line(format!("GPU error: {e}"))),
        // The device's own words say more than the call that noticed.
        (Err(e), Some(c)) => Err(one_line(format!("GPU error: {c} ({e})"))),
    }
}
