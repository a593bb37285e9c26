//! The grass's render pipelines: Bevy's mesh pipeline specialised for the
//! view (its view bindings, lights, shadows, fog, tonemapping, formats,
//! MSAA and depth: the shader defs and targets Bevy's own meshes get), with
//! `blades.wgsl` for shaders, no vertex buffers (vertices are pulled from
//! the storage buffers of group 2) and no back-face culling (blades and
//! billboards are seen from both sides).

use super::GrassDraw;
use bevy::asset::{AssetServer, load_embedded_asset};
use bevy::mesh::{Mesh, MeshVertexBufferLayouts, PrimitiveTopology};
use bevy::pbr::{MeshPipeline, MeshPipelineKey};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{
    storage_buffer_read_only_sized, uniform_buffer_sized,
};
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, BindGroupLayoutEntries, CachedRenderPipelineId, PipelineCache,
    ShaderStages, SpecializedMeshPipeline,
};

/// What the grass pipelines are made from (render world).
#[derive(Resource)]
pub struct GrassPipeline {
    /// Bevy's mesh pipeline: view layouts and the shader defs of a view.
    pub mesh_pipeline: MeshPipeline,
    /// `blades.wgsl`.
    pub shader: Handle<Shader>,
    /// Group 2: blade vertices, blade shape, drawn cells, parameters,
    /// billboards, the blades' chunk.
    pub grass_layout: BindGroupLayoutDescriptor,
    /// A vertex layout with positions only, to ask the mesh pipeline for
    /// its descriptor (the grass itself has no vertex buffer).
    vertex_layout: bevy::mesh::MeshVertexBufferLayoutRef,
    /// Pipelines made so far, per view key and draw.
    pub cache: HashMap<(MeshPipelineKey, GrassDraw), CachedRenderPipelineId>,
}

/// Makes the [`GrassPipeline`] once Bevy's mesh pipeline exists.
pub fn init_grass_pipeline(
    mut commands: Commands,
    mesh_pipeline: Res<MeshPipeline>,
    asset_server: Res<AssetServer>,
    mut layouts: ResMut<MeshVertexBufferLayouts>,
) {
    let grass_layout = BindGroupLayoutDescriptor::new(
        "trample grass",
        &BindGroupLayoutEntries::sequential(
            ShaderStages::VERTEX_FRAGMENT,
            (
                storage_buffer_read_only_sized(false, None),
                storage_buffer_read_only_sized(false, None),
                storage_buffer_read_only_sized(false, None),
                uniform_buffer_sized(false, None),
                storage_buffer_read_only_sized(false, None),
                uniform_buffer_sized(false, None),
            ),
        ),
    );
    let positions_only = Mesh::new(
        PrimitiveTopology::TriangleList,
        bevy::asset::RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; 3]);
    commands.insert_resource(GrassPipeline {
        mesh_pipeline: mesh_pipeline.clone(),
        shader: load_embedded_asset!(asset_server.as_ref(), "blades.wgsl"),
        grass_layout,
        vertex_layout: positions_only.get_mesh_vertex_buffer_layout(&mut layouts),
        cache: HashMap::default(),
    });
}

impl GrassPipeline {
    /// The pipeline for `draw` in a view whose mesh pipeline key is
    /// `view_key`, queued for creation the first time it is asked for.
    ///
    /// # Errors
    /// The mesh pipeline's own error for a key it cannot specialise.
    pub fn pipeline(
        &mut self,
        cache: &PipelineCache,
        view_key: MeshPipelineKey,
        draw: GrassDraw,
    ) -> Result<CachedRenderPipelineId, bevy::render::render_resource::SpecializedMeshPipelineError>
    {
        let key = view_key
            | MeshPipelineKey::from_primitive_topology_and_strip_index(
                PrimitiveTopology::TriangleList,
                None,
            );
        if let Some(&id) = self.cache.get(&(key, draw)) {
            return Ok(id);
        }
        let mut d = self.mesh_pipeline.specialize(key, &self.vertex_layout)?;
        d.label = Some(
            match draw {
                GrassDraw::Blades => "trample blades",
                GrassDraw::Billboards => "trample billboards",
            }
            .into(),
        );
        d.vertex.shader = self.shader.clone();
        d.vertex.entry_point = Some(
            match draw {
                GrassDraw::Blades => "blade_vertex",
                GrassDraw::Billboards => "billboard_vertex",
            }
            .into(),
        );
        d.vertex.buffers.clear();
        if let Some(f) = d.fragment.as_mut() {
            f.shader = self.shader.clone();
            f.entry_point = Some(
                match draw {
                    GrassDraw::Blades => "blade_fragment",
                    GrassDraw::Billboards => "billboard_fragment",
                }
                .into(),
            );
        }
        // Groups 0 and 1 are the view's; group 2 is the grass's (in place
        // of the mesh's).
        d.layout.truncate(2);
        d.layout.push(self.grass_layout.clone());
        d.primitive.cull_mode = None;
        let id = cache.queue_render_pipeline(d);
        self.cache.insert((key, draw), id);
        Ok(id)
    }
}
