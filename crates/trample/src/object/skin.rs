//! glTF skins and linear blend skinning on the CPU (ours, DESIGN §3
//! "Deforming meshes"; glTF 2.0 §3.7.3 "Skins").
//!
//! A skinned vertex follows up to four joints: `p' = Σ_k w_k J_{j_k} p`,
//! with the joint matrix `J_j = G(node_j) · IBM_j` (the joint node's global
//! transform times its inverse bind matrix) and weights summing to 1
//! (Magnenat-Thalmann et al. 1988, "linear blend skinning"). At the rest
//! pose of a file whose inverse bind matrices invert the joints' rest
//! transforms (what exporters write), every `J_j` is the identity and the
//! skinned mesh is the bind mesh.
//!
//! Every mesh node of the scene is loaded as [`super::gltf::parse_gltf`]
//! loads it; a node without a skin moves rigidly with its node, as one more
//! joint of weight 1 whose inverse bind matrix is the inverse of the node's
//! rest transform, so a rigid prop attached to an animated bone (or a whole
//! file of rigid animated nodes) deforms the same way. As glTF requires, a
//! skinned mesh's own node transform is not applied.

use std::collections::HashSet;
use std::path::Path;

use ::gltf::accessor::Dimensions;
use ::gltf::{Document, Semantic};
use glam::{Affine3A, Mat4, Quat, Vec3, Vec3A, Vec4};

use super::animation::{Animation, load_animations};
use super::error::MeshError;
use super::gltf::{
    append_primitive, mesh_instances, open_document, read_floats, read_joint_indices,
};
use super::mesh::TriMesh;
use super::rig_error::RigError;

/// A vertex's weights may sum to 1 ± this (they are then scaled to sum to
/// 1). Quantised `u8` weights, as glTF allows, round each of four weights by
/// up to 0.5/255: at most 0.008 off in all; 0.01 accepts those and refuses
/// weights that are simply wrong.
pub const WEIGHT_SUM_TOLERANCE: f32 = 0.01;

/// A node's local transform: translate · rotate · scale (glTF's TRS).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeTransform {
    /// Translation, metres.
    pub translation: Vec3,
    /// Rotation (unit quaternion).
    pub rotation: Quat,
    /// Scale factors.
    pub scale: Vec3,
}

impl NodeTransform {
    /// The identity transform.
    pub const IDENTITY: Self = Self {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    /// The matrix `T · R · S`.
    #[must_use]
    pub fn to_affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// The node hierarchy of a glTF file, with each node's rest transform.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    /// Node names (`None` where the file has none), by glTF node index.
    pub names: Vec<Option<String>>,
    /// Parent of each node, by glTF node index; `None` for a root.
    pub parents: Vec<Option<u32>>,
    /// Each node's local transform in the file (the rest pose).
    pub rest: Vec<NodeTransform>,
    /// Node indices, every parent before its children.
    order: Vec<u32>,
}

impl Skeleton {
    /// The hierarchy of every node of `document`.
    ///
    /// # Errors
    /// [`MeshError::GltfNodeGraph`] for a node with two parents or a cycle.
    fn from_document(document: &Document, name: &str) -> Result<Self, MeshError> {
        let n = document.nodes().len();
        let graph_error = |node: usize| MeshError::GltfNodeGraph {
            source_name: name.to_owned(),
            node,
        };
        let mut parents = vec![None; n];
        for node in document.nodes() {
            for child in node.children() {
                let slot = &mut parents[child.index()];
                if slot.is_some() || child.index() == node.index() {
                    return Err(graph_error(child.index()));
                }
                *slot = Some(node.index() as u32);
            }
        }
        // Parents first: walk down from the roots; a node never reached is
        // on a cycle.
        let mut order = Vec::with_capacity(n);
        let mut stack: Vec<u32> = (0..n as u32)
            .filter(|&i| parents[i as usize].is_none())
            .collect();
        let mut seen = HashSet::with_capacity(n);
        while let Some(i) = stack.pop() {
            if !seen.insert(i) {
                return Err(graph_error(i as usize));
            }
            order.push(i);
            if let Some(node) = document.nodes().nth(i as usize) {
                stack.extend(node.children().map(|c| c.index() as u32));
            }
        }
        if let Some(i) = (0..n).find(|&i| !seen.contains(&(i as u32))) {
            return Err(graph_error(i));
        }
        let rest = document
            .nodes()
            .map(|node| {
                let (t, r, s) = node.transform().decomposed();
                NodeTransform {
                    translation: Vec3::from_array(t),
                    rotation: Vec4::from_array(r)
                        .try_normalize()
                        .map_or(Quat::IDENTITY, Quat::from_vec4),
                    scale: Vec3::from_array(s),
                }
            })
            .collect();
        let names = document
            .nodes()
            .map(|node| node.name().map(str::to_owned))
            .collect();
        Ok(Self {
            names,
            parents,
            rest,
            order,
        })
    }

