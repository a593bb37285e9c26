//! Paths (DESIGN §3): positions and velocities at hand-computed times,
//! constant speed, the circle's direction, splines through their points,
//! keyframes, headings, and a message for every invalid parameter.

use glam::{Quat, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};
use trample::object::path::Keyframe;
use trample::object::{Path, PathParams};

fn path(params: PathParams) -> Path {
    Path::new(params).expect("valid path")
}

fn error(params: PathParams) -> String {
    Path::new(params).expect_err("invalid path").to_string()
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    a.distance(b) <= tolerance
}

fn key(t_s: f32, position: [f32; 3], rotation_deg: Option<[f32; 3]>) -> Keyframe {
    Keyframe {
        t_s,
        position,
        rotation_deg,
    }
}

#[test]
fn line_position_and_velocity_at_hand_computed_times() {
    let line = path(PathParams::Line {
        from: [1.0, 0.5, 0.0],
        to: [11.0, 0.5, -5.0],
        duration_s: 5.0,
    });
    let v = Vec3::new(2.0, 0.0, -1.0);
    assert_eq!(line.end_time(), Some(5.0));
    assert_eq!(
        (line.position(-1.0), line.velocity(-1.0)),
        (Vec3::new(1.0, 0.5, 0.0), Vec3::ZERO),
        "held before"
    );
    assert_eq!(
        (line.position(0.0), line.velocity(0.0)),
        (Vec3::new(1.0, 0.5, 0.0), v),
        "moving from t = 0"
    );
    assert!(close(line.position(2.5), Vec3::new(6.0, 0.5, -2.5), 1e-6));
    assert!(close(line.velocity(2.5), v, 1e-6));
    assert_eq!(
        (line.position(5.0), line.velocity(5.0)),
        (Vec3::new(11.0, 0.5, -5.0), Vec3::ZERO),
        "stopped at the end"
    );
    assert_eq!(line.position(100.0), Vec3::new(11.0, 0.5, -5.0));
}

#[test]
fn static_path_stays_and_has_no_heading() {
    let still = path(PathParams::Static {
        position: [1.0, 2.0, 3.0],
    });
    for t in [-1.0, 0.0, 7.0] {
        assert_eq!(
            (still.position(t), still.velocity(t)),
            (Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO)
        );
    }
    assert_eq!((still.end_time(), still.heading(1.0)), (Some(0.0), None));
}

