//! What the window hands the app besides keys, without a window: a resize
//! (the picture's aspect, which the camera culls with) and a mesh file
//! chosen in the panel as the first object's shape. CPU path, no GPU.

use std::path::Path;
use trample::scene::Scene;
use trample_view::App;
use trample_view::app::ShapeChoice;
use trample_view::input::Key;

const SCENE: &str = r#"
[field]
patches = [4, 4]
cells_per_patch = 16
[sim]
precision = 4
[[objects]]
name = "car"
shape = { kind = "sphere", radius_m = 0.5, subdivisions = 2 }
scale = 2.0
path = { kind = "line", from = [-2.0, 0.3, 0.0], to = [2.0, 0.3, 0.0], duration_s = 4.0 }
"#;

/// The project's copies of the shared meshes: `scenes/meshes/`.
fn scenes_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn app() -> App {
    App::new(Scene::parse(SCENE, "test", &scenes_dir()).unwrap()).unwrap()
}

/// The patches inside the view frustum after a frame.
fn visible(app: &mut App) -> Vec<bool> {
    app.update(1.0 / 60.0).unwrap();
    app.sim().visible.clone()
}

#[test]
fn a_resize_reaches_the_camera_and_a_wider_picture_sees_more() {
    let mut app = app();
    app.key(Key::Space, true, false); // paused: the view follows anyway
    app.set_aspect(0.5);
    let narrow = visible(&mut app);
    assert_eq!(app.sim().camera.params.aspect, 0.5);
    app.set_aspect(3.0);
    let wide = visible(&mut app);
    assert_eq!(app.sim().camera.params.aspect, 3.0);
    assert_eq!(app.sim().frame, 0, "paused");
    let count = |v: &[bool]| v.iter().filter(|&&v| v).count();
    assert!(
        count(&wide) > count(&narrow),
        "{} vs {}",
        count(&wide),
        count(&narrow)
    );
    for (n, w) in narrow.iter().zip(&wide) {
        assert!(!n || *w, "a patch seen narrow is seen wide");
    }
    assert_eq!(
        app.sim().timings.visible_patches as usize,
        count(&wide),
        "the stats count what is culled"
    );
    // A minimised window (0 high), or garbage, keeps the last aspect.
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        app.set_aspect(bad);
        app.update(1.0 / 60.0).unwrap();
        assert_eq!(app.sim().camera.params.aspect, 3.0, "{bad}");
    }
}

#[test]
fn a_mesh_file_becomes_the_first_object_at_the_next_reset() {
    let mut app = app();
    app.pending.shape = ShapeChoice::MeshFile;
    app.pending.mesh_path = "meshes/beetle.obj".into();
    // Pending: nothing changes before the reset.
    app.update(1.0 / 60.0).unwrap();
    assert_ne!(app.sim().bodies[0].object.mesh.triangle_count(), 2053);
    app.key(Key::R, true, false);
    assert_eq!(app.field_version, 1, "{}", app.message);
    assert!(app.message.starts_with("field reset"), "{}", app.message);
    let mesh = &app.sim().bodies[0].object.mesh;
    assert_eq!(mesh.triangle_count(), 2053, "the beetle's triangles");
    // Scaled by the scene's 2 and centred: about 1.8 m long along z.
    let (lo, hi) = mesh.bounds().unwrap();
    assert!((hi.z - lo.z - 1.78).abs() < 0.03, "{lo} {hi}");
    assert!(((hi + lo) * 0.5).length() < 1e-3, "centred: {lo} {hi}");
    // It drives and bends the grass like any shape.
    app.key(Key::ArrowUp, true, false);
    for _ in 0..30 {
        app.update(1.0 / 60.0).unwrap();
    }
    assert!(app.sim().blades_away_from_rest() > 0);

    // Missing, outside the scene's folder, not a mesh: the running field
    // stays and the panel says why, naming the file.
    for (path, says) in [
        ("meshes/nowhere.obj", "nowhere.obj"),
        ("../Cargo.toml", "Cargo.toml"),
        ("default.toml", "default.toml"),
        ("", "mesh"),
    ] {
        app.pending.mesh_path = path.into();
        app.act(trample_view::input::Action::ResetField);
        assert_eq!(app.field_version, 1, "{path}");
        assert!(
            app.message.starts_with("reset failed") && app.message.contains(says),
            "{path}: {}",
            app.message
        );
        assert_eq!(app.sim().bodies[0].object.mesh.triangle_count(), 2053);
    }
}
