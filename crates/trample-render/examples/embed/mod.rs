//! The host both embedding examples share (`embed_headless`,
//! `embed_window`), and the render crate's golden test of its frame: a
//! program with its own device, camera, render pass and depth buffer that
//! draws one unlit pure magenta (255, 0, 255) cube standing in the grass,
//! and lets trample draw the grass into that same pass
//! ([`trample_render::FieldRenderer`]). The cube is also a body of the
//! simulation, so the grass bends away from it and none grows through it.
//!
//! What a host does each frame ([`Host::frame`]):
//! 1. moves its cube ([`trample::Simulation::move_body`]) and hands its
//!    camera to the simulation ([`trample::Simulation::set_view`]), steps;
//! 2. `grass.prepare(…)` (uploads what the step changed);
//! 3. opens its pass (its colour and depth targets, cleared), draws the
//!    cube, then `grass.render(&mut pass)`; ends the pass and submits.

#![allow(dead_code)] // Each example uses a part.

use glam::{Mat4, Quat, Vec3};
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::{BodyId, HostView, Simulation};
use trample_render::{FieldRenderer, FrameCamera, Layers, RenderParams, TargetFormat};

/// Half the cube's side, metres (a 0.6 m cube).
pub const CUBE_HALF_M: f32 = 0.3;
/// The host's depth format.
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Vertical field of view of the host's camera, radians.
const FOV_Y: f32 = 0.9;
/// Simulation step, seconds.
pub const DT: f32 = 1.0 / 60.0;

/// The host's cube: its pipeline, vertices and model-view-projection uniform.
struct Cube {
    pipeline: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    uniform: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// The cube's shader: unlit, pure magenta.
const CUBE_WGSL: &str = r"
@group(0) @binding(0) var<uniform> mvp: mat4x4<f32>;
@vertex
fn vs_main(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> {
    return mvp * vec4<f32>(p, 1.0);
}
@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0, 0.0, 1.0, 1.0);
}
";

/// 36 vertices (12 triangles) of a cube of half side `h` round the origin.
fn cube_vertices(h: f32) -> Vec<[f32; 3]> {
    let mut out = Vec::with_capacity(36);
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            // Corners of the face at `sign` on `axis`.
            let corner = |u: f32, v: f32| {
                let mut p = [0.0; 3];
                p[axis] = sign * h;
                p[(axis + 1) % 3] = u * h;
                p[(axis + 2) % 3] = v * h;
                p
            };
            let (a, b, c, d) = (
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            );
            out.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    out
}

