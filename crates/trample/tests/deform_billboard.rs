//! Billboards (Eq. 8) and the transitions between geometric blades and
//! billboards (Eq. 9–13): hand-computed cases, the ground guard of the
//! billboard top, and the last-segment rule of the billboard → geometry
//! transition.

use glam::{Vec3, Vec3A};
use trample::deform::bend::{bend_blade, weights};
use trample::deform::billboard::{MIN_T, billboard_slope, billboard_top, deflect_billboard};
use trample::deform::transition::{
    bend_last_segment, blade_offset, mean_offset, offset_from_slope, slope_from_offset,
};
use trample::field::Terrain;

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn eq8_slope_hand_cases() {
    let origin = Vec3::Y;
    // t = (0,0,2), R = 1: t·R/|t|² = (0,0,0.5).
    assert_eq!(
        billboard_slope(origin, Vec3::new(0.0, 0.0, 2.0), 1.0),
        Vec3::new(0.0, 1.0, 0.5)
    );
    // t = (3,−4,0), R = 2.5: (3,−4,0)·2.5/25 = (0.3,−0.4,0).
    assert!(close(
        billboard_slope(origin, Vec3::new(3.0, -4.0, 0.0), 2.5),
        Vec3::new(0.3, 0.6, 0.0),
        1e-6
    ));
    // The closer the object, the larger the slope.
    let far = billboard_slope(origin, Vec3::new(0.0, 0.0, 2.0), 1.0);
    let near = billboard_slope(origin, Vec3::new(0.0, 0.0, 0.5), 1.0);
    assert!((near - origin).length() > (far - origin).length());
}

#[test]
fn eq8_object_on_the_centre_pushes_down_and_bad_input_is_ignored() {
    let origin = Vec3::new(0.1, 0.99, 0.0);
    let s = billboard_slope(origin, Vec3::ZERO, 1.0);
    assert!(s.is_finite());
    assert_eq!((s.x, s.z), (origin.x, origin.z));
    assert!((s.y - (origin.y - 1.0 / MIN_T)).abs() < 1e-2);
    assert_eq!(billboard_slope(origin, Vec3::X, -1.0), origin);
    assert_eq!(billboard_slope(origin, Vec3::X, f32::NAN), origin);
    assert_eq!(
        billboard_slope(origin, Vec3::new(f32::NAN, 0.0, 0.0), 1.0),
        origin
    );
}

#[test]
fn deflect_keeps_the_farther_slope() {
    let origin = Vec3::Y;
    let current = Vec3::new(0.0, 1.0, 0.5);
    assert_eq!(
        deflect_billboard(current, origin, Vec3::new(0.0, 1.0, 0.2)),
        current,
        "receding object"
    );
    let closer = Vec3::new(0.0, 1.0, 0.8);
    assert_eq!(
        deflect_billboard(current, origin, closer),
        closer,
        "approaching object"
    );
    assert_eq!(
        deflect_billboard(current, origin, Vec3::new(0.0, 1.0, -0.5)),
        current,
        "tie keeps current"
    );
    assert_eq!(deflect_billboard(current, origin, Vec3::NAN), current);
    assert_eq!(deflect_billboard(Vec3::NAN, origin, closer), closer);
}

#[test]
fn billboard_top_direction_height_and_ground_guard() {
    let flat = Terrain::Flat(0.0);
    let base = Vec3::new(1.0, 0.0, 2.0);
    assert_eq!(
        billboard_top(base, Vec3::Y, 0.5, &flat, 0.0),
        Vec3::new(1.0, 0.5, 2.0)
    );
    // Slopes are directions: (3,4,0) → (0.6,0.8,0).
    assert!(close(
        billboard_top(base, Vec3::new(3.0, 4.0, 0.0), 0.5, &flat, 0.0),
        Vec3::new(1.3, 0.4, 2.0),
        1e-6
    ));
    assert!(close(
        billboard_top(base, Vec3::new(30.0, 40.0, 0.0), 0.5, &flat, 0.0),
        Vec3::new(1.3, 0.4, 2.0),
        1e-6
    ));
    // Pointing into the ground: laid on it, same horizontal direction and height.
    let top = billboard_top(base, Vec3::new(1.0, -1.0, 0.0), 0.5, &flat, 0.0);
    assert!(close(top, Vec3::new(1.5, 0.0, 2.0), 1e-6), "{top:?}");
    let top = billboard_top(base, Vec3::new(0.0, -1e4, 1.0), 0.5, &flat, 0.05);
    assert!(
        top.y >= 0.05 && top.z > 2.0 && ((top - base).length() - 0.5).abs() < 1e-5,
        "{top:?}"
    );
    // Zero or NaN slope: straight up; no height: the base.
    assert_eq!(
        billboard_top(base, Vec3::ZERO, 0.5, &flat, 0.0),
        Vec3::new(1.0, 0.5, 2.0)
    );
    assert_eq!(
        billboard_top(base, Vec3::NAN, 0.5, &flat, 0.0),
        Vec3::new(1.0, 0.5, 2.0)
    );
    assert_eq!(billboard_top(base, Vec3::X, 0.0, &flat, 0.0), base);
    assert_eq!(billboard_top(base, Vec3::X, f32::NAN, &flat, 0.0), base);
}

