//! The broad phase's grid lookup (`patches_under`, issue 16 item 1) lists
//! exactly the patches the all-pairs test (`patches_hit`, every patch
//! against the box) lists, for random object poses and sizes over fields
//! with flat and noisy terrain, including boxes on patch borders, boxes
//! larger than the field and boxes off the field.

mod common;

use common::Rng;
use glam::{Quat, Vec3};
use trample::collision::{patch_rect, patches_hit, patches_under};
use trample::field::{Field, FieldParams, Terrain};
use trample::obb::Obb;

fn field(patches: [u32; 2], terrain: Terrain) -> Field {
    let p = FieldParams {
        patches,
        cells_per_patch: 4,
        ..FieldParams::default()
    };
    Field::generate(&p, terrain).expect("field")
}

fn random_box(rng: &mut Rng, extent: Vec3, size: f32) -> Obb {
    let rot = Quat::from_scaled_axis(rng.vec(1.0).normalize_or(Vec3::X) * rng.f32(0.0, 3.2));
    // Sizes over four decades: a pebble to more than the field.
    let half = Vec3::new(rng.f32(0.0, 1.0), rng.f32(0.0, 1.0), rng.f32(0.0, 1.0))
        .map(|u| size * 10f32.powf(4.0 * u - 3.0));
    Obb {
        center: rng.vec(1.0) * extent,
        axes: [rot * Vec3::X, rot * Vec3::Y, rot * Vec3::Z],
        half,
    }
}

fn assert_same_lists(f: &Field, obb: &Obb, what: &str) -> usize {
    let (mut all, mut grid) = (Vec::new(), Vec::new());
    patches_hit(&f.layout.patch_list, obb, &mut all);
    patches_under(&f.layout, obb, &mut grid);
    assert_eq!(grid, all, "{what}: {obb:?}");
    // The rectangle holds every listed patch.
    if let Some(rect) = patch_rect(&f.layout, obb) {
        assert!(rect.patch_count() >= all.len());
    } else {
        assert!(all.is_empty(), "{what}: no rectangle but {all:?} listed");
    }
    all.len()
}

#[test]
fn grid_lookup_lists_what_the_all_pairs_test_lists() {
    let mut rng = Rng(16);
    let noise = Terrain::Noise {
        amplitude: 0.6,
        wavelength: 1.3,
        seed: 5,
    };
    for (patches, terrain) in [
        ([9, 7], Terrain::Flat(0.0)),
        ([40, 9], noise.clone()),
        ([1, 1], noise),
    ] {
        let f = field(patches, terrain);
        assert!(
            f.layout.patch_overhang_m > 0.0,
            "blades reach out of patches"
        );
        let [ex, ez] = f.params.extent_m();
        let extent = Vec3::new(0.75 * ex, 1.0, 0.75 * ez);
        let (mut listed, mut nonempty) = (0, 0);
        for i in 0..4000 {
            let obb = random_box(&mut rng, extent, ex.min(ez) * 0.1);
            let n = assert_same_lists(&f, &obb, &format!("{patches:?} #{i}"));
            listed += n;
            nonempty += usize::from(n > 0);
        }
        assert!(
            nonempty > 1000,
            "{patches:?}: only {nonempty} boxes listed patches"
        );
        eprintln!("{patches:?}: {listed} patches listed by {nonempty} of 4000 boxes");
    }
}

#[test]
fn grid_lookup_on_patch_borders_and_edges() {
    let f = field([6, 5], Terrain::Flat(0.2));
    let size = f.layout.patch_size();
    let [ox, oz] = f.layout.origin;
    let reach = f.layout.patch_overhang_m;
    let mut checked = 0;
    // Axis-aligned boxes whose faces lie on patch borders, on the overhang's
    // edge, and one float step either side of them.
    for px in 0..=6 {
        for pz in 0..=5 {
            for edge in [0.0, reach, -reach] {
                for half_x in [0.01, 0.5 * size, size] {
                    let x = ox + px as f32 * size + edge + half_x;
                    let z = oz + pz as f32 * size - edge - half_x;
                    for step in [-1.0f32, 0.0, 1.0] {
                        let nudge =
                            |v: f32| f32::from_bits((v.to_bits() as i64 + step as i64) as u32);
                        let obb = Obb {
                            center: Vec3::new(nudge(x), 0.2, nudge(z)),
                            axes: [Vec3::X, Vec3::Y, Vec3::Z],
                            half: Vec3::new(half_x, 0.1, half_x),
                        };
                        assert_same_lists(&f, &obb, "border");
                        checked += 1;
                    }
                }
            }
        }
    }
    // Boxes just off each patch's box, within the SAT's slack (it accepts
    // a gap up to 1e-5 of the summed half extents): listed by both.
    let mut slack_hits = 0;
    for p in &f.layout.patch_list {
        let (a, b) = (p.aabb_min, p.aabb_max);
        let mid = (a + b) * 0.5;
        let half = Vec3::splat(0.3);
        for axis in [0usize, 2] {
            for sign in [-1.0f32, 1.0] {
                let face = if sign > 0.0 { b[axis] } else { a[axis] };
                let sum = 0.5 * (b[axis] - a[axis]) + half[axis];
                let mut center = mid;
                center[axis] = face + sign * (half[axis] + 0.5e-5 * sum);
                let obb = Obb {
                    center,
                    axes: [Vec3::X, Vec3::Y, Vec3::Z],
                    half,
                };
                let mut all = Vec::new();
                patches_hit(&f.layout.patch_list, &obb, &mut all);
                let index = p.coord[1] * f.layout.patches[0] + p.coord[0];
                slack_hits += usize::from(all.contains(&index));
                assert_same_lists(&f, &obb, "within slack");
            }
        }
    }
    assert!(
        slack_hits > 100,
        "{slack_hits} boxes within the slack listed"
    );
    assert!(checked > 1000);
    // Not finite, or far away: nothing, and no rectangle.
    let nan = Obb {
        center: Vec3::new(f32::NAN, 0.0, 0.0),
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half: Vec3::ONE,
    };
    assert_eq!(patch_rect(&f.layout, &nan), None);
    let far = Obb {
        center: Vec3::new(1e30, 0.0, 0.0),
        ..nan
    };
    assert_eq!(patch_rect(&f.layout, &far), None);
    let huge = Obb {
        center: Vec3::ZERO,
        half: Vec3::splat(1e30),
        ..nan
    };
    assert_eq!(assert_same_lists(&f, &huge, "huge"), 30);
}
