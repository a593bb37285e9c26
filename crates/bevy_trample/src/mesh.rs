//! A Bevy [`Mesh`] asset as the core's triangle mesh ([`TriMesh`]), with
//! the entity's scale baked in (the core's bodies move rigidly: position
//! and rotation only).

use bevy::asset::RenderAssetUsages;
use bevy::math::Vec3;
use bevy::mesh::{Indices, Mesh, PrimitiveTopology, VertexFormat};
use trample::object::TriMesh;

/// Why a mesh asset cannot be a trampler's collision mesh.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshConversionError {
    /// Only triangle lists are collision meshes.
    #[error("primitive topology {0:?}: a trampler's mesh must be a triangle list")]
    Topology(PrimitiveTopology),
    /// No `Mesh::ATTRIBUTE_POSITION`.
    #[error("the mesh has no POSITION attribute")]
    NoPositions,
    /// Positions in another format than three 32-bit floats.
    #[error("POSITION is {0}: must be Float32x3")]
    PositionFormat(String),
    /// The asset's data lives only in the render world.
    #[error(
        "the mesh's data was moved to the render world (RenderAssetUsages::RENDER_WORLD only): keep RenderAssetUsages::MAIN_WORLD on a trampler's mesh"
    )]
    NotInMainWorld,
}

/// The triangles of `mesh`, vertices scaled by `scale` (the entity's scale):
/// indexed meshes keep their indices, non-indexed ones take three vertices
/// per triangle.
///
/// # Errors
/// [`MeshConversionError`] for a mesh that is not a readable triangle list.
pub fn tri_mesh(mesh: &Mesh, scale: Vec3) -> Result<TriMesh, MeshConversionError> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(MeshConversionError::Topology(mesh.primitive_topology()));
    }
    if !mesh.asset_usage.contains(RenderAssetUsages::MAIN_WORLD) {
        return Err(MeshConversionError::NotInMainWorld);
    }
    let values = mesh
        .try_attribute_option(Mesh::ATTRIBUTE_POSITION)
        .map_err(|_| MeshConversionError::NotInMainWorld)?
        .ok_or(MeshConversionError::NoPositions)?;
    let Some(points) = values.as_float3() else {
        return Err(MeshConversionError::PositionFormat(format!(
            "{:?}",
            VertexFormat::from(values)
        )));
    };
    let positions: Vec<glam::Vec3> = points
        .iter()
        .map(|p| glam::Vec3::from_array(*p) * glam::Vec3::from_array(scale.to_array()))
        .collect();
    let flat: Vec<u32> = match mesh
        .try_indices_option()
        .map_err(|_| MeshConversionError::NotInMainWorld)?
    {
        Some(Indices::U16(i)) => i.iter().map(|&i| u32::from(i)).collect(),
        Some(Indices::U32(i)) => i.clone(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Ok(TriMesh { positions, indices })
}
