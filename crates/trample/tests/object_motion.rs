//! Objects and their motion (DESIGN §3): scene parameters baked into the
//! mesh, rolling without slipping, facing the motion, keyframed rotations,
//! start times, messages for bad objects, and poses that are a pure function
//! of time (frame-rate independence).

use glam::{DQuat, DVec3, Quat, Vec3};
use std::f32::consts::TAU;
use std::path::Path;
use trample::object::path::Keyframe;
use trample::object::pose::rotation_from_euler_deg;
use trample::object::{Anchor, Orientation, Scale};
use trample::object::{Object, ObjectParams, PathParams, Pose, ShapeParams};

fn params(shape: ShapeParams, orientation: Orientation, path: PathParams) -> ObjectParams {
    ObjectParams {
        name: "thing".into(),
        shape,
        scale: Scale::default(),
        rotation_deg: [0.0; 3],
        orientation,
        path,
        start_s: 0.0,
        track: Default::default(),
        parts: Vec::new(),
        animation: None,
    }
}

fn object(p: &ObjectParams) -> Object {
    Object::from_params(p, 0, Path::new(".")).expect("valid object")
}

fn error(p: &ObjectParams, index: usize) -> String {
    Object::from_params(p, index, Path::new("scenes"))
        .expect_err("invalid object")
        .to_string()
}

fn sphere(radius_m: f32) -> ShapeParams {
    ShapeParams::Sphere {
        radius_m,
        subdivisions: 3,
    }
}

fn line(from: [f32; 3], to: [f32; 3], duration_s: f32) -> PathParams {
    PathParams::Line {
        from,
        to,
        duration_s,
    }
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    a.distance(b) <= tolerance
}

/// Every bit of a pose, to compare poses exactly.
fn bits(pose: &Pose) -> Vec<u32> {
    [pose.position, pose.velocity, pose.angular_velocity]
        .iter()
        .flat_map(|v| v.to_array())
        .chain(pose.rotation.to_array())
        .map(f32::to_bits)
        .collect()
}

/// The world point of the object that touches the ground (r below the origin).
fn contact_point(pose: &Pose, radius: f32) -> Vec3 {
    pose.position - Vec3::Y * radius
}

#[test]
fn euler_degrees_are_yaw_then_pitch_then_roll() {
    let [yaw, pitch, roll] = [30.0_f32, -20.0, 75.0];
    let expected = Quat::from_rotation_y(yaw.to_radians())
        * Quat::from_rotation_x(pitch.to_radians())
        * Quat::from_rotation_z(roll.to_radians());
    assert!(rotation_from_euler_deg([yaw, pitch, roll]).angle_between(expected) < 1e-3);
    assert!(
        close(
            rotation_from_euler_deg([90.0, 0.0, 0.0]) * Vec3::Z,
            Vec3::X,
            1e-6
        ),
        "yaw 90° turns +z to +x"
    );
}

#[test]
fn sphere_rolling_on_a_line_does_not_slip_and_turns_by_distance_over_radius() {
    let r = 0.5;
    let ball = object(&params(
        sphere(r),
        Orientation::Rolling,
        line([0.0, r, 0.0], [10.0, r, 0.0], 4.0),
    ));
    assert_eq!(
        ball.motion.roll_radius(),
        r,
        "the icosphere has a vertex at its bottom pole"
    );
    for t in [0.0, 0.3, 1.7, 3.9] {
        let pose = ball.pose_at(t);
        let slip = pose.point_velocity(contact_point(&pose, r));
        assert!(
            slip.length() < 1e-5,
            "contact point slips at {slip} at t = {t}"
        );
        // Rolling along +x turns about up × x = −z by d / r.
        let distance = 2.5 * t;
        let expected = Quat::from_axis_angle(-Vec3::Z, distance / r);
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            assert!(
                close(pose.rotation * axis, expected * axis, 1e-4),
                "rotation at t = {t}"
            );
        }
    }
    let end = ball.pose_at(10.0);
    assert_eq!(
        (end.velocity, end.angular_velocity),
        (Vec3::ZERO, Vec3::ZERO)
    );
    assert!(close(
        end.rotation * Vec3::Y,
        Quat::from_axis_angle(-Vec3::Z, 20.0) * Vec3::Y,
        1e-4
    ));
}

