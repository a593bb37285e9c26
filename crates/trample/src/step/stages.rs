//! The stages of one sub-step, in DESIGN §7 order. Each stage is a plain
//! function over the simulation's slices; the equations live in the stage
//! modules (`collision`, `force`, `deform`, `recovery`) and are only called here.

use super::simulation::{BladeClass, Simulation, ms};
use super::timings::StepTimings;
use crate::collision::broad_phase::patches_hit;
use crate::collision::narrow_phase::{BladeContacts, collide_blade};
use crate::collision::segment_obb::segment_hits_obb;
use crate::deform::bend::{bend_blade, weights};
use crate::deform::billboard::{billboard_slope, billboard_top, deflect_billboard};
use crate::deform::transition::{
    bend_last_segment, blade_offset, mean_offset, offset_from_slope, slope_from_offset,
};
use crate::field::generate::GROUND_CLEARANCE_M;
use crate::field::{Lod, LodChange, MAX_SEGMENTS, classify_cells};
use crate::force::eqf::eqf;
use crate::force::propagation::{NO_GENERATION, PropagationParams, propagate_forces};
use crate::recovery::{RecoveryParams, recover_blade, recover_slope};
use glam::{Vec3, Vec3A};
use rayon::prelude::*;
use std::time::Instant;

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

/// Plans the sub-steps of a step of `dt` from each body's travel (and spin,
/// measured at the root box's half diagonal) between the step's ends.
pub fn plan_substeps(sim: &Simulation, dt: f32) -> SubstepPlan {
    let t0 = sim.time as f32;
    let (mut needed, mut fastest) = (1u32, None);
    for (i, body) in sim.bodies.iter().enumerate() {
        let (a, b) = (body.pose_at(t0), body.pose_at(t0 + dt));
        let root = body.tree.nodes[0].obb;
        let spin = 0.5
            * (a.angular_velocity.length() + b.angular_velocity.length())
            * root.half_diagonal()
            * dt;
        let travel = a.position.distance(b.position) + spin;
        let allowed = (2.0 * root.half.min_element()).max(sim.field.layout.cell_size);
        if travel.is_finite() && allowed > 0.0 {
            // `as` saturates: an absurd speed needs u32::MAX, not a wrap.
            let k = (travel / allowed).ceil() as u32;
            if k > needed {
                (needed, fastest) = (k, Some(i));
            }
        }
    }
    SubstepPlan {
        substeps: needed.clamp(1, sim.params.max_substeps),
        needed,
        fastest,
    }
}

