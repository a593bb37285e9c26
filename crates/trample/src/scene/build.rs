//! From a scene to a running [`Simulation`]: through
//! [`SimulationBuilder`], which holds every check, so a scene file and a
//! host's code are validated alike. Errors are the builder's, prefixed with
//! the file's name.

use super::{Scene, SceneError};
use crate::builder::SimulationBuilder;
use crate::object::Object;
use crate::step::Simulation;
use rayon::prelude::*;

impl Scene {
    /// The builder holding this scene's values (files resolved in its folder).
    #[must_use]
    pub fn builder(&self) -> SimulationBuilder {
        SimulationBuilder::from_scene_file(&self.file, &self.base_dir)
    }

    /// Checks every value that can be checked without loading files
    /// ([`SimulationBuilder::validate`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        self.builder()
            .validate()
            .map_err(|e| SceneError::invalid(&self.source, e))
    }

    /// Loads the objects (meshes, paths) without generating the field.
    pub fn objects(&self) -> Result<Vec<Object>, SceneError> {
        self.file
            .objects
            .par_iter()
            .enumerate()
            .map(|(i, o)| {
                Object::from_params(o, i, &self.base_dir)
                    .map_err(|e| SceneError::invalid(&self.source, e))
            })
            .collect()
    }

    /// Builds the simulation at time 0: terrain, grass maps, field, objects
    /// and trees, camera ([`SimulationBuilder::build`]).
    pub fn build(&self) -> Result<Simulation, SceneError> {
        self.builder()
            .build()
            .map_err(|e| SceneError::invalid(&self.source, e))
    }
}
