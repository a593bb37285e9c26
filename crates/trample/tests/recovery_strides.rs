//! Slow blades recover in strides (`[sim] recovery_stride_m`, ours, issue
//! 16): a displaced blade whose recovery moves it slowly is relaxed only
//! once it owes the time that moves it about a stride (default half a
//! millimetre), and then over all of it. Against the same scene with every
//! displaced blade relaxed every step (`recovery_stride_m = 0`), no vertex
//! is ever more than a few strides away, the trail comes back to rest as
//! soon, and far fewer blades are relaxed (and uploaded) a step.

mod common;
use common::sim_from;
use trample::Simulation;

/// A 6.4 m × 3.2 m field of 2,048 blades (every cell geometric) with a
/// 0.5 m ball rolling across it in 2 s and off it, its track recovering
/// with `recovery_s = 3` (trail 2: a flattened blade's `τ` is 9 s), and `sim` added to `[sim]`.
fn scene(sim: &str) -> Simulation {
    sim_from(&format!(
        r#"
[field]
patches = [2, 1]
cells_per_patch = 32
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
precision = 5
recovery_s = 3.0
trail = 2.0
{sim}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 5.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.5 }}
orientation = "rolling"
path = {{ kind = "line", from = [-3.0, 0.5, 0.0], to = [9.0, 0.5, 0.0], duration_s = 4.0 }}
"#
    ))
}

/// The largest distance between a vertex of `a` and the same vertex of `b`.
fn farthest_vertex(a: &Simulation, b: &Simulation) -> f32 {
    let (x, y) = (&a.field.blades, &b.field.blades);
    (0..x.count)
        .flat_map(|bl| (0..=x.segments).map(move |k| (bl, k)))
        .map(|(bl, k)| x.vertex(bl, k).distance(y.vertex(bl, k)))
        .fold(0.0, f32::max)
}

struct Run {
    /// The largest vertex distance from the every-step run at any step.
    worst: f32,
    /// Blades relaxed or bent (listed for upload), summed over the steps.
    uploads: usize,
    /// The every-step run's sum.
    uploads_every_step: usize,
    /// The first step at which each run has every blade at rest.
    at_rest: (Option<usize>, Option<usize>),
}

fn run(stride: f32, steps: usize) -> Run {
    let mut every = scene("recovery_stride_m = 0.0");
    let mut strided = scene(&format!("recovery_stride_m = {stride}"));
    let (mut worst, mut uploads, mut uploads_every_step) = (0.0f32, 0, 0);
    let mut at_rest = (None, None);
    for step in 0..steps {
        every.step(1.0 / 60.0).unwrap();
        strided.step(1.0 / 60.0).unwrap();
        uploads_every_step += every.changed_blades().count();
        uploads += strided.changed_blades().count();
        worst = worst.max(farthest_vertex(&every, &strided));
        if at_rest.0.is_none() && step > 60 && every.blades_away_from_rest() == 0 {
            at_rest.0 = Some(step);
        }
        if at_rest.1.is_none() && step > 60 && strided.blades_away_from_rest() == 0 {
            at_rest.1 = Some(step);
        }
    }
    Run {
        worst,
        uploads,
        uploads_every_step,
        at_rest,
    }
}

/// Strides of half a millimetre and of two: every vertex stays within
/// three strides of where it is when every displaced blade recovers every
/// step (measured 2026-11-30: 0.96 mm and 4.2 mm, the lag of a blade just
/// before its turn plus the trail's `τ` taken at the start of a stride),
/// the trail is back at rest within a third of a second of the every-step
/// run (4 and 13 steps later), and fewer blades are relaxed and uploaded
/// over the 30 s (48 % and 19 % as many).
#[test]
fn strides_stay_within_a_few_strides_of_every_step_and_relax_fewer_blades() {
    for (stride, share) in [(0.0005, 0.6), (0.002, 0.3)] {
        let r = run(stride, 30 * 60);
        let seen = format!(
            "stride {stride} m: worst {:.2e} m, uploads {} against {}, at rest {:?}",
            r.worst, r.uploads, r.uploads_every_step, r.at_rest
        );
        eprintln!("{seen}");
        assert!(r.worst < 3.0 * stride, "{seen}");
        assert!(
            (r.uploads as f64) < share * r.uploads_every_step as f64,
            "{seen}"
        );
        let (Some(every), Some(strided)) = r.at_rest else {
            panic!("the trail did not come back to rest: {seen}");
        };
        assert!(strided.abs_diff(every) <= 20, "{seen}");
    }
}

/// The default stride is half a millimetre: the same bits as the scene
/// with `recovery_stride_m = 0.0005` written out, and not those of the
/// every-step recovery (0).
#[test]
fn the_default_stride_is_half_a_millimetre() {
    let mut a = scene("");
    let mut b = scene("recovery_stride_m = 0.0005");
    let mut c = scene("recovery_stride_m = 0.0");
    for _ in 0..150 {
        a.step(1.0 / 60.0).unwrap();
        b.step(1.0 / 60.0).unwrap();
        c.step(1.0 / 60.0).unwrap();
    }
    assert!(a.blades_away_from_rest() > 100);
    assert_eq!(farthest_vertex(&a, &b), 0.0);
    assert!(farthest_vertex(&a, &c) > 0.0);
}
