//! Debug lines (DESIGN §8 debug views): the OBB-tree nodes each object is
//! tested against at the current precision, and the patch grid. Line
//! vertices are built on the CPU each frame (a few thousand at most) and
//! drawn over the scene without a depth test, so hidden boxes show too.

use crate::globals::shader_module;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use trample::Simulation;
use trample::obb::ObbTree;

/// One end of a line. Layout-compatible with `VertexIn` in lines.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LineVertex {
    /// World position, metres.
    pub position: [f32; 3],
    /// Linear RGB.
    pub color: [f32; 3],
}

const _: () = assert!(std::mem::size_of::<LineVertex>() == 24);

/// The 12 edges of a box as pairs of corner indices of
/// [`trample::obb::Obb::corners`] (bit 0: u, bit 1: v, bit 2: w).
const BOX_EDGES: [(usize, usize); 12] = [
    (0, 1),
    (2, 3),
    (4, 5),
    (6, 7),
    (0, 2),
    (1, 3),
    (4, 6),
    (5, 7),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// Colour of the OBB nodes at the precision (yellow), of leaves above it
/// (orange: their branch ends there).
const NODE_COLOUR: [f32; 3] = [1.0, 0.85, 0.1];
const LEAF_COLOUR: [f32; 3] = [1.0, 0.45, 0.05];
/// Patch borders (white) and cell lines (grey).
const PATCH_COLOUR: [f32; 3] = [1.0, 1.0, 1.0];
const CELL_COLOUR: [f32; 3] = [0.35, 0.35, 0.35];
/// Lines over the ground are lifted by this much, metres, so they are not
/// lost in it.
const LIFT_M: f32 = 0.02;
/// Cell lines are drawn only while the grid has at most this many cells per
/// side (beyond, they would fill the picture).
const MAX_CELL_LINES: u32 = 256;

/// The boxes of `tree` that a test at `precision` ends on: the nodes at depth
/// `precision` and the leaves above it (paper §4.2: the tree is walked down to
/// depth `precision`), posed by `model`, as line-list vertices.
pub fn obb_lines(tree: &ObbTree, precision: u32, model: Mat4, out: &mut Vec<LineVertex>) {
    for node in &tree.nodes {
        let at_precision = node.depth == precision;
        let leaf_above = node.is_leaf() && node.depth < precision;
        if !(at_precision || leaf_above) {
            continue;
        }
        let color = if at_precision {
            NODE_COLOUR
        } else {
            LEAF_COLOUR
        };
        let c = node.obb.corners().map(|p| model.transform_point3(p));
        for (a, b) in BOX_EDGES {
            out.push(LineVertex {
                position: c[a].to_array(),
                color,
            });
            out.push(LineVertex {
                position: c[b].to_array(),
                color,
            });
        }
    }
}

/// The patch grid of `sim`'s field (patch borders white, cell lines grey
/// while the grid is small enough), following the terrain, as line-list
/// vertices.
pub fn patch_grid_lines(sim: &Simulation, out: &mut Vec<LineVertex>) {
    let layout = &sim.field.layout;
    let terrain = &sim.field.terrain;
    let [gx, gz] = layout.grid_size();
    let cpp = layout.cells_per_patch.max(1);
    let s = layout.cell_size;
    let [x0, z0] = layout.origin;
    let cells = gx.max(gz) <= MAX_CELL_LINES;
    let at = |x: f32, z: f32| Vec3::new(x, terrain.height_at(x, z) + LIFT_M, z);
    let mut segment = |a: Vec3, b: Vec3, color| {
        out.push(LineVertex {
            position: a.to_array(),
            color,
        });
        out.push(LineVertex {
            position: b.to_array(),
            color,
        });
    };
    // Lines of constant x (i = 0..=gx), one piece per cell so they follow
    // the ground; then lines of constant z.
    for i in 0..=gx {
        let border = i % cpp == 0;
        if !border && !cells {
            continue;
        }
        let color = if border { PATCH_COLOUR } else { CELL_COLOUR };
        let x = x0 + i as f32 * s;
        for j in 0..gz {
            let (za, zb) = (z0 + j as f32 * s, z0 + (j + 1) as f32 * s);
            segment(at(x, za), at(x, zb), color);
        }
    }
    for j in 0..=gz {
        let border = j % cpp == 0;
        if !border && !cells {
            continue;
        }
        let color = if border { PATCH_COLOUR } else { CELL_COLOUR };
        let z = z0 + j as f32 * s;
        for i in 0..gx {
            let (xa, xb) = (x0 + i as f32 * s, x0 + (i + 1) as f32 * s);
            segment(at(xa, z), at(xb, z), color);
        }
    }
}

/// The debug-line pass: a vertex buffer grown as needed, rewritten each frame.
pub struct LinePass {
    pipeline: wgpu::RenderPipeline,
    vertices: Option<wgpu::Buffer>,
    count: u32,
    scratch: Vec<LineVertex>,
}

impl LinePass {
    /// Builds the pipeline.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        target: &crate::TargetFormat,
    ) -> Self {
        let module = shader_module(device, "lines.wgsl", include_str!("lines.wgsl"));
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "debug lines",
                module: &module,
                layouts: &[globals],
                buffers: &[wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &attributes,
                }],
                topology: wgpu::PrimitiveTopology::LineList,
                cull: None,
                // Over everything: a debug view shows the hidden boxes too.
                depth: crate::pipeline::DepthUse::Ignore,
                target,
                alpha_to_coverage: false,
            },
        );
        Self {
            pipeline,
            vertices: None,
            count: 0,
            scratch: Vec::new(),
        }
    }

    /// Builds this frame's lines: OBB nodes when `obb`, the patch grid when
    /// `grid`. Returns the bytes written.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        obb: bool,
        grid: bool,
    ) -> u64 {
        self.scratch.clear();
        if obb {
            for c in sim.bodies.iter().flat_map(trample::Body::colliders) {
                let model = Mat4::from_rotation_translation(c.pose.rotation, c.pose.position);
                obb_lines(c.tree, sim.params.precision, model, &mut self.scratch);
            }
        }
        if grid {
            patch_grid_lines(sim, &mut self.scratch);
        }
        self.count = self.scratch.len() as u32;
        if self.scratch.is_empty() {
            return 0;
        }
        let bytes: &[u8] = bytemuck::cast_slice(&self.scratch);
        if let Some(b) = crate::pipeline::grown(
            device,
            self.vertices.as_ref(),
            "debug lines",
            wgpu::BufferUsages::VERTEX,
            bytes.len() as u64,
        ) {
            self.vertices = Some(b);
        }
        if let Some(b) = &self.vertices {
            queue.write_buffer(b, 0, bytes);
        }
        bytes.len() as u64
    }

    /// Lines drawn by the last [`LinePass::prepare`].
    #[must_use]
    pub fn drawn(&self) -> usize {
        self.count as usize / 2
    }

    /// Records the draw into `pass` (nothing when there are no lines).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if let (Some(b), true) = (&self.vertices, self.count > 0) {
            pass.set_pipeline(&self.pipeline);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..self.count, 0..1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obb_lines_draw_the_nodes_at_the_precision_and_leaves_above_it() {
        let mesh = trample::object::shapes::sphere(1.0, 2);
        let tree = ObbTree::build(&mesh, 8);
        for precision in 1..=4 {
            let mut v = Vec::new();
            obb_lines(&tree, precision, Mat4::IDENTITY, &mut v);
            let expected = tree
                .nodes
                .iter()
                .filter(|n| n.depth == precision || (n.is_leaf() && n.depth < precision))
                .count();
            assert_eq!(v.len(), expected * 24, "precision {precision}");
            if precision == 1 {
                assert_eq!(expected, 1, "the root alone at precision 1");
            }
        }
    }

    #[test]
    fn obb_lines_follow_the_pose() {
        let mesh = trample::object::shapes::sphere(1.0, 1);
        let tree = ObbTree::build(&mesh, 4);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        obb_lines(&tree, 1, Mat4::IDENTITY, &mut a);
        obb_lines(&tree, 1, Mat4::from_translation(Vec3::X * 5.0), &mut b);
        for (p, q) in a.iter().zip(&b) {
            let d = Vec3::from(q.position) - Vec3::from(p.position);
            assert!((d - Vec3::X * 5.0).length() < 1e-5);
        }
    }
}
