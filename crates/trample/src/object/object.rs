//! An object of the scene: its mesh, in its local frame, and its motion.
//!
//! [`ObjectParams`] and the types it holds are the scene-file contract;
//! [`Object::from_params`] turns one into an [`Object`]: the mesh is built
//! or loaded, scaled, rotated, sanitised (DESIGN §9) and anchored, the path
//! and the orientation rule validated. The OBB tree of the mesh is built
//! elsewhere (`obb/`).

use super::animated::{AnimatedMesh, AnimationParams};
use super::error::MeshError;
use super::mesh::TriMesh;
use super::motion::{Motion, MotionError};
use super::parts::{Articulation, PartError, PartParams};
use super::path::{Path, PathError, PathParams};
use super::pose::{Pose, rotation_from_euler_deg};
use super::rig_error::RigError;
use super::sanitize::{SanitizeReport, sanitize_with_sources};
use super::shapes::{self, MAX_SPHERE_SUBDIVISIONS};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One `[[objects]]` entry of a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectParams {
    /// Name used in messages and by the camera's `look_at`.
    pub name: String,
    /// The mesh.
    pub shape: ShapeParams,
    /// Scale applied to the mesh (uniform or per axis), before
    /// `rotation_deg`. Every factor finite and > 0. Default 1.
    #[serde(default)]
    pub scale: Scale,
    /// Rotation baked into the mesh before anything else, Euler degrees
    /// (y, x, z order as in [`super::path::Keyframe`]), applied after
    /// `scale`; the orientation rules then act on the rotated mesh (so
    /// `face_motion` turns the rotated mesh's +z forward). Default none.
    #[serde(default)]
    pub rotation_deg: [f32; 3],
    /// How the object turns as it moves. Default `fixed`.
    #[serde(default)]
    pub orientation: Orientation,
    /// Where the object goes.
    pub path: PathParams,
    /// Simulation time at which the object starts along its path (path time
    /// 0), seconds; before it the object waits at the path's start. Finite.
    /// Default 0.
    #[serde(default)]
    pub start_s: f32,
    /// How the object marks the grass: how hard it presses and how long its
    /// track lasts (ours, DESIGN §6). Default: presses as Eq. 2 says, track
    /// as `[sim]` says.
    #[serde(default)]
    pub track: TrackParams,
    /// The parts of an articulated object (`[[objects.parts]]`: wheels,
    /// limbs), hanging from the object's own mesh (its body) or from one
    /// another; see [`PartParams`]. Default none: a rigid object.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<PartParams>,
    /// The animation a skinned glTF object plays (`shape` must then be a
    /// `.gltf` / `.glb` mesh file with a skin): its name and speed, looping,
    /// from `start_s` on; the mesh deforms and its OBB tree is refitted
    /// every sub-step. Default none: the mesh is rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<AnimationParams>,
}

/// How an object marks the grass (ours, DESIGN §6 "each object may set its
/// own trail"): a tractor leaves a lasting track, a walker a short one. In a
/// scene file: `track = { recovery_s = 30.0, trail = 4.0, press = 1.5 }`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrackParams {
    /// Recovery time constant of the blades this object pressed last,
    /// seconds (see `sim.recovery_s`); `inf` = they stay down. Default: none,
    /// `sim.recovery_s` applies.
    pub recovery_s: Option<f32>,
    /// How much more slowly the blades it flattened recover (see
    /// `sim.trail`), ≥ 0. Default: none, `sim.trail` applies.
    pub trail: Option<f32>,
    /// Factor on the force of Eq. 2 for this object, ≥ 0 (dimensionless): a
    /// heavy object pushes the grass farther per metre it travels. 0 leaves
    /// only the contact response. Default 1: the paper's force.
    pub press: f32,
    /// What counts as inside an open mesh (one with holes: a car body with
    /// no floor), for the contact response: `"sheet"` (default) what lies
    /// just behind its sheets; `"winding"` its hollow too, by the mesh's
    /// generalized winding number (`trample::collision::winding`), at a
    /// walk of the tree per query. No effect on a closed mesh.
    pub open_inside: OpenInside,
}

