//! Building the trees of many meshes at once, each distinct mesh once
//! (issue 16: "the tree build stays a one-off cost"). A scene of many
//! objects repeats a few meshes — the herd's 20 beetle cars and 20 cows —
//! and [`super::ObbTree::build`] is deterministic, so a copy of one build is
//! the tree every other build of the same mesh would give, bit for bit.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

use rayon::prelude::*;

use super::node::ObbTree;
use crate::object::{Object, OpenInside, TriMesh};

/// The winding number's data a mesh's tree gets in [`build_shared`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Winding {
    /// None: an open mesh's inside is the sheet rule's.
    #[default]
    Off,
    /// [`ObbTree::enable_winding`]: the dipoles, the rim and the grid.
    WithGrid,
    /// [`ObbTree::enable_winding_without_grid`]: for a mesh that deforms,
    /// whose first refit would drop the grid.
    WithoutGrid,
}

impl Winding {
    /// Gives `tree` this data (nothing for [`Winding::Off`], a closed mesh
    /// or a tree that has it).
    pub fn enable(self, tree: &mut ObbTree) {
        match self {
            Self::Off => {}
            Self::WithGrid => tree.enable_winding(),
            Self::WithoutGrid => tree.enable_winding_without_grid(),
        }
    }

    /// What `object`'s trees need, its own mesh's then its parts': none
    /// unless its track asks for the winding rule; a skinned mesh's without
    /// the grid (its first refit would drop it: the grid is a fraction of a
    /// second of load), the parts' (rigid) with it.
    pub fn of(object: &Object) -> impl Iterator<Item = Self> + use<> {
        let on = object.track.open_inside == OpenInside::Winding;
        let own = match (on, object.animated.is_some()) {
            (false, _) => Self::Off,
            (true, false) => Self::WithGrid,
            (true, true) => Self::WithoutGrid,
        };
        let parts = if on { Self::WithGrid } else { Self::Off };
        std::iter::once(own).chain(std::iter::repeat_n(parts, object.parts.parts.len()))
    }
}

/// The trees of `meshes` (to `max_depth`), in order: one
/// [`ObbTree::build`] per distinct mesh (equal positions, bit for bit, and
/// equal indices), in parallel, shared by every mesh equal to it (one copy
/// in memory: the narrow phase and the contact response of twenty cows walk
/// one tree, which stays in the cache). Also returns how many trees were
/// built. A body whose mesh deforms gets its own copy when it first refits
/// it ([`Arc::make_mut`]).
///
/// `winding[i]` (missing: [`Winding::Off`]) gives mesh `i`'s tree the
/// winding number's data ([`ObbTree::enable_winding`], with its grid: a
/// fraction of a second for the beetle car) — once per distinct mesh too,
/// so that the herd's twenty winding cars share one grid.
#[must_use]
pub fn build_shared(
    meshes: &[&TriMesh],
    winding: &[Winding],
    max_depth: u32,
) -> (Vec<Arc<ObbTree>>, usize) {
    let winds = |i: usize| winding.get(i).copied().unwrap_or_default();
    // Slot of each mesh's first equal, found by hash then compared.
    let mut by_hash: HashMap<u64, Vec<usize>> = HashMap::new();
    let mut first_equal = Vec::with_capacity(meshes.len());
    for (i, mesh) in meshes.iter().enumerate() {
        let seen = by_hash.entry(mesh_hash(mesh)).or_default();
        let same = seen
            .iter()
            .copied()
            .find(|&j| winds(j) == winds(i) && same_mesh(meshes[j], mesh));
        first_equal.push(same.unwrap_or(i));
        if same.is_none() {
            seen.push(i);
        }
    }
    let distinct: Vec<usize> = (0..meshes.len()).filter(|&i| first_equal[i] == i).collect();
    let built: Vec<Arc<ObbTree>> = distinct
        .par_iter()
        .map(|&i| {
            let mut tree = ObbTree::build(meshes[i], max_depth);
            winds(i).enable(&mut tree);
            Arc::new(tree)
        })
        .collect();
    let at: HashMap<usize, usize> = distinct.iter().enumerate().map(|(k, &i)| (i, k)).collect();
    let trees = first_equal
        .iter()
        .map(|j| Arc::clone(&built[at[j]]))
        .collect();
    (trees, distinct.len())
}

