//! Responses are continuous (DESIGN §5 "Contact"; CONTRIBUTING: a state a
//! few ulp away gives a result a few ulp away): a body driven along a path
//! moved by about 1e-7 m — an ulp or so of its coordinates, the noise
//! between two platforms or between the CPU and the GPU — leaves the field
//! within a millimetre of where the path itself leaves it, and no blade a
//! centimetre away in any run of a sweep of random ones.
//!
//! Two rules turned that noise into centimetres (found in session 58 by the
//! sweep at the end):
//! - the flat rule of a pinned segment (`deform::contact::pin_for_push`)
//!   applied whole the moment the vertex above passed the contact
//!   tolerance: one ulp of depth laid a segment down by 4 cm;
//! - a segment between two final nodes of opposite EqN (a sphere's halves
//!   at precision 2, under a blade's tip) took the normalised sum of their
//!   directions, which turns over where the sum changes sign: the force of
//!   Eq. 2 flipped for 1e-7 m and the track moved by 2–5 cm. It now fades
//!   with the sum (`collision::narrow_phase::agreement`).

use glam::{EulerRot, Quat, Vec3};
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::FieldParams;
use trample::object::ShapeParams;
use trample::step::SimParams;

/// A body driven over a 4 × 4-patch field (4,096 blades): `shape` at
/// `start` turned by `rot`, then moved by `vel` (m/s) and turned about y
/// by `spin` (rad/s) for `frames` steps of 1/60 s.
struct Drive {
    shape: ShapeParams,
    start: Vec3,
    vel: Vec3,
    rot: Quat,
    spin: f32,
    frames: u32,
    precision: u32,
    recovery_s: f32,
}

impl Drive {
    /// Every blade vertex after the drive along the path moved by `eps`.
    fn run(&self, eps: Vec3) -> Vec<f32> {
        let mut sim = SimulationBuilder::new()
            .field(FieldParams {
                patches: [4, 4],
                cells_per_patch: 16,
                ..FieldParams::default()
            })
            .sim(SimParams {
                recovery_s: self.recovery_s,
                precision: self.precision,
                ..SimParams::default()
            })
            .build()
            .unwrap();
        let id = sim.add_body(
            BodyBuilder::new("body", self.shape.clone())
                .at((self.start + eps).to_array())
                .build()
                .unwrap(),
        );
        sim.teleport_body(id, self.start + eps, self.rot).unwrap();
        let dt = 1.0 / 60.0;
        for f in 1..=self.frames {
            let t = f as f32 * dt;
            let turn = Quat::from_rotation_y(self.spin * t) * self.rot;
            sim.move_body(id, self.start + self.vel * t + eps, turn, dt)
                .unwrap();
            sim.step(dt).unwrap();
        }
        sim.blade_vertices()
    }

    /// The largest difference of one vertex coordinate between the drive
    /// and the drive along the path moved by `eps`, and its blade.
    fn difference(&self, eps: Vec3) -> (f32, usize) {
        largest_difference(&self.run(Vec3::ZERO), &self.run(eps))
    }
}

/// The largest difference of one vertex coordinate between two runs, and
/// the blade it is on.
fn largest_difference(a: &[f32], b: &[f32]) -> (f32, usize) {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(i, (x, y))| ((x - y).abs(), i / 15))
        .fold((0.0, 0), |m, d| if d.0 > m.0 { d } else { m })
}

/// A capsule lying low, its bottom below the ground, over blades whose
/// roots it pins. Its height 7e-8 m higher (one ulp at 0.08 m is 7.5e-9:
/// a few ulp) made the third vertex of one blade pass the contact
/// tolerance by 1e-7 m in step 25; the whole flat rule then laid that
/// segment down 4.0 cm from where it lay in the other run.
#[test]
fn a_pinned_segment_is_not_laid_down_by_one_ulp_of_depth() {
    let drive = Drive {
        shape: ShapeParams::Capsule {
            radius_m: 0.196_705_82,
            length_m: 0.397_129_83,
        },
        start: Vec3::new(-1.424_953, 0.080_533_58, 1.244_604_6),
        vel: Vec3::new(-0.186_791_08, 0.0, 3.464_77),
        rot: Quat::from_array([0.051_435_538, 0.931_683_3, 0.352_783_47, -0.069_745_22]),
        spin: 0.0,
        frames: 25,
        precision: 5,
        recovery_s: f32::INFINITY,
    };
    let eps = Vec3::new(-2.195_027_8e-8, 7.256_263_5e-8, 2.715_088_2e-8);
    let (d, blade) = drive.difference(eps);
    assert!(d < 1e-3, "blade {blade} moved {d} m for {eps} m");
}

/// A ball of 0.46 m grazing the blades' tips at precision 2, whose final
/// nodes are its two halves: a tip under the seam met both, their EqN
/// opposite. A 1e-7 m lower path turned the sum's sign and the force's
/// direction with it: one blade 1.8 cm away after 15 steps, 4.7 cm after 20.
#[test]
fn opposite_nodes_fade_the_push_instead_of_flipping_it() {
    let drive = Drive {
        shape: ShapeParams::Sphere {
            radius_m: 0.462_245_05,
            subdivisions: 3,
        },
        start: Vec3::new(-2.216_536_5, 0.895_404_76, 0.775_445_2),
        vel: Vec3::new(1.445_758_1, 0.0, -3.397_475_2),
        rot: Quat::from_array([-0.401_267_65, 0.563_780_4, -0.081_787_45, -0.717_249_45]),
        spin: 0.0,
        frames: 20,
        precision: 2,
        recovery_s: f32::INFINITY,
    };
    let eps = Vec3::new(6.726_942_6e-9, -9.932_108e-8, 8.574_691e-8);
    let (d, blade) = drive.difference(eps);
    assert!(d < 1e-3, "blade {blade} moved {d} m for {eps} m");
}

