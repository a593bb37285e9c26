//! Buffers a host can read (issue 14, item 2): blade vertices as bytes in
//! the documented layout without a copy, and the blades and cells the last
//! step changed — every blade whose position bits moved and every cell
//! whose level or billboard slope changed is listed, once, in order, so a
//! host that uploads only those stays in step with the simulation.

mod common;
use common::*;
use glam::Vec3;
use trample::field::BladeVertex;

/// A ball rolling across, recovering grass, LOD bands near the camera so
/// cells change level and billboards bend too.
const SCENE: &str = r#"
[field]
patches = [4, 4]
cells_per_patch = 12
cell_size_m = 0.1
[lod]
geometry_m = 1.5
billboard_m = 3.0
[sim]
recovery_s = 0.4
[camera]
path = { kind = "line", from = [-2.0, 1.0, 1.2], to = [2.0, 1.0, 1.2], duration_s = 1.5 }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.35 }
orientation = "rolling"
path = { kind = "line", from = [-2.8, 0.35, 0.0], to = [2.8, 0.35, 0.0], duration_s = 1.5 }
"#;

#[test]
fn every_blade_and_cell_a_step_changes_is_listed_once_in_order() {
    let mut sim = sim_from(SCENE);
    let dt = sim.params.dt_s;
    let (mut blades_changed, mut cells_changed, mut steps_with_slopes) = (0, 0, 0);
    for frame in 0..150 {
        let pos = position_bits(&sim);
        let slope: Vec<Vec3> = sim.field.cells.slope.clone();
        let lod = sim.field.cells.lod.clone();
        sim.step(dt).unwrap();

        let bl = &sim.field.blades;
        let listed: Vec<u32> = sim.changed_blades().collect();
        assert!(
            listed.windows(2).all(|w| w[0] < w[1]),
            "frame {frame}: blades not ascending or listed twice"
        );
        for b in 0..bl.count {
            let moved = (0..=bl.segments).any(|k| {
                let i = k * bl.count + b;
                bl.pos[i].pos.map(f32::to_bits) != pos[i]
            });
            if moved {
                assert!(
                    listed.binary_search(&(b as u32)).is_ok(),
                    "frame {frame}: blade {b} moved but is not listed"
                );
                blades_changed += 1;
            }
        }
        assert!(
            listed.len() < bl.count,
            "the list is sparse, not the whole field"
        );

        let cells = &sim.field.cells;
        let listed: Vec<u32> = sim.changed_cells().collect();
        assert!(listed.windows(2).all(|w| w[0] < w[1]));
        let mut slopes = 0;
        for c in 0..cells.lod.len() {
            let slope_moved = cells.slope[c].to_array().map(f32::to_bits)
                != slope[c].to_array().map(f32::to_bits);
            if slope_moved || cells.lod[c] != lod[c] {
                assert!(
                    listed.binary_search(&(c as u32)).is_ok(),
                    "frame {frame}: cell {c} changed but is not listed"
                );
                cells_changed += 1;
                slopes += usize::from(slope_moved);
            }
        }
        steps_with_slopes += usize::from(slopes > 0);
    }
    // The run exercised what it checks: bent and recovering blades, cells
    // changing level, billboards bending.
    assert!(blades_changed > 1000, "{blades_changed}");
    assert!(cells_changed > 100, "{cells_changed}");
    assert!(steps_with_slopes > 5, "{steps_with_slopes}");
}

#[test]
fn vertex_bytes_are_the_documented_layout_without_a_copy() {
    let mut sim = sim_from(SCENE);
    sim.run(40).unwrap();
    let bl = &sim.field.blades;
    let bytes = bl.pos_bytes();
    assert_eq!(bytes.len(), 16 * bl.count * (bl.segments + 1));
    assert_eq!(bytes.as_ptr(), bl.pos.as_ptr().cast::<u8>(), "no copy");
    for b in [0, 1, bl.count / 2, bl.count - 1] {
        for k in 0..=bl.segments {
            let at = 16 * (k * bl.count + b);
            let f = |i: usize| {
                f32::from_ne_bytes(bytes[at + 4 * i..at + 4 * i + 4].try_into().unwrap())
            };
            let v = bl.vertex(b, k);
            assert_eq!([f(0), f(1), f(2)], v.to_array(), "blade {b} vertex {k}");
            assert_eq!(f(3), 0.0, "padding");
        }
    }
    assert_eq!(std::mem::size_of::<BladeVertex>(), 16);
    assert_eq!(bl.rest_bytes().len(), bytes.len());
}
