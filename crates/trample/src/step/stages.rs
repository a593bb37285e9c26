//! The stages of one sub-step, in DESIGN §7 order. Each stage is a plain
//! function over the simulation's slices; the equations live in the stage
//! modules (`collision`, `force`, `deform`, `recovery`) and are only called
//! here and in the step modules beside this one (`collide.rs`: narrow phase
//! and forces; `deform.rs`: bending, contact, billboards, transitions;
//! `recover.rs`: recovery).

use super::at_rest::ColliderMemo;
use super::blade_class::BladeClass;
use super::collide::{accumulate_contacts, narrow_phase};
use super::deform::{
    apply_transitions, bend_billboards, bend_blades, cells_from_blades, resolve_contacts,
};
use super::passes::Pass;
use super::recover::recover;
use super::simulation::{Simulation, ms};
use super::timings::StepTimings;
use crate::collision::broad_phase::patches_under;
use crate::field::classify_cells;
use crate::force::propagation::{
    NO_GENERATION, PropagationParams, THRESHOLD_FADE, propagate_forces,
};
use glam::Vec3;
use std::time::Instant;

/// Contact weight from which a blade counts as hit directly (DBG) in a
/// sub-step (ours): its class becomes [`BladeClass::Direct`], it counts in
/// the DBG figures and it follows the touching object's track settings.
///
/// Why not 0: a segment that grazes a box on an exact float tie has weight
/// 0 on one machine and a few ulp on another, and the class of a blade
/// must not depend on that. A tie at 0.01, a generic value, is as rare as
/// any other; and it decides a class, never a position.
pub const DBG_WEIGHT: f32 = 0.01;

/// Contact weight from which a touched blade is wholly an ancestor of
/// propagation (Definition 4: never changed by a neighbour's push); a blade
/// touched more lightly is an ancestor in part and still takes part of a
/// neighbour's push ([`propagate_forces`]), so that the contact weight,
/// which rises continuously from 0, never switches a blade between
/// ancestor and child at once (a jump of `att` times a neighbour's push:
/// centimetres).
pub const HOLD_WEIGHT: f32 = 0.1;

/// How a step of `dt` is split (DESIGN §9, ours): no object may move
/// farther than its own thickness (or one cell, if it is thinner) in one
/// sub-step. `needed` is what that takes, `substeps` what is run: at most
/// `max_substeps`. When `needed` is larger the step is still taken, with
/// `max_substeps`, and the caller records the clamp (see
/// [`super::simulation::SubstepClamp`]): objects may then skip blades.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubstepPlan {
    /// Sub-steps to run, `1..=max_substeps`.
    pub substeps: u32,
    /// Sub-steps the fastest object needs (≥ 1; saturates at `u32::MAX`).
    pub needed: u32,
    /// Index of the body that needs the most (none when no body moves).
    pub fastest: Option<usize>,
}

/// Plans the sub-steps of a step of `dt` from now over every body, as if
/// all ran in one pass: each body's travel (and spin, at its root box's
/// farthest corner from the rotation axis through its origin:
/// [`crate::object::Pose::spin_speed`]) between the step's ends
/// (`body_substeps` with no travel bound). The step itself plans a pass
/// per group of bodies that need like sub-steps ([`super::passes`]); this
/// is the plan of the most any body needs.
pub fn plan_substeps(sim: &Simulation, dt: f32) -> SubstepPlan {
    let needs = sim
        .bodies
        .iter()
        .enumerate()
        .map(|(i, body)| (i, body_substeps(sim, body, sim.time, dt, f32::INFINITY)));
    plan_of_needs(needs, sim.params.max_substeps)
}

