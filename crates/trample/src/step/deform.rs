//! Stages 7–8 of a sub-step (DESIGN §7): bending of the blades with a force
//! (Eq. 5–7), the contact response (ours), the billboards (Eq. 8 in the
//! paper's mode; from their blades, Eq. 9–12, otherwise) and the
//! transitions between levels of detail (Eq. 9–13).

use super::at_rest::{ColliderMemo, RestKey, RestingBlades};
use super::contact_hints::ContactHints;
use super::simulation::Simulation;
use super::stages::{mark_displaced, reach_rect};
use crate::collision::contact::NO_HINT;
use crate::collision::segment_obb::segment_hits_obb;
use crate::deform::bend::{bend_blade, weights};
use crate::deform::billboard::{billboard_slope, billboard_top, deflect_billboard};
use crate::deform::contact::resolve_contact_hinted;
use crate::deform::transition::{
    bend_last_segment, cell_offset_and_flatness, offset_from_slope, slope_from_offset,
};
use crate::field::generate::GROUND_CLEARANCE_M;
use crate::field::{Lod, LodChange, MAX_SEGMENTS};
use glam::{Vec3, Vec3A};
use rayon::prelude::*;

/// Bends every blade with a force (Eq. 5–7) by the displacement `F · h`
/// (frame-rate independence, DESIGN §6), dividing by the blade's contact
/// weight where it is above 1 (Eq. 5's `num`, each segment counted by its
/// weight; PBG count 1). Returns the blades that moved (ascending) and
/// marks them displaced.
pub(crate) fn bend_blades(sim: &mut Simulation, forced: &[u32], h: f32) -> Vec<u32> {
    let blades = &sim.field.blades;
    let n = blades.segments;
    let w = weights(n, sim.params.weight_a, sim.params.weight_b);
    let terrain = &sim.field.terrain;
    let (force, weight) = (&sim.scratch.force, &sim.scratch.weight);
    // One work slot of n + 1 vertices per forced blade (not MAX_SEGMENTS + 1:
    // with the whole field under an object this list is as large as the
    // field's vertices).
    let mut work = vec![Vec3A::ZERO; forced.len() * (n + 1)];
    let mut moved = vec![false; forced.len()];
    work.par_chunks_mut(n + 1)
        .zip(moved.par_iter_mut())
        .zip(forced.par_iter())
        .for_each(|((v, moved), &b)| {
            let bi = b as usize;
            blades.load(bi, v);
            let mut before = [Vec3A::ZERO; MAX_SEGMENTS + 1];
            before[..=n].copy_from_slice(v);
            bend_blade(
                v,
                blades.seg_len[bi],
                force[bi] * h,
                weight[bi],
                &w[..n],
                terrain,
                GROUND_CLEARANCE_M,
            );
            *moved = v != &before[..=n];
        });
    let stored: Vec<(u32, u32)> = (0..forced.len() as u32)
        .filter(|&i| moved[i as usize])
        .map(|i| (forced[i as usize], i))
        .collect();
    sim.field.blades.store_slots(&stored, &work);
    let mut out = Vec::with_capacity(stored.len());
    for &(b, _) in &stored {
        mark_displaced(sim, b);
        out.push(b);
    }
    out
}

