//! Every built-in shape's OBB tree is well formed (every triangle inside its
//! node and all ancestors) at every depth cap, and Eq. 3 holds at the root.

use glam::Vec3;
use trample::obb::ObbTree;
use trample::object::shapes::{capsule, cuboid, knot, sphere};

#[test]
fn built_in_shapes_build_well_formed_trees_at_every_depth() {
    let shapes = [
        ("sphere", sphere(1.0, 3)),
        ("box", cuboid(Vec3::new(0.5, 0.3, 1.2))),
        ("capsule", capsule(0.4, 1.5)),
        ("knot", knot(2.4)),
    ];
    for (name, mesh) in shapes {
        let full = ObbTree::build(&mesh, trample::obb::build::DEFAULT_MAX_DEPTH);
        full.assert_well_formed();
        assert!(full.closed, "{name} must be closed");
        for depth in 1..=full.max_depth {
            let tree = ObbTree::build(&mesh, depth);
            tree.assert_well_formed();
            assert_eq!(
                tree.max_depth,
                depth.min(full.max_depth),
                "{name} at depth {depth}"
            );
            assert_eq!(tree.triangles.len(), mesh.triangle_count());
        }
        // Eq. 3 at the root of a closed shape: the area-weighted normals cancel.
        assert!(
            full.nodes[0].eqn.length() < 1e-3,
            "{name}: root EqN {}",
            full.nodes[0].eqn
        );
        println!(
            "{name}: {} triangles, tree depth {}, {} nodes",
            mesh.triangle_count(),
            full.max_depth,
            full.nodes.len()
        );
    }
}
