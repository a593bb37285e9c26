//! [`Trampler`]: the component that makes an entity a body in the grass,
//! and the system that keeps the simulation's bodies in step with the
//! entities that have it (added, removed, mesh changed, scale changed).

use crate::field::TrampleField;
use crate::host::{self, BodyId};
use crate::mesh::tri_mesh;
use bevy::prelude::*;
use trample::object::{ShapeParams, TrackParams};

/// Makes an entity trample the grass: its collision mesh becomes a body of
/// the [`TrampleField`] (the paper's OBB tree, §4, built from it), posed
/// from the entity's [`GlobalTransform`] at every simulation step, the
/// contact speed of Eq. 2 taken from the motion between two steps.
///
/// Plain data: change a field and the body is rebuilt.
#[derive(Component, Clone, Debug, PartialEq)]
#[require(Transform)]
pub struct Trampler {
    /// What collides: the entity's [`Mesh3d`] (default) or a built-in shape.
    pub shape: TramplerShape,
    /// How the body marks the grass: recovery time and trail of the blades
    /// it pressed last, and a factor on the force of Eq. 2 (the scene
    /// format's `track`). Default: the field's `[sim]` values, force as
    /// Eq. 2 says.
    pub track: TrackParams,
    /// Depth of the body's OBB tree (paper §4.2: root = 1, the paper uses 1
    /// to 7): how closely the collision test follows the mesh. The narrow
    /// phase stops at `min(precision, sim.precision)` (a tree's leaves end
    /// it). Default 7 (the field's `sim.precision` then decides).
    pub precision: u32,
    /// Speed above which a move is a jump (a respawn, a teleport), m/s: the
    /// body appears at its new place without sweeping the grass between
    /// the two. Default 100 m/s.
    pub teleport_speed_m_s: f32,
}

impl Default for Trampler {
    fn default() -> Self {
        Self {
            shape: TramplerShape::Mesh,
            track: TrackParams::default(),
            precision: 7,
            teleport_speed_m_s: 100.0,
        }
    }
}

impl Trampler {
    /// A trampler with a built-in shape instead of the entity's mesh.
    #[must_use]
    pub fn shape(shape: ShapeParams) -> Self {
        Self {
            shape: TramplerShape::Builtin(shape),
            ..Self::default()
        }
    }
}

/// A trampler's collision mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum TramplerShape {
    /// The entity's [`Mesh3d`] asset (a triangle list, kept in the main
    /// world), rebuilt when the asset changes. The entity's scale is baked
    /// in (rebuilt when the scale changes).
    #[default]
    Mesh,
    /// A built-in shape of the scene format (sphere, box, capsule,
    /// cylinder, knot, or a mesh file), scaled by the entity's scale.
    Builtin(ShapeParams),
}

/// The simulation body of a [`Trampler`] entity (kept by the plugin).
#[derive(Component, Clone, Debug, PartialEq)]
pub struct TramplerBody {
    /// Its stable id in the simulation.
    pub id: BodyId,
    /// The mesh asset its tree was built from ([`TramplerShape::Mesh`]).
    pub mesh: Option<AssetId<Mesh>>,
    /// The scale baked into its mesh.
    pub scale: Vec3,
}

/// Why a [`Trampler`] has no body (kept on the entity until it changes).
#[derive(Component, Clone, Debug, PartialEq, Eq)]
pub struct TramplerError(pub String);

/// On a trampler whose transform the simulation step could not pose its
/// body with (a position or rotation that is not finite): the core's
/// message. (A zero scale is a changed scale: the body is rebuilt, and a
/// [`TramplerError`] says why it cannot be.) The body stays where it was and the
/// game goes on; the component goes once a pose is taken again. Logged
/// when it appears, not at every step.
#[derive(Component, Clone, Debug, PartialEq, Eq)]
pub struct TramplerPoseRefused(pub String);

/// Puts `refused` on `entity` (logging it) when the pose was refused and
/// the entity did not say so yet; takes it off when a pose was taken and
/// it did.
pub(crate) fn note_pose(
    commands: &mut Commands,
    entity: Entity,
    posed: Result<(), String>,
    refused: bool,
) {
    match posed {
        Ok(()) if refused => {
            commands.entity(entity).remove::<TramplerPoseRefused>();
        }
        Err(e) if !refused => {
            warn!("bevy_trample: entity {entity}: pose refused, its body stays where it was: {e}");
            commands.entity(entity).insert(TramplerPoseRefused(e));
        }
        _ => {}
    }
}

