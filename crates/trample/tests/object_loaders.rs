//! Mesh files (DESIGN §3, §9): the real OBJ meshes (`scenes/meshes`, copies of `shared/meshes`) load
//! as they are; broken OBJ copies and glTF/GLB files generated here load or
//! fail with a message naming the file, the index and what is allowed.

mod common;
use common::gltf::{TRIANGLE, base64, buffer_bytes, document, embedded_triangle, glb};
use std::path::{Path, PathBuf};
use trample::object::gltf::load_gltf;
use trample::object::obj::load_obj;
use trample::object::{SanitizeReport, TriMesh, load_mesh_file, sanitize};

/// `scenes/meshes/NAME`: the project's copies of the shared test meshes,
/// unchanged (see `scenes/meshes/README.md`).
fn shared_mesh(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/meshes")
        .join(name)
}

/// A fresh folder for this test's files.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("trample-object-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write fixture");
    path
}

// ---------------------------------------------------------------- OBJ

#[test]
fn beetle_obj_loads_2053_triangles_and_welds_to_its_1148_vertices() {
    let mesh = load_obj(&shared_mesh("beetle.obj")).expect("beetle loads");
    // Every face of the file is a triangle: 2,053 `f` lines. tobj's
    // single index splits vertices by normal/texcoord: 1,254 of them.
    assert_eq!(mesh.triangle_count(), 2053);
    assert_eq!(mesh.positions.len(), 1254);
    let (mesh, report) = sanitize(mesh, "beetle.obj").expect("clean");
    assert_eq!(report, SanitizeReport::default());
    assert_eq!(mesh.triangle_count(), 2053);
    // Welding equal positions gives back the file's 1,148 `v` lines.
    assert_eq!(mesh.positions.len(), 1148);
    // The car is open (296 boundary edges: separate body panels).
    assert!(!mesh.is_closed());
    let (lo, hi) = mesh.bounds().expect("non-empty");
    assert!(
        (hi.z - lo.z - 0.89).abs() < 0.01,
        "about 0.9 units long along z: {lo} {hi}"
    );
}

#[test]
fn spot_obj_loads_5856_triangles_and_is_closed_after_welding() {
    let mesh = load_obj(&shared_mesh("spot.obj")).expect("spot loads");
    assert_eq!(mesh.triangle_count(), 5856);
    assert!(
        !mesh.is_closed(),
        "split by texture coordinates before welding"
    );
    let (mesh, report) = sanitize(mesh, "spot.obj").expect("clean");
    assert_eq!(report, SanitizeReport::default());
    assert_eq!(mesh.positions.len(), 2930);
    assert!(mesh.is_closed());
    assert!(mesh.signed_volume() > 0.0, "faces outwards");
}

#[test]
fn obj_polygons_are_triangulated_and_materials_normals_ignored() {
    let dir = temp_dir("quad");
    let text = "mtllib missing.mtl\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
                usemtl none\nf 1/1/1 2/1/1 3/1/1 4/1/1\no b\nv 5 0 0\nf 2 5 3\n";
    let mesh = load_obj(&write(&dir, "quad.obj", text)).expect("loads");
    assert_eq!(
        mesh.triangle_count(),
        3,
        "a quad gives 2 triangles, plus one from the second object"
    );
    let (mesh, _) = sanitize(mesh, "quad.obj").expect("clean");
    assert_eq!(
        mesh.positions.len(),
        5,
        "both objects merged, shared positions welded"
    );
}

#[test]
fn obj_face_index_out_of_range_is_an_error_with_its_line() {
    let dir = temp_dir("broken");
    let path = write(
        &dir,
        "broken.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n",
    );
    let message = load_obj(&path).expect_err("index 99").to_string();
    assert_eq!(
        message,
        format!(
            "{}: line 5: face refers to vertex 99 but the file defines 3; allowed: 1..=3 or -3..=-1",
            path.display()
        )
    );
}

