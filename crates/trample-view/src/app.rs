//! The viewer's state and what each key and panel control does to it, with
//! no window: [`App`] owns the simulation (on the CPU or the GPU path, see
//! [`crate::backend`]), the camera controllers, the driven object and the
//! settings that wait for a reset. The window feeds it keys and mouse motion,
//! lends it its GPU device and draws what it holds; tests script it directly.

use crate::ViewError;
use crate::backend::{Backend, BackendKind, GpuDevice};
use crate::camera::{CameraMode, Fly, Orbit};
use crate::driver::Driver;
use crate::input::{Action, Input, Key};
use glam::Vec3;
use trample::Simulation;
use trample::camera::Camera;
use trample::object::Orientation;
use trample::object::{Motion, ShapeParams};
use trample::scene::Scene;
use trample::step::HostView;
use trample_render::DebugView;

/// Highest precision the panel and keys offer (the paper's range is 1–7).
pub const MAX_PRECISION: u32 = 10;
/// Most blades per cell the panel offers for the next reset.
pub const MAX_BLADES_PER_CELL: u32 = 8;

/// The first object's shape as the panel offers it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeChoice {
    /// The scene's own shape.
    Scene,
    /// A 1 m sphere.
    Sphere,
    /// A 1.6 × 1 × 1 m box.
    Box,
    /// A capsule, 0.5 m radius, 1 m long.
    Capsule,
    /// The built-in torus knot, 2 m across.
    Knot,
    /// The mesh file in [`Pending::mesh_path`].
    MeshFile,
}

impl ShapeChoice {
    /// Every choice, in panel order.
    pub const ALL: [ShapeChoice; 6] = [
        Self::Scene,
        Self::Sphere,
        Self::Box,
        Self::Capsule,
        Self::Knot,
        Self::MeshFile,
    ];

    /// Name shown in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Scene => "as in the scene",
            Self::Sphere => "sphere",
            Self::Box => "box",
            Self::Capsule => "capsule",
            Self::Knot => "knot",
            Self::MeshFile => "mesh file",
        }
    }
}

/// Settings that take effect at the next field reset (they rebuild the field
/// or the object's tree).
#[derive(Clone, Debug, PartialEq)]
pub struct Pending {
    /// Blades per cell.
    pub blades_per_cell: u32,
    /// Shape of the first object.
    pub shape: ShapeChoice,
    /// Mesh file for [`ShapeChoice::MeshFile`] (`.obj`, `.gltf`, `.glb`),
    /// relative to the scene's folder and inside it.
    pub mesh_path: String,
}

/// The viewer's state.
pub struct App {
    /// The scene as last built (with the settings of the last reset).
    pub scene: Scene,
    /// The running simulation and the path that steps it: see [`App::sim`].
    backend: Backend,
    /// The device the window lends to the GPU path.
    gpu: Option<GpuDevice>,
    /// Why the GPU path failed on that device, if it did: the device may
    /// be lost, so the GPU path is not offered again.
    gpu_failed: Option<String>,
    /// Time each stage of a GPU step on its own (the panel sets it while
    /// its per-stage stats are shown; see `GpuSimulation::set_profiling`).
    pub stage_times: bool,
    /// Held keys.
    pub input: Input,
    /// Simulation paused.
    pub paused: bool,
    step_once: bool,
    /// The first object is driven by the arrow keys (else it follows its path).
    pub driving: bool,
    /// The driven object's state.
    pub driver: Driver,
    /// Camera in use.
    pub camera_mode: CameraMode,
    /// Orbit camera state.
    pub orbit: Orbit,
    /// Free-fly camera state.
    pub fly: Fly,
    /// Debug view of the renderer.
    pub debug: DebugView,
    /// Panel shown.
    pub show_panel: bool,
    /// Settings for the next reset.
    pub pending: Pending,
    /// A screenshot was asked for (the window takes it and clears this).
    pub screenshot_requested: bool,
    /// Counts field rebuilds: the window rebuilds its renderer when it changes.
    pub field_version: u64,
    /// Last message for the panel (errors of a reset, screenshot written, ...).
    pub message: String,
    scene_camera: Camera,
    aspect: f32,
}

