//! Stages 4–5 of a sub-step (DESIGN §7): the narrow phase of one object over
//! the blades the broad phase kept, and the forces of Eq. 2 it gives.

use super::body::Body;
use super::simulation::Simulation;
use super::stages::{DBG_WEIGHT, reach_rect};
use super::timings::StepTimings;
use crate::collision::narrow_phase::{BladeContacts, LocalMotion, box_clear_of, contact_blade};
use crate::field::Lod;
use crate::force::eqf::eqf;
use crate::obb::ObbTree;
use crate::object::Pose;
use glam::Vec3;
use rayon::prelude::*;

/// What one object does to one blade in a sub-step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BladeHit {
    /// The blade.
    pub blade: u32,
    /// Σ over its segments of `weight · press · EqF` (Eq. 2), world, m/s.
    pub force: Vec3,
    /// Σ over its segments of their contact weights (Eq. 5's `num`).
    pub weight: f32,
    /// Bit `k`: segment `k` touched the object.
    pub mask: u32,
}

/// The narrow phase of one collider ([`Body::collider`]: a body's own mesh
/// or one of its parts, with its own pose and velocities), made ready: the
/// blades its root box may reach, tile by tile, and what testing one of
/// them needs. [`narrow_phase`] runs the tiles of every collider in one
/// parallel loop.
struct ColliderNarrow<'a> {
    tree: &'a ObbTree,
    pose: Pose,
    press: f32,
    motion: LocalMotion,
    /// The candidate blades ([`candidate_tiles`]).
    candidates: Vec<u32>,
    /// Each tile's range in `candidates`.
    tiles: Vec<(u32, u32)>,
}

impl<'a> ColliderNarrow<'a> {
    /// Collider `k` of `body` over the listed `patches`, for a sub-step of
    /// `h` seconds.
    fn new(sim: &Simulation, body: &'a Body, k: usize, patches: &[u32], h: f32) -> Self {
        let shell = sim.params.contact_shell_m;
        let collider = body.collider(k);
        let (min, max) = reach_rect(collider.world_root, sim.field.max_blade_length + shell);
        let (candidates, tiles) = candidate_tiles(sim, patches, min, max);
        let pose = *collider.pose;
        let tree = collider.tree;
        let inverse = pose.rotation.inverse();
        Self {
            tree,
            pose,
            press: body.object.track.press,
            motion: LocalMotion {
                velocity: inverse * pose.velocity,
                angular_velocity: inverse * pose.angular_velocity,
                h,
                thickness: 2.0 * tree.nodes[0].obb.half.min_element(),
            },
            candidates,
            tiles,
        }
    }

    /// The hits of tile `t`: every blade of the tile moved into the
    /// object's frame once, the tile's box tested first ([`box_clear_of`]),
    /// then each blade down to the precision with the contact shell
    /// ([`contact_blade`]). `contacts` and `local` are scratch space.
    fn tile_hits(
        &self,
        sim: &Simulation,
        t: usize,
        contacts: &mut BladeContacts,
        local: &mut Vec<Vec3>,
    ) -> Vec<BladeHit> {
        let (start, end) = self.tiles[t];
        let tile = &self.candidates[start as usize..end as usize];
        let blades = &sim.field.blades;
        let n = blades.segments;
        let (precision, shell) = (sim.params.precision, sim.params.contact_shell_m);
        let pose = &self.pose;
        local.clear();
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let mut finite = true;
        for &b in tile {
            for k in 0..=n {
                let v = pose.to_local(Vec3::from(blades.vertex(b as usize, k)));
                finite &= v.is_finite();
                (lo, hi) = (lo.min(v), hi.max(v));
                local.push(v);
            }
        }
        let pad = Vec3::splat(TILE_PAD_M);
        if finite && box_clear_of(self.tree, lo - pad, hi + pad, precision, shell) {
            return Vec::new();
        }
        let mut hits = Vec::new();
        for (&b, v) in tile.iter().zip(local.chunks_exact(n + 1)) {
            contact_blade(v, self.tree, precision, shell, &self.motion, contacts);
            if contacts.mask == 0 {
                continue;
            }
            let mut force = Vec3::ZERO;
            for k in 0..n {
                if contacts.mask & (1 << k) != 0 {
                    let c = contacts.contacts[k];
                    // The surface's speed there: the collider's rigid
                    // motion and, for a deforming mesh, the limb's own.
                    let speed = (pose.point_velocity(pose.to_world(c.point))
                        + pose.rotation * c.velocity)
                        .length();
                    force += eqf(speed, pose.rotation * c.dir) * (c.weight * self.press);
                }
            }
            hits.push(BladeHit {
                blade: b,
                force,
                weight: contacts.weight_sum(),
                mask: contacts.mask,
            });
        }
        hits
    }
}

