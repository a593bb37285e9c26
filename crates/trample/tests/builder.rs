//! A simulation from values (issue 14, item 1): the builder gives the same
//! simulation as the scene file that says the same, refuses bad values
//! with error values whose text is the scene path's message without the
//! file name, and takes what only code can say (a mesh of the host's own,
//! a terrain, a host view deciding LOD from the start).

use glam::{Quat, Vec3};
use trample::builder::{BodyBuilder, BuildError, SimulationBuilder};
use trample::field::{FieldParams, Lod, LodError, LodParams, Terrain};
use trample::object::{PathParams, TriMesh};
use trample::scene::Scene;
use trample::step::HostView;

const SCENE: &str = r#"
[field]
patches = [3, 3]
cells_per_patch = 16
terrain = { kind = "noise", amplitude_m = 0.3, wavelength_m = 3.0, seed = 4 }
[lod]
geometry_m = 100.0
billboard_m = 200.0
[sim]
precision = 5
recovery_s = 1.5
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "line", from = [-2.5, 0.6, 0.0], to = [2.5, 0.6, 0.0], duration_s = 1.0 }
"#;

#[test]
fn values_in_code_make_the_simulation_the_scene_file_makes() {
    let mut from_file = Scene::parse(SCENE, "s.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap();
    let mut from_code = SimulationBuilder::new()
        .field(FieldParams {
            patches: [3, 3],
            cells_per_patch: 16,
            terrain: trample::field::TerrainParams::Noise {
                amplitude_m: 0.3,
                wavelength_m: 3.0,
                seed: 4,
            },
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 100.0,
            billboard_m: 200.0,
        })
        .sim(trample::step::SimParams {
            precision: 5,
            recovery_s: 1.5,
            ..Default::default()
        })
        .body(
            BodyBuilder::sphere("ball", 0.4)
                .orientation(trample::object::Orientation::Rolling)
                .path(PathParams::Line {
                    from: [-2.5, 0.6, 0.0],
                    to: [2.5, 0.6, 0.0],
                    duration_s: 1.0,
                }),
        )
        .build()
        .unwrap();
    from_file.run(45).unwrap();
    from_code.run(45).unwrap();
    assert!(from_file.blades_away_from_rest() > 0);
    assert_eq!(from_file.blade_vertices(), from_code.blade_vertices());
    assert_eq!(from_file.class, from_code.class);
}

#[test]
fn bad_values_are_error_values_with_the_scene_messages() {
    let bad_lod = SimulationBuilder::new()
        .lod(LodParams {
            geometry_m: 20.0,
            billboard_m: 10.0,
        })
        .build()
        .unwrap_err();
    assert!(matches!(
        bad_lod,
        BuildError::Lod(LodError::Decreasing { .. })
    ));
    assert_eq!(
        bad_lod.to_string(),
        "lod.billboard_m = 10 is less than lod.geometry_m = 20: LOD distances must not decrease"
    );
    let too_big = SimulationBuilder::new()
        .field(FieldParams {
            patches: [512, 512],
            cells_per_patch: 32,
            ..FieldParams::default()
        })
        .validate()
        .unwrap_err();
    assert!(matches!(too_big, BuildError::Memory { .. }), "{too_big}");
    let twice = SimulationBuilder::new()
        .body(BodyBuilder::sphere("a", 0.3))
        .body(BodyBuilder::sphere("a", 0.3))
        .build()
        .unwrap_err();
    assert_eq!(
        twice.to_string(),
        "objects[1].name = \"a\": another object already has this name"
    );
    let bad_body = BodyBuilder::sphere("ball", -1.0).build().unwrap_err();
    assert_eq!(
        bad_body.to_string(),
        "objects[0] (ball): shape.radius_m = -1: must be a finite number > 0"
    );
    let nan_mesh = TriMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)],
        indices: vec![[0, 1, 2]],
    };
    assert!(BodyBuilder::mesh("m", &nan_mesh).build().is_err());
}

#[test]
fn code_can_say_more_a_host_mesh_a_terrain_and_a_host_view() {
    // A tetrahedron of the host's own, 0.8 m across, on a code terrain.
    let tetra = TriMesh {
        positions: vec![
            Vec3::new(-0.4, -0.3, -0.4),
            Vec3::new(0.4, -0.3, -0.4),
            Vec3::new(0.0, -0.3, 0.4),
            Vec3::new(0.0, 0.4, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]],
    };
    let eye = Vec3::new(-2.0, 1.0, -2.0);
    let mut sim = SimulationBuilder::new()
        .field(FieldParams {
            patches: [3, 3],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .terrain(Terrain::Flat(0.25))
        .lod(LodParams {
            geometry_m: 2.0,
            billboard_m: 3.0,
        })
        .host_view(HostView::look_at(eye, Vec3::ZERO, 1.0, 1.0, 0.1, 50.0).unwrap())
        .body(BodyBuilder::mesh("tetra", &tetra).at([-1.5, 0.55, -1.5]))
        .build()
        .unwrap();
    // Roots on the code terrain.
    assert_eq!(sim.field.blades.rest_vertex(7, 0).y, 0.25);
    // Levels of detail from the host's eye from the start, before a step.
    for c in 0..sim.field.layout.cell_count() {
        let want = sim.lod.level(sim.field.cells.base[c].distance(eye));
        assert_eq!(sim.field.cells.lod[c], want, "cell {c}");
    }
    assert!(sim.field.cells.lod.contains(&Lod::Geometry));
    // The host's mesh collides: moved through the grass, it bends blades.
    let id = sim.bodies[0].id;
    let dt = sim.params.dt_s;
    for i in 1..=30 {
        let p = Vec3::new(-1.5 + 0.05 * i as f32, 0.55, -1.5);
        sim.move_body(id, p, Quat::IDENTITY, dt).unwrap();
        sim.step(dt).unwrap();
    }
    assert!(sim.blades_away_from_rest() > 10);
    assert_eq!(sim.bodies[0].object.mesh.triangle_count(), 4);
    assert!(sim.bodies[0].object.closed);
}
