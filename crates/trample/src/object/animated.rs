//! An object whose mesh is a skinned glTF playing one of its animations
//! (ours, DESIGN §3 "Deforming meshes"; issue 13): the scene file's
//! `animation = { name = "walk", speed = 1.0 }` beside
//! `shape = { kind = "mesh", path = "….glb" }`.
//!
//! The object's mesh ([`super::Object::mesh`]) is the skin's bind mesh with
//! the object's `scale`, `rotation_deg` and `anchor` baked in and sanitised
//! as every mesh is (DESIGN §9); [`AnimatedMesh::vertex_of`] remembers which
//! bind vertex each of its vertices is, so that a posed skin
//! ([`super::skin::SkinnedMesh::pose_into`]) gives the object's vertices at
//! any time ([`AnimatedMesh::pose_into`]), same triangles. The simulation
//! refits the object's OBB tree to them every sub-step (`step/rig.rs`).

use std::collections::HashMap;

use glam::{Affine3A, Vec3};
use serde::{Deserialize, Serialize};

use super::mesh::TriMesh;
use super::object::{ObjectErrorKind, Scale, ShapeParams, anchor_origin, mesh_file, scale_factors};
use super::pose::rotation_from_euler_deg;
use super::sanitize::{SanitizeReport, sanitize};
use super::skin::{SkinScratch, SkinnedMesh};

/// Which animation of the object's glTF plays, and how fast
/// (`[objects] animation`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationParams {
    /// The animation's name in the file (glTF `animations[].name`).
    pub name: String,
    /// Playback rate, dimensionless (finite, ≥ 0): 1 plays the file's
    /// seconds in simulation seconds, 2 twice as fast. Default 1.
    #[serde(default = "default_speed")]
    pub speed: f32,
    /// The ground speed the cycle is made for, m/s (finite, > 0): a walk
    /// cycle's planted foot keeps still on the ground when the body goes
    /// this fast. When set, the animation's clock runs with the body's
    /// horizontal speed, `speed · |v| / ground_speed_mps` animation seconds
    /// a second: it stops when the body stands, and a body the viewer or a
    /// host drives strides at the speed it is driven. Default: none, the
    /// clock runs with simulation time (`speed`).
    #[serde(default)]
    pub ground_speed_mps: Option<f32>,
}

fn default_speed() -> f32 {
    1.0
}

/// A skinned glTF mesh bound to an object: what [`AnimatedMesh::pose_into`]
/// needs to give the object's vertices at a time.
#[derive(Clone, Debug)]
pub struct AnimatedMesh {
    /// The skin, skeleton and animations as loaded.
    pub skin: SkinnedMesh,
    /// Index of the playing animation in [`SkinnedMesh::animations`].
    pub animation: usize,
    /// Playback rate (see [`AnimationParams::speed`]).
    pub speed: f32,
    /// The ground speed the cycle is made for (see
    /// [`AnimationParams::ground_speed_mps`]); none: the clock is time.
    pub ground_speed_mps: Option<f32>,
    /// Simulation time at which the animation starts (the object's
    /// `start_s`): before it the object stands in the animation's first
    /// pose, as it waits at its path's start.
    pub start_s: f32,
    /// Per vertex of the object's mesh, the vertex of [`SkinnedMesh::bind`]
    /// it is (sanitising welds equal positions and drops unused vertices).
    pub vertex_of: Vec<u32>,
    /// Bind space → the object's local frame: `scale`, `rotation_deg`, then
    /// the anchor's shift.
    pub bake: Affine3A,
}

/// Reusable memory of [`AnimatedMesh::pose_into`].
#[derive(Clone, Debug, Default)]
pub struct AnimatedScratch {
    skin: SkinScratch,
    bind_space: Vec<Vec3>,
}