/// What counts as inside an open mesh ([`TrackParams::open_inside`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OpenInside {
    /// What lies just behind a sheet (within a blade segment of it).
    #[default]
    Sheet,
    /// The hollow too: the generalized winding number's inside
    /// ([`crate::obb::ObbTree::enable_winding`]).
    Winding,
}

impl Default for TrackParams {
    fn default() -> Self {
        Self {
            recovery_s: None,
            trail: None,
            press: 1.0,
            open_inside: OpenInside::Sheet,
        }
    }
}

impl TrackParams {
    /// Checks the values; the error names the key under `track`.
    ///
    /// # Errors
    /// [`ObjectErrorKind::BadParameter`] for the first bad value.
    pub fn validate(&self) -> Result<(), ObjectErrorKind> {
        if let Some(r) = self.recovery_s
            && (r.is_nan() || r <= 0.0)
        {
            return Err(bad(
                "track.recovery_s",
                r.to_string(),
                "must be > 0 seconds, or inf for a lasting track",
            ));
        }
        if let Some(t) = self.trail
            && !(t.is_finite() && t >= 0.0)
        {
            return Err(bad(
                "track.trail",
                t.to_string(),
                "must be a finite number >= 0",
            ));
        }
        if !(self.press.is_finite() && self.press >= 0.0) {
            return Err(bad(
                "track.press",
                self.press.to_string(),
                "must be a finite number >= 0",
            ));
        }
        Ok(())
    }
}

/// A uniform scale or one per axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Scale {
    /// The same on all axes.
    Uniform(f32),
    /// Along x, y, z.
    PerAxis([f32; 3]),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

/// How an object is oriented along its path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    /// Keeps its initial orientation.
    #[default]
    Fixed,
    /// Turns about y to face its direction of motion (+z of the mesh forward).
    FaceMotion,
    /// Rolls without slipping on the ground: spins about `up × v` at
    /// `|v| / r`, r = height of the origin above the mesh's lowest point
    /// (after scale and rotation; must be > 0).
    Rolling,
    /// Takes the orientations of a `keyframes` path (whose keys must all
    /// have `rotation_deg`).
    Keyframes,
}

/// The mesh of an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeParams {
    /// An icosphere.
    Sphere {
        /// Radius, metres (> 0).
        radius_m: f32,
        /// Subdivisions of the icosahedron (0–7). Default 3 (1,280 triangles).
        #[serde(default = "default_subdivisions")]
        subdivisions: u32,
    },
    /// A box.
    Box {
        /// Half extents (x, y, z), metres (each > 0).
        half_extents_m: [f32; 3],
    },
    /// A capsule along y.
    Capsule {
        /// Radius, metres (> 0).
        radius_m: f32,
        /// Length of the cylindrical part, metres (≥ 0).
        length_m: f32,
    },
    /// A closed cylinder along y (a wheel, once turned by `rotation_deg`).
    Cylinder {
        /// Radius, metres (> 0).
        radius_m: f32,
        /// Length along y, metres (> 0).
        length_m: f32,
    },
    /// The built-in complex shape: a (3, 2) torus knot tube of several
    /// thousand triangles, `size_m` across.
    Knot {
        /// Outer diameter, metres (> 0).
        size_m: f32,
    },
    /// Triangles given as values (a mesh built in code, or a small one
    /// written into a scene file), metres, in the object's local frame
    /// (the origin is kept). Sanitised like every mesh (DESIGN §9): NaN
    /// coordinates and out-of-range indices are refused, degenerate and
    /// duplicate triangles dropped. Code only: not a kind scene files know
    /// (which keeps their list of kinds, and its messages, as it was).
    #[serde(skip)]
    Triangles {
        /// Vertex positions, metres.
        positions: Vec<[f32; 3]>,
        /// Triangles as three indices into `positions`, counter-clockwise
        /// seen from outside.
        indices: Vec<[u32; 3]>,
    },
    /// A mesh file: `.obj`, `.gltf` or `.glb`, relative to the scene file's
    /// folder and inside it (no absolute path, no `..` above it: see
    /// [`crate::paths`]), in metres (scale it otherwise). See
    /// [`super::load_mesh_file`].
    Mesh {
        /// The file.
        path: PathBuf,
        /// Where the mesh's local origin goes. Default `center`.
        #[serde(default)]
        anchor: Anchor,
    },
}

