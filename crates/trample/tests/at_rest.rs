//! Colliders at rest reuse their work (ours, `sim.reuse_at_rest`;
//! `trample::step` module `at_rest`): a parked crate, a ball that rolls and
//! stops, a box circling close by (its propagation and contact reach the
//! crate's blades), blades recovering around them, and the host teleporting,
//! moving, parking, removing and adding bodies — every blade, class and
//! track owner the same bits with reuse on as with it off, step by step;
//! and the reuse taking most of the parked bodies' work once they settle.

mod common;
use common::*;

use glam::{Quat, Vec3};
use trample::Simulation;

/// A 12.8 m field at precision 5, blades recovering in `recovery` seconds,
/// with a parked crate, a ball that stops after 1 s, a box circling the
/// crate and a ball rolling past it, 0.1 m from its side (bending into it
/// the blades it holds).
fn parked_field(reuse: bool, recovery: &str) -> Simulation {
    field_12m(
        9.0,
        &format!("recovery_s = {recovery}\nreuse_at_rest = {reuse}"),
        r#"
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.5, 0.3, 0.4] }
path = { kind = "static", position = [-3.0, 0.29, -3.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5 }
orientation = "rolling"
path = { kind = "line", from = [-5.0, 0.5, 2.0], to = [0.0, 0.5, 2.0], duration_s = 1.0 }
[[objects]]
name = "passer"
shape = { kind = "box", half_extents_m = [0.3, 0.25, 0.3] }
orientation = "face_motion"
path = { kind = "circle", center = [-3.0, 0.25, -3.0], radius_m = 1.3, period_s = 3.0 }
[[objects]]
name = "grazer"
shape = { kind = "sphere", radius_m = 0.3 }
orientation = "rolling"
path = { kind = "line", from = [-2.1, 0.3, -5.5], to = [-2.1, 0.3, -0.5], duration_s = 3.0 }
"#,
    )
}

/// [`parked_field`] with recovery off and the crate alone, after 180
/// steps: settled under it.
fn settled_crate(reuse: bool) -> Simulation {
    let mut parked = parked_field(reuse, "inf");
    for name in ["ball", "passer", "grazer"] {
        let id = parked
            .bodies
            .iter()
            .find(|b| b.object.name == name)
            .unwrap()
            .id;
        parked.remove_body(id).unwrap();
    }
    parked.run(180).unwrap();
    parked
}

/// The first difference between two simulations' blades, classes and
/// track owners, in words (`None`: the same bits).
fn first_difference(a: &Simulation, b: &Simulation) -> Option<String> {
    let (pa, pb) = (&a.field.blades.pos, &b.field.blades.pos);
    if let Some(i) = pa.iter().zip(pb).position(|(x, y)| {
        x.vec3a().to_array().map(f32::to_bits) != y.vec3a().to_array().map(f32::to_bits)
    }) {
        let count = a.field.blades.count;
        return Some(format!(
            "blade {} vertex {}: {} against {}",
            i % count,
            i / count,
            pa[i].vec3a(),
            pb[i].vec3a()
        ));
    }
    if let Some(i) = a.class.iter().zip(&b.class).position(|(x, y)| x != y) {
        return Some(format!("blade {i}'s class"));
    }
    if let Some(i) = a
        .track_owner
        .iter()
        .zip(&b.track_owner)
        .position(|(x, y)| x != y)
    {
        return Some(format!("blade {i}'s track owner"));
    }
    None
}

/// The host's moves at frame `f` (the same on both simulations).
fn host(sim: &mut Simulation, f: u64) {
    let id = |sim: &Simulation, name: &str| {
        sim.bodies
            .iter()
            .find(|b| b.object.name == name)
            .map(|b| b.id)
            .expect("body")
    };
    let dt = sim.params.dt_s;
    match f {
        // The crate jumps elsewhere and parks there.
        90 => sim
            .teleport_body(id(sim, "crate"), Vec3::new(3.0, 0.29, -3.0), Quat::IDENTITY)
            .unwrap(),
        // Then is pushed 1 m along x over 20 frames, and parks again.
        130..150 => {
            let x = 3.0 + (f - 129) as f32 * 0.05;
            sim.move_body(
                id(sim, "crate"),
                Vec3::new(x, 0.29, -3.0),
                Quat::IDENTITY,
                dt,
            )
            .unwrap();
        }
        // The stopped ball leaves; a copy of the crate, kept memory and
        // all, is added where the crate first stood.
        170 => {
            sim.remove_body(id(sim, "ball")).unwrap();
            let mut copy = sim.bodies[0].clone();
            copy.object.name = "copy".into();
            let copy = sim.add_body(copy);
            sim.teleport_body(copy, Vec3::new(-3.0, 0.29, -3.0), Quat::IDENTITY)
                .unwrap();
        }
        _ => {}
    }
}

