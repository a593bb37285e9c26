//! Driving a walker and a vehicle with the arrow keys (issue 13 item 6),
//! without a window: the app gets the keys as the window hands them over
//! and steps the scene on the CPU path. The walker of `scenes/walker.toml`
//! strides at the speed it is driven and stands still, its mesh unchanged,
//! once it has stopped (`animation.ground_speed_mps`); the tractor of
//! `scenes/tractor.toml` rolls its wheels at the driven speed (each wheel's
//! contact with the ground at rest, Eq. 2's contact speed there ~0) and
//! steers its front wheels when the arrows turn it.

use std::path::Path;
use trample::scene::Scene;
use trample_view::App;
use trample_view::input::Key;

fn app(name: &str) -> App {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    App::new(Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))).unwrap()
}

fn frames(app: &mut App, n: u32) {
    for _ in 0..n {
        app.update(1.0 / 60.0).unwrap();
    }
}

/// The largest distance between two meshes' vertices (m).
fn moved(a: &[glam::Vec3], b: &[glam::Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}

#[test]
fn a_driven_walker_strides_while_it_moves_and_stands_still_when_stopped() {
    let mut app = app("walker.toml");
    let start = app.sim().bodies[0].pose.position;
    app.key(Key::ArrowUp, true, false);
    frames(&mut app, 30);
    let before = app.sim().bodies[0].object.mesh.positions.clone();
    frames(&mut app, 3);
    let body = &app.sim().bodies[0];
    assert!(
        body.pose.position.distance(start) > 0.5,
        "the arrow key drives the walker"
    );
    assert!(
        moved(&before, &body.object.mesh.positions) > 0.01,
        "it strides while it moves"
    );
    // Let go: it coasts to a stop (3 m/s² from at most 6 m/s: within 2 s).
    app.key(Key::ArrowUp, false, false);
    frames(&mut app, 150);
    let stopped = app.sim().bodies[0].object.mesh.positions.clone();
    let at = app.sim().bodies[0].pose.position;
    frames(&mut app, 30);
    let body = &app.sim().bodies[0];
    assert_eq!(body.pose.position, at, "stopped");
    assert_eq!(
        moved(&stopped, &body.object.mesh.positions),
        0.0,
        "a walker that stands does not walk on the spot"
    );
    body.tree.assert_well_formed();
}

#[test]
fn a_driven_tractor_rolls_its_wheels_at_its_speed_and_steers_its_front_wheels() {
    let mut app = app("tractor.toml");
    app.key(Key::ArrowUp, true, false);
    frames(&mut app, 60);
    let body = &app.sim().bodies[0];
    let v = body.pose.velocity.length();
    assert!(v > 2.0, "driven at {v} m/s");
    let names: Vec<String> = body
        .object
        .parts
        .parts
        .iter()
        .map(|p| p.name.clone())
        .collect();
    for (name, radius) in [("rear_left", 0.7), ("front_right", 0.45)] {
        let i = names.iter().position(|n| *n == name).unwrap();
        let wheel = body.parts[i].pose;
        // Spin about the axle at v / r (the body goes straight).
        let spin = (wheel.angular_velocity - body.pose.angular_velocity).length();
        assert!(
            (spin - v / radius).abs() < 0.05 * v / radius,
            "{name}: spins at {spin} rad/s, v / r = {}",
            v / radius
        );
        // Its lowest point, on the ground, is at rest.
        let contact = wheel.position - glam::Vec3::Y * radius;
        let slip = wheel.point_velocity(contact).length();
        assert!(slip < 0.05 * v, "{name}: contact point moves at {slip} m/s");
    }
    // Steering left: the front wheels turn into the curve (about +y,
    // relative to the body), the rear ones do not.
    app.key(Key::ArrowLeft, true, false);
    frames(&mut app, 20);
    let body = &app.sim().bodies[0];
    let yaw = |i: usize| {
        let relative = body.pose.rotation.inverse() * body.parts[i].pose.rotation;
        // The wheel's axle (the joint's default axle, the part's x; its
        // spin turns about it) in the body's frame: its angle about +y.
        let axle = relative * glam::Vec3::X;
        axle.z.atan2(axle.x)
    };
    let front = names.iter().position(|n| *n == "front_left").unwrap();
    let rear = names.iter().position(|n| *n == "rear_left").unwrap();
    let (f, r) = (yaw(front), yaw(rear));
    eprintln!("front axle {f:.3} rad, rear {r:.3} rad");
    assert!(
        (f - r).abs() > 0.05,
        "the front wheels steer when the arrows turn the tractor ({f} vs {r})"
    );
}
