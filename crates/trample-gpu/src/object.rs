//! The objects on the GPU, all in one storage buffer (issue 16 item 3: one
//! narrow-phase dispatch for all objects, within the default binding
//! limits): each object's OBB tree (paper §4.2's HBV, built once on the CPU
//! by `trample::obb::ObbTree::build`: the paper's off-line stage)
//! flattened, its triangles and inside-voxel grid (for the inside test of
//! closed meshes), and its pose and settings, read by `object.wgsl`.
//!
//! The table, in 16-byte words (`vec4<u32>`; floats by their bits):
//! word 0 is the header (object count, mask words per patch of the broad
//! phase, first mask word in the broad phase's lists, 0); object `o`'s
//! [`GpuObjectParams`] are the 16 words from `1 + 16 o`; its nodes
//! ([`GpuNode`], 15 words each), triangles (3 words each, one a corner),
//! an open mesh's pseudo-normals (6 words a triangle: edges `ab`, `bc`, `ca`,
//! corners `a`, `b`, `c`; `trample::obb::pseudo_normals`), its winding data
//! when it winds (2 words a node, from the word `extra[2] − 1` counts from
//! its first; `trample::collision::winding`) and its winding grid (two
//! corners a word, from the word `extra[3] − 1` counts from its first;
//! `trample::collision::winding_grid`) and a closed mesh's voxels (two bits each, 16 to a `u32`, 64 to a word) start at the
//! words its `base` names. Only the parameters change during a run (one
//! write of `16 · 16` bytes an object per sub-step).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use trample::obb::slabs::EXTRA_BOXES;
use trample::obb::{EQN_EPSILON, ObbTree};
use trample::object::Pose;
use trample::step::Simulation;
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
    /// Half extents (hu, hv, hw); w: the thin axis its tilted boxes turn
    /// from (`trample::obb::slabs::NodeSlabs::thin`: 0, 1 or 2), or −1
    /// when the tree has none (a nested tree).
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
    /// The node's deformation velocity in the object's frame, m/s
    /// (`ObbTree::node_velocity`; zero for a mesh that does not deform)
    /// (w unused).
    pub velocity: [f32; 4],
    /// The node's tilted boxes (`trample::obb::slabs::NodeSlabs::faces`):
    /// per box, the centre and half extent along its two turned axes (zero
    /// when the tree has none).
    pub tilted: [[f32; 4]; EXTRA_BOXES],
}
const _: () = assert!(std::mem::size_of::<GpuNode>() == 240);

/// An object's pose and tree header. Layout-compatible with `ObjectParams`
/// in `object.wgsl` (read from the object table by `load_object`).
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
    /// Inside-grid box: centre, axes, half extents (zero without a grid);
    /// for a winding mesh, its winding grid's box, with its voxels along
    /// each axis in `grid_u.w`, `grid_v.w`, `grid_w.w`.
    pub grid_center: [f32; 4],
    /// Inside-grid axis u.
    pub grid_u: [f32; 4],
    /// Inside-grid axis v.
    pub grid_v: [f32; 4],
    /// Inside-grid axis w.
    pub grid_w: [f32; 4],
    /// Inside-grid half extents.
    pub grid_half: [f32; 4],
    /// Node count, closed (1) or open (0), final depth (precision), unused.
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
    /// everywhere (1) or the paper's geometric cells only (0), 1 + the
    /// first word of its winding data from its nodes' (0: none), 1 + the
    /// first word of its winding grid from its nodes' (0: none).
    pub extra: [u32; 4],
    /// Where the object's nodes, triangles, voxels and pseudo-normals start
    /// in the object table, in 16-byte words.
    pub base: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuObjectParams>() == 256);

/// 16-byte words of one object's [`GpuObjectParams`] in the table.
const PARAM_WORDS: usize = 16;
/// 16-byte words of one [`GpuNode`].
const NODE_WORDS: usize = 15;

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
            let slabs = tree.slabs.get(i);
            let thin = slabs.map_or(-1.0, |s| s.thin as f32);
            GpuNode {
                center: v4(c),
                axis_u: v4(n.obb.axes[0]),
                axis_v: v4(n.obb.axes[1]),
                axis_w: v4(n.obb.axes[2]),
                half: [n.obb.half.x, n.obb.half.y, n.obb.half.z, thin],
                dir: [d.x, d.y, d.z, if valid { 1.0 } else { 0.0 }],
                children: [n.children[0], n.children[1], n.first_tri, n.tri_count],
                reach_center: v4(reach.center),
                reach_half: v4(reach.half),
                velocity: v4(tree.node_velocity(i as u32)),
                tilted: slabs.map_or([[0.0; 4]; EXTRA_BOXES], |s| s.faces),
            }
        })
        .collect()
}

