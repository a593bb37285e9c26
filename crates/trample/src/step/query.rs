//! Queries on the field at rest, for `trample collide`, tests and benchmarks:
//! which segments of which blades an object hits at a given time.

use super::simulation::Simulation;
use crate::collision::broad_phase::{patches_under, world_obb};
use crate::collision::exact::segment_hits_exact;
use crate::collision::narrow_phase::collide_segment;
use glam::Vec3;
use rayon::prelude::*;

/// How a segment hit is decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HitMode {
    /// The paper's OBB-tree test stopped at this depth (root = 1).
    Precision(u32),
    /// The exact reference: the segment crosses a triangle, or lies inside a closed mesh.
    Exact,
}

impl Simulation {
    /// Hit flags of every segment of every blade at rest (whatever its level
    /// of detail), with the objects posed at time `t`: `flags[b * n + k]` is 1
    /// when segment k (vertex k → k+1) of blade b hits some object.
    #[must_use]
    pub fn segment_hits_at_rest(&self, t: f32, mode: HitMode) -> Vec<u8> {
        let bl = &self.field.blades;
        let n = bl.segments;
        let mut flags = vec![0u8; bl.count * n];
        for body in &self.bodies {
            let pose = body.object.pose_at(t);
            let root = world_obb(&body.tree.nodes[0].obb, &pose);
            let mut patches = Vec::new();
            patches_under(&self.field.layout, &root, &mut patches);
            for p in patches {
                let patch = &self.field.layout.patch_list[p as usize];
                let range = patch.first_blade as usize..(patch.first_blade + patch.blades) as usize;
                flags[range.start * n..range.end * n]
                    .par_chunks_mut(n)
                    .enumerate()
                    .for_each(|(i, out)| {
                        let b = range.start + i;
                        for (k, f) in out.iter_mut().enumerate() {
                            let p0 = pose.to_local(Vec3::from(bl.rest_vertex(b, k)));
                            let p1 = pose.to_local(Vec3::from(bl.rest_vertex(b, k + 1)));
                            let hit = match mode {
                                HitMode::Precision(d) => {
                                    collide_segment(p0, p1, &body.tree, d).is_some()
                                }
                                HitMode::Exact => segment_hits_exact(&body.tree, p0, p1),
                            };
                            *f |= u8::from(hit);
                        }
                    });
            }
        }
        flags
    }

    /// Every object's triangles in world space at time `t` (the `--dump-object` layout).
    #[must_use]
    pub fn object_triangles_at(&self, t: f32) -> Vec<[Vec3; 3]> {
        let mut out = Vec::new();
        for body in &self.bodies {
            let pose = body.object.pose_at(t);
            let m = &body.object.mesh;
            out.extend((0..m.triangle_count()).map(|i| m.triangle(i).map(|v| pose.to_world(v))));
        }
        out
    }
}