#[test]
fn eq9_10_blade_offset_per_unit_rest_height() {
    // Eq. 9–10: (V_n − V_0) − rest, here divided by the rest height 1.
    assert!(close(
        blade_offset(Vec3::new(0.3, 0.8, 0.0), Vec3::Y),
        Vec3::new(0.3, -0.2, 0.0),
        1e-6
    ));
    // A blade half as tall bent alike has the same offset.
    assert!(close(
        blade_offset(Vec3::new(0.15, 0.4, 0.0), Vec3::new(0.0, 0.5, 0.0)),
        Vec3::new(0.3, -0.2, 0.0),
        1e-6
    ));
    assert_eq!(blade_offset(Vec3::Y, Vec3::Y), Vec3::ZERO);
    assert_eq!(
        blade_offset(Vec3::Y, Vec3::ZERO),
        Vec3::ZERO,
        "no rest height"
    );
    assert_eq!(blade_offset(Vec3::NAN, Vec3::Y), Vec3::ZERO);
}

#[test]
fn eq11_mean_offset() {
    assert_eq!(
        mean_offset([Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0)]),
        Vec3::new(0.5, 0.0, 1.0)
    );
    assert_eq!(mean_offset(std::iter::empty()), Vec3::ZERO);
    assert_eq!(
        mean_offset([Vec3::X, Vec3::NAN, Vec3::new(3.0, 0.0, 0.0)]),
        Vec3::new(2.0, 0.0, 0.0),
        "NaN skipped"
    );
}

#[test]
fn eq12_13_slope_and_offset_are_inverse() {
    let origin = Vec3::new(0.1, 0.995, 0.0);
    let off = Vec3::new(0.3, -0.2, 0.1);
    let slope = slope_from_offset(origin, off);
    assert_eq!(slope, origin + off);
    assert!(close(offset_from_slope(slope, origin), off, 1e-6));
    assert_eq!(offset_from_slope(origin, origin), Vec3::ZERO);
}

/// Geometry → billboard → geometry: a cell of bent blades gives a billboard
/// slope whose direction is the blades' mean tip direction, and its Eq. 13
/// offset equals the blades' mean offset, so the billboard → geometry rule
/// applies nothing more (v1 = 0).
#[test]
fn transition_round_trip_is_consistent() {
    let h = 0.4;
    let rest: Vec<Vec<Vec3A>> = (0..4)
        .map(|i| {
            (0..=4)
                .map(|k| Vec3A::new(i as f32 * 0.1, k as f32 * h / 4.0, 0.0))
                .collect()
        })
        .collect();
    let mut bent = rest.clone();
    for (i, b) in bent.iter_mut().enumerate() {
        let push = Vec3::new(0.05, 0.0, 0.02 * i as f32);
        bend_blade(
            b,
            h / 4.0,
            push,
            1.0,
            &weights(4, 1.0, 2.0),
            &Terrain::Flat(0.0),
            0.0,
        );
    }
    let tip = |b: &[Vec3A]| Vec3::from(b[4] - b[0]);
    let off_b = mean_offset(
        bent.iter()
            .zip(&rest)
            .map(|(b, r)| blade_offset(tip(b), tip(r))),
    );
    let origin = Vec3::Y; // mean rest (V_n − V_0) / mean rest height
    let slope = slope_from_offset(origin, off_b);
    let mean_tip = bent.iter().map(|b| tip(b)).sum::<Vec3>() / 4.0;
    assert!(
        close(slope.normalize(), mean_tip.normalize(), 1e-6),
        "billboard leans like its blades"
    );
    let v1 = (offset_from_slope(slope, origin) - off_b) * h;
    assert!(v1.length() < 1e-6);
    let mut again = bent[2].clone();
    bend_last_segment(&mut again, h / 4.0, v1, &Terrain::Flat(0.0), 0.0);
    assert!(
        again
            .iter()
            .zip(&bent[2])
            .all(|(a, b)| (*a - *b).length() < 1e-6)
    );
}

