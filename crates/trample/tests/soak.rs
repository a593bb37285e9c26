//! Deformation invariants over long, busy runs (DESIGN §6; issue 6): the
//! test kit's busy scene — four objects on circles that never end, one of
//! them the knot, a camera circling so that cells keep changing level of
//! detail (transitions every step), noise terrain, finite recovery so
//! blades are bent, recover and are bent again — on a 2,304-blade field
//! stays sound. Every 50 steps: every vertex and billboard slope finite,
//! every segment within 1e-4 (relative) of its rest length, every root
//! where it was planted, no vertex below the terrain (the lowest vertex is
//! printed: the ground guard keeps 2 mm). Over the run: the
//! scene stays busy (DBG blades in most steps, LOD transitions, blade tips
//! lowered by 5 cm or more) and memory does not grow after a warm-up
//! (resident set size from `/proc/self/status`). The scene has no wind:
//! wind bends blades at draw time only (`trample::wind`), it never changes
//! the simulation state checked here (its tests are in the render crate).
//!
//! `soak_smoke_5000_steps` runs in CI; `soak_100000_steps` is `#[ignore]`d
//! (`cargo test -p trample --test soak -- --ignored --nocapture`); its
//! figures are recorded in RELIABILITY.md.

use std::sync::Mutex;
use std::time::Instant;
use trample::Simulation;
use trample_testkit::scenes;

/// The two soaks measure the process's memory: never at the same time.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Resident set size of this process, KiB (`VmRSS`).
fn rss_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
        .expect("VmRSS")
}

/// CPU time this process has used (user + system), seconds: fields 14 and
/// 15 of `/proc/self/stat`, in clock ticks of 1/100 s (Linux's USER_HZ).
/// Reported next to wall time because the machine is shared.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat");
    // The command name (field 2) may hold spaces: count from its ')'.
    let after = &stat[stat.rfind(')').expect("comm") + 2..];
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| fields[i - 3].parse::<f64>().expect("ticks");
    (ticks(14) + ticks(15)) / 100.0
}

/// Every how many steps the whole field is checked.
const CHECK_EVERY: u64 = 50;

/// A tip this far below its rest tip, metres, counts as visibly bent
/// (rest tips are 0.45 m ± 30 % high).
const BENT_TIP_M: f32 = 0.05;

/// What a check of the whole field found.
#[derive(Default)]
struct Soundness {
    non_finite: usize,
    non_finite_slopes: usize,
    max_length_drift: f32,
    roots_moved: usize,
    below_ground: usize,
    /// Lowest height of a vertex above the root over the terrain under it, metres.
    lowest_above_ground: f32,
}

fn check(sim: &Simulation) -> Soundness {
    let bl = &sim.field.blades;
    let mut s = Soundness {
        lowest_above_ground: f32::INFINITY,
        ..Soundness::default()
    };
    for b in 0..bl.count {
        if bl.vertex(b, 0) != bl.rest_vertex(b, 0) {
            s.roots_moved += 1;
        }
        for k in 0..=bl.segments {
            let v = bl.vertex(b, k);
            if !v.is_finite() {
                s.non_finite += 1;
                continue;
            }
            // The ground guard keeps vertices at the terrain plus a clearance.
            let above = v.y - sim.field.terrain.height_at(v.x, v.z);
            if above < 0.0 {
                s.below_ground += 1;
            }
            if k > 0 {
                s.lowest_above_ground = s.lowest_above_ground.min(above);
            }
            if k > 0 {
                let len = v.distance(bl.vertex(b, k - 1));
                let drift = (len - bl.seg_len[b]).abs() / bl.seg_len[b];
                s.max_length_drift = s.max_length_drift.max(drift);
            }
        }
    }
    s.non_finite_slopes = sim
        .field
        .cells
        .slope
        .iter()
        .filter(|v| !v.is_finite())
        .count();
    s
}

