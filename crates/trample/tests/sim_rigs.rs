//! Articulated and animated objects in the simulation (issue 13, "Tests that
//! must exist"): the tractor of `scenes/tractor.toml` (a body raised clear
//! of the grass, four wheels as parts) and the walker of
//! `scenes/walker.toml` (a skinned glTF playing "walk", its tree refitted
//! every sub-step).

use glam::Vec3;
use std::path::Path;
use trample::Simulation;
use trample::collision::segment_triangle::segment_hits_triangle;
use trample::scene::Scene;
use trample::step::BladeClass;
use trample::step::query::HitMode;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn run(sim: &mut Simulation, frames: u32) {
    let dt = sim.params.dt_s;
    for _ in 0..frames {
        sim.step(dt).expect("step");
    }
}

/// The tractor's wheels spin at v/r about their axles, and a wheel's lowest
/// point (its contact with the ground) is at rest: Eq. 2's contact speed,
/// the part's own `|v + ω × r|`, is ~0 there, while its top moves at 2v.
#[test]
fn tractor_wheels_roll_at_v_over_r_with_their_ground_contact_at_rest() {
    let mut sim = scene("tractor.toml").build().unwrap();
    run(&mut sim, 30);
    let body = &sim.bodies[0];
    let v = body.pose.velocity.length();
    assert!(v > 2.5, "the tractor drives (v = {v} m/s)");
    for (part, radius) in body.parts.iter().zip([0.7, 0.7, 0.45, 0.45]) {
        let pose = part.pose;
        // The wheel centre's own speed (on a curve, the outer wheels run
        // faster than the body's origin).
        let vc = pose.velocity.length();
        assert!(
            (vc - v).abs() < 0.2 * v,
            "wheel centre at {vc} m/s, body {v}"
        );
        // Spin about the axle (the body's own turn on the curve is about
        // the vertical, which does not move the contact point along).
        let spin = pose.angular_velocity.reject_from(Vec3::Y).length();
        assert!(
            (spin - vc / radius).abs() < 0.02 * vc / radius,
            "spin {spin} rad/s, v/r = {}",
            vc / radius
        );
        // The contact point does not move along the rolling direction (it
        // may scrub sideways: a rear wheel on a curve slides by the body's
        // turn rate times its distance from the body's origin).
        let ground = pose.position - Vec3::Y * radius;
        let axle = pose.angular_velocity.reject_from(Vec3::Y).normalize();
        let forward = axle.cross(Vec3::Y);
        let contact = pose.point_velocity(ground).dot(forward).abs();
        assert!(contact < 0.01 * vc, "contact point rolls at {contact} m/s");
        let top = pose
            .point_velocity(pose.position + Vec3::Y * radius)
            .length();
        assert!(
            (top - 2.0 * vc).abs() < 0.02 * vc,
            "top at {top} m/s, 2v = {}",
            2.0 * vc
        );
    }
}