/// The contact response (ours, DESIGN §5): for each collider in order (the
/// bodies in order, each body's own mesh then its parts), every
/// blade some object touched this sub-step (a segment mask, from the narrow
/// phase) in the patches the broad phase listed for it is moved out of it
/// ([`crate::deform::contact::resolve_contact`], from the lowest vertex touched). The GPU path runs
/// the same sets: one dispatch per object over its listed patches. Returns
/// the blades that moved and marks them displaced.
pub(crate) fn resolve_contacts(
    sim: &mut Simulation,
    colliders: &[(usize, usize)],
    patch_hits: &[Vec<u32>],
    keys: &[Option<RestKey>],
    memos: &mut [ColliderMemo],
    reused: &mut u32,
) -> Vec<u32> {
    let n = sim.field.blades.segments;
    let per_patch = sim.field.layout.cells_in_patch() * sim.field.layout.blades_per_cell as usize;
    let mut touched: Vec<u32> = sim
        .scratch
        .touched
        .iter()
        .copied()
        .filter(|&b| sim.scratch.mask[b as usize] != 0)
        .collect();
    touched.sort_unstable();
    touched.dedup();
    let mut out = Vec::new();
    for (((&(i, k), patches), &key), memo) in colliders.iter().zip(patch_hits).zip(keys).zip(memos)
    {
        let collider = sim.bodies[i].collider(k);
        // The touched blades in the collider's patches: blades are stored
        // patch by patch and `touched` is sorted, so each listed patch
        // (ascending) is one range of it — found by two binary searches,
        // not by testing every touched blade against every collider.
        let mut list: Vec<u32> = Vec::new();
        for &p in patches {
            let (first, end) = (p as usize * per_patch, (p as usize + 1) * per_patch);
            let lo = touched.partition_point(|&b| (b as usize) < first);
            let hi = touched.partition_point(|&b| (b as usize) < end);
            list.extend_from_slice(&touched[lo..hi]);
        }
        if list.is_empty() {
            memo.keep_blades(None, RestingBlades::default());
            memo.hints = ContactHints::default();
            continue;
        }
        let blades = &sim.field.blades;
        let terrain = &sim.field.terrain;
        let mask = &sim.scratch.mask;
        let kept: &ColliderMemo = memo;
        let mut work = vec![Vec3A::ZERO; list.len() * (n + 1)];
        // Per blade: whether it moved, whether it is where it was found (a
        // fixed point a collider at rest keeps, `super::at_rest`), and
        // whether it was left without a query (kept so before).
        let mut moved = vec![(false, false, false); list.len()];
        // Each vertex's closest triangle, from the collider's sub-step
        // before and for its next (`super::contact_hints`).
        let mut hints = vec![[NO_HINT; MAX_SEGMENTS + 1]; list.len()];
        work.par_chunks_mut(n + 1)
            .zip(moved.par_iter_mut())
            .zip(hints.par_iter_mut())
            .zip(list.par_iter())
            .for_each(|(((v, moved), hint), &b)| {
                *hint = kept.hints.of(b, n + 1);
                let b = b as usize;
                blades.load(b, v);
                let first = mask[b].trailing_zeros();
                let seg_len = blades.seg_len[b];
                if let Some(was) = kept.kept_blade(key, b as u32, first, seg_len, v) {
                    *moved = (was, true, true);
                    return;
                }
                // Only a collider at rest keeps fixed points: a moving one
                // copies and compares nothing.
                let before = key.map(|_| {
                    let mut copy = [Vec3A::ZERO; MAX_SEGMENTS + 1];
                    copy[..=n].copy_from_slice(v);
                    copy
                });
                let m = resolve_contact_hinted(
                    v,
                    seg_len,
                    first as usize,
                    collider.pose,
                    collider.tree,
                    terrain,
                    GROUND_CLEARANCE_M,
                    seg_len,
                    hint,
                );
                let fixed = before.is_some_and(|before| {
                    v.iter().zip(&before).all(|(a, b)| {
                        a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
                    })
                });
                *moved = (m, fixed, false);
            });
        let mut resting = memo.resting_buffers(n + 1);
        let mut stored = Vec::new();
        for (i, ((v, &b), &(m, fixed, skipped))) in
            work.chunks_exact(n + 1).zip(&list).zip(&moved).enumerate()
        {
            *reused += u32::from(skipped);
            if m {
                out.push(b);
                // A blade the response pushed back to its own bits is not
                // stored again: the step would list it as changed
                // (`Field::changed_blades`) and a host upload it for
                // nothing (3–4 k blades a step under the parked herd). A
                // blade found at its fixed point (or taken from the memo)
                // is known to be; any other is compared with what is stored.
                let blades = &sim.field.blades;
                let same = fixed
                    || v.iter().enumerate().all(|(k, v)| {
                        blades.pos[k * blades.count + b as usize]
                            .pos
                            .map(f32::to_bits)
                            == v.to_array().map(f32::to_bits)
                    });
                if !same {
                    stored.push((b, i as u32));
                }
            }
            if fixed {
                let first = sim.scratch.mask[b as usize].trailing_zeros();
                let seg_len = sim.field.blades.seg_len[b as usize];
                resting.push(b, first, seg_len, m, v);
            }
        }
        sim.field.blades.store_slots(&stored, &work);
        memo.keep_blades(key, resting);
        memo.hints = ContactHints::keep(list, &hints, n + 1);
    }
    for &b in &out {
        mark_displaced(sim, b);
    }
    out
}

