//! The ground under the grass (and the far field, the paper's Texture
//! level of detail, where no blade or billboard is drawn): an ordinary Bevy
//! mesh following the field's terrain, with a `StandardMaterial` the colour
//! of grass seen from afar, so it is lit, shadowed and fogged as the rest.
//! Its texture is the track (ours, as trample-render's terrain): each
//! cell's flatness (`Cells::flatness`) darkens and browns the ground, so a
//! track shows at every level of detail, past the billboards too.

use super::look::GrassLook;
use crate::field::TrampleField;
use bevy::asset::RenderAssetUsages;
use bevy::image::Image;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use trample::field::FieldLayout;

/// Marks the ground entity the plugin spawned for the field.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct TrampleGround;

/// Quads along a side of the ground mesh (it follows the terrain's heights).
pub const GROUND_QUADS: u32 = 128;

/// Linear colour of the far grass: the blades' mean albedo half-way up
/// (`blade_albedo` in `trample::blade_shape` at t = 0.5, tint 0.5).
pub const FAR_GRASS: LinearRgba = LinearRgba::rgb(0.09, 0.175, 0.03);

/// Most texels along a side of the track texture: a larger field's cells
/// share texels, `k × k` of them a texel (their mean flatness).
pub const MAX_TRACK_TEXELS: u32 = 2048;

/// Flattened ground's colour factor (linear; trample-render's terrain
/// browns its ground with the same): laid blades shade the ground and show
/// their duller undersides.
pub const FLATTENED_GROUND: [f32; 3] = [0.5, 0.45, 0.3];

/// The track texture on the ground, and what it covers.
#[derive(Resource, Clone, Debug)]
pub struct GroundTrack {
    /// The texture (linear RGBA8, white where nothing is flattened).
    pub image: Handle<Image>,
    /// Cells a texel covers along each side.
    pub cells_per_texel: u32,
    /// Texels along x and z.
    pub texels: [u32; 2],
    /// The darkening it was last drawn with
    /// ([`GrassLook::track_darkening_in_use`]).
    pub darkening: f32,
    /// The field it was made for ([`ground_key`]).
    pub key: GroundKey,
    /// Changed cells (scratch).
    changed: Vec<u32>,
}

/// What a ground is made for: the field's origin and cell size (m) and its
/// cells along x and z. A field with another key gets a new ground.
pub type GroundKey = ([f32; 2], f32, [u32; 2]);

/// The [`GroundKey`] of `field`.
#[must_use]
pub fn ground_key(field: &TrampleField) -> GroundKey {
    let layout = &field.sim.field.layout;
    (layout.origin, layout.cell_size, layout.grid_size())
}

