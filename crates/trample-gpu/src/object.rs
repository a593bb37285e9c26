//! One object on the GPU: its OBB tree (paper §4.2's HBV, built once on the
//! CPU by `trample::obb::ObbTree::build`: the paper's off-line stage)
//! flattened into storage buffers, its triangles and inside-voxel grid (for
//! the inside test of closed meshes), and a uniform with its pose.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use trample::obb::{EQN_EPSILON, ObbTree};
use trample::object::Pose;
use wgpu::util::DeviceExt;

use crate::error::GpuError;

/// One OBB tree node. Layout-compatible with `Node` in `narrow_phase.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuNode {
    /// Centre C (w unused).
    pub center: [f32; 4],
    /// Axis u (w unused).
    pub axis_u: [f32; 4],
    /// Axis v (w unused).
    pub axis_v: [f32; 4],
    /// Axis w (w unused).
    pub axis_w: [f32; 4],
    /// Half extents (hu, hv, hw) (w unused).
    pub half: [f32; 4],
    /// xyz: Eq. 3's EqN normalised when w = 1; else the node's fallback
    /// axis (see `ObbTree::eqn_direction`), w = 0.
    pub dir: [f32; 4],
    /// Left child, right child (`NO_CHILD` for a leaf), first triangle, triangle count.
    pub children: [u32; 4],
    /// Centre of the node's reach box (`trample::obb::reach`: the node's
    /// axes, holding its box and every descendant's) (w unused).
    pub reach_center: [f32; 4],
    /// Half extents of the reach box (w unused).
    pub reach_half: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuNode>() == 144);

/// An object's pose and tree header. Layout-compatible with `ObjectParams`
/// in `narrow_phase.wgsl` (uniform).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuObjectParams {
    /// World position of the local origin (w unused).
    pub position: [f32; 4],
    /// World-from-local rotation, quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Linear velocity, m/s.
    pub velocity: [f32; 4],
    /// Angular velocity, rad/s, world frame.
    pub angular_velocity: [f32; 4],
    /// Inside-grid box: centre, axes, half extents (zero without a grid).
    pub grid_center: [f32; 4],
    /// Inside-grid axis u.
    pub grid_u: [f32; 4],
    /// Inside-grid axis v.
    pub grid_v: [f32; 4],
    /// Inside-grid axis w.
    pub grid_w: [f32; 4],
    /// Inside-grid half extents.
    pub grid_half: [f32; 4],
    /// Node count, closed (1) or open (0), final depth (precision), 1 for
    /// the first object of a step (its dispatch overwrites the forces).
    pub tree: [u32; 4],
    /// Blade count, segments per blade, blades per cell, inside-grid side (0: none).
    pub field: [u32; 4],
    /// The velocity in the object's frame (`LocalMotion::velocity`), and its
    /// thickness (`LocalMotion::thickness`, m) in w.
    pub local_velocity: [f32; 4],
    /// The angular velocity in the object's frame, and the sub-step h (s) in w.
    pub local_angular: [f32; 4],
    /// Contact shell (m), press (the Eq. 2 factor of its `track`), unused ×2.
    pub contact: [f32; 4],
    /// 1 + the object's index (its track owner id; 0 past 254), track
    /// everywhere (1) or the paper's geometric cells only (0), unused ×2.
    pub extra: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuObjectParams>() == 240);

fn v4(v: Vec3) -> [f32; 4] {
    [v.x, v.y, v.z, 0.0]
}

/// Flattens `tree` into [`GpuNode`]s (same indices as `tree.nodes`).
#[must_use]
pub fn flatten_nodes(tree: &ObbTree) -> Vec<GpuNode> {
    (0..tree.nodes.len())
        .map(|i| {
            let n = &tree.nodes[i];
            let len = n.eqn.length();
            let valid = len >= EQN_EPSILON && len.is_finite();
            // With p0 = p1 = centre the fallback is the smallest axis; with a
            // valid EqN it is EqN / |EqN|, computed by the core itself.
            let c = n.obb.center;
            let d = tree.eqn_direction(i as u32, c, c);
            let reach = tree.reach.get(i).copied().unwrap_or(n.obb);
            GpuNode {
                center: v4(c),
                axis_u: v4(n.obb.axes[0]),
                axis_v: v4(n.obb.axes[1]),
                axis_w: v4(n.obb.axes[2]),
                half: v4(n.obb.half),
                dir: [d.x, d.y, d.z, if valid { 1.0 } else { 0.0 }],
                children: [n.children[0], n.children[1], n.first_tri, n.tri_count],
                reach_center: v4(reach.center),
                reach_half: v4(reach.half),
            }
        })
        .collect()
}

/// An object's tree, triangles and voxel grid in GPU buffers, and its
/// uniform. Build once per mesh; [`GpuObject::set_pose`] every step.
pub struct GpuObject {
    pub(crate) params: GpuObjectParams,
    pub(crate) uniform: wgpu::Buffer,
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) triangles: wgpu::Buffer,
    pub(crate) voxels: wgpu::Buffer,
}

