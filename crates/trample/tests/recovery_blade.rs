//! Recovery and trails (DESIGN §6, ours): the exponential law is frame-rate
//! independent, a bent blade returns to rest and snaps to it bit for bit,
//! `recovery_s = ∞` keeps the paper's lasting track, flattened blades recover
//! more slowly with a trail, and billboard slopes follow the same law.

use glam::{Vec3, Vec3A};
use trample::deform::bend::{bend_blade, weights};
use trample::field::Terrain;
use trample::recovery::{
    RECOVERY_TAIL_M, RecoveryParams, recover_blade, recover_slope, recovery_factor, tail_fraction,
};

const SEG: f32 = 0.1;

fn rest_blade() -> Vec<Vec3A> {
    (0..=4)
        .map(|k| Vec3A::new(0.5, SEG * k as f32, -0.25))
        .collect()
}

fn bent_blade(push: Vec3) -> Vec<Vec3A> {
    let mut v = rest_blade();
    bend_blade(
        &mut v,
        SEG,
        push,
        1.0,
        &weights(4, 1.0, 2.0),
        &Terrain::Flat(0.0),
        0.0,
    );
    v
}

fn max_deviation(v: &[Vec3A], rest: &[Vec3A]) -> f32 {
    v.iter()
        .zip(rest)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max)
}