#[test]
fn rolling_on_a_polyline_does_not_slip_on_either_leg() {
    let r = 0.25;
    let path = PathParams::Polyline {
        points: vec![[0.0, r, 0.0], [2.0, r, 0.0], [2.0, r, 3.0]],
        speed_m_s: 1.0,
    };
    let ball = object(&params(sphere(r), Orientation::Rolling, path));
    for t in [0.5, 1.9, 2.1, 4.5] {
        let pose = ball.pose_at(t);
        assert!(
            pose.point_velocity(contact_point(&pose, r)).length() < 1e-5,
            "slips at t = {t}"
        );
    }
    // The rotation is continuous through the corner.
    let (before, after) = (
        ball.pose_at(2.0 - 1e-3).rotation,
        ball.pose_at(2.0 + 1e-3).rotation,
    );
    assert!(before.angle_between(after) < 0.02);
}

/// Integrates dR/dt = [ω(t)] R (ω from the poses, 10⁻⁴ s steps, midpoint
/// rule, f64) and compares with the rotation of the poses at `checks`
/// (increasing); also checks that the contact point does not slip there.
fn assert_rotation_matches_integration(ball: &Object, r: f32, checks: &[f64]) {
    let h = 1e-4_f64;
    let mut rotation = DQuat::IDENTITY;
    let mut t = 0.0_f64;
    for &check in checks {
        while t + h / 2.0 < check {
            let omega = ball
                .pose_at((t + h / 2.0) as f32)
                .angular_velocity
                .as_dvec3();
            if let Some(axis) = omega.try_normalize() {
                rotation = DQuat::from_axis_angle(axis, omega.length() * h) * rotation;
            }
            t += h;
        }
        let pose = ball.pose_at(check as f32);
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let (computed, integrated) = (pose.rotation.as_dquat() * axis, rotation * axis);
            assert!(
                (computed - integrated).length() < 2e-3,
                "t = {check}: {computed} vs {integrated}"
            );
        }
        assert!(
            pose.point_velocity(contact_point(&pose, r)).length() < 1e-4,
            "slips at t = {check}"
        );
    }
}

#[test]
fn rolling_on_a_circle_matches_a_fine_numerical_integration() {
    let r = 0.5;
    let path = PathParams::Circle {
        center: [0.0, r, 0.0],
        radius_m: 4.0,
        period_s: 6.0,
        phase_rad: 0.4,
    };
    let ball = object(&params(sphere(r), Orientation::Rolling, path));
    assert_rotation_matches_integration(&ball, r, &[2.5, 7.3, 13.0]);
}

#[test]
fn rolling_on_a_spline_matches_a_fine_numerical_integration() {
    let r = 0.3;
    let points = vec![[0.0, r, 0.0], [3.0, r, 1.0], [4.0, r, 4.0], [1.0, r, 6.0]];
    let ball = object(&params(
        sphere(r),
        Orientation::Rolling,
        PathParams::Spline {
            points,
            speed_m_s: 2.0,
        },
    ));
    let end = f64::from(ball.motion.path().end_time().expect("finite"));
    assert_rotation_matches_integration(&ball, r, &[0.7, 2.0, end - 0.01, end + 1.0]);
}

#[test]
fn rolling_on_a_very_long_line_stays_exact() {
    // 0.01 m/s for 10⁵ s: the angle is the distance over the radius even
    // after 1,000 rad.
    let r = 0.5;
    let ball = object(&params(
        sphere(r),
        Orientation::Rolling,
        line([0.0, r, 0.0], [1000.0, r, 0.0], 1e5),
    ));
    let pose = ball.pose_at(5e4);
    let expected = Quat::from_axis_angle(-Vec3::Z, 500.0 / r);
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        assert!(
            close(pose.rotation * axis, expected * axis, 1e-4),
            "{}",
            pose.rotation * axis
        );
    }
}