/// The plan of bodies that each need `k` sub-steps (`(body index, k)` in
/// ascending index order, as [`body_substeps`] gives them): the most any
/// needs, the first body that needs it, and that many run, at most
/// `max_substeps`.
pub(crate) fn plan_of_needs(
    needs: impl IntoIterator<Item = (usize, u32)>,
    max_substeps: u32,
) -> SubstepPlan {
    let (mut needed, mut fastest) = (1u32, None);
    for (i, k) in needs {
        if k > needed {
            (needed, fastest) = (k, Some(i));
        }
    }
    SubstepPlan {
        substeps: needed.clamp(1, max_substeps),
        needed,
        fastest,
    }
}

/// The sub-steps `body` alone needs over `dt` seconds from `start`
/// (before `max_substeps`; a pass plans its bodies' most with
/// [`plan_of_needs`]): its own mesh's
/// and each part's travel (and spin) over its thickness, and its
/// position's travel over `max_travel`; a mesh whose vertices the host
/// sets ([`Simulation::set_body_vertices`]) also its vertices' farthest
/// travel, over its thickness and over `max_travel`; at least 1 (saturates
/// at `u32::MAX`).
pub(crate) fn body_substeps(
    sim: &Simulation,
    body: &super::Body,
    start: f64,
    dt: f32,
    max_travel: f32,
) -> u32 {
    let t0 = start as f32;
    // What one mesh moving from pose `a` to pose `b` needs.
    let need = |a: &crate::object::Pose, b: &crate::object::Pose, root: &crate::obb::Obb| {
        // How far its farthest point goes by the spin about the origin.
        let spin = 0.5 * (a.spin_speed(root) + b.spin_speed(root)) * dt;
        let moved = a.position.distance(b.position);
        let travel = moved + spin;
        let allowed = (2.0 * root.half.min_element()).max(sim.field.layout.cell_size);
        if travel.is_finite() && allowed > 0.0 {
            // `as` saturates: an absurd speed needs u32::MAX, not a wrap.
            ((travel / allowed).ceil() as u32).max((moved / max_travel).ceil() as u32)
        } else {
            1
        }
    };
    // The body's own mesh, then each part with its own motion.
    let root = &body.tree.nodes[0].obb;
    let mut needed = need(&body.pose_at(t0), &body.pose_at(t0 + dt), root).max(1);
    if let Some(host) = &body.rig.host {
        let travel = host.travel_within(t0, t0 + dt);
        let allowed = (2.0 * root.half.min_element()).max(sim.field.layout.cell_size);
        if travel.is_finite() && allowed > 0.0 {
            let by_mesh =
                ((travel / allowed).ceil() as u32).max((travel / max_travel).ceil() as u32);
            needed = needed.max(by_mesh);
        }
    }
    if !body.parts.is_empty() {
        let (a, b) = (body.part_poses_at(t0), body.part_poses_at(t0 + dt));
        for ((a, b), part) in a.iter().zip(&b).zip(&body.parts) {
            needed = needed.max(need(a, b, &part.tree.nodes[0].obb));
        }
    }
    needed
}

/// Every collider of every body, as (body index, collider index)
/// ([`super::Body::collider`]): the unit the broad phase, the narrow phase
/// and the contact response iterate over.
pub(crate) fn collider_list(sim: &Simulation) -> Vec<(usize, usize)> {
    sim.bodies
        .iter()
        .enumerate()
        .flat_map(|(i, b)| (0..b.collider_count()).map(move |k| (i, k)))
        .collect()
}