/// One sub-step ending at time `t`, `h` seconds long.
pub(crate) fn substep(sim: &mut Simulation, t: f32, h: f32, tm: &mut StepTimings) {
    // Poses.
    let clock = Instant::now();
    for body in &mut sim.bodies {
        body.set_time(t);
    }
    tm.poses_ms += ms(clock);

    // LOD per cell from the camera eye.
    let clock = Instant::now();
    let positions: Vec<Vec3> = sim.bodies.iter().map(|b| b.pose.position).collect();
    sim.view = sim.camera.view_at(t, &positions);
    let mut changes = Vec::new();
    tm.lod = classify_cells(
        &sim.field.layout,
        &mut sim.field.cells,
        sim.view.eye,
        &sim.lod,
        &mut changes,
    );
    tm.lod_ms += ms(clock);

    // Broad phase: patches under each object's root box.
    let clock = Instant::now();
    let patch_hits: Vec<Vec<u32>> = sim
        .bodies
        .iter()
        .map(|b| {
            let mut out = Vec::new();
            patches_hit(&sim.field.layout.patch_list, &b.world_root, &mut out);
            out
        })
        .collect();
    tm.broad_ms += ms(clock);

    // Reset what the previous sub-step left in the per-blade work arrays.
    for &b in &sim.scratch.touched {
        let b = b as usize;
        sim.scratch.force[b] = Vec3::ZERO;
        sim.scratch.num[b] = 0;
        sim.generation[b] = NO_GENERATION;
    }
    sim.scratch.touched.clear();

    // Narrow phase and EqF per geometric blade (Eq. 2), object by object.
    for (body, hits) in sim.bodies.iter().zip(&patch_hits) {
        let clock = Instant::now();
        let contacts = narrow_phase(sim, body, hits, tm);
        tm.narrow_ms += ms(clock);
        let clock = Instant::now();
        for (b, force, num) in contacts {
            let bi = b as usize;
            if sim.scratch.num[bi] == 0 {
                sim.scratch.touched.push(b);
            }
            sim.scratch.force[bi] += force;
            sim.scratch.num[bi] = sim.scratch.num[bi].saturating_add(num);
        }
        tm.forces_ms += ms(clock);
    }
    let clock = Instant::now();
    sim.scratch.touched.sort_unstable();
    let dbg = sim.scratch.touched.clone();
    for &b in &dbg {
        sim.generation[b as usize] = 0;
        sim.class[b as usize] = BladeClass::Direct as u8;
    }
    tm.dbg_blades = dbg.len() as u32;
    tm.forces_ms += ms(clock);

    // Propagation to neighbouring blades (Eq. 4).
    let clock = Instant::now();
    let prop = propagate_forces(
        &dbg,
        &sim.field.layout.neighbours,
        &mut sim.scratch.force,
        &mut sim.generation,
        &PropagationParams {
            att: sim.params.att,
            threshold: sim.params.threshold,
            max_generations: sim.params.max_generations,
        },
    );
    for &b in &prop.pbg {
        if sim.class[b as usize] == BladeClass::Untouched as u8 {
            sim.class[b as usize] = BladeClass::Propagated as u8;
        }
    }
    sim.scratch.touched.extend_from_slice(&prop.pbg);
    tm.pbg_blades = prop.pbg.len() as u32;
    tm.generations = prop.generations;
    tm.propagation_ms += ms(clock);

    // Deformation: blades (Eq. 5–7) and billboards (Eq. 8).
    let clock = Instant::now();
    let forced: Vec<u32> = dbg.iter().chain(&prop.pbg).copied().collect();
    bend_blades(sim, &forced, h);
    tm.bbg_cells += bend_billboards(sim, &patch_hits);
    tm.deformation_ms += ms(clock);

    // Transitions between levels of detail (Eq. 9–13).
    let clock = Instant::now();
    tm.transitions += changes.len() as u32;
    if sim.params.transitions {
        apply_transitions(sim, &changes);
    }
    tm.transitions_ms += ms(clock);

    // Recovery towards rest.
    let clock = Instant::now();
    recover(sim, h);
    tm.recovery_ms += ms(clock);
}

/// Narrow phase for one body: every geometric blade in the patches its root
/// box overlaps, segments moved into the body's frame once and tested down
/// to the precision; returns (blade, Σ EqF over hit segments, hit count).
fn narrow_phase(
    sim: &Simulation,
    body: &super::simulation::Body,
    patches: &[u32],
    tm: &mut StepTimings,
) -> Vec<(u32, Vec3, u8)> {
    let layout = &sim.field.layout;
    let bpc = layout.blades_per_cell as usize;
    let (min, max) = reach_rect(&body.world_root, sim.field.max_blade_length);
    let candidates: Vec<u32> = patches
        .iter()
        .flat_map(|&p| layout.patch_cells_overlapping(p as usize, min, max))
        .filter(|&c| sim.field.cells.lod[c] == Lod::Geometry)
        .flat_map(|c| (c * bpc) as u32..((c + 1) * bpc) as u32)
        .collect();
    tm.narrow_candidates += candidates.len() as u32;
    let blades = &sim.field.blades;
    let n = blades.segments;
    let pose = body.pose;
    let precision = sim.params.precision;
    candidates
        .par_iter()
        .map_init(BladeContacts::default, |contacts, &b| {
            let mut local = [Vec3::ZERO; MAX_SEGMENTS + 1];
            for (k, v) in local.iter_mut().enumerate().take(n + 1) {
                *v = pose.to_local(Vec3::from(blades.vertex(b as usize, k)));
            }
            collide_blade(&local[..=n], &body.tree, precision, contacts);
            if contacts.mask == 0 {
                return None;
            }
            let mut force = Vec3::ZERO;
            for k in 0..n {
                if contacts.mask & (1 << k) != 0 {
                    let c = contacts.contacts[k];
                    let speed = pose.point_velocity(pose.to_world(c.point)).length();
                    force += eqf(speed, pose.rotation * c.dir);
                }
            }
            Some((b, force, contacts.mask.count_ones() as u8))
        })
        .flatten()
        .collect()
}