    /// The global transform of every node from their local ones (`locals`
    /// indexed by node, as [`Animation::sample_into`] writes them):
    /// `G(i) = G(parent) · L(i)`. `out` is overwritten.
    pub fn global_transforms(&self, locals: &[NodeTransform], out: &mut Vec<Affine3A>) {
        out.clear();
        out.resize(self.parents.len(), Affine3A::IDENTITY);
        for &i in &self.order {
            let i = i as usize;
            let local = locals.get(i).unwrap_or(&self.rest[i]).to_affine();
            out[i] = match self.parents[i] {
                Some(p) => out[p as usize] * local,
                None => local,
            };
        }
    }

    /// The index of the node called `name`, if any (the first one).
    #[must_use]
    pub fn node_named(&self, name: &str) -> Option<u32> {
        self.names
            .iter()
            .position(|n| n.as_deref() == Some(name))
            .map(|i| i as u32)
    }
}

/// One entry of the joint palette a vertex refers to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    /// The glTF node whose global transform moves it; `None` for a mesh of
    /// a file without nodes (it never moves).
    pub node: Option<u32>,
    /// Inverse bind matrix: bind (mesh) space → the joint's space at bind.
    pub inverse_bind: Affine3A,
}

/// A skinned (and possibly animated) glTF mesh: the bind mesh, the joints
/// each vertex follows, the skeleton and the file's animations.
#[derive(Clone, Debug)]
pub struct SkinnedMesh {
    /// The file, for messages.
    pub source_name: String,
    /// The mesh at bind time, metres: skinned vertices as stored, rigid
    /// ones placed by their node's rest transform (what
    /// [`super::gltf::parse_gltf`] gives for a file whose skinned nodes
    /// have identity transforms). Not sanitised.
    pub bind: TriMesh,
    /// The joint palette: every skin's joints, then one per rigid mesh node.
    pub joints: Vec<Joint>,
    /// Per vertex of `bind`, four palette indices…
    pub vertex_joints: Vec<[u32; 4]>,
    /// …and their weights, summing to 1.
    pub vertex_weights: Vec<[f32; 4]>,
    /// The node hierarchy.
    pub skeleton: Skeleton,
    /// The file's animations.
    pub animations: Vec<Animation>,
}

/// Reusable memory of [`SkinnedMesh::pose_into`].
#[derive(Clone, Debug, Default)]
pub struct SkinScratch {
    /// Local node transforms.
    locals: Vec<NodeTransform>,
    /// Global node transforms.
    globals: Vec<Affine3A>,
    /// Joint matrices.
    joints: Vec<Affine3A>,
}

impl SkinnedMesh {
    /// Loads the skinned mesh, skeleton and animations of the glTF or GLB
    /// file at `path` (external buffers from its folder, as
    /// [`super::gltf::load_gltf`]).
    ///
    /// # Errors
    /// [`RigError`] naming the file and the item.
    pub fn load(path: &Path) -> Result<Self, RigError> {
        let bytes = super::read_mesh_bytes(path)?;
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        Self::parse(&bytes, Some(folder), &path.display().to_string())
    }