/// One sub-step of `pass` ending at time `t`, `h` seconds long: in the
/// main pass every stage; in a far pass ([`super::passes`]) only its
/// bodies are posed and collide, and the levels of detail, the view, the
/// transitions and the recovery (once per step, in the main pass) do not run.
pub(crate) fn substep(sim: &mut Simulation, pass: &Pass, t: f32, h: f32, tm: &mut StepTimings) {
    // Poses.
    let clock = Instant::now();
    for (i, body) in sim.bodies.iter_mut().enumerate() {
        body.pose_for_pass(t, pass.main, pass.has(i));
    }
    tm.poses_ms += ms(clock);

    // LOD per cell from the camera eye.
    let clock = Instant::now();
    // The list's memory is kept from step to step (`Scratch::lod_changes`):
    // a camera that jumps changes half a million cells.
    let mut changes = std::mem::take(&mut sim.scratch.lod_changes);
    changes.clear();
    if pass.main {
        sim.update_view(t);
        let eye = sim.eye();
        tm.lod = classify_cells(
            &sim.field.layout,
            &mut sim.field.cells,
            eye,
            &sim.lod,
            &mut changes,
        );
    }
    tm.lod_ms += ms(clock);

    // Broad phase: patches under each collider's root box (one per rigid
    // body, one per part of an articulated one) of the pass's bodies.
    let clock = Instant::now();
    let mut colliders = collider_list(sim);
    colliders.retain(|&(i, _)| pass.has(i));
    let patch_hits: Vec<Vec<u32>> = colliders
        .iter()
        .map(|&(i, k)| {
            let mut out = Vec::new();
            let root = sim.bodies[i].collider(k).world_root;
            patches_under(&sim.field.layout, root, &mut out);
            out
        })
        .collect();
    tm.broad_ms += ms(clock);

    // Reset what the previous sub-step left in the per-blade work arrays.
    for &b in &sim.scratch.touched {
        let b = b as usize;
        sim.scratch.force[b] = Vec3::ZERO;
        sim.scratch.weight[b] = 0.0;
        sim.scratch.owner_weight[b] = 0.0;
        sim.scratch.mask[b] = 0;
        sim.generation[b] = NO_GENERATION;
    }
    sim.scratch.touched.clear();

    // Narrow phase and EqF per blade (Eq. 2), collider by collider; the
    // blades count as pressed by the collider's body.
    let clock = Instant::now();
    // What each collider kept while at rest (`super::at_rest`), taken out
    // of its body for the sub-step.
    let mut memos: Vec<ColliderMemo> = colliders
        .iter()
        .map(|&(i, k)| {
            let rest = &mut sim.bodies[i].rest;
            if rest.len() <= k {
                rest.resize(k + 1, ColliderMemo::default());
            }
            std::mem::take(&mut rest[k])
        })
        .collect();
    let (found, rest_keys) = narrow_phase(sim, &colliders, &patch_hits, h, &mut memos, tm);
    tm.narrow_ms += ms(clock);
    let clock = Instant::now();
    for (&(i, _), hits) in colliders.iter().zip(&found) {
        accumulate_contacts(sim, i, hits);
    }
    tm.forces_ms += ms(clock);
    let clock = Instant::now();
    sim.scratch.touched.sort_unstable();
    // Every blade touched is an ancestor of propagation, held by its contact
    // weight (see `propagate_forces`); DBG in the paper's sense (class,
    // counts) from DBG_WEIGHT on.
    let dbg = sim.scratch.touched.clone();
    let mut direct = 0;
    for &b in &dbg {
        if sim.scratch.weight[b as usize] >= DBG_WEIGHT {
            sim.class[b as usize] = BladeClass::Direct;
            direct += 1;
        }
    }
    // The main pass's last sub-step, plus the far passes' (their blades).
    tm.dbg_blades = if pass.main {
        direct
    } else {
        tm.dbg_blades + direct
    };
    tm.forces_ms += ms(clock);

    // Propagation to neighbouring blades (Eq. 4).
    let clock = Instant::now();
    let prop = propagate_forces(
        &dbg,
        &sim.field.layout.neighbours,
        &mut sim.scratch.force,
        &mut sim.generation,
        &sim.scratch.weight,
        &PropagationParams {
            att: sim.params.att,
            threshold: sim.params.threshold,
            max_generations: sim.params.max_generations,
            threshold_fade: THRESHOLD_FADE,
            hold_weight: HOLD_WEIGHT,
        },
    );
    // A reached blade follows the owner its pusher had at the end of the
    // generation before (all of a generation's owners are read before any is
    // written, as the GPU's gather and commit passes do).
    let mut i = 0;
    while i < prop.pbg.len() {
        let g = sim.generation[prop.pbg[i] as usize];
        let end = i + prop.pbg[i..]
            .iter()
            .take_while(|&&b| sim.generation[b as usize] == g)
            .count();
        let owners: Vec<u8> = prop.sources[i..end]
            .iter()
            .map(|&s| sim.track_owner.get(s as usize).copied().unwrap_or(0))
            .collect();
        for (&b, owner) in prop.pbg[i..end].iter().zip(owners) {
            if sim.class[b as usize] == BladeClass::Untouched {
                sim.class[b as usize] = BladeClass::Propagated;
            }
            sim.track_owner[b as usize] = owner;
        }
        i = end;
    }
    let pbg = prop.pbg.len() as u32;
    tm.pbg_blades = if pass.main { pbg } else { tm.pbg_blades + pbg };
    tm.generations = if pass.main {
        prop.generations
    } else {
        tm.generations.max(prop.generations)
    };
    tm.propagation_ms += ms(clock);

    // Deformation: blades (Eq. 5–7), the contact response (ours) and, in the
    // paper's mode, billboards (Eq. 8).
    let clock = Instant::now();
    let mut forced: Vec<u32> = sim.scratch.touched.clone();
    forced.extend_from_slice(&prop.pbg);
    forced.sort_unstable();
    forced.dedup();
    sim.scratch.touched.extend_from_slice(&prop.pbg);
    let mut changed = bend_blades(sim, &forced, h);
    tm.deformation_ms += ms(clock);
    let clock = Instant::now();
    if sim.params.contact {
        let moved = resolve_contacts(
            sim,
            &colliders,
            &patch_hits,
            &rest_keys,
            &mut memos,
            &mut tm.reused_blades,
        );
        let n = moved.len() as u32;
        tm.contact_blades = if pass.main { n } else { tm.contact_blades + n };
        changed.extend(moved);
    }
    tm.contact_ms += ms(clock);
    for (&(i, k), memo) in colliders.iter().zip(memos) {
        sim.bodies[i].rest[k] = memo;
    }
    let clock = Instant::now();
    if !sim.params.track_everywhere {
        tm.bbg_cells += bend_billboards(sim, &colliders, &patch_hits);
    }
    tm.deformation_ms += ms(clock);

    // Transitions between levels of detail (Eq. 9–13).
    let clock = Instant::now();
    tm.transitions += changes.len() as u32;
    if sim.params.transitions {
        apply_transitions(sim, &changes);
    }
    sim.scratch.lod_changes = changes;
    tm.transitions_ms += ms(clock);

    // Recovery towards rest; then (ours) the billboards and the flatness of
    // every cell whose blades moved follow its blades (Eq. 9–12).
    let clock = Instant::now();
    if pass.main {
        changed.extend(recover(sim, h));
    }
    tm.recovery_ms += ms(clock);
    if sim.params.track_everywhere {
        let clock = Instant::now();
        if pass.main {
            tm.bbg_cells += cells_from_blades(sim, changed);
        } else {
            // Nothing reads a cell's billboard or flatness in a far pass
            // (no transitions, no recovery there): its cells follow their
            // blades once, after the step's last pass (`far_cells`), not
            // again at every sub-step of every pass over the same cells.
            sim.scratch.far_changed.extend(changed);
        }
        tm.deformation_ms += ms(clock);
    }
}

