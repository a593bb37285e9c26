//! Determinism (issue: core acceptance): the same scene twice, and on 1 vs 2
//! worker threads, gives bit-identical blade vertices and classes.

mod common;
use common::*;

fn run_on(threads: usize) -> (Vec<u32>, Vec<u8>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut sim = sim_from(&rolling_ball_toml(3, "2.0", 1.5));
        sim.run(90).unwrap();
        (
            sim.blade_vertices().iter().map(|v| v.to_bits()).collect(),
            sim.class.clone(),
        )
    })
}

#[test]
fn same_scene_twice_and_on_one_or_two_threads_is_bit_identical() {
    let one = run_on(1);
    let two = run_on(2);
    let again = run_on(2);
    assert!(one.1.iter().any(|&c| c != 0), "the run must touch blades");
    assert_eq!(two, again, "two runs on 2 threads differ");
    assert_eq!(one, two, "1 thread and 2 threads differ");
}
