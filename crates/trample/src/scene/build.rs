//! From a scene to a running [`Simulation`]: validation, memory estimate,
//! field generation, objects and their OBB trees.

use super::{Scene, SceneError};
use crate::camera::{Camera, CameraTarget, LookAt};
use crate::field::{Field, Terrain};
use crate::obb::build::DEFAULT_MAX_DEPTH;
use crate::object::{Object, Path};
use crate::step::Simulation;
use crate::step::simulation::Body;
use glam::Vec3;
use rayon::prelude::*;

impl Scene {
    /// Checks every value that can be checked without loading files.
    pub fn validate(&self) -> Result<(), SceneError> {
        let f = &self.file;
        let bad = |m: String| Err(SceneError::invalid(&self.source, m));
        f.field
            .validate()
            .map_err(|e| SceneError::invalid(&self.source, e))?;
        f.sim
            .validate()
            .map_err(|e| SceneError::invalid(&self.source, e))?;
        f.wind
            .validate()
            .map_err(|e| SceneError::invalid(&self.source, e))?;
        let lod = &f.lod;
        if !(lod.geometry_m.is_finite() && lod.geometry_m >= 0.0) {
            return bad(format!(
                "lod.geometry_m = {}: must be a finite distance >= 0 metres",
                lod.geometry_m
            ));
        }
        if lod.billboard_m.is_nan() {
            return bad(format!(
                "lod.billboard_m = NaN: must be a distance >= lod.geometry_m = {} metres (inf allowed)",
                lod.geometry_m
            ));
        }
        if lod.billboard_m < lod.geometry_m {
            return bad(format!(
                "lod.billboard_m = {} is less than lod.geometry_m = {}: LOD distances must not decrease",
                lod.billboard_m, lod.geometry_m
            ));
        }
        let c = &f.camera;
        if !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) {
            return bad(format!(
                "camera.fov_y_deg = {}: must be in (0, 180) degrees",
                c.fov_y_deg
            ));
        }
        if !(c.aspect.is_finite() && c.aspect > 0.0) {
            return bad(format!(
                "camera.aspect = {}: must be a finite number > 0",
                c.aspect
            ));
        }
        if !(c.near_m.is_finite() && c.near_m > 0.0 && c.far_m.is_finite() && c.far_m > c.near_m) {
            return bad(format!(
                "camera.near_m = {}, camera.far_m = {}: need 0 < near_m < far_m, both finite",
                c.near_m, c.far_m
            ));
        }
        if let Err(e) = Path::new(c.path.clone()) {
            return bad(format!("camera.{e}"));
        }
        if let LookAt::Object { name } = &c.look_at {
            // The default camera follows "ball"; a scene without it looks at the centre.
            let default_follow = *c == crate::camera::CameraParams::default();
            if !default_follow && !f.objects.iter().any(|o| &o.name == name) {
                let names: Vec<&str> = f.objects.iter().map(|o| o.name.as_str()).collect();
                return bad(format!(
                    "camera.look_at.name = \"{name}\": no object has that name (objects: {names:?})"
                ));
            }
        }
        let mut seen = std::collections::HashSet::new();
        for (i, o) in f.objects.iter().enumerate() {
            if !seen.insert(&o.name) {
                return bad(format!(
                    "objects[{i}].name = \"{}\": another object already has this name",
                    o.name
                ));
            }
        }
        let need = f.field.memory_estimate_bytes();
        let limit = (f64::from(f.sim.memory_limit_gib) * 1024f64.powi(3)) as u64;
        if need > limit {
            return bad(format!(
                "field needs about {:.1} GiB ({} blades); sim.memory_limit_gib = {} allows less",
                need as f64 / 1024f64.powi(3),
                f.field.blade_count(),
                f.sim.memory_limit_gib
            ));
        }
        Ok(())
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

    /// Builds the simulation at time 0: terrain, field, objects and trees, camera.
    pub fn build(&self) -> Result<Simulation, SceneError> {
        self.validate()?;
        let f = &self.file;
        let terrain = Terrain::from_params(&f.field.terrain, f.field.extent_m(), &self.base_dir)
            .map_err(|e| SceneError::invalid(&self.source, e))?;
        let bodies: Vec<Body> = self
            .objects()?
            .into_par_iter()
            .map(|o| Body::new(o, DEFAULT_MAX_DEPTH))
            .collect();
        let field =
            Field::generate(&f.field, terrain).map_err(|e| SceneError::invalid(&self.source, e))?;
        let camera = self.camera(&bodies)?;
        let mut sim = Simulation::new(field, bodies, camera, f.lod.clone(), f.sim.clone());
        sim.wind = f.wind.clone();
        Ok(sim)
    }

    fn camera(&self, bodies: &[Body]) -> Result<Camera, SceneError> {
        let c = &self.file.camera;
        let eye = Path::new(c.path.clone())
            .map_err(|e| SceneError::invalid(&self.source, format!("camera.{e}")))?;
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