/// After a step's far passes: the cells of the blades they moved follow
/// their blades (Eq. 9–12, [`cells_from_blades`]) — once for the step, as
/// the main pass does at each of its sub-steps; the same cells, from the
/// same blades, as at the far passes' sub-steps (nothing reads a cell in
/// between).
pub(crate) fn far_cells(sim: &mut Simulation, tm: &mut StepTimings) {
    if sim.scratch.far_changed.is_empty() {
        return;
    }
    let clock = Instant::now();
    let changed = std::mem::take(&mut sim.scratch.far_changed);
    tm.bbg_cells += cells_from_blades(sim, changed);
    tm.deformation_ms += ms(clock);
}

/// The (x, z) rectangle a world box covers, grown by `reach` metres: only
/// cells in it can hold a blade or a billboard (rooted in the cell, at most
/// `reach` long) that meets the box.
pub(crate) fn reach_rect(obb: &crate::obb::Obb, reach: f32) -> ([f32; 2], [f32; 2]) {
    let corners = obb.corners();
    let lo = corners.iter().fold(Vec3::INFINITY, |a, c| a.min(*c)) - Vec3::splat(reach);
    let hi = corners.iter().fold(Vec3::NEG_INFINITY, |a, c| a.max(*c)) + Vec3::splat(reach);
    ([lo.x, lo.z], [hi.x, hi.z])
}

