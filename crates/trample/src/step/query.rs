//! Queries on the field at rest, for `trample collide`, tests and benchmarks:
//! which segments of which blades an object hits at a given time.

use super::body::Body;
use super::simulation::Simulation;
use crate::collision::broad_phase::patches_under;
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
        let posed = self.bodies_at(t);
        for collider in posed.iter().flat_map(Body::colliders) {
            let pose = *collider.pose;
            let tree = collider.tree;
            let mut patches = Vec::new();
            patches_under(&self.field.layout, collider.world_root, &mut patches);
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
                                HitMode::Precision(d) => collide_segment(p0, p1, tree, d).is_some(),
                                HitMode::Exact => segment_hits_exact(tree, p0, p1),
                            };
                            *f |= u8::from(hit);
                        }
                    });
            }
        }
        flags
    }

    /// Every object's triangles in world space at time `t`, posed and
    /// deformed (the `--dump-object` layout): body after body, each body's
    /// own mesh then its parts' ([`Body::world_triangles`]).
    #[must_use]
    pub fn object_triangles_at(&self, t: f32) -> Vec<[Vec3; 3]> {
        self.bodies_at(t)
            .iter()
            .flat_map(Body::world_triangles)
            .collect()
    }

    /// Copies of the bodies posed at time `t` ([`Body::set_time`]: skinned
    /// meshes posed and their trees refitted, with their tilted boxes
    /// ([`crate::obb::slabs`]) fitted again, parts posed), the simulation
    /// left as it is.
    #[must_use]
    pub fn bodies_at(&self, t: f32) -> Vec<Body> {
        self.bodies
            .iter()
            .map(|b| {
                let mut b = b.clone();
                b.set_time(t);
                // A posed skin's tree comes without its tilted boxes
                // (`rig::skin_and_refit`): the yes/no walk wants them.
                if b.tree.slabs.is_empty() && !b.tree.nested {
                    std::sync::Arc::make_mut(&mut b.tree).fit_slabs();
                }
                b
            })
            .collect()
    }
}
