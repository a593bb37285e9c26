//! [`SimulationBuilder`]: a field, its bodies and the rest of a simulation
//! from values. Scene files build through it ([`crate::scene::Scene::build`]),
//! so every check lives here once.

use super::body::BodyBuilder;
use super::error::BuildError;
use crate::camera::{Camera, CameraParams, CameraTarget, LookAt};
use crate::field::generate::growing_blades;
use crate::field::{Field, FieldParams, GrassMaps, LodParams, Terrain};
use crate::obb::DEFAULT_MAX_DEPTH;
use crate::obb::shared::{Winding, build_shared};
use crate::object::Path as EyePath;
use crate::object::{Object, TriMesh};
use crate::recovery::RECOVERY_CLOCK_BYTES;
use crate::scene::SceneFile;
use crate::step::{Body, HostView, SimParams, Simulation};
use crate::wind::WindParams;
use glam::Vec3;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Everything a simulation is made of, as values; [`SimulationBuilder::build`]
/// checks them all and makes the [`Simulation`]. The defaults are the
/// scene-file defaults (the paper's 262,144-blade field, no bodies, the
/// default camera path); everything a scene file can say is a field here,
/// and code can say more (grass maps as closures, a terrain, a host view).
///
/// ```
/// use trample::builder::{BodyBuilder, SimulationBuilder};
/// use trample::field::FieldParams;
///
/// let mut sim = SimulationBuilder::new()
///     .field(FieldParams { patches: [2, 2], cells_per_patch: 16, ..FieldParams::default() })
///     .body(BodyBuilder::sphere("ball", 0.3).at([0.0, 0.3, 0.0]))
///     .build()?;
/// sim.step(1.0 / 60.0)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct SimulationBuilder {
    /// The field (`[field]`), including its grass-map images (`[field.maps]`).
    pub field: FieldParams,
    /// Level-of-detail distances (`[lod]`).
    pub lod: LodParams,
    /// Method parameters (`[sim]`).
    pub sim: SimParams,
    /// The scene's camera (`[camera]`); a host camera replaces it for LOD
    /// and culling ([`SimulationBuilder::host_view`]).
    pub camera: CameraParams,
    /// Wind drawn over the grass (`[wind]`).
    pub wind: WindParams,
    /// The bodies (`[[objects]]`), in order: their ids are 0, 1, ...
    pub bodies: Vec<BodyBuilder>,
    /// Grass maps given in code; `None`: those `field.maps` names (images).
    pub maps: Option<GrassMaps>,
    /// A terrain given in code; `None`: the one `field.terrain` describes.
    pub terrain: Option<Terrain>,
    /// The host's camera, in charge of LOD and culling from the start.
    pub host_view: Option<HostView>,
    /// Folder that files named by the values (meshes, height map, grass
    /// maps) are read from and must stay inside. Default `.`.
    pub base_dir: PathBuf,
}

impl Default for SimulationBuilder {
    fn default() -> Self {
        Self {
            field: FieldParams::default(),
            lod: LodParams::default(),
            sim: SimParams::default(),
            camera: CameraParams::default(),
            wind: WindParams::default(),
            bodies: Vec::new(),
            maps: None,
            terrain: None,
            host_view: None,
            base_dir: PathBuf::from("."),
        }
    }
}

impl SimulationBuilder {
    /// The defaults (see the type's docs).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The values of a scene file whose files are in `base_dir`.
    #[must_use]
    pub fn from_scene_file(file: &SceneFile, base_dir: &Path) -> Self {
        Self {
            field: file.field.clone(),
            lod: file.lod.clone(),
            sim: file.sim.clone(),
            camera: file.camera.clone(),
            wind: file.wind.clone(),
            bodies: file
                .objects
                .iter()
                .cloned()
                .map(BodyBuilder::from_params)
                .collect(),
            maps: None,
            terrain: None,
            host_view: None,
            base_dir: base_dir.to_path_buf(),
        }
    }

    /// Sets the field.
    #[must_use]
    pub fn field(mut self, field: FieldParams) -> Self {
        self.field = field;
        self
    }

    /// Sets the level-of-detail distances.
    #[must_use]
    pub fn lod(mut self, lod: LodParams) -> Self {
        self.lod = lod;
        self
    }

    /// Sets the method parameters.
    #[must_use]
    pub fn sim(mut self, sim: SimParams) -> Self {
        self.sim = sim;
        self
    }

    /// Sets the scene's camera.
    #[must_use]
    pub fn camera(mut self, camera: CameraParams) -> Self {
        self.camera = camera;
        self
    }