/// Adds blade `b` to the displaced set (recovered each step) if it is not in
/// it. Something other than its recovery moved it: with slow blades
/// recovering in strides it recovers at the next step again, from where
/// it is (the time it owed is dropped: at most a stride of recovery).
pub(crate) fn mark_displaced(sim: &mut Simulation, b: u32) {
    let s = &mut sim.scratch;
    if !s.displaced_flag[b as usize] {
        s.displaced_flag[b as usize] = true;
        s.displaced.push(b);
    }
    if let Some(clock) = s.recover_clock.get_mut(b as usize) {
        *clock = [0.0; 2];
    }
}

/// Sorts `v` whose first `sorted` values are ascending (the caller knows
/// where it appended): the rest is sorted alone and merged in from the
/// back, moving only the values of the prefix above the smallest appended
/// one — no pass over the whole set to find its order. The same result as
/// sorting all of it. The displaced blades and the bent cells hold the
/// whole lasting track (the herd: ~320 k of each after 5 s): sorted whole
/// every sub-step they cost 1.7 ms for the cells alone, found in order by a
/// pass and merged ~1 ms; so they are put in order only where they are
/// walked or filtered (`Scratch::sort_displaced`, `Scratch::sort_bent`;
/// BENCHMARKS.md, session 20).
pub(crate) fn merge_appended(v: &mut Vec<u32>, sorted: usize) {
    debug_assert!(
        v[..sorted.min(v.len())].is_sorted(),
        "merge_appended: prefix not in order"
    );
    if sorted >= v.len() {
        return;
    }
    let mut tail = v.split_off(sorted);
    tail.sort_unstable();
    let (mut i, mut j) = (v.len(), tail.len());
    v.resize(i + j, 0);
    let mut w = v.len();
    while j > 0 {
        w -= 1;
        if i > 0 && v[i - 1] > tail[j - 1] {
            v[w] = v[i - 1];
            i -= 1;
        } else {
            v[w] = tail[j - 1];
            j -= 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::merge_appended;
    use crate::test_rng::XorShift;

    /// Whatever was appended to a sorted set (nothing, one, many, smaller,
    /// larger or equal values), the set ends as `sort_unstable` leaves it.
    #[test]
    fn sorting_an_appended_tail_gives_the_whole_sort() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        for case in 0..400 {
            let prefix = (rng.unit() * 300.0) as usize;
            let tail = if case % 5 == 0 {
                0
            } else {
                (rng.unit() * 60.0) as usize
            };
            let range = if case % 3 == 0 { 20.0 } else { 1e5 };
            let mut v: Vec<u32> = (0..prefix).map(|_| (rng.unit() * range) as u32).collect();
            v.sort_unstable();
            v.extend((0..tail).map(|_| (rng.unit() * range) as u32));
            let mut want = v.clone();
            want.sort_unstable();
            merge_appended(&mut v, prefix);
            assert_eq!(v, want, "case {case}: merged after {prefix}");
        }
    }
}