/// The tractor leaves two wheel tracks with standing grass between them: in
/// the classes after 2.5 s, no blade rooted within 0.3 m of the body's
/// centre line has been touched (the body clears the grass), and blades
/// under the wheels on both sides have.
#[test]
fn tractor_leaves_two_separate_wheel_tracks_with_untouched_grass_between() {
    let mut sim = scene("tractor.toml").build().unwrap();
    let frames = 180;
    run(&mut sim, frames);
    let t_end = frames as f32 * sim.params.dt_s;
    let object = &sim.bodies[0].object;
    // The centre line, sampled every 1 cm of travel or so.
    let samples: Vec<(f32, Vec3, Vec3)> = (0..=(t_end * 300.0) as u32)
        .map(|i| {
            let t = i as f32 / 300.0;
            let pose = object.pose_at(t);
            (t, pose.position, pose.rotation * Vec3::X)
        })
        .collect();
    let blades = &sim.field.blades;
    let (mut middle, mut middle_touched) = (0, 0);
    let (mut left, mut right) = (0, 0);
    for b in 0..blades.count {
        let root = Vec3::from(blades.rest_vertex(b, 0));
        let (t, centre, side) = samples
            .iter()
            .copied()
            .min_by(|a, c| {
                let da = (a.1 - root).with_y(0.0).length_squared();
                let dc = (c.1 - root).with_y(0.0).length_squared();
                da.total_cmp(&dc)
            })
            .unwrap();
        // Away from both ends, where the wheels run ahead of and behind the
        // centre line's first and last points.
        if t < 0.5 || t > t_end - 0.6 {
            continue;
        }
        let lateral = (root - centre).with_y(0.0).dot(side);
        let touched = sim.class[b] != BladeClass::Untouched;
        if lateral.abs() < 0.3 {
            middle += 1;
            middle_touched += usize::from(touched);
        } else if touched && (0.75..1.15).contains(&lateral) {
            left += 1;
        } else if touched && (-1.15..-0.75).contains(&lateral) {
            right += 1;
        }
    }
    assert!(middle > 250, "{middle} blades between the tracks checked");
    assert_eq!(
        middle_touched, 0,
        "{middle_touched} of {middle} blades between the tracks were touched"
    );
    assert!(
        left > 200 && right > 200,
        "tracks: left {left}, right {right}"
    );
}

/// `trample collide scenes/walker.toml --time T --dump-object` at several
/// T: the exact hits (the queries the command dumps) agree with the
/// dumped, deformed triangles (a segment is an exact hit when it crosses
/// one of them, or lies inside the closed mesh: ray parity through them),
/// and no precision misses an exact hit. The deformation is real: the
/// dumped triangles differ from one T to the next by more than the root's
/// travel.
#[test]
fn walker_exact_hits_agree_with_the_dumped_deformed_triangles_at_several_times() {
    let sim = scene("walker.toml").build().unwrap();
    assert!(sim.bodies[0].object.closed, "the walker's mesh is closed");
    let n = sim.field.blades.segments;
    let blades = &sim.field.blades;
    let mut previous: Option<Vec<[Vec3; 3]>> = None;
    for t in [0.4_f32, 3.3, 7.9] {
        let tris = sim.object_triangles_at(t);
        assert_eq!(tris.len(), sim.bodies[0].object.mesh.triangle_count());
        let (lo, hi) = tris.iter().flatten().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let exact = sim.segment_hits_at_rest(t, HitMode::Exact);
        let (mut hits, mut disagree) = (0, 0);
        for b in 0..blades.count {
            let root = Vec3::from(blades.rest_vertex(b, 0));
            let near = root.x > lo.x - 0.7
                && root.x < hi.x + 0.7
                && root.z > lo.z - 0.7
                && root.z < hi.z + 0.7;
            for k in 0..n {
                let flag = exact[b * n + k] == 1;
                if !near {
                    assert!(!flag, "blade {b} far from the walker hit at t = {t}");
                    continue;
                }
                let p0 = Vec3::from(blades.rest_vertex(b, k));
                let p1 = Vec3::from(blades.rest_vertex(b, k + 1));
                let crosses = tris.iter().any(|tri| segment_hits_triangle(p0, p1, tri));
                let reference = crosses || inside(&tris, p0);
                hits += usize::from(reference);
                disagree += usize::from(reference != flag);
            }
        }
        // Two legs in grass of 100 blades a square metre: a few blades.
        assert!(hits >= 3, "the walker touches grass at t = {t} ({hits})");
        assert_eq!(disagree, 0, "t = {t}: {disagree} of {hits} hits disagree");
        for d in 1..=7 {
            let at_d = sim.segment_hits_at_rest(t, HitMode::Precision(d));
            let missed = exact
                .iter()
                .zip(&at_d)
                .filter(|(e, p)| **e == 1 && **p == 0)
                .count();
            assert_eq!(
                missed, 0,
                "precision {d} misses {missed} exact hits at t = {t}"
            );
        }
        if let Some(before) = previous {
            let moved = tris
                .iter()
                .zip(&before)
                .map(|(a, b)| (a[0] - b[0]).length())
                .fold(0.0f32, f32::max);
            assert!(moved > 0.1, "the mesh moved at most {moved} m");
        }
        previous = Some(tris);
    }
}

