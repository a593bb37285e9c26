//! Bodies a host adds, moves, teleports and removes on a running simulation
//! (issue 14, item 1; CPU path): a moved body sweeps the grass between its
//! poses, a teleported one does not (no track between the two places), a
//! removed one stops acting and the blades it bent recover; ids stay valid
//! while other bodies come and go.

use glam::{Quat, Vec3};
use trample::Simulation;
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::step::{BodyError, BodyId, HostView, SimParams};

/// 8 × 8 m of grass (4 × 4 patches of 20 × 20 cells of 0.1 m), every cell
/// geometric, seen by a host camera from above; no bodies yet.
fn field(recovery_s: f32) -> Simulation {
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [4, 4],
            cells_per_patch: 20,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 1000.0,
            billboard_m: 2000.0,
        })
        .sim(SimParams {
            recovery_s,
            ..SimParams::default()
        })
        .host_view(
            HostView::look_at(Vec3::new(0.0, 12.0, 0.1), Vec3::ZERO, 1.0, 1.0, 0.1, 100.0).unwrap(),
        )
        .build()
        .unwrap()
}

/// Root (x, z) of blade `b`.
fn root(sim: &Simulation, b: usize) -> (f32, f32) {
    let r = sim.field.blades.rest_vertex(b, 0);
    (r.x, r.z)
}

/// Blades away from rest whose roots satisfy `at`.
fn displaced_where(sim: &Simulation, at: impl Fn(f32, f32) -> bool) -> usize {
    (0..sim.field.blades.count)
        .filter(|&b| {
            let (x, z) = root(sim, b);
            at(x, z) && !sim.field.blades.is_at_rest(b)
        })
        .count()
}

const HALF: [f32; 3] = [0.3, 0.25, 0.3];
/// Height of the box's centre: its bottom 5 cm above the ground, in the grass.
const Y: f32 = 0.3;

#[test]
fn a_body_added_moved_teleported_and_removed() {
    let mut sim = field(0.3);
    let dt = sim.params.dt_s;
    let start = Vec3::new(-3.0, Y, -2.0);
    let body = BodyBuilder::cuboid("crate", HALF)
        .at(start)
        .build()
        .unwrap();
    let id = sim.add_body(body);
    assert_eq!(sim.body(id).unwrap().pose.position, start);

    // Moved by the host along +x at 1.5 m/s for 100 frames: it sweeps a track.
    let mut p = start;
    for _ in 0..100 {
        p += Vec3::X * 1.5 * dt;
        sim.move_body(id, p, Quat::IDENTITY, dt).unwrap();
        sim.step(dt).unwrap();
        assert!((sim.body(id).unwrap().pose.position - p).length() < 1e-5);
    }
    let end_of_track = p.x;
    let track = |x: f32, z: f32| (z + 2.0).abs() < 0.25 && x > -2.6 && x < end_of_track - 0.4;
    let on_track = (0..sim.field.blades.count)
        .filter(|&b| {
            let (x, z) = root(&sim, b);
            track(x, z)
        })
        .count();
    assert!(on_track > 60, "{on_track}");
    assert!(
        displaced_where(&sim, track) as f32 > 0.9 * on_track as f32,
        "the moved body must bend the blades it sweeps"
    );

    // Teleported across the field: it is there at once, at rest, and the
    // blades between the two places stay exactly at rest.
    let there = Vec3::new(2.5, Y, 2.5);
    sim.teleport_body(id, there, Quat::from_rotation_y(0.3))
        .unwrap();
    let posed = sim.body(id).unwrap().pose;
    assert_eq!(posed.position, there);
    assert_eq!(posed.velocity, Vec3::ZERO);
    for _ in 0..10 {
        sim.step(dt).unwrap();
    }
    assert_eq!(sim.body(id).unwrap().pose.position, there);
    // Every blade between the end of the track and the new place: the line
    // from (end, -2) to (2.5, 2.5), 0.8 m either side, but not within reach
    // of the box at either end.
    let (a, b) = (
        glam::Vec2::new(end_of_track, -2.0),
        glam::Vec2::new(2.5, 2.5),
    );
    let between = |x: f32, z: f32| {
        let q = glam::Vec2::new(x, z);
        let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
        (q - (a + t * (b - a))).length() < 0.8 && q.distance(a) > 1.2 && q.distance(b) > 1.2
    };
    let blades_between = (0..sim.field.blades.count)
        .filter(|&i| {
            let (x, z) = root(&sim, i);
            between(x, z)
        })
        .count();
    assert!(blades_between > 300, "{blades_between}");
    assert_eq!(
        displaced_where(&sim, between),
        0,
        "a teleport must not sweep the grass between the two places"
    );
    // Standing there, it presses only the grass it stands in (the contact
    // response turns segments out of it; Eq. 2 gives no force at rest):
    // blades within its reach of the new place, none beyond.
    let near = |x: f32, z: f32, p: glam::Vec2| glam::Vec2::new(x, z).distance(p) < 1.2;
    assert!(displaced_where(&sim, |x, z| near(x, z, b)) > 0);
    // Within reach of the swept segment: start → end of the track.
    let swept = |x: f32, z: f32| (z + 2.0).abs() < 1.2 && x > start.x - 1.2 && x < a.x + 1.2;
    assert_eq!(
        displaced_where(&sim, |x, z| !swept(x, z) && !near(x, z, b)),
        0,
        "only the track and the grass where the box stands are pressed"
    );

    // From there the host moves it again: it bends the grass where it goes.
    let mut p = there;
    for _ in 0..20 {
        p -= Vec3::Z * 1.5 * dt;
        sim.move_body(id, p, Quat::from_rotation_y(0.3), dt)
            .unwrap();
        sim.step(dt).unwrap();
    }
    assert!(displaced_where(&sim, |x, z| x > 1.5 && z > 1.0) > 20);

    // Removed: it acts no more, and every blade it bent recovers.
    let removed = sim.remove_body(id).unwrap();
    assert_eq!(removed.id, id);
    assert!(sim.body(id).is_none());
    assert!(matches!(
        sim.remove_body(id),
        Err(BodyError::Unknown { .. })
    ));
    assert!(sim.blades_away_from_rest() > 0);
    for _ in 0..360 {
        sim.step(dt).unwrap();
    }
    assert_eq!(
        sim.blades_away_from_rest(),
        0,
        "blades a removed body bent recover normally"
    );
    assert!((0..sim.field.blades.count).all(|b| sim.field.blades.is_at_rest(b)));
}

