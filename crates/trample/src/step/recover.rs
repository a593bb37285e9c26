//! Stage 9 of a sub-step (DESIGN §7): recovery of displaced blades and, in
//! the paper's mode, of bent billboards (ours; the paper's future work).

use super::simulation::Simulation;
use crate::field::MAX_SEGMENTS;
use crate::field::generate::GROUND_CLEARANCE_M;
use crate::recovery::{recover_blade, recover_slope, stride_wait};
use crate::recovery_wide::{LANES, Lane, recover_blades_wide};
use glam::Vec3A;
use rayon::prelude::*;

/// Relaxes displaced blades towards rest (DESIGN §6), each with the track
/// settings of its [`Simulation::track_owner`], for `h` seconds times how
/// free it is: `1 − min(1, contact weight)` — a blade an object holds does
/// not recover (ours), one it barely grazes nearly fully (a continuous
/// rule). With `sim.params.far_every > 1`, far patches' blades recover in
/// turns, each over the time its patch owes ([`super::recovery_turns`]):
/// `h` times [`Simulation::recovery_scale`]; a blade waiting for its turn
/// is not looked at. In the paper's mode (`sim.track_everywhere = false`) bent
/// billboards recover too, with `[sim]`'s settings. Returns the blades that
/// moved (ascending); blades back at rest leave the displaced set.
pub(crate) fn recover(sim: &mut Simulation, h: f32) -> Vec<u32> {
    let owners = 1 + sim.bodies.len().min(usize::from(u8::MAX));
    let params: Vec<_> = (0..owners).map(|o| sim.recovery_params(o as u8)).collect();
    if params.iter().all(|p| p.recovery_s.is_infinite()) {
        return Vec::new();
    }
    // Slow blades in strides: every blade's clock (owed time, wait).
    let stride = sim.params.recovery_stride_m;
    let strides = stride > 0.0;
    let count = sim.field.blades.count;
    let mut clock = std::mem::take(&mut sim.scratch.recover_clock);
    if strides && clock.len() != count {
        clock = vec![[0.0; 2]; count];
    } else if !strides {
        clock = Vec::new();
    }
    // Only here is the set walked: put in order the blades appended since.
    sim.scratch.sort_displaced();
    let displaced = std::mem::take(&mut sim.scratch.displaced);
    let mut work = std::mem::take(&mut sim.scratch.recover_work);
    let blades = &sim.field.blades;
    let n = blades.segments;
    let terrain = &sim.field.terrain;
    let (weight, owner) = (&sim.scratch.weight, &sim.track_owner);
    let scale = sim.recovery_turns.scale();
    let per_patch =
        (sim.field.layout.cells_in_patch() * sim.field.layout.blades_per_cell as usize).max(1);
    // A blade's recovery time this step, if it is looked at: the
    // sub-step's, or its patch's turn's (every displaced blade unless far
    // patches take turns; a blade waiting for its patch's turn is not
    // looked at), times how free the blade is (in strides, plus the time
    // it owes).
    let time = |b: u32| {
        let hb = match scale {
            None => h,
            Some(s) => h * s.get(b as usize / per_patch).copied().unwrap_or(1.0),
        };
        (hb != 0.0).then(|| hb * (1.0 - weight[b as usize].min(1.0)))
    };
    // The blades due, with their time: every blade looked at, or in
    // strides those that owe their wait; one looked at but not due owes
    // the time and waits on (its clock written here: the set is ascending,
    // so its chunks own disjoint ranges of the clock).
    let due: Vec<(u32, f32)> = if strides {
        clock_parts(&mut clock, &displaced, CLOCK_CHUNK)
            .into_par_iter()
            .flat_map_iter(|(set, start, part)| {
                set.iter().filter_map(move |&b| {
                    let c = &mut part[b as usize - start];
                    let t = c[0] + time(b)?;
                    if t >= c[1] {
                        Some((b, t))
                    } else {
                        c[0] = t;
                        None
                    }
                })
            })
            .collect()
    } else {
        displaced
            .par_iter()
            .filter_map(|&b| Some((b, time(b)?)))
            .collect()
    };
    // One work slot of n + 1 vertices per blade due (see bend_blades).
    if work.len() < due.len() * (n + 1) {
        work.resize(due.len() * (n + 1), Vec3A::ZERO);
    }
    // Per blade due: at rest now, moved, how far its farthest vertex moved.
    let mut state = vec![(false, false, 0.0f32); due.len()];
    // Four blades at a time (`recovery_wide`: the same bits as one at a
    // time), the last group's leftovers one by one.
    let group = LANES * (n + 1);
    work[..due.len() * (n + 1)]
        .par_chunks_mut(group)
        .zip(state.par_chunks_mut(LANES))
        .zip(due.par_chunks(LANES))
        .for_each(|((work, state), due)| {
            let mut rest = [[Vec3A::ZERO; MAX_SEGMENTS + 1]; LANES];
            let mut before = [[Vec3A::ZERO; MAX_SEGMENTS + 1]; LANES];
            let mut dt = [0.0f32; LANES];
            let slots = work.chunks_mut(n + 1).zip(due).zip(&mut rest);
            for (l, ((v, &(b, t)), rest)) in slots.enumerate() {
                let bi = b as usize;
                blades.load(bi, v);
                blades.load_rest(bi, rest);
                before[l][..=n].copy_from_slice(v);
                dt[l] = t;
            }
            let settings = |l: usize| {
                let owner = usize::from(owner[due[l].0 as usize]);
                params.get(owner).unwrap_or(&params[0])
            };
            let seg_len = |l: usize| blades.seg_len[due[l].0 as usize];
            let mut done = [false; LANES];
            if due.len() == LANES {
                let mut slots = work.chunks_mut(n + 1);
                let lanes = std::array::from_fn(|l| Lane {
                    verts: slots.next().expect("a slot a lane"),
                    rest: &rest[l][..=n],
                    seg_len: seg_len(l),
                    dt: dt[l],
                    params: settings(l),
                });
                done = recover_blades_wide(lanes, terrain, GROUND_CLEARANCE_M);
            } else {
                for (l, v) in work.chunks_mut(n + 1).enumerate() {
                    done[l] = recover_blade(
                        v,
                        &rest[l][..=n],
                        seg_len(l),
                        dt[l],
                        settings(l),
                        terrain,
                        GROUND_CLEARANCE_M,
                    );
                }
            }
            for (l, (s, v)) in state.iter_mut().zip(work.chunks(n + 1)).enumerate() {
                let moved = if strides {
                    v.iter()
                        .zip(&before[l][..=n])
                        .map(|(a, b)| a.distance_squared(*b))
                        .fold(0.0, f32::max)
                        .sqrt()
                } else {
                    0.0
                };
                *s = (done[l], v != &before[l][..=n], moved);
            }
        });
    let mut moved = Vec::new();
    let mut stored = Vec::new();
    for (i, (&(b, t), &(done, changed, far))) in due.iter().zip(&state).enumerate() {
        if strides {
            let wait = if done {
                0.0
            } else {
                stride_wait(stride, far, t)
            };
            clock[b as usize] = [0.0, wait];
        }
        if changed {
            stored.push((b, i as u32));
            moved.push(b);
        }
        if done {
            sim.scratch.displaced_flag[b as usize] = false;
        }
    }
    sim.scratch.recover_clock = clock;
    // The set less the blades back at rest, in order.
    let flags = &sim.scratch.displaced_flag;
    let still: Vec<u32> = displaced
        .par_iter()
        .copied()
        .filter(|&b| flags[b as usize])
        .collect();
    sim.field.blades.store_slots(&stored, &work);
    sim.scratch.recover_work = work;
    // In the order of the set: still in order.
    sim.scratch.displaced_sorted = still.len();
    sim.scratch.displaced = still;
    if !sim.params.track_everywhere {
        let cells = &mut sim.field.cells;
        sim.scratch.retain_bent(|c, _| {
            let mut slope = cells.slope[c];
            let done = recover_slope(&mut slope, cells.slope_origin[c], h, &params[0]);
            cells.set_slope(c, slope);
            !done
        });
    }
    moved
}