/// With reuse on and off, every step gives the same bits: blades, classes,
/// track owners. The reuse is not idle: the parked bodies take most of
/// their tiles and blades from what they kept (counted), so a version that
/// reused a tile whatever its blades, or a blade whatever its state, would
/// differ here (checked: both fail this test).
#[test]
fn parked_stopping_and_passing_objects_give_the_same_bits_with_reuse() {
    let (mut on, mut off) = (parked_field(true, "2.0"), parked_field(false, "2.0"));
    let (mut tiles, mut blades) = (0u64, 0u64);
    for f in 0..240 {
        host(&mut on, f);
        host(&mut off, f);
        on.step(on.params.dt_s).unwrap();
        off.step(off.params.dt_s).unwrap();
        if let Some(d) = first_difference(&on, &off) {
            panic!("frame {f}: {d}");
        }
        assert_eq!(off.timings.reused_tiles + off.timings.reused_blades, 0);
        tiles += u64::from(on.timings.reused_tiles);
        blades += u64::from(on.timings.reused_blades);
    }
    assert!(
        tiles > 1_000 && blades > 10_000,
        "reused {tiles} tiles, {blades} blades"
    );
}

/// Once settled, a parked body's work is taken from what it kept: a crate
/// parked alone for three seconds (the paper's lasting track, nothing
/// recovering) takes at least 9 in 10 of its tiles from memory, and its
/// contact response leaves at least 9 in 10 of the blades it touches
/// without a query (measured 2026-11-26: 19 of 20 tiles, 87 of 88 blades;
/// a few blades under it still settle by a few ulp a step, and their tile
/// is tested again); bodies that keep moving reuse nothing.
#[test]
fn a_settled_parked_body_reuses_its_work_and_moving_ones_none() {
    let mut parked = settled_crate(true);
    for _ in 0..10 {
        parked.step(parked.params.dt_s).unwrap();
        let t = &parked.timings;
        assert!(t.narrow_tiles > 10 && t.dbg_blades > 50, "{t:?}");
        assert!(t.reused_tiles * 10 >= t.narrow_tiles * 9, "{t:?}");
        assert!(t.reused_blades * 10 >= t.dbg_blades * 9, "{t:?}");
    }

    let mut moving = parked_field(true, "inf");
    let id = moving.bodies[0].id;
    moving.remove_body(id).unwrap();
    for f in 0..50 {
        moving.step(moving.params.dt_s).unwrap();
        let t = &moving.timings;
        assert!(t.narrow_tiles > 0, "frame {f}: {t:?}");
        assert_eq!(t.reused_tiles + t.reused_blades, 0, "frame {f}: {t:?}");
    }
}

/// A settled parked crate (recovery off, so nothing else writes its
/// blades) lists no blade as changed whose bits the step did not change:
/// the contact response leaves a blade it moved back to its own bits
/// unstored, and a host that uploads the listed blades uploads nothing
/// for it. (Before, the blades under it that the contact response pushed
/// back to where they were were stored again every step: ~20 % of those
/// under the parked herd.) Every blade whose bits changed is still listed
/// (`tests/host_buffers.rs`).
#[test]
fn a_settled_parked_body_lists_no_blade_it_left_as_it_was() {
    for reuse in [true, false] {
        let mut parked = settled_crate(reuse);
        let mut pushed = 0;
        for f in 0..10 {
            let before = position_bits(&parked);
            parked.step(parked.params.dt_s).unwrap();
            pushed += parked.timings.contact_blades;
            let bl = &parked.field.blades;
            for b in parked.changed_blades() {
                let moved = (0..=bl.segments).any(|k| {
                    let i = k * bl.count + b as usize;
                    bl.pos[i].pos.map(f32::to_bits) != before[i]
                });
                assert!(
                    moved,
                    "reuse {reuse}, step {f}: blade {b} listed, bits unchanged"
                );
            }
        }
        // The contact response did count blades as moved: the case exists.
        assert!(pushed > 10, "reuse {reuse}: {pushed}");
    }
}

/// A parked object keeps its work while the host's `dt` changes from step
/// to step (a game loop's): a still collider's key leaves the sub-step's
/// length out, since with no velocity neither the contact weights nor Eq.
/// 2 read it. The same bits with reuse on and off under a `dt` cycling
/// through 1/60, 1/45, 1/90 and 1/30 s, and the parked bodies reuse their
/// tiles (none would be if the key kept the length: checked).
#[test]
fn a_parked_body_reuses_its_work_under_a_varying_dt() {
    let (mut on, mut off) = (parked_field(true, "2.0"), parked_field(false, "2.0"));
    let mut reused = 0u64;
    for f in 0..200usize {
        let dt = [1.0 / 60.0, 1.0 / 45.0, 1.0 / 90.0, 1.0 / 30.0][f % 4];
        on.step(dt).unwrap();
        off.step(dt).unwrap();
        if let Some(d) = first_difference(&on, &off) {
            panic!("frame {f} (dt {dt}): {d}");
        }
        reused += u64::from(on.timings.reused_tiles);
    }
    assert!(reused > 1_000, "reused {reused} tiles");
}
