//! Forces on geometric blades: EqF of the blades hit directly (Eq. 2) and
//! the propagation to the blades around them (Eq. 4, Definitions 1–7):
//! hand-computed generations, the energy bound, the parallel relation,
//! agreement with the paper's scatter formulation, and determinism across
//! thread counts.

mod common;
use common::Rng;

use glam::Vec3;
use trample::field::layout::{NEG_X, NEG_Z, NO_NEIGHBOUR, POS_X, POS_Z};
use trample::force::eqf::eqf;
use trample::force::propagation::{
    GENERATION_CAP, NO_GENERATION, PropagationParams, PropagationResult, propagate_forces,
};

/// Neighbour table of a `w × h` grid, blade index `z · w + x`, order −x, +x, −z, +z.
fn grid(w: u32, h: u32) -> Vec<[u32; 4]> {
    let mut nb = Vec::with_capacity((w * h) as usize);
    for z in 0..h {
        for x in 0..w {
            let at = |x: u32, z: u32| z * w + x;
            let mut n = [NO_NEIGHBOUR; 4];
            if x > 0 {
                n[NEG_X] = at(x - 1, z);
            }
            if x + 1 < w {
                n[POS_X] = at(x + 1, z);
            }
            if z > 0 {
                n[NEG_Z] = at(x, z - 1);
            }
            if z + 1 < h {
                n[POS_Z] = at(x, z + 1);
            }
            nb.push(n);
        }
    }
    nb
}

/// The state the caller prepares: DBG forces set, everything else reset.
fn setup(blades: usize, dbg: &[(u32, Vec3)]) -> (Vec<u32>, Vec<Vec3>, Vec<u8>) {
    let mut force = vec![Vec3::ZERO; blades];
    let mut generation = vec![NO_GENERATION; blades];
    let mut list = Vec::new();
    for &(b, f) in dbg {
        force[b as usize] = f;
        generation[b as usize] = 0;
        list.push(b);
    }
    list.sort_unstable();
    list.dedup();
    (list, force, generation)
}

fn run(
    nb: &[[u32; 4]],
    dbg: &[(u32, Vec3)],
    params: &PropagationParams,
) -> (PropagationResult, Vec<Vec3>, Vec<u8>) {
    let (list, mut force, mut generation) = setup(nb.len(), dbg);
    let r = propagate_forces(&list, nb, &mut force, &mut generation, &[], params);
    (r, force, generation)
}

fn params(att: f32, threshold: f32) -> PropagationParams {
    PropagationParams {
        att,
        threshold,
        max_generations: GENERATION_CAP,
        threshold_fade: 0.0,
        hold_weight: 0.0,
    }
}

/// The paper's formulation of Eq. 4 as a scatter (Fig. 5 (b), Steps 1–4):
/// every active blade J of generation G hands `EF' · att` to the blades its
/// components point at. Contributions are recorded per receiving slot and
/// summed in the order −x, +x, −z, +z, so the sums are bit-comparable.
fn reference_scatter(
    nb: &[[u32; 4]],
    force: &mut [Vec3],
    generation: &mut [u8],
    p: &PropagationParams,
) -> u32 {
    let mut g = 0u8;
    loop {
        if u32::from(g) >= p.max_generations.min(GENERATION_CAP) {
            return u32::from(g);
        }
        let mut received: Vec<Option<[Vec3; 4]>> = vec![None; nb.len()];
        for j in 0..nb.len() {
            let f = force[j];
            if generation[j] != g || !(f.is_finite() && f.length() >= p.threshold) {
                continue;
            }
            // (component, slot of the target seen from J, slot of J seen from the target)
            let parts = [
                (
                    Vec3::new(f.x, 0.0, 0.0),
                    if f.x > 0.0 { POS_X } else { NEG_X },
                    if f.x > 0.0 { NEG_X } else { POS_X },
                ),
                (
                    Vec3::new(0.0, 0.0, f.z),
                    if f.z > 0.0 { POS_Z } else { NEG_Z },
                    if f.z > 0.0 { NEG_Z } else { POS_Z },
                ),
            ];
            for (ef, to, from) in parts {
                if ef == Vec3::ZERO || nb[j][to] == NO_NEIGHBOUR {
                    continue;
                }
                let t = nb[j][to] as usize;
                // Parallel relation: ancestors and children of generation ≤ G are skipped.
                if generation[t] != NO_GENERATION {
                    continue;
                }
                received[t].get_or_insert([Vec3::ZERO; 4])[from] = ef * p.att;
            }
        }
        let mut any = false;
        for (t, r) in received.iter().enumerate() {
            if let Some(parts) = r {
                let mut sum = force[t];
                for part in parts {
                    // A slot that received nothing adds +0, which changes no sum.
                    sum += *part;
                }
                force[t] = sum;
                generation[t] = g + 1;
                any = true;
            }
        }
        if !any {
            return u32::from(g);
        }
        g += 1;
    }
}

