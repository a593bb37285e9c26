//! Frame-rate independence (DESIGN §6): one second of the same motion at
//! 30 and at 144 steps per second leaves nearly the same field.
//!
//! Tolerance: the mean distance between the two runs' tips, over blades that
//! either run moved, is below 15 % of the mean tip displacement (measured
//! 2026-11-23: 4.2 %), and of the blades bent (tip more than 5 cm from
//! rest) in either run at least 90 % are bent in both (measured: 346 of 350).

mod common;
use common::*;

fn run_at(dt: f32) -> trample::Simulation {
    let mut sim = sim_from(&rolling_ball_toml(2, "inf", 1.0));
    let frames = (1.0 / dt).round() as u64;
    for _ in 0..frames {
        sim.step(dt).unwrap();
    }
    assert!((sim.time - 1.0).abs() < 1e-3);
    sim
}

#[test]
fn one_second_at_30_and_144_hz_gives_nearly_the_same_field() {
    let (a, b) = (run_at(1.0 / 30.0), run_at(1.0 / 144.0));
    let moved = (0..a.field.blades.count)
        .filter(|&i| {
            let bl = (&a.field.blades, &b.field.blades);
            let n = bl.0.segments;
            let rest = bl.0.rest_vertex(i, n);
            bl.0.vertex(i, n).distance(rest) > 1e-6 || bl.1.vertex(i, n).distance(rest) > 1e-6
        })
        .count();
    assert!(moved > 50);
    let (ratio, both, either) = track_difference(&a, &b);
    println!(
        "frame-rate: {moved} blades moved, mean tip difference / mean displacement = {ratio:.4}, bent in both {both} of {either}"
    );
    assert!(
        ratio < 0.15,
        "tips differ by {ratio:.3} of their displacement"
    );
    assert!(
        both as f32 >= 0.9 * either as f32,
        "bent sets differ: {both} of {either}"
    );
}
