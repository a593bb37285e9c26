//! Articulated objects (object/parts.rs, DESIGN §3 "Articulated bodies"):
//! a wheel of radius r rolling at speed v turns at v/r and its contact
//! point is at rest; steered wheels face where they go on a curve; keyframed
//! and host-posed joints compose down the tree; the scene-file form parses
//! (the tractor's wheels) and bad parts give one-line errors naming them.

use glam::{Quat, Vec3};
use std::f32::consts::FRAC_PI_2;
use trample::object::parts::{PartPose, PartsInput, WheelOdometer};
use trample::object::{Articulation, PartParams, Pose};

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Parts {
    parts: Vec<PartParams>,
}

fn articulation(toml_text: &str) -> Result<Articulation, String> {
    let parts: Parts = toml::from_str(toml_text).map_err(|e| e.to_string())?;
    Articulation::from_params(&parts.parts, std::path::Path::new(".")).map_err(|e| e.to_string())
}

fn tractor() -> Articulation {
    let text = include_str!("data/tractor_parts.toml");
    articulation(text).expect("the tractor's parts are valid")
}

fn poses(art: &Articulation, t: f32, body: Pose, rolled: &[f32]) -> Vec<PartPose> {
    let mut out = Vec::new();
    let input = PartsInput {
        t,
        body,
        rolled_m: rolled,
        host: &[],
    };
    art.poses_into(&input, &mut out);
    out
}

/// `a` and `b` are the same rotation (q and −q are), component by component.
fn same_rotation(a: Quat, b: Quat, tolerance: f32) -> bool {
    (a - b).length().min((a + b).length()) < tolerance
}

/// The speed of the material point of `pose`'s part that touches the
/// ground, `r` below the wheel centre.
fn contact_speed(pose: &Pose, r: f32) -> f32 {
    pose.point_velocity(pose.position - Vec3::Y * r).length()
}

#[test]
fn a_wheel_of_radius_r_rolling_at_speed_v_turns_at_v_over_r_with_its_contact_at_rest() {
    let art = tractor();
    let rear = art.index_of("rear_left").expect("exists");
    for (v, heading) in [(2.0f32, 0.0f32), (5.5, 0.7), (-1.5, 2.0)] {
        // The body drives straight along its +z, turned by `heading`.
        let rotation = Quat::from_rotation_y(heading);
        let body = Pose {
            position: Vec3::new(3.0, 1.3, -2.0),
            rotation,
            velocity: rotation * Vec3::Z * v,
            angular_velocity: Vec3::ZERO,
        };
        let out = poses(&art, 0.0, body, &[]);
        for (name, r) in [("rear_left", 0.7), ("front_right", 0.45)] {
            let p = out[art.index_of(name).expect("exists")];
            let spin = p.world.angular_velocity;
            assert!(
                (spin.length() - v.abs() / r).abs() < 1e-5 * v.abs() / r,
                "{name} at {v} m/s spins at {} rad/s, expected {}",
                spin.length(),
                v.abs() / r
            );
            // About its axle (the body's x), in the rolling sense.
            let axle = rotation * Vec3::X;
            assert!((spin.dot(axle) - v / r).abs() < 1e-5 * v.abs() / r);
            assert!(
                (p.world.position.y - r).abs() < 1e-6,
                "{name} stands on the ground"
            );
            let contact = contact_speed(&p.world, r);
            assert!(
                contact < 1e-5 * v.abs(),
                "{name}: contact speed {contact} at {v} m/s"
            );
            // Its top moves at twice the body's speed.
            let top = p
                .world
                .point_velocity(p.world.position + Vec3::Y * r)
                .length();
            assert!((top - 2.0 * v.abs()).abs() < 1e-4 * v.abs());
            assert!((p.rolling_speed_m_s - v).abs() < 1e-5 * v.abs());
        }
        // The spin angle follows the distance rolled: after 1 s at v the
        // rear wheel has turned v / r radians about its axle.
        let mut odometer = WheelOdometer::new(&out);
        for _ in 0..100 {
            odometer.advance(0.01, &out);
        }
        let rolled = odometer.rolled_m[rear];
        assert!((rolled - v).abs() < 1e-4 * v.abs(), "rolled {rolled}");
        let turned = poses(&art, 1.0, body, &odometer.rolled_m)[rear]
            .world
            .rotation;
        let want = rotation * Quat::from_rotation_x(v / 0.7);
        assert!(same_rotation(turned, want, 1e-5), "{turned} vs {want}");
    }
}