#[test]
fn obj_with_absurd_indices_or_garbage_is_an_error_not_a_panic() {
    let dir = temp_dir("garbage");
    // A texture-coordinate index so negative that tobj's arithmetic would
    // overflow: caught before tobj sees it.
    let path = write(
        &dir,
        "overflow.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-9223372036854775807 2/1 3/1\n",
    );
    assert!(
        load_obj(&path)
            .expect_err("bad vt")
            .to_string()
            .contains("texture coordinate -9223372036854775807")
    );
    let path = write(&dir, "words.obj", "v 0 0 zero\nf 1 1 1\n");
    let message = load_obj(&path).expect_err("bad number").to_string();
    assert!(
        message.starts_with(&format!("{}: not a valid OBJ file: ", path.display())),
        "{message}"
    );
    let path = write(&dir, "binary.obj", [0xff, 0xfe, 0x00, 0x41]);
    assert_eq!(
        load_obj(&path).expect_err("not text").to_string(),
        format!(
            "{}: not a valid OBJ file: not UTF-8 text (bad byte at offset 0)",
            path.display()
        )
    );
    let path = write(&dir, "empty.obj", "# nothing\n");
    let mesh = load_obj(&path).expect("an empty file parses");
    assert_eq!(
        sanitize(mesh, "empty.obj")
            .expect_err("but is refused")
            .to_string(),
        "empty.obj: mesh is empty (no triangles)"
    );
}

#[test]
fn missing_file_gives_the_os_reason() {
    let path = temp_dir("missing").join("nowhere.obj");
    let message = load_mesh_file(&path).expect_err("missing").to_string();
    assert_eq!(
        message,
        format!(
            "{}: cannot read the file: No such file or directory (os error 2)",
            path.display()
        )
    );
}

#[test]
fn unknown_extension_lists_the_allowed_ones_and_case_is_ignored() {
    let dir = temp_dir("extension");
    let path = write(&dir, "mesh.stl", "solid");
    assert_eq!(
        load_mesh_file(&path).expect_err("stl").to_string(),
        format!(
            "{}: unsupported mesh file extension \"stl\"; allowed: .obj, .gltf, .glb",
            path.display()
        )
    );
    let path = write(&dir, "tri.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(
        load_mesh_file(&path)
            .expect("upper-case .OBJ")
            .triangle_count(),
        1
    );
}

// ---------------------------------------------------------------- glTF

fn expected_triangle() -> TriMesh {
    TriMesh {
        positions: TRIANGLE.iter().map(|&p| p.into()).collect(),
        indices: vec![[0, 1, 2]],
    }
}

#[test]
fn base64_helper_matches_rfc_4648_examples() {
    assert_eq!(base64(b"f"), "Zg==");
    assert_eq!(base64(b"fo"), "Zm8=");
    assert_eq!(base64(b"foobar"), "Zm9vYmFy");
}