fn default_subdivisions() -> u32 {
    3
}

/// Where a loaded mesh's origin is placed, after scale and rotation. (The
/// built-in shapes keep their centre as origin.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Anchor {
    /// At the centre of its bounding box.
    #[default]
    Center,
    /// At the centre of the bottom face of its bounding box (cars, animals).
    Bottom,
    /// Where the file has it.
    File,
}

/// A ready object: its mesh in its local frame and its motion.
#[derive(Clone, Debug)]
pub struct Object {
    /// Name from the scene.
    pub name: String,
    /// The mesh in the object's local frame, metres: `scale`, `rotation_deg`
    /// and `anchor` baked in, sanitised. Counter-clockwise triangles face
    /// outwards (when the source's did).
    pub mesh: TriMesh,
    /// Where the object is and how it turns at any time.
    pub motion: Motion,
    /// What sanitising dropped.
    pub report: SanitizeReport,
    /// Whether the mesh is closed ([`TriMesh::is_closed`]).
    pub closed: bool,
    /// How it marks the grass (from [`ObjectParams::track`]); it holds for
    /// all of its parts.
    pub track: TrackParams,
    /// Its parts (from [`ObjectParams::parts`]); empty for a rigid object.
    pub parts: Articulation,
    /// Its skin and animation (from [`ObjectParams::animation`]); `None`
    /// for a rigid mesh. When set, `mesh` holds the latest posed vertices
    /// once the object is in a simulation (the bind pose before).
    pub animated: Option<Box<AnimatedMesh>>,
    /// How the vertices of the mesh it was made from map onto `mesh`
    /// (empty for an animated object).
    pub sources: SourceVertices,
}

/// Why an object of a scene was refused: `objects[INDEX] (NAME): ` and what
/// is wrong.
#[derive(Debug, thiserror::Error)]
#[error("objects[{index}] ({name}): {kind}")]
pub struct ObjectError {
    /// Index in the scene's `objects`.
    pub index: usize,
    /// The object's name.
    pub name: String,
    /// What is wrong.
    pub kind: ObjectErrorKind,
}

