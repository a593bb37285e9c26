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
use crate::field::{Blades, Lod, LodChange, MAX_SEGMENTS};
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
///
/// Colliders that share no blade are independent: they run side by side
/// ([`collider_groups`]), each over its blades in parallel too, so that a
/// thread that finished its share of one collider takes up another instead
/// of waiting (a herd's 128 colliders hold ~150 blades each; one collider
/// after the other, the contact ran 1.67× faster on two threads than on
/// one). Colliders that share a blade run one after the other, each where
/// the one before left the blade; what is stored, kept and returned is
/// gathered collider by collider afterwards: the same bits as one collider
/// after the other. Where a group holds more than [`MAX_GROUP`] colliders
/// (a crowd, a body of many parts in one place) they all run one after the
/// other, each storing what it moved before the next: finding where the
/// ones before left a blade would cost more than it wins.
pub(crate) fn resolve_contacts(
    sim: &mut Simulation,
    colliders: &[(usize, usize)],
    patch_hits: &[Vec<u32>],
    keys: &[Option<RestKey>],
    memos: &mut [ColliderMemo],
    reused: &mut u32,
) -> Vec<u32> {
    let n = sim.field.blades.segments;
    let (lists, shared) = contact_lists(sim, patch_hits);
    let groups = collider_groups(&shared);
    let mut out = Vec::new();
    let found: Vec<_> = colliders
        .iter()
        .map(|&(i, k)| sim.bodies[i].collider(k))
        .collect();
    let blades = &mut sim.field.blades;
    let terrain = &sim.field.terrain;
    let mask = &sim.scratch.mask;
    if groups.iter().any(|g| g.len() > MAX_GROUP) {
        for (j, list) in lists.into_iter().enumerate() {
            let work = collider_work(
                blades,
                terrain,
                mask,
                &list,
                &found[j],
                keys[j],
                &memos[j],
                |_| None,
            );
            finish_collider(
                blades,
                mask,
                list,
                work,
                keys[j],
                &mut memos[j],
                reused,
                &mut out,
            );
        }
    } else {
        let kept: &[ColliderMemo] = memos;
        let shared_blades: &Blades = blades;
        let done: Vec<Vec<(usize, ColliderWork)>> = groups
            .par_iter()
            .map(|group| {
                let mut done: Vec<(usize, ColliderWork)> = Vec::with_capacity(group.len());
                for &j in group {
                    let work = collider_work(
                        shared_blades,
                        terrain,
                        mask,
                        &lists[j],
                        &found[j],
                        keys[j],
                        &kept[j],
                        // Where the colliders before this one left the
                        // blade: the last of this group's that has it (at
                        // most MAX_GROUP - 1 to look in), or as stored.
                        |b| {
                            done.iter().rev().find_map(|(i, w)| {
                                let at = lists[*i].binary_search(&b).ok()?;
                                Some(&w.work[at * (n + 1)..(at + 1) * (n + 1)])
                            })
                        },
                    );
                    done.push((j, work));
                }
                done
            })
            .collect();
        let mut works: Vec<Option<ColliderWork>> = (0..lists.len()).map(|_| None).collect();
        for (j, w) in done.into_iter().flatten() {
            works[j] = Some(w);
        }
        for (j, (list, work)) in lists.into_iter().zip(works).enumerate() {
            let work = work.expect("every collider is in one group");
            finish_collider(
                blades,
                mask,
                list,
                work,
                keys[j],
                &mut memos[j],
                reused,
                &mut out,
            );
        }
    }
    for &b in &out {
        mark_displaced(sim, b);
    }
    out
}

/// The most colliders sharing blades that [`resolve_contacts`] runs beside
/// other groups; a larger group runs all colliders one after the other.
const MAX_GROUP: usize = 4;

/// One collider's contact response ([`resolve_contacts`]) over its blades
/// `list`, in parallel: each blade taken from `before` (where the
/// colliders before this one left it) or as stored, then moved out of the
/// collider unless the collider's memo knows its answer.
#[allow(clippy::too_many_arguments)]
fn collider_work<'a>(
    blades: &Blades,
    terrain: &crate::field::Terrain,
    mask: &[u32],
    list: &[u32],
    collider: &super::body::Collider<'_>,
    key: Option<RestKey>,
    memo: &ColliderMemo,
    before: impl Fn(u32) -> Option<&'a [Vec3A]> + Sync,
) -> ColliderWork {
    let n = blades.segments;
    let mut work = vec![Vec3A::ZERO; list.len() * (n + 1)];
    // Per blade: whether it moved, whether it is where it was found (a
    // fixed point a collider at rest keeps, `super::at_rest`), and whether
    // it was left without a query (kept so before).
    let mut moved = vec![(false, false, false); list.len()];
    // Each vertex's closest triangle, from the collider's sub-step before
    // and for its next (`super::contact_hints`).
    let mut hints = vec![[NO_HINT; MAX_SEGMENTS + 1]; list.len()];
    work.par_chunks_mut(n + 1)
        .zip(moved.par_iter_mut())
        .zip(hints.par_iter_mut())
        .zip(list.par_iter())
        .for_each(|(((v, moved), hint), &b)| {
            *hint = memo.hints.of(b, n + 1);
            match before(b) {
                Some(before) => v.copy_from_slice(before),
                None => blades.load(b as usize, v),
            }
            let b = b as usize;
            let first = mask[b].trailing_zeros();
            let seg_len = blades.seg_len[b];
            if let Some(was) = memo.kept_blade(key, b as u32, first, seg_len, v) {
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
                v.iter()
                    .zip(&before)
                    .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
            });
            *moved = (m, fixed, false);
        });
    ColliderWork { work, moved, hints }
}

