//! Force propagation from the blades hit directly (DBG) to the blades around
//! them (PBG): paper §5.2, Definitions 1–7 and Eq. 4; DESIGN §5.
//!
//! Generation 0 are the **ancestors** (DBG, Definition 4). Each **active**
//! blade J of generation G (its energy |F_J| — Definition 1 — is at least the
//! threshold L, Definition 2) splits its force into an x and a z component,
//! `EF1' = (F.x, 0, 0)` and `EF2' = (0, 0, F.z)` (Step 2; the vertical part
//! is dropped); each points at one of J's four adjacent blades (Definition
//! 6): `EF1'` at the +x neighbour when `F.x > 0`, at the −x one when
//! `F.x < 0`, at none when `F.x = 0`; `EF2'` likewise along z. A blade so
//! pointed at that is neither an ancestor nor a **child** of generation ≤ G
//! (the **parallel relation**, Definition 7) receives `EF' · att` on top of
//! its own force `EF_origin` (Eq. 4) and becomes a child of generation G+1
//! (Step 4). Blades already reached are never changed again. Propagation ends
//! when a generation has no active blade (termination status, Definition 3)
//! or at a generation cap.
//!
//! # As a gather
//! The paper scatters from J to its neighbours. Here each blade of
//! generation G+1 *gathers* the contributions pointing at it, summed in the
//! fixed neighbour order −x, +x, −z, +z (DESIGN §5): the result does not
//! depend on the thread count, and the GPU path can do the same without float
//! atomics. The work follows the frontier: it is proportional to the number
//! of blades reached, never to the size of the field.
//!
//! # Energies
//! A blade of generation G+1 gets at most one x contribution from its −x
//! neighbour (pointing +x) and one from its +x neighbour (pointing −x): they
//! have opposite signs, so their sum is at most `att · max|F_G|` in
//! magnitude; the same holds for z. Hence
//! `|F_{G+1}| ≤ √2 · att · max |F_G|`, and for `att < 1/√2` the energies
//! decay geometrically: propagation ends after at most
//! `⌈ln(L / max|F_0|) / ln(√2 · att)⌉` generations.

use crate::field::layout::{NEG_X, NEG_Z, NO_NEIGHBOUR, POS_X, POS_Z};
use glam::Vec3;
use rayon::prelude::*;

/// Generation of a blade that propagation has not reached (neither DBG nor
/// PBG) in the `generation` slice of [`propagate_forces`].
pub const NO_GENERATION: u8 = u8::MAX;

/// The highest generation [`propagate_forces`] creates, whatever
/// [`PropagationParams::max_generations`] says: generations are stored as
/// `u8` and [`NO_GENERATION`] (255) is taken.
pub const GENERATION_CAP: u32 = 254;

/// Frontiers larger than this are gathered on the rayon pool; smaller ones
/// cost less than the fork-join. The result is the same either way.
const PARALLEL_FRONTIER: usize = 4096;

/// Parameters of the propagation (Eq. 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropagationParams {
    /// Decay factor `att ∈ [0, 1]` of Eq. 4 (dimensionless). Values outside
    /// are clamped into it; NaN counts as 0 (no propagation). Below `1/√2` the
    /// energies are guaranteed to decay (module docs).
    pub att: f32,
    /// Threshold `L` on the energy |F| (Definitions 2–3), m/s: a blade with
    /// `|F| ≥ L` is active and propagates; below it, it is in termination
    /// status. NaN: no blade is active.
    pub threshold: f32,
    /// Safety cap on the number of generations created after the ancestors;
    /// values above [`GENERATION_CAP`] are lowered to it. 0 turns
    /// propagation off.
    pub max_generations: u32,
    /// Width of the fade-in of the threshold, as a fraction of `L` (ours,
    /// DESIGN §5 "continuous"): an active blade of energy `|F|` pushes its
    /// neighbours with `EF' · att · min(1, (|F| − L) / (fade · L))`, so a
    /// blade a few ulp either side of `L` pushes by a few ulp, not by
    /// `att · L` or nothing. 0 (or NaN) is the paper's hard threshold.
    /// The simulation uses [`THRESHOLD_FADE`].
    pub threshold_fade: f32,
    /// Contact weight at which a DBG blade is wholly held, an ancestor of
    /// the paper (ours; see `weight` of [`propagate_forces`]): a blade of
    /// weight `w` is held `min(1, w / hold_weight)`. 0 (or NaN): every DBG
    /// blade is wholly held, as in the paper. The simulation uses
    /// [`crate::step::stages::HOLD_WEIGHT`].
    pub hold_weight: f32,
}