#[test]
fn eq2_eqf_is_speed_times_unit_eqn() {
    assert_eq!(eqf(2.0, Vec3::Z), Vec3::new(0.0, 0.0, 2.0));
    // EqN is used as a direction (DESIGN §3): its length does not scale the force.
    assert_eq!(eqf(3.0, Vec3::new(0.0, 0.0, 2.0)), Vec3::new(0.0, 0.0, 3.0));
    let f = eqf(5.0, Vec3::new(3.0, 0.0, 4.0));
    assert!((f - Vec3::new(3.0, 0.0, 4.0)).length() < 1e-6);
    // Eq. 2 takes |v|.
    assert_eq!(eqf(-2.0, Vec3::X), Vec3::new(2.0, 0.0, 0.0));
    // No direction or bad input: no force.
    assert_eq!(eqf(1.0, Vec3::ZERO), Vec3::ZERO);
    assert_eq!(eqf(f32::NAN, Vec3::X), Vec3::ZERO);
    assert_eq!(eqf(f32::INFINITY, Vec3::X), Vec3::ZERO);
    assert_eq!(eqf(1.0, Vec3::new(f32::NAN, 0.0, 1.0)), Vec3::ZERO);
}

/// 5×5 grid, one ancestor at (2,2) with F = (4, −3, 2), att = 0.5, L = 1.
/// Gen 1: (3,2) ← (2,0,0), (2,3) ← (0,0,1). Gen 2: (4,2) ← (1,0,0),
/// (2,4) ← (0,0,0.5). (4,2) is active but points off the field; (2,4) is
/// below L: propagation ends after 2 generations.
#[test]
fn eq4_single_ancestor_hand_computed() {
    let nb = grid(5, 5);
    let (r, force, generation) = run(&nb, &[(12, Vec3::new(4.0, -3.0, 2.0))], &params(0.5, 1.0));
    assert_eq!(r.generations, 2);
    assert_eq!(r.pbg, vec![13, 17, 14, 22]);
    let expect = [
        (12, Vec3::new(4.0, -3.0, 2.0), 0),
        (13, Vec3::new(2.0, 0.0, 0.0), 1),
        (17, Vec3::new(0.0, 0.0, 1.0), 1),
        (14, Vec3::new(1.0, 0.0, 0.0), 2),
        (22, Vec3::new(0.0, 0.0, 0.5), 2),
    ];
    for (b, f, g) in expect {
        assert_eq!(force[b], f, "force of blade {b}");
        assert_eq!(generation[b], g, "generation of blade {b}");
    }
    for b in 0..25 {
        if !expect.iter().any(|e| e.0 == b) {
            assert_eq!(
                (force[b], generation[b]),
                (Vec3::ZERO, NO_GENERATION),
                "blade {b} untouched"
            );
        }
    }
}