    /// Sets the wind.
    #[must_use]
    pub fn wind(mut self, wind: WindParams) -> Self {
        self.wind = wind;
        self
    }

    /// Adds a body (its id will be its position in this list).
    #[must_use]
    pub fn body(mut self, body: BodyBuilder) -> Self {
        self.bodies.push(body);
        self
    }

    /// Grass maps from code (values or closures), instead of `field.maps`.
    #[must_use]
    pub fn maps(mut self, maps: GrassMaps) -> Self {
        self.maps = Some(maps);
        self
    }

    /// A terrain from code, instead of `field.terrain`.
    #[must_use]
    pub fn terrain(mut self, terrain: Terrain) -> Self {
        self.terrain = Some(terrain);
        self
    }

    /// The host's camera decides LOD and culling from the first step.
    #[must_use]
    pub fn host_view(mut self, view: HostView) -> Self {
        self.host_view = Some(view);
        self
    }

    /// The folder files named by the values are read from.
    #[must_use]
    pub fn base_dir(mut self, base_dir: impl Into<PathBuf>) -> Self {
        self.base_dir = base_dir.into();
        self
    }

    /// Checks every value that can be checked without reading files, in
    /// this order: field, sim, wind, lod, camera, the camera's target, body
    /// names, memory. The memory check counts the blades the grass maps
    /// leave out when they are given in code; maps still to be read from
    /// images are checked by [`SimulationBuilder::build`] once read.
    ///
    /// # Errors
    /// The first [`BuildError`] found.
    pub fn validate(&self) -> Result<(), BuildError> {
        self.field.validate()?;
        self.sim.validate()?;
        self.wind.validate().map_err(BuildError::Wind)?;
        self.lod.validate()?;
        self.camera.validate()?;
        if let LookAt::Object { name } = &self.camera.look_at {
            // The default camera follows "ball"; a scene without it looks at the centre.
            let default_follow = self.camera == CameraParams::default();
            if !default_follow && !self.bodies.iter().any(|b| &b.params.name == name) {
                return Err(BuildError::CameraTarget {
                    name: name.clone(),
                    names: self.bodies.iter().map(|b| b.params.name.clone()).collect(),
                });
            }
        }
        let mut seen = std::collections::HashSet::new();
        for (index, b) in self.bodies.iter().enumerate() {
            if !seen.insert(&b.params.name) {
                return Err(BuildError::DuplicateName {
                    index,
                    name: b.params.name.clone(),
                });
            }
        }
        if let Some(view) = &self.host_view {
            view.check()?;
        }
        if !self.maps_from_images() {
            let maps = self.maps.clone().unwrap_or_default();
            self.check_memory(&maps)?;
        }
        Ok(())
    }

    /// The memory the field needs at most, bytes
    /// ([`FieldParams::memory_estimate_bytes_for`] with the blades the
    /// grass maps let grow, plus, while `sim.recovery_stride_m` > 0, the
    /// strides' clock: [`RECOVERY_CLOCK_BYTES`] a blade); reads the map
    /// images if there are any.
    ///
    /// # Errors
    /// [`BuildError::Maps`] when a map image cannot be read.
    pub fn memory_estimate_bytes(&self) -> Result<u64, BuildError> {
        let maps = self.grass_maps()?;
        Ok(self.memory_estimate_bytes_with(&maps))
    }

    /// [`SimulationBuilder::memory_estimate_bytes`] with grass maps read
    /// already (e.g. by [`SimulationBuilder::load_ground`]):
    /// [`FieldParams::memory_estimate_bytes_for`] the blades `maps` let
    /// grow, plus, with slow blades recovering in strides
    /// (`sim.recovery_stride_m` > 0), their clock: [`RECOVERY_CLOCK_BYTES`]
    /// a blade (`Scratch::recover_clock`, made when some owner recovers —
    /// a body the host adds later may, so it is counted whatever the
    /// scene's own recovery).
    #[must_use]
    pub fn memory_estimate_bytes_with(&self, maps: &GrassMaps) -> u64 {
        let clock = if self.sim.recovery_stride_m > 0.0 {
            self.field.blade_count() * RECOVERY_CLOCK_BYTES
        } else {
            0
        };
        self.field
            .memory_estimate_bytes_for(growing_blades(&self.field, maps))
            + clock
    }