    /// [`SkinnedMesh::load`] from bytes (`name` names the file in messages;
    /// `buffer_folder` as in [`super::gltf::parse_gltf`]).
    ///
    /// # Errors
    /// The mesh errors of [`super::gltf::parse_gltf`] ([`RigError::Mesh`]);
    /// [`RigError::MissingAttribute`], [`RigError::JointOutOfRange`] (a
    /// joint index beyond its skin with a non-zero weight; one with weight
    /// 0 is ignored), [`RigError::WeightSum`] (weights negative or not
    /// summing to 1 ± [`WEIGHT_SUM_TOLERANCE`]), [`RigError::Accessor`]
    /// (inverse bind matrices, joints, weights or animation data of the
    /// wrong type or count, or not finite).
    pub fn parse(bytes: &[u8], buffer_folder: Option<&Path>, name: &str) -> Result<Self, RigError> {
        let (document, buffers) = open_document(bytes, buffer_folder, name)?;
        if document.meshes().len() == 0 {
            return Err(MeshError::GltfNoMeshes {
                source_name: name.to_owned(),
            }
            .into());
        }
        let skeleton = Skeleton::from_document(&document, name)?;
        let mut rest_globals = Vec::new();
        skeleton.global_transforms(&skeleton.rest, &mut rest_globals);

        // The palette: each skin's joints at an offset.
        let mut joints = Vec::new();
        let mut skin_offset = Vec::with_capacity(document.skins().len());
        for skin in document.skins() {
            skin_offset.push(joints.len() as u32);
            let count = skin.joints().len();
            let matrices = match skin.inverse_bind_matrices() {
                Some(accessor) => {
                    let item = format!("skin {} inverseBindMatrices", skin.index());
                    let flat =
                        read_floats(&accessor, &buffers, Dimensions::Mat4).map_err(|problem| {
                            RigError::Accessor {
                                source_name: name.to_owned(),
                                item: item.clone(),
                                problem,
                            }
                        })?;
                    if flat.len() != 16 * count {
                        return Err(RigError::Accessor {
                            source_name: name.to_owned(),
                            item,
                            problem: format!(
                                "holds {} matrices for {count} joints; allowed: one per joint",
                                flat.len() / 16
                            ),
                        });
                    }
                    flat.chunks_exact(16)
                        .map(|m| Affine3A::from_mat4(Mat4::from_cols_slice(m)))
                        .collect()
                }
                None => vec![Affine3A::IDENTITY; count],
            };
            joints.extend(
                skin.joints()
                    .zip(matrices)
                    .map(|(node, inverse_bind)| Joint {
                        node: Some(node.index() as u32),
                        inverse_bind,
                    }),
            );
        }

        let instances = mesh_instances(&document, name)?;
        if instances.is_empty() {
            return Err(MeshError::GltfSceneWithoutMeshes {
                source_name: name.to_owned(),
                meshes: document.meshes().len(),
            }
            .into());
        }
        let mut bind = TriMesh::default();
        let mut vertex_joints = Vec::new();
        let mut vertex_weights = Vec::new();
        for (node, mesh, world) in instances {
            let skin = node.as_ref().and_then(::gltf::Node::skin);
            // A rigid node: one more joint, at identity at rest.
            let rigid = match (&skin, &node) {
                (None, node) => {
                    let index = node.as_ref().map(|n| n.index() as u32);
                    let inverse_bind =
                        index.map_or(Affine3A::IDENTITY, |i| rest_globals[i as usize].inverse());
                    joints.push(Joint {
                        node: index,
                        inverse_bind,
                    });
                    Some((joints.len() - 1) as u32)
                }
                (Some(_), _) => None,
            };
            let transform = if skin.is_some() {
                Mat4::IDENTITY
            } else {
                world
            };
            for primitive in mesh.primitives() {
                let before = bind.positions.len();
                append_primitive(
                    &mut bind,
                    &primitive,
                    mesh.index(),
                    transform,
                    &buffers,
                    name,
                )?;
                let count = bind.positions.len() - before;
                match (&skin, rigid) {
                    (_, Some(j)) => {
                        vertex_joints.extend(std::iter::repeat_n([j, j, j, j], count));
                        vertex_weights.extend(std::iter::repeat_n([1.0, 0.0, 0.0, 0.0], count));
                    }
                    (Some(skin), None) => {
                        let place = Place {
                            source_name: name,
                            mesh: mesh.index(),
                            primitive: primitive.index(),
                            skin: skin.index(),
                        };
                        let (js, ws) =
                            read_influences(&primitive, &buffers, &place, skin.joints().len())?;
                        if js.len() != count {
                            return Err(place.accessor(
                                "JOINTS_0",
                                format!(
                                    "has {} elements for {count} vertices; allowed: one per vertex",
                                    js.len()
                                ),
                            ));
                        }
                        let offset = skin_offset[skin.index()];
                        vertex_joints.extend(js.into_iter().map(|j| j.map(|k| k + offset)));
                        vertex_weights.extend(ws);
                    }
                    (None, None) => unreachable!("a node without a skin is rigid"),
                }
            }
        }
        let animations = load_animations(&document, &buffers, name)?;
        Ok(Self {
            source_name: name.to_owned(),
            bind,
            joints,
            vertex_joints,
            vertex_weights,
            skeleton,
            animations,
        })
    }

