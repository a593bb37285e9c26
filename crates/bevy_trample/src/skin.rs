//! Skinned tramplers: an entity with a [`SkinnedMesh`] (a glTF character, an
//! animal) tramples with its mesh as Bevy's skinning poses it, not with its
//! bind pose. The plugin skins the collision mesh on the CPU at every
//! simulation step — the joints' global transforms times their inverse
//! bind poses, blended by the vertices' joint weights, as Bevy's skinning
//! shader does — and hands the vertices to the core
//! (`Simulation::set_body_vertices`, through [`crate::host`]), which
//! refits the body's OBB tree at every sub-step: legs that swing push the
//! grass with their own speed.

use bevy::math::{Affine3A, Mat4, Quat, Vec3, Vec3A};
use bevy::mesh::skinning::SkinnedMesh;
use bevy::mesh::{Mesh, VertexAttributeValues};

/// Why a skinned mesh cannot be skinned on the CPU.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SkinError {
    /// No `JOINT_INDEX` or `JOINT_WEIGHT`, or not in Bevy's formats.
    #[error(
        "the skinned mesh needs JOINT_INDEX (Uint16x4) and JOINT_WEIGHT (Float32x4) in the main world"
    )]
    NoWeights,
    /// The attributes' lengths differ from the positions'.
    #[error("{what} has {got} values for {want} vertices")]
    Length {
        /// The attribute.
        what: &'static str,
        /// Its length.
        got: usize,
        /// The vertex count.
        want: usize,
    },
    /// A vertex names a joint the skin does not have.
    #[error(
        "vertex {vertex} uses joint {joint}, but the skin has {joints} joints (and bind poses)"
    )]
    Joint {
        /// The vertex.
        vertex: usize,
        /// The joint index it uses.
        joint: u16,
        /// How many joints the skin has.
        joints: usize,
    },
}

/// The vertices of `mesh` posed by the skin, in the body's frame: each
/// vertex `v` goes to `Σ wᵢ · (joints[jᵢ] · inverse_bindposes[jᵢ]) · v` (the
/// world, as Bevy's skinning shader places it), then into the frame of a
/// body at `rotation`, `position` whose mesh has `scale` baked in
/// (`R⁻¹ · (world − position)`), in `mesh`'s vertex order: what the
/// body's mesh was made from ([`crate::mesh::tri_mesh`]). `joints` are
/// the joints' global transforms, in the skin's order.
///
/// # Errors
/// [`SkinError`] for a mesh without readable joint attributes, or a vertex
/// naming a joint past `joints` or `inverse_bindposes`.
pub fn skinned_positions(
    mesh: &Mesh,
    joints: &[Affine3A],
    inverse_bindposes: &[Mat4],
    rotation: Quat,
    position: Vec3,
) -> Result<Vec<Vec3>, SkinError> {
    let read = |attribute| mesh.try_attribute_option(attribute).ok().flatten();
    let (Some(VertexAttributeValues::Float32x3(points)), Some(indices), Some(weights)) = (
        read(Mesh::ATTRIBUTE_POSITION),
        read(Mesh::ATTRIBUTE_JOINT_INDEX),
        read(Mesh::ATTRIBUTE_JOINT_WEIGHT),
    ) else {
        return Err(SkinError::NoWeights);
    };
    let (VertexAttributeValues::Uint16x4(indices), VertexAttributeValues::Float32x4(weights)) =
        (indices, weights)
    else {
        return Err(SkinError::NoWeights);
    };
    let want = points.len();
    for (what, got) in [
        ("JOINT_INDEX", indices.len()),
        ("JOINT_WEIGHT", weights.len()),
    ] {
        if got != want {
            return Err(SkinError::Length { what, got, want });
        }
    }
    let count = joints.len().min(inverse_bindposes.len());
    let skin: Vec<Affine3A> = joints
        .iter()
        .zip(inverse_bindposes)
        .map(|(j, b)| *j * Affine3A::from_mat4(*b))
        .collect();
    let to_body = Affine3A::from_rotation_translation(rotation, position).inverse();
    points
        .iter()
        .zip(indices)
        .zip(weights)
        .enumerate()
        .map(|(vertex, ((p, js), ws))| {
            let p = Vec3A::from_array(*p);
            let mut world = Vec3A::ZERO;
            for (&j, &w) in js.iter().zip(ws) {
                if w == 0.0 {
                    continue;
                }
                let m = skin.get(usize::from(j)).ok_or(SkinError::Joint {
                    vertex,
                    joint: j,
                    joints: count,
                })?;
                world += m.transform_point3a(p) * w;
            }
            Ok(Vec3::from(to_body.transform_point3a(world)))
        })
        .collect()
}