/// Billboard → geometry: only the last segment turns (Eq. 5 with num = 1 on
/// the tip, then its length restored). Vertical blade of 3 segments of 0.25,
/// v1 = (0.1,0,0): V3 = V2 + 0.25 · normalize(0.1, 0.25, 0)
/// = (0.0928477, 0.7321192, 0).
#[test]
fn bend_last_segment_moves_only_the_tip() {
    let rest: Vec<Vec3A> = (0..=3)
        .map(|k| Vec3A::new(0.0, 0.25 * k as f32, 0.0))
        .collect();
    let mut v = rest.clone();
    bend_last_segment(
        &mut v,
        0.25,
        Vec3::new(0.1, 0.0, 0.0),
        &Terrain::Flat(0.0),
        0.0,
    );
    for k in 0..3 {
        assert_eq!(
            v[k].to_array().map(f32::to_bits),
            rest[k].to_array().map(f32::to_bits),
            "vertex {k}"
        );
    }
    assert!(
        close(v[3].into(), Vec3::new(0.092_847_7, 0.732_119_2, 0.0), 1e-6),
        "{:?}",
        v[3]
    );
    assert!(((v[3] - v[2]).length() - 0.25).abs() < 1e-6);
    // Bad input or no perpendicular force: unchanged.
    for v1 in [Vec3::NAN, Vec3::Y, Vec3::ZERO] {
        let mut w = rest.clone();
        bend_last_segment(&mut w, 0.25, v1, &Terrain::Flat(0.0), 0.0);
        assert_eq!(w, rest);
    }
    // A bent blade (coordinates not exact in f32): the lower vertices keep their bits.
    let mut bent = rest.clone();
    bend_blade(
        &mut bent,
        0.25,
        Vec3::new(0.07, 0.0, 0.03),
        1.0,
        &weights(3, 1.0, 2.0),
        &Terrain::Flat(0.0),
        0.0,
    );
    let mut v = bent.clone();
    bend_last_segment(
        &mut v,
        0.25,
        Vec3::new(-0.05, 0.0, 0.08),
        &Terrain::Flat(0.0),
        0.0,
    );
    for k in 0..3 {
        assert_eq!(
            v[k].to_array().map(f32::to_bits),
            bent[k].to_array().map(f32::to_bits),
            "bent vertex {k}"
        );
    }
    assert!((v[3] - bent[3]).length() > 1e-3 && ((v[3] - v[2]).length() - 0.25).abs() < 1e-6);
    let mut root_only = vec![Vec3A::ZERO];
    bend_last_segment(&mut root_only, 0.25, Vec3::X, &Terrain::Flat(0.0), 0.0);
}

/// A billboard whose base lies beside an object's footprint but which leans
/// into the object's box is deflected (Eq. 8): the cells tested reach a
/// blade's length beyond the box (they stopped at its footprint before).
#[test]
fn a_billboard_leaning_into_the_box_from_beside_it_is_deflected() {
    // Eq. 8 is the paper's mode; otherwise billboards follow their blades.
    let text = r#"
[sim]
track_everywhere = false
[field]
patches = [2, 2]
cells_per_patch = 8
cell_size_m = 0.1
[lod]
geometry_m = 0.01
billboard_m = 100.0
[camera]
path = { kind = "static", position = [0.0, 5.0, 0.5] }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.1, 0.05, 0.3] }
path = { kind = "static", position = [0.0, 0.22, 0.0] }
"#;
    let mut sim = trample::scene::Scene::parse(text, "leaning.toml", std::path::Path::new("."))
        .and_then(|s| s.build())
        .expect("scene builds");
    let layout = &sim.field.layout;
    let [gx, gz] = layout.cell_at(0.25, 0.05).expect("inside the field");
    let c = layout.cell_index(gx, gz);
    let cells = &mut sim.field.cells;
    // Lean 45° towards −x: the top edge (the cell's billboard is ≈ 0.34 m
    // tall) ends in the box (y 0.17–0.27 m), its base 0.1 m beyond the
    // footprint's edge.
    let origin = cells.slope_origin[c];
    cells.slope[c] = Vec3::new(-1.0, 1.0, 0.0).normalize() * origin.length();
    let leaning = cells.slope[c];
    let top = trample::deform::billboard::billboard_top(
        cells.base[c],
        leaning,
        cells.height[c],
        &sim.field.terrain,
        trample::field::generate::GROUND_CLEARANCE_M,
    );
    assert!(
        cells.base[c].x > 0.15 && top.x < 0.1,
        "base {} top {top}",
        cells.base[c]
    );
    assert!((0.17..0.27).contains(&top.y), "top {top}");
    sim.step(sim.params.dt_s).unwrap();
    assert_eq!(sim.field.cells.lod[c], trample::field::Lod::Billboard);
    assert!(sim.timings.bbg_cells > 0, "no billboard deflected");
    assert_ne!(
        sim.field.cells.slope[c], leaning,
        "the leaning billboard was not deflected"
    );
}