    /// The animation called `name`.
    ///
    /// # Errors
    /// [`RigError::AnimationNotFound`] naming the file and listing the
    /// animations it has.
    pub fn animation(&self, name: &str) -> Result<&Animation, RigError> {
        self.animations
            .iter()
            .find(|a| a.name == name)
            .ok_or_else(|| RigError::AnimationNotFound {
                source_name: self.source_name.clone(),
                name: name.to_owned(),
                available: if self.animations.is_empty() {
                    "none".to_owned()
                } else {
                    self.animations
                        .iter()
                        .map(|a| format!("{:?}", a.name))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            })
    }

    /// The joint matrices `J_j = G(node_j) · IBM_j` for the node global
    /// transforms `globals` ([`Skeleton::global_transforms`]). `out` is
    /// overwritten.
    pub fn joint_matrices(&self, globals: &[Affine3A], out: &mut Vec<Affine3A>) {
        out.clear();
        out.extend(self.joints.iter().map(|j| {
            let g = j
                .node
                .and_then(|n| globals.get(n as usize))
                .copied()
                .unwrap_or(Affine3A::IDENTITY);
            g * j.inverse_bind
        }));
    }

    /// Linear blend skinning of the bind mesh's vertices with the joint
    /// matrices `joints` ([`SkinnedMesh::joint_matrices`]): `out[v] =
    /// Σ_k w_k J_{j_k} bind[v]`. `out` is overwritten with one position per
    /// vertex; a joint index beyond `joints` counts as the identity.
    pub fn skin_into(&self, joints: &[Affine3A], out: &mut Vec<Vec3>) {
        out.clear();
        out.reserve(self.bind.positions.len());
        let joint = |j: u32| joints.get(j as usize).unwrap_or(&Affine3A::IDENTITY);
        for ((p, js), ws) in self
            .bind
            .positions
            .iter()
            .zip(&self.vertex_joints)
            .zip(&self.vertex_weights)
        {
            let p = Vec3A::from(*p);
            let q = if ws[0] == 1.0 {
                joint(js[0]).transform_point3a(p)
            } else {
                let mut acc = Vec3A::ZERO;
                for k in 0..4 {
                    if ws[k] != 0.0 {
                        acc += joint(js[k]).transform_point3a(p) * ws[k];
                    }
                }
                acc
            };
            out.push(Vec3::from(q));
        }
    }

    /// The skinned vertex positions at time `t` seconds of `animation`
    /// (looping; `None`: the rest pose): sample, global transforms, joint
    /// matrices, [`SkinnedMesh::skin_into`]. `out` is overwritten.
    pub fn pose_into(
        &self,
        animation: Option<&Animation>,
        t: f32,
        scratch: &mut SkinScratch,
        out: &mut Vec<Vec3>,
    ) {
        match animation {
            Some(a) => a.sample_into(t, &self.skeleton.rest, &mut scratch.locals),
            None => {
                scratch.locals.clear();
                scratch.locals.extend_from_slice(&self.skeleton.rest);
            }
        }
        self.skeleton
            .global_transforms(&scratch.locals, &mut scratch.globals);
        self.joint_matrices(&scratch.globals, &mut scratch.joints);
        self.skin_into(&scratch.joints, out);
    }
}

/// Where a primitive is, for messages.
struct Place<'a> {
    source_name: &'a str,
    mesh: usize,
    primitive: usize,
    skin: usize,
}