/// Blades a part of [`clock_parts`] holds (a few thousand: enough parts for
/// the threads, few enough to cost nothing to make).
const CLOCK_CHUNK: usize = 4096;

/// `clock` (per blade) split along the ascending, duplicate-free `set` cut
/// into chunks of `chunk` blades: each chunk with the first blade its part
/// starts at and the part, which holds every blade of the chunk and no
/// other chunk's (from the chunk's first blade to the next chunk's).
fn clock_parts<'a, T>(
    mut clock: &'a mut [T],
    set: &'a [u32],
    chunk: usize,
) -> Vec<(&'a [u32], usize, &'a mut [T])> {
    let mut parts = Vec::with_capacity(set.len().div_ceil(chunk));
    let mut start = 0;
    let mut chunks = set.chunks(chunk).peekable();
    while let Some(c) = chunks.next() {
        let end = chunks
            .peek()
            .map_or(start + clock.len(), |next| next[0] as usize);
        let (part, rest) = std::mem::take(&mut clock).split_at_mut(end - start);
        parts.push((c, start, part));
        clock = rest;
        start = end;
    }
    parts
}

#[cfg(test)]
mod tests {
    use super::clock_parts;

    /// Every blade of a chunk lies in its own part, the parts tile the
    /// clock in order, and writes through them land on the blades' slots.
    #[test]
    fn clock_parts_give_each_chunk_the_slots_of_its_blades() {
        let set: Vec<u32> = vec![0, 3, 4, 9, 10, 11, 17, 25, 26, 31];
        for chunk in [1, 2, 3, 4, 10, 64] {
            let mut clock: Vec<u32> = vec![0; 32];
            let parts = clock_parts(&mut clock, &set, chunk);
            assert_eq!(parts.len(), set.len().div_ceil(chunk));
            let mut next = 0;
            for (blades, start, part) in parts {
                assert_eq!(start, next, "chunk {chunk}: parts tile the clock");
                for &b in blades {
                    part[b as usize - start] = b + 100;
                }
                next = start + part.len();
            }
            assert_eq!(next, 32);
            for (b, &v) in clock.iter().enumerate() {
                let want = if set.contains(&(b as u32)) {
                    b as u32 + 100
                } else {
                    0
                };
                assert_eq!(v, want, "chunk {chunk}, blade {b}");
            }
        }
        let mut clock = vec![0u32; 8];
        assert!(clock_parts(&mut clock, &[], 4).is_empty());
    }
}