/// Runs `steps` steps of the busy scene at 60 steps/s, checking the field
/// every [`CHECK_EVERY`] steps; returns after printing the figures.
fn soak(steps: u64, warm_up: u64, max_rss_growth_kib: u64) {
    let _guard = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut sim = scenes::simulation(scenes::BUSY);
    let dt = 1.0 / 60.0;
    let (clock, cpu_start) = (Instant::now(), cpu_s());
    let (mut worst_drift, mut max_displaced, mut transitions, mut dbg_steps) = (0f32, 0, 0u64, 0);
    let (mut most_bent, mut lowest) = (0, f32::INFINITY);
    let mut rss_after_warm_up = 0;
    let mut stage_ms = [0f64; 9];
    for i in 1..=steps {
        let t = sim.step(dt).unwrap();
        for (sum, (_, ms)) in stage_ms.iter_mut().zip(t.stages()) {
            *sum += ms;
        }
        max_displaced = max_displaced.max(t.displaced_blades);
        transitions += u64::from(t.transitions);
        dbg_steps += u64::from(t.dbg_blades > 0);
        if i == warm_up {
            rss_after_warm_up = rss_kib();
        }
        if i % CHECK_EVERY == 0 || i == steps {
            let s = check(&sim);
            assert_eq!(s.non_finite, 0, "step {i}: non-finite vertices");
            assert_eq!(
                s.non_finite_slopes, 0,
                "step {i}: non-finite billboard slopes"
            );
            assert_eq!(s.roots_moved, 0, "step {i}: roots moved");
            assert_eq!(s.below_ground, 0, "step {i}: vertices below the ground");
            assert!(
                s.max_length_drift <= 1e-4,
                "step {i}: a segment's length drifted by {:.2e} of its rest length",
                s.max_length_drift
            );
            worst_drift = worst_drift.max(s.max_length_drift);
            lowest = lowest.min(s.lowest_above_ground);
            most_bent = most_bent.max(sim.field.blades.tips_lowered_by(BENT_TIP_M));
        }
    }
    let wall = clock.elapsed().as_secs_f64();
    let cpu = cpu_s() - cpu_start;
    let rss_end = rss_kib();
    let names = sim.timings.stages().map(|(n, _)| n);
    let per_stage: Vec<String> = names
        .iter()
        .zip(stage_ms)
        .map(|(n, ms)| format!("{n} {:.3}", ms / steps as f64))
        .collect();
    println!("soak: mean ms per stage: {}", per_stage.join(", "));
    println!(
        "soak: {steps} steps ({:.0} s simulated) of {} blades and {} objects in {wall:.1} s wall, {cpu:.1} s CPU ({:.3} ms/step wall); \
         max length drift {worst_drift:.2e}; lowest vertex {lowest:.4} m above the terrain; up to {max_displaced} blades displaced and {most_bent} tips lowered by {BENT_TIP_M} m or more at once; \
         {dbg_steps} steps with DBG blades; {transitions} LOD transitions; {} steps clamped; \
         RSS {rss_after_warm_up} KiB after {warm_up} warm-up steps, {rss_end} KiB at the end",
        sim.time,
        sim.field.blades.count,
        sim.bodies.len(),
        wall * 1e3 / steps as f64,
        sim.substep_clamps
    );
    assert!(
        dbg_steps > steps / 2 && transitions > 0 && most_bent > 100,
        "the scene must stay busy: DBG blades in {dbg_steps} of {steps} steps, \
         {transitions} transitions, at most {most_bent} tips lowered by {BENT_TIP_M} m"
    );
    assert!(
        rss_end <= rss_after_warm_up + max_rss_growth_kib,
        "memory grew from {rss_after_warm_up} KiB to {rss_end} KiB after the warm-up"
    );
}

#[test]
fn soak_smoke_5000_steps() {
    soak(5_000, 1_000, 1024);
}

#[test]
#[ignore = "long: about a minute; run with --ignored, figures in RELIABILITY.md"]
fn soak_100000_steps() {
    soak(100_000, 5_000, 1024);
}
