//! Deformation invariants over a long, busy run (DESIGN §6): every segment
//! keeps its rest length (relative error < 1e-4), roots never move, no
//! vertex goes below the terrain, every value stays finite — over 10,000
//! steps of several objects, propagation, transitions and recovery.

mod common;
use common::sim_from;

const BUSY: &str = r#"
[field]
patches = [2, 2]
cells_per_patch = 16
blades_per_cell = 2
terrain = { kind = "noise", amplitude_m = 0.3, wavelength_m = 2.0, seed = 4 }
[lod]
geometry_m = 2.0
billboard_m = 3.0
[sim]
precision = 5
recovery_s = 1.5
att = 0.7
threshold = 0.1
[camera]
path = { kind = "circle", center = [0.0, 1.5, 0.0], radius_m = 2.0, period_s = 7.0 }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "circle", center = [0.0, 0.4, 0.0], radius_m = 1.0, period_s = 3.0 }
[[objects]]
name = "box"
shape = { kind = "box", half_extents_m = [0.3, 0.2, 0.5] }
orientation = "face_motion"
path = { kind = "circle", center = [0.3, 0.25, -0.2], radius_m = 0.8, period_s = 2.0 }
[[objects]]
name = "knot"
shape = { kind = "knot", size_m = 0.9 }
path = { kind = "polyline", points = [[-1.6, 0.3, -1.2], [1.6, 0.3, 1.2], [-1.6, 0.3, 1.2], [1.6, 0.3, -1.2]], speed_m_s = 1.5 }
"#;

#[test]
fn ten_thousand_busy_steps_keep_every_invariant() {
    let mut sim = sim_from(BUSY);
    let bl_count = sim.field.blades.count;
    let n = sim.field.blades.segments;
    let roots: Vec<_> = (0..bl_count)
        .map(|b| sim.field.blades.vertex(b, 0))
        .collect();
    let mut worst_len = 0.0f32;
    let mut touched = 0;
    for step in 0..10_000 {
        sim.step(sim.params.dt_s).unwrap();
        if step % 50 != 49 {
            continue;
        }
        let bl = &sim.field.blades;
        for (b, root) in roots.iter().enumerate() {
            assert_eq!(
                bl.vertex(b, 0),
                *root,
                "root of blade {b} moved at step {step}"
            );
            for k in 1..=n {
                let v = bl.vertex(b, k);
                assert!(
                    v.is_finite(),
                    "blade {b} vertex {k} not finite at step {step}"
                );
                let ground = sim.field.terrain.height_at(v.x, v.z);
                assert!(
                    v.y >= ground,
                    "blade {b} vertex {k} below ground at step {step}"
                );
                let len = (v - bl.vertex(b, k - 1)).length();
                worst_len = worst_len.max((len - bl.seg_len[b]).abs() / bl.seg_len[b]);
            }
        }
        for c in 0..sim.field.cells.slope.len() {
            assert!(sim.field.cells.slope[c].is_finite());
        }
        touched = touched.max(sim.blades_away_from_rest());
    }
    assert!(worst_len < 1e-4, "segment length drifted by {worst_len}");
    assert!(
        touched > 100,
        "the scene must actually be busy ({touched} blades displaced at most)"
    );
}
