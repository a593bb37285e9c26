//! The plugin in a headless Bevy `App` (no window, no renderer), issue 17's
//! "Tests that must exist": a `Trampler` with a sphere mesh moved by a
//! system across the field bends the blades on its path and not elsewhere;
//! removing the component removes the body; a changed mesh asset rebuilds
//! its tree. And a transform the core cannot pose a body with leaves the
//! body where it was, says so on the entity, and the game goes on. The
//! ground shows the track (its texture redrawn from the cells the steps
//! changed), and another field gets a ground of its own. A field that
//! asks for it steps the tramplers out of the camera's view in turns.

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_trample::{
    TrampleCamera, TrampleField, TramplePlugin, TrampleSystems, Trampler, TramplerBody,
    TramplerPoseRefused,
};
use std::time::Duration;
use trample::builder::SimulationBuilder;
use trample::field::{FieldParams, LodParams};
use trample::step::SimParams;

/// Frame and fixed step: 1/60 s, so each `update` runs one simulation step.
const DT: f64 = 1.0 / 60.0;
/// The sphere: radius (m), height of its centre (m; grass is about 0.45 m
/// tall), speed along +x (m/s), start and end x (m), on the line z = 0.
const RADIUS: f32 = 0.3;
const CENTRE_Y: f32 = 0.25;
const SPEED: f32 = 4.0;
const START_X: f32 = -4.0;
const END_X: f32 = 4.0;

/// 12.8 × 12.8 m of grass (8 × 8 patches of 16 × 16 cells of 0.1 m, one
/// blade a cell), the paper's lasting track (`recovery_s = inf`).
fn field() -> TrampleField {
    field_with(SimParams {
        recovery_s: f32::INFINITY,
        ..SimParams::default()
    })
}

/// [`field`] with other `[sim]` values.
fn field_with(sim: SimParams) -> TrampleField {
    let builder = SimulationBuilder::new()
        .field(FieldParams {
            patches: [8, 8],
            cells_per_patch: 16,
            ..FieldParams::default()
        })
        .lod(LodParams {
            geometry_m: 30.0,
            billboard_m: 40.0,
        })
        .sim(sim);
    TrampleField::from_builder(&builder).expect("test field")
}

#[derive(Component)]
struct Mover;

/// Moves the sphere along +x at `SPEED` in the fixed timestep, before the
/// simulation step, and stops it at `END_X`.
fn drive(time: Res<Time>, mut movers: Query<&mut Transform, With<Mover>>) {
    for mut t in &mut movers {
        t.translation.x = (t.translation.x + SPEED * time.delta_secs()).min(END_X);
    }
}

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin::default(),
        TransformPlugin,
        TramplePlugin,
    ))
    .init_asset::<Mesh>()
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        DT,
    )))
    .insert_resource(Time::<Fixed>::from_seconds(DT))
    .insert_resource(field())
    .add_systems(FixedUpdate, drive.before(TrampleSystems::Step));
    app
}

fn spawn_sphere(app: &mut App, radius: f32) -> (Entity, Handle<Mesh>) {
    let mesh = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .add(Sphere::new(radius).mesh().ico(3).expect("icosphere"));
    let entity = app
        .world_mut()
        .spawn((
            Mesh3d(mesh.clone()),
            Transform::from_xyz(START_X, CENTRE_Y, 0.0),
            Trampler::default(),
            Mover,
        ))
        .id();
    (entity, mesh)
}

/// How far blade `b`'s tip is below its rest tip, metres.
fn lowering(field: &TrampleField, b: usize) -> f32 {
    field.sim.field.blades.tip_lowering(b)
}