/// Bends every blade with a force (Eq. 5–7) by the displacement `F · h`
/// (frame-rate independence, DESIGN §6); DBG divide by their hit count, PBG by 1.
fn bend_blades(sim: &mut Simulation, forced: &[u32], h: f32) {
    let blades = &sim.field.blades;
    let n = blades.segments;
    let w = weights(n, sim.params.weight_a, sim.params.weight_b);
    let terrain = &sim.field.terrain;
    let (force, num) = (&sim.scratch.force, &sim.scratch.num);
    // One work slot of n + 1 vertices per forced blade (not MAX_SEGMENTS + 1:
    // with the whole field under an object this list is as large as the
    // field's vertices).
    let mut work = vec![Vec3A::ZERO; forced.len() * (n + 1)];
    work.par_chunks_mut(n + 1)
        .zip(forced.par_iter())
        .for_each(|(v, &b)| {
            let bi = b as usize;
            blades.load(bi, v);
            let count = u32::from(num[bi].max(1));
            bend_blade(
                v,
                blades.seg_len[bi],
                force[bi] * h,
                count,
                &w[..n],
                terrain,
                GROUND_CLEARANCE_M,
            );
        });
    for (v, &b) in work.chunks_exact(n + 1).zip(forced) {
        sim.field.blades.store(b as usize, v);
        mark_displaced(sim, b);
    }
}

/// Eq. 8 for billboard cells whose skeleton line (base centre → top) meets
/// an object's root box; returns how many were deflected. The cells tested
/// are those within a blade's length of the box (a billboard as tall as
/// its blades can lean into the box from a cell beside it).
fn bend_billboards(sim: &mut Simulation, patch_hits: &[Vec<u32>]) -> u32 {
    let mut deflected = 0;
    let reach = sim.field.max_blade_length;
    for (body, patches) in sim.bodies.iter().zip(patch_hits) {
        let obb = body.world_root;
        let r = obb.half_diagonal();
        let (min, max) = reach_rect(&obb, reach);
        for &p in patches {
            for c in sim
                .field
                .layout
                .patch_cells_overlapping(p as usize, min, max)
            {
                let cells = &mut sim.field.cells;
                if cells.lod[c] != Lod::Billboard {
                    continue;
                }
                let (base, height) = (cells.base[c], cells.height[c]);
                let top = billboard_top(
                    base,
                    cells.slope[c],
                    height,
                    &sim.field.terrain,
                    GROUND_CLEARANCE_M,
                );
                if !segment_hits_obb(base, top, &obb) {
                    continue;
                }
                let centre = 0.5 * (base + top);
                let candidate = billboard_slope(cells.slope_origin[c], centre - obb.center, r);
                cells.slope[c] =
                    deflect_billboard(cells.slope[c], cells.slope_origin[c], candidate);
                if !sim.scratch.bent_flag[c] {
                    sim.scratch.bent_flag[c] = true;
                    sim.scratch.bent_cells.push(c as u32);
                }
                deflected += 1;
            }
        }
    }
    sim.scratch.bent_cells.sort_unstable();
    deflected
}

