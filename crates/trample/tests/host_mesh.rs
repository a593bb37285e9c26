//! A host's animated mesh (DESIGN §3 "Deforming meshes": "a host's animated
//! mesh"; issue 13 item 2): the host sets a body's vertices every frame
//! (`Simulation::set_body_vertices`) and the body's tree is refitted to
//! them at every sub-step. A mesh whose vertices the host slides along
//! +x, on a body that never moves, must leave the track the same body
//! moved along +x leaves, and no blade inside it where the host put it;
//! bad vertices are refused with the
//! body, the index or the count, and what is allowed, leaving the body as
//! it was.

use glam::{Quat, Vec3};
use trample::Simulation;
use trample::builder::{BodyBuilder, SimulationBuilder};
use trample::field::{FieldParams, LodParams};
use trample::object::{Anchor, Scale, ShapeParams, TriMesh, shapes};
use trample::step::{BodyError, BodyId, HostView, SimParams};

/// 8 × 8 m of grass (4 × 4 patches of 20 × 20 cells of 0.1 m), every cell
/// geometric, seen by a host camera from above; the paper's lasting track.
fn field() -> Simulation {
    field_with(SimParams::default(), Vec3::new(0.0, 12.0, 0.1))
}

/// The same grass under `sim`, seen from `eye`.
fn field_with(sim: SimParams, eye: Vec3) -> Simulation {
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
        .sim(sim)
        .host_view(HostView::look_at(eye, Vec3::ZERO, 1.0, 1.0, 0.1, 500.0).unwrap())
        .build()
        .unwrap()
}

const HALF: [f32; 3] = [0.3, 0.25, 0.3];

/// A box as a host's engine often hands one over: three vertices of its
/// own per triangle (no shared vertex; the body welds them).
fn unshared_box(half: [f32; 3]) -> TriMesh {
    let m = shapes::cuboid(Vec3::from(half));
    let positions = m
        .indices
        .iter()
        .flatten()
        .map(|&i| m.positions[i as usize])
        .collect();
    let indices = (0..m.indices.len() as u32)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    TriMesh { positions, indices }
}
/// The box's centre: its bottom 5 cm above the ground, in the grass.
const START: Vec3 = Vec3::new(-2.2, 0.3, 0.4);
/// How fast the box goes, m/s.
const SPEED: f32 = 1.5;

#[test]
fn vertices_slid_by_the_host_leave_the_track_the_moved_body_leaves() {
    slid_against_moved(SPEED, 40);
}

/// At 45 m/s the box goes 0.75 m a frame, more than its 0.6 m: both are
/// sub-stepped (the slid mesh by its vertices' travel) and leave the same
/// unbroken track.
#[test]
fn vertices_slid_fast_are_sub_stepped_as_the_body_moved_fast_is() {
    slid_against_moved(45.0, 4);
}

/// Far from the camera with `far_every = 4`, the body steps one frame in
/// four, and its turn joins the frames it sat out: the host's vertices as
/// `move_body` joins the host's moves. The same track (at 6 m/s a turn
/// travels 0.4 m, so it takes two sub-steps).
#[test]
fn vertices_slid_far_away_join_the_frames_a_far_body_sits_out() {
    slid_against_moved_in(6.0, 40, far_field);
}

/// [`field`] seen from 85 m away, its bodies stepped one frame in four.
fn far_field() -> Simulation {
    let sim = SimParams {
        far_every: 4,
        far_beyond_m: 20.0,
        ..SimParams::default()
    };
    field_with(sim, Vec3::new(60.0, 10.0, 60.0))
}

fn slid_against_moved(speed: f32, frames: u32) {
    slid_against_moved_in(speed, frames, field);
}