/// The global transforms of `skin`'s joints, from `global` (an entity's
/// global transform, `None` when it has none); `None` when a joint has
/// none.
pub fn joint_transforms(
    skin: &SkinnedMesh,
    mut global: impl FnMut(bevy::prelude::Entity) -> Option<Affine3A>,
) -> Option<Vec<Affine3A>> {
    skin.joints.iter().map(|&j| global(j)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::PrimitiveTopology;

    /// Two vertices: one wholly on joint 0, one half on joint 0 and half on
    /// joint 1.
    fn mesh() -> Mesh {
        Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all())
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_POSITION,
                vec![[1.0f32, 0.0, 0.0], [0.0, 2.0, 0.0]],
            )
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_JOINT_INDEX,
                VertexAttributeValues::Uint16x4(vec![[0, 0, 0, 0], [0, 1, 0, 0]]),
            )
            .with_inserted_attribute(
                Mesh::ATTRIBUTE_JOINT_WEIGHT,
                vec![[1.0f32, 0.0, 0.0, 0.0], [0.5, 0.5, 0.0, 0.0]],
            )
    }

    #[test]
    fn vertices_go_where_their_joints_take_them_in_the_bodys_frame() {
        let m = mesh();
        // Bind poses: joint 1 was bound 1 m up (its inverse takes it down).
        let bind = [
            Mat4::IDENTITY,
            Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0)),
        ];
        // Joint 0 moved 3 m along x; joint 1 turned 90° about z where it was bound.
        let joints = [
            Affine3A::from_translation(Vec3::new(3.0, 0.0, 0.0)),
            Affine3A::from_rotation_translation(
                Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
                Vec3::new(0.0, 1.0, 0.0),
            ),
        ];
        // The body at (1, 0, 0), turned 90° about y.
        let rotation = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let got = skinned_positions(&m, &joints, &bind, rotation, Vec3::X).unwrap();
        // By hand: vertex 0 → (4, 0, 0) in the world; vertex 1: joint 0
        // takes it to (3, 2, 0), joint 1 to (0,1,0) + rot_z(90°)·(0,1,0) =
        // (−1, 1, 0); half each: (1, 1.5, 0).
        let world = [Vec3::new(4.0, 0.0, 0.0), Vec3::new(1.0, 1.5, 0.0)];
        for (g, w) in got.iter().zip(world) {
            let back = rotation * *g + Vec3::X;
            assert!(back.distance(w) < 1e-5, "{back} against {w}");
        }
    }

    #[test]
    fn a_joint_the_skin_lacks_is_named() {
        let e = skinned_positions(
            &mesh(),
            &[Affine3A::IDENTITY],
            &[Mat4::IDENTITY],
            Quat::IDENTITY,
            Vec3::ZERO,
        )
        .unwrap_err();
        assert_eq!(
            e,
            SkinError::Joint {
                vertex: 1,
                joint: 1,
                joints: 1
            }
        );
        let bare = Mesh::new(PrimitiveTopology::TriangleList, RenderAssetUsages::all())
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]]);
        assert_eq!(
            skinned_positions(&bare, &[], &[], Quat::IDENTITY, Vec3::ZERO).unwrap_err(),
            SkinError::NoWeights
        );
    }
}
