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

/// Geometry → billboard → geometry, by hand. A track bent into a cell of
/// four blades (rest: vertical, 4 segments of 0.1 m, height h = 0.4): two
/// blades in the track lie straight along (0.6, 0.8, 0) and (0, 0.8, 0.6),
/// two at its edge are untouched.
///
/// - Eq. 9–10 (per unit rest height): offsets (0.24, −0.08, 0)/0.4 =
///   (0.6, −0.2, 0), (0, −0.2, 0.6), 0, 0.
/// - Eq. 11: their mean `off^b` = (0.15, −0.1, 0.15).
/// - Eq. 12: `slope^b` = (0, 1, 0) + off^b = (0.15, 0.9, 0.15), which
///   points along the blades' mean tip (0.06, 0.36, 0.06).
/// - Back to geometry after the blades recovered under the billboard
///   (mean blade offset 0): Eq. 13 gives `off^b` again, the force
///   v1 = off^b · h = (0.06, −0.04, 0.06) on the last segment.
/// - Eq. 5 (num = 1) with AB = (0, 0.4, 0): base = v1 less its part along
///   AB = (0.06, 0, 0.06); the tip (0, 0.4, 0) + base, brought back to
///   0.1 m from V3 = (0, 0.3, 0) (Fig. 7): V3 + 0.1 · (0.06, 0.1, 0.06) /
///   |(0.06, 0.1, 0.06)| = (0.0457496, 0.3762493, 0.0457496).
#[test]
fn transition_round_trip_matches_eq5_by_hand() {
    let (h, seg) = (0.4, 0.1);
    let root = |i: usize| Vec3A::new(i as f32 * 0.1, 0.0, 0.0);
    let straight = |i: usize, dir: Vec3A| -> Vec<Vec3A> {
        (0..=4).map(|k| root(i) + dir * (k as f32 * seg)).collect()
    };
    let rest: Vec<Vec<Vec3A>> = (0..4).map(|i| straight(i, Vec3A::Y)).collect();
    let track = [
        straight(0, Vec3A::new(0.6, 0.8, 0.0)),
        straight(1, Vec3A::new(0.0, 0.8, 0.6)),
        rest[2].clone(),
        rest[3].clone(),
    ];
    let tip = |b: &[Vec3A]| Vec3::from(b[4] - b[0]);
    let offsets: Vec<Vec3> = track
        .iter()
        .zip(&rest)
        .map(|(b, r)| blade_offset(tip(b), tip(r)))
        .collect();
    assert!(close(offsets[0], Vec3::new(0.6, -0.2, 0.0), 1e-6));
    assert!(close(offsets[1], Vec3::new(0.0, -0.2, 0.6), 1e-6));
    let off_b = mean_offset(offsets.iter().copied());
    assert!(close(off_b, Vec3::new(0.15, -0.1, 0.15), 1e-6), "{off_b}");
    let origin = Vec3::Y; // mean rest (V_n − V_0) / mean rest height
    let slope = slope_from_offset(origin, off_b);
    assert!(close(slope, Vec3::new(0.15, 0.9, 0.15), 1e-6), "{slope}");
    let mean_tip = track.iter().map(|b| tip(b)).sum::<Vec3>() / 4.0;
    assert!(
        close(slope.normalize(), mean_tip.normalize(), 1e-6),
        "the billboard leans like its blades: {slope} vs {mean_tip}"
    );

    // The blades recovered while the cell was a billboard: the whole
    // offset of Eq. 13 acts on their last segment.
    let back = offset_from_slope(slope, origin);
    assert!(close(back, off_b, 1e-6), "Eq. 13 undoes Eq. 12: {back}");
    let blades_offset = Vec3::ZERO;
    let v1 = (back - blades_offset) * h;
    for (i, r) in rest.iter().enumerate() {
        let mut blade = r.clone();
        bend_last_segment(&mut blade, seg, v1, &Terrain::Flat(0.0), 0.0);
        assert_eq!(blade[..4], r[..4], "blade {i}: only the tip moves");
        let expected = root(i) + Vec3A::new(0.045_749_57, 0.376_249_3, 0.045_749_57);
        assert!(
            (blade[4] - expected).length() < 1e-6,
            "blade {i}: tip {} where Eq. 5 by hand gives {expected}",
            blade[4]
        );
    }
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