/// Ray parity through `tris` from `p` along a generic direction.
fn inside(tris: &[[Vec3; 3]], p: Vec3) -> bool {
    let dir = Vec3::new(0.2113, 0.9, 0.3797).normalize() * 100.0;
    tris.iter()
        .filter(|tri| segment_hits_triangle(p, p + dir, tri))
        .count()
        % 2
        == 1
}

/// The walker's legs sweep the grass as it walks, its tree refitted every
/// sub-step stays well formed, and the deformation reaches the collision:
/// blades are touched along the circle it walks.
#[test]
fn walker_tramples_grass_along_its_loop_and_its_refitted_tree_stays_well_formed() {
    let mut sim = scene("walker.toml").build().unwrap();
    let mut touched_before = 0;
    for _ in 0..4 {
        run(&mut sim, 30);
        sim.bodies[0].tree.assert_well_formed();
        // The stepped tree goes without tilted boxes (the contact walk
        // does not use them); the posed copies queries use have them,
        // around the posed triangles.
        assert!(sim.bodies[0].tree.slabs.is_empty());
        let posed = &sim.bodies_at(sim.time as f32)[0].tree;
        assert_eq!(posed.slabs.len(), posed.nodes.len());
        posed.assert_well_formed();
        let touched = sim
            .class
            .iter()
            .filter(|c| **c != BladeClass::Untouched)
            .count();
        assert!(touched > touched_before, "the trail grows ({touched})");
        touched_before = touched;
    }
    // Every touched blade lies near the 4 m circle.
    let blades = &sim.field.blades;
    for (b, c) in sim.class.iter().enumerate() {
        if *c != BladeClass::Untouched {
            let r = Vec3::from(blades.rest_vertex(b, 0)).with_y(0.0).length();
            assert!((r - 4.0).abs() < 1.2, "blade {b} touched at r = {r} m");
        }
    }
}

/// A small field seen from above, every cell geometric; no bodies.
fn small_field() -> Simulation {
    use trample::builder::SimulationBuilder;
    use trample::field::{FieldParams, LodParams};
    use trample::step::HostView;
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [2, 2],
            cells_per_patch: 20,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 1000.0,
            billboard_m: 2000.0,
        })
        .host_view(
            HostView::look_at(Vec3::new(0.0, 12.0, 0.1), Vec3::ZERO, 1.0, 1.0, 0.1, 100.0).unwrap(),
        )
        .build()
        .unwrap()
}

