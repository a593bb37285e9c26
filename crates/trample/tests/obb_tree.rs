//! OBB fit, tree build (Eq. 3) and validation (DESIGN §3): boxes contain
//! their triangles at every depth, the tree is well formed for every mesh and
//! depth cap and for arbitrary triangle soups, EqN is Eq. 3, and the EqN
//! direction falls back as DESIGN §3 says.

mod collision_meshes;

use collision_meshes::*;
use glam::{Quat, Vec3};
use proptest::prelude::*;
use trample::obb::{DEFAULT_MAX_DEPTH, EQN_EPSILON, MAX_TREE_DEPTH, NO_CHILD, ObbTree, fit_obb};
use trample::object::{TriMesh, shapes};

fn triangles(mesh: &TriMesh) -> Vec<[Vec3; 3]> {
    (0..mesh.triangle_count())
        .map(|i| mesh.triangle(i))
        .collect()
}

/// Sorted half extents, to compare boxes whatever the order of their axes.
fn sorted(v: Vec3) -> [f32; 3] {
    let mut a = v.to_array();
    a.sort_by(f32::total_cmp);
    a
}

#[test]
fn test_meshes_are_closed_and_wound_outwards() {
    for (name, mesh) in all_meshes() {
        let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        let want_closed = !matches!(name, "wavy sheet" | "random soup");
        assert_eq!(tree.closed, want_closed, "{name}");
        if want_closed {
            assert!(signed_volume(&mesh) > 0.0, "{name} is wound inwards");
        }
    }
    let v = signed_volume(&uv_sphere(1.0, 24, 48));
    assert!(
        (v - 4.0 / 3.0 * std::f32::consts::PI).abs() < 0.05,
        "sphere volume {v}"
    );
}

#[test]
fn fit_is_tight_for_an_axis_aligned_box() {
    let half = Vec3::new(1.0, 0.5, 0.25);
    let centre = Vec3::new(0.3, -0.2, 0.1);
    for n in [1, 3] {
        let obb = fit_obb(&triangles(&box_mesh(centre, half, n)));
        assert!(
            (obb.center - centre).length() < 1e-5,
            "centre {}",
            obb.center
        );
        let got = sorted(obb.half);
        for (g, w) in got.iter().zip(sorted(half)) {
            assert!(*g >= w && *g - w < 3e-5, "half extents {got:?} vs {half}");
        }
        for a in obb.axes {
            assert!(
                a.abs().max_element() > 1.0 - 1e-6,
                "axis {a} not world-aligned"
            );
        }
    }
}

#[test]
fn fit_is_tight_for_a_rotated_box() {
    // A box rotated off the world axes: the covariance axes must find it.
    let rot = Quat::from_euler(glam::EulerRot::YXZ, 0.4, 0.3, -0.2);
    let half = Vec3::new(1.0, 0.5, 0.25);
    let mesh = box_mesh(Vec3::ZERO, half, 2);
    let tris: Vec<[Vec3; 3]> = triangles(&mesh)
        .into_iter()
        .map(|t| t.map(|p| rot * p))
        .collect();
    let obb = fit_obb(&tris);
    let got = sorted(obb.half);
    for (g, w) in got.iter().zip(sorted(half)) {
        assert!(*g >= w && *g - w < 1e-4, "half extents {got:?} vs {half}");
    }
}

#[test]
fn fit_contains_every_corner() {
    for (name, mesh) in all_meshes() {
        let tris = triangles(&mesh);
        let obb = fit_obb(&tris);
        for p in tris.iter().flatten() {
            let q = obb.to_box(*p);
            assert!(
                q.abs().cmple(obb.half).all(),
                "{name}: {p} → {q} outside {}",
                obb.half
            );
        }
        // Right-handed orthonormal axes.
        let [u, v, w] = obb.axes;
        assert!((u.cross(v) - w).length() < 1e-5, "{name}");
    }
}

#[test]
fn fit_handles_degenerate_input() {
    // One point repeated, collinear points, empty: finite boxes, no panic.
    let p = Vec3::new(1.0, 2.0, 3.0);
    let obb = fit_obb(&[[p, p, p]]);
    assert_eq!(obb.center, p);
    assert!(obb.half.max_element() < 1e-4 && obb.half.min_element() > 0.0);
    let line = fit_obb(&[[Vec3::ZERO, Vec3::X, Vec3::X * 2.0]]);
    assert!((sorted(line.half)[2] - 1.0).abs() < 1e-4);
    let empty = fit_obb(&[]);
    assert_eq!(empty.half, Vec3::ZERO);
    let nan = fit_obb(&[[Vec3::NAN, Vec3::ONE, Vec3::ZERO]]);
    let _ = nan; // no panic is the test
}