/// Adds, rebuilds and removes bodies: a new or changed [`Trampler`], a
/// changed mesh asset or a changed scale rebuilds the body; an entity that
/// lost its `Trampler` (or was despawned) loses its body. Runs in
/// `PostUpdate` after transform propagation.
#[allow(clippy::type_complexity)]
pub fn sync_bodies(
    mut commands: Commands,
    field: Option<ResMut<TrampleField>>,
    meshes: Res<Assets<Mesh>>,
    mut mesh_events: MessageReader<AssetEvent<Mesh>>,
    mut removed: RemovedComponents<Trampler>,
    mut gone: Local<Vec<(Entity, BodyId)>>,
    mut known: Local<bevy::platform::collections::HashMap<Entity, BodyId>>,
    tramplers: Query<(
        Entity,
        Ref<Trampler>,
        &GlobalTransform,
        Option<&Mesh3d>,
        Option<&TramplerBody>,
        Has<TramplerError>,
    )>,
) {
    let Some(mut field) = field else {
        mesh_events.clear();
        removed.clear();
        return;
    };
    let field = &mut *field;
    let changed_meshes: Vec<AssetId<Mesh>> = mesh_events
        .read()
        .filter_map(|e| match e {
            AssetEvent::Modified { id } | AssetEvent::LoadedWithDependencies { id } => Some(*id),
            _ => None,
        })
        .collect();

    // Removed components and despawned entities.
    gone.clear();
    for entity in removed.read() {
        if tramplers.get(entity).is_err()
            && let Some(key) = known.remove(&entity)
        {
            gone.push((entity, key));
        }
    }
    for &(entity, id) in gone.iter() {
        if host::remove_body(&mut field.sim, id) {
            field.tramplers -= 1;
        }
        if let Ok(mut e) = commands.get_entity(entity) {
            e.try_remove::<(
                TramplerBody,
                TramplerError,
                TramplerPoseRefused,
                crate::step::TramplerSkinRefused,
            )>();
        }
    }

    for (entity, trampler, global, mesh3d, body, failed) in &tramplers {
        let (scale, rotation, position) = global.to_scale_rotation_translation();
        let mesh_id = mesh3d.map(|m| m.id());
        let stale = match body {
            // A refused one is tried again when it or its mesh changes.
            None if failed => {
                trampler.is_changed() || mesh_id.is_some_and(|id| changed_meshes.contains(&id))
            }
            None => true,
            Some(b) => {
                trampler.is_changed()
                    || (trampler.shape == TramplerShape::Mesh && b.mesh != mesh_id)
                    || b.mesh.is_some_and(|id| changed_meshes.contains(&id))
                    || (b.scale - scale).abs().max_element() > 1e-4 * b.scale.abs().max_element()
            }
        };
        if !stale {
            continue;
        }
        if let Some(b) = body {
            if host::remove_body(&mut field.sim, b.id) {
                field.tramplers -= 1;
            }
            known.remove(&entity);
        }
        let name = format!("entity {entity}");
        let built = match &trampler.shape {
            TramplerShape::Mesh => {
                let Some(id) = mesh_id else {
                    commands
                        .entity(entity)
                        .remove::<TramplerBody>()
                        .insert(TramplerError(format!(
                            "{name}: Trampler with TramplerShape::Mesh needs a Mesh3d"
                        )));
                    continue;
                };
                let Some(mesh) = meshes.get(id) else {
                    // Not loaded yet: built when its event arrives.
                    commands.entity(entity).remove::<TramplerBody>();
                    continue;
                };
                tri_mesh(mesh, scale)
                    .map_err(|e| crate::TrampleError::Object(name.clone(), e.to_string()))
                    .and_then(|m| {
                        host::body_from_mesh(&name, &m, trampler.track, trampler.precision)
                    })
            }
            TramplerShape::Builtin(shape) => {
                host::body_from_shape(&name, shape, scale, trampler.track, trampler.precision)
            }
        };
        match built {
            Ok(b) => {
                let id = host::add_body(&mut field.sim, b);
                // Where the entity is, without sweeping the grass from the origin.
                let posed = host::teleport_body(&mut field.sim, id, position, rotation);
                note_pose(&mut commands, entity, posed, false);
                field.tramplers += 1;
                known.insert(entity, id);
                commands
                    .entity(entity)
                    .remove::<TramplerError>()
                    .insert(TramplerBody {
                        id,
                        mesh: match trampler.shape {
                            TramplerShape::Mesh => mesh_id,
                            TramplerShape::Builtin(_) => None,
                        },
                        scale,
                    });
            }
            Err(e) => {
                warn!("bevy_trample: {e}");
                commands
                    .entity(entity)
                    .remove::<TramplerBody>()
                    .insert(TramplerError(e.to_string()));
            }
        }
    }
}
