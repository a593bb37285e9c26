//! Stages 4–5 of a sub-step (DESIGN §7): the narrow phase of one object over
//! the blades the broad phase kept, and the forces of Eq. 2 it gives.

use super::body::Body;
use super::simulation::Simulation;
use super::stages::{DBG_WEIGHT, reach_rect};
use super::timings::StepTimings;
use crate::collision::narrow_phase::{BladeContacts, LocalMotion, contact_blade};
use crate::field::{Lod, MAX_SEGMENTS};
use crate::force::eqf::eqf;
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

/// Narrow phase for collider `k` of one body ([`Body::collider`]: its own
/// mesh or one of its parts, with its own pose and velocities): every
/// blade in the patches its root box
/// overlaps (only those of geometric cells in the paper's mode,
/// `sim.track_everywhere = false`), segments moved into the body's frame
/// once and tested down to the precision with the contact shell
/// ([`contact_blade`], weights set by the object's travel in the sub-step
/// of `h` seconds); returns the blades touched, ascending, with
/// `Σ_k w_k · press · |v + ω × r + R · v_k| · EqN_k` (Eq. 2 per segment,
/// weighted; `v_k` the deforming mesh's own velocity at the contact,
/// [`crate::collision::narrow_phase::SegmentContact::velocity`]).
pub(crate) fn narrow_phase(
    sim: &Simulation,
    body: &Body,
    k: usize,
    patches: &[u32],
    h: f32,
    tm: &mut StepTimings,
) -> Vec<BladeHit> {
    let layout = &sim.field.layout;
    let bpc = layout.blades_per_cell as usize;
    let shell = sim.params.contact_shell_m;
    let collider = body.collider(k);
    let (min, max) = reach_rect(collider.world_root, sim.field.max_blade_length + shell);
    let everywhere = sim.params.track_everywhere;
    let mut candidates: Vec<u32> = patches
        .iter()
        .flat_map(|&p| layout.patch_cells_overlapping(p as usize, min, max))
        .filter(|&c| everywhere || sim.field.cells.lod[c] == Lod::Geometry)
        .flat_map(|c| (c * bpc) as u32..((c + 1) * bpc) as u32)
        .collect();
    if sim.field.absent_blades > 0 {
        // Blades a grass map left out are not grass: nothing collides with them.
        candidates.retain(|&b| sim.field.blades.is_present(b as usize));
    }
    tm.narrow_candidates += candidates.len() as u32;
    let blades = &sim.field.blades;
    let n = blades.segments;
    let pose = *collider.pose;
    let tree = collider.tree;
    let press = body.object.track.press;
    let precision = sim.params.precision;
    let inverse = pose.rotation.inverse();
    let motion = LocalMotion {
        velocity: inverse * pose.velocity,
        angular_velocity: inverse * pose.angular_velocity,
        h,
        thickness: 2.0 * tree.nodes[0].obb.half.min_element(),
    };
    candidates
        .par_iter()
        .map_init(BladeContacts::default, |contacts, &b| {
            let mut local = [Vec3::ZERO; MAX_SEGMENTS + 1];
            for (k, v) in local.iter_mut().enumerate().take(n + 1) {
                *v = pose.to_local(Vec3::from(blades.vertex(b as usize, k)));
            }
            contact_blade(&local[..=n], tree, precision, shell, &motion, contacts);
            if contacts.mask == 0 {
                return None;
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
                    force += eqf(speed, pose.rotation * c.dir) * (c.weight * press);
                }
            }
            Some(BladeHit {
                blade: b,
                force,
                weight: contacts.weight_sum(),
                mask: contacts.mask,
            })
        })
        .flatten()
        .collect()
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
