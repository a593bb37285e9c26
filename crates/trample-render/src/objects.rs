//! Objects: each collider's mesh (a body's own, then its parts', see
//! `trample::step::Body::colliders`) uploaded once (flat normals, triangles
//! unshared), drawn with its pose each frame; an animated body's mesh is
//! uploaded again every frame (its posed vertices).

use crate::globals::shader_module;
use crate::terrain::GroundVertex;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};
use trample::Simulation;

/// Per-object uniform. Layout-compatible with `Object` in objects.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ObjectUniform {
    /// Local → world (the body's pose).
    pub model: Mat4,
    /// rgb base colour (linear), w checker cells per metre (0 = plain).
    pub color: Vec4,
}

const _: () = assert!(std::mem::size_of::<ObjectUniform>() == 80);

/// Colours given to objects in scene order (linear RGB).
const PALETTE: [Vec3; 4] = [
    Vec3::new(0.75, 0.08, 0.05),
    Vec3::new(0.10, 0.25, 0.75),
    Vec3::new(0.80, 0.60, 0.10),
    Vec3::new(0.60, 0.60, 0.65),
];

struct Drawn {
    /// The body's stable id (the drawn list is made again when the ids change).
    id: trample::BodyId,
    /// Index of the body in `sim.bodies` and of the collider in the body.
    body: usize,
    collider: usize,
    vertices: wgpu::Buffer,
    count: u32,
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// The object pass: one vertex buffer and one uniform per collider (a
/// body's own mesh, then its parts'), made again when the simulation's
/// bodies change (a host adds or removes one).
pub struct ObjectPass {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    objects: Vec<Drawn>,
}

/// Flat-shaded triangle list of a mesh: three vertices per triangle, each
/// with the triangle's normal.
#[must_use]
pub fn flat_vertices(mesh: &trample::object::TriMesh) -> Vec<GroundVertex> {
    let mut out = Vec::with_capacity(mesh.indices.len() * 3);
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.triangle(t);
        let n = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for p in [a, b, c] {
            out.push(GroundVertex {
                position: p.to_array(),
                normal: n.to_array(),
            });
        }
    }
    out
}

impl ObjectPass {
    /// Uploads every collider's mesh of `sim`.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        sim: &Simulation,
        target: &crate::TargetFormat,
    ) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("object"),
            entries: &[crate::pipeline::uniform(
                0,
                wgpu::ShaderStages::VERTEX_FRAGMENT,
            )],
        });
        let objects = upload_bodies(device, &layout, sim);
        let module = shader_module(device, "objects.wgsl", include_str!("objects.wgsl"));
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "objects",
                module: &module,
                layouts: &[globals, &layout],
                buffers: &[wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<GroundVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                }],
                topology: wgpu::PrimitiveTopology::TriangleList,
                // Meshes may be open or wound either way: draw both sides.
                cull: None,
                depth: crate::pipeline::DepthUse::Write,
                target,
                alpha_to_coverage: false,
            },
        );
        Self {
            pipeline,
            layout,
            objects,
        }
    }

    /// Writes each collider's current pose and an animated body's posed
    /// vertices (uploading the meshes again when the bodies are not those
    /// of the last frame); returns the bytes written.
    pub fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, sim: &Simulation) -> u64 {
        let ids = |objects: &[Drawn]| {
            let mut ids: Vec<trample::BodyId> = objects.iter().map(|o| o.id).collect();
            ids.dedup();
            ids
        };
        let same = ids(&self.objects)
            .iter()
            .eq(sim.bodies.iter().map(|b| &b.id))
            && self.objects.len() == sim.bodies.iter().map(|b| b.collider_count()).sum::<usize>();
        if !same {
            self.objects = upload_bodies(device, &self.layout, sim);
        }
        let mut bytes = 0u64;
        for drawn in &self.objects {
            let Some(body) = sim.bodies.get(drawn.body) else {
                continue;
            };
            if drawn.collider >= body.collider_count() {
                continue;
            }
            let c = body.collider(drawn.collider);
            if drawn.collider == 0 && body.object.animated.is_some() {
                let verts = flat_vertices(c.mesh);
                if verts.len() as u32 == drawn.count {
                    queue.write_buffer(&drawn.vertices, 0, bytemuck::cast_slice(&verts));
                    bytes += std::mem::size_of_val(verts.as_slice()) as u64;
                }
            }
            let model = Mat4::from_rotation_translation(c.pose.rotation, c.pose.position);
            let (lo, hi) = body.object.mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ONE));
            // About six checker cells across the object (its body).
            let checker = 6.0 / (hi - lo).max_element().max(1e-3);
            let u = ObjectUniform {
                model,
                color: PALETTE[drawn.body % PALETTE.len()].extend(checker),
            };
            queue.write_buffer(&drawn.uniform, 0, bytemuck::bytes_of(&u));
        }
        bytes + (self.objects.len() * std::mem::size_of::<ObjectUniform>()) as u64
    }

    /// The layout of each collider's group 1 (its uniform).
    #[must_use]
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// Records every collider's triangles into `pass` with the pipeline
    /// and group 0 the caller set (the shadow map's casters,
    /// `shadows.rs`): group 1 and the vertex buffer per collider.
    pub fn draw_casters(&self, pass: &mut wgpu::RenderPass<'_>) {
        for o in &self.objects {
            pass.set_bind_group(1, &o.bind_group, &[]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.draw(0..o.count, 0..1);
        }
    }

    /// Records the draws into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        self.draw_casters(pass);
    }
}

/// Each collider's mesh of `sim` (a body's own, then its parts') in a
/// vertex buffer, with its uniform.
fn upload_bodies(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    sim: &Simulation,
) -> Vec<Drawn> {
    use wgpu::util::DeviceExt;
    sim.bodies
        .iter()
        .enumerate()
        .flat_map(|(i, body)| (0..body.collider_count()).map(move |k| (i, k, body)))
        .map(|(i, k, body)| {
            let verts = flat_vertices(body.collider(k).mesh);
            let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&body.object.name),
                contents: bytemuck::cast_slice(&verts),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            });
            let uniform = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&body.object.name),
                size: std::mem::size_of::<ObjectUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&body.object.name),
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                }],
            });
            Drawn {
                id: body.id,
                body: i,
                collider: k,
                vertices,
                count: verts.len() as u32,
                uniform,
                bind_group,
            }
        })
        .collect()
}
