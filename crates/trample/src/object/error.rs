//! Why a mesh was refused (DESIGN §9).
//!
//! Every message is one line that starts with the file (or built-in shape)
//! it is about, names the offending index or key, and says what is allowed.

/// Why a mesh could not be loaded or was refused by [`super::sanitize::sanitize`].
///
/// `source_name` is the file path as given to the loader, or the name of a
/// built-in shape (`"sphere"`, ...).
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The mesh has no triangles (or no vertices).
    #[error("{source_name}: mesh is empty (no triangles)")]
    Empty {
        /// File or shape name.
        source_name: String,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "{source_name}: triangle {triangle} uses vertex {index} but the mesh has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// File or shape name.
        source_name: String,
        /// Index of the triangle (0-based).
        triangle: usize,
        /// The offending vertex index (0-based).
        index: u32,
        /// How many vertices the mesh has.
        vertex_count: usize,
    },
    /// A raw index list cannot be cut into triangles.
    #[error("{source_name}: index count {count} is not a multiple of 3")]
    IndexCountNotMultipleOf3 {
        /// File or shape name.
        source_name: String,
        /// Number of indices given.
        count: usize,
    },
    /// A vertex has a NaN or infinite coordinate.
    #[error("{source_name}: vertex {vertex} has a non-finite coordinate ({value})")]
    NonFiniteVertex {
        /// File or shape name.
        source_name: String,
        /// Index of the vertex (0-based).
        vertex: usize,
        /// The first non-finite coordinate (NaN, inf or -inf).
        value: f32,
    },
    /// The mesh is more than [`super::sanitize::MAX_SIZE_M`] across.
    #[error("{source_name}: mesh is {size_m:e} m across; at most 10000 m is allowed")]
    TooLarge {
        /// File or shape name.
        source_name: String,
        /// Diagonal of its bounding box, metres.
        size_m: f32,
    },
    /// The mesh is less than [`super::sanitize::MIN_SIZE_M`] across.
    #[error("{source_name}: mesh is {size_m:e} m across; at least 1e-6 m is needed")]
    TooSmall {
        /// File or shape name.
        source_name: String,
        /// Diagonal of its bounding box, metres.
        size_m: f32,
    },
    /// No triangle with a non-zero area is left.
    #[error("{source_name}: every triangle is degenerate (zero area)")]
    AllDegenerate {
        /// File or shape name.
        source_name: String,
    },
    /// More vertices than a `u32` index can address.
    #[error("{source_name}: {count} vertices; at most 4294967295 are allowed")]
    TooManyVertices {
        /// File or shape name.
        source_name: String,
        /// Number of vertices.
        count: usize,
    },
    /// The file could not be read (missing, no permission, not a regular
    /// file, larger than [`super::MAX_MESH_FILE_BYTES`]).
    #[error("{source_name}: cannot read the file: {reason}")]
    Io {
        /// The file.
        source_name: String,
        /// What the operating system said, or why the file was not read.
        reason: crate::paths::ReadError,
    },
    /// The file name does not end in a known mesh extension.
    #[error(
        "{source_name}: unsupported mesh file extension {extension:?}; allowed: .obj, .gltf, .glb"
    )]
    UnsupportedExtension {
        /// The file.
        source_name: String,
        /// Its extension (empty when it has none).
        extension: String,
    },
    /// An OBJ face refers to a vertex, texture coordinate or normal that the
    /// file does not define.
    #[error(
        "{source_name}: line {line}: face refers to {what} {index} but the file defines {count}; allowed: 1..={count} or -{defined_above}..=-1"
    )]
    ObjFaceIndex {
        /// The file.
        source_name: String,
        /// Line number (1-based).
        line: usize,
        /// `"vertex"`, `"texture coordinate"` or `"normal"`.
        what: &'static str,
        /// The index as written (1-based, or negative = relative).
        index: i64,
        /// How many the whole file defines (the limit of positive indices).
        count: usize,
        /// How many are defined above the line (the limit of negative indices).
        defined_above: usize,
    },
    /// An OBJ face with fewer than three corners.
    #[error(
        "{source_name}: line {line}: face has {corners} corner{}; at least 3 are needed (a point or a line is not a surface)", if *.corners == 1 { "" } else { "s" }
    )]
    ObjShortFace {
        /// The file.
        source_name: String,
        /// Line number (1-based).
        line: usize,
        /// Corners the face lists.
        corners: usize,
    },
    /// The OBJ parser refused the file.
    #[error("{source_name}: not a valid OBJ file: {reason}")]
    ObjParse {
        /// The file.
        source_name: String,
        /// What the parser said.
        reason: String,
    },
    /// The glTF parser or validator refused the file.
    #[error("{source_name}: not a valid glTF file: {reason}")]
    GltfParse {
        /// The file.
        source_name: String,
        /// What the parser said.
        reason: String,
    },
    /// A glTF buffer has no data: a `.glb` buffer without a BIN chunk.
    #[error(
        "{source_name}: buffer {buffer} has no data (it names no uri and the file has no BIN chunk)"
    )]
    GltfMissingBuffer {
        /// The file.
        source_name: String,
        /// Index of the buffer.
        buffer: usize,
    },
    /// A glTF buffer's external file cannot be read.
    #[error("{source_name}: buffer {buffer} refers to {uri:?}, which cannot be read: {reason}")]
    GltfExternalBuffer {
        /// The file.
        source_name: String,
        /// Index of the buffer.
        buffer: usize,
        /// The uri as written.
        uri: String,
        /// What went wrong (the operating system's reason, or a bad encoding).
        reason: String,
    },
    /// A glTF buffer's uri uses a scheme other than `data:` and relative paths.
    #[error(
        "{source_name}: buffer {buffer} has uri {uri:?}; allowed: a data:...;base64 uri or a path relative to the file"
    )]
    GltfUnsupportedUri {
        /// The file.
        source_name: String,
        /// Index of the buffer.
        buffer: usize,
        /// The uri as written (cut to 80 characters).
        uri: String,
    },
    /// A glTF buffer holds fewer bytes than its `byteLength`.
    #[error(
        "{source_name}: buffer {buffer} holds {actual} bytes but declares byteLength {expected}"
    )]
    GltfBufferTooShort {
        /// The file.
        source_name: String,
        /// Index of the buffer.
        buffer: usize,
        /// Declared length, bytes.
        expected: usize,
        /// Bytes available.
        actual: usize,
    },
    /// The glTF file has no mesh to load.
    #[error("{source_name}: the file has no meshes")]
    GltfNoMeshes {
        /// The file.
        source_name: String,
    },
    /// The glTF file has meshes, but no node of its scene uses one.
    #[error(
        "{source_name}: no node of the scene uses a mesh (the file has {meshes}); allowed: a scene whose nodes use at least one mesh"
    )]
    GltfSceneWithoutMeshes {
        /// The file.
        source_name: String,
        /// How many meshes the file has.
        meshes: usize,
    },
    /// A glTF primitive is not made of triangles.
    #[error(
        "{source_name}: mesh {mesh} primitive {primitive} has mode {mode}; allowed: TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN"
    )]
    GltfPrimitiveMode {
        /// The file.
        source_name: String,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// The mode found (POINTS, LINES, ...).
        mode: &'static str,
    },
    /// A glTF accessor cannot be read as positions or indices.
    #[error("{source_name}: mesh {mesh} primitive {primitive}: {attribute} {problem}")]
    GltfAccessor {
        /// The file.
        source_name: String,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// `"POSITION"` or `"indices"`.
        attribute: &'static str,
        /// What is wrong, and what is allowed.
        problem: String,
    },
    /// A glTF node is reached twice from the scene: it has more than one
    /// parent, or the hierarchy has a cycle.
    #[error(
        "{source_name}: node {node} is reached twice (more than one parent, or a cycle); each node must have at most one parent"
    )]
    GltfNodeGraph {
        /// The file.
        source_name: String,
        /// The node reached twice.
        node: usize,
    },
    /// A third-party parser panicked on the file (a bug in that parser, but
    /// the file is refused rather than the program stopped).
    #[error("{source_name}: the {parser} parser failed on this file (it panicked): {reason}")]
    ParserPanic {
        /// The file.
        source_name: String,
        /// `"OBJ"` or `"glTF"`.
        parser: &'static str,
        /// The panic message, when it was a string.
        reason: String,
    },
}
