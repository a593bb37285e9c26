//! The many-object scenes (issue 16, item 4): `scenes/herd.toml`, 128 mixed
//! objects circling over a 16.8 M-blade field, parses, validates and fits
//! its memory limit (it is not built here: 7.8 GiB estimated); its smaller twin
//! `scenes/herd_small.toml` (1 M blades) builds and steps, and every object
//! is over the field (the broad phase lists patches under each); its
//! variants `herd_parked.toml` (standing still) and `herd_stopgo.toml`
//! (changing speed) are the same objects.

mod common;

use std::collections::BTreeMap;
use std::path::Path;
use trample::collision::patches_under;
use trample::object::ShapeParams;
use trample::scene::Scene;

fn load(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Objects per kind of shape (mesh files by their file name).
fn kinds(s: &Scene) -> BTreeMap<String, usize> {
    let mut out = BTreeMap::new();
    for o in &s.file.objects {
        let kind = match &o.shape {
            ShapeParams::Sphere { .. } => "sphere".to_string(),
            ShapeParams::Box { .. } => "box".to_string(),
            ShapeParams::Knot { .. } => "knot".to_string(),
            ShapeParams::Mesh { path, .. } => path.file_name().unwrap().to_string_lossy().into(),
            other => format!("{other:?}"),
        };
        *out.entry(kind).or_insert(0) += 1;
    }
    out
}

#[test]
fn herd_is_128_mixed_objects_over_16_8_m_blades_within_its_memory_limit() {
    let s = load("herd.toml");
    s.validate().expect("herd.toml is valid");
    let f = &s.file.field;
    assert_eq!(f.blade_count(), 16_777_216);
    assert_eq!(s.file.sim.precision, 7);
    assert_eq!(s.file.objects.len(), 128);
    let want: BTreeMap<String, usize> = [
        ("beetle.obj", 20),
        ("box", 32),
        ("knot", 24),
        ("sphere", 32),
        ("spot.obj", 20),
    ]
    .into_iter()
    .map(|(k, n)| (k.to_string(), n))
    .collect();
    assert_eq!(kinds(&s), want);
    // Several GiB, within the scene's limit (the default 8 GiB).
    let gib = f.memory_estimate_bytes() as f64 / f64::from(1u32 << 30);
    assert!(
        gib > 4.0 && gib <= f64::from(s.file.sim.memory_limit_gib),
        "{gib:.2} GiB"
    );
}

#[test]
fn herd_small_builds_steps_and_every_object_is_over_the_field() {
    let s = load("herd_small.toml");
    assert_eq!(s.file.field.blade_count(), 1_048_576);
    assert_eq!(kinds(&s), kinds(&load("herd.toml")));
    let mut sim = s.build().expect("herd_small builds");
    assert_eq!(sim.bodies.len(), 128);
    for _ in 0..3 {
        sim.step(sim.params.dt_s).unwrap();
    }
    let mut patches = Vec::new();
    for b in &sim.bodies {
        patches_under(&sim.field.layout, &b.world_root, &mut patches);
        assert!(!patches.is_empty(), "{} is off the field", b.object.name);
    }
    assert!(sim.timings.total_ms > 0.0);
}

/// `scenes/herd_parked.toml` is the herd's field and objects, each standing
/// still (a static path) where its circle in `herd.toml` starts.
#[test]
fn herd_parked_is_the_herd_standing_still() {
    let (parked, herd) = (load("herd_parked.toml"), load("herd.toml"));
    parked.validate().expect("herd_parked.toml is valid");
    assert_eq!(parked.file.field.blade_count(), 16_777_216);
    assert_eq!(kinds(&parked), kinds(&herd));
    for (p, h) in parked.file.objects.iter().zip(&herd.file.objects) {
        assert_eq!(p.name, h.name);
        assert_eq!(p.path.kind_name(), "static", "{}", p.name);
        assert_eq!(h.path.kind_name(), "circle", "{}", h.name);
    }
}

/// `scenes/herd_stopgo.toml` is the herd's field and objects going round
/// their circles in `herd.toml` (every key on the circle, the first where
/// the circle starts) in legs: each object stops and changes speed
/// (far bodies whose far pass's load changes, `step::passes::far_schedule`).
#[test]
fn herd_stopgo_is_the_herd_going_round_its_circles_at_changing_speeds() {
    use trample::object::PathParams;
    let (stopgo, herd) = (load("herd_stopgo.toml"), load("herd.toml"));
    stopgo.validate().expect("herd_stopgo.toml is valid");
    assert_eq!(stopgo.file.field.blade_count(), 16_777_216);
    assert_eq!(kinds(&stopgo), kinds(&herd));
    for (s, h) in stopgo.file.objects.iter().zip(&herd.file.objects) {
        assert_eq!(s.name, h.name);
        let PathParams::Circle {
            center,
            radius_m,
            period_s,
            phase_rad,
        } = h.path
        else {
            panic!("{}: {:?}", h.name, h.path)
        };
        let PathParams::Keyframes { keys } = &s.path else {
            panic!("{}: {:?}", s.name, s.path)
        };
        let start = [
            center[0] + radius_m * phase_rad.cos(),
            center[2] - radius_m * phase_rad.sin(),
        ];
        let first = keys[0].position;
        assert!(
            (first[0] - start[0]).hypot(first[2] - start[1]) < 0.01,
            "{}: starts at {first:?}, its circle at {start:?}",
            s.name
        );
        let speed = std::f32::consts::TAU * radius_m / period_s;
        let mut speeds = Vec::new();
        for w in keys.windows(2) {
            let (a, b) = (w[0].position, w[1].position);
            assert_eq!(a[1], center[1], "{}: height", s.name);
            let off = (b[0] - center[0]).hypot(b[2] - center[2]) - radius_m;
            assert!(off.abs() < 0.01, "{}: a key {off} m off its circle", s.name);
            let v = (b[0] - a[0]).hypot(b[2] - a[2]) / (w[1].t_s - w[0].t_s);
            speeds.push((v / speed * 2.0).round() / 2.0);
        }
        assert!(keys.last().unwrap().t_s >= 20.0, "{}: 20 s of keys", s.name);
        assert!(
            speeds.iter().all(|f| [0.0, 0.5, 1.0, 1.5].contains(f)),
            "{}: legs at {speeds:?} times its speed",
            s.name
        );
        let legs = speeds.windows(2).filter(|w| w[0] != w[1]).count();
        assert!(legs >= 3, "{}: changes speed {legs} times", s.name);
    }
}