#[test]
fn eqn_is_the_area_weighted_mean_normal_eq3() {
    // T1: area 0.5, normal +z. T2: area 4.5, normal +x.
    let mesh = TriMesh {
        positions: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(5.0, 0.0, 0.0),
            Vec3::new(5.0, 3.0, 0.0),
            Vec3::new(5.0, 0.0, 3.0),
        ],
        indices: vec![[0, 1, 2], [3, 4, 5]],
    };
    let tree = ObbTree::build(&mesh, 1);
    tree.assert_well_formed();
    assert_eq!(tree.nodes.len(), 1);
    let want = (Vec3::Z * 0.5 + Vec3::X * 4.5) / 5.0;
    assert!(
        (tree.nodes[0].eqn - want).length() < 1e-6,
        "{} vs {want}",
        tree.nodes[0].eqn
    );
    // Deeper, each leaf's EqN is its unit normal.
    let tree = ObbTree::build(&mesh, 2);
    tree.assert_well_formed();
    assert_eq!(tree.nodes.len(), 3);
    let leaf_eqns: Vec<Vec3> = tree.nodes[1..].iter().map(|n| n.eqn).collect();
    assert!(
        leaf_eqns.iter().any(|e| (*e - Vec3::Z).length() < 1e-6),
        "{leaf_eqns:?}"
    );
    assert!(
        leaf_eqns.iter().any(|e| (*e - Vec3::X).length() < 1e-6),
        "{leaf_eqns:?}"
    );
}

#[test]
fn tree_is_well_formed_at_every_depth_cap() {
    for (name, mesh) in all_meshes() {
        for depth in 1..=12 {
            let tree = ObbTree::build(&mesh, depth);
            if let Err(e) = tree.validate() {
                panic!("{name}, max_depth {depth}: {e}");
            }
            assert!(tree.max_depth <= depth, "{name}");
            assert_eq!(tree.triangles.len(), mesh.triangle_count(), "{name}");
        }
        let full = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        full.assert_well_formed();
        // Balanced enough: one triangle per leaf well before the cap.
        assert!(
            full.nodes
                .iter()
                .filter(|n| n.is_leaf())
                .all(|n| n.tri_count == 1),
            "{name}"
        );
        assert!(full.max_depth < 24, "{name}: depth {}", full.max_depth);
        // Siblings are adjacent, children after parents (documented layout).
        for (i, n) in full.nodes.iter().enumerate() {
            if !n.is_leaf() {
                assert!(n.children[0] as usize > i && n.children[1] == n.children[0] + 1);
            }
        }
    }
}

#[test]
fn tree_keeps_the_triangles_of_the_mesh() {
    let mesh = torus(1.0, 0.3, 16, 8);
    let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    let key = |t: &[Vec3; 3]| t.map(|p| p.to_array().map(f32::to_bits));
    let mut want: Vec<_> = triangles(&mesh).iter().map(key).collect();
    let mut got: Vec<_> = tree.triangles.iter().map(key).collect();
    want.sort();
    got.sort();
    assert_eq!(got, want);
}

#[test]
fn depth_cap_is_clamped() {
    let mesh = random_soup(50, 1.0, 3);
    let tree = ObbTree::build(&mesh, 0);
    tree.assert_well_formed();
    assert_eq!(tree.nodes.len(), 1);
    assert_eq!(tree.max_depth, 1);
    // A degenerate soup (all triangles the same) splits by median forever;
    // the hard cap keeps it finite.
    let same = TriMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![[0, 1, 2]; 300],
    };
    let tree = ObbTree::build(&same, u32::MAX);
    tree.assert_well_formed();
    assert!(tree.max_depth <= MAX_TREE_DEPTH);
    assert!(!tree.closed);
}

#[test]
fn empty_and_invalid_meshes_do_not_panic() {
    let tree = ObbTree::build(&TriMesh::default(), DEFAULT_MAX_DEPTH);
    tree.assert_well_formed();
    assert!(tree.is_empty() && !tree.closed);
    // Out-of-range indices are skipped.
    let mesh = TriMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![[0, 1, 2], [0, 1, 9]],
    };
    let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    tree.assert_well_formed();
    assert_eq!(tree.triangles.len(), 1);
    // NaN coordinates: a tree comes back (and fails validation), no panic.
    let mesh = TriMesh {
        positions: vec![Vec3::NAN, Vec3::X, Vec3::Y, Vec3::Z],
        indices: vec![[0, 1, 2], [1, 2, 3]],
    };
    let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    assert!(tree.validate().is_err());
}