/// What is wrong with an object.
#[derive(Debug, thiserror::Error)]
pub enum ObjectErrorKind {
    /// A shape, scale or rotation parameter out of range.
    #[error("{key} = {value}: {allowed}")]
    BadParameter {
        /// The key, e.g. `shape.radius_m`.
        key: &'static str,
        /// The value as written.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A file path leaves the scene's folder ([`crate::paths`]).
    #[error("{key} = {path:?}: {reason}")]
    PathOutside {
        /// The key, e.g. `shape.path`.
        key: &'static str,
        /// The path as written.
        path: PathBuf,
        /// How it leaves the folder (boxed: keeps `ObjectError` small).
        reason: Box<crate::paths::PathEscape>,
    },
    /// The mesh could not be loaded or was refused.
    #[error("{0}")]
    Mesh(MeshError),
    /// The path is invalid.
    #[error("{0}")]
    Path(PathError),
    /// The orientation rule or start time is invalid.
    #[error("{0}")]
    Motion(MotionError),
    /// A part was refused (`parts[INDEX] (NAME): …`).
    #[error("{0}")]
    Part(Box<PartError>),
    /// The skin or the animation was refused, or the file has no animation
    /// of that name (boxed: keeps `ObjectError` small).
    #[error("{0}")]
    Rig(Box<RigError>),
}

impl Object {
    /// Builds the object `params` = `objects[index]` of a scene; mesh files
    /// are found relative to `base_dir` (the scene file's folder) and must
    /// stay inside it ([`crate::paths::resolve_inside`]).
    ///
    /// The mesh is made (built-in shape) or loaded, scaled, rotated by
    /// `rotation_deg`, sanitised, then anchored (mesh files only). The roll
    /// radius of a rolling object is the depth of the mesh's lowest point
    /// below its origin.
    ///
    /// # Errors
    /// [`ObjectError`] prefixed `objects[INDEX] (NAME): `, wrapping bad
    /// shape/scale/rotation parameters, [`MeshError`], [`PathError`] or
    /// [`MotionError`].
    pub fn from_params(
        params: &ObjectParams,
        index: usize,
        base_dir: &std::path::Path,
    ) -> Result<Self, ObjectError> {
        let error = |kind| ObjectError {
            index,
            name: params.name.clone(),
            kind,
        };
        let (mesh, report, animated, sources) = match &params.animation {
            None => {
                let (mesh, report, sources) = baked_mesh_with_sources(
                    &params.shape,
                    params.scale,
                    params.rotation_deg,
                    base_dir,
                )
                .map_err(error)?;
                (mesh, report, None, sources)
            }
            Some(animation) => {
                let (animated, mesh, report) = AnimatedMesh::load(
                    animation,
                    &params.shape,
                    params.scale,
                    params.rotation_deg,
                    params.start_s,
                    base_dir,
                )
                .map_err(error)?;
                (
                    mesh,
                    report,
                    Some(Box::new(animated)),
                    SourceVertices::default(),
                )
            }
        };
        let parts = Articulation::from_params(&params.parts, base_dir)
            .map_err(|e| error(ObjectErrorKind::Part(Box::new(e))))?;
        params.track.validate().map_err(error)?;
        let path = Path::new(params.path.clone()).map_err(|e| error(ObjectErrorKind::Path(e)))?;
        let roll_radius = mesh.bounds().map_or(0.0, |(lo, _)| 0.0 - lo.y); // 0 - y: never -0
        let motion = Motion::new(path, params.orientation, params.start_s, roll_radius)
            .map_err(|e| error(ObjectErrorKind::Motion(e)))?;
        let closed = mesh.is_closed();
        Ok(Self {
            name: params.name.clone(),
            mesh,
            motion,
            report,
            closed,
            track: params.track,
            parts,
            animated,
            sources,
        })
    }

