//! Drawing the meadow with Bevy's renderer (DESIGN §8): geometric blades
//! pulled from a storage buffer (the core's vertex layout, Eq. 1), crossed
//! billboards for the middle distance (Eq. 8's slope) and the far ground,
//! lit by Bevy's lights (directional light and its shadows, ambient, fog)
//! in Bevy's opaque pass, so depth is shared with the rest of the scene.
//!
//! The data flow is Bevy's: the main world simulates; [`extract`] copies
//! what changed (the blades the last steps moved, this frame's drawn cells
//! and billboards, the [`look::GrassLook`]: blend bands and render
//! density) into the render world; [`gpu`] uploads only that;
//! [`queue`] puts the two draws into each camera's opaque phase (and,
//! with [`look::GrassLook::cast_shadows`], into each light's shadow
//! phase, depth-only pipelines from [`pipeline`]);
//! [`pipeline`] specialises Bevy's mesh pipeline (its view bindings and
//! shader defs) for `blades.wgsl`, whose blade shape, wind and colour are
//! the shader library `trample::blade_shape` shared with trample-render.
//!
//! A field whose blade vertices pass one storage binding is uploaded and
//! drawn in chunks of patches ([`trample::field::chunks`]), one draw a
//! chunk. On the GPU path ([`crate::gpu_path`]) the draws read the GPU's
//! own buffers (its chunks, its lists, indirect) in place of the uploads.

pub mod extract;
pub mod gpu;
pub mod ground;
pub mod look;
pub mod pipeline;
pub mod queue;

use bevy::asset::{embedded_asset, uuid_handle};
use bevy::camera::primitives::Aabb;
use bevy::camera::visibility::{self, VisibilityClass};
use bevy::core_pipeline::core_3d::Opaque3d;
use bevy::pbr::{MeshPipelineSystems, Shadow};
use bevy::prelude::*;
use bevy::render::extract_component::{ExtractComponent, ExtractComponentPlugin};
use bevy::render::render_phase::AddRenderCommand;
use bevy::render::{ExtractSchedule, Render, RenderApp, RenderStartup, RenderSystems};

use crate::field::TrampleField;

/// Handle of the shader library `trample::blade_shape`: the core's
/// [`trample::blade_shape::WGSL`] with Bevy's import path.
pub const BLADE_SHAPE_SHADER: Handle<Shader> = uuid_handle!("6f0c2b0e-7a4f-4b55-9d0e-2f7b1c3a9e41");

/// One of the two draws of the field (an entity each, so Bevy's visibility
/// and phase machinery handle them as any other drawn thing).
#[derive(Component, ExtractComponent, Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[require(VisibilityClass)]
#[component(on_add = visibility::add_visibility_class::<GrassDraw>)]
pub enum GrassDraw {
    /// The blades of the visible Geometry-LOD cells.
    Blades,
    /// The billboards of the visible Billboard-LOD cells.
    Billboards,
}

/// Draws the [`TrampleField`] (added by [`crate::TramplePlugin`] when the
/// app has Bevy's renderer).
#[derive(Clone, Debug, Default)]
pub struct TrampleRenderPlugin;

impl Plugin for TrampleRenderPlugin {
    fn build(&self, app: &mut App) {
        embedded_asset!(app, "blades.wgsl");
        let shape = format!(
            "#define_import_path trample::blade_shape\n{}",
            trample::blade_shape::WGSL
        );
        let _ = app.world_mut().resource_mut::<Assets<Shader>>().insert(
            &BLADE_SHAPE_SHADER,
            Shader::from_wgsl(shape, "trample/blade_shape.wgsl"),
        );
        app.init_resource::<look::GrassLook>()
            .add_plugins(ExtractComponentPlugin::<GrassDraw>::default())
            .add_systems(
                PostUpdate,
                (
                    spawn_draws,
                    ground::spawn_ground,
                    ground::update_ground_track.after(ground::spawn_ground),
                )
                    .run_if(resource_exists::<TrampleField>),
            );
        let Some(render_app) = app.get_sub_app_mut(RenderApp) else {
            return;
        };
        render_app
            .init_resource::<extract::GrassFrame>()
            .init_resource::<queue::PendingGrassQueues>()
            .add_render_command::<Opaque3d, queue::DrawGrass>()
            .add_render_command::<Shadow, queue::DrawGrassShadow>()
            .add_systems(
                RenderStartup,
                pipeline::init_grass_pipeline.after(MeshPipelineSystems),
            )
            .add_systems(ExtractSchedule, extract::extract_grass)
            .add_systems(
                Render,
                (
                    queue::queue_grass.in_set(RenderSystems::Queue),
                    queue::queue_grass_shadows.in_set(RenderSystems::Queue),
                    gpu::prepare_grass_buffers.in_set(RenderSystems::PrepareResources),
                    gpu::prepare_grass_bind_group.in_set(RenderSystems::PrepareBindGroups),
                ),
            );
    }
}

/// Spawns the two draw entities once a field exists; their bounds cover
/// the field and its tallest blades (Bevy culls them as a whole; the
/// patches are culled by the simulation's camera).
fn spawn_draws(
    mut commands: Commands,
    field: Res<TrampleField>,
    draws: Query<(), With<GrassDraw>>,
) {
    if !draws.is_empty() {
        return;
    }
    let aabb = field_bounds(&field);
    for draw in [GrassDraw::Blades, GrassDraw::Billboards] {
        commands.spawn((draw, aabb, Transform::default(), Visibility::default()));
    }
}

/// Bounds of the field's blades and ground (metres, world frame).
fn field_bounds(field: &TrampleField) -> Aabb {
    let bl = &field.sim.field.blades;
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for v in bl.rest.iter() {
        let v = Vec3::from_array(v.pos);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo.x > hi.x {
        return Aabb::from_min_max(Vec3::ZERO, Vec3::ZERO);
    }
    // Billboards are a bit wider than a cell; the wind leans tips sideways.
    let margin = Vec3::splat(field.sim.field.params.cell_size_m + trample::wind::MAX_WIND_M);
    Aabb::from_min_max(lo - margin, hi + margin)
}