fn bits(v: &[Vec3A]) -> Vec<[u32; 3]> {
    v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

fn params(recovery_s: f32, trail: f32) -> RecoveryParams {
    RecoveryParams { recovery_s, trail }
}

#[test]
fn factor_is_frame_rate_independent() {
    for tau in [0.1f32, 1.0, 10.0] {
        for dt in [1.0f32 / 144.0, 1.0 / 60.0, 1.0 / 30.0] {
            for steps in [2u32, 4, 10] {
                let small = f64::from(recovery_factor(dt, tau)).powi(steps as i32);
                let big = f64::from(recovery_factor(dt * steps as f32, tau));
                assert!(
                    (small - big).abs() < 1e-6,
                    "τ {tau}, dt {dt}, {steps} steps: {small} vs {big}"
                );
            }
        }
    }
    assert!((recovery_factor(1.0, 1.0) - (-1.0f32).exp()).abs() < 1e-7);
    assert_eq!(
        recovery_factor(0.1, f32::INFINITY),
        1.0,
        "the paper: no recovery"
    );
    assert_eq!(recovery_factor(0.0, 1.0), 1.0);
    assert_eq!(recovery_factor(-0.1, 1.0), 1.0);
    assert_eq!(recovery_factor(0.1, 0.0), 0.0, "instant");
    assert_eq!(recovery_factor(f32::NAN, 1.0), 1.0);
    assert_eq!(recovery_factor(0.1, f32::NAN), 1.0);
}

/// Recovering for one second gives nearly the same blade at 30 and at 144
/// steps per second.
#[test]
fn blade_recovery_is_nearly_frame_rate_independent() {
    let rest = rest_blade();
    let p = params(0.5, 0.0);
    let flat = Terrain::Flat(0.0);
    let after = |steps: u32| {
        let mut v = bent_blade(Vec3::new(0.2, 0.0, 0.1));
        for _ in 0..steps {
            recover_blade(&mut v, &rest, SEG, 1.0 / steps as f32, &p, &flat, 0.0);
        }
        v
    };
    let (slow, fast) = (after(30), after(144));
    let start = max_deviation(&bent_blade(Vec3::new(0.2, 0.0, 0.1)), &rest);
    assert!(max_deviation(&slow, &rest) < 0.3 * start, "it recovers");
    assert!(
        max_deviation(&slow, &fast) < 0.01 * start,
        "{} vs {}",
        max_deviation(&slow, &fast),
        start
    );
}

#[test]
fn blade_returns_to_rest_and_snaps_bit_exactly() {
    let rest = rest_blade();
    let mut v = bent_blade(Vec3::new(0.3, 0.0, 0.0));
    let p = params(0.3, 0.0);
    let flat = Terrain::Flat(0.0);
    let mut dev = max_deviation(&v, &rest);
    assert!(dev > 0.1, "well bent: {dev}");
    let mut steps = 0;
    while !recover_blade(&mut v, &rest, SEG, 1.0 / 60.0, &p, &flat, 0.0) {
        let now = max_deviation(&v, &rest);
        assert!(
            now < dev,
            "step {steps}: deviation {now} did not fall below {dev}"
        );
        for i in 1..v.len() {
            assert!(
                ((v[i] - v[i - 1]).length() / SEG - 1.0).abs() < 1e-5,
                "lengths kept"
            );
        }
        dev = now;
        steps += 1;
        assert!(steps < 1000, "never reached rest");
    }
    // The exponential down to the tail, τ · ln(deviation / RECOVERY_TAIL_M)
    // · 60 ≈ 0.3 · ln(0.4 / 0.01) · 60 ≈ 66 steps, then the last centimetre
    // at the tail's constant speed, about τ · 60 = 18 steps (the
    // exponential alone would take τ · ln(0.4 / 1e-4) · 60 ≈ 150).
    assert!((60..100).contains(&steps), "{steps} steps");
    // The last step before rest moved at most the tail's speed.
    let q = 1.0 - recovery_factor(1.0 / 60.0, 0.3);
    assert!(dev <= RECOVERY_TAIL_M * q * 1.01, "{dev}");
    assert_eq!(bits(&v), bits(&rest));
    assert!(
        recover_blade(&mut v, &rest, SEG, 1.0 / 60.0, &p, &flat, 0.0),
        "stays at rest"
    );
    assert_eq!(bits(&v), bits(&rest));
}

/// Within `RECOVERY_TAIL_M` of rest a blade goes on at the speed the
/// exponential has there and reaches rest in finite time: a blade brushed
/// 8 mm aside is back in about `deviation / (RECOVERY_TAIL_M / τ)` = 0.4 s
/// (τ = 0.5 s), where the exponential alone took τ · ln(8 mm / 0.1 mm) ≈
/// 2.2 s. Frame-rate independent as the exponential is.
#[test]
fn the_last_centimetre_is_recovered_at_a_constant_speed() {
    let rest = rest_blade();
    let flat = Terrain::Flat(0.0);
    let p = params(0.5, 0.0);
    let brushed = bent_blade(Vec3::new(0.0065, 0.0, 0.0));
    let start = max_deviation(&brushed, &rest);
    assert!(
        (0.005..RECOVERY_TAIL_M).contains(&start),
        "brushed within the tail: {start}"
    );
    let speed = RECOVERY_TAIL_M / p.recovery_s;
    // At 60 steps a second: every step takes about the same distance off.
    let mut v = brushed.clone();
    let (mut dev, mut steps) = (start, 0u32);
    while !recover_blade(&mut v, &rest, SEG, 1.0 / 60.0, &p, &flat, 0.0) {
        let now = max_deviation(&v, &rest);
        let took = dev - now;
        assert!(
            (took - speed / 60.0).abs() < 0.05 * speed / 60.0,
            "step {steps}: {took} m off, the tail's speed gives {}",
            speed / 60.0
        );
        dev = now;
        steps += 1;
        assert!(steps < 1000, "never reached rest");
    }
    assert_eq!(bits(&v), bits(&rest));
    let expected = start / speed * 60.0;
    assert!(
        (f64::from(steps) - f64::from(expected)).abs() <= 2.0,
        "{steps} steps, about {expected} expected"
    );
    // The same 0.2 s at 30 and at 144 steps a second.
    let after = |rate: u32| {
        let mut v = brushed.clone();
        for _ in 0..(rate / 5) {
            recover_blade(&mut v, &rest, SEG, 1.0 / rate as f32, &p, &flat, 0.0);
        }
        max_deviation(&v, &rest)
    };
    let (slow, fast) = (after(30), after(144));
    assert!(
        (slow - fast).abs() < 0.02 * start,
        "{slow} at 30 steps a second, {fast} at 144"
    );
    assert!((start - slow - 0.2 * speed).abs() < 0.05 * start, "{slow}");
    // A billboard's slope, with the same law per unit height.
    let origin = Vec3::Y;
    let mut slope = Vec3::new(0.006, 1.0, 0.0);
    let mut steps = 0u32;
    while !recover_slope(&mut slope, origin, 1.0 / 60.0, &p) {
        steps += 1;
        assert!(steps < 1000, "never reached rest");
    }
    let expected = 0.006 / speed * 60.0;
    assert!(
        (f64::from(steps) - f64::from(expected)).abs() <= 2.0,
        "slope: {steps} steps, about {expected} expected"
    );
}

/// The tail's fraction is continuous where it meets the exponential and
/// leaves a held blade held.
#[test]
fn the_tail_meets_the_exponential_without_a_jump() {
    let q = 1.0 - recovery_factor(1.0 / 60.0, 2.0);
    for d in [
        RECOVERY_TAIL_M * (1.0 - 1e-6),
        RECOVERY_TAIL_M,
        RECOVERY_TAIL_M * (1.0 + 1e-6),
    ] {
        let t = tail_fraction(q, d);
        assert!((t - q).abs() <= 2e-6 * q, "{d}: {t} against {q}");
    }
    // The distance moved, fraction times deviation, is the same below.
    for d in [1e-3f32, 3e-3, 9e-3] {
        let moved = tail_fraction(q, d) * d;
        assert!((moved - q * RECOVERY_TAIL_M).abs() < 1e-6 * RECOVERY_TAIL_M);
    }
    assert_eq!(tail_fraction(0.0, 1e-3), 0.0, "held");
    assert_eq!(tail_fraction(q, 1e-9), 1.0, "at most the whole way");
    assert_eq!(tail_fraction(q, 0.0), q);
    assert_eq!(tail_fraction(q, 0.5), q);
}

#[test]
fn infinite_recovery_keeps_the_track() {
    let rest = rest_blade();
    let bent = bent_blade(Vec3::new(0.2, 0.0, 0.0));
    let mut v = bent.clone();
    for _ in 0..100 {
        assert!(!recover_blade(
            &mut v,
            &rest,
            SEG,
            0.1,
            &params(f32::INFINITY, 2.0),
            &Terrain::Flat(0.0),
            0.0
        ));
    }
    assert_eq!(bits(&v), bits(&bent));
    let mut r = rest.clone();
    assert!(recover_blade(
        &mut r,
        &rest,
        SEG,
        0.1,
        &params(f32::INFINITY, 0.0),
        &Terrain::Flat(0.0),
        0.0
    ));
    // NaN parameters or dt: unchanged too.
    for (p, dt) in [
        (params(f32::NAN, 0.0), 0.1),
        (params(1.0, 0.0), f32::NAN),
        (params(1.0, 0.0), -1.0),
    ] {
        let mut v = bent.clone();
        assert!(!recover_blade(
            &mut v,
            &rest,
            SEG,
            dt,
            &p,
            &Terrain::Flat(0.0),
            0.0
        ));
        assert_eq!(bits(&v), bits(&bent));
    }
}

#[test]
fn trail_slows_flattened_blades() {
    let rest = rest_blade();
    let flat = Terrain::Flat(0.0);
    let flattened = bent_blade(Vec3::new(3.0, 0.0, 0.0));
    let flatness = 1.0 - (flattened[4].y - flattened[0].y) / (rest[4].y - rest[0].y);
    assert!(flatness > 0.8, "flattened: {flatness}");
    let step = |start: &[Vec3A], trail: f32| {
        let mut v = start.to_vec();
        recover_blade(&mut v, &rest, SEG, 0.5, &params(0.5, trail), &flat, 0.0);
        max_deviation(&v, &rest) / max_deviation(start, &rest)
    };
    let (plain, trailed) = (step(&flattened, 0.0), step(&flattened, 4.0));
    assert!(
        trailed > plain + 0.2,
        "kept {trailed} with a trail, {plain} without"
    );
    // A slightly bent blade is hardly flattened: the trail barely matters.
    let brushed = bent_blade(Vec3::new(0.02, 0.0, 0.0));
    let (plain, trailed) = (step(&brushed, 0.0), step(&brushed, 4.0));
    assert!(
        trailed - plain < 0.05,
        "kept {trailed} with a trail, {plain} without"
    );
}

#[test]
fn bad_blades_are_reset_or_ignored() {
    let rest = rest_blade();
    let mut v = rest.clone();
    v[2] = Vec3A::NAN;
    assert!(recover_blade(
        &mut v,
        &rest,
        SEG,
        0.1,
        &params(1.0, 0.0),
        &Terrain::Flat(0.0),
        0.0
    ));
    assert_eq!(bits(&v), bits(&rest));
    let mut short = rest[..3].to_vec();
    assert!(!recover_blade(
        &mut short,
        &rest,
        SEG,
        0.1,
        &params(1.0, 0.0),
        &Terrain::Flat(0.0),
        0.0
    ));
}

#[test]
fn slope_recovers_with_the_same_law() {
    let origin = Vec3::Y;
    let start = Vec3::new(0.5, 0.8, 0.0);
    let mut s = start;
    assert!(!recover_slope(&mut s, origin, 0.1, &params(1.0, 0.0)));
    let k = recovery_factor(0.1, 1.0);
    assert!(
        (s - (origin + (start - origin) * k)).length() < 1e-6,
        "deviation times exp(−dt/τ)"
    );
    let mut steps = 0;
    while !recover_slope(&mut s, origin, 0.1, &params(1.0, 0.0)) {
        steps += 1;
        assert!(steps < 1000);
    }
    assert_eq!(s, origin);
    // Infinite recovery: unchanged; a flattened billboard with a trail recovers more slowly.
    let mut kept = start;
    assert!(!recover_slope(
        &mut kept,
        origin,
        0.1,
        &params(f32::INFINITY, 0.0)
    ));
    assert_eq!(kept, start);
    let down = Vec3::new(1.0, 0.05, 0.0);
    let (mut a, mut b) = (down, down);
    recover_slope(&mut a, origin, 0.5, &params(0.5, 0.0));
    recover_slope(&mut b, origin, 0.5, &params(0.5, 4.0));
    assert!(b.distance(origin) > a.distance(origin) + 0.2);
    let mut bad = Vec3::NAN;
    assert!(recover_slope(&mut bad, origin, 0.1, &params(1.0, 0.0)));
    assert_eq!(bad, origin);
}
