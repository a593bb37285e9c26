//! Puts the two grass draws into every 3D view's opaque phase (Bevy's
//! `Opaque3d`: the same pass and depth buffer as the scene's meshes) and
//! the render command that draws them: view bindings (groups 0 and 1),
//! the grass's bind group (group 2), then one instanced draw. With
//! `GrassLook::cast_shadows`, both draws go into every shadow view's
//! `Shadow` phase too (the prepass's view bindings, the same draws).

use super::GrassDraw;
use super::gpu::{DRAW_ARGS_BYTES, GrassGpu};
use super::pipeline::GrassPipeline;
use bevy::asset::AssetId;
use bevy::core_pipeline::core_3d::{Opaque3d, Opaque3dBatchSetKey, Opaque3dBinKey};
use bevy::ecs::query::ROQueryItem;
use bevy::ecs::system::SystemParamItem;
use bevy::ecs::system::lifetimeless::{Read, SRes};
use bevy::mesh::Mesh;
use bevy::pbr::{
    LightEntity, PrepassPipeline, SetMeshViewBindGroup, SetMeshViewBindingArrayBindGroup,
    SetPrepassViewBindGroup, SetPrepassViewEmptyBindGroup, Shadow, ShadowBatchSetKey, ShadowBinKey,
    ViewKeyCache,
};
use bevy::prelude::*;
use bevy::render::camera::{DirtySpecializations, PendingQueues};
use bevy::render::mesh::allocator::MeshSlabs;
use bevy::render::render_phase::{
    BinnedRenderPhaseType, DrawFunctions, InputUniformIndex, PhaseItem, RenderCommand,
    RenderCommandResult, SetItemPipeline, TrackedRenderPass, ViewBinnedRenderPhases,
};
use bevy::render::render_resource::PipelineCache;
use bevy::render::sync_world::MainEntity;
use bevy::render::view::{ExtractedView, RenderVisibleEntities};

/// Draw entities that could not be queued yet (Bevy's bookkeeping for
/// [`DirtySpecializations`]; the grass's pipelines never wait on assets).
#[derive(Default, Deref, DerefMut, Resource)]
pub struct PendingGrassQueues(pub PendingQueues);

/// The render command of a grass draw.
pub type DrawGrass = (
    SetItemPipeline,
    SetMeshViewBindGroup<0>,
    SetMeshViewBindingArrayBindGroup<1>,
    DrawGrassInstances,
);

/// The render command of a grass draw into a light's shadow map:
/// the prepass's view bindings (the light's view; groups 0 and 1), then
/// the draw of [`DrawGrass`].
pub type DrawGrassShadow = (
    SetItemPipeline,
    SetPrepassViewBindGroup<0>,
    SetPrepassViewEmptyBindGroup<1>,
    DrawGrassInstances,
);

/// Binds group 2 and draws: every drawn blade (each of its drawn copies)
/// as an instance of `6 · segments` vertices (two triangles a segment),
/// one draw a chunk of blade vertices, or every billboard as an instance
/// of 12 (two crossed quads); on the GPU path the same draws, indirect
/// (the GPU listed them).
pub struct DrawGrassInstances;

impl<P: PhaseItem> RenderCommand<P> for DrawGrassInstances {
    // Optional: a field the device cannot draw has none (the draws stay
    // queued and skip).
    type Param = Option<SRes<GrassGpu>>;
    type ViewQuery = ();
    type ItemQuery = Read<GrassDraw>;

    fn render<'w>(
        _item: &P,
        _view: ROQueryItem<'w, '_, Self::ViewQuery>,
        draw: Option<ROQueryItem<'w, '_, Self::ItemQuery>>,
        gpu: SystemParamItem<'w, '_, Self::Param>,
        pass: &mut TrackedRenderPass<'w>,
    ) -> RenderCommandResult {
        let Some(gpu) = gpu.map(|g| g.into_inner()) else {
            return RenderCommandResult::Skip;
        };
        let (Some(draw), Some(group)) = (draw, gpu.bind_groups.first()) else {
            return RenderCommandResult::Skip;
        };
        if let Some(indirect) = &gpu.indirect {
            // The GPU path's lists: the counts are on the GPU; the blades
            // one draw a chunk of their vertices.
            match draw {
                GrassDraw::Blades => {
                    for (k, group) in gpu.bind_groups.iter().enumerate() {
                        pass.set_bind_group(2, group, &[]);
                        pass.draw_indirect(&indirect.args, DRAW_ARGS_BYTES * k as u64);
                    }
                }
                GrassDraw::Billboards => {
                    pass.set_bind_group(2, group, &[]);
                    pass.draw_indirect(&indirect.args, indirect.billboard_args);
                }
            }
            return RenderCommandResult::Success;
        }
        match draw {
            GrassDraw::Blades => {
                // One draw a chunk of blade vertices, of the listed cells
                // whose blades it holds.
                let mut drew = false;
                for (group, instances) in gpu.bind_groups.iter().zip(&gpu.drawn) {
                    if instances.is_empty() {
                        continue;
                    }
                    pass.set_bind_group(2, group, &[]);
                    pass.draw(0..6 * gpu.segments, instances.clone());
                    drew = true;
                }
                if !drew {
                    return RenderCommandResult::Skip;
                }
            }
            GrassDraw::Billboards => {
                // The first piece with the first chunk's group, each
                // further piece with its own.
                let more = gpu.bind_groups.get(gpu.chunks.len()..).unwrap_or(&[]);
                let groups = std::iter::once(group).chain(more);
                let mut drew = false;
                for (group, &count) in groups.zip(&gpu.billboard_counts) {
                    if count == 0 {
                        continue;
                    }
                    pass.set_bind_group(2, group, &[]);
                    pass.draw(0..12, 0..count);
                    drew = true;
                }
                if !drew {
                    return RenderCommandResult::Skip;
                }
            }
        }
        RenderCommandResult::Success
    }
}