/// What [`resolve_contacts`] keeps of one collider's work, collider by
/// collider in order: the blades it moved stored (those it left as stored
/// are not), appended to `out`; the blades at their fixed points and the
/// closest triangles kept in its memo.
#[allow(clippy::too_many_arguments)]
fn finish_collider(
    blades: &mut Blades,
    mask: &[u32],
    list: Vec<u32>,
    work: ColliderWork,
    key: Option<RestKey>,
    memo: &mut ColliderMemo,
    reused: &mut u32,
    out: &mut Vec<u32>,
) {
    let n = blades.segments;
    if list.is_empty() {
        memo.keep_blades(None, RestingBlades::default());
        memo.hints = ContactHints::default();
        return;
    }
    let ColliderWork { work, moved, hints } = work;
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
            // is known to be; any other is compared with what is stored
            // (where the colliders before this one left it).
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
            let first = mask[b as usize].trailing_zeros();
            let seg_len = blades.seg_len[b as usize];
            resting.push(b, first, seg_len, m, v);
        }
    }
    blades.store_slots(&stored, &work);
    memo.keep_blades(key, resting);
    memo.hints = ContactHints::keep(list, &hints, n + 1);
}

/// The blades [`resolve_contacts`] moves out of each collider: those some
/// object touched this sub-step (a segment mask) in the patches listed for
/// it (`patch_hits`), ascending; and the patches of the list that hold
/// such blades, ascending (two colliders share a blade exactly when they
/// share one of those). Blades are stored patch by patch and the
/// touched ones are sorted, so each listed patch (ascending) is one range
/// of them — found by two binary searches, not by testing every touched
/// blade against every collider.
fn contact_lists(sim: &Simulation, patch_hits: &[Vec<u32>]) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
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
    patch_hits
        .iter()
        .map(|patches| {
            let (mut list, mut shared) = (Vec::new(), Vec::new());
            for &p in patches {
                let (first, end) = (p as usize * per_patch, (p as usize + 1) * per_patch);
                let lo = touched.partition_point(|&b| (b as usize) < first);
                let hi = touched.partition_point(|&b| (b as usize) < end);
                if hi > lo {
                    list.extend_from_slice(&touched[lo..hi]);
                    shared.push(p);
                }
            }
            (list, shared)
        })
        .unzip()
}

/// What [`resolve_contacts`] did to one collider's blades, in the order of
/// its list: their vertices after it, whether each moved, was at its fixed
/// point, was left without a query; each vertex's closest triangle.
struct ColliderWork {
    work: Vec<Vec3A>,
    moved: Vec<(bool, bool, bool)>,
    hints: Vec<[u32; MAX_SEGMENTS + 1]>,
}