/// The host poses a `host` part by name or index (issue 13: "the API sets a
/// part's pose by name or index"): a boot held above the grass presses
/// nothing; lowered into it by the host, it presses the grass under it.
/// Unknown parts and parts whose joint is not `host` are refused with
/// messages naming them.
#[test]
fn host_poses_a_part_by_name_or_index_and_it_presses_the_grass() {
    use glam::Quat;
    use trample::builder::BodyBuilder;
    use trample::object::parts::{JointParams, PartParams};
    use trample::object::{Pose, Scale, ShapeParams};
    use trample::step::BodyError;
    use trample::step::rig::PartRef;
    let part = |name: &str, joint| PartParams {
        name: name.into(),
        parent: None,
        shape: ShapeParams::Box {
            half_extents_m: [0.3, 0.3, 0.3],
        },
        scale: Scale::default(),
        rotation_deg: [0.0; 3],
        offset_m: [0.0, -1.0, 0.0],
        joint,
    };
    let body = BodyBuilder::cuboid("crane", [0.2, 0.2, 0.2])
        .at([0.0, 2.0, 0.0])
        .parts([
            part("boot", JointParams::Host),
            part("weight", JointParams::Fixed),
        ])
        .build()
        .unwrap();
    let mut sim = small_field();
    let id = sim.add_body(body);
    run(&mut sim, 10);
    let displaced = |sim: &Simulation| {
        sim.class
            .iter()
            .filter(|c| **c != BladeClass::Untouched)
            .count()
    };
    assert_eq!(
        displaced(&sim),
        0,
        "the boot at rest (y = 0.7..1.3) clears the grass"
    );
    let lowered = Pose::at_rest(Vec3::new(0.5, -0.8, 0.0));
    sim.set_part_pose(id, PartRef::Name("boot"), Some(lowered))
        .unwrap();
    run(&mut sim, 10);
    let boot = sim.body(id).unwrap().parts[0].pose.position;
    assert!(
        (boot - Vec3::new(0.5, 0.2, 0.0)).length() < 1e-5,
        "boot at {boot}"
    );
    assert!(displaced(&sim) > 20, "the lowered boot presses the grass");
    // The same part by index, back to rest; the weight (fixed) did not move.
    sim.set_part_pose(id, PartRef::Index(0), None).unwrap();
    run(&mut sim, 1);
    let body = sim.body(id).unwrap();
    assert!((body.parts[0].pose.position - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-5);
    assert_eq!(body.parts[1].pose.rotation, Quat::IDENTITY);
    // A zero rotation names none: refused, the boot stays at rest.
    let zero = Pose {
        rotation: Quat::from_xyzw(0.0, 0.0, 0.0, 0.0),
        ..lowered
    };
    let e = sim
        .set_part_pose(id, PartRef::Name("boot"), Some(zero))
        .unwrap_err();
    assert!(
        matches!(&e, BodyError::NotFinite { .. }) && e.to_string().contains("rotation not zero"),
        "{e}"
    );
    run(&mut sim, 1);
    assert!(
        (sim.body(id).unwrap().parts[0].pose.position - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-5
    );
    for (part, problem) in [
        (PartRef::Name("arm"), "no such part"),
        (PartRef::Index(2), "no such part"),
        (PartRef::Name("weight"), "its joint is not a host joint"),
    ] {
        let e = sim.set_part_pose(id, part, Some(lowered)).unwrap_err();
        assert!(
            matches!(&e, BodyError::Part { problem: p, allowed, .. } if *p == problem && allowed.contains("\"boot\"")),
            "{e}"
        );
    }
}

/// A skinned body built in code ([`BodyBuilder::animation`]) plays its
/// animation: its mesh and refitted tree move with time, the tree stays
/// well formed, and a missing animation is refused naming the file.
#[test]
fn a_skinned_body_built_in_code_plays_its_animation() {
    use trample::builder::BodyBuilder;
    use trample::object::{Anchor, ShapeParams};
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
    let walker = BodyBuilder::new(
        "walker",
        ShapeParams::Mesh {
            path: "walker.glb".into(),
            anchor: Anchor::File,
        },
    );
    let mut body = walker
        .clone()
        .animation("walk", 1.0)
        .build_in(0, &meshes)
        .unwrap();
    let bind = body.object.mesh.positions.clone();
    body.set_time(0.25);
    body.tree.assert_well_formed();
    let moved = body
        .object
        .mesh
        .positions
        .iter()
        .zip(&bind)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0f32, f32::max);
    assert!(
        moved > 0.05,
        "a quarter of the walk moves the mesh ({moved} m)"
    );
    let root = body.tree.nodes[0].obb;
    for p in &body.object.mesh.positions {
        let q = root.to_box(*p).abs();
        assert!(q.cmple(root.half + 1e-4).all(), "root box misses {p}");
    }
    let e = walker
        .animation("run", 1.0)
        .build_in(0, &meshes)
        .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("walker.glb") && text.contains("\"run\"") && text.contains("\"walk\""),
        "{text}"
    );
}

