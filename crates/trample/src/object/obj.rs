//! Wavefront OBJ loading (through `tobj`).
//!
//! Only geometry is read: polygons are triangulated as fans, every object
//! and group of the file is merged into one mesh; normals, texture
//! coordinates, `mtllib` and `usemtl` are ignored (no `.mtl` file is opened).
//! Before `tobj` sees the text, every face index is checked here, so that an
//! out-of-range index is reported with its line number (and so that `tobj`,
//! which can overflow on absurd indices, only ever parses valid ones).

use super::error::MeshError;
use super::mesh::TriMesh;
use super::sanitize::triangles_from_indices;
use glam::Vec3;
use std::path::Path;

/// Loads every face of the OBJ file at `path` as one triangle mesh, in the
/// file's units and frame: [`super::read_mesh_bytes`] then [`parse_obj`].
/// The mesh is not sanitised: pass it through [`super::sanitize::sanitize`]
/// (as [`super::object::Object::from_params`] does).
///
/// # Errors
/// [`MeshError::Io`] when the file cannot be read (missing, no permission,
/// not a regular file, larger than [`super::MAX_MESH_FILE_BYTES`]), else
/// those of [`parse_obj`]. Every message names the file.
pub fn load_obj(path: &Path) -> Result<TriMesh, MeshError> {
    let bytes = super::read_mesh_bytes(path)?;
    parse_obj(&bytes, &path.display().to_string())
}

/// Parses the bytes of an OBJ file (`name` is used in messages) as one
/// triangle mesh. Polygons of more than three corners are triangulated as
/// fans (a quad gives two triangles, a pentagon three); faces of fewer than
/// three corners are refused ([`MeshError::ObjShortFace`]); `p` and `l`
/// elements are ignored. Never panics (the fuzz target `obj` holds it to
/// that).
///
/// # Errors
/// [`MeshError::ObjParse`] for text that is not UTF-8 or that `tobj`
/// refuses, [`MeshError::ObjFaceIndex`] for a face index outside the file's
/// vertices (or texture coordinates or normals), [`MeshError::ObjShortFace`],
/// and [`MeshError::ParserPanic`] if `tobj` panics.
pub fn parse_obj(bytes: &[u8], name: &str) -> Result<TriMesh, MeshError> {
    let name = name.to_owned();
    let text = std::str::from_utf8(bytes).map_err(|e| MeshError::ObjParse {
        source_name: name.clone(),
        reason: format!("not UTF-8 text (bad byte at offset {})", e.valid_up_to()),
    })?;
    check_face_indices(text, &name)?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let ignore_materials = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let parsed = super::catch_parser_panic(&name, "OBJ", || {
        tobj::load_obj_buf(&mut text.as_bytes(), &options, ignore_materials)
    })?;
    let (models, _materials) = parsed.map_err(|e| MeshError::ObjParse {
        source_name: name.clone(),
        reason: e.to_string(),
    })?;

    let mut positions = Vec::new();
    let mut raw_indices = Vec::new();
    for model in &models {
        let offset = u32::try_from(positions.len()).map_err(|_| MeshError::TooManyVertices {
            source_name: name.clone(),
            count: positions.len(),
        })?;
        positions.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        for &i in &model.mesh.indices {
            let index = i
                .checked_add(offset)
                .ok_or_else(|| MeshError::TooManyVertices {
                    source_name: name.clone(),
                    count: positions.len(),
                })?;
            raw_indices.push(index);
        }
    }
    let indices = triangles_from_indices(&raw_indices, &name)?;
    Ok(TriMesh { positions, indices })
}

/// What an OBJ face index refers to, by its position in `v/vt/vn`.
const FACE_INDEX_KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];

/// Checks every `f` line's indices against the `v`, `vt` and `vn` lines:
/// a positive index against the whole file's count (`tobj` resolves them at
/// the end), a negative one against the count above the line. Texture
/// coordinate and normal indices are only checked when the file has some
/// (otherwise `tobj` ignores them). Unparsable indices are left to `tobj`.
/// A face of fewer than three corners is refused here: `tobj` would keep
/// it as a point or a line and drop it without a word.
fn check_face_indices(text: &str, name: &str) -> Result<(), MeshError> {
    let mut totals = [0usize; 3];
    for line in text.lines() {
        if let Some(kind) = element_kind(line) {
            totals[kind] += 1;
        }
    }
    let mut above = [0usize; 3];
    for (line_index, line) in text.lines().enumerate() {
        if let Some(kind) = element_kind(line) {
            above[kind] += 1;
            continue;
        }
        let mut words = line.split_whitespace();
        if words.next() != Some("f") {
            continue;
        }
        let corners = words.clone().count();
        if corners < 3 {
            return Err(MeshError::ObjShortFace {
                source_name: name.to_owned(),
                line: line_index + 1,
                corners,
            });
        }
        for word in words {
            for (kind, part) in word.split('/').enumerate().take(3) {
                let Ok(index) = part.parse::<i64>() else {
                    continue;
                };
                if kind > 0 && totals[kind] == 0 {
                    continue;
                }
                let valid = match index {
                    1.. => index.unsigned_abs() <= totals[kind] as u64,
                    ..0 => index.unsigned_abs() <= above[kind] as u64,
                    0 => false,
                };
                if !valid {
                    return Err(MeshError::ObjFaceIndex {
                        source_name: name.to_owned(),
                        line: line_index + 1,
                        what: FACE_INDEX_KINDS[kind],
                        index,
                        count: totals[kind],
                        defined_above: above[kind],
                    });
                }
            }
        }
    }
    Ok(())
}

/// 0 for a `v` line, 1 for `vt`, 2 for `vn`, `None` otherwise.
fn element_kind(line: &str) -> Option<usize> {
    match line.split_whitespace().next()? {
        "v" => Some(0),
        "vt" => Some(1),
        "vn" => Some(2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> Result<(), String> {
        check_face_indices(text, "t.obj").map_err(|e| e.to_string())
    }

    #[test]
    fn face_indices_in_range_pass_including_relative_and_forward_ones() {
        let text =
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -3 -2 -1\nf 1//1 2//1 3//1\nf 4 1 2\nv 0 0 1\n";
        assert_eq!(check(text), Ok(()));
    }

    #[test]
    fn out_of_range_face_indices_name_the_line_and_the_allowed_range() {
        let cube_like = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n";
        assert_eq!(
            check(cube_like),
            Err("t.obj: line 4: face refers to vertex 99 but the file defines 3; allowed: 1..=3 or -3..=-1".into())
        );
        assert_eq!(
            check("v 0 0 0\nf 1 -2 1\nv 1 1 1\n"),
            Err("t.obj: line 2: face refers to vertex -2 but the file defines 2; allowed: 1..=2 or -1..=-1".into())
        );
        assert_eq!(
            check("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"),
            Err(
                "t.obj: line 5: face refers to texture coordinate 2 but the file defines 1; allowed: 1..=1 or -1..=-1"
                    .into()
            )
        );
        assert!(
            check("v 0 0 0\nf 0 1 1\n").is_err(),
            "OBJ indices start at 1"
        );
        assert_eq!(
            check("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            Err("t.obj: line 3: face has 2 corners; at least 3 are needed (a point or a line is not a surface)".into())
        );
    }
}