#[test]
fn ids_stay_valid_while_bodies_come_and_go() {
    let mut sim = field(f32::INFINITY);
    let make = |name: &str, x: f32| {
        BodyBuilder::sphere(name, 0.3)
            .at([x, 0.3, 0.0])
            .build()
            .unwrap()
    };
    let a = sim.add_body(make("a", -2.0));
    let b = sim.add_body(make("b", 0.0));
    let c = sim.add_body(make("c", 2.0));
    assert_eq!((a, b, c), (BodyId(0), BodyId(1), BodyId(2)));
    sim.remove_body(a).unwrap();
    assert_eq!(sim.index_of(b).unwrap(), 0);
    assert_eq!(sim.body(c).unwrap().object.name, "c");
    // A new body never takes a removed body's id.
    let d = sim.add_body(make("d", 1.0));
    assert_eq!(d, BodyId(3));
    sim.teleport_body(c, Vec3::new(2.0, 0.3, 1.0), Quat::IDENTITY)
        .unwrap();
    assert_eq!(sim.body(c).unwrap().pose.position, Vec3::new(2.0, 0.3, 1.0));
    // Bad input is an error value, never a panic, and changes nothing.
    assert!(matches!(
        sim.move_body(a, Vec3::ZERO, Quat::IDENTITY, 0.1),
        Err(BodyError::Unknown { .. })
    ));
    let before = sim.body(b).unwrap().pose;
    let nan = sim.teleport_body(b, Vec3::NAN, Quat::IDENTITY).unwrap_err();
    assert!(nan.to_string().contains("must be finite"), "{nan}");
    assert!(sim.move_body(b, Vec3::ONE, Quat::IDENTITY, 0.0).is_err());
    assert_eq!(sim.body(b).unwrap().pose, before);
    sim.step(sim.params.dt_s).unwrap();
}

/// A zero quaternion names no rotation: moving or teleporting a body with
/// one is refused with a [`BodyError::NotFinite`] that says so, and the
/// body stays as it was (glam's `normalize` made its pose NaN, a body that
/// silently hit nothing). A quaternion of any other size is the rotation it
/// points at, however small or large its components.
#[test]
fn a_zero_rotation_is_refused_and_any_other_size_is_normalised() {
    let mut sim = field(f32::INFINITY);
    let dt = sim.params.dt_s;
    let at = Vec3::new(0.0, Y, 0.0);
    let id = sim.add_body(BodyBuilder::cuboid("crate", HALF).at(at).build().unwrap());
    let zero = Quat::from_xyzw(0.0, 0.0, 0.0, 0.0);
    let e = sim
        .move_body(id, at + Vec3::X * 0.02, zero, dt)
        .unwrap_err();
    assert!(
        matches!(&e, BodyError::NotFinite { .. }) && e.to_string().contains("rotation not zero"),
        "{e}"
    );
    let e = sim.teleport_body(id, at + Vec3::X, zero).unwrap_err();
    assert!(e.to_string().contains("rotation not zero"), "{e}");
    sim.step(dt).unwrap();
    let pose = sim.body(id).unwrap().pose;
    assert_eq!((pose.position, pose.rotation), (at, Quat::IDENTITY));

    let turn = Quat::from_rotation_y(0.5);
    for scale in [1e-30, 1e30] {
        let q = Quat::from_vec4(glam::Vec4::from(turn) * scale);
        sim.move_body(id, at, q, dt).unwrap();
        sim.step(dt).unwrap();
        let r = sim.body(id).unwrap().pose.rotation;
        assert!(r.abs_diff_eq(turn, 1e-6), "{scale}: {r}");
        sim.teleport_body(id, at, q).unwrap();
        assert!(sim.body(id).unwrap().pose.rotation.abs_diff_eq(turn, 1e-6));
    }
}
