//! Many interactors driven by the host: a crowd of characters (capsules
//! of one size, so one shared OBB tree) wandering over a meadow of a
//! million blades, each walking to a waypoint, standing there a while,
//! then walking on — what a game's NPCs do. The host moves each one every
//! frame ([`Simulation::move_body`](trample::Simulation::move_body)); a
//! character standing still costs a comparison of the blades under it
//! (`SimParams::reuse_at_rest`), and
//! with `far_every` above 1 the ones far from the camera step in turns
//! and so does the recovery of the trails far from it
//! (`SimParams::far_every`). The trails' blades creeping back slowly are
//! relaxed in strides of half a millimetre (`SimParams::recovery_stride_m`,
//! the default: each only every few frames, over all the time it owes). Every second it prints the step's median and
//! 90th percentile, how many characters stand, how many stepped far, and
//! how many blades a renderer would upload (`Simulation::changed_blades`).
//!
//! ```sh
//! cargo run --release -p trample --example crowd                # 64 characters, 600 frames
//! cargo run --release -p trample --example crowd -- 200 600 8   # 200 characters, far_every = 8
//! cargo run --release -p trample --example crowd -- 64 600 1 0  # every trail blade every step
//! cargo run --release -p trample --example crowd -- 64 600 4 0.5 follow-unseen
//! ```
//!
//! Arguments: characters (1..=1000, default 64), frames (default 600),
//! `far_every` (1..=64, default 1: every character every step), the
//! recovery stride in millimetres (0..=50, default 0.5; 0: every displaced
//! blade relaxed every step), the camera: `overview` (the default: above
//! the field's edge, looking across it), `follow` (a game's third-person
//! camera, 6 m behind the first character and 3 m up, set every frame) or
//! `follow-unseen` (that camera, and the characters and trails out of its
//! view take turns too: `SimParams::far_outside_view`).

use std::time::Instant;

use glam::{Quat, Vec3};
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::FieldParams;
use trample::object::ShapeParams;
use trample::step::{BodyId, HostView, SimParams};

/// Half the side of the square the characters wander in, metres.
const AREA_M: f32 = 40.0;
/// Walking speed, metres a second.
const WALK_M_S: f32 = 1.4;
/// A character's capsule: radius and the length of its cylinder, metres
/// (1.7 m tall in all).
const RADIUS_M: f32 = 0.3;
const LENGTH_M: f32 = 1.1;

/// The host's camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Camera {
    /// Above the field's edge, looking across it (fixed).
    Overview,
    /// Behind the first character, following it (set every frame).
    Follow,
    /// [`Camera::Follow`], and what it does not see takes turns
    /// (`SimParams::far_outside_view`).
    FollowUnseen,
}

/// The third-person view of character `c`: 6 m behind it and 3 m up,
/// looking 4 m ahead of it.
fn behind(c: &Character) -> Result<HostView, trample::step::ViewError> {
    let forward = Vec3::new(c.heading.sin(), 0.0, c.heading.cos());
    HostView::look_at(
        c.at - forward * 6.0 + Vec3::Y * 3.0,
        c.at + forward * 4.0,
        0.9,
        16.0 / 9.0,
        0.1,
        300.0,
    )
}

/// One character of the crowd, as a game would keep it.
struct Character {
    id: BodyId,
    at: Vec3,
    heading: f32,
    target: Vec3,
    /// Seconds left standing at the waypoint (0: walking).
    idle_s: f32,
}

/// A small deterministic generator (the same crowd every run).
struct Lcg(u64);

impl Lcg {
    /// Uniform in [0, 1).
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A point on the ground within the area.
    fn point(&mut self) -> Vec3 {
        let (x, z) = (self.next(), self.next());
        Vec3::new((2.0 * x - 1.0) * AREA_M, 0.0, (2.0 * z - 1.0) * AREA_M)
    }
}

/// The median and 90th percentile (nearest rank) of `v`, milliseconds.
fn median_p90(v: &mut [f64]) -> (f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0);
    }
    v.sort_by(f64::total_cmp);
    let rank = |q: f64| v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
    (rank(0.5), rank(0.9))
}