#[test]
fn face_motion_turns_mesh_z_along_the_horizontal_velocity() {
    let period = 8.0;
    let circle = PathParams::Circle {
        center: [0.0; 3],
        radius_m: 5.0,
        period_s: period,
        phase_rad: 0.0,
    };
    let car = object(&params(
        ShapeParams::Box {
            half_extents_m: [1.0, 0.5, 2.0],
        },
        Orientation::FaceMotion,
        circle,
    ));
    for t in [0.0, 1.3, 5.9, 100.2] {
        let pose = car.pose_at(t);
        assert!(
            close(pose.rotation * Vec3::Z, pose.velocity.normalize(), 1e-4),
            "faces the motion at t = {t}"
        );
        assert!(
            close(pose.angular_velocity, Vec3::Y * TAU / period, 1e-5),
            "turns with the circle at t = {t}"
        );
    }
    // Before the start it faces its initial direction; after the end, its last one.
    let straight = object(&params(
        ShapeParams::Box {
            half_extents_m: [1.0; 3],
        },
        Orientation::FaceMotion,
        line([0.0; 3], [-4.0, 0.0, 0.0], 2.0),
    ));
    for t in [-3.0, 1.0, 9.0] {
        assert!(
            close(straight.pose_at(t).rotation * Vec3::Z, -Vec3::X, 1e-6),
            "faces −x at t = {t}"
        );
    }
}

#[test]
fn face_motion_yaw_rate_on_a_spline_is_the_derivative_of_the_yaw() {
    let path = PathParams::Spline {
        points: vec![[0.0; 3], [5.0, 0.0, 2.0], [7.0, 0.0, 7.0], [3.0, 0.0, 10.0]],
        speed_m_s: 2.0,
    };
    let car = object(&params(
        ShapeParams::Box {
            half_extents_m: [1.0; 3],
        },
        Orientation::FaceMotion,
        path,
    ));
    let yaw = |t: f32| {
        let forward = car.pose_at(t).rotation * Vec3::Z;
        forward.x.atan2(forward.z)
    };
    let h = 0.01;
    for t in [1.0, 3.3, 5.2, 7.0] {
        let rate = (yaw(t + h) - yaw(t - h)) / (2.0 * h);
        let omega = car.pose_at(t).angular_velocity;
        assert!(
            (omega.y - rate).abs() < 5e-3,
            "t = {t}: ω = {omega}, yaw rate {rate}"
        );
    }
}

#[test]
fn keyframes_orientation_takes_the_key_rotations() {
    let keys = vec![
        Keyframe {
            t_s: 0.0,
            position: [0.0; 3],
            rotation_deg: Some([0.0, 0.0, 0.0]),
        },
        Keyframe {
            t_s: 2.0,
            position: [2.0, 0.0, 0.0],
            rotation_deg: Some([0.0, 0.0, 90.0]),
        },
    ];
    let thing = object(&params(
        sphere(1.0),
        Orientation::Keyframes,
        PathParams::Keyframes { keys },
    ));
    let pose = thing.pose_at(1.0);
    assert!(
        pose.rotation
            .angle_between(Quat::from_rotation_z(std::f32::consts::FRAC_PI_4))
            < 1e-3
    );
    assert!(close(
        pose.angular_velocity,
        Vec3::Z * std::f32::consts::FRAC_PI_4,
        1e-5
    ));
    assert!(close(pose.velocity, Vec3::X, 1e-6));
}

#[test]
fn before_start_s_the_object_waits_at_the_start_of_its_path() {
    let mut p = params(
        sphere(1.0),
        Orientation::Rolling,
        line([0.0, 1.0, 0.0], [6.0, 1.0, 0.0], 3.0),
    );
    p.start_s = 2.0;
    let ball = object(&p);
    let waiting = ball.pose_at(1.0);
    assert_eq!(waiting, Pose::at_rest(Vec3::new(0.0, 1.0, 0.0)));
    assert!(close(
        ball.pose_at(3.5).position,
        Vec3::new(3.0, 1.0, 0.0),
        1e-6
    ));
    assert!(close(
        ball.pose_at(3.5).velocity,
        Vec3::new(2.0, 0.0, 0.0),
        1e-6
    ));
}

