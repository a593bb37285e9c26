//! The simulation step in Bevy's fixed timestep: poses from the tramplers'
//! transforms, the viewpoint from the [`TrampleCamera`], then one core step
//! of the fixed `dt` (frame-rate independent, as the core is).

use crate::diagnostics;
use crate::field::TrampleField;
use crate::host;
use crate::skin;
use crate::trampler::{Trampler, TramplerBody, TramplerPoseRefused, TramplerShape, note_pose};
use bevy::diagnostic::Diagnostics;
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::prelude::*;
use bevy::transform::helper::TransformHelper;

/// Marks the camera whose eye and frustum decide the grass's level of
/// detail and culling (paper Fig. 1's viewpoint P). Without one, the
/// field's scene camera does. With several, the first found.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct TrampleCamera;

/// Steps the field by the fixed timestep: each trampler moves to where its
/// entity is now (sweeping the grass between; a jump faster than its
/// `teleport_speed_m_s` does not sweep), the trample camera sets the
/// viewpoint, then `Simulation::step`. Transforms are read through
/// [`TransformHelper`], so a game that moves its entities in `FixedUpdate`
/// before [`crate::TrampleSystems::Step`] is seen at once. A transform the
/// core refuses (a position or rotation that is not finite) leaves the body where it
/// was and puts a [`TramplerPoseRefused`] on the entity until a pose is
/// taken again. A trampler with a [`SkinnedMesh`] (and
/// [`TramplerShape::Mesh`]) tramples with its mesh as the skin poses it
/// ([`crate::skin`]); a skin that cannot be posed on the CPU puts a
/// [`TramplerSkinRefused`] on the entity (the body keeps its last shape).
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
pub fn step_field(
    time: Res<Time>,
    field: Option<ResMut<TrampleField>>,
    transforms: TransformHelper,
    tramplers: Query<(
        Entity,
        &Trampler,
        &TramplerBody,
        Has<TramplerPoseRefused>,
        Option<(&SkinnedMesh, &Mesh3d, Has<TramplerSkinRefused>)>,
    )>,
    cameras: Query<(Entity, &Projection), With<TrampleCamera>>,
    meshes: Option<Res<Assets<Mesh>>>,
    bindposes: Option<Res<Assets<SkinnedMeshInverseBindposes>>>,
    mut diagnostics: Diagnostics,
    mut commands: Commands,
    #[cfg(feature = "gpu")] gpu: crate::gpu_path::GpuContext,
) {
    let Some(mut field) = field else { return };
    let field = &mut *field;
    let dt = time.delta_secs();
    if dt <= 0.0 {
        return;
    }
    for (entity, trampler, body, refused, skinned) in &tramplers {
        let Ok(global) = transforms.compute_global_transform(entity) else {
            continue;
        };
        let (_, rotation, position) = global.to_scale_rotation_translation();
        if let Some((skin, mesh3d, skin_refused)) = skinned
            && trampler.shape == TramplerShape::Mesh
        {
            let posed = skin_vertices(
                &transforms,
                skin,
                meshes.as_deref().and_then(|m| m.get(mesh3d.id())),
                bindposes.as_deref(),
                (rotation, position),
            )
            .and_then(|v| host::set_body_vertices(&mut field.sim, body.id, &v, dt));
            note_skin(&mut commands, entity, posed, skin_refused);
        }
        let here = host::body_position(&field.sim, body.id);
        let jump = here.is_some_and(|p| p.distance(position) > trampler.teleport_speed_m_s * dt);
        let posed = if jump {
            host::teleport_body(&mut field.sim, body.id, position, rotation)
        } else {
            host::move_body(&mut field.sim, body.id, position, rotation, dt)
        };
        note_pose(&mut commands, entity, posed, refused);
    }
    let view = cameras.iter().next().and_then(|(entity, projection)| {
        let global = transforms.compute_global_transform(entity).ok()?;
        Some((global.translation(), view_proj(projection, &global)?))
    });
    match view {
        Some((eye, m)) if host::set_view(&mut field.sim, eye, m) => {}
        _ => host::clear_view(&mut field.sim),
    }
    #[cfg(feature = "gpu")]
    if let Some(stepped) = crate::gpu_path::step(field, &gpu, dt) {
        match stepped {
            Ok(t) => diagnostics::record(&mut diagnostics, &t),
            Err(e) => warn!("bevy_trample: GPU step refused: {e}"),
        }
        return;
    }
    match field.sim.step(dt) {
        Ok(t) => diagnostics::record(&mut diagnostics, t),
        Err(e) => warn!("bevy_trample: step refused: {e}"),
    }
    field.changes.after_step(&field.sim);
    field.cell_changes.after_step(&field.sim);
}