/// The words of one object's tree, triangles and voxels, and its
/// parameters with their `base` still relative to the object's own words.
fn object_words(tree: &ObbTree) -> (GpuObjectParams, Vec<[u32; 4]>) {
    let words = |v: [f32; 4]| v.map(f32::to_bits);
    let nodes = flatten_nodes(tree);
    let mut out: Vec<[u32; 4]> = Vec::with_capacity(nodes.len() * NODE_WORDS);
    for n in &nodes {
        out.extend([
            words(n.center),
            words(n.axis_u),
            words(n.axis_v),
            words(n.axis_w),
            words(n.half),
            words(n.dir),
            n.children,
            words(n.reach_center),
            words(n.reach_half),
            words(n.velocity),
        ]);
        out.extend(n.tilted.map(words));
    }
    let mut params = GpuObjectParams::zeroed();
    params.base[0] = 0;
    params.base[1] = out.len() as u32;
    out.extend(tree.triangles.iter().flat_map(|t| t.map(|c| words(v4(c)))));
    // An open mesh's pseudo-normals (six per triangle; none for a closed
    // mesh): `trample::obb::pseudo_normals`.
    params.base[3] = out.len() as u32;
    out.extend(
        tree.feature_normals
            .iter()
            .flat_map(|n| n.map(|v| words(v4(v)))),
    );
    // An open mesh's winding data, when it winds
    // (`trample::collision::winding`): per node, its area vector, then its
    // dipole's centre and radius. `extra[2]`: 1 + their first word from
    // the object's own first word (0: none, the sheet rule).
    if tree.winds() {
        params.extra[2] = out.len() as u32 + 1;
        for d in &tree.dipoles {
            out.push(words(v4(d.area)));
            out.push(words(d.centre.extend(d.radius).to_array()));
        }
        // Its winding grid (`trample::collision::winding_grid`): per
        // corner (x fastest) the tree sum and the trust, two corners a
        // word; the box in `grid_*`, the voxels along u, v, w in their w
        // lanes. `extra[3]`: 1 + its first word from the object's own first
        // word (0: none, the tree sum alone).
        if let Some(g) = &tree.winding_grid {
            params.extra[3] = out.len() as u32 + 1;
            out.extend(g.corners.chunks(2).map(|c| {
                let second = c.get(1).copied().unwrap_or([0.0; 2]);
                words([c[0][0], c[0][1], second[0], second[1]])
            }));
            let n = g.voxels.as_vec3();
            params.grid_center = v4(g.obb.center);
            params.grid_u = [g.obb.axes[0].x, g.obb.axes[0].y, g.obb.axes[0].z, n.x];
            params.grid_v = [g.obb.axes[1].x, g.obb.axes[1].y, g.obb.axes[1].z, n.y];
            params.grid_w = [g.obb.axes[2].x, g.obb.axes[2].y, g.obb.axes[2].z, n.z];
            params.grid_half = v4(g.obb.half);
        }
    }
    params.base[2] = out.len() as u32;
    params.tree = [tree.nodes.len() as u32, u32::from(tree.closed), 1, 0];
    params.local_velocity[3] = 2.0 * tree.nodes.first().map_or(0.0, |n| n.obb.half.min_element());
    if let Some(g) = tree.inside.as_ref().filter(|_| tree.closed) {
        // Two bits a voxel, 16 to a `u32`, as the grid keeps them: a 64³
        // grid takes 64 KiB, so a herd of differently sized balls stays
        // within the binding limits.
        out.extend(g.words.chunks(4).map(|c| {
            let mut w = [0u32; 4];
            w[..c.len()].copy_from_slice(c);
            w
        }));
        params.grid_center = v4(g.obb.center);
        params.grid_u = v4(g.obb.axes[0]);
        params.grid_v = v4(g.obb.axes[1]);
        params.grid_w = v4(g.obb.axes[2]);
        params.grid_half = v4(g.obb.half);
        params.field[3] = g.side;
    }
    (params, out)
}