/// Two ancestors point at the same blade from both sides: the gather sums
/// both contributions (Eq. 4). (1,1): F = (2,0,2); (3,1): F = (−3,0,1);
/// att = 0.5, L = 0.9. Gen 1: (2,1) ← (1 − 1.5, 0, 0) = (−0.5,0,0) (inactive),
/// (1,2) ← (0,0,1) (active), (3,2) ← (0,0,0.5) (inactive). Gen 2: (1,3) ←
/// (0,0,0.5), inactive: the end.
#[test]
fn eq4_two_ancestors_gathered_hand_computed() {
    let nb = grid(5, 5);
    let (r, force, generation) = run(
        &nb,
        &[
            (6, Vec3::new(2.0, 0.0, 2.0)),
            (8, Vec3::new(-3.0, 0.0, 1.0)),
        ],
        &params(0.5, 0.9),
    );
    assert_eq!(r.generations, 2);
    assert_eq!(r.pbg, vec![7, 11, 13, 16]);
    assert_eq!(force[7], Vec3::new(-0.5, 0.0, 0.0));
    assert_eq!(force[11], Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(force[13], Vec3::new(0.0, 0.0, 0.5));
    assert_eq!(force[16], Vec3::new(0.0, 0.0, 0.5));
    assert_eq!(
        [
            generation[7],
            generation[11],
            generation[13],
            generation[16]
        ],
        [1, 1, 1, 2]
    );
}

/// Definition 7: ancestors point at each other; neither receives anything.
#[test]
fn parallel_relation_ancestors_never_receive() {
    let nb = grid(5, 5);
    let dbg = [
        (12, Vec3::new(2.0, 0.0, 0.0)),
        (13, Vec3::new(-2.0, 0.0, 0.0)),
    ];
    let (r, force, generation) = run(&nb, &dbg, &params(1.0, 0.1));
    assert_eq!(
        r,
        PropagationResult {
            generations: 0,
            pbg: vec![],
            sources: vec![]
        }
    );
    assert_eq!((force[12], force[13]), (dbg[0].1, dbg[1].1));
    assert_eq!((generation[12], generation[13]), (0, 0));
}

#[test]
fn below_threshold_zero_generations_and_bad_input_do_not_propagate() {
    let nb = grid(5, 5);
    let f = Vec3::new(0.5, 0.0, 0.5);
    assert_eq!(
        run(&nb, &[(12, f)], &params(0.9, 1.0)).0.generations,
        0,
        "|F| < L: terminated"
    );
    let p = PropagationParams {
        max_generations: 0,
        ..params(0.9, 0.1)
    };
    assert_eq!(
        run(&nb, &[(12, f)], &p).0.generations,
        0,
        "max_generations = 0"
    );
    let nan = Vec3::new(f32::NAN, 0.0, 1.0);
    assert_eq!(
        run(&nb, &[(12, nan)], &params(0.9, 0.1)).0.generations,
        0,
        "NaN force is inert"
    );
    assert_eq!(
        run(&nb, &[(12, f)], &params(f32::NAN, 0.1)).1[13],
        Vec3::ZERO,
        "NaN att counts as 0"
    );
    // Indices out of range, neighbour indices out of range, short slices: no panic.
    let mut short_nb = nb.clone();
    short_nb[12][POS_X] = 999;
    let (mut force, mut generation) = (vec![Vec3::ZERO; 25], vec![NO_GENERATION; 25]);
    force[12] = f;
    let r = propagate_forces(
        &[12, 4000],
        &short_nb,
        &mut force,
        &mut generation,
        &[],
        &params(0.9, 0.1),
    );
    assert!(r.pbg.iter().all(|&b| b < 25));
    let r = propagate_forces(
        &[3],
        &nb[..2],
        &mut force,
        &mut generation,
        &[],
        &params(0.9, 0.1),
    );
    assert_eq!(r.generations, 0);
}

/// A row of 300 blades, att = 1, L = 0: the force never decays, so the
/// generation cap (stored as u8, 255 = none) ends it.
#[test]
fn generation_cap_fits_u8() {
    let nb = grid(300, 1);
    let p = PropagationParams {
        att: 1.0,
        threshold: 0.0,
        max_generations: 10_000,
        threshold_fade: 0.0,
        hold_weight: 0.0,
    };
    let (r, force, generation) = run(&nb, &[(0, Vec3::X)], &p);
    assert_eq!(r.generations, GENERATION_CAP);
    assert_eq!(generation[254], 254);
    assert_eq!(force[254], Vec3::X);
    assert_eq!(generation[255], NO_GENERATION);
    let p = PropagationParams {
        max_generations: 7,
        ..p
    };
    assert_eq!(run(&nb, &[(0, Vec3::X)], &p).0.generations, 7);
}

/// Random ancestors on a 20×20 grid, att < 0.7: every property of the
/// propagation, checked generation by generation.
#[test]
fn propagation_properties_random_fields() {
    let (w, h) = (20, 20);
    let nb = grid(w, h);
    let mut rng = Rng(0x5EED);
    for case in 0..150 {
        let p = params(rng.f32(0.0, 0.69), rng.f32(0.05, 1.0));
        let mut dbg = Vec::new();
        for _ in 0..1 + rng.below(6) {
            let dir = Vec3::new(rng.f32(-1.0, 1.0), rng.f32(-1.0, 1.0), rng.f32(-1.0, 1.0))
                .normalize_or_zero();
            dbg.push((rng.below(w * h), dir * rng.f32(0.5, 10.0)));
        }
        // Duplicate blades in the list: the first force wins in `setup`; make them agree.
        dbg.sort_by_key(|d| d.0);
        dbg.dedup_by_key(|d| d.0);
        let (r, force, generation) = run(&nb, &dbg, &p);

        // Terminates through decay, far before the cap.
        assert!(
            r.generations < GENERATION_CAP,
            "case {case}: {} generations",
            r.generations
        );
        // PBG ordered by (generation, index), generations 1 ..= r.generations.
        let keys: Vec<(u8, u32)> = r.pbg.iter().map(|&b| (generation[b as usize], b)).collect();
        assert!(
            keys.windows(2).all(|k| k[0] < k[1]),
            "case {case}: pbg order"
        );
        assert!(
            keys.iter()
                .all(|k| k.0 >= 1 && u32::from(k.0) <= r.generations)
        );
        // Untouched blades stay reset; PBG forces are horizontal.
        for b in 0..force.len() as u32 {
            let reached = dbg.iter().any(|d| d.0 == b) || r.pbg.contains(&b);
            if !reached {
                assert_eq!(
                    (force[b as usize], generation[b as usize]),
                    (Vec3::ZERO, NO_GENERATION)
                );
            }
        }
        assert!(r.pbg.iter().all(|&b| force[b as usize].y == 0.0));

        // Energy bound |F_{G+1}| ≤ √2 · att · max |F_G|; every child has an
        // active parent of the previous generation pointing at it.
        for g in 0..r.generations as u8 {
            let max_of = |wanted: u8| {
                (0..force.len())
                    .filter(|&b| generation[b] == wanted)
                    .map(|b| force[b].length())
                    .fold(0.0, f32::max)
            };
            let (parent_max, child_max) = (max_of(g), max_of(g + 1));
            assert!(
                child_max <= std::f32::consts::SQRT_2 * p.att * parent_max * (1.0 + 1e-6),
                "case {case} gen {g}: {child_max} > √2·{}·{parent_max}",
                p.att
            );
            for b in (0..force.len()).filter(|&b| generation[b] == g + 1) {
                let has_parent = nb[b].iter().any(|&j| {
                    j != NO_NEIGHBOUR
                        && generation[j as usize] == g
                        && force[j as usize].length() >= p.threshold
                });
                assert!(
                    has_parent,
                    "case {case}: blade {b} of generation {} has no active parent",
                    g + 1
                );
            }
        }

        // The paper's scatter gives the same bits.
        let (_, mut sf, mut sg) = setup(nb.len(), &dbg);
        let sgens = reference_scatter(&nb, &mut sf, &mut sg, &p);
        assert_eq!(sgens, r.generations, "case {case}: generations vs scatter");
        assert_eq!(
            sg, generation,
            "case {case}: generations per blade vs scatter"
        );
        assert!(
            sf.iter()
                .zip(&force)
                .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
        );

        // Generation G never changes a blade of generation ≤ G: run with
        // max_generations = G and G + 1 and compare.
        for g in 0..r.generations {
            let before = run(
                &nb,
                &dbg,
                &PropagationParams {
                    max_generations: g,
                    ..p
                },
            );
            let after = run(
                &nb,
                &dbg,
                &PropagationParams {
                    max_generations: g + 1,
                    ..p
                },
            );
            assert_eq!(before.0.generations, g);
            for b in 0..force.len() {
                if before.2[b] != NO_GENERATION {
                    assert_eq!(
                        after.2[b], before.2[b],
                        "case {case}: generation of {b} changed by generation {g}"
                    );
                    assert_eq!(
                        after.1[b], before.1[b],
                        "case {case}: force of {b} changed by generation {g}"
                    );
                }
            }
            assert!(after.0.pbg.starts_with(&before.0.pbg));
        }
    }
}

fn bits(force: &[Vec3]) -> Vec<[u32; 3]> {
    force
        .iter()
        .map(|f| f.to_array().map(f32::to_bits))
        .collect()
}

/// A 200×200 grid with (a) a checkerboard of ancestors, so that a frontier of
/// ~20 000 blades, each gathering from up to four neighbours, goes through
/// the parallel path, and (b) a line of ancestors with many generations:
/// the same bits on 1 and 2 threads and on the paper's scatter.
#[test]
fn deterministic_independent_of_thread_count() {
    let (w, h) = (200, 200);
    let nb = grid(w, h);
    let mut rng = Rng(42);
    let checker: Vec<(u32, Vec3)> = (0..w * h)
        .filter(|b| (b % w + b / w) % 2 == 0)
        .map(|b| {
            (
                b,
                Vec3::new(rng.f32(-5.0, 5.0), rng.f32(-1.0, 1.0), rng.f32(-5.0, 5.0)),
            )
        })
        .collect();
    let line: Vec<(u32, Vec3)> = (0..h)
        .map(|z| {
            (
                z * w + 100,
                Vec3::new(rng.f32(-9.0, 9.0), 0.0, rng.f32(-9.0, 9.0)),
            )
        })
        .collect();
    for (name, dbg, p) in [
        ("checkerboard", &checker, params(0.6, 0.5)),
        ("line", &line, params(0.69, 0.01)),
    ] {
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| run(&nb, dbg, &p))
        };
        let (one, two) = (on(1), on(2));
        assert!(
            one.0.pbg.len() > 1000,
            "{name}: a big frontier ({})",
            one.0.pbg.len()
        );
        assert_eq!(one.0, two.0, "{name}: result");
        assert_eq!(one.2, two.2, "{name}: generations");
        assert_eq!(bits(&one.1), bits(&two.1), "{name}: forces");
        let (_, mut sf, mut sg) = setup(nb.len(), dbg);
        reference_scatter(&nb, &mut sf, &mut sg, &p);
        assert_eq!(bits(&sf), bits(&one.1), "{name}: scatter");
        assert_eq!(sg, one.2, "{name}: scatter generations");
    }
}