fn slid_against_moved_in(speed: f32, frames: u32, field: fn() -> Simulation) {
    let mesh = unshared_box(HALF);
    let crate_body = BodyBuilder::mesh("crate", &mesh)
        .at(START.to_array())
        .build()
        .unwrap();
    let (mut slid, mut moved) = (field(), field());
    let a = slid.add_body(crate_body.clone());
    let b = moved.add_body(crate_body);
    // The host's vertices: its own 36, not the body's 8 welded ones.
    assert_eq!(slid.bodies[0].object.mesh.positions.len(), 8);
    let rest = mesh.positions;
    let dt = slid.params.dt_s;
    let mut offset = Vec3::ZERO;
    let mut far_turns = 0;
    for _ in 0..frames {
        offset += Vec3::X * speed * dt;
        let vertices: Vec<Vec3> = rest.iter().map(|&p| p + offset).collect();
        slid.set_body_vertices(a, &vertices, dt).unwrap();
        moved
            .move_body(b, START + offset, Quat::IDENTITY, dt)
            .unwrap();
        if slid.params.far_every > 1 {
            // A far turn's cost is estimated by the mesh's speed (its
            // farthest vertex's), as by a moved body's: how the turns are
            // balanced (`trample::step::passes::far_work`).
            let work = |sim: &Simulation| trample::step::passes::far_work(sim, &sim.bodies[0]);
            let p = &slid.params;
            let want = f64::from(speed * dt * p.far_every as f32 / p.far_travel_m);
            let (ws, wm) = (work(&slid).travel, work(&moved).travel);
            eprintln!("far turn travel: slid {ws}, moved {wm}, want {want}");
            assert!(
                (ws - want).abs() <= 1e-3 * want,
                "a far turn's travel: slid mesh {ws}, {want} at its speed"
            );
        }
        let timings = slid.step(dt).unwrap();
        let substeps = timings.substeps;
        far_turns += timings.far_bodies;
        let want = moved.step(dt).unwrap().substeps;
        assert_eq!(
            substeps, want,
            "sub-steps of the slid mesh and of the moved body"
        );
        if speed * dt > 2.0 * HALF[0] {
            assert!(substeps > 1, "a mesh slid 0.75 m a frame is sub-stepped");
        }
    }
    if slid.params.far_every > 1 {
        eprintln!("far turns: {far_turns}");
        assert!(
            far_turns > 0 && far_turns < frames,
            "the body must step far, in turns: {far_turns} far turns in {frames} frames"
        );
    }
    // The slid body never moved; its mesh and tree did.
    let body = &slid.bodies[0];
    assert_eq!(body.pose.position, START);
    assert!(body.deforms());
    body.tree
        .validate()
        .expect("the refitted tree is well formed");
    // (A far body's mesh stays where its last turn left it, up to
    // `far_every - 1` frames behind.)
    let behind = (slid.params.far_every - 1) as f32 * speed * dt;
    let centre = body.world_root.center;
    assert!(
        (centre.x - (START.x + offset.x)).abs() < 1e-4 + behind,
        "the root box follows the vertices: {centre}"
    );
    // The same track, blade for blade. (The box's bottom is 5 cm above
    // the ground, so no segment is pinned and laid flat away from the
    // body's centre, `deform::contact::flat_direction`: that centre is the
    // pose's, which stays at START for the slid mesh.)
    let away = |sim: &Simulation| -> Vec<bool> {
        (0..sim.field.blades.count)
            .map(|b| !sim.field.blades.is_at_rest(b))
            .collect()
    };
    let (sa, ma) = (away(&slid), away(&moved));
    let (ns, nm) = (
        sa.iter().filter(|a| **a).count(),
        ma.iter().filter(|a| **a).count(),
    );
    let worst = slid
        .field
        .blades
        .pos
        .iter()
        .zip(&moved.field.blades.pos)
        .map(|(p, q)| Vec3::from(p.vec3a()).distance(q.vec3a().into()))
        .fold(0.0f32, |w, d| {
            w.max(if d.is_nan() { f32::INFINITY } else { d })
        });
    eprintln!("blades away from rest: slid {ns}, moved {nm}; worst vertex {worst:.2e} m");
    assert!(ns > 100, "the slid mesh must leave a track: {ns} blades");
    assert!(
        worst <= 1e-3,
        "the slid mesh's track is {worst} m from the moved body's"
    );
    let end_x = START.x + offset.x;
    let at_end = (0..slid.field.blades.count)
        .filter(|&b| sa[b] && (slid.field.blades.rest_vertex(b, 0).x - end_x).abs() < 0.25)
        .count();
    assert!(
        at_end > 20,
        "blades under the mesh's last place are bent: {at_end}"
    );
    // Contact holds against the mesh where the host put it: no blade
    // vertex lies inside the slid box (a few mm of the contact tolerance
    // and the ground's clearance aside). At 45 m/s a few are still on
    // their way out after the last sub-step, as many as the moved body
    // leaves (`deform::contact::CONTACT_ITERATIONS` a sub-step).
    let inside = |sim: &Simulation| {
        let half = Vec3::from(HALF) - 0.01;
        let centre = START + offset;
        sim.field
            .blades
            .pos
            .iter()
            .filter(|p| {
                let d = (Vec3::from(p.vec3a()) - centre).abs();
                d.x < half.x && d.y < half.y && d.z < half.z
            })
            .count()
    };
    let (si, mi) = (inside(&slid), inside(&moved));
    eprintln!("vertices inside: slid {si}, moved {mi}");
    assert_eq!(
        si, mi,
        "blade vertices inside the slid mesh and the moved body"
    );
    // (Far away, the box has gone on since its last turn: the blades
    // where it is now wait for its next.)
    if speed <= SPEED && slid.params.far_every == 1 {
        assert_eq!(si, 0, "blade vertices inside the slid mesh");
    }
}