#[test]
fn pose_at_is_a_pure_function_of_time() {
    let r = 0.5;
    let keys = vec![
        Keyframe {
            t_s: 0.0,
            position: [0.0; 3],
            rotation_deg: Some([0.0, 10.0, 0.0]),
        },
        Keyframe {
            t_s: 1.5,
            position: [1.0, 0.0, 3.0],
            rotation_deg: Some([80.0, 0.0, 30.0]),
        },
    ];
    let objects = [
        params(
            sphere(r),
            Orientation::Fixed,
            line([0.0; 3], [3.0, 0.0, 1.0], 2.0),
        ),
        params(
            sphere(r),
            Orientation::FaceMotion,
            PathParams::Spline {
                points: vec![[0.0; 3], [3.0, 0.0, 1.0], [4.0, 0.0, 5.0]],
                speed_m_s: 1.5,
            },
        ),
        params(
            sphere(r),
            Orientation::Rolling,
            PathParams::Polyline {
                points: vec![[0.0; 3], [3.0, 0.0, 1.0], [4.0, 0.0, 5.0]],
                speed_m_s: 1.5,
            },
        ),
        params(
            sphere(r),
            Orientation::Rolling,
            PathParams::Circle {
                center: [0.0; 3],
                radius_m: 3.0,
                period_s: 5.0,
                phase_rad: 0.0,
            },
        ),
        params(
            sphere(r),
            Orientation::Keyframes,
            PathParams::Keyframes { keys },
        ),
    ]
    .map(|p| object(&p));
    let times: Vec<f32> = (0..200).map(|k| -0.5 + k as f32 * 0.037).collect();
    for thing in &objects {
        let forward: Vec<Vec<u32>> = times.iter().map(|&t| bits(&thing.pose_at(t))).collect();
        let backward: Vec<Vec<u32>> = times
            .iter()
            .rev()
            .map(|&t| bits(&thing.pose_at(t)))
            .collect();
        assert!(
            forward.iter().eq(backward.iter().rev()),
            "{:?}: order changes the pose",
            thing.motion.orientation()
        );
        // A copy made later, asked in steps of a different size first, agrees.
        let copy = thing.clone();
        for k in 0..1000 {
            let _ = copy.pose_at(k as f32 / 60.0);
        }
        for (&t, expected) in times.iter().zip(&forward) {
            assert_eq!(&bits(&copy.pose_at(t)), expected, "t = {t}");
        }
    }
}