#[test]
fn steered_wheels_face_where_they_go_on_a_curve_and_do_not_slip() {
    let art = tractor();
    // The body (origin between the wheels, 1.3 m up) drives on a circle of
    // radius 8 m about (0, 0, 0), counter-clockwise seen from above, at
    // 3 m/s, facing its motion: at (8, 1.3, 0) it heads along −z.
    let (radius, v) = (8.0f32, 3.0f32);
    let omega = v / radius;
    let body = Pose {
        position: Vec3::new(radius, 1.3, 0.0),
        rotation: Quat::from_rotation_y(std::f32::consts::PI),
        velocity: Vec3::new(0.0, 0.0, -v),
        angular_velocity: Vec3::Y * omega,
    };
    let out = poses(&art, 0.0, body, &[]);
    for name in ["front_left", "front_right"] {
        let p = out[art.index_of(name).expect("exists")].world;
        let contact = contact_speed(&p, 0.45);
        assert!(
            contact < 1e-4,
            "{name}: steered wheel slips at {contact} m/s"
        );
        // It faces its own velocity: its axle (the spin keeps it) is
        // perpendicular to it.
        let axle = p.rotation * Vec3::X;
        assert!(
            p.velocity.normalize().dot(axle).abs() < 1e-4,
            "{name}: {axle}"
        );
    }
    // Inner wheel (left, towards the centre) steers more than the outer one.
    let angle = |name: &str| {
        let p = out[art.index_of(name).expect("exists")].world;
        (body.rotation.inverse() * p.rotation * Vec3::X).angle_between(Vec3::X)
    };
    let (inner, outer) = (angle("front_left"), angle("front_right"));
    assert!(inner > outer && outer > 0.1, "inner {inner}, outer {outer}");
    // Rear wheels do not steer; they slip sideways only by the body's turn
    // (ω × offset), nothing along their rolling direction.
    let p = out[art.index_of("rear_left").expect("exists")].world;
    let slip = p.point_velocity(p.position - Vec3::Y * 0.7);
    assert!(slip.dot(p.rotation * Vec3::Z).abs() < 1e-5, "{slip}");
    assert!((slip.length() - omega * 0.9).abs() < 1e-4, "{slip}");
}

#[test]
fn steering_fades_out_as_the_vehicle_stops() {
    let art = tractor();
    let front = art.index_of("front_left").expect("exists");
    let mut last = f32::NAN;
    for k in 0..=20 {
        let v = 0.1 * (20 - k) as f32 / 20.0;
        let body = Pose {
            position: Vec3::new(0.0, 1.3, 0.0),
            rotation: Quat::IDENTITY,
            velocity: Vec3::Z * v,
            angular_velocity: Vec3::Y * v / 4.0,
        };
        let p = poses(&art, 0.0, body, &[])[front].world;
        let angle = (p.rotation * Vec3::X).angle_between(Vec3::X);
        if last.is_finite() {
            assert!(angle <= last + 1e-6, "steering grew as the tractor slowed");
        }
        last = angle;
    }
    assert_eq!(last, 0.0, "straight ahead at rest");
}

#[test]
fn keyframed_and_host_joints_compose_down_the_tree() {
    let art = articulation(
        r#"
[[parts]]
name = "arm"
parent = "shoulder"
shape = { kind = "box", half_extents_m = [0.05, 0.3, 0.05] }
offset_m = [0.0, -0.3, 0.0]
joint = { kind = "keyframes", loop_s = 2.0, keys = [
  { t_s = 0.0, position = [0.0, 0.0, 0.0], rotation_deg = [0.0, 0.0, 0.0] },
  { t_s = 1.0, position = [0.0, 0.0, 0.0], rotation_deg = [0.0, 90.0, 0.0] },
] }

[[parts]]
name = "shoulder"
shape = { kind = "sphere", radius_m = 0.1 }
offset_m = [0.5, 1.0, 0.0]
joint = { kind = "host" }
"#,
    )
    .expect("valid");
    // Parents first, whatever the file order.
    assert_eq!(art.index_of("shoulder"), Some(0));
    assert_eq!(art.index_of("arm"), Some(1));
    assert_eq!(art.parts[1].parent, Some(0));

    let body = Pose {
        position: Vec3::new(1.0, 0.0, 0.0),
        rotation: Quat::from_rotation_y(FRAC_PI_2),
        velocity: Vec3::new(0.0, 0.0, 2.0),
        angular_velocity: Vec3::Y * 0.5,
    };
    let host = [Some(Pose {
        position: Vec3::new(0.0, 0.2, 0.0),
        rotation: Quat::from_rotation_z(0.3),
        velocity: Vec3::new(0.0, 0.1, 0.0),
        angular_velocity: Vec3::Z * 0.25,
    })];
    let mut out = Vec::new();
    // t = 2.5 s plays the keys at 0.5 s: the arm is half-way, 45° about x.
    let input = PartsInput {
        t: 2.5,
        body,
        rolled_m: &[],
        host: &host,
    };
    art.poses_into(&input, &mut out);
    let shoulder = out[0].world;
    let local = host[0].expect("set");
    let arm_vec = body.rotation * (Vec3::new(0.5, 1.0, 0.0) + local.position);
    assert!((shoulder.position - (body.position + arm_vec)).length() < 1e-6);
    assert!(same_rotation(
        shoulder.rotation,
        body.rotation * local.rotation,
        1e-6
    ));
    let v = body.velocity + body.angular_velocity.cross(arm_vec) + body.rotation * local.velocity;
    assert!(
        (shoulder.velocity - v).length() < 1e-6,
        "{} vs {v}",
        shoulder.velocity
    );
    let w = body.angular_velocity + body.rotation * local.angular_velocity;
    assert!((shoulder.angular_velocity - w).length() < 1e-6);

    let arm = out[1].world;
    let key = Quat::from_rotation_x(std::f32::consts::FRAC_PI_4);
    assert!(same_rotation(arm.rotation, shoulder.rotation * key, 1e-5));
    let reach = shoulder.rotation * Vec3::new(0.0, -0.3, 0.0);
    assert!((arm.position - (shoulder.position + reach)).length() < 1e-6);
    // Its own turn: 90° per second about the shoulder's x, on top of the
    // shoulder's.
    let w = shoulder.angular_velocity + shoulder.rotation * Vec3::X * FRAC_PI_2;
    assert!(
        (arm.angular_velocity - w).length() < 1e-4,
        "{}",
        arm.angular_velocity
    );
    let v = shoulder.velocity + shoulder.angular_velocity.cross(reach);
    assert!((arm.velocity - v).length() < 1e-5);
    // Without a host pose, the shoulder sits at its joint.
    let input = PartsInput { host: &[], ..input };
    art.poses_into(&input, &mut out);
    assert!(
        (out[0].world.position - (body.position + body.rotation * Vec3::new(0.5, 1.0, 0.0)))
            .length()
            < 1e-6
    );
}

