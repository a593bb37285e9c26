//! Mesh sanitising on load (DESIGN §9): refuse what cannot be a mesh, drop
//! and count what is only untidy.
//!
//! Refused ([`MeshError`]): no triangles, indices out of range, NaN or
//! infinite coordinates, absurd sizes, nothing left after dropping.
//! Dropped and counted ([`SanitizeReport`]): zero-area triangles and
//! duplicate triangles. Vertices with bit-identical positions are welded
//! (so that [`TriMesh::is_closed`] sees shared edges) and unused vertices
//! removed. Nothing here panics, whatever the input.

use super::error::MeshError;
use super::mesh::TriMesh;
use glam::Vec3;
use std::collections::{HashMap, HashSet};

/// Largest accepted mesh, metres across (bounding-box diagonal): a mesh
/// bigger than a 10 km field is a unit mistake.
pub const MAX_SIZE_M: f32 = 10_000.0;
/// Smallest accepted mesh, metres across: below a micrometre no blade could
/// ever touch it, and it is almost certainly a unit mistake.
pub const MIN_SIZE_M: f32 = 1e-6;
/// A triangle is degenerate when twice its area is at most this times the
/// mesh's squared diagonal. 1e-12 is the rounding level of the f64 cross
/// product of f32 edge vectors: only truly flat triangles (repeated or
/// exactly collinear corners) are dropped, never a thin but real one.
pub const DEGENERATE_RELATIVE_AREA: f64 = 1e-12;

/// What [`sanitize`] dropped.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SanitizeReport {
    /// Triangles of zero area (repeated or collinear corners).
    pub degenerate_dropped: usize,
    /// Triangles with the same three corner positions as an earlier one, in
    /// any order (so also a back-to-back copy).
    pub duplicate_dropped: usize,
}

/// Cuts a raw index list into triangles, for loaders whose index count may
/// not be a multiple of 3. Index ranges are checked later by [`sanitize`].
///
/// # Errors
/// [`MeshError::IndexCountNotMultipleOf3`] naming `source`.
pub fn triangles_from_indices(indices: &[u32], source: &str) -> Result<Vec<[u32; 3]>, MeshError> {
    if !indices.len().is_multiple_of(3) {
        return Err(MeshError::IndexCountNotMultipleOf3 {
            source_name: source.to_owned(),
            count: indices.len(),
        });
    }
    Ok(indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect())
}

/// Checks and tidies `mesh`; `source` (file or shape name) starts every error
/// message. Keeps the order of the remaining triangles and vertices.
///
/// # Errors
/// In this order: [`MeshError::Empty`], [`MeshError::IndexOutOfRange`] (the
/// first bad triangle), [`MeshError::NonFiniteVertex`] (the first bad vertex,
/// used or not), [`MeshError::TooLarge`] / [`MeshError::TooSmall`] (bounds of
/// the used vertices against [`MAX_SIZE_M`] / [`MIN_SIZE_M`]),
/// [`MeshError::AllDegenerate`].
pub fn sanitize(mesh: TriMesh, source: &str) -> Result<(TriMesh, SanitizeReport), MeshError> {
    sanitize_with_sources(mesh, source).map(|(m, r, _)| (m, r))
}

/// [`sanitize`], and for each vertex of the result the index of the input
/// vertex it was taken from (welding keeps the first of equal positions;
/// unused vertices go): what maps a host's vertices of the input mesh onto
/// the sanitised one (`Simulation::set_body_vertices`).
///
/// # Errors
/// As [`sanitize`].
pub fn sanitize_with_sources(
    mesh: TriMesh,
    source: &str,
) -> Result<(TriMesh, SanitizeReport, Vec<u32>), MeshError> {
    let source_name = || source.to_owned();
    if mesh.indices.is_empty() || mesh.positions.is_empty() {
        return Err(MeshError::Empty {
            source_name: source_name(),
        });
    }
    if u32::try_from(mesh.positions.len()).is_err() {
        return Err(MeshError::TooManyVertices {
            source_name: source_name(),
            count: mesh.positions.len(),
        });
    }
    let vertex_count = mesh.positions.len();
    for (triangle, tri) in mesh.indices.iter().enumerate() {
        if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(MeshError::IndexOutOfRange {
                source_name: source_name(),
                triangle,
                index,
                vertex_count,
            });
        }
    }
    for (vertex, p) in mesh.positions.iter().enumerate() {
        if let Some(&value) = p.to_array().iter().find(|c| !c.is_finite()) {
            return Err(MeshError::NonFiniteVertex {
                source_name: source_name(),
                vertex,
                value,
            });
        }
    }
    let size_m = used_diagonal(&mesh);
    if size_m > MAX_SIZE_M {
        return Err(MeshError::TooLarge {
            source_name: source_name(),
            size_m,
        });
    }
    if size_m < MIN_SIZE_M {
        return Err(MeshError::TooSmall {
            source_name: source_name(),
            size_m,
        });
    }

    let welded = weld_equal_positions(&mesh.positions);
    let min_twice_area = DEGENERATE_RELATIVE_AREA * f64::from(size_m) * f64::from(size_m);
    let mut report = SanitizeReport::default();
    let mut seen = HashSet::with_capacity(mesh.indices.len());
    let mut kept = Vec::with_capacity(mesh.indices.len());
    for tri in &mesh.indices {
        let tri = tri.map(|i| welded[i as usize]);
        let [a, b, c] = tri.map(|i| mesh.positions[i as usize].as_dvec3());
        if (b - a).cross(c - a).length() <= min_twice_area {
            report.degenerate_dropped += 1;
            continue;
        }
        let mut key = tri;
        key.sort_unstable();
        if !seen.insert(key) {
            report.duplicate_dropped += 1;
            continue;
        }
        kept.push(tri);
    }
    if kept.is_empty() {
        return Err(MeshError::AllDegenerate {
            source_name: source_name(),
        });
    }
    let (mesh, sources) = remove_unused_vertices(&mesh.positions, kept);
    Ok((mesh, report, sources))
}