impl Cube {
    fn new(device: &wgpu::Device, target: &TargetFormat) -> Self {
        use wgpu::util::DeviceExt;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("host cube"),
            source: wgpu::ShaderSource::Wgsl(CUBE_WGSL.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("host cube"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("host cube"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("host cube"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                }],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: target.depth.map(|format| wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState {
                count: target.samples,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(target.color.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("host cube"),
            contents: bytemuck::cast_slice(&cube_vertices(CUBE_HALF_M)),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("host cube"),
            size: 64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("host cube"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        Self {
            pipeline,
            vertices,
            uniform,
            group,
        }
    }

    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.draw(0..36, 0..1);
    }
}

/// The host: its simulation (a 12.8 m square meadow and the cube as a
/// body), its cube, trample's grass renderer and its camera.
pub struct Host {
    /// The simulation the host steps.
    pub sim: Simulation,
    cube_id: BodyId,
    /// Where the cube stands (its centre), metres.
    pub cube_at: Vec3,
    /// Which way the cube faces: rotation about y, radians.
    pub cube_yaw: f32,
    cube: Cube,
    /// Trample's renderer, drawing into the host's pass.
    pub grass: FieldRenderer,
    /// Whether the frame has the grass (the test's frame without it shows
    /// how much of the cube the grass hides).
    pub draw_grass: bool,
    aspect: f32,
}

impl Host {
    /// A host drawing into passes of `target`'s formats, `width / height`
    /// = `aspect`.
    ///
    /// # Errors
    /// A field or renderer that cannot be made.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: TargetFormat,
        aspect: f32,
    ) -> Result<Self, Box<dyn std::error::Error>> {
        // 8 × 8 patches of 16 × 16 cells of 0.1 m (16,384 blades), blades
        // out to 8 m, billboards to 20 m.
        let mut sim = SimulationBuilder::new()
            .field(FieldParams {
                patches: [8, 8],
                cells_per_patch: 16,
                ..FieldParams::default()
            })
            .lod(LodParams {
                geometry_m: 8.0,
                billboard_m: 20.0,
            })
            .build()?;
        let cube_at = Vec3::new(0.0, CUBE_HALF_M, 0.0);
        let cube_id = sim.add_body(
            BodyBuilder::cuboid("cube", [CUBE_HALF_M; 3])
                .at(cube_at)
                .build()?,
        );
        // The host draws the cube itself: trample's objects layer is off.
        // The simulated blades alone (`near_density: 1`): the meadow's
        // denser near grass would hide most of the host's small cube from
        // this low camera, and the example is about sharing the frame.
        let params = RenderParams {
            layers: Layers {
                objects: false,
                ..Layers::default()
            },
            near_density: 1,
            ..RenderParams::default()
        };
        let grass = FieldRenderer::new(device, queue, &sim, target, params)?;
        Ok(Self {
            sim,
            cube_id,
            cube_at,
            cube_yaw: 0.0,
            cube: Cube::new(device, &target),
            grass,
            draw_grass: true,
            aspect,
        })
    }

    /// The host's camera: 2.6 m in front of the cube, a little above the
    /// grass, looking down at it over (and through) the grass.
    pub fn camera(&self) -> HostView {
        let target = self.cube_at + Vec3::new(0.0, -0.1, 0.0);
        let eye = self.cube_at + Vec3::new(0.5, 0.5, 2.6);
        HostView::look_at(eye, target, FOV_Y, self.aspect, 0.05, 300.0).expect("a valid lens")
    }

    /// A new width / height (a window was resized).
    pub fn set_aspect(&mut self, aspect: f32) {
        self.aspect = aspect;
    }

    /// One step of the host's world: the cube moves to `cube_at`
    /// (sweeping the grass on the way), the camera follows, the grass is
    /// simulated.
    ///
    /// # Errors
    /// A bad pose or step.
    pub fn step(&mut self) -> Result<(), Box<dyn std::error::Error>> {
        let rotation = Quat::from_rotation_y(self.cube_yaw);
        self.sim
            .move_body(self.cube_id, self.cube_at, rotation, DT)?;
        self.sim.set_view(self.camera())?;
        self.sim.step(DT)?;
        Ok(())
    }

    /// Records the frame into `encoder`: the host's pass on `color`
    /// (resolving into `resolve` under MSAA) and `depth`, both cleared,
    /// the cube drawn, then the grass into the same pass.
    pub fn frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        resolve: Option<&wgpu::TextureView>,
        depth: &wgpu::TextureView,
    ) {
        let view = self.camera();
        let model =
            Mat4::from_rotation_translation(Quat::from_rotation_y(self.cube_yaw), self.cube_at);
        queue.write_buffer(
            &self.cube.uniform,
            0,
            bytemuck::bytes_of(&(view.view_proj * model)),
        );
        let camera = FrameCamera::from(view);
        self.grass
            .prepare(device, queue, encoder, &self.sim, &camera);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
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
        self.cube.draw(&mut pass);
        if self.draw_grass {
            self.grass.render(&mut pass);
        }
    }
}

/// A render-attachment texture view of `format`, `samples` samples.
pub fn attachment(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    [width, height]: [u32; 2],
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: usage | wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    })
}

/// `wanted` MSAA samples if `adapter` renders and resolves them for
/// `color` and [`DEPTH`], else 1.
pub fn msaa(adapter: &wgpu::Adapter, color: wgpu::TextureFormat, wanted: u32) -> u32 {
    use wgpu::TextureFormatFeatureFlags as F;
    let c = adapter.get_texture_format_features(color).flags;
    let d = adapter.get_texture_format_features(DEPTH).flags;
    let ok = c.sample_count_supported(wanted)
        && c.contains(F::MULTISAMPLE_RESOLVE)
        && d.sample_count_supported(wanted);
    if ok { wanted } else { 1 }
}

/// The headless host's whole run: `steps` steps (the grass settles round
/// the cube), then one `width × height` frame read back (sRGB RGBA8),
/// with the grass drawn or not (`grass`).
///
/// # Errors
/// A failed step, renderer or read-back.
pub fn render_headless(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    adapter: &wgpu::Adapter,
    [width, height]: [u32; 2],
    steps: u32,
    grass: bool,
) -> Result<image::RgbaImage, Box<dyn std::error::Error>> {
    let color_format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let samples = msaa(adapter, color_format, 4);
    let target = TargetFormat {
        color: color_format,
        depth: Some(DEPTH),
        samples,
    };
    let mut host = Host::new(device, queue, target, width as f32 / height as f32)?;
    host.draw_grass = grass;
    for _ in 0..steps {
        host.step()?;
    }
    let size = [width, height];
    // The multisampled attachments are render attachments only: on GL a
    // multisampled texture that may also be sampled or copied does not
    // share a framebuffer with one that may not (nothing is drawn then).
    let only = wgpu::TextureUsages::empty();
    let copy = wgpu::TextureUsages::COPY_SRC;
    let resolved = attachment(device, "host colour", color_format, size, 1, copy);
    let msaa_view = (samples > 1).then(|| {
        attachment(
            device,
            "host colour (msaa)",
            color_format,
            size,
            samples,
            only,
        )
        .create_view(&Default::default())
    });
    let resolved_view = resolved.create_view(&Default::default());
    let depth = attachment(device, "host depth", DEPTH, size, samples, only)
        .create_view(&Default::default());
    let mut encoder = device.create_command_encoder(&Default::default());
    match &msaa_view {
        Some(m) => host.frame(device, queue, &mut encoder, m, Some(&resolved_view), &depth),
        None => host.frame(device, queue, &mut encoder, &resolved_view, None, &depth),
    }
    // Read back: rows padded to wgpu's copy alignment.
    let row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("host readback"),
        size: u64::from(row * height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    encoder.copy_texture_to_buffer(
        resolved.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(height),
            },
        },
        resolved.size(),
    );
    queue.submit([encoder.finish()]);
    let slice = readback.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely())?;
    rx.recv()??;
    let mut pixels = Vec::with_capacity((width * height * 4) as usize);
    {
        let data = slice.get_mapped_range();
        for r in data.chunks(row as usize) {
            pixels.extend_from_slice(&r[..(width * 4) as usize]);
        }
    }
    readback.unmap();
    image::RgbaImage::from_raw(width, height, pixels).ok_or_else(|| "short read-back".into())
}