#[test]
fn a_moving_sphere_bends_the_blades_on_its_path_and_not_elsewhere() {
    let mut app = app();
    let (entity, _) = spawn_sphere(&mut app, RADIUS);
    // Long enough for the sphere to cross from START_X to END_X.
    let frames = ((END_X - START_X) / SPEED / DT as f32).ceil() as usize + 10;
    for _ in 0..frames {
        app.update();
    }
    let body = app.world().get::<TramplerBody>(entity).expect("a body");
    let field = app.world().resource::<TrampleField>();
    assert_eq!(field.tramplers(), 1);
    let at = field
        .sim
        .body(body.id)
        .expect("in the simulation")
        .pose
        .position;
    assert!(
        (at.x - END_X).abs() < 1e-3,
        "the body followed its entity: {at}"
    );

    let bl = &field.sim.field.blades;
    let (mut on_path, mut bent_on_path, mut away, mut bent_away) = (0, 0, 0, 0);
    for b in 0..bl.count {
        let root = bl.rest_vertex(b, 0);
        // Well inside the swept band (the sphere is 0.3 m in radius and
        // about 0.5 m wide where it meets the grass), away from its ends.
        if root.z.abs() < 0.1 && root.x > START_X + 0.5 && root.x < END_X - 0.5 {
            on_path += 1;
            bent_on_path += usize::from(lowering(field, b) > 0.05);
        }
        // Farther than 1.5 m from the swept segment.
        let dx = (root.x - root.x.clamp(START_X, END_X)).abs();
        if dx.hypot(root.z) > 1.5 {
            away += 1;
            bent_away += usize::from(!bl.is_at_rest(b));
        }
    }
    assert!(on_path > 100, "{on_path} blades on the path");
    assert!(
        bent_on_path * 10 >= on_path * 9,
        "{bent_on_path} of {on_path} blades on the path bent by more than 5 cm"
    );
    assert!(away > 5000, "{away} blades away from the path");
    assert_eq!(bent_away, 0, "blades away from the path moved");
}

#[test]
fn removing_the_component_removes_the_body() {
    let mut app = app();
    let (entity, _) = spawn_sphere(&mut app, RADIUS);
    for _ in 0..30 {
        app.update();
    }
    let id = app.world().get::<TramplerBody>(entity).expect("a body").id;
    assert!(
        app.world()
            .resource::<TrampleField>()
            .sim
            .body(id)
            .is_some()
    );
    app.world_mut().entity_mut(entity).remove::<Trampler>();
    app.update();
    let field = app.world().resource::<TrampleField>();
    assert!(field.sim.body(id).is_none(), "body {id} still simulated");
    assert!(field.sim.bodies.is_empty());
    assert_eq!(field.tramplers(), 0);
    assert!(app.world().get::<TramplerBody>(entity).is_none());

    // The entity keeps moving through the grass without bending it any more.
    let before: Vec<_> = field.sim.field.blades.pos.clone();
    for _ in 0..30 {
        app.update();
    }
    let field = app.world().resource::<TrampleField>();
    let x = app.world().get::<Transform>(entity).unwrap().translation.x;
    assert!(x > START_X + 1.5, "the entity moved on (x = {x})");
    let bl = &field.sim.field.blades;
    // With the paper's lasting track, blades ahead of where the body was
    // removed are exactly as they were.
    let ahead = (0..bl.count)
        .filter(|&b| {
            let r = bl.rest_vertex(b, 0);
            r.z.abs() < 0.1 && r.x > START_X + 1.0 && r.x < x
        })
        .filter(|&b| {
            (0..=bl.segments).any(|k| bl.pos[k * bl.count + b] != before[k * bl.count + b])
        })
        .count();
    assert_eq!(ahead, 0, "blades moved after the body was removed");

    // Despawning an entity with a body removes its body too.
    app.world_mut()
        .entity_mut(entity)
        .insert(Trampler::default());
    app.update();
    assert_eq!(app.world().resource::<TrampleField>().sim.bodies.len(), 1);
    app.world_mut().despawn(entity);
    app.update();
    let field = app.world().resource::<TrampleField>();
    assert!(field.sim.bodies.is_empty() && field.tramplers() == 0);
}