impl GpuObject {
    /// Whether `tree`'s buffers (nodes, triangles, inside-test voxels) each
    /// fit one storage binding of `device`; checked before anything is
    /// allocated.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] naming the buffer.
    pub fn fits(device: &wgpu::Device, tree: &ObbTree) -> Result<(), GpuError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        let voxels = tree
            .inside
            .as_ref()
            .filter(|_| tree.closed)
            .map_or(1, |g| g.voxels.len());
        for (what, bytes) in [
            (
                "the object's OBB-tree nodes",
                (tree.nodes.len().max(1) * std::mem::size_of::<GpuNode>()) as u64,
            ),
            (
                "the object's triangles",
                (tree.triangles.len().max(1) * 48) as u64,
            ),
            ("the object's inside-test voxels", (voxels * 4) as u64),
        ] {
            if bytes > limit {
                return Err(GpuError::TooLarge { what, bytes, limit });
            }
        }
        Ok(())
    }

    /// Uploads `tree`.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] when one of its buffers exceeds one storage
    /// binding ([`GpuObject::fits`]).
    pub fn new(device: &wgpu::Device, tree: &ObbTree) -> Result<Self, GpuError> {
        Self::fits(device, tree)?;
        let mut nodes = flatten_nodes(tree);
        if nodes.is_empty() {
            nodes.push(GpuNode::zeroed()); // bindings may not be empty
        }
        let mut tris: Vec<[f32; 4]> = tree.triangles.iter().flat_map(|t| t.map(v4)).collect();
        if tris.is_empty() {
            tris.push([0.0; 4]);
        }
        let mut params = GpuObjectParams::zeroed();
        params.tree = [tree.nodes.len() as u32, u32::from(tree.closed), 1, 1];
        params.local_velocity[3] =
            2.0 * tree.nodes.first().map_or(0.0, |n| n.obb.half.min_element());
        let mut voxels: Vec<u32> = vec![0];
        if let Some(g) = tree.inside.as_ref().filter(|_| tree.closed) {
            voxels = g.voxels.iter().map(|&v| u32::from(v)).collect();
            params.grid_center = v4(g.obb.center);
            params.grid_u = v4(g.obb.axes[0]);
            params.grid_v = v4(g.obb.axes[1]);
            params.grid_w = v4(g.obb.axes[2]);
            params.grid_half = v4(g.obb.half);
            params.field[3] = g.side;
        }
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        Ok(Self {
            params,
            uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu object params"),
                size: std::mem::size_of::<GpuObjectParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            nodes: storage("trample-gpu obb nodes", bytemuck::cast_slice(&nodes)),
            triangles: storage("trample-gpu triangles", bytemuck::cast_slice(&tris)),
            voxels: storage("trample-gpu inside voxels", bytemuck::cast_slice(&voxels)),
        })
    }

    /// Sets the pose for the next dispatch. **Not yet on the GPU**: poses
    /// are computed on the CPU (`Motion::pose_at`, a pure function of time,
    /// a few floats per object) and uploaded.
    pub fn set_pose(&mut self, pose: &Pose) {
        self.params.position = v4(pose.position);
        let q = pose.rotation;
        self.params.rotation = [q.x, q.y, q.z, q.w];
        self.params.velocity = v4(pose.velocity);
        self.params.angular_velocity = v4(pose.angular_velocity);
        // `LocalMotion` as `trample::step::collide::narrow_phase` makes it.
        let inverse = pose.rotation.inverse();
        let (v, w) = (inverse * pose.velocity, inverse * pose.angular_velocity);
        self.params.local_velocity = [v.x, v.y, v.z, self.params.local_velocity[3]];
        self.params.local_angular = [w.x, w.y, w.z, self.params.local_angular[3]];
    }

    /// The object's bind group (`object.wgsl`'s group 1) for `layout`
    /// ([`crate::narrow_phase::object_layout`]).
    pub(crate) fn bind(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
    ) -> wgpu::BindGroup {
        let buffers = [&self.uniform, &self.nodes, &self.triangles, &self.voxels];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("trample-gpu object"),
            layout,
            entries: &entries,
        })
    }

    /// Sets what the simulation's contact walk needs besides the pose: the
    /// sub-step `h` (s), the contact shell (m), the object's press, its
    /// index among the bodies and whether every level of detail is
    /// simulated (`sim.track_everywhere`).
    pub fn set_contact(&mut self, h: f32, shell: f32, press: f32, index: usize, everywhere: bool) {
        self.params.local_angular[3] = h;
        self.params.contact = [shell, press, 0.0, 0.0];
        self.params.extra = [
            u8::try_from(index + 1).map_or(0, u32::from),
            u32::from(everywhere),
            0,
            0,
        ];
    }
}
