//! A fast object is sub-stepped, not tunnelled (DESIGN §9): a small ball
//! crossing the field at 36 m/s with 30 steps/s (1.2 m per step, three times
//! its 0.4 m diameter) still hits every blade on its path; with sub-stepping
//! switched off (`max_substeps = 1`) it skips blades, which shows the test
//! can fail. Past `max_substeps` the step is clamped, never silently: each
//! such step is counted and the first is kept for a one-time warning.

mod common;
use common::{root_xz, sim_from};

struct Outcome {
    hit_share: f32,
    max_substeps_run: u32,
    max_substeps_needed: u32,
    clamps: u64,
    first_clamp: Option<trample::step::SubstepClamp>,
}

fn run_bullet(max_substeps: u32) -> Outcome {
    let toml = format!(
        r#"
[field]
patches = [4, 2]
cells_per_patch = 16
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
precision = 7
max_substeps = {max_substeps}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 5.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "bullet"
shape = {{ kind = "sphere", radius_m = 0.2 }}
orientation = "rolling"
path = {{ kind = "line", from = [-4.0, 0.2, 0.0], to = [4.0, 0.2, 0.0], duration_s = 0.22222222 }}
"#
    );
    let mut sim = sim_from(&toml);
    let (mut substeps, mut needed) = (0, 0);
    for _ in 0..10 {
        let t = sim.step(1.0 / 30.0).unwrap();
        substeps = substeps.max(t.substeps);
        needed = needed.max(t.substeps_needed);
    }
    let (mut on, mut hit) = (0, 0);
    for b in 0..sim.field.blades.count {
        let (x, z) = root_xz(&sim, b);
        if x.abs() < 2.8 && z.abs() < 0.08 {
            on += 1;
            hit += usize::from(sim.class[b] == trample::step::BladeClass::Direct);
        }
    }
    assert!(on > 40);
    Outcome {
        hit_share: hit as f32 / on as f32,
        max_substeps_run: substeps,
        max_substeps_needed: needed,
        clamps: sim.substep_clamps,
        first_clamp: sim.first_substep_clamp.clone(),
    }
}

#[test]
fn fast_ball_is_sub_stepped_and_misses_no_blade() {
    let with = run_bullet(16);
    let without = run_bullet(1);
    let (substeps, one) = (with.max_substeps_run, without.max_substeps_run);
    println!(
        "hit share on the path: {:.3} with {substeps} sub-steps, {:.3} without",
        with.hit_share, without.hit_share
    );
    assert!(substeps >= 2 && one == 1);
    assert!(
        with.hit_share > 0.99,
        "sub-stepped ball hit only {:.3} of the blades on its path",
        with.hit_share
    );
    assert!(
        without.hit_share < 0.9,
        "without sub-steps the ball should skip blades (hit {:.3})",
        without.hit_share
    );
    assert_eq!(with.max_substeps_needed, substeps);
    assert_eq!((with.clamps, with.first_clamp), (0, None));
}

#[test]
fn ball_too_fast_for_max_substeps_is_clamped_counted_and_reported_once() {
    let clamped = run_bullet(2);
    assert_eq!(clamped.max_substeps_run, 2);
    assert!(
        clamped.max_substeps_needed > 2,
        "needed {}",
        clamped.max_substeps_needed
    );
    // The ball crosses the 8 m path in 0.222 s: frames 0..6 at 30 steps/s
    // move it (frame 6 only for its last 0.022 s, too little to clamp).
    assert!(
        (5..=7).contains(&clamped.clamps),
        "clamped steps: {}",
        clamped.clamps
    );
    let first = clamped.first_clamp.expect("the first clamp is kept");
    assert_eq!((first.frame, first.object.as_str()), (0, "bullet"));
    assert_eq!(first.max_substeps, 2);
    let text = first.to_string();
    assert!(
        text.contains("\"bullet\"") && text.contains("sim.max_substeps = 2"),
        "{text}"
    );
}

/// A ball that crosses the whole 6.4 m field, and 60 m beyond, in a single
/// step of 1/30 s (about 2,000 m/s): with enough sub-steps (here up to
/// 1024) it still hits every blade on its path; the default 16 are not
/// enough — it skips blades — and the step says so instead of tunnelling
/// silently.
#[test]
fn ball_crossing_the_field_in_one_step_is_sub_stepped_or_reported() {
    let run = |max_substeps: u32| {
        let toml = format!(
            r#"
[field]
patches = [4, 1]
cells_per_patch = 16
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
precision = 7
max_substeps = {max_substeps}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 5.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "bullet"
shape = {{ kind = "sphere", radius_m = 0.2 }}
path = {{ kind = "line", from = [-34.0, 0.2, 0.0], to = [34.0, 0.2, 0.0], duration_s = 0.033333335 }}
"#
        );
        let mut sim = sim_from(&toml);
        let t = sim.step(1.0 / 30.0).unwrap().clone();
        let (mut on, mut hit) = (0, 0);
        for b in 0..sim.field.blades.count {
            let (x, z) = root_xz(&sim, b);
            if x.abs() < 3.0 && z.abs() < 0.08 {
                on += 1;
                hit += usize::from(sim.class[b] == trample::step::BladeClass::Direct);
            }
        }
        (t, hit as f32 / on as f32, sim.substep_clamps)
    };
    let (enough, share, clamps) = run(1024);
    assert!(
        enough.substeps > 16 && enough.substeps == enough.substeps_needed,
        "{enough}"
    );
    assert!(share > 0.99, "hit {share:.3} of the blades on the path");
    assert_eq!(clamps, 0);
    let (default, share16, clamps) = run(16);
    assert_eq!(default.substeps, 16);
    assert!(default.substeps_needed > 16, "{default}");
    assert_eq!(clamps, 1, "the clamped step is counted");
    assert!(
        share16 < 0.5,
        "16 sub-steps of 4 m should skip blades ({share16:.3})"
    );
    println!(
        "{} sub-steps needed; hit share {share:.3} with them, {share16:.3} with 16",
        enough.substeps_needed
    );
}
