//! The primitive collision queries of paper §4 / DESIGN §4: segment vs OBB
//! (ref. [16]), segment vs triangle, the exact reference (inside test and
//! segment vs mesh), and the broad phase over patches.

mod collision_meshes;

use collision_meshes::*;
use glam::{Quat, Vec3};
use trample::collision::{
    obb_may_overlap_aabb, obb_overlaps_aabb, patches_hit, point_inside,
    segment_crosses_triangle_interior, segment_hits_box_local, segment_hits_exact,
    segment_hits_obb, segment_hits_triangle, world_obb,
};
use trample::field::Patch;
use trample::obb::{DEFAULT_MAX_DEPTH, Obb, ObbTree};
use trample::object::Pose;

fn unit_box() -> Obb {
    Obb {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half: Vec3::ONE,
    }
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

#[test]
fn segment_obb_hand_cases() {
    let b = unit_box();
    let cases = [
        ("through", v(-2.0, 0.0, 0.0), v(2.0, 0.0, 0.0), true),
        ("through, skew", v(-2.0, -1.5, 0.3), v(2.0, 1.5, -0.3), true),
        ("miss above", v(-2.0, 2.0, 0.0), v(2.0, 2.0, 0.0), false),
        (
            "miss, line hits but segment stops short",
            v(-3.0, 0.0, 0.0),
            v(-1.01, 0.0, 0.0),
            false,
        ),
        ("lies on a face", v(-2.0, 1.0, 0.0), v(2.0, 1.0, 0.0), true),
        ("starts on a face", v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0), true),
        ("ends on a face", v(0.0, -3.0, 0.0), v(0.0, -1.0, 0.0), true),
        (
            "just off a face",
            v(1.0001, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            false,
        ),
        (
            "touches a corner only",
            v(0.0, 2.0, 2.0),
            v(2.0, 0.0, 0.0),
            true,
        ),
        (
            "passes a corner",
            v(0.0, 2.01, 2.01),
            v(2.0, 0.01, 0.01),
            false,
        ),
        ("along an edge", v(1.0, 1.0, -5.0), v(1.0, 1.0, 5.0), true),
        (
            "parallel to x slab, inside y z",
            v(-2.0, 0.5, 0.3),
            v(2.0, 0.5, 0.3),
            true,
        ),
        (
            "parallel to x slab, outside y",
            v(-2.0, 1.5, 0.0),
            v(2.0, 1.5, 0.0),
            false,
        ),
        (
            "parallel, beyond the x range",
            v(2.0, 0.0, 0.0),
            v(3.0, 0.0, 0.0),
            false,
        ),
        (
            "inside entirely",
            v(-0.5, 0.2, 0.1),
            v(0.5, -0.2, 0.3),
            true,
        ),
        (
            "zero length inside",
            v(0.5, 0.5, 0.5),
            v(0.5, 0.5, 0.5),
            true,
        ),
        (
            "zero length on surface",
            v(1.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            true,
        ),
        (
            "zero length outside",
            v(1.5, 0.0, 0.0),
            v(1.5, 0.0, 0.0),
            false,
        ),
        (
            "diagonal, misses the edge x = y = 1",
            v(2.1, 0.0, 0.0),
            v(0.0, 2.1, 0.0),
            false,
        ),
        (
            "diagonal, clips the edge x = y = 1",
            v(1.9, 0.0, 0.0),
            v(0.0, 1.9, 0.0),
            true,
        ),
    ];
    for (what, p0, p1, want) in cases {
        assert_eq!(segment_hits_obb(p0, p1, &b), want, "{what}");
        assert_eq!(segment_hits_obb(p1, p0, &b), want, "{what}, reversed");
        assert_eq!(
            segment_hits_box_local(p0, p1, b.half),
            want,
            "{what}, local"
        );
    }
}

#[test]
fn segment_obb_rejects_non_finite() {
    let b = unit_box();
    for bad in [
        Vec3::NAN,
        v(f32::NAN, 0.0, 0.0),
        v(f32::INFINITY, 0.0, 0.0),
        v(0.0, f32::NEG_INFINITY, 0.0),
    ] {
        assert!(!segment_hits_obb(bad, Vec3::ZERO, &b), "{bad}");
        assert!(!segment_hits_obb(Vec3::ZERO, bad, &b), "{bad}");
        assert!(!segment_hits_box_local(bad, Vec3::ZERO, b.half), "{bad}");
        assert!(!segment_hits_box_local(bad, bad, b.half), "{bad}");
    }
}

#[test]
fn segment_obb_rotated_box() {
    // A long thin box along the diagonal of the x–z plane.
    let rot = Quat::from_rotation_y(std::f32::consts::FRAC_PI_4);
    let obb = Obb {
        center: v(0.5, 0.0, 0.0),
        axes: [rot * Vec3::X, rot * Vec3::Y, rot * Vec3::Z],
        half: v(2.0, 0.1, 0.1),
    };
    let along = obb.axes[0] * 1.5 + obb.center;
    assert!(
        segment_hits_obb(along - Vec3::Y, along + Vec3::Y, &obb),
        "vertical blade on the box's axis"
    );
    let beside = obb.center + v(1.5, 0.0, 0.0);
    assert!(
        !segment_hits_obb(beside - Vec3::Y, beside + Vec3::Y, &obb),
        "inside the AABB, outside the OBB"
    );
    // Same answers as the local test on transformed endpoints, for many
    // random segments.
    let mut rng = Rng::new(5);
    for _ in 0..10_000 {
        let (p0, p1) = (rng.in_cube(3.0), rng.in_cube(3.0));
        let local = segment_hits_box_local(obb.to_box(p0), obb.to_box(p1), obb.half);
        // Skip the few segments within rounding of touching.
        let grown = Obb {
            half: obb.half + 1e-4,
            ..obb
        };
        let shrunk = Obb {
            half: obb.half - 1e-4,
            ..obb
        };
        if segment_hits_obb(p0, p1, &grown) == segment_hits_obb(p0, p1, &shrunk) {
            assert_eq!(segment_hits_obb(p0, p1, &obb), local, "{p0} {p1}");
        }
    }
}

const TRI: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

#[test]
fn segment_triangle_hand_cases() {
    let cases = [
        (
            "through the interior",
            v(0.2, 0.2, -1.0),
            v(0.2, 0.2, 1.0),
            true,
        ),
        (
            "slanted through",
            v(-0.5, 0.0, -1.0),
            v(0.9, 0.4, 1.0),
            true,
        ),
        (
            "misses outside the hypotenuse",
            v(0.8, 0.8, -1.0),
            v(0.8, 0.8, 1.0),
            false,
        ),
        (
            "stops short of the plane",
            v(0.2, 0.2, -1.0),
            v(0.2, 0.2, -0.01),
            false,
        ),
        (
            "ends on the plane",
            v(0.2, 0.2, -1.0),
            v(0.2, 0.2, 0.0),
            true,
        ),
        (
            "starts on the plane",
            v(0.2, 0.2, 0.0),
            v(0.2, 0.2, 1.0),
            true,
        ),
        (
            "through the hypotenuse",
            v(0.5, 0.5, -1.0),
            v(0.5, 0.5, 1.0),
            true,
        ),
        (
            "through an edge on an axis",
            v(0.5, 0.0, -1.0),
            v(0.5, 0.0, 1.0),
            true,
        ),
        (
            "through a vertex",
            v(0.0, 0.0, -1.0),
            v(0.0, 0.0, 1.0),
            true,
        ),
        (
            "just outside an edge",
            v(0.5, -1e-4, -1.0),
            v(0.5, -1e-4, 1.0),
            false,
        ),
        (
            "coplanar, overlapping",
            v(-0.5, 0.2, 0.0),
            v(0.5, 0.2, 0.0),
            true,
        ),
        (
            "coplanar, crossing both sides",
            v(-1.0, 0.1, 0.0),
            v(2.0, 0.1, 0.0),
            true,
        ),
        (
            "coplanar, outside",
            v(-0.5, 2.0, 0.0),
            v(0.5, 2.0, 0.0),
            false,
        ),
        (
            "coplanar, along an edge",
            v(-1.0, 0.0, 0.0),
            v(2.0, 0.0, 0.0),
            true,
        ),
        (
            "parallel, above",
            v(-0.5, 0.2, 0.1),
            v(0.5, 0.2, 0.1),
            false,
        ),
        (
            "point on the triangle",
            v(0.3, 0.3, 0.0),
            v(0.3, 0.3, 0.0),
            true,
        ),
        (
            "point off the triangle",
            v(0.3, 0.3, 0.1),
            v(0.3, 0.3, 0.1),
            false,
        ),
    ];
    for (what, p0, p1, want) in cases {
        assert_eq!(segment_hits_triangle(p0, p1, &TRI), want, "{what}");
        assert_eq!(
            segment_hits_triangle(p1, p0, &TRI),
            want,
            "{what}, reversed"
        );
        let flipped = [TRI[0], TRI[2], TRI[1]];
        assert_eq!(
            segment_hits_triangle(p0, p1, &flipped),
            want,
            "{what}, flipped winding"
        );
    }
    assert!(!segment_hits_triangle(
        v(0.2, 0.2, -1.0),
        v(0.2, 0.2, 1.0),
        &[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]
    ));
    assert!(!segment_hits_triangle(Vec3::NAN, Vec3::ZERO, &TRI));
    assert!(!segment_hits_triangle(
        v(0.2, 0.2, -1.0),
        v(0.2, 0.2, 1.0),
        &[Vec3::NAN, Vec3::X, Vec3::Y]
    ));
}

#[test]
fn strict_crossing_excludes_the_boundary() {
    assert!(segment_crosses_triangle_interior(
        v(0.2, 0.2, -1.0),
        v(0.2, 0.2, 1.0),
        &TRI
    ));
    assert!(!segment_crosses_triangle_interior(
        v(0.5, 0.5, -1.0),
        v(0.5, 0.5, 1.0),
        &TRI
    ));
    assert!(!segment_crosses_triangle_interior(
        v(0.2, 0.2, -1.0),
        v(0.2, 0.2, 0.0),
        &TRI
    ));
    assert!(!segment_crosses_triangle_interior(
        v(-0.5, 0.2, 0.0),
        v(0.5, 0.2, 0.0),
        &TRI
    ));
}

#[test]
fn segment_through_a_shared_edge_hits_a_triangle() {
    // Exactly on the shared diagonal of a unit square: both triangles count.
    let lower = [Vec3::ZERO, Vec3::X, Vec3::ONE.with_z(0.0)];
    let upper = [Vec3::ZERO, Vec3::ONE.with_z(0.0), Vec3::Y];
    for p in [v(0.25, 0.25, 0.0), v(0.5, 0.5, 0.0), v(0.75, 0.75, 0.0)] {
        let d = v(0.125, -0.25, 1.0); // exact in f32: the segment meets z = 0 at p
        let (p0, p1) = (p - d, p + d);
        assert!(segment_hits_triangle(p0, p1, &lower), "{p}");
        assert!(segment_hits_triangle(p0, p1, &upper), "{p}");
    }
    // Random segments crossing a closed mesh through random points of its
    // edges (within f32 rounding): every one hits a triangle.
    let mesh = uv_sphere(1.0, 8, 16);
    let tris: Vec<[Vec3; 3]> = (0..mesh.triangle_count())
        .map(|i| mesh.triangle(i))
        .collect();
    let mut rng = Rng::new(17);
    for _ in 0..3000 {
        let t = tris[(rng.next_u64() % tris.len() as u64) as usize];
        let k = (rng.next_u64() % 3) as usize;
        let p = t[k].lerp(t[(k + 1) % 3], rng.unit());
        // Across the surface: mostly along the outward normal of the unit sphere.
        let d = (p.normalize() + rng.direction() * 0.6) * rng.range(0.01, 0.3);
        let (p0, p1) = (p - d, p + d);
        assert!(
            tris.iter().any(|t| segment_hits_triangle(p0, p1, t)),
            "{p0} {p1}"
        );
    }
}

/// Analytic inside tests with a band of `margin` around the surface where
/// the tessellation may decide either way; `None` in the band.
fn analytic_inside(name: &str, p: Vec3) -> Option<bool> {
    let margin = 0.03;
    match name {
        "sphere" => {
            let r = p.length();
            (r < 1.0 - margin || r > 1.0 + margin).then_some(r < 1.0)
        }
        "torus" => {
            let ring = Vec3::new(p.x, 0.0, p.z).normalize_or_zero();
            let d = (p - ring).length();
            (d < 0.35 - margin || d > 0.35 + margin).then_some(d < 0.35)
        }
        _ => {
            // box centred at (0.3, -0.2, 0.1), half (1, 0.5, 0.25)
            let q = (p - Vec3::new(0.3, -0.2, 0.1)).abs() - Vec3::new(1.0, 0.5, 0.25);
            let m = q.max_element();
            (m.abs() > margin * 0.1).then_some(m < 0.0)
        }
    }
}

#[test]
fn point_inside_matches_the_analytic_shape() {
    let meshes = [
        ("sphere", uv_sphere(1.0, 24, 48)),
        ("torus", torus(1.0, 0.35, 64, 32)),
        (
            "box",
            box_mesh(Vec3::new(0.3, -0.2, 0.1), Vec3::new(1.0, 0.5, 0.25), 4),
        ),
    ];
    for (name, mesh) in meshes {
        let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        assert!(tree.closed);
        let mut rng = Rng::new(23);
        let (mut inside, mut checked) = (0, 0);
        for _ in 0..20_000 {
            let p = rng.in_cube(1.6);
            if let Some(want) = analytic_inside(name, p) {
                assert_eq!(point_inside(&tree, p), want, "{name}: {p}");
                inside += usize::from(want);
                checked += 1;
            }
        }
        assert!(
            inside > 500 && checked > 15_000,
            "{name}: {inside} inside of {checked}"
        );
    }
}

#[test]
fn point_inside_hand_cases() {
    let tree = ObbTree::build(&uv_sphere(1.0, 24, 48), DEFAULT_MAX_DEPTH);
    assert!(point_inside(&tree, Vec3::ZERO));
    assert!(
        point_inside(&tree, v(0.0, 0.98, 0.0)),
        "just under the north pole"
    );
    assert!(
        point_inside(&tree, v(0.0, -0.98, 0.0)),
        "just above the south pole"
    );
    assert!(
        point_inside(&tree, v(0.97, 0.0, 0.0)),
        "near the surface, inside"
    );
    assert!(
        !point_inside(&tree, v(1.02, 0.0, 0.0)),
        "near the surface, outside"
    );
    assert!(!point_inside(&tree, v(0.0, -1.5, 0.0)), "below");
    assert!(
        !point_inside(&tree, v(0.5, 0.95, 0.0)),
        "above, in the root box: the ray crosses twice"
    );
    assert!(
        !point_inside(&tree, v(5.0, 5.0, 5.0)),
        "outside the root box"
    );
    assert!(!point_inside(&tree, Vec3::NAN));
    // Not defined for an open mesh.
    let sheet = ObbTree::build(&wavy_sheet(8), DEFAULT_MAX_DEPTH);
    assert!(!sheet.closed);
    assert!(!point_inside(&sheet, v(0.0, -0.5, 0.0)));
    // Torus hole: inside the root box, outside the mesh.
    let tree = ObbTree::build(&torus(1.0, 0.35, 64, 32), DEFAULT_MAX_DEPTH);
    assert!(!point_inside(&tree, Vec3::ZERO));
    assert!(point_inside(&tree, v(1.0, 0.0, 0.0)));
    assert!(point_inside(&tree, v(0.0, 0.2, -1.1)));
}

#[test]
fn segment_hits_exact_matches_brute_force() {
    for (name, mesh) in all_meshes() {
        let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        let tris: Vec<[Vec3; 3]> = (0..mesh.triangle_count())
            .map(|i| mesh.triangle(i))
            .collect();
        let mut rng = Rng::new(29);
        let (mut hits, mut inside_only) = (0, 0);
        for _ in 0..1500 {
            let c = rng.in_cube(1.4);
            let d = rng.direction() * rng.range(0.0, 0.3);
            let (p0, p1) = (c - d, c + d);
            let crosses = tris.iter().any(|t| segment_hits_triangle(p0, p1, t));
            let inside = !crosses && tree.closed && point_inside(&tree, (p0 + p1) * 0.5);
            assert_eq!(
                segment_hits_exact(&tree, p0, p1),
                crosses || inside,
                "{name}: {p0} {p1}"
            );
            hits += usize::from(crosses || inside);
            inside_only += usize::from(inside);
        }
        assert!(hits > 20, "{name}: {hits}");
        if tree.closed {
            assert!(inside_only > 20, "{name}: {inside_only}");
        }
    }
    let tree = ObbTree::build(&uv_sphere(1.0, 8, 8), DEFAULT_MAX_DEPTH);
    assert!(!segment_hits_exact(&tree, Vec3::NAN, Vec3::ZERO));
    assert!(!segment_hits_exact(
        &ObbTree::build(&Default::default(), 8),
        Vec3::ZERO,
        Vec3::X
    ));
}

fn patch_grid() -> Vec<Patch> {
    // 4 × 4 patches of 1 m, blades up to 0.5 m, field from (0, 0) to (4, 4).
    let mut out = Vec::new();
    for pz in 0..4u32 {
        for px in 0..4u32 {
            out.push(Patch {
                coord: [px, pz],
                aabb_min: Vec3::new(px as f32, 0.0, pz as f32),
                aabb_max: Vec3::new(px as f32 + 1.0, 0.5, pz as f32 + 1.0),
                first_blade: (pz * 4 + px) * 100,
                blades: 100,
                first_cell: (pz * 4 + px) * 100,
            });
        }
    }
    out
}

#[test]
fn broad_phase_hand_placed_patches() {
    let patches = patch_grid();
    // A ball's root box, world-aligned (the fit may turn it: a 24-gon's
    // smallest box is flush with an edge), so the placements below are exact.
    let root = Obb {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half: Vec3::splat(0.4),
    };
    let mut out = vec![99];
    let mut hit = |pos: Vec3, rot: Quat| {
        let pose = Pose {
            rotation: rot,
            ..Pose::at_rest(pos)
        };
        patches_hit(&patches, &world_obb(&root, &pose), &mut out);
        out.clone()
    };
    // Inside one patch.
    assert_eq!(hit(Vec3::new(0.5, 0.3, 0.5), Quat::IDENTITY), vec![0]);
    // Over the corner shared by patches 0, 1, 4, 5.
    assert_eq!(
        hit(Vec3::new(1.0, 0.3, 1.0), Quat::IDENTITY),
        vec![0, 1, 4, 5]
    );
    // Over an edge between 6 and 7 (x = 3, z in patch row 1).
    assert_eq!(hit(Vec3::new(3.0, 0.3, 1.5), Quat::IDENTITY), vec![6, 7]);
    // Above the blades: nothing.
    assert_eq!(
        hit(Vec3::new(1.0, 1.2, 1.0), Quat::IDENTITY),
        Vec::<u32>::new()
    );
    // Touching the top of the blades counts (conservative).
    let top = 0.5 + root.half.y;
    assert_eq!(hit(Vec3::new(0.5, top, 0.5), Quat::IDENTITY), vec![0]);
    // Off the field.
    assert_eq!(
        hit(Vec3::new(-1.0, 0.3, 2.0), Quat::IDENTITY),
        Vec::<u32>::new()
    );
}

#[test]
fn broad_phase_uses_the_oriented_box_not_its_aabb() {
    // A thin plank rotated 45° about y near the corner of patch 0: its
    // world AABB overlaps patch 5 diagonally, the plank itself does not.
    let plank = Obb {
        center: Vec3::ZERO,
        axes: [Vec3::X, Vec3::Y, Vec3::Z],
        half: Vec3::new(0.6, 0.2, 0.05),
    };
    let pose = Pose {
        rotation: Quat::from_rotation_y(-std::f32::consts::FRAC_PI_4),
        ..Pose::at_rest(Vec3::new(0.6, 0.2, 1.4))
    };
    let world = world_obb(&plank, &pose);
    assert!(
        !obb_overlaps_aabb(&world, Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.5, 1.0)),
        "patch 1"
    );
    assert!(
        obb_overlaps_aabb(&world, Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.5, 2.0)),
        "patch 4"
    );
    // world_obb moves the corners like the pose.
    let want = plank.corners().map(|c| pose.to_world(c));
    for (a, b) in world.corners().iter().zip(want) {
        assert!((*a - b).length() < 1e-5);
    }
    // Non-finite or inverted boxes never overlap.
    assert!(!obb_overlaps_aabb(
        &Obb {
            center: Vec3::NAN,
            ..plank
        },
        Vec3::ZERO,
        Vec3::ONE
    ));
    assert!(!obb_overlaps_aabb(&plank, Vec3::ONE, Vec3::ZERO));
}