/// A walker whose animation clock runs with its ground speed
/// (`animation.ground_speed_mps`, issue 13 item 6: driven, it strides at
/// the speed it is driven): standing, its mesh stays in the first pose;
/// driven at the cycle's ground speed for 0.25 s its clock reads 0.25 s, at
/// twice that speed for 0.25 s more, 0.75 s. Without the key the clock is
/// time (it walks on the spot while standing).
#[test]
fn a_driven_walker_strides_at_the_speed_it_is_driven() {
    use glam::Quat;
    use trample::builder::BodyBuilder;
    use trample::object::{Anchor, AnimatedScratch, ShapeParams};
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
    let walker = |ground: Option<f32>| {
        let b = BodyBuilder::new(
            "walker",
            ShapeParams::Mesh {
                path: "walker.glb".into(),
                anchor: Anchor::File,
            },
        )
        .animation("walk", 1.0);
        let b = match ground {
            Some(g) => b.animation_ground_speed(g),
            None => b,
        };
        b.build_in(0, &meshes).unwrap()
    };
    // How far the walker's mesh is from the walk's pose at `clock`.
    let off = |sim: &Simulation, clock: f32| {
        let body = &sim.bodies[0];
        let animated = body.object.animated.as_ref().unwrap();
        let mut out = Vec::new();
        animated.pose_at_clock(clock, &mut AnimatedScratch::default(), &mut out);
        out.iter()
            .zip(&body.object.mesh.positions)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0f32, f32::max)
    };
    let ground = 1.4;
    for matched in [true, false] {
        let mut sim = small_field();
        let dt = sim.params.dt_s;
        let id = sim.add_body(walker(matched.then_some(ground)));
        let mut p = Vec3::ZERO;
        let mut drive = |sim: &mut Simulation, speed: f32, seconds: f32| {
            for _ in 0..(seconds / dt).round() as u32 {
                p += Vec3::Z * speed * dt;
                sim.move_body(id, p, Quat::IDENTITY, dt).unwrap();
                sim.step(dt).unwrap();
            }
        };
        drive(&mut sim, 0.0, 0.25);
        if matched {
            assert!(off(&sim, 0.0) < 1e-4, "standing: {}", off(&sim, 0.0));
            drive(&mut sim, ground, 0.25);
            assert!(off(&sim, 0.25) < 1e-3, "at 1.4 m/s: {}", off(&sim, 0.25));
            drive(&mut sim, 2.0 * ground, 0.25);
            assert!(off(&sim, 0.75) < 1e-3, "at 2.8 m/s: {}", off(&sim, 0.75));
            sim.bodies[0].tree.assert_well_formed();
        } else {
            // The clock is time: a quarter of the walk, standing.
            assert!(off(&sim, 0.25) < 1e-4, "{}", off(&sim, 0.25));
            assert!(off(&sim, 0.0) > 0.05, "{}", off(&sim, 0.0));
        }
    }
}