/// A plate above the grass that the host lowers into it in place (a foot
/// stamping, its pose still): the blades under it are pressed down and
/// none stays inside it. Its box covers the same blades all along, so
/// this also holds that a still body whose mesh the host deforms never
/// reuses what it found at the sub-step before (`step/at_rest.rs`).
#[test]
fn a_plate_the_host_lowers_in_place_presses_the_grass() {
    let mut sim = field();
    let half = Vec3::new(0.4, 0.05, 0.4);
    let centre = Vec3::new(0.5, 0.75, 0.5);
    let plate = shapes::cuboid(half);
    let id = sim.add_body(
        BodyBuilder::mesh("plate", &plate)
            .at(centre.to_array())
            .build()
            .unwrap(),
    );
    let rest = plate.positions;
    let dt = sim.params.dt_s;
    let frames = 30;
    let drop = 0.55;
    for k in 1..=frames {
        let down = Vec3::Y * (-drop * k as f32 / frames as f32);
        let vertices: Vec<Vec3> = rest.iter().map(|&p| p + down).collect();
        sim.set_body_vertices(id, &vertices, dt).unwrap();
        sim.step(dt).unwrap();
    }
    for _ in 0..10 {
        sim.step(dt).unwrap();
    }
    // The plate's bottom is now 15 cm above the ground.
    let now = centre - Vec3::Y * drop;
    let blades = &sim.field.blades;
    let under: Vec<usize> = (0..blades.count)
        .filter(|&b| {
            let r = blades.rest_vertex(b, 0);
            (r.x - now.x).abs() < half.x - 0.05 && (r.z - now.z).abs() < half.z - 0.05
        })
        .collect();
    let pressed = under.iter().filter(|&&b| !blades.is_at_rest(b)).count();
    let inside = blades
        .pos
        .iter()
        .filter(|p| {
            let d = (Vec3::from(p.vec3a()) - now).abs();
            d.x < half.x - 0.01 && d.y < half.y - 0.01 && d.z < half.z - 0.01
        })
        .count();
    eprintln!(
        "under the plate: {} blades, {pressed} bent; {inside} vertices inside",
        under.len()
    );
    assert!(under.len() > 30);
    assert_eq!(pressed, under.len(), "every blade under the plate is bent");
    assert_eq!(inside, 0, "blade vertices inside the lowered plate");
}