/// The ground's colour factor for a mean flatness `flat` in [0, 1]: white
/// at 0, towards [`FLATTENED_GROUND`] with the square root of `flat`
/// times `darkening` (the square root makes a half-flattened patch read as
/// a track, continuously from 0), as trample-render's terrain. Linear.
#[must_use]
pub fn track_texel(flat: f32, darkening: f32) -> [u8; 4] {
    let f = if flat.is_finite() {
        flat.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = if darkening.is_finite() {
        darkening.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let t = f.sqrt() * d;
    let c = FLATTENED_GROUND.map(|g| ((1.0 + (g - 1.0) * t) * 255.0).round() as u8);
    [c[0], c[1], c[2], 255]
}

/// Cells along x and z of `layout`, the cells a texel covers along a side
/// (`MAX_TRACK_TEXELS` at most along each), and the texels along x and z.
#[must_use]
pub fn track_grid(layout: &FieldLayout) -> ([u32; 2], u32, [u32; 2]) {
    let cells = layout.grid_size();
    let k = cells[0].max(cells[1]).div_ceil(MAX_TRACK_TEXELS).max(1);
    (cells, k, [cells[0].div_ceil(k), cells[1].div_ceil(k)])
}

/// Texel `(tx, tz)` of the track of `field`: its cells' mean flatness.
fn texel_of(field: &TrampleField, k: u32, cells: [u32; 2], tx: u32, tz: u32, d: f32) -> [u8; 4] {
    let layout = &field.sim.field.layout;
    let flatness = &field.sim.field.cells.flatness;
    let (mut sum, mut n) = (0.0f32, 0u32);
    for gz in tz * k..((tz + 1) * k).min(cells[1]) {
        for gx in tx * k..((tx + 1) * k).min(cells[0]) {
            sum += flatness
                .get(layout.cell_index(gx, gz))
                .copied()
                .unwrap_or(0.0);
            n += 1;
        }
    }
    track_texel(sum / n.max(1) as f32, d)
}

/// Every texel of the track of `field` at `darkening`: rows along z,
/// texels along x, RGBA8.
#[must_use]
pub fn track_texels(field: &TrampleField, darkening: f32) -> Vec<u8> {
    let (cells, k, [w, h]) = track_grid(&field.sim.field.layout);
    let mut data = Vec::with_capacity((w * h * 4) as usize);
    for tz in 0..h {
        for tx in 0..w {
            data.extend_from_slice(&texel_of(field, k, cells, tx, tz, darkening));
        }
    }
    data
}

/// Redraws in `data` (the texels of [`track_texels`]) the texels of the
/// cells `changed` (storage indices, ascending) of `field`.
pub fn redraw_texels(field: &TrampleField, changed: &[u32], darkening: f32, data: &mut [u8]) {
    let layout = &field.sim.field.layout;
    let (cells, k, [w, _]) = track_grid(layout);
    let mut last = None;
    for &c in changed {
        let [gx, gz] = layout.cell_coord(c as usize);
        let (tx, tz) = (gx / k, gz / k);
        if last == Some((tx, tz)) {
            continue;
        }
        last = Some((tx, tz));
        let at = ((tz * w + tx) * 4) as usize;
        if let Some(px) = data.get_mut(at..at + 4) {
            px.copy_from_slice(&texel_of(field, k, cells, tx, tz, darkening));
        }
    }
}

/// The track texture of `field` (linear RGBA8, [`track_texels`]).
fn track_image(field: &TrampleField, darkening: f32) -> Image {
    let (_, _, [width, height]) = track_grid(&field.sim.field.layout);
    Image::new(
        Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        track_texels(field, darkening),
        TextureFormat::Rgba8Unorm,
        RenderAssetUsages::default(),
    )
}

/// Spawns the ground once a field exists (and there is a `Mesh` and
/// `StandardMaterial` asset store, i.e. the app renders), textured with the
/// field's track ([`GroundTrack`]); anew for another field.
#[allow(clippy::too_many_arguments)]
pub fn spawn_ground(
    mut commands: Commands,
    field: Res<TrampleField>,
    look: Option<Res<GrassLook>>,
    track: Option<Res<GroundTrack>>,
    ground: Query<Entity, With<TrampleGround>>,
    meshes: Option<ResMut<Assets<Mesh>>>,
    materials: Option<ResMut<Assets<StandardMaterial>>>,
    images: Option<ResMut<Assets<Image>>>,
) {
    let (Some(mut meshes), Some(mut materials), Some(mut images)) = (meshes, materials, images)
    else {
        return;
    };
    let key = ground_key(&field);
    if !ground.is_empty() {
        if track.is_some_and(|t| t.key == key) {
            return;
        }
        for e in &ground {
            commands.entity(e).despawn();
        }
    }
    let darkening = look.map_or_else(
        || GrassLook::default().track_darkening_in_use(),
        |l| l.track_darkening_in_use(),
    );
    let (_, cells_per_texel, texels) = track_grid(&field.sim.field.layout);
    let image = images.add(track_image(&field, darkening));
    commands.insert_resource(GroundTrack {
        image: image.clone(),
        cells_per_texel,
        texels,
        darkening,
        key,
        changed: Vec::new(),
    });
    let mesh = meshes.add(ground_mesh(&field));
    let material = materials.add(StandardMaterial {
        base_color: FAR_GRASS.into(),
        base_color_texture: Some(image),
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

/// Redraws the texels of the cells the steps changed since the last frame
/// (every texel when [`GrassLook::track_darkening`] changed).
pub fn update_ground_track(
    mut field: ResMut<TrampleField>,
    look: Option<Res<GrassLook>>,
    track: Option<ResMut<GroundTrack>>,
    images: Option<ResMut<Assets<Image>>>,
) {
    let (Some(mut track), Some(mut images)) = (track, images) else {
        return;
    };
    let track = &mut *track;
    let darkening = look.map_or_else(
        || GrassLook::default().track_darkening_in_use(),
        |l| l.track_darkening_in_use(),
    );
    let mut changed = std::mem::take(&mut track.changed);
    changed.clear();
    // The first take is every cell: the texture was made from them all.
    let _ = field.cell_changes.take(&mut changed);
    let all = darkening != track.darkening;
    if changed.is_empty() && !all {
        track.changed = changed;
        return;
    }
    let Some(mut image) = images.get_mut(&track.image) else {
        track.changed = changed;
        return;
    };
    let field = &*field;
    if track.key != ground_key(field) {
        // Another field: its ground is made anew (`spawn_ground`).
        track.changed = changed;
        return;
    }
    if all || image.data.is_none() {
        image.data = Some(track_texels(field, darkening));
        track.darkening = darkening;
    } else if let Some(data) = image.data.as_mut() {
        redraw_texels(field, &changed, darkening, data);
    }
    track.changed = changed;
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
    let mut uvs = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let x = ox + side_x * u;
            let z = oz + side_z * v;
            positions.push([x, terrain.height_at(x, z), z]);
            // The track texture: u along x, v along z, over the cells.
            uvs.push([u, v]);
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
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_indices(Indices::U32(indices));
    mesh.compute_smooth_normals();
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use trample::scene::Scene;

    #[test]
    fn a_flattened_cell_darkens_its_texel_and_nothing_else() {
        assert_eq!(track_texel(0.0, 0.8), [255; 4]);
        assert_eq!(track_texel(0.7, 0.0), [255; 4], "darkening off");
        assert_eq!(track_texel(f32::NAN, 0.8), [255; 4]);
        let full = track_texel(1.0, 1.0);
        assert_eq!(full, [128, 115, 77, 255], "FLATTENED_GROUND");
        // Continuous from 0, darker with the flatness.
        let (a, b) = (track_texel(0.01, 0.8), track_texel(0.25, 0.8));
        assert!(
            a[0] > b[0] && b[0] > track_texel(1.0, 0.8)[0],
            "{a:?} {b:?}"
        );
        assert!(255 - a[0] < 30, "{a:?}");

        let scene = Scene::default_scene().unwrap();
        let mut field = TrampleField::from_scene(&scene).unwrap();
        let layout = field.sim.field.layout.clone();
        let (cells, k, texels) = track_grid(&layout);
        assert_eq!((cells, k, texels), ([512, 512], 1, [512, 512]));
        field.sim.field.cells.flatness.fill(0.0);
        let (gx, gz) = (37, 401);
        field.sim.field.cells.flatness[layout.cell_index(gx, gz)] = 1.0;
        let data = track_texels(&field, 0.8);
        assert_eq!(data.len(), 512 * 512 * 4);
        let dark: Vec<usize> = data
            .chunks(4)
            .enumerate()
            .filter(|(_, p)| p[0] < 255)
            .map(|(i, _)| i)
            .collect();
        assert_eq!(dark, vec![gz as usize * 512 + gx as usize]);
        // Cells changed later: redrawn where they are, the rest kept.
        let mut data = data;
        let mut changed = Vec::new();
        for (gx, gz, f) in [(0, 0, 0.5), (511, 3, 1.0), (200, 511, 0.04), (37, 401, 0.0)] {
            let c = layout.cell_index(gx, gz);
            field.sim.field.cells.flatness[c] = f;
            changed.push(c as u32);
        }
        changed.sort_unstable();
        redraw_texels(&field, &changed, 0.8, &mut data);
        assert_eq!(data, track_texels(&field, 0.8));
    }

    #[test]
    fn a_large_field_shares_texels_among_cells() {
        let layout = FieldLayout {
            patches: [128, 128],
            cells_per_patch: 32,
            ..Scene::default_scene()
                .unwrap()
                .build()
                .unwrap()
                .field
                .layout
        };
        let (cells, k, texels) = track_grid(&layout);
        assert_eq!(cells, [4096, 4096]);
        assert_eq!(k, 2);
        assert_eq!(texels, [2048, 2048]);
    }
}