#[test]
fn polyline_moves_at_constant_speed_through_its_corners() {
    // 3 m along +x, a repeated point, 4 m along +z: 7 m at 2 m/s.
    let points = vec![
        [0.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
        [3.0, 0.0, 4.0],
    ];
    let polyline = path(PathParams::Polyline {
        points,
        speed_m_s: 2.0,
    });
    assert_eq!(polyline.end_time(), Some(3.5));
    assert!(close(
        polyline.position(1.5),
        Vec3::new(3.0, 0.0, 0.0),
        1e-6
    ));
    assert!(close(
        polyline.position(2.5),
        Vec3::new(3.0, 0.0, 2.0),
        1e-6
    ));
    assert!(close(
        polyline.velocity(0.5),
        Vec3::new(2.0, 0.0, 0.0),
        1e-6
    ));
    assert!(close(
        polyline.velocity(2.0),
        Vec3::new(0.0, 0.0, 2.0),
        1e-6
    ));
    let dt = 0.01;
    for k in 0..350 {
        let t = k as f32 * dt;
        assert!(
            (polyline.velocity(t).length() - 2.0).abs() < 1e-5,
            "speed at {t}"
        );
        // Path length covered over dt is speed × dt (chords cut the corner).
        let covered = polyline.position(t).distance(polyline.position(t + dt));
        assert!(
            covered <= 2.0 * dt + 1e-5 && covered > 0.7 * 2.0 * dt,
            "step at {t} covers {covered}"
        );
    }
}

#[test]
fn circle_has_its_radius_and_period_and_runs_counter_clockwise_from_above() {
    let center = Vec3::new(1.0, 0.3, 2.0);
    let circle = path(PathParams::Circle {
        center: center.into(),
        radius_m: 3.0,
        period_s: 4.0,
        phase_rad: 0.0,
    });
    assert_eq!(circle.end_time(), None);
    assert!(close(
        circle.position(0.0),
        center + Vec3::new(3.0, 0.0, 0.0),
        1e-6
    ));
    // A quarter turn later: from +x towards −z (counter-clockwise seen from +y).
    assert!(close(
        circle.position(1.0),
        center + Vec3::new(0.0, 0.0, -3.0),
        1e-5
    ));
    for k in 0..40 {
        let t = 0.01 + k as f32 * 0.37;
        let (p, v) = (circle.position(t), circle.velocity(t));
        assert!((p.distance(center) - 3.0).abs() < 1e-5, "radius at {t}");
        assert!(close(circle.position(t + 4.0), p, 1e-4), "period at {t}");
        assert!((v.length() - TAU * 3.0 / 4.0).abs() < 1e-4, "speed at {t}");
        assert!(
            ((p - center).cross(v).normalize() - Vec3::Y).length() < 1e-5,
            "positive turn about +y at {t}"
        );
        // The velocity is the derivative of the position.
        let h = 1e-3;
        assert!(
            close(
                (circle.position(t + h) - circle.position(t - h)) / (2.0 * h),
                v,
                2e-2
            ),
            "derivative at {t}"
        );
        let a = circle.acceleration(t);
        assert!(
            close(a, -(p - center) * (TAU / 4.0).powi(2), 1e-4),
            "centripetal at {t}"
        );
    }
    assert_eq!(
        (circle.position(-2.0), circle.velocity(-2.0)),
        (circle.position(0.0), Vec3::ZERO)
    );
    let phased = path(PathParams::Circle {
        center: [0.0; 3],
        radius_m: 1.0,
        period_s: 1.0,
        phase_rad: FRAC_PI_2,
    });
    assert!(
        close(phased.position(0.0), Vec3::new(0.0, 0.0, -1.0), 1e-6),
        "phase from +x towards −z"
    );
}

#[test]
fn circle_keeps_its_precision_after_a_long_time() {
    let circle = path(PathParams::Circle {
        center: [0.0; 3],
        radius_m: 2.0,
        period_s: 3.0,
        phase_rad: 0.3,
    });
    // t = 30,000 s is exactly 10,000 turns.
    assert!(close(circle.position(30_000.0), circle.position(0.0), 1e-4));
}

#[test]
fn spline_passes_through_its_points_at_nearly_constant_speed() {
    let points = [
        [0.0, 0.0, 0.0],
        [4.0, 0.0, 1.0],
        [6.0, 1.0, 5.0],
        [2.0, 0.0, 8.0],
        [-1.0, 0.0, 6.0],
    ];
    let spline = path(PathParams::Spline {
        points: points.to_vec(),
        speed_m_s: 3.0,
    });
    let end = spline.end_time().expect("finite");
    // Through every point: the nearest of 100,000 samples (3 × 10⁻⁴ m apart)
    // is within 10⁻³ m.
    let dense = 100_000;
    for p in points {
        let nearest = (0..=dense)
            .map(|k| {
                spline
                    .position(end * k as f32 / dense as f32)
                    .distance(p.into())
            })
            .fold(f32::INFINITY, f32::min);
        assert!(nearest < 1e-3, "passes {p:?} within {nearest}");
    }
    assert!(
        close(spline.position(0.0), points[0].into(), 1e-6)
            && close(spline.position(end), points[4].into(), 1e-4)
    );
    // Speed measured over 2,000 steps of 1.5 cm (long enough for f32
    // rounding of the positions to stay below 10⁻⁴ of a step).
    let samples = 2_000;
    let track: Vec<Vec3> = (0..=samples)
        .map(|k| spline.position(end * k as f32 / samples as f32))
        .collect();
    let dt = end / samples as f32;
    let worst = track
        .windows(2)
        .map(|pair| (pair[0].distance(pair[1]) / dt - 3.0).abs())
        .fold(0.0, f32::max);
    assert!(worst < 0.003, "speed off by {worst} m/s (0.1 % allowed)");
    for k in 0..100 {
        let t = end * k as f32 / 100.0;
        assert!(
            (spline.velocity(t).length() - 3.0).abs() < 1e-4,
            "velocity = speed × unit tangent"
        );
    }
    assert_eq!(spline.velocity(end), Vec3::ZERO);
}

#[test]
fn keyframes_interpolate_positions_and_slerp_rotations() {
    let keys = vec![
        key(1.0, [0.0, 0.0, 0.0], Some([0.0, 0.0, 0.0])),
        key(3.0, [4.0, 0.0, 0.0], Some([90.0, 0.0, 0.0])),
    ];
    let keyed = path(PathParams::Keyframes { keys });
    assert_eq!((keyed.start_time(), keyed.end_time()), (1.0, Some(3.0)));
    assert_eq!(
        (keyed.position(0.0), keyed.velocity(0.0)),
        (Vec3::ZERO, Vec3::ZERO),
        "held before the first key"
    );
    assert!(close(keyed.position(2.0), Vec3::new(2.0, 0.0, 0.0), 1e-6));
    assert!(close(keyed.velocity(2.0), Vec3::new(2.0, 0.0, 0.0), 1e-6));
    let halfway = keyed.keyframe_rotation(2.0).expect("rotations");
    assert!(halfway.angle_between(Quat::from_rotation_y(FRAC_PI_4)) < 1e-3);
    assert!(close(
        keyed.keyframe_angular_velocity(2.0).expect("rotations"),
        Vec3::Y * FRAC_PI_4,
        1e-5
    ));
    assert!(
        keyed
            .keyframe_rotation(9.0)
            .expect("held")
            .angle_between(Quat::from_rotation_y(FRAC_PI_2))
            < 1e-3
    );
    assert_eq!(keyed.keyframe_angular_velocity(9.0), Some(Vec3::ZERO));
    let line = path(PathParams::Line {
        from: [0.0; 3],
        to: [1.0; 3],
        duration_s: 1.0,
    });
    assert_eq!(line.keyframe_rotation(0.5), None);
}

#[test]
fn keyframe_rotations_take_the_short_way() {
    let keys = vec![
        key(0.0, [0.0; 3], Some([170.0, 0.0, 0.0])),
        key(1.0, [0.0; 3], Some([-170.0, 0.0, 0.0])),
    ];
    let keyed = path(PathParams::Keyframes { keys });
    // 20° through 180°, not 340° back through 0°.
    assert!(
        keyed
            .keyframe_rotation(0.5)
            .expect("rotations")
            .angle_between(Quat::from_rotation_y(PI))
            < 1e-3
    );
    assert!(close(
        keyed.keyframe_angular_velocity(0.5).expect("rotations"),
        Vec3::Y * 20f32.to_radians(),
        1e-4
    ));
}

#[test]
fn heading_is_held_through_pauses_and_vertical_moves() {
    let keys = vec![
        key(0.0, [0.0, 0.0, 0.0], None),
        key(1.0, [0.0, 0.0, 2.0], None), // along +z
        key(2.0, [0.0, 0.0, 2.0], None), // pause
        key(3.0, [0.0, 1.0, 2.0], None), // straight up
        key(4.0, [2.0, 1.0, 2.0], None), // along +x
    ];
    let keyed = path(PathParams::Keyframes { keys });
    for (t, heading) in [
        (-1.0, Vec3::Z),
        (0.5, Vec3::Z),
        (1.5, Vec3::Z),
        (2.5, Vec3::Z),
        (3.5, Vec3::X),
        (9.0, Vec3::X),
    ] {
        assert_eq!(keyed.heading(t), Some(heading), "heading at {t}");
    }
    let vertical = path(PathParams::Line {
        from: [0.0; 3],
        to: [0.0, 5.0, 0.0],
        duration_s: 1.0,
    });
    assert_eq!(vertical.heading(0.5), None);
}

#[test]
fn invalid_paths_name_the_key_and_what_is_allowed() {
    let line = |duration_s| PathParams::Line {
        from: [0.0; 3],
        to: [1.0, 0.0, 0.0],
        duration_s,
    };
    assert_eq!(error(line(-1.0)), "path.duration_s = -1: must be > 0");
    assert_eq!(
        error(line(f32::NAN)),
        "path.duration_s = NaN: must be finite"
    );
    assert_eq!(
        error(PathParams::Line {
            from: [0.0, f32::INFINITY, 0.0],
            to: [0.0; 3],
            duration_s: 1.0
        }),
        "path.from = [0, inf, 0]: must be finite"
    );
    assert_eq!(
        error(PathParams::Polyline {
            points: vec![[0.0; 3]],
            speed_m_s: 1.0
        }),
        "path.points: 1 point given; at least 2 are needed"
    );
    assert_eq!(
        error(PathParams::Spline {
            points: vec![],
            speed_m_s: 1.0
        }),
        "path.points: 0 points given; at least 2 are needed"
    );
    assert_eq!(
        error(PathParams::Polyline {
            points: vec![[0.0; 3], [1.0, f32::NAN, 0.0]],
            speed_m_s: 1.0
        }),
        "path.points[1] = [1, NaN, 0]: must be finite"
    );
    assert_eq!(
        error(PathParams::Polyline {
            points: vec![[1.0; 3], [1.0; 3]],
            speed_m_s: 1.0
        }),
        "path.points: all points are the same; the path must have a length > 0"
    );
    assert_eq!(
        error(PathParams::Polyline {
            points: vec![[0.0; 3], [1.0; 3]],
            speed_m_s: 0.0
        }),
        "path.speed_m_s = 0: must be > 0"
    );
    assert_eq!(
        error(PathParams::Polyline {
            points: vec![[0.0; 3], [1000.0, 0.0, 0.0]],
            speed_m_s: 1e-7
        }),
        "path.speed_m_s = 0.0000001: the path would take 1.0e10 s; at most 1e9 s is allowed"
    );
    assert_eq!(
        error(PathParams::Spline {
            points: vec![[0.0; 3], [1.0; 3], [1.0; 3]],
            speed_m_s: 1.0
        }),
        "path.points[2] repeats points[1]; consecutive spline points must differ"
    );
    let circle = |radius_m, period_s| PathParams::Circle {
        center: [0.0; 3],
        radius_m,
        period_s,
        phase_rad: 0.0,
    };
    assert_eq!(error(circle(0.0, 1.0)), "path.radius_m = 0: must be > 0");
    assert_eq!(
        error(circle(1.0, -2.5)),
        "path.period_s = -2.5: must be > 0"
    );
    assert_eq!(
        error(PathParams::Keyframes { keys: vec![] }),
        "path.keys: 0 keys given; at least 1 is needed"
    );
    let keys = vec![
        key(0.0, [0.0; 3], None),
        key(1.0, [0.0; 3], None),
        key(2.0, [0.0; 3], None),
        key(2.0, [1.0; 3], None),
    ];
    assert_eq!(
        error(PathParams::Keyframes { keys }),
        "path.keys[3].t_s = 2 is not after keys[2].t_s = 2"
    );
    let keys = vec![key(0.0, [0.0; 3], Some([0.0; 3])), key(1.0, [0.0; 3], None)];
    assert_eq!(
        error(PathParams::Keyframes { keys }),
        "path.keys[1] has no rotation_deg but keys[0] has one; give rotation_deg on every key or on none"
    );
    let keys = vec![key(0.0, [0.0; 3], None), key(f32::NAN, [0.0; 3], None)];
    assert_eq!(
        error(PathParams::Keyframes { keys }),
        "path.keys[1].t_s = NaN: must be finite"
    );
}