#[test]
fn a_changed_mesh_asset_rebuilds_the_tree() {
    let mut app = app();
    let (entity, mesh) = spawn_sphere(&mut app, RADIUS);
    app.update();
    let extent = |app: &App| {
        let body = app.world().get::<TramplerBody>(entity).expect("a body");
        let field = app.world().resource::<TrampleField>();
        let b = field.sim.body(body.id).expect("in the simulation");
        let (lo, hi) = b.object.mesh.bounds().expect("a mesh");
        (body.id, hi.x - lo.x)
    };
    let (first_id, width) = extent(&app);
    assert!((width - 2.0 * RADIUS).abs() < 0.01, "width {width}");

    // The game swaps the asset's data for a sphere twice as large.
    let bigger = Sphere::new(2.0 * RADIUS).mesh().ico(3).expect("icosphere");
    let _ = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .insert(&mesh, bigger);
    app.update();
    let (id, width) = extent(&app);
    assert_ne!(id, first_id, "the body was rebuilt");
    assert!(
        (width - 4.0 * RADIUS).abs() < 0.02,
        "width {width} after the change"
    );
    let field = app.world().resource::<TrampleField>();
    assert_eq!(
        field.sim.bodies.len(),
        1,
        "the old body was replaced, not kept"
    );

    // A mesh the core refuses leaves an error on the entity, not a panic.
    let empty = Mesh::new(
        bevy::mesh::PrimitiveTopology::TriangleList,
        bevy::asset::RenderAssetUsages::default(),
    );
    let _ = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .insert(&mesh, empty);
    app.update();
    assert!(
        app.world()
            .get::<bevy_trample::TramplerError>(entity)
            .is_some()
    );
    assert!(app.world().resource::<TrampleField>().sim.bodies.is_empty());
}

#[test]
fn a_transform_that_cannot_pose_the_body_leaves_it_where_it_was() {
    let mut app = app();
    let (entity, _) = spawn_sphere(&mut app, RADIUS);
    for _ in 0..10 {
        app.update();
    }
    let id = app.world().get::<TramplerBody>(entity).expect("a body").id;
    let position = |app: &App| {
        let field = app.world().resource::<TrampleField>();
        field.sim.body(id).expect("still simulated").pose.position
    };
    let before = position(&app);
    assert!(app.world().get::<TramplerPoseRefused>(entity).is_none());

    // A NaN rotation (a zero scale is a changed scale: the body is
    // rebuilt, and a `TramplerError` says why it cannot be).
    app.world_mut()
        .get_mut::<Transform>(entity)
        .unwrap()
        .rotation = Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0);
    for _ in 0..5 {
        app.update();
    }
    let refused = app
        .world()
        .get::<TramplerPoseRefused>(entity)
        .expect("the refusal is on the entity");
    assert!(refused.0.contains("must be finite"), "{}", refused.0);
    assert_eq!(position(&app), before, "the body moved on a refused pose");
    assert_eq!(app.world().resource::<TrampleField>().tramplers(), 1);

    // A NaN position: the same.
    {
        let mut t = app.world_mut().get_mut::<Transform>(entity).unwrap();
        t.rotation = Quat::IDENTITY;
        t.translation.y = f32::NAN;
    }
    app.update();
    assert_eq!(position(&app), before);
    assert!(app.world().get::<TramplerPoseRefused>(entity).is_some());

    // A pose it can take again: the body follows, the refusal goes.
    app.world_mut()
        .get_mut::<Transform>(entity)
        .unwrap()
        .translation
        .y = CENTRE_Y;
    app.update();
    let x = app.world().get::<Transform>(entity).unwrap().translation.x;
    assert!(app.world().get::<TramplerPoseRefused>(entity).is_none());
    assert!(
        (position(&app).x - x).abs() < 1e-4,
        "the body follows its entity again: {} against {x}",
        position(&app)
    );
}