/// The threshold's fade-in (ours, DESIGN §5 "continuous"): an ancestor a
/// hair below L pushes nothing, a hair above it pushes a hair; without the
/// fade the same hair decides between nothing and `att · L`.
#[test]
fn a_force_at_the_threshold_pushes_continuously() {
    let nb = grid(5, 5);
    let l = 0.25;
    let push = |f: f32, fade: f32| {
        let p = PropagationParams {
            threshold_fade: fade,
            ..params(0.5, l)
        };
        run(&nb, &[(12, Vec3::new(f, 0.0, 0.0))], &p).1[13].x
    };
    let (below, above) = (l * (1.0 - 1e-6), l * (1.0 + 1e-6));
    assert_eq!(push(below, 0.25), 0.0);
    assert!(push(above, 0.25) < 1e-5, "{}", push(above, 0.25));
    assert!((push(above, 0.0) - 0.5 * above).abs() < 1e-7);
    // Full push from (1 + fade) L on.
    assert!((push(2.0 * l, 0.25) - 0.5 * 2.0 * l).abs() < 1e-7);
}

/// An ancestor barely touched (contact weight near 0) takes a neighbour's
/// push as a child would; one touched at the hold weight or more is the
/// paper's ancestor and takes none; in between, in proportion.
#[test]
fn lightly_held_ancestors_take_part_of_a_push() {
    let nb = grid(5, 5);
    let p = PropagationParams {
        hold_weight: 0.1,
        ..params(0.5, 0.1)
    };
    let taken = |w13: f32| {
        let (list, mut force, mut generation) = setup(
            nb.len(),
            &[
                (12, Vec3::new(2.0, 0.0, 0.0)),
                (13, Vec3::new(0.0, 0.0, 0.01)),
            ],
        );
        let mut weight = vec![0.0; nb.len()];
        weight[12] = 1.0;
        weight[13] = w13;
        propagate_forces(&list, &nb, &mut force, &mut generation, &weight, &p);
        (force[13], generation[13])
    };
    let (f, g) = taken(1.0);
    assert_eq!((f, g), (Vec3::new(0.0, 0.0, 0.01), 0), "wholly held");
    let (f, g) = taken(0.0);
    assert_eq!(g, 1);
    assert!((f.x - 1.0).abs() < 1e-6 && (f.z - 0.01).abs() < 1e-7, "{f}");
    let (f, _) = taken(0.05);
    assert!((f.x - 0.5).abs() < 1e-6, "half held takes half: {f}");
    let (a, _) = taken(0.1 - 1e-6);
    assert!(a.x < 1e-4, "at the hold weight: {a}");
}