    /// Builds the simulation at time 0: checks ([`SimulationBuilder::validate`]),
    /// terrain, grass maps (and the memory check they wait for), bodies and
    /// their OBB trees, the field, the camera.
    ///
    /// # Errors
    /// The first [`BuildError`] found.
    pub fn build(&self) -> Result<Simulation, BuildError> {
        let (terrain, maps) = self.load_ground()?;
        let estimate = self.memory_estimate_bytes_with(&maps);
        let objects: Vec<Object> = self
            .bodies
            .par_iter()
            .enumerate()
            .map(|(i, b)| Object::from_params(&b.params, i, &self.base_dir))
            .collect::<Result<_, _>>()?;
        // Each distinct mesh's tree once (a herd repeats a few meshes).
        let meshes: Vec<&TriMesh> = objects
            .iter()
            .flat_map(|o| std::iter::once(&o.mesh).chain(o.parts.parts.iter().map(|p| &p.mesh)))
            .collect();
        let winding: Vec<Winding> = objects.iter().flat_map(Winding::of).collect();
        let (trees, _) = build_shared(&meshes, &winding, DEFAULT_MAX_DEPTH);
        let mut trees = trees.into_iter();
        let bodies: Vec<Body> = objects
            .into_iter()
            .map(|o| {
                let tree = trees.next().expect("one tree per mesh");
                let parts = trees.by_ref().take(o.parts.parts.len()).collect();
                Body::with_trees(o, tree, parts)
            })
            .collect();
        let field = Field::generate_with_maps(&self.field, terrain, &maps)?;
        let camera = self.make_camera(&bodies)?;
        let mut sim = Simulation::new(field, bodies, camera, self.lod.clone(), self.sim.clone());
        sim.wind = self.wind.clone();
        sim.memory_estimate_bytes = Some(estimate);
        if let Some(view) = self.host_view {
            sim.set_view(view)?;
            // Levels of detail from the host's eye before the first step too.
            sim.classify_at_rest();
        }
        Ok(sim)
    }

    /// Checks ([`SimulationBuilder::validate`]) and reads the ground as
    /// [`SimulationBuilder::build`] does: the terrain (its height map, if
    /// any) and the grass maps (their images), then checks the memory
    /// limit that waits for the maps. What `trample check` runs, so that a
    /// bad height map or map image is found there, not only by a run. The
    /// objects' meshes are not read ([`crate::scene::Scene::objects`]).
    ///
    /// # Errors
    /// The first [`BuildError`] found.
    pub fn load_ground(&self) -> Result<(Terrain, GrassMaps), BuildError> {
        self.validate()?;
        let terrain = match &self.terrain {
            Some(t) => t.clone(),
            None => {
                Terrain::from_params(&self.field.terrain, self.field.extent_m(), &self.base_dir)?
            }
        };
        let maps = self.grass_maps()?;
        if self.maps_from_images() {
            self.check_memory(&maps)?;
        }
        Ok((terrain, maps))
    }

    /// True when the grass maps are still to be read from images.
    fn maps_from_images(&self) -> bool {
        self.maps.is_none() && !self.field.maps.is_empty()
    }

    /// The grass maps: from code, or read from `field.maps`.
    fn grass_maps(&self) -> Result<GrassMaps, BuildError> {
        match &self.maps {
            Some(m) => Ok(m.clone()),
            None => Ok(GrassMaps::from_params(
                &self.field.maps,
                self.field.extent_m(),
                &self.base_dir,
            )?),
        }
    }

    fn check_memory(&self, maps: &GrassMaps) -> Result<(), BuildError> {
        let need = self.memory_estimate_bytes_with(maps);
        let limit = (f64::from(self.sim.memory_limit_gib) * 1024f64.powi(3)) as u64;
        if need > limit {
            return Err(BuildError::Memory {
                need_bytes: need,
                blades: self.field.blade_count(),
                limit_gib: self.sim.memory_limit_gib,
            });
        }
        Ok(())
    }

    fn make_camera(&self, bodies: &[Body]) -> Result<Camera, BuildError> {
        let c = &self.camera;
        let eye = EyePath::new(c.path.clone()).map_err(crate::camera::CameraError::Path)?;
        let target = match &c.look_at {
            LookAt::Point { at } => CameraTarget::Point(Vec3::from(*at)),
            LookAt::Object { name } => match bodies.iter().position(|b| &b.object.name == name) {
                Some(i) => CameraTarget::Object(i),
                None => CameraTarget::Point(Vec3::ZERO),
            },
        };
        Ok(Camera {
            eye,
            target,
            params: c.clone(),
        })
    }
}