/// A skinned trampler (a `SkinnedMesh` with one joint): the joint moves
/// across the field while the trampler's own entity stays where it was
/// spawned, as a character's root may while its skeleton walks. The grass
/// is trampled where the skin puts the mesh — along the joint's path — not
/// at the entity's place alone.
#[test]
fn a_skinned_mesh_tramples_where_its_joints_put_it() {
    use bevy::mesh::VertexAttributeValues;
    use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
    let mut app = app();
    app.init_asset::<SkinnedMeshInverseBindposes>();
    // The mesh around its joint's bind place (the origin), all on joint 0.
    let mut mesh = Sphere::new(RADIUS).mesh().ico(3).expect("icosphere");
    let n = mesh.count_vertices();
    mesh.insert_attribute(
        Mesh::ATTRIBUTE_JOINT_INDEX,
        VertexAttributeValues::Uint16x4(vec![[0, 0, 0, 0]; n]),
    );
    mesh.insert_attribute(
        Mesh::ATTRIBUTE_JOINT_WEIGHT,
        vec![[1.0f32, 0.0, 0.0, 0.0]; n],
    );
    let world = app.world_mut();
    let mesh = world.resource_mut::<Assets<Mesh>>().add(mesh);
    let bindposes = world
        .resource_mut::<Assets<SkinnedMeshInverseBindposes>>()
        .add(SkinnedMeshInverseBindposes::from(vec![Mat4::IDENTITY]));
    // The joint moves along +x (the `Mover` system); the trampler stays.
    let joint = world
        .spawn((Transform::from_xyz(START_X, CENTRE_Y, 0.0), Mover))
        .id();
    let entity = world
        .spawn((
            Mesh3d(mesh),
            SkinnedMesh {
                inverse_bindposes: bindposes,
                joints: vec![joint],
            },
            Transform::from_xyz(START_X, CENTRE_Y, 0.0),
            Trampler::default(),
        ))
        .id();
    let frames = ((END_X - START_X) / SPEED / DT as f32).ceil() as usize + 10;
    for _ in 0..frames {
        app.update();
    }
    assert!(
        app.world()
            .get::<bevy_trample::TramplerSkinRefused>(entity)
            .is_none(),
        "{:?}",
        app.world().get::<bevy_trample::TramplerSkinRefused>(entity)
    );
    let body = app.world().get::<TramplerBody>(entity).expect("a body");
    let field = app.world().resource::<TrampleField>();
    let b = field.sim.body(body.id).expect("in the simulation");
    assert!(
        (b.pose.position.x - START_X).abs() < 1e-4,
        "the body stays with its entity: {}",
        b.pose.position
    );
    let bl = &field.sim.field.blades;
    let (mut on_path, mut bent) = (0, 0);
    for k in 0..bl.count {
        let root = bl.rest_vertex(k, 0);
        if root.z.abs() < 0.1 && root.x > START_X + 0.5 && root.x < END_X - 0.5 {
            on_path += 1;
            bent += usize::from(lowering(field, k) > 0.05);
        }
    }
    assert!(on_path > 100, "{on_path} blades on the path");
    assert!(
        bent * 10 >= on_path * 9,
        "{bent} of {on_path} blades on the joint's path bent by more than 5 cm"
    );
}