/// A random OBB (centre within 1.5 m, any rotation, half extents 1–80 cm)
/// and a random AABB `min..max` within 1 m of the origin.
fn random_obb_and_aabb(rng: &mut Rng) -> (Obb, Vec3, Vec3) {
    let rot = Quat::from_scaled_axis(rng.direction() * rng.range(0.0, 3.0));
    let obb = Obb {
        center: rng.in_cube(1.5),
        axes: [rot * Vec3::X, rot * Vec3::Y, rot * Vec3::Z],
        half: Vec3::new(
            rng.range(0.01, 0.8),
            rng.range(0.01, 0.8),
            rng.range(0.01, 0.8),
        ),
    };
    let (lo, hi) = (rng.in_cube(1.0), rng.in_cube(1.0));
    (obb, lo.min(hi), lo.max(hi))
}

#[test]
fn broad_phase_is_conservative() {
    // Whenever a point of the OBB lies in the AABB, they overlap.
    let mut rng = Rng::new(31);
    for _ in 0..400 {
        let (obb, min, max) = random_obb_and_aabb(&mut rng);
        let overlap = obb_overlaps_aabb(&obb, min, max);
        let mut sample_inside = false;
        for i in 0..=8 {
            for j in 0..=8 {
                for k in 0..=8 {
                    let s = Vec3::new(i as f32, j as f32, k as f32) / 4.0 - 1.0;
                    let p = obb.center
                        + obb.axes[0] * s.x * obb.half.x
                        + obb.axes[1] * s.y * obb.half.y
                        + obb.axes[2] * s.z * obb.half.z;
                    sample_inside |= p.cmpge(min).all() && p.cmple(max).all();
                }
            }
        }
        assert!(!sample_inside || overlap, "{obb:?} {min} {max}");
        // The AABB's own corners inside the OBB also imply overlap.
        for c in 0..8 {
            let p = Vec3::new(
                if c & 1 == 0 { min.x } else { max.x },
                if c & 2 == 0 { min.y } else { max.y },
                if c & 4 == 0 { min.z } else { max.z },
            );
            if obb.to_box(p).abs().cmple(obb.half).all() {
                assert!(overlap);
            }
        }
    }
}

#[test]
fn the_face_axes_test_is_looser_than_the_full_test() {
    // Wherever the full test finds an overlap, the face-axes test does
    // too; it also finds separations (it is not always true), and it says
    // "overlap" for a box the full test separates on an edge axis only.
    let mut rng = Rng::new(47);
    let (mut both, mut separated, mut looser) = (0, 0, 0);
    for _ in 0..4000 {
        let (obb, min, max) = random_obb_and_aabb(&mut rng);
        let (full, faces) = (
            obb_overlaps_aabb(&obb, min, max),
            obb_may_overlap_aabb(&obb, min, max),
        );
        assert!(!full || faces, "{obb:?} {min} {max}");
        both += u32::from(full);
        separated += u32::from(!faces);
        looser += u32::from(faces && !full);
    }
    assert!(both > 500 && separated > 500, "{both} {separated}");
    assert!(looser > 0, "no box separated by an edge axis alone");
    assert!(!obb_may_overlap_aabb(
        &Obb {
            center: Vec3::NAN,
            axes: [Vec3::X, Vec3::Y, Vec3::Z],
            half: Vec3::ONE,
        },
        Vec3::ZERO,
        Vec3::ONE
    ));
}