impl Place<'_> {
    fn accessor(&self, attribute: &str, problem: String) -> RigError {
        RigError::Accessor {
            source_name: self.source_name.to_owned(),
            item: format!(
                "mesh {} primitive {} {attribute}",
                self.mesh, self.primitive
            ),
            problem,
        }
    }
}

/// Per vertex, four joint indices and their weights.
type Influences = (Vec<[u32; 4]>, Vec<[f32; 4]>);

/// A skinned primitive's `JOINTS_0` and `WEIGHTS_0`, checked: joint
/// indices within the skin's `joint_count` where their weight is non-zero
/// (those with weight 0 are set to 0), weights finite, ≥ 0, summing to 1 ±
/// [`WEIGHT_SUM_TOLERANCE`], then scaled to sum to 1.
fn read_influences(
    primitive: &::gltf::Primitive<'_>,
    buffers: &[Vec<u8>],
    place: &Place<'_>,
    joint_count: usize,
) -> Result<Influences, RigError> {
    let missing = |attribute| RigError::MissingAttribute {
        source_name: place.source_name.to_owned(),
        mesh: place.mesh,
        primitive: place.primitive,
        skin: place.skin,
        attribute,
    };
    let joints = primitive
        .get(&Semantic::Joints(0))
        .ok_or_else(|| missing("JOINTS_0"))?;
    let weights = primitive
        .get(&Semantic::Weights(0))
        .ok_or_else(|| missing("WEIGHTS_0"))?;
    let mut joints =
        read_joint_indices(&joints, buffers).map_err(|p| place.accessor("JOINTS_0", p))?;
    let flat = read_floats(&weights, buffers, Dimensions::Vec4)
        .map_err(|p| place.accessor("WEIGHTS_0", p))?;
    let mut weights: Vec<[f32; 4]> = flat
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    if weights.len() != joints.len() {
        return Err(place.accessor(
            "WEIGHTS_0",
            format!(
                "has {} elements but JOINTS_0 has {}; allowed: one per vertex",
                weights.len(),
                joints.len()
            ),
        ));
    }
    for (vertex, (js, ws)) in joints.iter_mut().zip(&mut weights).enumerate() {
        let sum: f32 = ws.iter().sum();
        if ws.iter().any(|w| *w < 0.0) || (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
            return Err(RigError::WeightSum {
                source_name: place.source_name.to_owned(),
                mesh: place.mesh,
                primitive: place.primitive,
                vertex,
                weights: *ws,
                sum,
                tolerance: WEIGHT_SUM_TOLERANCE,
            });
        }
        for k in 0..4 {
            if js[k] as usize >= joint_count {
                if ws[k] != 0.0 {
                    return Err(RigError::JointOutOfRange {
                        source_name: place.source_name.to_owned(),
                        mesh: place.mesh,
                        primitive: place.primitive,
                        vertex,
                        skin: place.skin,
                        joint: js[k],
                        weight: ws[k],
                        joints: joint_count,
                    });
                }
                js[k] = 0;
            }
            ws[k] /= sum;
        }
    }
    Ok((joints, weights))
}