/// Words of one object's nodes, triangles, pseudo-normals and winding
/// data (what [`GpuObjects::write_tree`] uploads).
fn mesh_words(tree: &ObbTree) -> usize {
    let winding = if tree.winds() {
        tree.dipoles.len() * 2
            + tree
                .winding_grid
                .as_ref()
                .map_or(0, |g| g.corners.len().div_ceil(2))
    } else {
        0
    };
    tree.nodes.len() * NODE_WORDS
        + tree.triangles.len() * 3
        + tree.feature_normals.len() * 6
        + winding
}

/// The object table after its header: every object's parameters (their
/// `base` absolute) and the words they point at. An object whose words
/// equal an earlier object's (the same mesh at the same scale: a herd's
/// twenty cows) points at that object's words instead of a copy, unless
/// `rewritten[i]` (its tree is written again every sub-step: an animated
/// body, [`GpuObjects::write_tree`]; such an object neither shares nor is
/// shared). Built once per upload: its size is checked against the
/// device ([`TableLayout::check`]) before anything is allocated, then the
/// same layout is uploaded ([`GpuObjects::from_layout`]).
pub struct TableLayout {
    params: Vec<GpuObjectParams>,
    data: Vec<[u32; 4]>,
    /// Per object: its words are shared with another object's.
    shared: Vec<bool>,
}

impl TableLayout {
    /// The layout of `trees` (one per object, in order), `rewritten` as
    /// above (missing entries: not rewritten).
    #[must_use]
    pub fn new(trees: &[&ObbTree], rewritten: &[bool]) -> Self {
        use std::collections::HashMap;
        use std::hash::{BuildHasher, BuildHasherDefault, DefaultHasher};
        let hash = |w: &[[u32; 4]]| BuildHasherDefault::<DefaultHasher>::default().hash_one(w);
        let mut params = Vec::with_capacity(trees.len());
        let mut data: Vec<[u32; 4]> = Vec::new();
        let mut shared = vec![false; trees.len()];
        // Words' hash -> (object, first word in `data`) of the objects stored.
        let mut stored: HashMap<u64, Vec<(usize, usize)>> = HashMap::new();
        let start = (1 + PARAM_WORDS * trees.len()) as u32;
        for (i, tree) in trees.iter().enumerate() {
            let (mut p, words) = object_words(tree);
            let own = rewritten.get(i).copied().unwrap_or(false);
            let key = hash(&words);
            let same = (!own)
                .then(|| stored.get(&key))
                .flatten()
                .and_then(|v| {
                    v.iter()
                        .find(|&&(_, at)| data.get(at..at + words.len()) == Some(&words[..]))
                })
                .copied();
            let at = if let Some((first, at)) = same {
                shared[first] = true;
                shared[i] = true;
                at
            } else {
                let at = data.len();
                if !own {
                    stored.entry(key).or_default().push((i, at));
                }
                data.extend_from_slice(&words);
                at
            };
            for b in &mut p.base {
                *b += start + at as u32;
            }
            params.push(p);
        }
        Self {
            params,
            data,
            shared,
        }
    }

    /// The layout of `sim`'s colliders (each body's own mesh, then its
    /// parts; an animated body's rewritten): what the GPU path uploads.
    #[must_use]
    pub fn of_simulation(sim: &Simulation) -> Self {
        let (trees, rewritten): (Vec<_>, Vec<_>) = sim
            .bodies
            .iter()
            .flat_map(|b| {
                let animated = b.deforms();
                b.colliders().map(move |c| (c.tree, animated))
            })
            .unzip();
        Self::new(&trees, &rewritten)
    }

    /// Bytes of the table: header, parameters, the words.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        (1 + self.params.len() * PARAM_WORDS + self.data.len()) as u64 * 16
    }

    /// Whether the table fits one storage binding of `device`.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`].
    pub fn check(&self, device: &wgpu::Device) -> Result<(), GpuError> {
        let limit = device.limits().max_storage_buffer_binding_size;
        if self.bytes() > limit {
            return Err(too_large(self.bytes(), limit));
        }
        Ok(())
    }
}

