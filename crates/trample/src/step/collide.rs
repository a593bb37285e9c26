//! Stages 4–5 of a sub-step (DESIGN §7): the narrow phase of one object over
//! the blades the broad phase kept, and the forces of Eq. 2 it gives.

use super::at_rest::{ColliderMemo, NarrowPlan, RestKey, TestedTile, tile_vertices};
use super::body::Body;
use super::simulation::Simulation;
use super::stages::{DBG_WEIGHT, reach_rect};
use super::timings::StepTimings;
use crate::collision::narrow_phase::{
    BladeContacts, LocalMotion, NearBounds, box_clear_of, box_outside, contact_blade,
    contact_blade_near, final_nodes_near, near_bounds,
};
use crate::field::{BladeVertex, Lod};
use crate::force::eqf::eqf;
use crate::obb::ObbTree;
use crate::object::Pose;
use glam::{Vec3, Vec3A};
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
    /// What the collider reads besides the blades, when it may be at rest
    /// ([`super::at_rest`]; `None`: an animated body, the paper's mode, or
    /// `sim.reuse_at_rest = false`).
    key: Option<RestKey>,
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
        let params = &sim.params;
        let key = super::at_rest::may_reuse(params, body).then(|| {
            RestKey::new(
                &pose,
                tree,
                h,
                params.precision,
                shell,
                body.object.track.press,
                sim.field.max_blade_length + shell,
            )
        });
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
            key,
        }
    }

    /// The hits of tile `t`: nothing when the tile's world box, turned
    /// into the object's frame whole, is clear ([`world_box_clear`]);
    /// otherwise every blade of the tile moved into the object's frame
    /// once, the final nodes the box of those vertices may meet found
    /// ([`final_nodes_near`]; none, and the box outside a closed mesh: no
    /// hit), then each blade tested against those nodes with the contact
    /// shell ([`contact_blade_near`]). `contacts` and `scratch` are scratch
    /// space.
    fn tile_hits(
        &self,
        sim: &Simulation,
        t: usize,
        contacts: &mut BladeContacts,
        scratch: &mut TileScratch,
    ) -> Vec<BladeHit> {
        let (start, end) = self.tiles[t];
        let tile = &self.candidates[start as usize..end as usize];
        if world_box_clear(sim, tile, &self.pose, self.tree) {
            return Vec::new();
        }
        self.turned_tile_hits(sim, tile, contacts, scratch)
    }

    /// [`ColliderNarrow::tile_hits`] after its first test: the blades of
    /// `tile` moved into the object's frame, their box tested, then each
    /// blade walked.
    fn turned_tile_hits(
        &self,
        sim: &Simulation,
        tile: &[u32],
        contacts: &mut BladeContacts,
        scratch: &mut TileScratch,
    ) -> Vec<BladeHit> {
        let TileScratch {
            local,
            near,
            bounds,
        } = scratch;
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
        let (lo, hi) = (lo - pad, hi + pad);
        // The final nodes any of the tile's segments may meet, found once:
        // each blade is then tested against them alone (the same contacts
        // as its walk from the root, `contact_blade_near`).
        let listed = finite && final_nodes_near(self.tree, lo, hi, precision, shell, near);
        if listed && near.is_empty() && box_outside(self.tree, lo, hi) {
            return Vec::new();
        }
        if listed {
            near_bounds(self.tree, near, shell, bounds);
        }
        let mut hits = Vec::new();
        for (&b, v) in tile.iter().zip(local.chunks_exact(n + 1)) {
            if listed {
                contact_blade_near(
                    v,
                    self.tree,
                    near,
                    bounds,
                    precision,
                    shell,
                    &self.motion,
                    contacts,
                );
            } else {
                contact_blade(v, self.tree, precision, shell, &self.motion, contacts);
            }
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
                    force += eqf(speed, pose.rotation * c.dir) * (c.weight * c.agree * self.press);
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

/// Work memory of one thread's tiles ([`ColliderNarrow::tile_hits`]).
#[derive(Default)]
struct TileScratch {
    /// The tile's vertices in the object's frame.
    local: Vec<Vec3>,
    /// The final nodes the tile's box may meet ([`final_nodes_near`]).
    near: Vec<u32>,
    /// Their bounds ([`near_bounds`]).
    bounds: Vec<NearBounds>,
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
    memos: &mut [ColliderMemo],
    tm: &mut StepTimings,
) -> (Vec<Vec<BladeHit>>, Vec<Option<RestKey>>) {
    // Each collider's candidate blades and tiles, colliders in parallel
    // (listed in collider order: the same lists on any thread count).
    let jobs: Vec<ColliderNarrow> = colliders
        .par_iter()
        .zip(patches)
        .map(|(&(i, k), p)| ColliderNarrow::new(sim, &sim.bodies[i], k, p, h))
        .collect();
    tm.narrow_candidates += jobs.iter().map(|j| j.candidates.len() as u32).sum::<u32>();
    // Colliders at rest take the kept hits of the tiles whose blades did
    // not change (`super::at_rest`).
    let plans: Vec<NarrowPlan> = jobs
        .par_iter()
        .zip(memos.par_iter_mut())
        .map(|(job, memo)| memo.plan(job.key, &job.candidates, &job.tiles))
        .collect();
    let work: Vec<(usize, usize)> = jobs
        .iter()
        .enumerate()
        .flat_map(|(j, job)| (0..job.tiles.len()).map(move |t| (j, t)))
        .collect();
    let blades = &sim.field.blades;
    let n = blades.segments;
    let kept: &[ColliderMemo] = memos;
    let found: Vec<(Vec<BladeHit>, Option<Vec<BladeVertex>>, bool)> = work
        .par_iter()
        .map_init(
            || (BladeContacts::default(), TileScratch::default()),
            |(contacts, scratch), &(j, t)| {
                let plan = plans[j];
                let (start, end) = jobs[j].tiles[t];
                let tile = &jobs[j].candidates[start as usize..end as usize];
                if plan == NarrowPlan::Reuse
                    && let Some(hits) = kept[j].kept_tile(t, blades, tile)
                {
                    return (hits.to_vec(), None, true);
                }
                let hits = jobs[j].tile_hits(sim, t, contacts, scratch);
                let copy = (plan != NarrowPlan::Plain).then(|| tile_vertices(blades, tile));
                (hits, copy, false)
            },
        )
        .collect();
    let mut per_collider = vec![Vec::new(); jobs.len()];
    let mut tested: Vec<Vec<Option<TestedTile>>> =
        jobs.iter().map(|job| vec![None; job.tiles.len()]).collect();
    tm.narrow_tiles += work.len() as u32;
    for (&(j, t), (hits, copy, reused)) in work.iter().zip(found) {
        tm.reused_tiles += u32::from(reused);
        if let Some(verts) = copy {
            tested[j][t] = Some((verts, hits.clone()));
        }
        per_collider[j].extend(hits);
    }
    for (((job, memo), plan), tested) in jobs.iter().zip(memos.iter_mut()).zip(&plans).zip(tested) {
        memo.keep_tiles(*plan, &job.candidates, &job.tiles, n, tested);
    }
    for hits in &mut per_collider {
        hits.sort_unstable_by_key(|hit| hit.blade);
    }
    let keys = memos
        .iter()
        .zip(&plans)
        .map(|(memo, &plan)| memo.rest_key(plan))
        .collect();
    (per_collider, keys)
}

/// Whether the blades of `tile` surely have no contact with `tree` (posed
/// at `pose`), judged without moving a vertex into the object's frame:
/// the world box of their vertices is turned into that frame whole (its
/// centre moved like a vertex, its half extents through the absolute
/// rotation matrix: a box around the turned box), grown by [`TILE_PAD_M`]
/// and by the rounding of a vertex's transform, and tested with
/// [`box_clear_of`]. That box holds the padded box of the vertices as
/// [`ColliderNarrow::tile_hits`] moves them, so when it is clear, so is
/// that one (same answers: the narrow phase finds nothing in the tile
/// either way); most tiles beside an object are cleared here, and their
/// vertices are never turned.
fn world_box_clear(sim: &Simulation, tile: &[u32], pose: &Pose, tree: &ObbTree) -> bool {
    let blades = &sim.field.blades;
    let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
    for k in 0..=blades.segments {
        for &b in tile {
            let v = blades.vertex(b as usize, k);
            (lo, hi) = (lo.min(v), hi.max(v));
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return false;
    }
    let (centre, half) = (Vec3::from((lo + hi) * 0.5), Vec3::from((hi - lo) * 0.5));
    let turn = glam::Mat3::from_quat(pose.rotation.inverse());
    let half =
        glam::Mat3::from_cols(turn.x_axis.abs(), turn.y_axis.abs(), turn.z_axis.abs()) * half;
    // A vertex's transform rounds by a few ulps of the coordinates it
    // subtracts and turns; this is far above that.
    let scale =
        Vec3::from(lo.abs().max(hi.abs())).max_element() + pose.position.abs().max_element();
    let pad = Vec3::splat(TILE_PAD_M + 16.0 * f32::EPSILON * scale);
    let at = pose.to_local(centre);
    box_clear_of(
        tree,
        at - half - pad,
        at + half + pad,
        sim.params.precision,
        sim.params.contact_shell_m,
    )
}

/// Cells along a side of the tiles the narrow phase tests as one box
/// ([`box_clear_of`]) and whose final nodes it lists once
/// ([`final_nodes_near`]): 6 × 6 cells, 36 blades at the default density —
/// small enough that most tiles beside an object miss it and the lists stay
/// short, large enough that the tests pay. Measured on `herd_small`
/// (2026-11-26, one thread, narrow phase a step): 2 × 2 cells 72 ms, 3 × 3
/// 58, 4 × 4 52, 6 × 6 50.5, 8 × 8 52; the default scene's is the same at
/// 4 and 6 (0.17 ms).
pub(crate) const TILE_CELLS: usize = 6;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::broad_phase::patches_under;
    use crate::scene::Scene;
    use crate::test_rng::XorShift;
    use glam::Quat;

    /// A tile cleared by its world box has no hit: for a box and a knot
    /// teleported to random poses (turned every way, over the whole field
    /// and partly below the ground) over a field bent by an earlier pass,
    /// every tile [`world_box_clear`]
    /// clears finds nothing when its blades are moved and walked. Most
    /// tiles beside the objects are cleared, and some tiles have hits (the
    /// test is not vacuous).
    #[test]
    fn a_tile_cleared_by_its_world_box_has_no_hit() {
        let mut rng = XorShift(0x6a09_e667_f3bc_c909);
        let (mut cleared, mut walked, mut hit) = (0, 0, 0);
        for shape in [
            r#"{ kind = "box", half_extents_m = [0.7, 0.25, 0.45] }"#,
            r#"{ kind = "knot", size_m = 1.2 }"#,
        ] {
            let text = format!(
                r#"
[field]
patches = [4, 4]
cells_per_patch = 16
[[objects]]
name = "ball"
shape = {shape}
path = {{ kind = "line", from = [-3.0, 0.3, -1.0], to = [3.0, 0.3, 1.0], duration_s = 0.5 }}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 4.0] }}
"#
            );
            let mut sim = Scene::parse(&text, "tiles", std::path::Path::new("."))
                .unwrap()
                .build()
                .unwrap();
            sim.params.track_everywhere = true;
            sim.run(20).unwrap();
            let id = sim.bodies[0].id;
            let h = sim.params.dt_s;
            for _ in 0..40 {
                let at = Vec3::new(
                    rng.range(-4.0, 4.0),
                    rng.range(-0.2, 0.6),
                    rng.range(-4.0, 4.0),
                );
                let turn = Quat::from_scaled_axis(rng.vec(-3.0, 3.0));
                sim.teleport_body(id, at, turn).unwrap();
                let mut patches = Vec::new();
                patches_under(
                    &sim.field.layout,
                    sim.bodies[0].collider(0).world_root,
                    &mut patches,
                );
                let job = ColliderNarrow::new(&sim, &sim.bodies[0], 0, &patches, h);
                let (mut contacts, mut scratch) =
                    (BladeContacts::default(), TileScratch::default());
                for &(start, end) in &job.tiles {
                    let tile = &job.candidates[start as usize..end as usize];
                    let hits = job.turned_tile_hits(&sim, tile, &mut contacts, &mut scratch);
                    if world_box_clear(&sim, tile, &job.pose, job.tree) {
                        assert!(
                            hits.is_empty(),
                            "a cleared tile at {at} has {} hits",
                            hits.len()
                        );
                        cleared += 1;
                    } else {
                        walked += 1;
                        hit += usize::from(!hits.is_empty());
                    }
                }
            }
        }
        assert!(
            cleared > walked && hit > 50,
            "cleared {cleared}, walked {walked}, hit {hit}"
        );
    }
}
