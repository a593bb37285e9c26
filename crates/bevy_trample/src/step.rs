//! The simulation step in Bevy's fixed timestep: poses from the tramplers'
//! transforms, the viewpoint from the [`TrampleCamera`], then one core step
//! of the fixed `dt` (frame-rate independent, as the core is).

use crate::diagnostics;
use crate::field::TrampleField;
use crate::host;
use crate::trampler::{Trampler, TramplerBody, TramplerPoseRefused, note_pose};
use bevy::diagnostic::Diagnostics;
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
/// taken again.
#[allow(clippy::type_complexity)]
pub fn step_field(
    time: Res<Time>,
    field: Option<ResMut<TrampleField>>,
    transforms: TransformHelper,
    tramplers: Query<(Entity, &Trampler, &TramplerBody, Has<TramplerPoseRefused>)>,
    cameras: Query<(Entity, &Projection), With<TrampleCamera>>,
    mut diagnostics: Diagnostics,
    mut commands: Commands,
) {
    let Some(mut field) = field else { return };
    let field = &mut *field;
    let dt = time.delta_secs();
    if dt <= 0.0 {
        return;
    }
    for (entity, trampler, body, refused) in &tramplers {
        let Ok(global) = transforms.compute_global_transform(entity) else {
            continue;
        };
        let (_, rotation, position) = global.to_scale_rotation_translation();
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
    match field.sim.step(dt) {
        Ok(t) => diagnostics::record(&mut diagnostics, t),
        Err(e) => warn!("bevy_trample: step refused: {e}"),
    }
    field.changes.after_step(&field.sim);
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