#[test]
fn embedded_gltf_and_glb_load_the_same_triangle() {
    let dir = temp_dir("triangle");
    let gltf = load_gltf(&write(
        &dir,
        "tri.gltf",
        embedded_triangle(r#"[{ "mesh": 0 }]"#),
    ))
    .expect("gltf loads");
    assert_eq!(gltf, expected_triangle());
    let bytes = buffer_bytes(&TRIANGLE, &[0, 1, 2]);
    let json = document(None, bytes.len(), 3, 3, 4, r#"[{ "mesh": 0 }]"#);
    let glb = load_mesh_file(&write(&dir, "tri.glb", glb(&json, Some(&bytes)))).expect("glb loads");
    assert_eq!(glb, gltf);
}

#[test]
fn gltf_external_buffer_is_read_relative_to_the_file() {
    let dir = temp_dir("external");
    let bytes = buffer_bytes(&TRIANGLE, &[0, 1, 2]);
    write(&dir, "tri data.bin", &bytes);
    let path = write(
        &dir,
        "tri.gltf",
        document(
            Some("tri%20data.bin"),
            bytes.len(),
            3,
            3,
            4,
            r#"[{ "mesh": 0 }]"#,
        ),
    );
    assert_eq!(load_gltf(&path).expect("loads"), expected_triangle());
}

#[test]
fn gltf_missing_external_buffer_names_the_file_and_the_uri() {
    let dir = temp_dir("missing-buffer");
    let path = write(
        &dir,
        "tri.gltf",
        document(Some("missing.bin"), 44, 3, 3, 4, r#"[{ "mesh": 0 }]"#),
    );
    assert_eq!(
        load_gltf(&path).expect_err("no bin").to_string(),
        format!(
            "{}: buffer 0 refers to \"missing.bin\", which cannot be read: No such file or directory (os error 2)",
            path.display()
        )
    );
}

#[test]
fn glb_without_bin_chunk_and_gltf_without_uri_are_missing_buffers() {
    let dir = temp_dir("no-bin");
    let json = document(None, 44, 3, 3, 4, r#"[{ "mesh": 0 }]"#);
    for path in [
        write(&dir, "tri.glb", glb(&json, None)),
        write(&dir, "tri.gltf", &json),
    ] {
        assert_eq!(
            load_gltf(&path).expect_err("no data").to_string(),
            format!(
                "{}: buffer 0 has no data (it names no uri and the file has no BIN chunk)",
                path.display()
            )
        );
    }
}

#[test]
fn gltf_node_transforms_are_applied_and_mirrors_keep_triangles_outward() {
    let dir = temp_dir("transform");
    let nodes =
        r#"[{ "children": [1], "translation": [0, 2, 0] }, { "mesh": 0, "scale": [-1, 1, 1] }]"#;
    let mesh = load_gltf(&write(&dir, "tri.gltf", embedded_triangle(nodes))).expect("loads");
    assert_eq!(
        mesh.positions,
        vec![
            [0.0, 2.0, 0.0].into(),
            [-1.0, 2.0, 0.0].into(),
            [0.0, 3.0, 0.0].into()
        ]
    );
    // Mirrored in x, the triangle would face −z; reordered it faces +z again.
    let [a, b, c] = mesh.triangle(0);
    assert!(
        (b - a).cross(c - a).z > 0.0,
        "winding reversed with the mirror: {:?}",
        mesh.indices
    );
}

#[test]
fn gltf_triangle_strip_is_converted_with_a_consistent_winding() {
    let dir = temp_dir("strip");
    let square = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let bytes = buffer_bytes(&square, &[0, 1, 2, 3]);
    let uri = format!("data:application/octet-stream;base64,{}", base64(&bytes));
    let path = write(
        &dir,
        "strip.gltf",
        document(Some(&uri), bytes.len(), 4, 4, 5, r#"[{ "mesh": 0 }]"#),
    );
    let mesh = load_gltf(&path).expect("loads");
    assert_eq!(mesh.indices, vec![[0, 1, 2], [1, 3, 2]]);
    for i in 0..2 {
        let [a, b, c] = mesh.triangle(i);
        assert!((b - a).cross(c - a).z > 0.0, "triangle {i} faces +z");
    }
}

#[test]
fn gltf_bad_files_are_refused_with_their_reason() {
    let dir = temp_dir("bad-gltf");
    let lines = write(
        &dir,
        "lines.gltf",
        embedded_triangle(r#"[{ "mesh": 0 }]"#).replace(r#""mode": 4"#, r#""mode": 1"#),
    );
    assert_eq!(
        load_gltf(&lines).expect_err("lines").to_string(),
        format!(
            "{}: mesh 0 primitive 0 has mode LINES; allowed: TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN",
            lines.display()
        )
    );
    let no_meshes = write(&dir, "empty.gltf", r#"{ "asset": { "version": "2.0" } }"#);
    assert_eq!(
        load_gltf(&no_meshes).expect_err("no meshes").to_string(),
        format!("{}: the file has no meshes", no_meshes.display())
    );
    // Three indices declared, but the buffer view only holds two of them.
    let short = embedded_triangle(r#"[{ "mesh": 0 }]"#)
        .replace(r#""byteLength": 6 }"#, r#""byteLength": 4 }"#);
    let short = write(&dir, "short.gltf", short);
    assert_eq!(
        load_gltf(&short).expect_err("short view").to_string(),
        format!(
            "{}: mesh 0 primitive 0: indices accessor 1: 3 elements do not fit in bufferView 1 of 4 bytes",
            short.display()
        )
    );
    let http = write(
        &dir,
        "http.gltf",
        document(
            Some("https://example.com/a.bin"),
            44,
            3,
            3,
            4,
            r#"[{ "mesh": 0 }]"#,
        ),
    );
    assert_eq!(
        load_gltf(&http).expect_err("remote").to_string(),
        format!(
            "{}: buffer 0 has uri \"https://example.com/a.bin\"; allowed: a data:...;base64 uri or a path relative to the file",
            http.display()
        )
    );
    let garbage = write(&dir, "garbage.glb", b"glTF\x02\x00\x00\x00\xff\xff");
    let message = load_gltf(&garbage).expect_err("garbage").to_string();
    assert!(
        message.starts_with(&format!("{}: not a valid glTF file: ", garbage.display())),
        "{message}"
    );
    let cycle = write(
        &dir,
        "cycle.gltf",
        embedded_triangle(r#"[{ "mesh": 0, "children": [1] }, { "children": [0] }]"#),
    );
    assert!(
        load_gltf(&cycle).is_err(),
        "a cyclic node graph is refused (by validation or by the loader)"
    );
}