/// Diagonal of the bounding box of the vertices used by a triangle, metres.
/// Indices must be in range and positions finite.
fn used_diagonal(mesh: &TriMesh) -> f32 {
    let first = mesh.positions[mesh.indices[0][0] as usize];
    let (lo, hi) = mesh
        .indices
        .iter()
        .flatten()
        .fold((first, first), |(lo, hi), &i| {
            let p = mesh.positions[i as usize];
            (lo.min(p), hi.max(p))
        });
    // f64: the diagonal of finite f32 bounds may overflow f32 (then it is
    // reported as inf m across, which is right: too large).
    let d = (hi.as_dvec3() - lo.as_dvec3()).length();
    d as f32
}

/// For each vertex, the index of the first vertex with the same position
/// (`-0.0` and `0.0` count as equal). Positions must be finite.
fn weld_equal_positions(positions: &[Vec3]) -> Vec<u32> {
    let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // Adding 0.0 turns -0.0 into 0.0 and leaves every other value as is.
            let bits = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            *first.entry(bits).or_insert(i as u32)
        })
        .collect()
}

/// The mesh made of `triangles` with only the vertices they use, in their
/// original order, and each kept vertex's index in `positions`.
fn remove_unused_vertices(positions: &[Vec3], triangles: Vec<[u32; 3]>) -> (TriMesh, Vec<u32>) {
    let mut new_index = vec![u32::MAX; positions.len()];
    for &i in triangles.iter().flatten() {
        new_index[i as usize] = 0;
    }
    let mut kept_positions = Vec::new();
    let mut sources = Vec::new();
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept_positions.len() as u32;
            kept_positions.push(positions[i]);
            sources.push(i as u32);
        }
    }
    let indices = triangles
        .into_iter()
        .map(|t| t.map(|i| new_index[i as usize]))
        .collect();
    (
        TriMesh {
            positions: kept_positions,
            indices,
        },
        sources,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::shapes;

    fn mesh(positions: &[[f32; 3]], indices: &[[u32; 3]]) -> TriMesh {
        TriMesh {
            positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
            indices: indices.to_vec(),
        }
    }

    fn message(result: Result<(TriMesh, SanitizeReport), MeshError>) -> String {
        result.expect_err("must be refused").to_string()
    }

    const QUAD: [[f32; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];

    #[test]
    fn clean_shapes_pass_unchanged() {
        for m in [
            shapes::sphere(1.0, 2),
            shapes::cuboid(Vec3::ONE),
            shapes::knot(1.0),
        ] {
            let (out, report) = sanitize(m.clone(), "shape").expect("clean");
            assert_eq!(report, SanitizeReport::default());
            assert_eq!(out, m);
        }
    }

    #[test]
    fn degenerate_and_duplicate_triangles_are_dropped_and_counted() {
        let m = mesh(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
                [2.0, 0.0, 0.0],
                [9.0, 9.0, 9.0],
            ],
            &[
                [0, 1, 2], // kept
                [0, 2, 3], // kept
                [0, 0, 1], // repeated corner: degenerate
                [0, 1, 4], // collinear: degenerate
                [1, 2, 0], // same corners rotated: duplicate
                [0, 2, 1], // back-to-back copy: duplicate
                [3, 0, 2], // rotation of the second: duplicate
            ],
        );
        let (out, report) = sanitize(m, "m.obj").expect("some triangles remain");
        assert_eq!(
            report,
            SanitizeReport {
                degenerate_dropped: 2,
                duplicate_dropped: 3
            }
        );
        // Vertex 4 (only in a degenerate triangle) and 5 (unused) are gone.
        assert_eq!(out, mesh(&QUAD, &[[0, 1, 2], [0, 2, 3]]));
    }

    #[test]
    fn equal_positions_are_welded_so_duplicates_by_position_are_found() {
        // Vertices 3..6 repeat 0..3 (as an OBJ loader splitting by normal
        // would write them); -0.0 equals 0.0.
        let m = mesh(
            &[
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [-0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            &[[0, 1, 2], [3, 4, 5]],
        );
        let (out, report) = sanitize(m, "m").expect("one triangle remains");
        assert_eq!(
            report,
            SanitizeReport {
                degenerate_dropped: 0,
                duplicate_dropped: 1
            }
        );
        assert_eq!(out.positions.len(), 3);
    }

    #[test]
    fn welding_closes_a_box_with_split_vertices() {
        let cube = shapes::cuboid(Vec3::ONE);
        let split = TriMesh {
            positions: cube
                .indices
                .iter()
                .flatten()
                .map(|&i| cube.positions[i as usize])
                .collect(),
            indices: (0..12).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        };
        assert!(!split.is_closed());
        let (out, _) = sanitize(split, "box").expect("clean");
        assert!(out.is_closed());
        assert_eq!(out.positions.len(), 8);
    }

    #[test]
    fn bad_meshes_are_refused_with_a_message_naming_file_index_and_limit() {
        let tri = [[0u32, 1, 2]];
        assert_eq!(
            message(sanitize(TriMesh::default(), "e.obj")),
            "e.obj: mesh is empty (no triangles)"
        );
        assert_eq!(
            message(sanitize(mesh(&QUAD, &[]), "e.obj")),
            "e.obj: mesh is empty (no triangles)"
        );
        assert_eq!(
            message(sanitize(
                mesh(&QUAD, &[[0, 1, 2], [0, 2, 3], [0, 3, 99]]),
                "cube.obj"
            )),
            "cube.obj: triangle 2 uses vertex 99 but the mesh has 4 vertices"
        );
        let mut nan = QUAD;
        nan[3][1] = f32::NAN;
        assert_eq!(
            message(sanitize(mesh(&nan, &tri), "cube.obj")),
            "cube.obj: vertex 3 has a non-finite coordinate (NaN)"
        );
        let mut inf = QUAD;
        inf[1][2] = f32::NEG_INFINITY;
        assert_eq!(
            message(sanitize(mesh(&inf, &tri), "c.gltf")),
            "c.gltf: vertex 1 has a non-finite coordinate (-inf)"
        );
        let huge = [[0.0, 0.0, 0.0], [3.2e7, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(
            message(sanitize(mesh(&huge, &tri), "x.obj")),
            "x.obj: mesh is 3.2e7 m across; at most 10000 m is allowed"
        );
        let tiny = [[0.0, 0.0, 0.0], [1e-7, 0.0, 0.0], [0.0, 0.0, 0.0]];
        assert_eq!(
            message(sanitize(mesh(&tiny, &tri), "x.obj")),
            "x.obj: mesh is 1e-7 m across; at least 1e-6 m is needed"
        );
        assert_eq!(
            message(sanitize(mesh(&QUAD, &[[0, 1, 1], [0, 0, 0]]), "x.obj")),
            "x.obj: every triangle is degenerate (zero area)"
        );
        assert_eq!(
            triangles_from_indices(&[0, 1, 2, 3, 4, 5, 6], "x.obj")
                .expect_err("7 indices")
                .to_string(),
            "x.obj: index count 7 is not a multiple of 3"
        );
    }

    #[test]
    fn size_is_measured_on_used_vertices_only() {
        // A far unused vertex does not make the mesh absurdly large.
        let mut positions = QUAD.to_vec();
        positions.push([1e9, 0.0, 0.0]);
        let (out, _) = sanitize(mesh(&positions, &[[0, 1, 2]]), "m").expect("small mesh");
        assert_eq!(out.positions.len(), 3);
    }

    #[test]
    fn triangles_from_indices_groups_by_three() {
        assert_eq!(
            triangles_from_indices(&[0, 1, 2, 2, 3, 0], "m").expect("6"),
            vec![[0, 1, 2], [2, 3, 0]]
        );
        assert_eq!(
            triangles_from_indices(&[], "m").expect("0"),
            Vec::<[u32; 3]>::new()
        );
    }

    mod never_panics {
        use super::*;
        use proptest::prelude::*;

        fn any_coordinate() -> impl Strategy<Value = f32> {
            prop_oneof![
                8 => -10.0f32..10.0,
                1 => Just(f32::NAN),
                1 => Just(f32::INFINITY),
                1 => Just(1e30f32),
                1 => Just(0.0f32),
            ]
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]
            #[test]
            fn sanitize_returns_a_mesh_or_an_error(
                positions in prop::collection::vec(prop::array::uniform3(any_coordinate()), 0..8),
                indices in prop::collection::vec(prop::array::uniform3(0u32..10), 0..12),
            ) {
                if let Ok((out, report)) = sanitize(mesh(&positions, &indices), "p") {
                    prop_assert!(!out.indices.is_empty());
                    prop_assert_eq!(out.indices.len() + report.degenerate_dropped + report.duplicate_dropped, indices.len());
                    prop_assert!(out.indices.iter().flatten().all(|&i| (i as usize) < out.positions.len()));
                }
            }
        }
    }
}
