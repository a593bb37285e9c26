//! The grass's render pipelines: Bevy's mesh pipeline specialised for the
//! view (its view bindings, lights, shadows, fog, tonemapping, formats,
//! MSAA and depth: the shader defs and targets Bevy's own meshes get), with
//! `blades.wgsl` for shaders, no vertex buffers (vertices are pulled from
//! the storage buffers of group 2) and no back-face culling (blades and
//! billboards are seen from both sides).
//!
//! The shadow pipelines (`GrassLook::cast_shadows`) draw the same vertex
//! stages into a light's shadow map, depth only (the billboards' strands
//! cut out of their quads by a fragment stage), with Bevy's prepass view
//! bindings (the light's view) in group 0, as Bevy's own shadow casters
//! are drawn.

use super::GrassDraw;
use bevy::asset::{AssetServer, load_embedded_asset};
use bevy::core_pipeline::core_3d::CORE_3D_DEPTH_FORMAT;
use bevy::mesh::{Mesh, MeshVertexBufferLayouts, PrimitiveTopology};
use bevy::pbr::{MeshPipeline, MeshPipelineKey, PrepassPipeline};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::binding_types::{
    storage_buffer_read_only_sized, uniform_buffer_sized,
};
use bevy::render::render_resource::{
    BindGroupLayoutDescriptor, BindGroupLayoutEntries, CachedRenderPipelineId, CompareFunction,
    DepthBiasState, DepthStencilState, MultisampleState, PipelineCache, ShaderStages,
    SpecializedMeshPipeline, SpecializedMeshPipelineError, StencilState,
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
    /// The shadow pipelines made so far, per draw: for directional
    /// lights' views (`true`: orthographic, depth unclipped) and for the
    /// others.
    pub shadow_cache: HashMap<(bool, GrassDraw), CachedRenderPipelineId>,
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
        shadow_cache: HashMap::default(),
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

    /// The pipeline of `draw` for a light's shadow view (`directional`: a
    /// cascade of a directional light, else a point or spot light's face),
    /// queued for creation the first time it is asked for: the draw's
    /// vertex stage; no fragment stage for the blades, for the billboards
    /// one that keeps only their strands (`billboard_shadow_fragment`: the
    /// cut-out of their colour pass, no colour); Bevy's shadow depth
    /// (reverse Z, `GreaterEqual`, no bias: Bevy biases when it samples),
    /// group 0 the prepass's view bindings, group 1 its empty group, group
    /// 2 the grass's. A directional light's casters nearer to it than its
    /// cascade's near plane still cast (unclipped depth where the device
    /// has it, else the depth clamped in the vertex stage,
    /// `SHADOW_CLAMP_ORTHO`), as Bevy does for its meshes.
    ///
    /// # Errors
    /// The mesh pipeline's own error for a key it cannot specialise.
    pub fn shadow_pipeline(
        &mut self,
        cache: &PipelineCache,
        prepass: &PrepassPipeline,
        directional: bool,
        draw: GrassDraw,
    ) -> Result<CachedRenderPipelineId, SpecializedMeshPipelineError> {
        if let Some(&id) = self.shadow_cache.get(&(directional, draw)) {
            return Ok(id);
        }
        let projection = if directional {
            MeshPipelineKey::VIEW_PROJECTION_ORTHOGRAPHIC
        } else {
            MeshPipelineKey::VIEW_PROJECTION_PERSPECTIVE
        };
        let key = MeshPipelineKey::DEPTH_PREPASS
            | projection
            | MeshPipelineKey::from_primitive_topology_and_strip_index(
                PrimitiveTopology::TriangleList,
                None,
            );
        // The mesh pipeline's descriptor gives the shader defs its view
        // bindings need; the vertex stages read only `view` of group 0,
        // which the prepass's view layout binds the same way.
        let mut d = self.mesh_pipeline.specialize(key, &self.vertex_layout)?;
        let (label, vertex, fragment) = match draw {
            GrassDraw::Blades => ("trample blades shadow", "blade_vertex", None),
            GrassDraw::Billboards => (
                "trample billboards shadow",
                "billboard_vertex",
                Some("billboard_shadow_fragment"),
            ),
        };
        d.label = Some(label.into());
        d.vertex.shader = self.shader.clone();
        d.vertex.entry_point = Some(vertex.into());
        d.vertex.buffers.clear();
        let unclipped = directional && prepass.depth_clip_control_supported;
        if directional && !unclipped {
            d.vertex.shader_defs.push("SHADOW_CLAMP_ORTHO".into());
        }
        d.fragment = match (fragment, d.fragment.take()) {
            (Some(entry), Some(mut f)) => {
                f.shader = self.shader.clone();
                f.shader_defs.clone_from(&d.vertex.shader_defs);
                f.entry_point = Some(entry.into());
                f.targets.clear();
                Some(f)
            }
            _ => None,
        };
        d.layout = vec![
            prepass.view_layout_no_motion_vectors.clone(),
            prepass.empty_layout.clone(),
            self.grass_layout.clone(),
        ];
        d.primitive.cull_mode = None;
        d.primitive.unclipped_depth = unclipped;
        d.depth_stencil = Some(DepthStencilState {
            format: CORE_3D_DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(CompareFunction::GreaterEqual),
            stencil: StencilState::default(),
            bias: DepthBiasState::default(),
        });
        d.multisample = MultisampleState::default();
        let id = cache.queue_render_pipeline(d);
        self.shadow_cache.insert((directional, draw), id);
        Ok(id)
    }
}
