//! glTF 2.0 loading, `.gltf` (JSON) and `.glb` (binary), through the `gltf`
//! crate for parsing and validation.
//!
//! Loaded: every primitive of every mesh used by a node of the default scene
//! (the first scene when none is marked default; every root node when the
//! file has no scene; every mesh, untransformed, when it has no node), with
//! the node's world transform applied, as one triangle mesh. Triangle strips
//! and fans are converted to triangles; points and lines are refused.
//!
//! Buffers are read here rather than by `gltf::import`, so that images are
//! never decoded and a missing external file is reported with its uri, and
//! accessors are read here with every offset checked, so that a bad file is
//! an error, never an out-of-bounds panic.

use super::error::MeshError;
use super::mesh::TriMesh;
use super::sanitize::triangles_from_indices;
use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::buffer::Source;
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Document, Gltf, Node, Primitive, Semantic};
use glam::{Mat4, Vec3};
use std::collections::HashSet;
use std::path::Path;

/// Loads the triangles of the glTF or GLB file at `path` as one mesh:
/// [`super::read_mesh_bytes`] then [`parse_gltf`] with the file's folder as
/// the folder its external buffers must be in. The mesh is not sanitised:
/// see [`super::sanitize::sanitize`].
///
/// # Errors
/// [`MeshError::Io`] when the file cannot be read, else those of
/// [`parse_gltf`]. Every message names the file.
pub fn load_gltf(path: &Path) -> Result<TriMesh, MeshError> {
    let bytes = super::read_mesh_bytes(path)?;
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    parse_gltf(&bytes, Some(folder), &path.display().to_string())
}

/// Parses the bytes of a glTF or GLB file (`name` is used in messages) as
/// one mesh, in the file's units (metres by the glTF convention) and world
/// frame (glTF is y-up and right-handed, like trample). A transform that
/// mirrors (negative determinant) has its triangles' order reversed, so
/// they keep facing outwards.
///
/// External buffers (`"uri": "car.bin"`) are read from `buffer_folder` and
/// must stay inside it ([`crate::paths::resolve_inside`]: no absolute path,
/// no `..` above it); with `None` (the fuzz target) only embedded buffers
/// (`data:` uris, a GLB's BIN chunk) are read. Never panics (the fuzz
/// target `gltf` holds it to that).
///
/// # Errors
/// [`MeshError::GltfParse`] (invalid JSON/GLB or glTF validation), buffer
/// errors ([`MeshError::GltfMissingBuffer`], [`MeshError::GltfExternalBuffer`],
/// [`MeshError::GltfUnsupportedUri`], [`MeshError::GltfBufferTooShort`]),
/// [`MeshError::GltfNoMeshes`], [`MeshError::GltfSceneWithoutMeshes`],
/// [`MeshError::GltfNodeGraph`], [`MeshError::GltfPrimitiveMode`],
/// [`MeshError::GltfAccessor`].
pub fn parse_gltf(
    bytes: &[u8],
    buffer_folder: Option<&Path>,
    name: &str,
) -> Result<TriMesh, MeshError> {
    let name = name.to_owned();
    let (document, buffers) = open_document(bytes, buffer_folder, &name)?;
    if document.meshes().len() == 0 {
        return Err(MeshError::GltfNoMeshes { source_name: name });
    }
    let instances = mesh_instances(&document, &name)?;
    if instances.is_empty() {
        return Err(MeshError::GltfSceneWithoutMeshes {
            source_name: name,
            meshes: document.meshes().len(),
        });
    }
    let mut out = TriMesh::default();
    for (_, mesh, transform) in instances {
        for primitive in mesh.primitives() {
            append_primitive(
                &mut out,
                &primitive,
                mesh.index(),
                transform,
                &buffers,
                &name,
            )?;
        }
    }
    Ok(out)
}

/// The validated document of a glTF or GLB file and the bytes of its
/// buffers (see [`parse_gltf`] for `buffer_folder`). Shared with the skin
/// and animation loaders ([`super::skin`]).
pub(crate) fn open_document(
    bytes: &[u8],
    buffer_folder: Option<&Path>,
    name: &str,
) -> Result<(Document, Vec<Vec<u8>>), MeshError> {
    let name = name.to_owned();
    let parse_error = |e: ::gltf::Error| MeshError::GltfParse {
        source_name: name.clone(),
        reason: e.to_string(),
    };
    check_glb_length(bytes, &name)?;
    let Gltf { document, blob } =
        super::catch_parser_panic(&name, "glTF", || Gltf::from_slice_without_validation(bytes))?
            .map_err(parse_error)?;
    // gltf-json 1.4's validation indexes each primitive's POSITION accessor
    // without a bounds check (found by the fuzz target `gltf`): check those
    // indices first, then validate.
    check_position_accessors(&document, &name)?;
    let document =
        super::catch_parser_panic(&name, "glTF", || Document::from_json(document.into_json()))?
            .map_err(parse_error)?;
    let buffers = load_buffers(&document, buffer_folder, blob, &name)?;
    Ok((document, buffers))
}