/// Queues the grass draws visible from each view into its opaque phase.
#[allow(clippy::too_many_arguments)]
pub fn queue_grass(
    pipeline_cache: Res<PipelineCache>,
    pipeline: Option<ResMut<GrassPipeline>>,
    mut phases: ResMut<ViewBinnedRenderPhases<Opaque3d>>,
    draw_functions: Res<DrawFunctions<Opaque3d>>,
    views: Query<(&ExtractedView, &RenderVisibleEntities)>,
    view_keys: Res<ViewKeyCache>,
    draws: Query<&GrassDraw>,
    dirty: Res<DirtySpecializations>,
    mut pending: ResMut<PendingGrassQueues>,
) {
    let Some(mut pipeline) = pipeline else { return };
    let draw_grass = draw_functions.read().id::<DrawGrass>();
    for (view, visible) in &views {
        let Some(phase) = phases.get_mut(&view.retained_view_entity) else {
            continue;
        };
        let Some(&view_key) = view_keys.get(&view.retained_view_entity) else {
            continue;
        };
        let Some(visible_draws) = visible.get::<GrassDraw>() else {
            continue;
        };
        let view_pending = pending.prepare_for_new_frame(view.retained_view_entity);
        for &main_entity in dirty.iter_to_dequeue(view.retained_view_entity, visible_draws) {
            phase.remove(main_entity);
        }
        for (render_entity, main_entity) in dirty.iter_to_queue(
            view.retained_view_entity,
            visible_draws,
            &view_pending.prev_frame,
        ) {
            let Ok(&draw) = draws.get(*render_entity) else {
                continue;
            };
            let pipeline_id = match pipeline.pipeline(&pipeline_cache, view_key, draw) {
                Ok(id) => id,
                Err(e) => {
                    error!("bevy_trample: grass pipeline: {e}");
                    continue;
                }
            };
            phase.add(
                Opaque3dBatchSetKey {
                    draw_function: draw_grass,
                    pipeline: pipeline_id,
                    material_bind_group_index: None,
                    lightmap_slab: None,
                    slabs: MeshSlabs::default(),
                },
                Opaque3dBinKey {
                    asset_id: AssetId::<Mesh>::invalid().untyped(),
                },
                (*render_entity, *main_entity),
                InputUniformIndex::default(),
                BinnedRenderPhaseType::NonMesh,
            );
        }
    }
}

/// Queues the two grass draws into every shadow view's phase (each cascade
/// of a directional light, each face of a point light, each spot light)
/// when `GrassLook::cast_shadows` is on this frame, and takes them out of
/// them when it is off. The draws are not culled per light: the blades and
/// billboards drawn are the camera's (its drawn cells and their blend
/// bands), which lie within the field's bounds, so that the shadows fall
/// from the grass the camera sees and change where its levels of detail
/// do, as the grass does.
#[allow(clippy::too_many_arguments)]
pub fn queue_grass_shadows(
    pipeline_cache: Res<PipelineCache>,
    pipeline: Option<ResMut<GrassPipeline>>,
    prepass: Option<Res<PrepassPipeline>>,
    frame: Res<super::extract::GrassFrame>,
    mut phases: ResMut<ViewBinnedRenderPhases<Shadow>>,
    draw_functions: Res<DrawFunctions<Shadow>>,
    lights: Query<(&LightEntity, &ExtractedView)>,
    draws: Query<(Entity, &MainEntity, &GrassDraw)>,
) {
    let (Some(mut pipeline), Some(prepass)) = (pipeline, prepass) else {
        return;
    };
    let draw_shadow = draw_functions.read().id::<DrawGrassShadow>();
    for (light, view) in &lights {
        let Some(phase) = phases.get_mut(&view.retained_view_entity) else {
            continue;
        };
        let directional = matches!(light, LightEntity::Directional { .. });
        for (entity, &main_entity, &draw) in &draws {
            // Added anew each frame (the pipeline may differ): out first.
            phase.remove(main_entity);
            if !frame.cast_shadows || frame.layout.is_none() {
                continue;
            }
            let pipeline_id =
                match pipeline.shadow_pipeline(&pipeline_cache, &prepass, directional, draw) {
                    Ok(id) => id,
                    Err(e) => {
                        error!("bevy_trample: grass shadow pipeline: {e}");
                        continue;
                    }
                };
            phase.add(
                ShadowBatchSetKey {
                    pipeline: pipeline_id,
                    draw_function: draw_shadow,
                    material_bind_group_index: None,
                    slabs: MeshSlabs::default(),
                },
                ShadowBinKey {
                    asset_id: AssetId::<Mesh>::invalid().untyped(),
                },
                (entity, main_entity),
                InputUniformIndex::default(),
                BinnedRenderPhaseType::NonMesh,
            );
        }
    }
}