/// The colliders of `lists` (per collider, its keys, ascending: the
/// patches that hold its blades, [`contact_lists`]) in groups that share
/// no key with one another: colliders that share a key, directly or
/// through others, are in one group, ascending; the groups are in the
/// order of their first collider.
fn collider_groups(lists: &[Vec<u32>]) -> Vec<Vec<usize>> {
    // Union–find over the colliders; the smaller root leads, so a group's
    // root is its first collider.
    fn root(parent: &mut [usize], mut j: usize) -> usize {
        while parent[j] != j {
            parent[j] = parent[parent[j]];
            j = parent[j];
        }
        j
    }
    let mut parent: Vec<usize> = (0..lists.len()).collect();
    let mut keys: Vec<(u32, usize)> = lists
        .iter()
        .enumerate()
        .flat_map(|(j, list)| list.iter().map(move |&b| (b, j)))
        .collect();
    keys.sort_unstable();
    for pair in keys.windows(2) {
        if pair[0].0 == pair[1].0 {
            let (a, b) = (root(&mut parent, pair[0].1), root(&mut parent, pair[1].1));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut slot = vec![usize::MAX; lists.len()];
    for j in 0..lists.len() {
        let r = root(&mut parent, j);
        if slot[r] == usize::MAX {
            slot[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[slot[r]].push(j);
    }
    groups
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::broad_phase::patches_under;
    use crate::scene::Scene;

    #[test]
    fn colliders_are_grouped_by_the_blades_they_share() {
        let lists = vec![
            vec![1, 2, 3],
            vec![10, 11],
            vec![3, 4],
            vec![11],
            vec![20],
            vec![],
            vec![4, 30],
        ];
        assert_eq!(
            collider_groups(&lists),
            vec![vec![0, 2, 6], vec![1, 3], vec![4], vec![5]]
        );
        assert!(collider_groups(&[]).is_empty());
    }

    /// Boxes side by side, overlapping, sliding over the same blades: the
    /// contact response gives the bits of the colliders taken one after the
    /// other, each loading the blades as the one before stored them (what
    /// `resolve_contacts` did before it ran independent colliders side by
    /// side), and many blades are moved by two of them; with two boxes (a
    /// group run beside the others) and with more than `MAX_GROUP` (all
    /// one after the other).
    #[test]
    fn colliders_sharing_blades_meet_them_one_after_the_other() {
        for boxes in [2, MAX_GROUP + 2] {
            colliders_meet_shared_blades_one_after_the_other(boxes);
        }
    }

    fn colliders_meet_shared_blades_one_after_the_other(boxes: usize) {
        let mut text = String::from(
            r#"
[field]
patches = [2, 2]
cells_per_patch = 16
[camera]
path = { kind = "static", position = [0.0, 3.0, 4.0] }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
"#,
        );
        for i in 0..boxes {
            let (x, z) = (-2.0 + 0.6 * i as f32, 0.2 * (i % 2) as f32);
            text += &format!(
                "[[objects]]\nname = \"b{i}\"\nshape = {{ kind = \"box\", half_extents_m = [0.5, 0.3, 0.5] }}\n\
                 path = {{ kind = \"line\", from = [{x}, 0.25, {z}], to = [{}, 0.25, {z}], duration_s = 2.0 }}\n",
                x + 4.0
            );
        }
        let mut sim = Scene::parse(&text, "boxes", std::path::Path::new("."))
            .unwrap()
            .build()
            .unwrap();
        sim.run(12).unwrap();
        let colliders: Vec<(usize, usize)> = (0..boxes).map(|i| (i, 0)).collect();
        let patch_hits: Vec<Vec<u32>> = colliders
            .iter()
            .map(|&(i, k)| {
                let mut out = Vec::new();
                patches_under(
                    &sim.field.layout,
                    sim.bodies[i].collider(k).world_root,
                    &mut out,
                );
                out
            })
            .collect();
        let (lists, shared) = contact_lists(&sim, &patch_hits);
        assert_eq!(
            collider_groups(&shared),
            vec![(0..boxes).collect::<Vec<_>>()]
        );

        let mut got = sim.clone();
        let mut memos = vec![ColliderMemo::default(); boxes];
        let mut reused = 0;
        resolve_contacts(
            &mut got,
            &colliders,
            &patch_hits,
            &vec![None; boxes],
            &mut memos,
            &mut reused,
        );

        // One collider after the other, each storing what it moved.
        let mut want = sim.clone();
        let n = want.field.blades.segments;
        let mut moved_by = vec![Vec::new(); colliders.len()];
        for (j, (&(i, k), list)) in colliders.iter().zip(&lists).enumerate() {
            for &b in list {
                let mut v = vec![Vec3A::ZERO; n + 1];
                want.field.blades.load(b as usize, &mut v);
                let first = want.scratch.mask[b as usize].trailing_zeros() as usize;
                let seg_len = want.field.blades.seg_len[b as usize];
                let collider = want.bodies[i].collider(k);
                let mut hint = [NO_HINT; MAX_SEGMENTS + 1];
                if resolve_contact_hinted(
                    &mut v,
                    seg_len,
                    first,
                    collider.pose,
                    collider.tree,
                    &want.field.terrain,
                    GROUND_CLEARANCE_M,
                    seg_len,
                    &mut hint,
                ) {
                    moved_by[j].push(b);
                    want.field.blades.store(b as usize, &v);
                }
            }
        }
        let both = moved_by[0]
            .iter()
            .filter(|b| moved_by[1].binary_search(b).is_ok())
            .count();
        assert!(both > 20, "only {both} blades moved by both boxes");
        let bits = |sim: &Simulation| -> Vec<[u32; 3]> {
            sim.field
                .blades
                .pos
                .iter()
                .map(|v| v.pos.map(f32::to_bits))
                .collect()
        };
        assert!(bits(&got) == bits(&want), "the blades differ");
    }
}
