//! A fast object is sub-stepped, not tunnelled (DESIGN §9): a small ball
//! crossing the field at 36 m/s with 30 steps/s (1.2 m per step, three times
//! its 0.4 m diameter) still hits every blade on its path; with sub-stepping
//! switched off (`max_substeps = 1`) it skips blades, which shows the test
//! can fail.

mod common;
use common::{root_xz, sim_from};

fn hit_share_on_path(max_substeps: u32) -> (f32, u32) {
    let toml = format!(
        r#"
[field]
patches = [4, 2]
cells_per_patch = 16
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
precision = 7
max_substeps = {max_substeps}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 5.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "bullet"
shape = {{ kind = "sphere", radius_m = 0.2 }}
orientation = "rolling"
path = {{ kind = "line", from = [-4.0, 0.2, 0.0], to = [4.0, 0.2, 0.0], duration_s = 0.22222222 }}
"#
    );
    let mut sim = sim_from(&toml);
    let mut substeps = 0;
    for _ in 0..10 {
        substeps = substeps.max(sim.step(1.0 / 30.0).unwrap().substeps);
    }
    let (mut on, mut hit) = (0, 0);
    for b in 0..sim.field.blades.count {
        let (x, z) = root_xz(&sim, b);
        if x.abs() < 2.8 && z.abs() < 0.08 {
            on += 1;
            hit += usize::from(sim.class[b] == 1);
        }
    }
    assert!(on > 40);
    (hit as f32 / on as f32, substeps)
}

#[test]
fn fast_ball_is_sub_stepped_and_misses_no_blade() {
    let (with, substeps) = hit_share_on_path(16);
    let (without, one) = hit_share_on_path(1);
    println!("hit share on the path: {with:.3} with {substeps} sub-steps, {without:.3} without");
    assert!(substeps >= 2 && one == 1);
    assert!(
        with > 0.99,
        "sub-stepped ball hit only {with:.3} of the blades on its path"
    );
    assert!(
        without < 0.9,
        "without sub-steps the ball should skip blades (hit {without:.3})"
    );
}