/// The ground's track texture (`render::ground`): after the sphere crossed
/// the field, the texels on its path are darker and those far from it
/// white, and the texture redrawn cell by cell as the steps went equals
/// one drawn from the cells at the end; another field gets a ground (and
/// a texture) of its own size.
#[cfg(feature = "render")]
#[test]
fn the_ground_shows_the_track_where_the_sphere_went_and_a_new_field_gets_a_new_ground() {
    use bevy_trample::render::ground::{
        GroundTrack, TrampleGround, spawn_ground, track_texels, update_ground_track,
    };
    let mut app = app();
    app.init_asset::<Image>()
        .init_asset::<StandardMaterial>()
        .add_systems(
            PostUpdate,
            (spawn_ground, update_ground_track.after(spawn_ground)),
        );
    spawn_sphere(&mut app, RADIUS);
    let frames = ((END_X - START_X) / SPEED / DT as f32).ceil() as usize + 10;
    for _ in 0..frames {
        app.update();
    }
    let world = app.world();
    let track = world.resource::<GroundTrack>();
    assert_eq!(track.texels, [128, 128]);
    let data = world
        .resource::<Assets<Image>>()
        .get(&track.image)
        .and_then(|i| i.data.clone())
        .expect("the track's texels");
    let field = world.resource::<TrampleField>();
    assert_eq!(data, track_texels(field, track.darkening));
    // Texel (tx, tz) is the cell at x = -6.4 + 0.1 (tx + 0.5), likewise z.
    let texel = |x: f32, z: f32| {
        let (tx, tz) = (((x + 6.4) / 0.1) as usize, ((z + 6.4) / 0.1) as usize);
        data[(tz * 128 + tx) * 4]
    };
    let on_path: Vec<u8> = (-30..=30).map(|i| texel(i as f32 * 0.1, 0.0)).collect();
    let dark = on_path.iter().filter(|&&r| r < 230).count();
    assert!(
        dark * 10 >= on_path.len() * 9,
        "texels on the path: {on_path:?}"
    );
    assert_eq!(texel(0.0, 3.0), 255, "far from the path");
    assert_eq!(texel(-5.5, -5.5), 255, "far from the path");

    // Another field, a quarter the cells: a new ground, a new texture.
    let small = TrampleField::from_builder(&SimulationBuilder::new().field(FieldParams {
        patches: [4, 4],
        cells_per_patch: 16,
        ..FieldParams::default()
    }))
    .expect("small field");
    app.insert_resource(small);
    app.update();
    app.update();
    let world = app.world_mut();
    let grounds = world
        .query_filtered::<Entity, With<TrampleGround>>()
        .iter(world)
        .count();
    assert_eq!(grounds, 1, "one ground");
    let track = world.resource::<GroundTrack>();
    assert_eq!(track.texels, [64, 64]);
    let image = world
        .resource::<Assets<Image>>()
        .get(&track.image)
        .expect("the new texture");
    assert_eq!(image.width(), 64);
    assert!(
        image
            .data
            .as_ref()
            .is_some_and(|d| d.iter().all(|&v| v == 255)),
        "nothing trampled on the new field"
    );
}

/// Tramplers out of the `TrampleCamera`'s view take turns when the field
/// asks (`far_every = 4`, `far_outside_view`): the sphere rolling behind
/// the camera, within a few metres of it, steps on one frame in four; when
/// the camera turns onto it, it catches up in that step and steps every
/// frame after.
#[test]
fn a_trampler_behind_the_camera_takes_turns_when_asked() {
    let mut app = app();
    app.insert_resource(field_with(SimParams {
        recovery_s: f32::INFINITY,
        far_every: 4,
        far_outside_view: true,
        ..SimParams::default()
    }));
    let (entity, _) = spawn_sphere(&mut app, RADIUS);
    // The camera 3 m from the sphere's line, looking away from it.
    let camera = app
        .world_mut()
        .spawn((
            Camera3d::default(),
            Projection::default(),
            Transform::from_xyz(0.0, 2.0, 3.0).looking_at(Vec3::new(0.0, 0.0, 10.0), Vec3::Y),
            TrampleCamera,
        ))
        .id();
    let stepped = |app: &App| {
        let id = app.world().get::<TramplerBody>(entity).expect("a body").id;
        let field = app.world().resource::<TrampleField>();
        let body = field.sim.body(id).expect("in the simulation");
        body.stepped_to() == field.sim.time
    };
    let mut up_to_date = 0;
    for _ in 0..40 {
        app.update();
        up_to_date += usize::from(stepped(&app));
    }
    assert!(
        (9..=11).contains(&up_to_date),
        "out of view: up to date after {up_to_date} of 40 steps"
    );
    app.world_mut()
        .entity_mut(camera)
        .insert(Transform::from_xyz(0.0, 2.0, 3.0).looking_at(Vec3::ZERO, Vec3::Y));
    for step in 0..8 {
        app.update();
        assert!(stepped(&app), "in view: up to date after step {step}");
    }
}