    /// The pose at simulation time `t`, seconds ([`Motion::pose_at`]).
    #[must_use]
    pub fn pose_at(&self, t: f32) -> Pose {
        self.motion.pose_at(t)
    }
}

/// The mesh of `shape` in its local frame: made (built-in shape) or loaded
/// (relative to `base_dir`), scaled by `scale`, rotated by `rotation_deg`,
/// sanitised, then anchored (mesh files only). Shared by objects and by the
/// parts of articulated objects ([`super::parts`]).
pub(crate) fn baked_mesh(
    shape: &ShapeParams,
    scale: Scale,
    rotation_deg: [f32; 3],
    base_dir: &std::path::Path,
) -> Result<(TriMesh, SanitizeReport), ObjectErrorKind> {
    baked_mesh_with_sources(shape, scale, rotation_deg, base_dir).map(|(m, r, _)| (m, r))
}

/// [`baked_mesh`], and how the source's vertices map onto the baked mesh's
/// ([`SourceVertices`]).
pub(crate) fn baked_mesh_with_sources(
    shape: &ShapeParams,
    scale: Scale,
    rotation_deg: [f32; 3],
    base_dir: &std::path::Path,
) -> Result<(TriMesh, SanitizeReport, SourceVertices), ObjectErrorKind> {
    let (raw, source) = build_shape(shape, base_dir)?;
    // Before scale and rotation turn an infinite coordinate into NaN.
    if let Some((vertex, p)) = raw
        .positions
        .iter()
        .enumerate()
        .find(|(_, p)| !p.is_finite())
    {
        let value = p
            .to_array()
            .into_iter()
            .find(|c| !c.is_finite())
            .unwrap_or(f32::NAN);
        return Err(ObjectErrorKind::Mesh(MeshError::NonFiniteVertex {
            source_name: source,
            vertex,
            value,
        }));
    }
    let scale = scale_factors(scale)?;
    if rotation_deg.iter().any(|d| !d.is_finite()) {
        return Err(bad(
            "rotation_deg",
            format3(rotation_deg),
            "every angle must be finite",
        ));
    }
    let rotation = rotation_from_euler_deg(rotation_deg);
    let count = raw.positions.len();
    let baked = TriMesh {
        positions: raw
            .positions
            .iter()
            .map(|&p| rotation * (p * scale))
            .collect(),
        indices: raw.indices,
    };
    let (mut mesh, report, kept) =
        sanitize_with_sources(baked, &source).map_err(ObjectErrorKind::Mesh)?;
    let mut origin = Vec3::ZERO;
    if let ShapeParams::Mesh { anchor, .. } = shape {
        origin = anchor_origin(&mesh, *anchor);
        apply_anchor(&mut mesh, *anchor);
    }
    let sources = SourceVertices {
        count,
        kept,
        scale,
        rotation,
        origin,
    };
    Ok((mesh, report, sources))
}

/// How the vertices of the mesh an object was made from (a built-in
/// shape's, a file's, the host's triangles) map onto its baked mesh
/// ([`Object::mesh`]): vertex `k` of the baked mesh is source vertex
/// `kept[k]`, scaled, rotated and moved to the anchor as the object was
/// (sanitising welds equal positions and drops unused vertices). What
/// `Simulation::set_body_vertices` takes the host's vertices through.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceVertices {
    /// How many vertices the source mesh has.
    pub count: usize,
    /// For each vertex of the baked mesh, its index in the source.
    pub kept: Vec<u32>,
    /// The object's scale, per axis.
    pub scale: Vec3,
    /// The object's `rotation_deg` as a rotation.
    pub rotation: glam::Quat,
    /// Where the anchor put the origin (subtracted), metres.
    pub origin: Vec3,
}

impl SourceVertices {
    /// The baked mesh's vertices from the source's `positions` (exactly
    /// [`SourceVertices::count`] of them), into `out`: `None` (and `out`
    /// untouched) for another count.
    pub fn bake(&self, positions: &[Vec3], out: &mut Vec<Vec3>) -> Option<()> {
        if positions.len() != self.count {
            return None;
        }
        out.clear();
        out.extend(self.kept.iter().map(|&i| {
            let p = positions.get(i as usize).copied().unwrap_or(Vec3::NAN);
            self.rotation * (p * self.scale) - self.origin
        }));
        Some(())
    }
}