impl App {
    /// Builds the scene's simulation.
    ///
    /// # Errors
    /// [`ViewError::Scene`] when the scene does not build.
    pub fn new(scene: Scene) -> Result<Self, ViewError> {
        let sim = scene.build().map_err(|e| ViewError::Scene(e.to_string()))?;
        let view = sim.view;
        let pending = Pending {
            blades_per_cell: scene.file.field.blades_per_cell,
            shape: ShapeChoice::Scene,
            mesh_path: String::new(),
        };
        let mut app = Self {
            input: Input::default(),
            paused: false,
            step_once: false,
            driving: false,
            driver: driver_for(&sim),
            camera_mode: CameraMode::default(),
            orbit: Orbit::default(),
            fly: Fly::looking_at(view.eye, view.target),
            debug: DebugView::None,
            show_panel: true,
            pending,
            screenshot_requested: false,
            field_version: 0,
            message: String::new(),
            scene_camera: sim.camera.clone(),
            aspect: sim.camera.params.aspect,
            scene,
            backend: Backend::Cpu(Box::new(sim)),
            gpu: None,
            gpu_failed: None,
            stage_times: false,
        };
        app.apply_camera();
        Ok(app)
    }

    /// The running simulation (on the GPU path: its CPU side, with the
    /// field as read back after the last step).
    #[must_use]
    pub fn sim(&self) -> &Simulation {
        self.backend.sim()
    }

    /// The running simulation, to edit: parameters (`params`, `lod`,
    /// `wind`) take effect at the next step on either path.
    pub fn sim_mut(&mut self) -> &mut Simulation {
        self.backend.sim_mut()
    }

    /// The path that steps the simulation.
    #[must_use]
    pub fn backend(&self) -> &Backend {
        &self.backend
    }

    /// On the GPU path: the GPU simulation, for the renderer to draw
    /// straight from its buffers.
    pub fn gpu_mut(&mut self) -> Option<&mut trample_gpu::GpuSimulation> {
        self.backend.gpu_mut()
    }

    /// On the GPU path: the field read back into [`App::sim`] (see
    /// [`Backend::sync_field`]); nothing on the CPU path.
    ///
    /// # Errors
    /// The read-back failed (device lost).
    pub fn sync_field(&mut self) -> Result<(), String> {
        self.backend.sync_field()
    }

    /// Lends the GPU path a device (the window's own; tests bring one).
    pub fn attach_gpu(&mut self, device: GpuDevice) {
        self.gpu = Some(device);
        self.gpu_failed = None;
    }

    /// Why the GPU path failed on the lent device, if it did (it is not
    /// offered again on that device).
    #[must_use]
    pub fn gpu_failed(&self) -> Option<&str> {
        self.gpu_failed.as_deref()
    }

    /// The device lent to the GPU path, if any.
    #[must_use]
    pub fn gpu_device(&self) -> Option<&GpuDevice> {
        self.gpu.as_ref()
    }

    /// Moves the simulation to the `kind` path, field state and all; says
    /// what happened in [`App::message`]. The GPU path needs a device
    /// ([`App::attach_gpu`]) and a scene it supports.
    ///
    /// # Errors
    /// Why the GPU path was refused (no device, a field too large for it)
    /// or failed: the simulation then runs on the CPU.
    pub fn set_backend(&mut self, kind: BackendKind) -> Result<(), String> {
        if kind == self.backend.kind() {
            return Ok(());
        }
        let done = match kind {
            BackendKind::Cpu => self.backend.to_cpu().map_err(|e| {
                self.gpu_failed = Some(e.clone());
                format!("{e}; simulating on the CPU from the last state read back")
            }),
            BackendKind::Gpu => match (&self.gpu, &self.gpu_failed) {
                (None, _) => Err("no GPU device to simulate on; simulating on the CPU".to_string()),
                (Some(_), Some(failed)) => Err(format!(
                    "GPU path refused: it failed on this device before ({failed}); simulating on the CPU"
                )),
                (Some(d), None) => self
                    .backend
                    .to_gpu(d)
                    .map_err(|e| format!("GPU path refused: {e}; simulating on the CPU")),
            },
        };
        self.message = match &done {
            Ok(()) => self.backend_line(),
            Err(e) => e.clone(),
        };
        done
    }

    /// "simulating on the CPU" / "simulating on the GPU: ADAPTER".
    fn backend_line(&self) -> String {
        match self.backend.adapter() {
            Some(a) => format!("simulating on the GPU: {a}"),
            None => "simulating on the CPU".to_string(),
        }
    }