/// Bytes of the object table for `trees` (header, parameters, every
/// object's nodes, triangles, pseudo-normals, winding data and voxels, identical ones
/// once: see [`GpuObjects::new`]).
#[must_use]
pub fn table_bytes<'a>(trees: impl IntoIterator<Item = &'a ObbTree>) -> u64 {
    let trees: Vec<&ObbTree> = trees.into_iter().collect();
    TableLayout::new(&trees, &[]).bytes()
}

/// Every object of a simulation in one storage buffer (see the module
/// docs), and their parameters on the CPU. Build once; set the poses
/// ([`GpuObjects::set_pose`]) and write them ([`GpuObjects::write`]) every
/// sub-step.
pub struct GpuObjects {
    params: Vec<GpuObjectParams>,
    /// Per object: its words are shared with another object's.
    shared: Vec<bool>,
    /// The object table (group 1 of the narrow phase and the contact
    /// response).
    pub(crate) table: wgpu::Buffer,
}

/// The error for an object table of `bytes` over the binding `limit`.
fn too_large(bytes: u64, limit: u64) -> GpuError {
    GpuError::TooLarge {
        what: "the objects' OBB trees, triangles, pseudo-normals, winding data and inside-test voxels (one buffer)",
        bytes,
        limit,
    }
}

impl GpuObjects {
    /// Uploads `trees` (one per object, in order). `masks` is where the
    /// broad phase keeps its per-patch object masks: (words per patch,
    /// first word in its lists), `(0, 0)` without a broad phase. Objects
    /// with identical trees (the same mesh at the same scale) share one
    /// copy of their nodes, triangles and voxels in the table.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] when the table exceeds one storage binding
    /// ([`TableLayout::check`]).
    pub fn new(
        device: &wgpu::Device,
        trees: &[&ObbTree],
        masks: (u32, u32),
    ) -> Result<Self, GpuError> {
        Self::with_rewritten(device, trees, &[], masks)
    }

    /// As [`GpuObjects::new`]; the objects `i` with `rewritten[i]` (an
    /// animated body's, whose refitted tree [`GpuObjects::write_tree`]
    /// writes every sub-step) keep words of their own.
    ///
    /// # Errors
    /// As [`GpuObjects::new`].
    pub fn with_rewritten(
        device: &wgpu::Device,
        trees: &[&ObbTree],
        rewritten: &[bool],
        masks: (u32, u32),
    ) -> Result<Self, GpuError> {
        Self::from_layout(device, TableLayout::new(trees, rewritten), masks)
    }

