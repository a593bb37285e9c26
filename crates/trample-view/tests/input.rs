//! Scripted key sequences through the viewer's window-free state ([`App`]):
//! the arrows drive the first object, keys change parameters, pause and
//! step, switch cameras, reset the field and restart paths. No window, no GPU.

use glam::Vec3;
use trample::scene::Scene;
use trample_view::App;
use trample_view::camera::CameraMode;
use trample_view::input::Key;

const SCENE: &str = r#"
[field]
patches = [4, 4]
cells_per_patch = 16
[sim]
precision = 3
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5, subdivisions = 2 }
orientation = "rolling"
path = { kind = "line", from = [-2.0, 0.5, 0.0], to = [2.0, 0.5, 0.0], duration_s = 4.0 }
"#;

fn app() -> App {
    let scene = Scene::parse(SCENE, "test", std::path::Path::new(".")).unwrap();
    App::new(scene).unwrap()
}

/// `frames` frames of 1/60 s with `keys` held down, then released.
fn hold(app: &mut App, keys: &[Key], frames: usize) {
    for &k in keys {
        app.key(k, true, false);
    }
    for _ in 0..frames {
        app.update(1.0 / 60.0).unwrap();
    }
    for &k in keys {
        app.key(k, false, false);
    }
}

#[test]
fn arrow_up_drives_the_ball_forward_and_left_turns_it() {
    let mut app = app();
    let start = app.sim().bodies[0].pose.position;
    // The line path goes along +x: driving starts facing +x.
    hold(&mut app, &[Key::ArrowUp], 60);
    assert!(app.driving, "an arrow key starts driving");
    let after = app.sim().bodies[0].pose.position;
    let moved = after - start;
    // 1 s at 4 m/s² from rest: v = 4 m/s, about 2 m (steps are discrete).
    assert!((moved.x - 2.0).abs() < 0.15, "moved {moved}");
    assert!(
        moved.z.abs() < 1e-4 && (moved.y).abs() < 1e-5,
        "moved {moved}"
    );
    assert!(
        (app.driver.speed - 4.0).abs() < 1e-3,
        "{}",
        app.driver.speed
    );
    // The simulation saw the driven velocity (Eq. 2 scales forces by it).
    assert!(app.sim().bodies[0].pose.velocity.x > 3.5);
    // The ball bent grass on its way.
    assert!(app.sim().blades_away_from_rest() > 0);

    // Up + left: heading turns counter-clockwise seen from above (+x → −z).
    let heading = app.driver.heading;
    hold(&mut app, &[Key::ArrowUp, Key::ArrowLeft], 30);
    assert!(app.driver.heading > heading + 0.5, "{}", app.driver.heading);
    assert!(app.sim().bodies[0].pose.position.z < after.z);

    // Nothing held: the ball coasts to a stop and stays.
    hold(&mut app, &[], 180);
    assert_eq!(app.driver.speed, 0.0);
    let stopped = app.sim().bodies[0].pose.position;
    hold(&mut app, &[], 5);
    assert_eq!(app.sim().bodies[0].pose.position, stopped);

    // G: back to the path (t = 4.5 s: past the end of the 4 s line).
    app.key(Key::G, true, false);
    assert!(!app.driving);
    assert_eq!(app.sim().bodies[0].pose.position, Vec3::new(2.0, 0.5, 0.0));
}

#[test]
fn keys_change_precision_within_range() {
    let mut app = app();
    assert_eq!(app.sim().params.precision, 3);
    app.key(Key::BracketRight, true, false);
    app.key(Key::BracketRight, false, false);
    app.key(Key::BracketRight, true, false);
    // An auto-repeat of a held key does not act again.
    app.key(Key::BracketRight, true, true);
    app.key(Key::BracketRight, false, false);
    assert_eq!(app.sim().params.precision, 5);
    for _ in 0..20 {
        app.key(Key::BracketLeft, true, false);
        app.key(Key::BracketLeft, false, false);
    }
    assert_eq!(app.sim().params.precision, 1);
    for _ in 0..20 {
        app.key(Key::BracketRight, true, false);
    }
    assert_eq!(app.sim().params.precision, 10);
    // The step runs with it.
    app.update(1.0 / 60.0).unwrap();
}

#[test]
fn pause_single_step_and_restart() {
    let mut app = app();
    hold(&mut app, &[], 30);
    assert_eq!(app.sim().frame, 30);
    app.key(Key::Space, true, false);
    hold(&mut app, &[], 10);
    assert_eq!(app.sim().frame, 30, "paused");
    app.key(Key::N, true, false);
    hold(&mut app, &[], 10);
    assert_eq!(app.sim().frame, 31, "one step");
    app.key(Key::Space, true, false);
    hold(&mut app, &[], 1);
    assert_eq!(app.sim().frame, 32);

    // T: the ball starts its path again from where the path starts.
    let x_before = app.sim().bodies[0].pose.position.x;
    assert!(x_before > -2.0 + 0.4);
    app.key(Key::T, true, false);
    assert_eq!(app.sim().bodies[0].pose.position, Vec3::new(-2.0, 0.5, 0.0));
    let bent = app.sim().blades_away_from_rest();
    assert!(bent > 0, "the field is kept");
}

#[test]
fn cameras_cycle_and_free_fly_moves_with_wasd() {
    let mut app = app();
    assert_eq!(app.camera_mode, CameraMode::Orbit);
    // Orbit: the eye is at the orbit distance from the ball.
    app.update(1.0 / 60.0).unwrap();
    let d = app.sim().eye().distance(app.sim().bodies[0].pose.position);
    assert!((d - app.orbit.distance).abs() < 0.2, "{d}");
    app.key(Key::C, true, false);
    assert_eq!(app.camera_mode, CameraMode::Fly);
    let eye = app.fly.eye;
    let forward = app.fly.forward();
    hold(&mut app, &[Key::W], 30);
    let moved = app.fly.eye - eye;
    assert!(moved.dot(forward) > 2.0, "{moved}");
    assert!((app.sim().eye() - app.fly.eye).length() < 1e-4);
    app.key(Key::C, true, false);
    assert_eq!(app.camera_mode, CameraMode::Scene);
    app.key(Key::C, true, false);
    assert_eq!(app.camera_mode, CameraMode::Orbit);
}

#[test]
fn reset_applies_the_pending_blade_density() {
    let mut app = app();
    let blades = app.sim().field.blades.count;
    hold(&mut app, &[], 20);
    app.pending.blades_per_cell = 2;
    app.sim_mut().params.att = 0.25;
    app.key(Key::R, true, false);
    assert_eq!(app.field_version, 1);
    assert_eq!(app.sim().field.blades.count, 2 * blades);
    assert_eq!(app.sim().frame, 0);
    assert_eq!(
        app.sim().params.att,
        0.25,
        "live parameters survive a reset"
    );
    // A bad mesh path keeps the running field and says why.
    app.pending.shape = trample_view::app::ShapeChoice::MeshFile;
    app.pending.mesh_path = "../outside.obj".into();
    app.key(Key::R, false, false);
    app.key(Key::R, true, false);
    assert_eq!(app.field_version, 1);
    assert!(app.message.starts_with("reset failed"), "{}", app.message);
}