impl AnimatedMesh {
    /// Loads the skinned glTF of `shape` (which must be a `.gltf` / `.glb`
    /// mesh file, found as an object's mesh is) and binds the animation
    /// `params.name`; returns it with the object's baked, sanitised mesh.
    ///
    /// # Errors
    /// [`ObjectErrorKind::BadParameter`] for a shape that is not a glTF
    /// file or a bad speed, [`ObjectErrorKind::PathOutside`],
    /// [`ObjectErrorKind::Rig`] (a bad skin, or no animation of that name:
    /// the message names the file and lists the animations it has),
    /// [`ObjectErrorKind::Mesh`] (sanitising refused the mesh).
    pub(crate) fn load(
        params: &AnimationParams,
        shape: &ShapeParams,
        scale: Scale,
        rotation_deg: [f32; 3],
        start_s: f32,
        base_dir: &std::path::Path,
    ) -> Result<(Self, TriMesh, SanitizeReport), ObjectErrorKind> {
        let bad = |key, value: String, allowed| ObjectErrorKind::BadParameter {
            key,
            value,
            allowed,
        };
        if !(params.speed.is_finite() && params.speed >= 0.0) {
            return Err(bad(
                "animation.speed",
                params.speed.to_string(),
                "must be a finite number >= 0",
            ));
        }
        if let Some(g) = params.ground_speed_mps
            && !(g.is_finite() && g > 0.0)
        {
            return Err(bad(
                "animation.ground_speed_mps",
                g.to_string(),
                "must be a finite speed > 0 (m/s), or left out",
            ));
        }
        let ShapeParams::Mesh { path, anchor } = shape else {
            return Err(bad(
                "animation",
                format!("{{ name = {:?} }}", params.name),
                "needs shape = { kind = \"mesh\", path = \"….gltf or .glb\" } (a skinned glTF)",
            ));
        };
        let is_gltf = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .is_some_and(|e| e == "gltf" || e == "glb");
        if !is_gltf {
            return Err(bad(
                "animation",
                format!("{{ name = {:?} }}", params.name),
                "needs a .gltf or .glb mesh file (a skinned glTF)",
            ));
        }
        let file = mesh_file(base_dir, path)?;
        let skin = SkinnedMesh::load(&file).map_err(|e| ObjectErrorKind::Rig(Box::new(e)))?;
        let animation = skin
            .animation(&params.name)
            .map_err(|e| ObjectErrorKind::Rig(Box::new(e)))?;
        let animation = skin
            .animations
            .iter()
            .position(|a| std::ptr::eq(a, animation))
            .unwrap_or(0);
        if rotation_deg.iter().any(|d| !d.is_finite()) {
            return Err(bad(
                "rotation_deg",
                format!("{rotation_deg:?}"),
                "every angle must be finite",
            ));
        }
        let linear = Affine3A::from_scale_rotation_translation(
            scale_factors(scale)?,
            rotation_from_euler_deg(rotation_deg),
            Vec3::ZERO,
        );
        let baked = TriMesh {
            positions: skin
                .bind
                .positions
                .iter()
                .map(|&p| linear.transform_point3(p))
                .collect(),
            indices: skin.bind.indices.clone(),
        };
        // Which bind vertex each baked position is (the first of equal ones,
        // as sanitising welds them).
        let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(baked.positions.len());
        for (i, p) in baked.positions.iter().enumerate() {
            first.entry(position_key(*p)).or_insert(i as u32);
        }
        let (mut mesh, report) =
            sanitize(baked, &file.display().to_string()).map_err(ObjectErrorKind::Mesh)?;
        let vertex_of = mesh
            .positions
            .iter()
            .map(|p| first.get(&position_key(*p)).copied().unwrap_or(0))
            .collect();
        let origin = anchor_origin(&mesh, *anchor);
        for p in &mut mesh.positions {
            *p -= origin;
        }
        let bake = Affine3A::from_translation(-origin) * linear;
        Ok((
            Self {
                skin,
                animation,
                speed: params.speed,
                ground_speed_mps: params.ground_speed_mps,
                start_s,
                vertex_of,
                bake,
            },
            mesh,
            report,
        ))
    }

    /// The animation's own time (before looping) at simulation time `t`:
    /// `speed · max(t − start_s, 0)`.
    #[must_use]
    pub fn animation_time(&self, t: f32) -> f32 {
        self.speed * (t - self.start_s).max(0.0)
    }

    /// Animation seconds a second for a body going `velocity` (m/s,
    /// world): `speed` without a ground speed, else `speed · |v_xz| /
    /// ground_speed_mps` (see [`AnimationParams::ground_speed_mps`]).
    #[must_use]
    pub fn clock_rate(&self, velocity: Vec3) -> f32 {
        match self.ground_speed_mps {
            None => self.speed,
            Some(g) => self.speed * Vec3::new(velocity.x, 0.0, velocity.z).length() / g,
        }
    }

    /// The object's mesh vertices (its local frame, metres) at simulation
    /// time `t` with the clock on time ([`AnimatedMesh::animation_time`]):
    /// as [`AnimatedMesh::pose_at_clock`].
    pub fn pose_into(&self, t: f32, scratch: &mut AnimatedScratch, out: &mut Vec<Vec3>) {
        self.pose_at_clock(self.animation_time(t), scratch, out);
    }

    /// The object's mesh vertices (its local frame, metres) at the
    /// animation's own time `clock` (seconds, before looping): the
    /// animation sampled (looping), the skin posed (linear blend skinning),
    /// baked as the mesh was. `out` is overwritten with one position per
    /// vertex of the object's mesh.
    pub fn pose_at_clock(&self, clock: f32, scratch: &mut AnimatedScratch, out: &mut Vec<Vec3>) {
        let animation = self.skin.animations.get(self.animation);
        self.skin
            .pose_into(animation, clock, &mut scratch.skin, &mut scratch.bind_space);
        out.clear();
        out.extend(self.vertex_of.iter().map(|&v| {
            let p = scratch
                .bind_space
                .get(v as usize)
                .copied()
                .unwrap_or(Vec3::ZERO);
            self.bake.transform_point3(p)
        }));
    }
}

/// The bits of a position, `-0.0` counted as `0.0` (sanitising's weld key).
fn position_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}