/// A change that breaks a tree invariant.
type Corruption = fn(&mut ObbTree);

#[test]
fn validation_catches_corruption() {
    let mesh = uv_sphere(1.0, 8, 16);
    let good = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    good.assert_well_formed();
    let corruptions: Vec<(&str, Corruption)> = vec![
        ("shrunk box", |t| t.nodes[3].obb.half *= 0.9),
        ("moved triangle", |t| t.triangles[0][0] += Vec3::splat(0.5)),
        ("skewed axes", |t| {
            t.nodes[0].obb.axes[1] = Vec3::new(0.1, 1.0, 0.0).normalize()
        }),
        ("left-handed", |t| {
            t.nodes[0].obb.axes[2] = -t.nodes[0].obb.axes[2]
        }),
        ("bad depth", |t| t.nodes[1].depth = 5),
        ("bad range", |t| t.nodes[1].tri_count += 1),
        ("child index", |t| t.nodes[0].children[1] = 99_999),
        ("half a leaf", |t| t.nodes[0].children[1] = NO_CHILD),
        ("max depth", |t| t.max_depth += 1),
        ("nan eqn", |t| t.nodes[2].eqn = Vec3::NAN),
        ("nan corner", |t| t.triangles[5][1] = Vec3::NAN),
    ];
    for (what, corrupt) in corruptions {
        let mut t = good.clone();
        corrupt(&mut t);
        assert!(t.validate().is_err(), "validation missed: {what}");
    }
}

