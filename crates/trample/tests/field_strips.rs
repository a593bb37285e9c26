//! Level of detail and frustum culling by strips of patches (issue 16 item
//! 1: per-step work over the whole field only where the bands and the
//! frustum's sides cross it) give the same result, bit for bit, as the
//! passes that visit every patch (`classify_cells_by_patch`,
//! `cull_patches_each`): over a camera that stands still, creeps, and jumps,
//! on a field whose rows do not divide into whole strips.

mod common;

use common::Rng;
use glam::Vec3;
use glam::camera::rh::{proj::directx::perspective, view::look_at_mat4};
use trample::field::{
    Field, FieldParams, Frustum, Lod, LodParams, Terrain, classify_cells, classify_cells_by_patch,
    cull_patches, cull_patches_each,
};

fn field() -> Field {
    let p = FieldParams {
        // 40 patches a row: strips of 16, 16 and 8.
        patches: [40, 9],
        cells_per_patch: 4,
        ..FieldParams::default()
    };
    let terrain = Terrain::Noise {
        amplitude: 0.4,
        wavelength: 1.1,
        seed: 3,
    };
    Field::generate(&p, terrain).expect("field")
}

/// Viewpoints: still, creeping, jumping, far away and high above.
fn viewpoints(rng: &mut Rng, n: usize) -> Vec<Vec3> {
    let mut eye = Vec3::new(0.0, 1.0, 0.0);
    (0..n)
        .map(|i| {
            match i % 7 {
                0 | 1 => {}                                                    // still
                2..=4 => eye += rng.vec(0.05) * Vec3::new(1.0, 0.2, 1.0),      // creeping
                5 => eye = rng.vec(12.0) * Vec3::new(1.0, 0.2, 0.5) + Vec3::Y, // a jump
                _ => eye = rng.vec(60.0) + Vec3::Y * 30.0,                     // far or high
            }
            eye
        })
        .collect()
}

#[test]
fn lod_by_strips_equals_lod_by_patch() {
    let (mut a, mut b) = (field(), field());
    let lod = LodParams {
        geometry_m: 2.0,
        billboard_m: 5.0,
    };
    let mut rng = Rng(7);
    let (mut changed, mut settled_steps) = (0, 0);
    for (i, eye) in viewpoints(&mut rng, 700).into_iter().enumerate() {
        let (mut ca, mut cb) = (Vec::new(), Vec::new());
        let na = classify_cells(&a.layout, &mut a.cells, eye, &lod, &mut ca);
        let nb = classify_cells_by_patch(&b.layout, &mut b.cells, eye, &lod, &mut cb);
        assert_eq!(na, nb, "step {i}, eye {eye}: counts");
        assert_eq!(ca, cb, "step {i}, eye {eye}: changes");
        assert!(a.cells.lod == b.cells.lod, "step {i}: levels");
        assert_eq!(
            a.cells.patch_lod, b.cells.patch_lod,
            "step {i}: patch levels"
        );
        changed += ca.len();
        settled_steps += usize::from(ca.is_empty());
        // Every cell at the level of its own distance (the specification).
        if i % 50 == 0 {
            for (c, base) in a.cells.base.iter().enumerate() {
                assert_eq!(a.cells.lod[c], lod.level(base.distance(eye)), "cell {c}");
            }
        }
    }
    assert!(
        changed > 10_000 && settled_steps > 100,
        "{changed} changes, {settled_steps} still steps"
    );
}

/// Every cell at the level of its own distance to `eye` (the specification).
fn assert_levels(f: &Field, eye: Vec3, lod: &LodParams, what: &str) {
    for (c, base) in f.cells.base.iter().enumerate() {
        assert_eq!(
            f.cells.lod[c],
            lod.level(base.distance(eye)),
            "{what}: cell {c}"
        );
    }
}

/// The last classification is reused only for the same viewpoint and the
/// same distances: new distances at the same eye classify again, and
/// levels written another way (as a GPU read-back writes them) followed by
/// `Cells::levels_written` are put right by the next classification, even
/// where a patch or strip looked settled before.
#[test]
fn reuse_is_keyed_by_viewpoint_and_distances() {
    let mut f = field();
    let eye = Vec3::new(0.5, 1.0, -0.3);
    let near = LodParams {
        geometry_m: 2.0,
        billboard_m: 5.0,
    };
    let far = LodParams {
        geometry_m: 6.0,
        billboard_m: 12.0,
    };
    let mut changes = Vec::new();
    classify_cells(&f.layout, &mut f.cells, eye, &near, &mut changes);
    assert_levels(&f, eye, &near, "first pass");
    changes.clear();
    classify_cells(&f.layout, &mut f.cells, eye, &far, &mut changes);
    assert!(!changes.is_empty());
    assert_levels(&f, eye, &far, "same eye, new distances");
    f.cells.lod.fill(Lod::Geometry);
    f.cells.levels_written(&f.layout);
    changes.clear();
    classify_cells(&f.layout, &mut f.cells, eye, &far, &mut changes);
    assert_levels(&f, eye, &far, "after levels written elsewhere");
}

#[test]
fn culling_by_strips_equals_culling_by_patch() {
    let f = field();
    let mut rng = Rng(11);
    let (mut visible, mut reference) = (Vec::new(), Vec::new());
    let (mut some, mut all, mut none) = (0, 0, 0);
    let patches = f.layout.patch_list.len() as u32;
    for i in 0..1500 {
        let eye = if i % 5 == 0 {
            rng.vec(60.0) + Vec3::Y * 30.0
        } else {
            rng.vec(9.0) * Vec3::new(1.0, 0.1, 0.4) + Vec3::Y
        };
        // Mostly looking at the field, sometimes anywhere.
        let target = if i % 4 == 0 {
            eye + rng.vec(1.0).normalize_or(Vec3::X)
        } else {
            rng.vec(8.0) * Vec3::new(1.0, 0.0, 0.25)
        };
        let up = if (target - eye).normalize().y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let fov = rng.f32(0.3, 1.6);
        let far = rng.f32(3.0, 200.0);
        let proj = perspective(fov, rng.f32(0.5, 2.5), 0.05, far);
        let frustum = Frustum::from_view_proj(proj * look_at_mat4(eye, target, up));
        let n = cull_patches(&f.layout, &frustum, &mut visible);
        let m = cull_patches_each(&f.layout.patch_list, &frustum, &mut reference);
        assert_eq!(visible, reference, "view {i}");
        assert_eq!(n, m, "view {i}");
        some += usize::from(n > 0 && n < patches);
        all += usize::from(n == patches);
        none += usize::from(n == 0);
    }
    eprintln!("{some} partial views, {all} whole, {none} empty");
    assert!(
        some > 500 && all > 20 && none > 50,
        "{some} partial views, {all} whole, {none} empty"
    );
}
