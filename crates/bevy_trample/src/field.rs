//! The grass field: a [`Resource`] holding the simulation, built from the
//! same parameters as a scene file ([`SceneFile`]) or from a scene file.

use crate::TrampleError;
use crate::host::{BladeChanges, CellChanges};
use bevy::prelude::*;
use std::path::Path;
use trample::Simulation;
use trample::builder::SimulationBuilder;
use trample::scene::{Scene, SceneFile};

/// The meadow: the trample simulation of one grass field (its blades,
/// cells and terrain, the bodies in it, its parameters).
///
/// Insert it before or after adding [`crate::TramplePlugin`]; entities with
/// [`crate::Trampler`] then become bodies in it. Scene-file objects (a
/// scene's `[[objects]]`) stay in it and follow their paths; the plugin
/// neither draws nor removes them.
///
/// World frame: the core's, which is Bevy's (y up, right-handed, metres);
/// the field is centred on the origin.
#[derive(Resource)]
pub struct TrampleField {
    /// The simulation (read it for the blades, cells and timings; the
    /// plugin steps it).
    pub sim: Simulation,
    /// Blades the steps changed since the renderer last took them.
    pub(crate) changes: BladeChanges,
    /// Cells the steps changed since the ground last took them.
    pub(crate) cell_changes: CellChanges,
    /// Bodies the plugin put in the simulation for [`crate::Trampler`]s.
    pub(crate) tramplers: usize,
    /// The path asked for ([`TrampleField::on_gpu`]).
    pub(crate) backend: TrampleBackend,
    /// The field on the GPU path, once handed over.
    #[cfg(feature = "gpu")]
    pub(crate) gpu: Option<crate::gpu_path::GpuPath>,
    /// Why the GPU path was refused, when it was.
    pub(crate) gpu_refused: Option<String>,
}

/// Which of trample's two paths steps the field: the CPU path (the
/// specification, the default) or the GPU path (feature `gpu`, Bevy's own
/// device; see [`TrampleField::on_gpu`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TrampleBackend {
    /// The CPU path (`Simulation::step`, on all cores).
    #[default]
    Cpu,
    /// The GPU path (trample-gpu on Bevy's render device), the draws
    /// reading its buffers.
    Gpu,
}

impl TrampleField {
    /// Builds the field a scene file's values describe (every key of a
    /// scene file can be set in code this way; `file.objects` become bodies
    /// that follow their paths).
    ///
    /// # Errors
    /// [`TrampleError::Scene`] with the message a scene file with these
    /// values would give (the key, its value and what is allowed).
    pub fn from_scene_file(file: &SceneFile) -> Result<Self, TrampleError> {
        Self::from_builder(&SimulationBuilder::from_scene_file(file, Path::new(".")))
    }

    /// Builds the field a [`SimulationBuilder`] describes (the core's
    /// builder: field, level of detail, simulation, wind, grass maps,
    /// bodies of its own).
    ///
    /// # Errors
    /// [`TrampleError::Scene`] naming the key, its value and what is allowed.
    pub fn from_builder(builder: &SimulationBuilder) -> Result<Self, TrampleError> {
        let sim = builder
            .build()
            .map_err(|e| TrampleError::Scene(e.to_string()))?;
        Ok(Self::from_simulation(sim))
    }

    /// Builds the field of the scene file at `path` (meshes it names are
    /// read from its folder).
    ///
    /// # Errors
    /// [`TrampleError::Scene`]: unreadable file, TOML error, bad value.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, TrampleError> {
        let scene = Scene::load(path.as_ref()).map_err(|e| TrampleError::Scene(e.to_string()))?;
        Self::from_scene(&scene)
    }

    /// Builds the field of a parsed scene.
    ///
    /// # Errors
    /// [`TrampleError::Scene`] for a value the scene does not allow.
    pub fn from_scene(scene: &Scene) -> Result<Self, TrampleError> {
        let sim = scene
            .build()
            .map_err(|e| TrampleError::Scene(e.to_string()))?;
        Ok(Self::from_simulation(sim))
    }

    /// Wraps a simulation built some other way.
    #[must_use]
    pub fn from_simulation(sim: Simulation) -> Self {
        Self {
            sim,
            changes: BladeChanges::default(),
            cell_changes: CellChanges::default(),
            tramplers: 0,
            backend: TrampleBackend::Cpu,
            #[cfg(feature = "gpu")]
            gpu: None,
            gpu_refused: None,
        }
    }

    /// The field asks to be stepped on the GPU path (feature `gpu`): the
    /// first step once Bevy's render device exists hands the simulation
    /// to trample's GPU path on that device, and the draws read its
    /// buffers (nothing goes back to the CPU). Steps before that, and every
    /// step in an app without a renderer, run on the CPU path. A field the
    /// GPU path cannot take stays on the CPU path, and
    /// [`TrampleField::gpu_refused`] says why.
    ///
    /// On the GPU path `sim` holds the bodies, poses, time and timings
    /// (`total_ms` is the time to record the step), and the cells'
    /// flatness (copied back a frame or two late, for the track on the
    /// ground), but its blades and the rest of its cells keep the state
    /// they were handed over in: [`TrampleField::read_back_gpu`] copies the
    /// GPU's back.
    #[must_use]
    pub fn on_gpu(mut self) -> Self {
        self.backend = TrampleBackend::Gpu;
        #[cfg(not(feature = "gpu"))]
        {
            self.gpu_refused = Some("bevy_trample was built without its `gpu` feature".to_string());
        }
        self
    }

    /// The path that stepped the field last (the GPU path only once the
    /// simulation was handed over).
    #[must_use]
    pub fn backend(&self) -> TrampleBackend {
        #[cfg(feature = "gpu")]
        if self.gpu.is_some() {
            return TrampleBackend::Gpu;
        }
        TrampleBackend::Cpu
    }

    /// Why the GPU path asked for was refused (the device's limits, a field
    /// too large, a plugin built without the `gpu` feature), when it was.
    #[must_use]
    pub fn gpu_refused(&self) -> Option<&str> {
        self.gpu_refused.as_deref()
    }

    /// Whether the next step is to try the GPU path.
    #[cfg(feature = "render")]
    pub(crate) fn wants_gpu(&self) -> bool {
        self.backend == TrampleBackend::Gpu && self.gpu_refused.is_none()
    }

    /// The paper's field (16 × 16 patches of 32 × 32 cells, 262,144 blades,
    /// 51.2 m square) with no objects of its own: what a game starts from.
    #[must_use]
    pub fn paper_meadow() -> SceneFile {
        SceneFile {
            objects: Vec::new(),
            ..Scene::default_scene().map(|s| s.file).unwrap_or_default()
        }
    }

    /// Bodies the plugin put in the simulation for [`crate::Trampler`]s.
    #[must_use]
    pub fn tramplers(&self) -> usize {
        self.tramplers
    }
}