/// Per-cell transitions (DESIGN §6). Geometry → billboard/texture: the
/// billboard takes its blades' mean offset (Eq. 9–12). Billboard/texture →
/// geometry: the part of the billboard's offset (Eq. 13) that the blades do
/// not already show acts on their last segment through Eq. 5.
fn apply_transitions(sim: &mut Simulation, changes: &[LodChange]) {
    let bpc = sim.field.layout.blades_per_cell as usize;
    let n = sim.field.blades.segments;
    for ch in changes {
        let c = ch.cell as usize;
        let blades_of_cell = c * bpc..(c + 1) * bpc;
        let off_g = {
            let bl = &sim.field.blades;
            mean_offset(blades_of_cell.clone().map(|b| {
                let chord = Vec3::from(bl.vertex(b, n) - bl.vertex(b, 0));
                let rest = Vec3::from(bl.rest[n * bl.count + b] - bl.rest[b]);
                blade_offset(chord, rest)
            }))
        };
        let cells = &mut sim.field.cells;
        match (ch.from, ch.to) {
            (Lod::Geometry, _) => {
                cells.slope[c] = slope_from_offset(cells.slope_origin[c], off_g);
                if !cells.slope_at_rest(c) && !sim.scratch.bent_flag[c] {
                    sim.scratch.bent_flag[c] = true;
                    sim.scratch.bent_cells.push(ch.cell);
                }
            }
            (_, Lod::Geometry) => {
                let missing = offset_from_slope(cells.slope[c], cells.slope_origin[c]) - off_g;
                if missing.length_squared() < 1e-12 {
                    continue;
                }
                for b in blades_of_cell {
                    let bl = &mut sim.field.blades;
                    let rest_h = Vec3::from(bl.rest[n * bl.count + b] - bl.rest[b]).length();
                    let mut v = [Vec3A::ZERO; MAX_SEGMENTS + 1];
                    bl.load(b, &mut v);
                    bend_last_segment(
                        &mut v[..=n],
                        bl.seg_len[b],
                        missing * rest_h,
                        &sim.field.terrain,
                        GROUND_CLEARANCE_M,
                    );
                    bl.store(b, &v[..=n]);
                    mark_displaced(sim, b as u32);
                }
            }
            _ => {}
        }
    }
    sim.scratch.bent_cells.sort_unstable();
    sim.scratch.bent_cells.dedup();
    sim.scratch.displaced.sort_unstable();
}

/// Relaxes displaced blades and bent billboards towards rest (DESIGN §6).
fn recover(sim: &mut Simulation, h: f32) {
    sim.scratch.displaced.sort_unstable();
    if sim.params.recovery_s.is_infinite() {
        return;
    }
    let p = RecoveryParams {
        recovery_s: sim.params.recovery_s,
        trail: sim.params.trail,
    };
    let blades = &sim.field.blades;
    let n = blades.segments;
    let terrain = &sim.field.terrain;
    // One work slot of n + 1 vertices per displaced blade (see bend_blades).
    let displaced = &sim.scratch.displaced;
    let mut work = vec![Vec3A::ZERO; displaced.len() * (n + 1)];
    let mut done = vec![false; displaced.len()];
    work.par_chunks_mut(n + 1)
        .zip(done.par_iter_mut())
        .zip(displaced.par_iter())
        .for_each(|((v, done), &b)| {
            let bi = b as usize;
            let mut rest = [Vec3A::ZERO; MAX_SEGMENTS + 1];
            blades.load(bi, v);
            blades.load_rest(bi, &mut rest);
            *done = recover_blade(
                v,
                &rest[..=n],
                blades.seg_len[bi],
                h,
                &p,
                terrain,
                GROUND_CLEARANCE_M,
            );
        });
    let mut still = Vec::with_capacity(displaced.len());
    for ((v, &done), &b) in work.chunks_exact(n + 1).zip(&done).zip(displaced) {
        sim.field.blades.store(b as usize, v);
        if done {
            sim.scratch.displaced_flag[b as usize] = false;
        } else {
            still.push(b);
        }
    }
    sim.scratch.displaced = still;
    let cells = &mut sim.field.cells;
    let flags = &mut sim.scratch.bent_flag;
    sim.scratch.bent_cells.retain(|&c| {
        let c = c as usize;
        let done = recover_slope(&mut cells.slope[c], cells.slope_origin[c], h, &p);
        if done {
            flags[c] = false;
        }
        !done
    });
}

/// The (x, z) rectangle a world box covers, grown by `reach` metres: only
/// cells in it can hold a blade or a billboard (rooted in the cell, at most
/// `reach` long) that meets the box.
fn reach_rect(obb: &crate::obb::Obb, reach: f32) -> ([f32; 2], [f32; 2]) {
    let corners = obb.corners();
    let lo = corners.iter().fold(Vec3::INFINITY, |a, c| a.min(*c)) - Vec3::splat(reach);
    let hi = corners.iter().fold(Vec3::NEG_INFINITY, |a, c| a.max(*c)) + Vec3::splat(reach);
    ([lo.x, lo.z], [hi.x, hi.z])
}

fn mark_displaced(sim: &mut Simulation, b: u32) {
    if !sim.scratch.displaced_flag[b as usize] {
        sim.scratch.displaced_flag[b as usize] = true;
        sim.scratch.displaced.push(b);
    }
}