#[test]
fn scale_rotation_and_anchor_are_baked_into_the_mesh() {
    let dir = std::env::temp_dir().join(format!("trample-object-{}-bake", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    // A tetrahedron from (0, 10, 0) to (1, 12, 3) in file units.
    let text = "v 0 10 0\nv 1 10 0\nv 0 12 0\nv 0 10 3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("tet.obj"), text).expect("write");
    let shape = |anchor| ShapeParams::Mesh {
        path: "tet.obj".into(),
        anchor,
    };
    let mut p = params(
        shape(Anchor::Bottom),
        Orientation::Fixed,
        PathParams::Static { position: [0.0; 3] },
    );
    p.scale = Scale::PerAxis([2.0, 1.0, 1.0]);
    p.rotation_deg = [90.0, 0.0, 0.0];
    let thing = Object::from_params(&p, 0, &dir).expect("valid");
    // Scaled: x spans 2, y 2, z 3; turned 90° about y: x spans 3, z spans 2;
    // anchored: bottom centre at the origin.
    let (lo, hi) = thing.mesh.bounds().expect("non-empty");
    assert!(
        close(lo, Vec3::new(-1.5, 0.0, -1.0), 1e-5) && close(hi, Vec3::new(1.5, 2.0, 1.0), 1e-5),
        "{lo} {hi}"
    );
    assert!(thing.closed && thing.mesh.signed_volume() > 0.0);
    assert_eq!(
        thing.report.degenerate_dropped + thing.report.duplicate_dropped,
        0
    );
    // Bottom anchor: no depth below the origin, nothing to roll on.
    p.orientation = Orientation::Rolling;
    assert_eq!(
        Object::from_params(&p, 4, &dir)
            .expect_err("roll radius 0")
            .to_string(),
        "objects[4] (thing): orientation = \"rolling\" needs the mesh's lowest point below its origin (a roll radius > 0); the roll radius is 0 m"
    );
    p.orientation = Orientation::Fixed;
    p.shape = shape(Anchor::File);
    p.scale = Scale::Uniform(1.0);
    p.rotation_deg = [0.0; 3];
    let (lo, _) = Object::from_params(&p, 0, &dir)
        .expect("valid")
        .mesh
        .bounds()
        .expect("non-empty");
    assert_eq!(
        lo,
        Vec3::new(0.0, 10.0, 0.0),
        "file anchor keeps the file's origin"
    );
}

#[test]
fn knot_and_capsule_objects_are_closed() {
    for shape in [
        ShapeParams::Knot { size_m: 2.0 },
        ShapeParams::Capsule {
            radius_m: 0.3,
            length_m: 1.0,
        },
    ] {
        let thing = object(&params(
            shape,
            Orientation::Fixed,
            PathParams::Static { position: [0.0; 3] },
        ));
        assert!(thing.closed);
    }
}

#[test]
fn bad_objects_are_refused_with_their_index_name_key_and_limit() {
    let still = || PathParams::Static { position: [0.0; 3] };
    let mut p = params(sphere(-1.0), Orientation::Fixed, still());
    p.name = "ball".into();
    assert_eq!(
        error(&p, 2),
        "objects[2] (ball): shape.radius_m = -1: must be a finite number > 0"
    );
    p.shape = ShapeParams::Sphere {
        radius_m: 1.0,
        subdivisions: 9,
    };
    assert_eq!(
        error(&p, 2),
        "objects[2] (ball): shape.subdivisions = 9: must be at most 7"
    );
    p.shape = ShapeParams::Box {
        half_extents_m: [1.0, 0.0, 1.0],
    };
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): shape.half_extents_m = [1, 0, 1]: each must be a finite number > 0"
    );
    p.shape = ShapeParams::Capsule {
        radius_m: 1.0,
        length_m: f32::NAN,
    };
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): shape.length_m = NaN: must be a finite number ≥ 0"
    );
    p.shape = ShapeParams::Knot {
        size_m: f32::INFINITY,
    };
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): shape.size_m = inf: must be a finite number > 0"
    );
    p.shape = sphere(1.0);
    p.scale = Scale::PerAxis([1.0, -2.0, 1.0]);
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): scale = [1, -2, 1]: every factor must be a finite number > 0"
    );
    p.scale = Scale::Uniform(1e5);
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): built-in sphere: mesh is 3.4641016e5 m across; at most 10000 m is allowed"
    );
    p.scale = Scale::default();
    p.rotation_deg = [0.0, f32::NAN, 0.0];
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): rotation_deg = [0, NaN, 0]: every angle must be finite"
    );
    p.rotation_deg = [0.0; 3];
    p.path = line([0.0; 3], [1.0; 3], -1.0);
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): path.duration_s = -1: must be > 0"
    );
    p.path = line([0.0; 3], [1.0; 3], 1.0);
    p.orientation = Orientation::Keyframes;
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): orientation = \"keyframes\" needs a keyframes path with rotation_deg on its keys; the path is a line"
    );
    p.orientation = Orientation::Fixed;
    p.start_s = f32::NAN;
    assert_eq!(
        error(&p, 0),
        "objects[0] (ball): start_s = NaN: must be finite"
    );
    p.start_s = 0.0;
    p.shape = ShapeParams::Mesh {
        path: "nowhere.obj".into(),
        anchor: Anchor::Center,
    };
    assert_eq!(
        error(&p, 1),
        "objects[1] (ball): scenes/nowhere.obj: cannot read the file: No such file or directory (os error 2)"
    );
}

#[test]
fn scene_toml_deserializes_into_object_params() {
    let text = r#"
        name = "car"
        orientation = "face_motion"
        scale = [4.0, 4.0, 4.0]
        shape = { kind = "mesh", path = "beetle.obj", anchor = "bottom" }
        path = { kind = "circle", center = [0.0, 0.0, 0.0], radius_m = 10.0, period_s = 20.0 }
    "#;
    let p: ObjectParams = toml::from_str(text).expect("valid scene object");
    assert_eq!(p.orientation, Orientation::FaceMotion);
    assert_eq!(p.scale, Scale::PerAxis([4.0; 3]));
    assert!(
        toml::from_str::<ObjectParams>(&text.replace("scale", "scael")).is_err(),
        "unknown keys are errors"
    );
}
