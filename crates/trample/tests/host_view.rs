//! The host's camera decides the level of detail and the culling (issue 14,
//! item 1): the same field seen from two host cameras gives the two LOD
//! maps their eyes call for (paper Fig. 1: a cell's level follows its
//! centre's distance to the eye), not the scene camera's; culling follows
//! the host's view-projection; clearing the host view hands both back.

use glam::{Mat4, Vec3};
use trample::Simulation;
use trample::builder::SimulationBuilder;
use trample::camera::{CameraParams, LookAt};
use trample::field::{FieldParams, Lod, LodParams};
use trample::object::PathParams;
use trample::step::{HostView, ViewError};

const LOD: LodParams = LodParams {
    geometry_m: 2.0,
    billboard_m: 4.5,
};

/// 8 × 8 m (4 × 4 patches of 8 × 8 cells of 0.25 m); the scene's own camera
/// hangs 60 m up, from where every cell is ground texture.
fn sim() -> Simulation {
    SimulationBuilder::new()
        .field(FieldParams {
            patches: [4, 4],
            cells_per_patch: 8,
            cell_size_m: 0.25,
            ..FieldParams::default()
        })
        .lod(LOD)
        .camera(CameraParams {
            path: PathParams::Static {
                position: [0.0, 60.0, 1.0],
            },
            look_at: LookAt::Point { at: [0.0; 3] },
            ..CameraParams::default()
        })
        .build()
        .unwrap()
}

/// The levels the paper's rule gives for an eye at `eye`, from the cells'
/// grid coordinates (cell centres on the flat ground at y = 0).
fn expected_map(sim: &Simulation, eye: Vec3) -> Vec<Lod> {
    let l = &sim.field.layout;
    (0..l.cell_count())
        .map(|c| {
            let [gx, gz] = l.cell_coord(c);
            let [x, z] = l.cell_centre(gx, gz);
            let d = Vec3::new(x, 0.0, z).distance(eye);
            if d < LOD.geometry_m {
                Lod::Geometry
            } else if d < LOD.billboard_m {
                Lod::Billboard
            } else {
                Lod::Texture
            }
        })
        .collect()
}

fn view(eye: Vec3, target: Vec3) -> HostView {
    HostView::look_at(eye, target, 1.0, 1.5, 0.1, 100.0).unwrap()
}

#[test]
fn two_host_cameras_give_their_two_lod_maps() {
    let mut sim = sim();
    let dt = sim.params.dt_s;
    sim.step(dt).unwrap();
    assert!(
        sim.field.cells.lod.iter().all(|&l| l == Lod::Texture),
        "from the scene camera, 60 m up, every cell is texture"
    );

    let a = Vec3::new(-3.0, 1.0, -3.0);
    sim.set_view(view(a, Vec3::ZERO)).unwrap();
    sim.step(dt).unwrap();
    let map_a = sim.field.cells.lod.clone();
    assert_eq!(map_a, expected_map(&sim, a));
    assert_eq!(sim.eye(), a);

    let b = Vec3::new(2.5, 1.5, 3.0);
    sim.set_view(view(b, Vec3::ZERO)).unwrap();
    sim.step(dt).unwrap();
    let map_b = sim.field.cells.lod.clone();
    assert_eq!(map_b, expected_map(&sim, b));

    // The two maps are different pictures, each with all three levels.
    assert_ne!(map_a, map_b);
    for map in [&map_a, &map_b] {
        for level in [Lod::Geometry, Lod::Billboard, Lod::Texture] {
            assert!(map.contains(&level), "{level:?}");
        }
    }
    // Counts agree with the map.
    let geometric = map_b.iter().filter(|&&l| l == Lod::Geometry).count();
    assert_eq!(sim.timings.lod.geometry as usize, geometric);

    // Back to the scene camera: texture everywhere again.
    sim.clear_view();
    sim.step(dt).unwrap();
    assert!(sim.field.cells.lod.iter().all(|&l| l == Lod::Texture));
}

#[test]
fn culling_follows_the_host_view_projection_at_once() {
    let mut sim = sim();
    let patches = sim.field.layout.patch_list.len();
    // Looking down at the whole field: every patch visible.
    sim.set_view(view(Vec3::new(0.0, 20.0, 0.5), Vec3::ZERO))
        .unwrap();
    assert_eq!(sim.visible.iter().filter(|&&v| v).count(), patches);
    // From the -x edge looking away from the field: nothing visible, before
    // any step (a paused host draws the right patches).
    sim.set_view(view(Vec3::new(-5.0, 1.0, 0.0), Vec3::new(-20.0, 1.0, 0.0)))
        .unwrap();
    assert_eq!(sim.visible.iter().filter(|&&v| v).count(), 0);
    assert_eq!(sim.timings.visible_patches, 0);
    // From the -x edge looking along +x with a narrow lens: some, not all.
    let eye = Vec3::new(-5.0, 1.0, -3.0);
    let narrow = HostView::look_at(eye, Vec3::new(5.0, 0.0, -3.0), 0.3, 1.0, 0.1, 100.0).unwrap();
    sim.set_view(narrow).unwrap();
    let seen = sim.visible.iter().filter(|&&v| v).count();
    assert!(seen > 0 && seen < patches, "{seen} of {patches}");
    // The renderer's matrix is the host's, whatever aspect it draws at.
    assert_eq!(sim.view_proj(3.0), narrow.view_proj);
}

#[test]
fn a_host_view_that_is_not_a_camera_is_refused() {
    let mut sim = sim();
    let good = view(Vec3::new(0.0, 3.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    sim.set_view(good).unwrap();
    let bad_eye = HostView {
        eye: Vec3::NAN,
        ..good
    };
    assert!(matches!(
        sim.set_view(bad_eye),
        Err(ViewError::NonFiniteEye { .. })
    ));
    let flat = HostView {
        view_proj: Mat4::ZERO,
        ..good
    };
    assert!(matches!(
        sim.set_view(flat),
        Err(ViewError::BadMatrix { .. })
    ));
    assert!(HostView::look_at(Vec3::ZERO, Vec3::X, 0.0, 1.0, 0.1, 10.0).is_err());
    // Refused views change nothing.
    assert_eq!(sim.host_view(), Some(&good));
}