#[test]
fn bad_parts_give_one_line_errors_naming_the_part() {
    let wheel = |name: &str, extra: &str| {
        format!(
            "[[parts]]\nname = \"{name}\"\nshape = {{ kind = \"cylinder\", radius_m = 0.4, length_m = 0.2 }}\n{extra}\n"
        )
    };
    let cases = [
        (
            wheel("a", "parent = \"axle\""),
            r#"parts[0] (a): parent = "axle" does not exist; allowed: omitted (the object's body) or one of no other part"#,
        ),
        (
            wheel("a", "") + &wheel("b", "parent = \"front\""),
            r#"parts[1] (b): parent = "front" does not exist; allowed: omitted (the object's body) or one of "a""#,
        ),
        (
            wheel("a", "") + &wheel("a", ""),
            r#"parts[1] (a): name "a" is already used by parts[0]; allowed: a name no other part has"#,
        ),
        (
            wheel("a", "parent = \"b\"") + &wheel("b", "parent = \"a\""),
            r#"parts[0] (a): parent = "b" makes a loop (a → b → a); allowed: parents that lead to the body"#,
        ),
        (
            wheel("w", "joint = { kind = \"wheel\", radius_m = 0.0 }"),
            "parts[0] (w): joint.radius_m = 0: must be a finite number > 0",
        ),
        (
            wheel(
                "w",
                "joint = { kind = \"wheel\", radius_m = 0.4, axle = [0.0, 2.0, 0.0] }",
            ),
            "parts[0] (w): joint.axle = [0, 2, 0]: must be a finite, non-zero direction at least 6° from vertical (a wheel rolls about a horizontal axle)",
        ),
        (
            wheel(
                "w",
                "joint = { kind = \"wheel\", radius_m = 0.4, max_steer_deg = 95.0 }",
            ),
            "parts[0] (w): joint.max_steer_deg = 95: must be in [0, 89]",
        ),
        (
            wheel("w", "offset_m = [0.0, inf, 0.0]"),
            "parts[0] (w): offset_m = [0, inf, 0]: every coordinate must be finite",
        ),
        (
            "[[parts]]\nname = \"s\"\nshape = { kind = \"sphere\", radius_m = -1.0 }\n".to_owned(),
            "parts[0] (s): shape.radius_m = -1: must be a finite number > 0",
        ),
        (
            wheel("k", "joint = { kind = \"keyframes\", keys = [] }"),
            "parts[0] (k): joint.keys: path.keys: 0 keys given; at least 1 is needed",
        ),
    ];
    for (text, want) in cases {
        let got = articulation(&text).expect_err(want);
        assert_eq!(got, want);
        assert!(!got.contains('\n'));
    }
    // Unknown keys are errors (deny_unknown_fields), in the joint too.
    let e = articulation(&wheel(
        "w",
        "joint = { kind = \"wheel\", radius_m = 0.4, spin = 2 }",
    ))
    .expect_err("unknown key");
    assert!(e.contains("unknown field `spin`"), "{e}");
    let e = articulation(&wheel("w", "colour = 1")).expect_err("unknown key");
    assert!(e.contains("unknown field `colour`"), "{e}");
}