/// Eq. 8 for billboard cells whose skeleton line (base centre → top) meets
/// an object's root box; returns how many were deflected. The cells tested
/// are those within a blade's length of the box (a billboard as tall as
/// its blades can lean into the box from a cell beside it). The paper's
/// mode only (`sim.track_everywhere = false`): otherwise billboards follow
/// their blades ([`cells_from_blades`]).
pub(crate) fn bend_billboards(
    sim: &mut Simulation,
    colliders: &[(usize, usize)],
    patch_hits: &[Vec<u32>],
) -> u32 {
    let mut deflected = 0;
    let reach = sim.field.max_blade_length;
    for (&(i, k), patches) in colliders.iter().zip(patch_hits) {
        let obb = *sim.bodies[i].collider(k).world_root;
        let r = obb.half_diagonal();
        let (min, max) = reach_rect(&obb, reach);
        for &p in patches {
            for c in sim
                .field
                .layout
                .patch_cells_overlapping(p as usize, min, max)
            {
                let cells = &mut sim.field.cells;
                // A cell without grass (grass maps) has a billboard of height 0.
                if cells.lod[c] != Lod::Billboard || cells.height[c] <= 0.0 {
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
                let slope = deflect_billboard(cells.slope[c], cells.slope_origin[c], candidate);
                cells.set_slope(c, slope);
                if !sim.scratch.bent_flag[c] {
                    sim.scratch.bent_flag[c] = true;
                    sim.scratch.bent_cells.push(c as u32);
                }
                deflected += 1;
            }
        }
    }
    deflected
}

/// Per-cell transitions (DESIGN §6). Geometry → billboard/texture: the
/// billboard takes its blades' mean offset (Eq. 9–12). Billboard/texture →
/// geometry: the part of the billboard's offset (Eq. 13) that the blades do
/// not already show acts on their last segment through Eq. 5 — nothing
/// when the billboard follows its blades (`sim.track_everywhere`).
pub(crate) fn apply_transitions(sim: &mut Simulation, changes: &[LodChange]) {
    let bpc = sim.field.layout.blades_per_cell as usize;
    let n = sim.field.blades.segments;
    for ch in changes {
        let c = ch.cell as usize;
        let blades_of_cell = c * bpc..(c + 1) * bpc;
        // Eq. 9–11's mean offset, read from the cell's blades only where a
        // transition uses it: a cell passing between billboard and texture
        // (most of the changes when the camera jumps) reads nothing.
        let off_g = || cell_offset_and_flatness(&sim.field.blades, blades_of_cell.clone()).0;
        match (ch.from, ch.to) {
            (Lod::Geometry, _) => {
                let off_g = off_g();
                let cells = &mut sim.field.cells;
                cells.set_slope(c, slope_from_offset(cells.slope_origin[c], off_g));
                if !cells.slope_at_rest(c) && !sim.scratch.bent_flag[c] {
                    sim.scratch.bent_flag[c] = true;
                    sim.scratch.bent_cells.push(ch.cell);
                }
            }
            // Track everywhere: the blades hold the track already (and the
            // billboard follows them), no guess from the slope (DESIGN §6).
            (_, Lod::Geometry) if sim.params.track_everywhere => {}
            (_, Lod::Geometry) => {
                let off_g = off_g();
                let cells = &sim.field.cells;
                let missing = offset_from_slope(cells.slope[c], cells.slope_origin[c]) - off_g;
                if missing.length_squared() < 1e-12 {
                    continue;
                }
                for b in blades_of_cell {
                    let bl = &mut sim.field.blades;
                    if !bl.is_present(b) {
                        continue;
                    }
                    let rest_h = Vec3::from(bl.rest_vertex(b, n) - bl.rest_vertex(b, 0)).length();
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
}

/// Track everywhere (ours, DESIGN §2): every cell holding a blade of
/// `changed` takes its billboard slope from its blades (Eq. 9–12, whatever
/// its level of detail) and its flatness; the set of bent billboards
/// follows. Returns how many cells were updated.
pub(crate) fn cells_from_blades(sim: &mut Simulation, changed: Vec<u32>) -> u32 {
    let bpc = sim.field.layout.blades_per_cell;
    let mut cells: Vec<u32> = changed.into_iter().map(|b| b / bpc).collect();
    cells.sort_unstable();
    cells.dedup();
    let bpc = bpc as usize;
    let blades = &sim.field.blades;
    let state: Vec<(Vec3, f32)> = cells
        .par_iter()
        .map(|&c| cell_offset_and_flatness(blades, c as usize * bpc..(c as usize + 1) * bpc))
        .collect();
    let f = &mut sim.field.cells;
    let s = &mut sim.scratch;
    // Cells newly bent are appended (`Scratch::bent_cells`), and the set
    // filtered only when one came back to rest: no pass over the whole set
    // otherwise (it holds the whole lasting track).
    let mut unbent = false;
    for (&c, &(off, flat)) in cells.iter().zip(&state) {
        let c = c as usize;
        f.set_slope(c, slope_from_offset(f.slope_origin[c], off));
        f.flatness[c] = flat;
        let bent = !f.slope_at_rest(c);
        if bent != s.bent_flag[c] {
            s.bent_flag[c] = bent;
            if bent {
                s.bent_cells.push(c as u32);
            } else {
                unbent = true;
            }
        }
    }
    if unbent {
        s.retain_bent(|_, bent| bent);
    }
    cells.len() as u32
}