fn arg(
    args: &[String],
    i: usize,
    name: &str,
    default: u32,
    range: (u32, u32),
) -> Result<u32, String> {
    let Some(text) = args.get(i) else {
        return Ok(default);
    };
    match text.parse::<u32>() {
        Ok(v) if (range.0..=range.1).contains(&v) => Ok(v),
        _ => Err(format!(
            "{name} = {text:?}: must be a whole number in {}..={} (usage: crowd [CHARACTERS] [FRAMES] [FAR_EVERY] [STRIDE_MM] [CAMERA])",
            range.0, range.1
        )),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let count = arg(&args, 0, "characters", 64, (1, 1000))?;
    let frames = arg(&args, 1, "frames", 600, (1, 1_000_000))?;
    let far_every = arg(&args, 2, "far_every", 1, (1, 64))?;
    let camera = match args.get(4).map(String::as_str) {
        None | Some("overview") => Camera::Overview,
        Some("follow") => Camera::Follow,
        Some("follow-unseen") => Camera::FollowUnseen,
        Some(text) => {
            return Err(format!(
                "camera = {text:?}: must be overview, follow or follow-unseen (usage: crowd [CHARACTERS] [FRAMES] [FAR_EVERY] [STRIDE_MM] [CAMERA])"
            )
            .into());
        }
    };
    let stride_mm = match args.get(3) {
        None => 0.5,
        Some(text) => match text.parse::<f32>() {
            Ok(v) if (0.0..=50.0).contains(&v) => v,
            _ => {
                return Err(format!(
                    "stride = {text:?}: must be a number of millimetres in 0..=50 (usage: crowd [CHARACTERS] [FRAMES] [FAR_EVERY] [STRIDE_MM] [CAMERA])"
                )
                .into());
            }
        },
    };

    // 102.4 m square: 32 × 32 patches of 32 × 32 cells of 0.1 m, one blade
    // a cell (1,048,576 blades); a track recovers over 6 s.
    let mut sim = SimulationBuilder::new()
        .field(FieldParams {
            patches: [32, 32],
            ..FieldParams::default()
        })
        .sim(SimParams {
            recovery_s: 6.0,
            far_every,
            far_outside_view: camera == Camera::FollowUnseen,
            recovery_stride_m: stride_mm * 1e-3,
            ..SimParams::default()
        })
        .build()?;

    let mut rng = Lcg(7);
    let mut crowd = Vec::with_capacity(count as usize);
    let centre_height = RADIUS_M + 0.5 * LENGTH_M;
    for i in 0..count {
        let at = rng.point();
        let body = BodyBuilder::new(
            format!("npc{i}"),
            ShapeParams::Capsule {
                radius_m: RADIUS_M,
                length_m: LENGTH_M,
            },
        )
        .at(at + Vec3::Y * centre_height)
        .build()?;
        crowd.push(Character {
            id: sim.add_body(body),
            at,
            heading: 0.0,
            target: rng.point(),
            idle_s: 3.0 * rng.next(),
        });
    }
    println!(
        "{count} characters over {} blades, far_every = {far_every}, recovery stride {stride_mm} mm, camera {camera:?}",
        sim.field.blades.count
    );

    // The host's camera: above the middle of the field, looking across it.
    let view = HostView::look_at(
        Vec3::new(0.0, 12.0, -45.0),
        Vec3::ZERO,
        0.9,
        16.0 / 9.0,
        0.1,
        300.0,
    )?;
    sim.set_view(view)?;

    let dt = 1.0 / 60.0;
    let per_second = 60;
    let (mut second, mut all) = (Vec::new(), Vec::new());
    let mut uploads = 0usize;
    for frame in 0..frames {
        let mut standing = 0;
        for c in &mut crowd {
            if c.idle_s > 0.0 {
                // Standing at the waypoint: not moved, so at rest.
                c.idle_s -= dt;
                standing += 1;
                continue;
            }
            let to = c.target - c.at;
            let step = WALK_M_S * dt;
            if to.length() <= step {
                c.at = c.target;
                c.target = rng.point();
                c.idle_s = 1.0 + 3.0 * rng.next();
            } else {
                c.at += to.normalize() * step;
                c.heading = to.x.atan2(to.z);
            }
            let position = c.at + Vec3::Y * centre_height;
            sim.move_body(c.id, position, Quat::from_rotation_y(c.heading), dt)?;
        }
        if camera != Camera::Overview {
            sim.set_view(behind(&crowd[0])?)?;
        }
        let start = Instant::now();
        let t = sim.step(dt)?.clone();
        let ms = start.elapsed().as_secs_f64() * 1e3;
        second.push(ms);
        all.push(ms);
        let changed = sim.changed_blades().count();
        uploads += changed;
        if (frame + 1) % per_second == 0 || frame + 1 == frames {
            let (median, p90) = median_p90(&mut second);
            println!(
                "t = {:5.1} s: step median {median:6.2} ms, p90 {p90:6.2} ms; {standing:4} of {count} standing, {:3} far, {:6} DBG, {changed:7} blades to upload",
                f64::from(frame + 1) / 60.0,
                t.far_bodies,
                t.dbg_blades,
            );
            second.clear();
        }
    }
    let (median, p90) = median_p90(&mut all);
    println!(
        "{frames} frames: step median {median:.2} ms, p90 {p90:.2} ms; {:.0} blades uploaded a frame on average",
        uploads as f64 / f64::from(frames)
    );
    Ok(())
}
