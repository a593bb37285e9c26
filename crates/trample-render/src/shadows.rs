//! The sun's shadow map (issue 15 item 3): a depth-only pass that draws the
//! bodies (every collider's mesh, posed: [`ObjectPass::draw_casters`]) as
//! the sun sees them, orthographic, into a square `Depth32Float` texture
//! around the eye. The blades, billboards, ground and bodies sample it
//! (`sun_visibility` in `globals.wgsl`, 2×2 PCF through a linear comparison
//! sampler; the blades and billboards per vertex, the ground and bodies per
//! fragment): in a body's shadow only the sky's ambient light is left.
//! Grass does not cast (the grass's own darkening is its ambient occlusion,
//! `grass_ao`).
//!
//! The pass is recorded by [`crate::FieldRenderer::prepare`] (and
//! `prepare_gpu`) into the host's encoder, before the host's pass: the
//! middleware's `render` only records draws into the pass the host opened.

use crate::globals::shader_module;
use crate::objects::ObjectPass;
use crate::params::RenderParams;
use crate::terrain::GroundVertex;
use glam::camera::rh::{proj::directx::orthographic, view::look_to_mat4};
use glam::{Mat4, Vec3};

/// Format of the shadow map.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Metres of the light's depth range on either side of the eye: bodies up
/// to this far above (along the sun) or below the eye cast.
pub const DEPTH_RANGE_M: f32 = 250.0;

/// The shadow map, its pipeline and what the receivers bind.
pub struct ShadowPass {
    /// `None` when shadows are off (a 1×1 map is bound, never sampled).
    pipeline: Option<wgpu::RenderPipeline>,
    /// Group 0 of the casters' pipeline: the globals alone (the frame's
    /// group 0 also binds the map, which the pass writes).
    globals_group: wgpu::BindGroup,
    view: wgpu::TextureView,
    sampler: wgpu::Sampler,
    size: u32,
}

/// Group-0 layout entries of the map and its comparison sampler (bindings
/// 1 and 2; vertex and fragment stages: blades and billboards look up
/// per vertex), beside the globals at binding 0.
#[must_use]
pub fn layout_entries() -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        wgpu::BindGroupLayoutEntry {
            binding: 1,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: 2,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            count: None,
        },
    ]
}

impl ShadowPass {
    /// The map (`params.shadow_map_size`² when `params.shadow_strength > 0`,
    /// else 1×1 and no pipeline) and the casters' pipeline, whose group 1
    /// is the objects' (`objects`).
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::Buffer,
        objects: &wgpu::BindGroupLayout,
        params: &RenderParams,
    ) -> Self {
        let on = params.shadow_strength > 0.0;
        let max = device.limits().max_texture_dimension_2d;
        let size = if on {
            params.shadow_map_size.clamp(16, max)
        } else {
            1
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow casters globals"),
            entries: &[crate::pipeline::vertex_uniform(0)],
        });
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow casters globals"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let pipeline = on.then(|| casters_pipeline(device, &layout, objects));
        Self {
            pipeline,
            globals_group,
            view,
            sampler,
            size,
        }
    }

    /// Whether the pass draws (shadows on).
    #[must_use]
    pub fn enabled(&self) -> bool {
        self.pipeline.is_some()
    }

    /// The map's side, texels (1 when shadows are off).
    #[must_use]
    pub fn size(&self) -> u32 {
        self.size
    }

    /// Group-0 entries binding the map and its sampler ([`layout_entries`]).
    #[must_use]
    pub fn bind_entries(&self) -> [wgpu::BindGroupEntry<'_>; 2] {
        [
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&self.view),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&self.sampler),
            },
        ]
    }

    /// Records the shadow pass into `encoder`: the map cleared to the far
    /// plane, the bodies drawn into it with the globals' `light_view_proj`
    /// (written before the encoder is submitted). Nothing when shadows are
    /// off.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, objects: &ObjectPass) {
        let Some(pipeline) = &self.pipeline else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow map"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.globals_group, &[]);
        objects.draw_casters(&mut pass);
    }
}

/// Depth-only pipeline of the casters: positions only, both faces, a
/// slope-scaled bias against self-shadowing acne on the bodies.
fn casters_pipeline(
    device: &wgpu::Device,
    globals: &wgpu::BindGroupLayout,
    objects: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let module = shader_module(device, "shadows.wgsl", include_str!("shadows.wgsl"));
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow casters"),
        bind_group_layouts: &[Some(globals), Some(objects)],
        immediate_size: 0,
    });
    let attributes = wgpu::vertex_attr_array![0 => Float32x3];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow casters"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<GroundVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &attributes,
            }],
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 2.0,
                clamp: 0.0,
            },
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: None,
        multiview_mask: None,
        cache: None,
    })
}

/// The sun's world → shadow-clip matrix for a frame seen from `eye`: an
/// orthographic box looking along `-sun` (unit, towards the sun), `2 ·
/// radius_m` square around the eye, ±[`DEPTH_RANGE_M`] deep; its centre
/// snapped to whole texels of a `size`² map, so that the shadows' edges
/// stand still as the eye moves. Returns the matrix and the depth (clip z)
/// of one metre along the sun.
#[must_use]
pub fn light_view_proj(sun: Vec3, eye: Vec3, radius_m: f32, size: u32) -> (Mat4, f32) {
    let sun = sun.normalize_or(Vec3::Y);
    let up = if sun.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    // The light's view from the origin; the box is moved to the eye in the
    // projection, in light-space units (metres).
    let view = look_to_mat4(Vec3::ZERO, -sun, up);
    let e = view.transform_point3(eye);
    let texel = 2.0 * radius_m / size.max(1) as f32;
    let (x, y) = ((e.x / texel).round() * texel, (e.y / texel).round() * texel);
    // Looking down -z: the eye is at depth -e.z.
    let (near, far) = (-e.z - DEPTH_RANGE_M, -e.z + DEPTH_RANGE_M);
    let proj = orthographic(
        x - radius_m,
        x + radius_m,
        y - radius_m,
        y + radius_m,
        near,
        far,
    );
    (proj * view, 1.0 / (far - near))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_eye_is_in_the_middle_of_the_map_and_the_sun_nearer() {
        let sun = Vec3::new(-0.35, 0.75, 0.55).normalize();
        let eye = Vec3::new(3.0, 1.7, -4.0);
        let (m, per_m) = light_view_proj(sun, eye, 30.0, 2048);
        let c = m.project_point3(eye);
        assert!(c.x.abs() < 1e-3 && c.y.abs() < 1e-3, "{c}");
        assert!((c.z - 0.5).abs() < 1e-4, "{c}");
        // A point towards the sun is nearer the light (smaller depth).
        let up = m.project_point3(eye + sun * 2.0);
        assert!((c.z - up.z - 2.0 * per_m).abs() < 1e-5, "{} {}", c.z, up.z);
        // The corners of the square are at the map's edges.
        assert!(m.project_point3(eye + Vec3::new(100.0, 0.0, 0.0)).x > 1.0);
    }
}