    /// Uploads `layout` (checked first, [`TableLayout::check`]) with the
    /// broad phase's `masks` (see [`GpuObjects::new`]).
    ///
    /// # Errors
    /// As [`GpuObjects::new`].
    pub fn from_layout(
        device: &wgpu::Device,
        layout: TableLayout,
        masks: (u32, u32),
    ) -> Result<Self, GpuError> {
        layout.check(device)?;
        let TableLayout {
            params,
            data,
            shared,
        } = layout;
        let mut table: Vec<[u32; 4]> =
            Vec::with_capacity(1 + params.len() * PARAM_WORDS + data.len());
        table.push([params.len() as u32, masks.0, masks.1, 0]);
        table.extend(
            params
                .iter()
                .flat_map(|p| bytemuck::cast::<GpuObjectParams, [[u32; 4]; PARAM_WORDS]>(*p)),
        );
        table.extend(data);
        Ok(Self {
            params,
            shared,
            table: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trample-gpu objects"),
                contents: bytemuck::cast_slice(&table),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            }),
        })
    }

    /// Whether object `i` shares its table words with another object
    /// (identical trees, [`GpuObjects::new`]).
    #[must_use]
    pub fn is_shared(&self, i: usize) -> bool {
        self.shared.get(i).copied().unwrap_or(false)
    }

    /// Bytes of the object table on the device.
    #[must_use]
    pub fn table_size(&self) -> u64 {
        self.table.size()
    }

    /// Number of objects.
    #[must_use]
    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// True with no object.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// Object `i`'s parameters as the next [`GpuObjects::write`] uploads them.
    #[must_use]
    pub fn params(&self, i: usize) -> &GpuObjectParams {
        &self.params[i]
    }

    /// Sets object `i`'s pose for the next dispatch. **Not yet on the
    /// GPU**: poses are computed on the CPU (`Motion::pose_at`, a pure
    /// function of time, a few floats per object) and uploaded.
    pub fn set_pose(&mut self, i: usize, pose: &Pose) {
        let p = &mut self.params[i];
        p.position = v4(pose.position);
        let q = pose.rotation;
        p.rotation = [q.x, q.y, q.z, q.w];
        p.velocity = v4(pose.velocity);
        p.angular_velocity = v4(pose.angular_velocity);
        // `LocalMotion` as `trample::step::collide::narrow_phase` makes it.
        let inverse = pose.rotation.inverse();
        let (v, w) = (inverse * pose.velocity, inverse * pose.angular_velocity);
        p.local_velocity = [v.x, v.y, v.z, p.local_velocity[3]];
        p.local_angular = [w.x, w.y, w.z, p.local_angular[3]];
    }

    /// Sets what the simulation's contact walk needs besides object `i`'s
    /// pose: the sub-step `h` (s), the contact shell (m), the object's
    /// press, and whether every level of detail is simulated
    /// (`sim.track_everywhere`). Its track owner id is `1 + i` (0 past 254).
    pub fn set_contact(&mut self, i: usize, h: f32, shell: f32, press: f32, everywhere: bool) {
        let p = &mut self.params[i];
        p.local_angular[3] = h;
        p.contact = [shell, press, 0.0, 0.0];
        p.extra = [
            u8::try_from(i + 1).map_or(0, u32::from),
            u32::from(everywhere),
            p.extra[2],
            p.extra[3],
        ];
    }

    /// Sets object `i`'s track owner id to `1 + body` (0 past 254): the
    /// body whose collider it is (a part presses for its body).
    pub fn set_owner(&mut self, i: usize, body: usize) {
        self.params[i].extra[0] = u8::try_from(body + 1).map_or(0, u32::from);
    }

    /// Writes object `i`'s tree again: the same tree refitted to a deformed
    /// mesh ([`trample::obb::ObbTree::refit`]: same topology, so the same
    /// number of words; a refitted tree has no inside grid, and neither
    /// has the object made from it: the inside test casts rays). The
    /// object's thickness (the contact ramp's, as the CPU takes it from the
    /// current root box) follows the root. A tree of another size is
    /// ignored, and so is an object that shares its words with another
    /// (make the table with [`GpuObjects::with_rewritten`]). Returns the
    /// bytes uploaded (in order with `encoder`'s commands:
    /// [`crate::upload::Uploads`]).
    pub fn write_tree(
        &mut self,
        i: usize,
        tree: &ObbTree,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        uploads: &mut crate::upload::Uploads,
        encoder: &mut wgpu::CommandEncoder,
    ) -> u64 {
        if self.is_shared(i) {
            // Another object reads these words: made with `with_rewritten`,
            // a rewritten object never shares.
            return 0;
        }
        let (fresh, words) = object_words(tree);
        let p = &mut self.params[i];
        let (old_len, new_len) = (p.base[2] - p.base[0], fresh.base[2] - fresh.base[0]);
        if old_len != new_len || fresh.field[3] != 0 || p.field[3] != 0 {
            return 0;
        }
        p.local_velocity[3] = fresh.local_velocity[3];
        let bytes: &[u8] = bytemuck::cast_slice(&words[..new_len as usize]);
        uploads.upload(
            device,
            queue,
            encoder,
            &self.table,
            u64::from(p.base[0]) * 16,
            bytes,
        );
        bytes.len() as u64
    }

    /// Bytes [`GpuObjects::write_tree`] uploads for `tree`.
    #[must_use]
    pub fn tree_bytes(tree: &ObbTree) -> u64 {
        (mesh_words(tree) * 16) as u64
    }

    /// Sets every object's final depth (`precision`, root = 1; clamped to
    /// 1..=64 as on the CPU) and the field it runs over: blade count,
    /// segments per blade, blades per cell.
    pub fn set_walk(&mut self, precision: u32, blades: u32, segments: u32, per_cell: u32) {
        for p in &mut self.params {
            p.tree[2] = precision.clamp(1, trample::obb::MAX_TREE_DEPTH);
            p.field[0] = blades;
            p.field[1] = segments;
            p.field[2] = per_cell;
        }
    }

    /// Writes every object's parameters into the table (one upload, in
    /// order with `encoder`'s commands: [`crate::upload::Uploads`]).
    pub fn write(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        uploads: &mut crate::upload::Uploads,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let bytes = bytemuck::cast_slice(&self.params);
        uploads.upload(device, queue, encoder, &self.table, 16, bytes);
    }

    /// Bytes of one [`GpuObjects::write`].
    #[must_use]
    pub fn params_bytes(&self) -> u64 {
        std::mem::size_of_val(self.params.as_slice()) as u64
    }

    /// The table's bind group (`object.wgsl`'s group 1) for `layout`
    /// ([`crate::narrow_phase::object_layout`]), kept in `cache` (the
    /// caller's, one per layout) while the table stays the same buffer.
    pub(crate) fn bind(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        cache: &crate::kernel::BindCache,
    ) -> wgpu::BindGroup {
        cache.bind(device, layout, &[&self.table], 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trample::object::shapes::{knot, sphere};

    /// `object.wgsl`'s winding constants are the CPU's, bit for bit (a
    /// drift would show in the parity tests only as a small error).
    #[test]
    fn the_shaders_winding_constants_are_the_cpus() {
        use trample::collision::winding::{
            ATAN_POLY, FAR_HI, FAR_LO, WINDING_INSIDE_HI, WINDING_INSIDE_LO,
        };
        let wgsl = crate::OBJECT_WGSL;
        let value = |name: &str| crate::wgsl_f32_const(wgsl, name);
        let names = [
            "ATAN_C1", "ATAN_C3", "ATAN_C5", "ATAN_C7", "ATAN_C9", "ATAN_C11",
        ];
        for (name, want) in names.iter().zip(ATAN_POLY) {
            assert_eq!(value(name).to_bits(), want.to_bits(), "{name}");
        }
        for (name, want) in [
            ("FAR_LO", FAR_LO),
            ("FAR_HI", FAR_HI),
            ("WINDING_INSIDE_LO", WINDING_INSIDE_LO),
            ("WINDING_INSIDE_HI", WINDING_INSIDE_HI),
            ("HALF_PI", std::f32::consts::FRAC_PI_2),
            ("PI", std::f32::consts::PI),
        ] {
            assert_eq!(value(name).to_bits(), want.to_bits(), "{name}");
        }
        let at = wgsl.find("const EXACT_TRIANGLES: u32 = ").unwrap() + 29;
        let text = &wgsl[at..at + wgsl[at..].find("u;").unwrap()];
        assert_eq!(
            text.parse::<u32>().unwrap(),
            trample::collision::winding::EXACT_TRIANGLES
        );
    }

    /// Objects with identical trees are stored once (their parameters point
    /// at the same words); a rewritten one, or a different tree, gets its
    /// own. Fails when every object gets a copy.
    #[test]
    fn identical_trees_share_their_words_unless_rewritten() {
        let a = ObbTree::build(&sphere(1.0, 2), 32);
        let b = ObbTree::build(&knot(2.0), 32);
        let a2 = a.clone();
        let words = |t: &ObbTree| object_words(t).1.len();
        let TableLayout {
            params,
            data,
            shared,
        } = TableLayout::new(&[&a, &b, &a2, &a], &[]);
        assert_eq!(data.len(), words(&a) + words(&b));
        assert_eq!(shared, [true, false, true, true]);
        assert_eq!(params[0].base, params[2].base);
        assert_eq!(params[0].base, params[3].base);
        assert_ne!(params[0].base, params[1].base);
        assert_eq!(
            table_bytes([&a, &b, &a2, &a]),
            (1 + 4 * PARAM_WORDS + data.len()) as u64 * 16
        );
        // A rewritten object neither shares nor is shared.
        let TableLayout {
            params,
            data,
            shared,
        } = TableLayout::new(&[&a, &a2, &a], &[false, true, false]);
        assert_eq!(data.len(), 2 * words(&a));
        assert_eq!(shared, [true, false, true]);
        assert_ne!(params[1].base, params[0].base);
        assert_eq!(params[2].base, params[0].base);
    }
}