/// The probe's generator: xorshift64, seeded by the run's number.
struct Probe(u64);

impl Probe {
    fn new(seed: u64) -> Self {
        let mut r = Self(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x2545_f491_4f6c_dd1d));
        for _ in 0..4 {
            r.next();
        }
        r
    }
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

/// Run `seed` of the sweep and again with its path moved by up to 1e-7 m
/// on each axis: the largest difference of a vertex coordinate, its blade,
/// and whether the run bent the grass by a centimetre anywhere. (The
/// ranges are the probe's as it ran: 6.283 and 6.28, not τ, so that run
/// `n` is the session's run `n`.)
#[allow(clippy::approx_constant)]
fn sweep_run(seed: u64) -> (f32, usize, bool) {
    let mut r = Probe::new(seed);
    let kind = r.next() % 5;
    let s = r.range(0.15, 0.8);
    let shape = match kind {
        0 => ShapeParams::Sphere {
            radius_m: s,
            subdivisions: 3,
        },
        1 => ShapeParams::Box {
            half_extents_m: [s, r.range(0.1, 0.6), r.range(0.1, 0.6)],
        },
        2 => ShapeParams::Capsule {
            radius_m: s * 0.6,
            length_m: r.range(0.0, 1.0),
        },
        3 => ShapeParams::Cylinder {
            radius_m: s,
            length_m: r.range(0.1, 1.0),
        },
        _ => ShapeParams::Knot { size_m: s * 2.0 },
    };
    let y = r.range(-0.2, 0.9);
    let start = Vec3::new(r.range(-4.0, 0.0), y, r.range(-3.0, 3.0));
    let speed = if r.unit() < 0.25 {
        0.0
    } else {
        r.range(0.2, 6.0)
    };
    let heading = r.range(0.0, 6.283);
    let vel = Vec3::new(heading.cos() * speed, 0.0, heading.sin() * speed);
    let rot = Quat::from_euler(
        EulerRot::YXZ,
        r.range(0.0, 6.28),
        r.range(-1.0, 1.0),
        r.range(-1.0, 1.0),
    );
    let spin = if r.unit() < 0.5 {
        0.0
    } else {
        r.range(-3.0, 3.0)
    };
    let frames = 1 + (r.next() % 40) as u32;
    let precision = 1 + (r.next() % 8) as u32;
    let recovery_s = if r.unit() < 0.5 {
        f32::INFINITY
    } else {
        r.range(0.3, 3.0)
    };
    let e = 1e-7;
    let eps = Vec3::new(r.range(-e, e), r.range(-e, e), r.range(-e, e));
    let drive = Drive {
        shape,
        start,
        vel,
        rot,
        spin,
        frames,
        precision,
        recovery_s,
    };
    let here = drive.run(Vec3::ZERO);
    let (d, blade) = largest_difference(&here, &drive.run(eps));
    let away = Drive {
        start: start + Vec3::Y * 50.0,
        frames: 1,
        ..drive
    };
    let bent = largest_difference(&here, &away.run(Vec3::ZERO)).0 > 0.01;
    (d, blade, bent)
}

/// The sweep that found both (BENCHMARKS.md, "Session 58"): random
/// built-in shapes at random heights (resting on the ground, pressing,
/// grazing the tips), speeds (0 to 6 m/s), tilts and spins, precisions
/// 1–8, with and without recovery, 1 to 40 steps, each run again with its
/// path moved by up to 1e-7 m on each axis. Runs 1–150 here (run 45 is
/// the capsule above: 3.4 cm before the fix); `CONTINUITY_RUNS=1-3000`
/// (with `--release --nocapture`) runs the session's 3,000 and prints the
/// counts. No blade may end a centimetre away. Over the 3,000, before the
/// fixes 21 runs moved a blade by over 1 mm and 10 by over 1 cm (up to
/// 11.9 cm); since, 6 and none (up to 8.0 mm); runs 3,001–6,000 have one
/// over 1 cm (run 4911: 19.8 mm). What is left is the steep but continuous
/// way out of a vertex deep inside (RELIABILITY.md, "Continuity").
#[test]
fn a_path_an_ulp_away_moves_no_blade_by_a_centimetre() {
    let (first, last) = std::env::var("CONTINUITY_RUNS")
        .ok()
        .and_then(|v| {
            let (a, b) = v.split_once('-')?;
            Some((a.trim().parse().ok()?, b.trim().parse().ok()?))
        })
        .unwrap_or((1u64, 150u64));
    let (mut worst, mut over_mm, mut over_cm, mut bent) = ((0.0f32, 0u64, 0usize), 0, 0, 0);
    for seed in first..=last {
        let (d, blade, pressed) = sweep_run(seed);
        if d > worst.0 {
            worst = (d, seed, blade);
        }
        over_mm += usize::from(d > 1e-3);
        over_cm += usize::from(d > 1e-2);
        bent += usize::from(pressed);
    }
    let runs = (last + 1).saturating_sub(first);
    eprintln!(
        "runs {first}-{last}: over 1 mm {over_mm}, over 1 cm {over_cm}, largest {} m (run {}, blade {}); {bent} bent the grass",
        worst.0, worst.1, worst.2
    );
    assert!(
        worst.0 < 1e-2,
        "run {}: blade {} moved {} m for a path 1e-7 m away",
        worst.1,
        worst.2,
        worst.0
    );
    assert!(
        bent as u64 * 2 > runs,
        "only {bent} of {runs} runs bent the grass"
    );
}