/// The simulation's [`PropagationParams::threshold_fade`]: the push of Eq. 4
/// reaches its full `EF' · att` at 1.25 L (a quarter of the threshold above
/// it). Measured on the default scene: two runs whose blades differ by two
/// ulp at one frame ended 1.4 mm apart 50 frames later with the paper's
/// hard threshold (one blade a hair's breadth from L), a few µm with the
/// fade.
pub const THRESHOLD_FADE: f32 = 0.25;

/// What [`propagate_forces`] reached.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PropagationResult {
    /// Number of generations of children (≥ 1) created.
    pub generations: u32,
    /// The blades reached by propagation (PBG: generation ≥ 1), ordered by
    /// (generation, index). With the DBG list these are all the blades whose
    /// `force` and `generation` the call changed: the caller resets exactly
    /// these before the next call.
    pub pbg: Vec<u32>,
    /// For each entry of `pbg`, the blade of the previous generation whose
    /// contribution comes first in the fixed neighbour order −x, +x, −z, +z:
    /// the one that pushed it (ours: a reached blade follows the track
    /// settings of the object that pushed its ancestor, DESIGN §6).
    pub sources: Vec<u32>,
}

/// Propagates the forces of the directly hit blades (DBG) to the blades
/// around them (PBG), generation by generation: Eq. 4 with Definitions 1–7,
/// computed as a gather (module docs).
///
/// - `dbg`: the ancestors (Definition 4), blade indices, preferably sorted
///   ascending and unique (duplicates are harmless; indices out of range are
///   ignored).
/// - `neighbours[b]`: the four adjacent blades of blade `b` (Definition 6) in
///   the order −x, +x, −z, +z ([`NEG_X`], [`POS_X`], [`NEG_Z`], [`POS_Z`]);
///   [`NO_NEIGHBOUR`] at the field border. A neighbour counts only if the
///   relation is mutual (`neighbours[j][POS_X] == b` for `b`'s −x neighbour
///   `j`, and so on), as it is in any grid.
/// - `force[b]`: world-space force, m/s. Precondition: set for every DBG
///   blade (Eq. 2), [`Vec3::ZERO`] elsewhere. The reached blades get theirs
///   (Eq. 4, with `EF_origin` = their own force, zero by this precondition;
///   the result has no vertical component).
/// - `generation[b]`: precondition [`NO_GENERATION`] for every blade not in
///   `dbg`; DBG blades are set to 0 here. Reached blades get 1, 2, ….
/// - `weight[b]` (ours, DESIGN §5 "continuous"), for the DBG blades: how
///   firmly an object touches the blade (its contact weight). It is held
///   `min(1, weight / hold_weight)` (1 where `weight` is too short to cover
///   the blade, or `hold_weight` is 0). The paper's ancestors (held 1) are
///   never changed again (Definition 7); an ancestor held less can still be
///   reached, once, by a neighbour's push, and takes `(1 − held)` of it on
///   top of its own force — it then joins that generation. A blade barely
///   touched is so nearly a child, one held firmly an ancestor, with no
///   jump between.
///
/// Only the first `min(neighbours.len(), force.len(), generation.len())`
/// blades take part. A blade with a non-finite force is never active (a bad
/// value does not spread). Deterministic and independent of the rayon thread
/// count. Allocates the result and the frontier; cost proportional to the
/// blades reached.
///
/// See also [`crate::force::eqf::eqf`] for the forces of the ancestors.
pub fn propagate_forces(
    dbg: &[u32],
    neighbours: &[[u32; 4]],
    force: &mut [Vec3],
    generation: &mut [u8],
    weight: &[f32],
    params: &PropagationParams,
) -> PropagationResult {
    let len = neighbours.len().min(force.len()).min(generation.len());
    let att = if params.att.is_nan() {
        0.0
    } else {
        params.att.clamp(0.0, 1.0)
    };
    let threshold = params.threshold;
    let fade = if params.threshold_fade > 0.0 {
        params.threshold_fade * threshold
    } else {
        0.0
    };
    let cap = params.max_generations.min(GENERATION_CAP);
    let hold = params.hold_weight;
    let held_at = |b: usize| match weight.get(b) {
        Some(&w) if hold > 0.0 => (w / hold).clamp(0.0, 1.0),
        _ => 1.0,
    };

    let mut frontier: Vec<u32> = dbg
        .iter()
        .copied()
        .filter(|&b| (b as usize) < len)
        .collect();
    for &b in &frontier {
        generation[b as usize] = 0;
    }
    let mut result = PropagationResult::default();
    let mut candidates = Vec::new();
    let mut sums = Vec::new();
    while result.generations < cap {
        let g = result.generations as u8;
        // The blades of generation G+1: unassigned blades some active blade
        // of generation G points at (Step 3; assigned ones are ancestors or
        // children of generation ≤ G: parallel relation, never changed).
        candidates.clear();
        for &j in &frontier {
            let f = force[j as usize];
            if !is_active(f, threshold) {
                continue;
            }
            let nb = &neighbours[j as usize];
            for target in [
                pointed_at(nb, f.x, NEG_X, POS_X),
                pointed_at(nb, f.z, NEG_Z, POS_Z),
            ] {
                let t = target as usize;
                // Unreached, or an ancestor not wholly held that has not
                // been reached yet (it would have left generation 0).
                if t < len
                    && (generation[t] == NO_GENERATION || (generation[t] == 0 && held_at(t) < 1.0))
                {
                    candidates.push(target);
                }
            }
        }
        if candidates.is_empty() {
            break;
        }
        candidates.sort_unstable();
        candidates.dedup();

        // Eq. 4, gathered: every candidate sums what points at it.
        let (f_read, g_read) = (&*force, &*generation);
        let gather = |&c: &u32| {
            let take = if g_read[c as usize] == 0 {
                1.0 - held_at(c as usize)
            } else {
                1.0
            };
            gather_force(
                c, g, neighbours, f_read, g_read, len, att, threshold, fade, take,
            )
        };
        sums.clear();
        if candidates.len() > PARALLEL_FRONTIER {
            candidates
                .par_iter()
                .map(gather)
                .collect_into_vec(&mut sums);
        } else {
            sums.extend(candidates.iter().map(gather));
        }
        for (&c, &(f, source)) in candidates.iter().zip(&sums) {
            force[c as usize] = f;
            generation[c as usize] = g + 1;
            result.sources.push(source);
        }
        result.pbg.extend_from_slice(&candidates);
        result.generations += 1;
        std::mem::swap(&mut frontier, &mut candidates);
    }
    result
}