/// A GLB's declared total length (bytes 8..12) is at least its 12-byte
/// header: the `gltf` crate (1.4) subtracts 12 from it unchecked, which
/// panics (overflow) in a build with debug assertions (found by the fuzz
/// target `gltf`). Other lengths it checks itself.
fn check_glb_length(bytes: &[u8], name: &str) -> Result<(), MeshError> {
    if let Some([b'g', b'l', b'T', b'F', _, _, _, _, l0, l1, l2, l3]) = bytes.get(..12) {
        let length = u32::from_le_bytes([*l0, *l1, *l2, *l3]);
        if length < 12 {
            return Err(MeshError::GltfParse {
                source_name: name.to_owned(),
                reason: format!(
                    "GLB header declares a total length of {length} bytes; at least its own 12 are needed"
                ),
            });
        }
    }
    Ok(())
}

/// Every primitive's POSITION accessor index is below the number of
/// accessors (before validation, which would panic on it).
fn check_position_accessors(document: &Document, name: &str) -> Result<(), MeshError> {
    use ::gltf::json::validation::Checked;
    let json = document.as_json();
    let accessors = json.accessors.len();
    for (mesh, m) in json.meshes.iter().enumerate() {
        for (primitive, p) in m.primitives.iter().enumerate() {
            if let Some(index) = p.attributes.get(&Checked::Valid(Semantic::Positions))
                && index.value() >= accessors
            {
                return Err(MeshError::GltfAccessor {
                    source_name: name.to_owned(),
                    mesh,
                    primitive,
                    attribute: "POSITION",
                    problem: format!(
                        "refers to accessor {} but the file has {accessors}; allowed: 0..{accessors}",
                        index.value()
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The bytes of every buffer, in order.
fn load_buffers(
    document: &Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
    name: &str,
) -> Result<Vec<Vec<u8>>, MeshError> {
    let mut buffers = Vec::with_capacity(document.buffers().len());
    for buffer in document.buffers() {
        let index = buffer.index();
        let data = match buffer.source() {
            Source::Bin => blob.take().ok_or_else(|| MeshError::GltfMissingBuffer {
                source_name: name.to_owned(),
                buffer: index,
            })?,
            Source::Uri(uri) => read_uri(uri, base, index, name)?,
        };
        if data.len() < buffer.length() {
            return Err(MeshError::GltfBufferTooShort {
                source_name: name.to_owned(),
                buffer: index,
                expected: buffer.length(),
                actual: data.len(),
            });
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// Reads a buffer uri: a `data:` uri (decoded by the `gltf` crate), or a
/// percent-encoded path (optionally `file:`) relative to `base` and inside
/// it. With no `base`, only `data:` uris are read.
fn read_uri(
    uri: &str,
    base: Option<&Path>,
    buffer: usize,
    name: &str,
) -> Result<Vec<u8>, MeshError> {
    let external = |reason: String| MeshError::GltfExternalBuffer {
        source_name: name.to_owned(),
        buffer,
        uri: uri.chars().take(80).collect(),
        reason,
    };
    if uri.starts_with("data:") {
        let data = ::gltf::buffer::Data::from_source(Source::Uri(uri), None)
            .map_err(|e| external(format!("bad data uri: {e}")))?;
        return Ok(data.0);
    }
    let relative = uri
        .strip_prefix("file://")
        .or_else(|| uri.strip_prefix("file:"))
        .unwrap_or(uri);
    if relative.contains(':') {
        return Err(MeshError::GltfUnsupportedUri {
            source_name: name.to_owned(),
            buffer,
            uri: uri.chars().take(80).collect(),
        });
    }
    let base = base.ok_or_else(|| external("no folder to read external buffers from".into()))?;
    let decoded =
        percent_decode(relative).ok_or_else(|| external("bad percent-encoding".into()))?;
    let file = crate::paths::resolve_inside(base, Path::new(&decoded))
        .map_err(|e| external(format!("the path {e}")))?;
    crate::paths::read_regular_file(&file, super::MAX_MESH_FILE_BYTES)
        .map_err(|e| external(e.to_string()))
}

/// Decodes `%XX` escapes; `None` when an escape is malformed or the result
/// is not UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Every (node, mesh, world transform) to load, in scene order (see the
/// module documentation for which nodes are visited; `None` for a mesh of a
/// file without nodes).
pub(crate) fn mesh_instances<'a>(
    document: &'a Document,
    name: &str,
) -> Result<Vec<(Option<Node<'a>>, ::gltf::Mesh<'a>, Mat4)>, MeshError> {
    let roots: Vec<Node<'a>> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None if document.nodes().len() == 0 => {
            return Ok(document
                .meshes()
                .map(|mesh| (None, mesh, Mat4::IDENTITY))
                .collect());
        }
        None => {
            let children: HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()))
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    let mut instances = Vec::new();
    let mut visited = HashSet::new();
    let mut stack: Vec<(Node<'a>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    while let Some((node, parent)) = stack.pop() {
        if !visited.insert(node.index()) {
            return Err(MeshError::GltfNodeGraph {
                source_name: name.to_owned(),
                node: node.index(),
            });
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            instances.push((Some(node.clone()), mesh, world));
        }
        let children: Vec<Node<'a>> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
    }
    Ok(instances)
}

/// Appends one primitive's triangles, transformed, to `out`.
pub(crate) fn append_primitive(
    out: &mut TriMesh,
    primitive: &Primitive<'_>,
    mesh: usize,
    transform: Mat4,
    buffers: &[Vec<u8>],
    name: &str,
) -> Result<(), MeshError> {
    let index = primitive.index();
    let accessor_error = |attribute: &'static str, problem: String| MeshError::GltfAccessor {
        source_name: name.to_owned(),
        mesh,
        primitive: index,
        attribute,
        problem,
    };
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        let mode = match mode {
            Mode::Points => "POINTS",
            Mode::Lines => "LINES",
            Mode::LineLoop => "LINE_LOOP",
            _ => "LINE_STRIP",
        };
        return Err(MeshError::GltfPrimitiveMode {
            source_name: name.to_owned(),
            mesh,
            primitive: index,
            mode,
        });
    }
    let positions = primitive.get(&Semantic::Positions).ok_or_else(|| {
        accessor_error("POSITION", "is missing; every primitive needs one".into())
    })?;
    let positions =
        read_positions(&positions, buffers).map_err(|p| accessor_error("POSITION", p))?;
    let vertex_count = positions.len();
    let order: Vec<u32> = match primitive.indices() {
        Some(accessor) => {
            read_indices(&accessor, buffers).map_err(|p| accessor_error("indices", p))?
        }
        None => (0..u32::try_from(vertex_count).unwrap_or(u32::MAX)).collect(),
    };
    if let Some(&bad) = order.iter().find(|&&i| i as usize >= vertex_count) {
        return Err(accessor_error(
            "indices",
            format!("has index {bad}; allowed: 0..{vertex_count} (the POSITION count)"),
        ));
    }
    let mut triangles = match mode {
        Mode::TriangleStrip => (0..order.len().saturating_sub(2))
            .map(|i| {
                let odd = i % 2;
                [order[i], order[i + 1 + odd], order[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (0..order.len().saturating_sub(2))
            .map(|i| [order[i + 1], order[i + 2], order[0]])
            .collect(),
        _ => triangles_from_indices(&order, name)?,
    };
    if transform.determinant() < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let offset = u32::try_from(out.positions.len() + vertex_count)
        .map(|end| end - vertex_count as u32)
        .map_err(|_| MeshError::TooManyVertices {
            source_name: name.to_owned(),
            count: out.positions.len() + vertex_count,
        })?;
    out.positions
        .extend(positions.into_iter().map(|p| transform.transform_point3(p)));
    out.indices
        .extend(triangles.into_iter().map(|t| t.map(|i| i + offset)));
    Ok(())
}

/// A POSITION accessor's points: `VEC3` of `f32`, as the glTF core requires.
fn read_positions(accessor: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<Vec3>, String> {
    if accessor.dimensions() != Dimensions::Vec3 || accessor.data_type() != DataType::F32 {
        return Err(format!(
            "accessor {} is {:?} of {:?}; allowed: Vec3 of F32",
            accessor.index(),
            accessor.dimensions(),
            accessor.data_type()
        ));
    }
    Ok(elements(accessor, buffers)?
        .map(|b| {
            let f =
                |k: usize| f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]);
            Vec3::new(f(0), f(1), f(2))
        })
        .collect())
}

/// An index accessor's values: `SCALAR` of `u8`, `u16` or `u32`.
fn read_indices(accessor: &Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    let data_type = accessor.data_type();
    if accessor.dimensions() != Dimensions::Scalar
        || !matches!(data_type, DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "accessor {} is {:?} of {:?}; allowed: Scalar of U8, U16 or U32",
            accessor.index(),
            accessor.dimensions(),
            data_type
        ));
    }
    Ok(elements(accessor, buffers)?
        .map(|b| match data_type {
            DataType::U8 => u32::from(b[0]),
            DataType::U16 => u32::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        })
        .collect())
}

/// An accessor of `dimensions` as floats, `components` per element (VEC4:
/// 4, MAT4: 16, ...), column-major as stored: `F32`, or a `normalized`
/// integer type mapped as glTF §3.11 says (unsigned `c / max`, signed
/// `max(c / max, −1)`). Non-finite values are refused. Used for skins and
/// animations ([`super::skin`], [`super::animation`]).
pub(crate) fn read_floats(
    accessor: &Accessor<'_>,
    buffers: &[Vec<u8>],
    dimensions: Dimensions,
) -> Result<Vec<f32>, String> {
    let data_type = accessor.data_type();
    let normalized = accessor.normalized();
    if accessor.dimensions() != dimensions || !(data_type == DataType::F32 || normalized) {
        return Err(format!(
            "accessor {} is {:?} of {:?}{}; allowed: {dimensions:?} of F32 (or of a normalized integer type)",
            accessor.index(),
            accessor.dimensions(),
            data_type,
            if normalized { " (normalized)" } else { "" },
        ));
    }
    let components = dimensions.multiplicity();
    let width = data_type.size();
    let mut out = Vec::with_capacity(accessor.count() * components);
    for element in elements(accessor, buffers)? {
        for c in element.chunks_exact(width).take(components) {
            let value = match data_type {
                DataType::F32 => f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
                DataType::U8 => f32::from(c[0]) / 255.0,
                DataType::I8 => (f32::from(c[0] as i8) / 127.0).max(-1.0),
                DataType::U16 => f32::from(u16::from_le_bytes([c[0], c[1]])) / 65535.0,
                DataType::I16 => (f32::from(i16::from_le_bytes([c[0], c[1]])) / 32767.0).max(-1.0),
                DataType::U32 => {
                    u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f32 / u32::MAX as f32
                }
            };
            if !value.is_finite() {
                return Err(format!(
                    "accessor {} holds a non-finite value ({value}); allowed: finite numbers",
                    accessor.index()
                ));
            }
            out.push(value);
        }
    }
    Ok(out)
}

/// An accessor of `VEC4` unsigned integers (`U8` or `U16`, as glTF allows
/// for `JOINTS_0`), four per element.
pub(crate) fn read_joint_indices(
    accessor: &Accessor<'_>,
    buffers: &[Vec<u8>],
) -> Result<Vec<[u32; 4]>, String> {
    let data_type = accessor.data_type();
    if accessor.dimensions() != Dimensions::Vec4
        || !matches!(data_type, DataType::U8 | DataType::U16)
    {
        return Err(format!(
            "accessor {} is {:?} of {:?}; allowed: Vec4 of U8 or U16",
            accessor.index(),
            accessor.dimensions(),
            data_type
        ));
    }
    Ok(elements(accessor, buffers)?
        .map(|b| {
            std::array::from_fn(|k| match data_type {
                DataType::U8 => u32::from(b[k]),
                _ => u32::from(u16::from_le_bytes([b[2 * k], b[2 * k + 1]])),
            })
        })
        .collect())
}

/// The bytes of each element of a (non-sparse) accessor, every range checked
/// against its buffer view and buffer.
pub(crate) fn elements<'b>(
    accessor: &Accessor<'_>,
    buffers: &'b [Vec<u8>],
) -> Result<impl Iterator<Item = &'b [u8]>, String> {
    let id = accessor.index();
    if accessor.sparse().is_some() {
        return Err(format!(
            "accessor {id} is sparse; sparse accessors are not supported"
        ));
    }
    let view = accessor
        .view()
        .ok_or_else(|| format!("accessor {id} has no bufferView"))?;
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("accessor {id}: buffer missing"))?;
    let view_bytes = view
        .offset()
        .checked_add(view.length())
        .and_then(|end| buffer.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "accessor {id}: bufferView {} lies outside its buffer of {} bytes",
                view.index(),
                buffer.len()
            )
        })?;
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if size == 0 || stride < size {
        return Err(format!(
            "accessor {id}: byteStride {stride} is smaller than its element size {size}"
        ));
    }
    let count = accessor.count();
    let needed = match count {
        0 => Some(accessor.offset()),
        _ => stride
            .checked_mul(count - 1)
            .and_then(|s| s.checked_add(accessor.offset()))
            .and_then(|s| s.checked_add(size)),
    };
    let data = needed
        .and_then(|end| view_bytes.get(accessor.offset()..end))
        .ok_or_else(|| {
            format!(
                "accessor {id}: {count} elements do not fit in bufferView {} of {} bytes",
                view.index(),
                view.length()
            )
        })?;
    Ok((0..count).map(move |k| &data[k * stride..k * stride + size]))
}