/// The unscaled mesh of a shape and its name for messages (the file path,
/// or `"built-in sphere"` etc.).
fn build_shape(
    shape: &ShapeParams,
    base_dir: &std::path::Path,
) -> Result<(TriMesh, String), ObjectErrorKind> {
    Ok(match shape {
        &ShapeParams::Sphere {
            radius_m,
            subdivisions,
        } => {
            if subdivisions > MAX_SPHERE_SUBDIVISIONS {
                return Err(bad(
                    "shape.subdivisions",
                    subdivisions.to_string(),
                    "must be at most 7",
                ));
            }
            (
                shapes::sphere(positive("shape.radius_m", radius_m)?, subdivisions),
                "built-in sphere".into(),
            )
        }
        ShapeParams::Box { half_extents_m } => {
            if !half_extents_m.iter().all(|h| h.is_finite() && *h > 0.0) {
                return Err(bad(
                    "shape.half_extents_m",
                    format3(*half_extents_m),
                    "each must be a finite number > 0",
                ));
            }
            (
                shapes::cuboid(Vec3::from_array(*half_extents_m)),
                "built-in box".into(),
            )
        }
        &ShapeParams::Capsule { radius_m, length_m } => {
            if !(length_m.is_finite() && length_m >= 0.0) {
                return Err(bad(
                    "shape.length_m",
                    length_m.to_string(),
                    "must be a finite number ≥ 0",
                ));
            }
            (
                shapes::capsule(positive("shape.radius_m", radius_m)?, length_m),
                "built-in capsule".into(),
            )
        }
        &ShapeParams::Cylinder { radius_m, length_m } => (
            shapes::cylinder(
                positive("shape.radius_m", radius_m)?,
                positive("shape.length_m", length_m)?,
            ),
            "built-in cylinder".into(),
        ),
        &ShapeParams::Knot { size_m } => (
            shapes::knot(positive("shape.size_m", size_m)?),
            "built-in knot".into(),
        ),
        ShapeParams::Triangles { positions, indices } => (
            TriMesh {
                positions: positions.iter().map(|&p| Vec3::from_array(p)).collect(),
                indices: indices.clone(),
            },
            "triangles given as values".into(),
        ),
        ShapeParams::Mesh { path, .. } => {
            let file = mesh_file(base_dir, path)?;
            let mesh = super::load_mesh_file(&file).map_err(ObjectErrorKind::Mesh)?;
            (mesh, file.display().to_string())
        }
    })
}

/// The file `shape.path` names, inside the scene's folder `base_dir`
/// ([`crate::paths::resolve_inside`]).
pub(crate) fn mesh_file(
    base_dir: &std::path::Path,
    path: &std::path::Path,
) -> Result<PathBuf, ObjectErrorKind> {
    crate::paths::resolve_inside(base_dir, path).map_err(|reason| ObjectErrorKind::PathOutside {
        key: "shape.path",
        path: path.to_path_buf(),
        reason: Box::new(reason),
    })
}

/// The per-axis scale factors, each finite and > 0.
pub(crate) fn scale_factors(scale: Scale) -> Result<Vec3, ObjectErrorKind> {
    let (factors, value) = match scale {
        Scale::Uniform(s) => (Vec3::splat(s), s.to_string()),
        Scale::PerAxis(s) => (Vec3::from_array(s), format3(s)),
    };
    if factors.is_finite() && factors.min_element() > 0.0 {
        Ok(factors)
    } else {
        Err(bad(
            "scale",
            value,
            "every factor must be a finite number > 0",
        ))
    }
}

/// Moves the mesh so that its origin is where `anchor` says.
fn apply_anchor(mesh: &mut TriMesh, anchor: Anchor) {
    let origin = anchor_origin(mesh, anchor);
    for p in &mut mesh.positions {
        *p -= origin;
    }
}

/// Where `anchor` puts the origin of `mesh`, in its current frame (zero
/// for [`Anchor::File`] and for an empty mesh).
pub(crate) fn anchor_origin(mesh: &TriMesh, anchor: Anchor) -> Vec3 {
    let Some((lo, hi)) = mesh.bounds() else {
        return Vec3::ZERO;
    };
    let centre = (lo + hi) * 0.5;
    match anchor {
        Anchor::Center => centre,
        Anchor::Bottom => Vec3::new(centre.x, lo.y, centre.z),
        Anchor::File => Vec3::ZERO,
    }
}

fn positive(key: &'static str, value: f32) -> Result<f32, ObjectErrorKind> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(bad(key, value.to_string(), "must be a finite number > 0"))
    }
}

fn bad(key: &'static str, value: String, allowed: &'static str) -> ObjectErrorKind {
    ObjectErrorKind::BadParameter {
        key,
        value,
        allowed,
    }
}

fn format3(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}
