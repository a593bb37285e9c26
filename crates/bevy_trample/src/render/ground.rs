//! The ground under the grass (and the far field, the paper's Texture
//! level of detail, where no blade or billboard is drawn): an ordinary Bevy
//! mesh following the field's terrain, with a `StandardMaterial` the colour
//! of grass seen from afar, so it is lit, shadowed and fogged as the rest.

use crate::field::TrampleField;
use bevy::asset::RenderAssetUsages;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;

/// Marks the ground entity the plugin spawned for the field.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct TrampleGround;

/// Quads along a side of the ground mesh (it follows the terrain's heights).
pub const GROUND_QUADS: u32 = 128;

/// Linear colour of the far grass: the blades' mean albedo half-way up
/// (`blade_albedo` in `trample::blade_shape` at t = 0.5, tint 0.5).
pub const FAR_GRASS: LinearRgba = LinearRgba::rgb(0.09, 0.175, 0.03);

/// Spawns the ground once a field exists (and there is a `Mesh` and
/// `StandardMaterial` asset store, i.e. the app renders).
pub fn spawn_ground(
    mut commands: Commands,
    field: Res<TrampleField>,
    ground: Query<(), With<TrampleGround>>,
    meshes: Option<ResMut<Assets<Mesh>>>,
    materials: Option<ResMut<Assets<StandardMaterial>>>,
) {
    let (Some(mut meshes), Some(mut materials)) = (meshes, materials) else {
        return;
    };
    if !ground.is_empty() {
        return;
    }
    let mesh = meshes.add(ground_mesh(&field));
    let material = materials.add(StandardMaterial {
        base_color: FAR_GRASS.into(),
        perceptual_roughness: 0.95,
        reflectance: 0.2,
        ..default()
    });
    commands.spawn((
        TrampleGround,
        Mesh3d(mesh),
        MeshMaterial3d(material),
        Transform::default(),
    ));
}

/// The terrain under the field as a grid of `GROUND_QUADS`² quads, y up.
#[must_use]
pub fn ground_mesh(field: &TrampleField) -> Mesh {
    let layout = &field.sim.field.layout;
    let terrain = &field.sim.field.terrain;
    let [ox, oz] = layout.origin;
    let side_x = layout.cell_size * (layout.patches[0] * layout.cells_per_patch) as f32;
    let side_z = layout.cell_size * (layout.patches[1] * layout.cells_per_patch) as f32;
    let n = GROUND_QUADS;
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let x = ox + side_x * i as f32 / n as f32;
            let z = oz + side_z * j as f32 / n as f32;
            positions.push([x, terrain.height_at(x, z), z]);
        }
    }
    let mut indices = Vec::with_capacity((n * n * 6) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    let mut mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_indices(Indices::U32(indices));
    mesh.compute_smooth_normals();
    mesh
}