/// The GPU path (a field that asks for it, [`TrampleField::on_gpu`]):
/// hands the field over once Bevy's device is in the main world, and makes
/// the draw lists again when the [`crate::GrassLook`] changed since the
/// last step (a paused game whose look is changed).
#[cfg(feature = "gpu")]
pub fn refresh_gpu_lists(field: Option<ResMut<TrampleField>>, gpu: crate::gpu_path::GpuContext) {
    if let Some(mut field) = field {
        crate::gpu_path::refresh_lists(&mut field, &gpu);
    }
}

/// On a skinned trampler whose skin could not be posed on the CPU (a mesh
/// without joint weights in the main world, a joint without a transform,
/// a vertex naming a joint the skin lacks, vertices the core refuses): why.
/// The body keeps its last shape; the component goes once the skin is
/// posed again. Logged when it appears, not at every step.
#[derive(Component, Clone, Debug, PartialEq, Eq)]
pub struct TramplerSkinRefused(pub String);

/// The vertices of a skinned trampler's mesh as its joints pose them now,
/// in the frame of its body at `(rotation, position)`.
fn skin_vertices(
    transforms: &TransformHelper,
    skin: &SkinnedMesh,
    mesh: Option<&Mesh>,
    bindposes: Option<&Assets<SkinnedMeshInverseBindposes>>,
    (rotation, position): (Quat, Vec3),
) -> Result<Vec<Vec3>, String> {
    let mesh = mesh.ok_or("the mesh asset is not loaded (or not in the main world)")?;
    let bind = bindposes
        .and_then(|b| b.get(&skin.inverse_bindposes))
        .ok_or("the skin's inverse bind poses are not loaded")?;
    let joints = skin::joint_transforms(skin, |j| {
        transforms
            .compute_global_transform(j)
            .ok()
            .map(|g| g.affine())
    })
    .ok_or("a joint of the skin has no transform")?;
    skin::skinned_positions(mesh, &joints, bind, rotation, position).map_err(|e| e.to_string())
}

/// Puts [`TramplerSkinRefused`] on `entity` (logging it) when its skin
/// could not be posed and the entity did not say so yet; takes it off when
/// it was and it did.
fn note_skin(commands: &mut Commands, entity: Entity, posed: Result<(), String>, refused: bool) {
    match posed {
        Ok(()) if refused => {
            commands.entity(entity).remove::<TramplerSkinRefused>();
        }
        Err(e) if !refused => {
            warn!(
                "bevy_trample: entity {entity}: skin not posed, its body keeps its last shape: {e}"
            );
            commands.entity(entity).insert(TramplerSkinRefused(e));
        }
        _ => {}
    }
}

/// World → clip of a camera with clip z in [0, 1] from near to far (the
/// core's convention; Bevy's own projections are reversed-z, often with an
/// infinite far plane): a perspective camera's lens with its near and far
/// planes, or an orthographic camera's box. `None` for other projections.
#[must_use]
pub fn view_proj(projection: &Projection, camera: &GlobalTransform) -> Option<Mat4> {
    let proj = match projection {
        Projection::Perspective(p) => {
            Mat4::perspective_rh(p.fov, p.aspect_ratio, p.near, p.far.max(p.near * 2.0))
        }
        Projection::Orthographic(o) => Mat4::orthographic_rh(
            o.area.min.x,
            o.area.max.x,
            o.area.min.y,
            o.area.max.y,
            o.near,
            o.far,
        ),
        _ => return None,
    };
    Some(proj * camera.to_matrix().inverse())
}