/// Narrow phase of every collider (`colliders`, as (body, collider) pairs:
/// [`Body::collider`]; `patches[j]` the patches the broad phase listed for
/// collider `j`) in a sub-step of `h` seconds: every blade in the patches a
/// collider's root box overlaps (only those of geometric cells in the
/// paper's mode, `sim.track_everywhere = false`), segments moved into the
/// collider's frame once and tested down to the precision with the contact
/// shell ([`contact_blade`], weights set by the object's travel in the
/// sub-step); returns, per collider, the blades touched, ascending, with
/// `Σ_k w_k · press · |v + ω × r + R · v_k| · EqN_k` (Eq. 2 per segment,
/// weighted; `v_k` the deforming mesh's own velocity at the contact,
/// [`crate::collision::narrow_phase::SegmentContact::velocity`]).
///
/// The tiles of all colliders run in one parallel loop (not one loop per
/// collider: a herd's colliders each hold a few dozen tiles, too few to
/// keep the threads busy); each collider's hits are the same whatever the
/// thread count.
pub(crate) fn narrow_phase(
    sim: &Simulation,
    colliders: &[(usize, usize)],
    patches: &[Vec<u32>],
    h: f32,
    tm: &mut StepTimings,
) -> Vec<Vec<BladeHit>> {
    let jobs: Vec<ColliderNarrow> = colliders
        .iter()
        .zip(patches)
        .map(|(&(i, k), p)| ColliderNarrow::new(sim, &sim.bodies[i], k, p, h))
        .collect();
    tm.narrow_candidates += jobs.iter().map(|j| j.candidates.len() as u32).sum::<u32>();
    let work: Vec<(usize, usize)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(j, job)| (0..job.tiles.len()).map(move |t| (j, t)))
        .collect();
    let found: Vec<Vec<BladeHit>> = work
        .par_iter()
        .map_init(
            || (BladeContacts::default(), Vec::new()),
            |(contacts, local), &(j, t)| jobs[j].tile_hits(sim, t, contacts, local),
        )
        .collect();
    let mut per_collider = vec![Vec::new(); jobs.len()];
    for (&(j, _), hits) in work.iter().zip(found) {
        per_collider[j].extend(hits);
    }
    for hits in &mut per_collider {
        hits.sort_unstable_by_key(|hit| hit.blade);
    }
    per_collider
}

/// Cells along a side of the tiles the narrow phase tests as one box
/// before it walks the tree for each of their blades ([`box_clear_of`]):
/// 4 × 4 cells, 16 blades at the default density — small enough that most
/// tiles beside an object miss it, large enough that the test pays.
pub(crate) const TILE_CELLS: usize = 4;

/// How much a tile's box is grown before [`box_clear_of`], metres: far
/// above the rounding of the vertices' transform, so that a segment the
/// wide test would find in a box is in the tile's box too.
const TILE_PAD_M: f32 = 1e-4;

/// The blades the narrow phase tests (every blade rooted in a cell of the
/// listed patches that overlaps the rectangle `min ..= max`, of geometric
/// cells only in the paper's mode, `sim.track_everywhere = false`; blades
/// a grass map left out are not grass), tile by tile: the blades, and the
/// range of each tile in them.
fn candidate_tiles(
    sim: &Simulation,
    patches: &[u32],
    min: [f32; 2],
    max: [f32; 2],
) -> (Vec<u32>, Vec<(u32, u32)>) {
    let layout = &sim.field.layout;
    let bpc = layout.blades_per_cell as usize;
    let cpp = layout.cells_per_patch as usize;
    let everywhere = sim.params.track_everywhere;
    let (mut blades, mut tiles) = (Vec::new(), Vec::new());
    for &p in patches {
        let ([x0, x1], [z0, z1]) = layout.patch_cell_range(p as usize, min, max);
        let first = p as usize * layout.cells_in_patch();
        for tz in (z0..=z1).step_by(TILE_CELLS) {
            for tx in (x0..=x1).step_by(TILE_CELLS) {
                let start = blades.len();
                for lz in tz..=(tz + TILE_CELLS - 1).min(z1) {
                    for lx in tx..=(tx + TILE_CELLS - 1).min(x1) {
                        let c = first + lz * cpp + lx;
                        if !everywhere && sim.field.cells.lod[c] != Lod::Geometry {
                            continue;
                        }
                        blades.extend(
                            ((c * bpc) as u32..((c + 1) * bpc) as u32)
                                .filter(|&b| sim.field.blades.is_present(b as usize)),
                        );
                    }
                }
                if blades.len() > start {
                    tiles.push((start as u32, blades.len() as u32));
                }
            }
        }
    }
    (blades, tiles)
}

/// Adds one body's hits (body `index`, in body order) to the sub-step's
/// per-blade force, weight and segment mask, lists the blades touched for the first time
/// this sub-step, and moves a blade's track owner to the body whose contact
/// is the firmest so far (at least [`DBG_WEIGHT`]; the first on ties).
pub(crate) fn accumulate_contacts(sim: &mut Simulation, index: usize, hits: &[BladeHit]) {
    let owner = u8::try_from(index + 1).unwrap_or(0);
    let s = &mut sim.scratch;
    for h in hits {
        let b = h.blade as usize;
        if s.weight[b] == 0.0 {
            s.touched.push(h.blade);
        }
        s.force[b] += h.force;
        s.weight[b] += h.weight;
        s.mask[b] |= h.mask;
        if h.weight >= DBG_WEIGHT && h.weight > s.owner_weight[b] {
            s.owner_weight[b] = h.weight;
            sim.track_owner[b] = owner;
        }
    }
}