/// Eq. 2's contact speed on a skinned mesh is the limb's own (issue 13:
/// "the contact speed of Eq. 2 comes from the part's own motion"): the
/// refitted tree carries each node's deformation velocity
/// (`ObbTree::node_velocity`), which the narrow phase adds to the body's
/// rigid motion. Walking in a straight line at the cycle's ground speed
/// (1.4 m/s), the lowest final-depth box (a foot) is nearly at rest while
/// it is planted and moves at about twice the body's speed while it swings;
/// with the root's velocity alone it would always move at 1.4 m/s.
#[test]
fn a_planted_foot_is_at_rest_and_a_swinging_one_outruns_the_body() {
    use trample::builder::BodyBuilder;
    use trample::object::{Anchor, Orientation, PathParams, ShapeParams};
    let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
    let precision = 5;
    let mut body = BodyBuilder::new(
        "walker",
        ShapeParams::Mesh {
            path: "walker.glb".into(),
            anchor: Anchor::File,
        },
    )
    .animation("walk", 1.0)
    .animation_ground_speed(1.4)
    .orientation(Orientation::FaceMotion)
    .path(PathParams::Line {
        from: [0.0, 0.0, -5.0],
        to: [0.0, 0.0, 9.0],
        duration_s: 10.0,
    })
    .build_in(0, &meshes)
    .unwrap();
    let (mut slowest, mut fastest) = (f32::INFINITY, 0.0f32);
    let dt = 1.0 / 120.0;
    for k in 0..=240 {
        body.set_time(1.0 + k as f32 * dt);
        let tree = &body.tree;
        let pose = body.pose;
        // The final-depth boxes near the ground: the feet.
        for (i, n) in tree.nodes.iter().enumerate() {
            let last = n.depth == precision || (n.is_leaf() && n.depth < precision);
            let centre = pose.to_world(n.obb.center);
            if !last || centre.y > 0.2 {
                continue;
            }
            let v = pose.point_velocity(centre) + pose.rotation * tree.node_velocity(i as u32);
            let horizontal = glam::Vec2::new(v.x, v.z).length();
            slowest = slowest.min(horizontal);
            fastest = fastest.max(horizontal);
        }
    }
    eprintln!("foot boxes: {slowest:.2} .. {fastest:.2} m/s (body 1.40 m/s)");
    assert!(slowest < 0.5, "a planted foot moves at {slowest} m/s");
    assert!(fastest > 2.0, "a swinging foot moves at only {fastest} m/s");
}

/// Two walkers on the same glTF: the scene builds one tree for both (issue
/// 16: one build per distinct mesh, shared), and each refits its own copy
/// to its own pose as it animates (from its first pose on), so neither
/// bends the other's collision: their trees are apart, each holds its own
/// posed mesh, and they differ (the second walker's clock runs at half
/// speed).
#[test]
fn two_walkers_on_one_mesh_each_refit_their_own_tree() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/walker.toml"),
    )
    .unwrap();
    let second = text[text.find("[[objects]]").unwrap()..]
        .replace("name = \"walker\"", "name = \"walker2\"")
        .replace("speed = 1.0, ground_speed_mps = 1.4", "speed = 0.5")
        .replace(
            "period_s = 18.0 }",
            "period_s = 18.0, phase_rad = 3.14159 }",
        );
    assert!(second.contains("speed = 0.5") && second.contains("walker2"));
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut sim = Scene::parse(&format!("{text}\n{second}"), "two_walkers.toml", &scenes)
        .unwrap()
        .build()
        .unwrap();
    assert_eq!(sim.bodies.len(), 2);
    run(&mut sim, 10);
    let [a, b] = [&sim.bodies[0], &sim.bodies[1]];
    assert!(
        !std::sync::Arc::ptr_eq(&a.tree, &b.tree),
        "each walker refits its own tree"
    );
    for body in [a, b] {
        body.tree.assert_well_formed();
        // The tree's triangles are the body's own posed mesh.
        let mesh = &body.object.mesh;
        let key = |t: [glam::Vec3; 3]| t.map(|p| p.to_array().map(f32::to_bits));
        let mut own: Vec<_> = mesh
            .indices
            .iter()
            .map(|t| key(t.map(|i| mesh.positions[i as usize])))
            .collect();
        let mut tree: Vec<_> = body.tree.triangles.iter().map(|t| key(*t)).collect();
        own.sort_unstable();
        tree.sort_unstable();
        assert!(
            own == tree,
            "{}: the tree holds its own pose",
            body.object.name
        );
    }
    assert!(
        a.tree.triangles != b.tree.triangles,
        "the walkers are at different phases of their walk"
    );
}