/// The vertices of the mesh file a body was made from, set unchanged,
/// give the body's mesh bit for bit: scaled, rotated and anchored as it
/// was built, the file's welded and unused vertices mapped away (the
/// beetle: 4.5 times, turned 30°, its bottom at the origin).
#[test]
fn a_files_own_vertices_give_the_bodys_mesh_bit_for_bit() {
    let meshes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
    let shape = ShapeParams::Mesh {
        path: "beetle.obj".into(),
        anchor: Anchor::Bottom,
    };
    let car = BodyBuilder::new("car", shape)
        .scale(Scale::PerAxis([4.5, 4.0, 4.5]))
        .rotation_deg([0.0, 30.0, 0.0])
        .at([0.0, 0.0, 0.0])
        .build_in(0, &meshes)
        .unwrap();
    let mut sim = field();
    let id = sim.add_body(car);
    let built = sim.bodies[0].object.mesh.positions.clone();
    let file = trample::object::load_mesh_file(&meshes.join("beetle.obj")).unwrap();
    eprintln!(
        "beetle: {} vertices in the file, {} in the body",
        file.positions.len(),
        built.len()
    );
    let dt = sim.params.dt_s;
    sim.set_body_vertices(id, &file.positions, dt).unwrap();
    sim.step(dt).unwrap();
    let now = &sim.bodies[0].object.mesh.positions;
    assert_eq!(now.len(), built.len());
    for (k, (a, b)) in now.iter().zip(&built).enumerate() {
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits),
            "vertex {k}"
        );
    }
}

#[test]
fn bad_vertices_are_refused_and_leave_the_body_as_it_was() {
    let mut sim = field();
    let mesh = unshared_box(HALF);
    let id = sim.add_body(
        BodyBuilder::mesh("crate", &mesh)
            .at(START.to_array())
            .build()
            .unwrap(),
    );
    let built = sim.bodies[0].object.mesh.positions.clone();
    let rest = mesh.positions.clone();
    let dt = sim.params.dt_s;
    let expect = |e: BodyError, want: &[&str]| {
        let text = e.to_string();
        for w in want {
            assert!(text.contains(w), "{text:?} should name {w:?}");
        }
    };
    let short = &rest[..rest.len() - 1];
    expect(
        sim.set_body_vertices(id, short, dt).unwrap_err(),
        &[
            "body 0",
            &format!("{} positions given", rest.len() - 1),
            &format!("exactly {}", rest.len()),
        ],
    );
    let mut bad = rest.clone();
    bad[5].y = f32::NAN;
    expect(
        sim.set_body_vertices(id, &bad, dt).unwrap_err(),
        &["body 0", "position 5", "not finite"],
    );
    for dt in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        expect(
            sim.set_body_vertices(id, &rest, dt).unwrap_err(),
            &["body 0", "dt =", "finite and > 0"],
        );
    }
    expect(
        sim.set_body_vertices(BodyId(7), &rest, dt).unwrap_err(),
        &["body 7", "no such body"],
    );
    // The body's own (welded) vertex count is not the host's.
    expect(
        sim.set_body_vertices(id, &built, dt).unwrap_err(),
        &["8 positions given", "exactly 36"],
    );
    // Finite, but not once scaled as the body is (a body made at scale
    // 1,000: 600 m across).
    let big = sim.add_body(
        BodyBuilder::mesh("big crate", &mesh)
            .scale(Scale::Uniform(1000.0))
            .at([0.0, -1000.0, 0.0])
            .build()
            .unwrap(),
    );
    let far: Vec<Vec3> = rest.iter().map(|p| *p * 1e37).collect();
    expect(
        sim.set_body_vertices(big, &far, dt).unwrap_err(),
        &["body 1", "not finite once scaled"],
    );
    sim.remove_body(big).unwrap();
    // Nothing changed: not deforming, the mesh and tree as built.
    assert!(!sim.bodies[0].deforms());
    sim.step(dt).unwrap();
    assert_eq!(sim.bodies[0].object.mesh.positions, built);

    // A body that plays a glTF animation has its vertices from it.
    let meshes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
    let shape = ShapeParams::Mesh {
        path: "walker.glb".into(),
        anchor: Anchor::File,
    };
    let walker = BodyBuilder::new("walker", shape)
        .animation("walk", 1.0)
        .build_in(2, &meshes)
        .expect("scenes/meshes/walker.glb with its walk");
    let w = sim.add_body(walker);
    let n = sim.bodies[1].object.mesh.positions.clone();
    assert_eq!(sim.bodies[1].id, w);
    expect(
        sim.set_body_vertices(w, &n, dt).unwrap_err(),
        &["body 2", "glTF animation"],
    );
}