/// Active status (Definition 2): finite energy (Definition 1) at least the
/// threshold.
fn is_active(f: Vec3, threshold: f32) -> bool {
    f.is_finite() && f.length() >= threshold
}

/// How much of its push an active blade of force `f` gives (see
/// [`PropagationParams::threshold_fade`]): `min(1, (|F| − L) / fade)`, 1
/// when `fade` is 0.
fn fade_in(f: Vec3, threshold: f32, fade: f32) -> f32 {
    if fade > 0.0 {
        ((f.length() - threshold) / fade).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The neighbour a force component points at (Definition 6): `pos` slot for
/// a positive component, `neg` slot for a negative one, none for zero.
fn pointed_at(nb: &[u32; 4], component: f32, neg: usize, pos: usize) -> u32 {
    if component > 0.0 {
        nb[pos]
    } else if component < 0.0 {
        nb[neg]
    } else {
        NO_NEIGHBOUR
    }
}

/// Eq. 4 for blade `c` of generation `g + 1`: its own force `EF_origin` plus
/// `take ·` `EF' · att` (faded in, see [`fade_in`]) from each active
/// generation-`g` neighbour pointing at it, in the fixed order −x, +x, −z,
/// +z; and the first such neighbour ([`NO_NEIGHBOUR`] if none, which a
/// candidate never has).
fn gather_force(
    c: u32,
    g: u8,
    neighbours: &[[u32; 4]],
    force: &[Vec3],
    generation: &[u8],
    len: usize,
    att: f32,
    threshold: f32,
    fade: f32,
    take: f32,
) -> (Vec3, u32) {
    // (slot of the neighbour J seen from c, slot of c seen from J, axis, sign
    // of J's component that points at c).
    const FROM: [(usize, usize, usize, f32); 4] = [
        (NEG_X, POS_X, 0, 1.0),
        (POS_X, NEG_X, 0, -1.0),
        (NEG_Z, POS_Z, 2, 1.0),
        (POS_Z, NEG_Z, 2, -1.0),
    ];
    let mut sum = force[c as usize];
    let mut first = NO_NEIGHBOUR;
    for (slot, back, axis, sign) in FROM {
        let j = neighbours[c as usize][slot];
        if j as usize >= len || generation[j as usize] != g || neighbours[j as usize][back] != c {
            continue;
        }
        let f = force[j as usize];
        let component = f[axis];
        if component * sign > 0.0 && is_active(f, threshold) {
            let mut ef = Vec3::ZERO;
            ef[axis] = component;
            sum += ef * (att * fade_in(f, threshold, fade) * take);
            if first == NO_NEIGHBOUR {
                first = j;
            }
        }
    }
    (sum, first)
}