/// Equal positions bit for bit (so −0.0 ≠ +0.0 and NaN never equals, as
/// the build could tell them apart) and equal indices.
fn same_mesh(a: &TriMesh, b: &TriMesh) -> bool {
    a.indices == b.indices
        && a.positions.len() == b.positions.len()
        && a.positions
            .iter()
            .zip(&b.positions)
            .all(|(p, q)| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits))
}

fn mesh_hash(mesh: &TriMesh) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    mesh.indices.hash(&mut h);
    for p in &mesh.positions {
        p.to_array().map(f32::to_bits).hash(&mut h);
    }
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::shapes::{cuboid, sphere};
    use glam::Vec3;

    #[test]
    fn each_distinct_mesh_is_built_once_and_every_tree_is_its_own_build() {
        let a = sphere(1.0, 2);
        let b = cuboid(Vec3::new(0.5, 0.2, 0.3));
        let mut a_moved = a.clone();
        a_moved.positions[3].x += 1e-6;
        let meshes = [&a, &b, &a, &a_moved, &b, &a];
        let (trees, built) = build_shared(&meshes, &[], 12);
        assert_eq!(built, 3, "a, b and the moved copy of a");
        assert_eq!(trees.len(), meshes.len());
        assert!(Arc::ptr_eq(&trees[0], &trees[2]) && Arc::ptr_eq(&trees[0], &trees[5]));
        assert!(Arc::ptr_eq(&trees[1], &trees[4]) && !Arc::ptr_eq(&trees[0], &trees[3]));
        for (tree, mesh) in trees.iter().zip(meshes) {
            let alone = ObbTree::build(mesh, 12);
            assert_eq!(format!("{tree:?}"), format!("{alone:?}"));
        }
    }

    /// Winding trees are shared among themselves, not with the sheet-rule
    /// trees of the same mesh, and carry their grid.
    #[test]
    fn winding_trees_are_built_once_apart_from_the_others() {
        let s = sphere(1.0, 2);
        // Open: the sphere less one triangle.
        let open = TriMesh {
            positions: s.positions.clone(),
            indices: s.indices[1..].to_vec(),
        };
        let meshes = [&open, &open, &open, &open];
        let on = Winding::WithGrid;
        let (trees, built) = build_shared(&meshes, &[on, Winding::Off, on], 12);
        assert_eq!(built, 2);
        assert!(Arc::ptr_eq(&trees[0], &trees[2]) && Arc::ptr_eq(&trees[1], &trees[3]));
        assert!(trees[0].winds() && trees[0].winding_grid.is_some());
        assert!(!trees[1].winds() && trees[1].winding_grid.is_none());
        // A deforming mesh's: the winding number's data but no grid, and
        // not shared with the rigid ones.
        let (trees, built) = build_shared(&meshes[..2], &[on, Winding::WithoutGrid], 12);
        assert_eq!(built, 2);
        assert!(trees[1].winds() && trees[1].winding_grid.is_none());
        assert!(trees[0].winding_grid.is_some());
    }

    /// A skinned body on the winding rule gets its tree without the grid
    /// (its first refit would drop it); a rigid one with it; the sheet rule
    /// none.
    #[test]
    fn a_skinned_winding_mesh_gets_no_grid() {
        use crate::object::{Anchor, ShapeParams, TrackParams};
        let meshes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes");
        let winding = TrackParams {
            open_inside: OpenInside::Winding,
            ..TrackParams::default()
        };
        let mesh = |name: &str| {
            crate::builder::BodyBuilder::new(
                "a",
                ShapeParams::Mesh {
                    path: name.into(),
                    anchor: Anchor::File,
                },
            )
        };
        let object = |b: crate::builder::BodyBuilder| b.build_in(0, &meshes).unwrap().object;
        let walker = object(mesh("walker.glb").animation("walk", 1.0).track(winding));
        assert_eq!(
            Winding::of(&walker).collect::<Vec<_>>(),
            [Winding::WithoutGrid]
        );
        let car = object(mesh("beetle.obj").track(winding));
        assert_eq!(Winding::of(&car).collect::<Vec<_>>(), [Winding::WithGrid]);
        let sheet = object(mesh("beetle.obj"));
        assert_eq!(Winding::of(&sheet).collect::<Vec<_>>(), [Winding::Off]);
    }
}