    /// A key went down (`pressed`) or up; `repeat` for auto-repeat.
    pub fn key(&mut self, key: Key, pressed: bool, repeat: bool) {
        if let Some(action) = self.input.key(key, pressed, repeat) {
            self.act(action);
        }
    }

    /// Does what `action` asks.
    pub fn act(&mut self, action: Action) {
        match action {
            Action::TogglePause => self.paused = !self.paused,
            Action::SingleStep => {
                self.paused = true;
                self.step_once = true;
            }
            Action::ResetField => {
                if let Err(e) = self.reset_field() {
                    self.message = format!("reset failed: {e}");
                }
            }
            Action::RestartPath => self.restart_paths(),
            Action::ToggleDrive => self.set_driving(!self.driving),
            Action::NextCamera => self.camera_mode = self.camera_mode.next(),
            Action::NextDebugView => {
                self.debug = self.debug.next();
            }
            Action::Screenshot => self.screenshot_requested = true,
            Action::TogglePanel => self.show_panel = !self.show_panel,
            Action::Precision(d) => {
                let params = &mut self.sim_mut().params;
                let p = params.precision as i32 + d;
                params.precision = p.clamp(1, MAX_PRECISION as i32) as u32;
            }
        }
    }

    /// A mouse drag over the scene of (dx, dy) pixels: turns the orbit or
    /// free-fly camera.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        match self.camera_mode {
            CameraMode::Orbit => self.orbit.drag(dx, dy),
            CameraMode::Fly => self.fly.drag(dx, dy),
            CameraMode::Scene => {}
        }
    }

    /// Mouse wheel over the scene, in notches (orbit zoom).
    pub fn scroll(&mut self, lines: f32) {
        self.orbit.zoom(lines);
    }

    /// Width / height of the picture (culling and the camera's aspect).
    pub fn set_aspect(&mut self, aspect: f32) {
        if aspect.is_finite() && aspect > 0.0 {
            self.aspect = aspect;
        }
    }

    /// Starts or stops driving the first object. Driving starts where the
    /// object is, facing where it goes; stopping gives it back to its path.
    pub fn set_driving(&mut self, on: bool) {
        if self.sim().bodies.is_empty() || on == self.driving {
            return;
        }
        self.driving = on;
        if on {
            self.driver = driver_for(self.sim());
        } else {
            self.sim_mut().release(0);
        }
    }

    /// One frame that took `frame_dt` seconds of wall time: the free-fly
    /// camera moves in wall time; the simulation takes one step of its
    /// `dt_s` unless paused (so a slow machine shows slow motion, not a
    /// coarser simulation). Returns whether it stepped. On the GPU path a
    /// failed step (device lost, out of memory) puts the simulation back on
    /// the CPU, from the last state read back, and says so in
    /// [`App::message`].
    ///
    /// # Errors
    /// [`ViewError::Step`] when the step refuses its parameters.
    pub fn update(&mut self, frame_dt: f32) -> Result<bool, ViewError> {
        let held = self.input.held;
        if self.camera_mode == CameraMode::Fly {
            self.fly
                .update(held.fly(), held.shift, frame_dt.clamp(0.0, 0.1));
        }
        if held.arrows() && !self.driving {
            self.set_driving(true);
        }
        let step = !self.paused || std::mem::take(&mut self.step_once);
        if !step {
            self.apply_camera();
            return Ok(false);
        }
        let dt = self.sim().params.dt_s;
        if self.driving {
            self.driver.update(&held, dt);
            let (position, rotation) = (self.driver.position, self.driver.rotation);
            self.sim_mut().drive(0, position, rotation, dt);
        }
        self.apply_camera();
        let fell_back = self
            .backend
            .step(dt, self.stage_times)
            .map_err(|e| ViewError::Step(e.to_string()))?;
        if let Some(e) = fell_back {
            self.message = format!("{e}; simulating on the CPU from the last state read back");
            self.gpu_failed = Some(e);
        }
        Ok(true)
    }

    /// Rebuilds the field at rest with the live parameters and the pending
    /// settings (blade density, shape), on the same path (the GPU path is
    /// rebuilt; if it refuses the new field, the CPU path takes it). On
    /// error the running simulation is kept and the error returned.
    ///
    /// # Errors
    /// The scene's message for a setting it refuses (e.g. a mesh path
    /// outside the scene's folder).
    pub fn reset_field(&mut self) -> Result<(), String> {
        let mut scene = self.scene.clone();
        let live = self.sim();
        scene.file.sim = live.params.clone();
        scene.file.lod = live.lod.clone();
        scene.file.wind = live.wind.clone();
        scene.file.field.blades_per_cell = self.pending.blades_per_cell;
        if let Some(object) = scene.file.objects.first_mut() {
            object.shape = self.pending_shape(&object.shape);
        }
        let sim = scene.build().map_err(|e| e.to_string())?;
        self.scene = scene;
        self.scene_camera = sim.camera.clone();
        let blades = sim.field.blades.count;
        let on_gpu = self.backend.replace(sim);
        self.driving = false;
        self.driver = driver_for(self.sim());
        self.field_version += 1;
        self.message = match on_gpu {
            Ok(()) => format!("field reset: {blades} blades"),
            Err(e) => format!(
                "field reset: {blades} blades; GPU path refused: {e}; simulating on the CPU"
            ),
        };
        self.apply_camera();
        Ok(())
    }

    /// Every object starts its path again from now (the field is kept).
    pub fn restart_paths(&mut self) {
        self.set_driving(false);
        let sim = self.backend.sim_mut();
        let t = sim.time as f32;
        for (body, params) in sim.bodies.iter_mut().zip(&self.scene.file.objects) {
            let m = &body.object.motion;
            if let Ok(motion) = Motion::new(
                m.path().clone(),
                m.orientation(),
                params.start_s + t,
                m.roll_radius(),
            ) {
                body.object.motion = motion;
                body.set_time(t);
            }
        }
    }

    fn pending_shape(&self, current: &ShapeParams) -> ShapeParams {
        match self.pending.shape {
            ShapeChoice::Scene => current.clone(),
            ShapeChoice::Sphere => ShapeParams::Sphere {
                radius_m: 1.0,
                subdivisions: 3,
            },
            ShapeChoice::Box => ShapeParams::Box {
                half_extents_m: [0.8, 0.5, 0.5],
            },
            ShapeChoice::Capsule => ShapeParams::Capsule {
                radius_m: 0.5,
                length_m: 1.0,
            },
            ShapeChoice::Knot => ShapeParams::Knot { size_m: 2.0 },
            ShapeChoice::MeshFile => ShapeParams::Mesh {
                path: self.pending.mesh_path.clone().into(),
                anchor: Default::default(),
            },
        }
    }

    /// Puts the current camera into the simulation: the scene's camera
    /// path, or the orbit or free-fly camera as the host's view
    /// ([`Simulation::set_view`]: its eye is the LOD viewpoint and its
    /// frustum culls the patches, at once, so a paused view follows too;
    /// levels of detail follow at the next step, which blends them).
    fn apply_camera(&mut self) {
        let target = self
            .sim()
            .bodies
            .first()
            .map_or(Vec3::ZERO, |b| b.pose.position);
        let eye_target = match self.camera_mode {
            CameraMode::Scene => None,
            CameraMode::Orbit => Some((self.orbit.eye(target), target)),
            CameraMode::Fly => Some((self.fly.eye, self.fly.target())),
        };
        let mut camera = self.scene_camera.clone();
        camera.params.aspect = self.aspect;
        let lens = camera.params.clone();
        let sim = self.backend.sim_mut();
        sim.camera = camera;
        match eye_target {
            None => sim.clear_view(),
            Some((eye, target)) => {
                // A non-finite eye (cannot come from the controllers) keeps the last view.
                if let Ok(view) = HostView::look_at(
                    eye,
                    target,
                    lens.fov_y_deg.to_radians(),
                    lens.aspect,
                    lens.near_m,
                    lens.far_m,
                ) {
                    let _ = sim.set_view(view);
                }
            }
        }
    }
}

/// A driver starting at the first object's pose, facing its motion.
fn driver_for(sim: &Simulation) -> Driver {
    let Some(body) = sim.bodies.first() else {
        return Driver::new(Vec3::ZERO, 0.0, glam::Quat::IDENTITY, 0.0);
    };
    let pose = body.pose;
    let motion = &body.object.motion;
    let heading = motion
        .path()
        .heading(sim.time as f32 - motion.start_s())
        .map_or(0.0, |h| h.x.atan2(h.z));
    let roll = if motion.orientation() == Orientation::Rolling {
        motion.roll_radius()
    } else {
        0.0
    };
    Driver::new(pose.position, heading, pose.rotation, roll)
}