#[test]
fn eqn_direction_falls_back_to_centre_to_segment_on_a_sphere_root() {
    let tree = ObbTree::build(&uv_sphere(1.0, 24, 48), DEFAULT_MAX_DEPTH);
    let root = &tree.nodes[0];
    assert!(
        root.eqn.length() < 1e-3,
        "closed mesh root EqN {}",
        root.eqn
    );
    // A vertical blade at x = 1.2: pushed along +x.
    let d = tree.eqn_direction(0, Vec3::new(1.2, -1.0, 0.0), Vec3::new(1.2, 1.0, 0.0));
    assert!((d - Vec3::X).length() < 1e-3, "{d}");
    // A point-like segment off the diagonal.
    let p = Vec3::new(-0.5, 0.2, 0.7);
    let d = tree.eqn_direction(0, p, p);
    assert!(
        (d - (p - root.obb.center).normalize()).length() < 1e-5,
        "{d}"
    );
    // Through the centre: a unit axis of the box, pointing up-ish.
    let d = tree.eqn_direction(0, Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    assert!(d.is_normalized(), "{d}");
    // Out of range node: +y.
    assert_eq!(tree.eqn_direction(u32::MAX, Vec3::ZERO, Vec3::X), Vec3::Y);
}

#[test]
fn eqn_direction_uses_eq3_when_it_is_long_enough() {
    let tree = ObbTree::build(&uv_sphere(1.0, 24, 48), DEFAULT_MAX_DEPTH);
    let mut checked = 0;
    for (i, n) in tree.nodes.iter().enumerate() {
        let d = tree.eqn_direction(i as u32, Vec3::splat(5.0), Vec3::splat(6.0));
        assert!(d.is_normalized());
        if n.eqn.length() >= EQN_EPSILON {
            assert!((d - n.eqn.normalize()).length() < 1e-6);
            // Outward: EqN of a sphere node points away from the centre.
            assert!(d.dot(n.obb.center) > 0.0, "node {i}");
            checked += 1;
        }
    }
    assert!(checked > tree.nodes.len() / 2);
}

/// Three icospheres apart, as one mesh, and the sphere each triangle of the
/// tree belongs to (by its centroid).
fn three_balls() -> (TriMesh, [Vec3; 3]) {
    let centres = [
        Vec3::new(-3.0, 0.0, 0.0),
        Vec3::new(0.5, 0.0, 2.0),
        Vec3::new(2.5, 1.0, -1.0),
    ];
    let mut mesh = TriMesh::default();
    for (i, c) in centres.iter().enumerate() {
        // Different sizes, so the pieces hold different shares of triangles.
        let ball = shapes::sphere(0.5 + 0.25 * i as f32, 2 + (i as u32 % 2));
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend(ball.positions.iter().map(|p| *p + *c));
        mesh.indices
            .extend(ball.indices.iter().map(|t| t.map(|k| k + base)));
    }
    (mesh, centres)
}

#[test]
fn apart_pieces_stay_whole() {
    let (mesh, centres) = three_balls();
    let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    tree.assert_well_formed();
    let ball = |t: &[Vec3; 3]| {
        let c = (t[0] + t[1] + t[2]) / 3.0;
        (0..3)
            .min_by(|&a, &b| c.distance(centres[a]).total_cmp(&c.distance(centres[b])))
            .unwrap()
    };
    let balls_in = |node: usize| {
        let n = &tree.nodes[node];
        let range = n.first_tri as usize..(n.first_tri + n.tri_count) as usize;
        let mut set: Vec<usize> = tree.triangles[range].iter().map(ball).collect();
        set.sort_unstable();
        set.dedup();
        set
    };
    // A node over several balls splits between them: no ball in both children.
    let mut mixed = 0;
    for (i, n) in tree.nodes.iter().enumerate() {
        if n.is_leaf() || balls_in(i).len() < 2 {
            continue;
        }
        mixed += 1;
        let (l, r) = (
            balls_in(n.children[0] as usize),
            balls_in(n.children[1] as usize),
        );
        assert!(
            l.iter().all(|b| !r.contains(b)),
            "node {i}: children hold balls {l:?} and {r:?}"
        );
    }
    assert_eq!(mixed, 2, "three balls take two splits to separate");
}

#[test]
fn nested_trees_hold_their_children() {
    let mut refused = 0;
    for (name, mesh) in all_meshes()
        .into_iter()
        .chain([("knot", shapes::knot(2.4))])
    {
        let tight = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
        assert!(!tight.nested);
        let mut nested = tight.clone();
        nested.nest_boxes();
        nested.assert_well_formed();
        // Grown, never shrunk, and only where a child stuck out.
        let mut grown = 0;
        for (a, b) in tight.nodes.iter().zip(&nested.nodes) {
            assert_eq!(a.obb.axes, b.obb.axes, "{name}");
            for c in a.obb.corners() {
                let slack = Vec3::splat(1e-5 * b.obb.half.max_element());
                assert!(
                    b.obb.to_box(c).abs().cmple(b.obb.half + slack).all(),
                    "{name}: {} vs {}",
                    b.obb.to_box(c),
                    b.obb.half
                );
            }
            grown += usize::from(a.obb != b.obb);
        }
        // Where a tight child sticks out, the tight tree marked nested is refused.
        let mut claimed = tight.clone();
        claimed.nested = true;
        // As `nest_boxes` leaves it: no tilted boxes.
        claimed.slabs.clear();
        match claimed.validate() {
            Err(e) => {
                assert!(grown > 0 && e.contains("child"), "{name}: {e}");
                refused += 1;
            }
            Ok(()) => assert_eq!(grown, 0, "{name}"),
        }
    }
    // Curved meshes have children that stick out of their parents.
    assert!(refused >= 4, "{refused}");
}

/// A triangle soup: random corners in a cube of side 2·10^k, some triangles
/// nearly degenerate (corners within 1e-6 of each other, or collinear).
fn soup() -> impl Strategy<Value = TriMesh> {
    let coord = -10.0f32..10.0;
    let point = (coord.clone(), coord.clone(), coord).prop_map(|(x, y, z)| Vec3::new(x, y, z));
    let tri = (point.clone(), point.clone(), point, 0u8..4, -1e-6f32..1e-6).prop_map(
        |(a, b, c, kind, eps)| match kind {
            0 => [a, a + Vec3::splat(eps), a + Vec3::new(eps, -eps, 0.0)], // tiny
            1 => [a, b, a + (b - a) * 0.5 + Vec3::splat(eps)],             // collinear-ish
            _ => [a, b, c],
        },
    );
    (proptest::collection::vec(tri, 1..=200), 0i32..=3).prop_map(|(tris, scale)| {
        let s = 10f32.powi(scale - 1);
        let mut mesh = TriMesh::default();
        for t in tris {
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(t.map(|p| p * s));
            mesh.indices.push([base, base + 1, base + 2]);
        }
        mesh
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn random_soups_build_well_formed_trees(mesh in soup(), depth in 1u32..=40) {
        let tree = ObbTree::build(&mesh, depth);
        prop_assert!(tree.validate().is_ok(), "{:?}", tree.validate());
        let mut nested = tree.clone();
        nested.nest_boxes();
        prop_assert!(nested.validate().is_ok(), "nested: {:?}", nested.validate());
        prop_assert_eq!(tree.triangles.len(), mesh.triangle_count());
        for i in 0..tree.nodes.len() as u32 {
            prop_assert!(tree.eqn_direction(i, Vec3::ZERO, Vec3::ONE).is_normalized());
        }
    }
}
