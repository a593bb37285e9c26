//! A fast object is sub-stepped, not tunnelled (DESIGN §9): a small ball
//! crossing the field at 36 m/s with 30 steps/s (1.2 m per step, three times
//! its 0.4 m diameter) still hits every blade on its path; with sub-stepping
//! switched off (`max_substeps = 1`) it skips blades, which shows the test
//! can fail. Past `max_substeps` the step is clamped, never silently: each
//! such step is counted and the first is kept for a one-time warning.

mod common;
use common::{deepest_inside, position_bits, root_xz, sim_from};

/// An 8 m × 3.2 m field of 5,120 blades, every cell geometric, at
/// precision 7, watched from the side, with `sim` added to its `[sim]`
/// table and `objects` after it.
fn field_toml(sim: &str, objects: &str) -> String {
    format!(
        r#"
[field]
patches = [4, 2]
cells_per_patch = 16
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
precision = 7
{sim}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 5.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
{objects}"#
    )
}

struct Outcome {
    hit_share: f32,
    max_substeps_run: u32,
    max_substeps_needed: u32,
    clamps: u64,
    first_clamp: Option<trample::step::SubstepClamp>,
}

fn run_bullet(max_substeps: u32) -> Outcome {
    let toml = field_toml(
        &format!("max_substeps = {max_substeps}"),
        r#"
[[objects]]
name = "bullet"
shape = { kind = "sphere", radius_m = 0.2 }
orientation = "rolling"
path = { kind = "line", from = [-4.0, 0.2, 0.0], to = [4.0, 0.2, 0.0], duration_s = 0.22222222 }
"#,
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

/// An `[[objects]]` table: a rolling ball `name` of `radius` metres on a
/// line at its own height, from `x0, z` to `x1, z` in `seconds`.
fn ball(name: &str, radius: f32, (x0, x1, z): (f32, f32, f32), seconds: f32) -> String {
    format!(
        r#"
[[objects]]
name = "{name}"
shape = {{ kind = "sphere", radius_m = {radius} }}
orientation = "rolling"
path = {{ kind = "line", from = [{x0}, {radius}, {z}], to = [{x1}, {radius}, {z}], duration_s = {seconds} }}
"#
    )
}

/// A field with, when `slow`, a ball rolling on its left half at 3 m/s
/// (0.1 m a step at 30 steps/s: one sub-step) and, when `bullet`, a
/// smaller one crossing its right half at 18 m/s (0.6 m a step:
/// sub-stepped), recovering over `recovery` seconds.
fn slow_and_fast(slow: bool, bullet: bool, recovery: &str) -> trample::Simulation {
    let mut objects = String::new();
    if slow {
        objects.push_str(&ball("slow", 0.3, (-3.5, -0.5, -0.5), 1.0));
    }
    if bullet {
        objects.push_str(&ball("bullet", 0.2, (0.5, 3.9, 0.5), 0.18888889));
    }
    sim_from(&field_toml(&format!("recovery_s = {recovery}"), &objects))
}

/// A body is sub-stepped for its own speed, not for the fastest body's
/// (`step/passes.rs`, near passes): with a fast ball on the field a slow
/// one still steps once a step, in the main pass, and the fast one takes
/// its sub-steps in a pass of its own. Each leaves, bit for bit, the track
/// it leaves alone on the field (their tracks are apart). Before, the slow
/// ball was sub-stepped with the fast one, and its track's bits changed.
/// `stages::plan_substeps`, the plan of the step as one pass, is the
/// fastest pass's.
#[test]
fn a_slow_object_is_not_sub_stepped_for_a_fast_one() {
    let dt = 1.0 / 30.0;
    let mut both = slow_and_fast(true, true, "inf");
    let mut slow = slow_and_fast(true, false, "inf");
    let mut fast = slow_and_fast(false, true, "inf");
    let rest = position_bits(&both);
    let mut substeps = 0;
    for step in 0..10 {
        let passes = trample::step::passes::plan_passes(&both, dt);
        if step == 0 {
            assert_eq!(passes.len(), 2, "{passes:?}");
            assert!(passes[0].main && passes[0].has(0) && !passes[0].has(1));
            assert_eq!(passes[0].plan.substeps, 1);
            assert!(!passes[1].main && passes[1].has(1) && !passes[1].has(0));
            assert!(passes[1].plan.substeps >= 2, "{:?}", passes[1].plan);
            assert_eq!(
                (passes[1].start, passes[1].dt),
                (passes[0].start, passes[0].dt)
            );
        }
        // The whole step's plan, as if every body ran in one pass: the
        // fastest body's, which its own pass runs.
        let whole = trample::step::stages::plan_substeps(&both, dt);
        let fastest = passes.iter().map(|p| p.plan).max_by_key(|p| p.needed);
        assert_eq!(Some(whole), fastest, "step {step}");
        if passes.len() == 2 {
            assert_eq!(whole.fastest, Some(1), "the bullet is the fastest");
        }
        let t = both.step(dt).unwrap();
        assert_eq!(t.far_bodies, 0, "near bodies are not far");
        substeps = substeps.max(t.substeps);
        slow.step(dt).unwrap();
        fast.step(dt).unwrap();
    }
    assert!(substeps >= 2, "the step reports the fast ball's sub-steps");
    let (both, slow, fast) = (
        position_bits(&both),
        position_bits(&slow),
        position_bits(&fast),
    );
    let (mut by_slow, mut by_fast) = (0, 0);
    for (i, v) in both.iter().enumerate() {
        let (s, f) = (slow[i] != rest[i], fast[i] != rest[i]);
        assert!(!(s && f), "the two tracks are apart");
        if s {
            by_slow += 1;
            assert_eq!(v, &slow[i], "vertex {i} of the slow ball's track");
        } else if f {
            by_fast += 1;
            assert_eq!(v, &fast[i], "vertex {i} of the fast ball's track");
        } else {
            assert_eq!(v, &rest[i], "vertex {i} at rest");
        }
    }
    assert!(
        by_slow > 100 && by_fast > 100,
        "{by_slow} and {by_fast} vertices moved"
    );
}

/// With a finite `recovery_s` a blade the fast ball holds recovers in the
/// main pass, which runs first, and its own pass presses it again: at the
/// end of every step no blade lies inside either ball by more than the
/// 2 cm that `tests/contact.rs` allows an object at rest (at the end of
/// the step the fast ball's contact response has run last).
#[test]
fn no_blade_stays_inside_a_fast_object_stepped_in_its_own_pass() {
    let mut sim = slow_and_fast(true, true, "0.5");
    let mut deepest = [0.0f32; 2];
    for _ in 0..10 {
        sim.step(1.0 / 30.0).unwrap();
        for (i, d) in deepest.iter_mut().enumerate() {
            *d = d.max(deepest_inside(&sim, i));
        }
    }
    println!(
        "deepest inside: slow {} m, fast {} m",
        deepest[0], deepest[1]
    );
    assert!(deepest.iter().all(|&d| d <= 0.02), "{deepest:?}");
}

/// A paddle on an arm: a small box 1.2 m from its body's origin, the body
/// turning about its origin twice a second (keyframed yaw), so the paddle
/// sweeps a circle at 15 m/s (0.5 m a step of 1/30 s, four times its
/// 0.12 m thickness). Returns the shares of the blades under its circle
/// hit directly and moved at all in one turn, and the most sub-steps a
/// step ran.
fn run_paddle(max_substeps: u32) -> (f32, f32, u32) {
    use trample::object::path::Keyframe;
    use trample::object::{Orientation, PathParams};
    let mut sim = sim_from(&field_toml(&format!("max_substeps = {max_substeps}"), ""));
    let mut paddle = trample::object::shapes::cuboid(glam::Vec3::new(0.06, 0.15, 0.06));
    for p in &mut paddle.positions {
        *p += glam::Vec3::new(1.2, 0.15, 0.0);
    }
    let keys = (0..=4)
        .map(|k| Keyframe {
            t_s: 0.125 * k as f32,
            position: [0.0; 3],
            rotation_deg: Some([90.0 * k as f32, 0.0, 0.0]),
        })
        .collect();
    sim.add_body(
        trample::BodyBuilder::mesh("paddle", &paddle)
            .path(PathParams::Keyframes { keys })
            .orientation(Orientation::Keyframes)
            .build()
            .unwrap(),
    );
    let mut substeps = 0;
    for _ in 0..15 {
        substeps = substeps.max(sim.step(1.0 / 30.0).unwrap().substeps);
    }
    let (mut on, mut hit, mut moved) = (0, 0, 0);
    for b in 0..sim.field.blades.count {
        let (x, z) = root_xz(&sim, b);
        if (x.hypot(z) - 1.2).abs() < 0.04 {
            on += 1;
            hit += usize::from(sim.class[b] == trample::step::BladeClass::Direct);
            moved += usize::from(!sim.field.blades.is_at_rest(b));
        }
    }
    assert!(on > 50, "{on} blades under the circle");
    (hit as f32 / on as f32, moved as f32 / on as f32, substeps)
}

/// A part of a body far from its origin is sub-stepped for how fast it
/// sweeps about the origin, not for how fast its box turns about its own
/// centre: the paddle hits every blade under its circle. (Before, the spin
/// counted `|ω|` times the root box's half diagonal, 0.17 m here against
/// the 1.26 m its far corners turn at: one sub-step a step, and the paddle
/// skipped most of its circle, as it does with `max_substeps = 1`.)
#[test]
fn a_box_spinning_about_a_distant_origin_is_sub_stepped_and_misses_no_blade() {
    let (with, moved, substeps) = run_paddle(16);
    let (without, moved_one, one) = run_paddle(1);
    println!(
        "paddle's circle: hit {with:.3}, moved {moved:.3} with {substeps} sub-steps; \
         hit {without:.3}, moved {moved_one:.3} with {one}"
    );
    assert!(substeps >= 4 && one == 1, "{substeps} {one}");
    // Every blade under the circle moved; nearly all hit directly (one
    // at the paddle's inner edge may be only pushed by the contact).
    assert_eq!(
        moved, 1.0,
        "the paddle left blades under its circle standing"
    );
    assert!(with > 0.95, "the paddle hit only {with:.3} of its circle");
    assert!(
        moved_one < 0.75,
        "with one sub-step it should skip blades ({moved_one:.3})"
    );
}
