//! glTF skins and animations (object/skin.rs, object/animation.rs): a joint
//! rotated by a known angle moves its vertices where hand computation says,
//! step/linear/cubic-spline sampling, looping, the rest pose reproduces the
//! bind mesh (also for scenes/meshes/walker.glb), and bad rigs give one-line
//! errors naming the file and the item.

mod common;

use common::gltf::{TRIANGLE, buffer_bytes, document, glb};
use glam::Vec3;
use std::f32::consts::FRAC_1_SQRT_2;
use trample::object::skin::SkinScratch;
use trample::object::{RigError, SkinnedMesh};

/// Fixture data: a triangle skinned to two joints, "root" at the origin
/// and "arm" at (0, 1, 0) (its child). Vertices A = (0, 2, 0) and
/// B = (1, 2, 0) follow the arm; C = (0, 0.5, 0) is half root, half arm.
struct Rig {
    joints: [[u8; 4]; 3],
    weights: [[f32; 4]; 3],
    /// Extra JSON in the WEIGHTS_0 attribute slot (to drop it).
    attributes: &'static str,
}

impl Default for Rig {
    fn default() -> Self {
        Self {
            joints: [[1, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]],
            weights: [
                [1.0, 0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
                [0.5, 0.5, 0.0, 0.0],
            ],
            attributes: r#""POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2"#,
        }
    }
}

const POSITIONS: [[f32; 3]; 3] = [[0.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.5, 0.0]];

/// The GLB of `rig`, with animations: "bend" (arm: identity → 90° about z
/// over 1 s, LINEAR), "snap" (the same keys, STEP), "slide" (root
/// translation (0,0,0) → (2,0,0) over 1 s, CUBICSPLINE with out-tangent
/// (4,0,0) at the first key and zero tangents elsewhere).
fn rig_glb(rig: &Rig) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut push = |bytes: Vec<u8>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(format!(
            r#"{{ "buffer": 0, "byteOffset": {}, "byteLength": {} }}"#,
            bin.len(),
            bytes.len()
        ));
        bin.extend(bytes);
    };
    let floats = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    push(floats(&POSITIONS.concat())); // 0 positions
    push(rig.joints.concat()); // 1 joints
    push(floats(&rig.weights.concat())); // 2 weights
    push([0u16, 1, 2].iter().flat_map(|i| i.to_le_bytes()).collect()); // 3 indices
    let ibm: Vec<f32> = [
        glam::Mat4::IDENTITY,
        glam::Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0)),
    ]
    .iter()
    .flat_map(|m| m.to_cols_array())
    .collect();
    push(floats(&ibm)); // 4 inverse bind matrices
    push(floats(&[0.0, 1.0])); // 5 key times
    let (s, c) = (
        std::f32::consts::FRAC_PI_4.sin(),
        std::f32::consts::FRAC_PI_4.cos(),
    );
    push(floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, s, c])); // 6 rotations
    #[rustfmt::skip]
    push(floats(&[
        0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  4.0, 0.0, 0.0, // key 0: in, value, out
        0.0, 0.0, 0.0,  2.0, 0.0, 0.0,  0.0, 0.0, 0.0, // key 1
    ])); // 7 cubic translation
    let json = format!(
        r#"{{
  "asset": {{ "version": "2.0" }},
  "scene": 0,
  "scenes": [{{ "nodes": [0, 2] }}],
  "nodes": [
    {{ "name": "root", "children": [1] }},
    {{ "name": "arm", "translation": [0, 1, 0] }},
    {{ "name": "skinned", "mesh": 0, "skin": 0 }}
  ],
  "skins": [{{ "joints": [0, 1], "inverseBindMatrices": 4 }}],
  "meshes": [{{ "primitives": [{{ "attributes": {{ {attributes} }}, "indices": 3 }}] }}],
  "animations": [
    {{ "name": "bend", "samplers": [{{ "input": 5, "output": 6, "interpolation": "LINEAR" }}],
       "channels": [{{ "sampler": 0, "target": {{ "node": 1, "path": "rotation" }} }}] }},
    {{ "name": "snap", "samplers": [{{ "input": 5, "output": 6, "interpolation": "STEP" }}],
       "channels": [{{ "sampler": 0, "target": {{ "node": 1, "path": "rotation" }} }}] }},
    {{ "name": "slide", "samplers": [{{ "input": 5, "output": 7, "interpolation": "CUBICSPLINE" }}],
       "channels": [{{ "sampler": 0, "target": {{ "node": 0, "path": "translation" }} }}] }}
  ],
  "buffers": [{{ "byteLength": {len} }}],
  "bufferViews": [{views}],
  "accessors": [
    {{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0.5, 0], "max": [1, 2, 0] }},
    {{ "bufferView": 1, "componentType": 5121, "count": 3, "type": "VEC4" }},
    {{ "bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC4" }},
    {{ "bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR" }},
    {{ "bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4" }},
    {{ "bufferView": 5, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1] }},
    {{ "bufferView": 6, "componentType": 5126, "count": 2, "type": "VEC4" }},
    {{ "bufferView": 7, "componentType": 5126, "count": 6, "type": "VEC3" }}
  ]
}}"#,
        attributes = rig.attributes,
        len = bin.len(),
        views = views.join(", "),
    );
    glb(&json, Some(&bin))
}

fn load(rig: &Rig) -> Result<SkinnedMesh, RigError> {
    SkinnedMesh::parse(&rig_glb(rig), None, "rig.glb")
}

/// Skinned positions of `mesh` at `t` of `animation` (`None`: rest pose).
fn pose(mesh: &SkinnedMesh, animation: Option<&str>, t: f32) -> Vec<Vec3> {
    let animation = animation.map(|a| mesh.animation(a).expect("animation exists"));
    let mut out = Vec::new();
    mesh.pose_into(animation, t, &mut SkinScratch::default(), &mut out);
    out
}

fn assert_close(got: &[Vec3], want: &[Vec3], tolerance: f32, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: vertex count");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (*g - *w).length() <= tolerance,
            "{what}: vertex {i} at {g}, expected {w}"
        );
    }
}

#[test]
fn a_joint_rotated_by_a_known_angle_moves_its_vertices_where_hand_computation_says() {
    let mesh = load(&Rig::default()).expect("valid rig");
    assert_eq!(mesh.bind.positions.len(), 3);
    assert_eq!(mesh.joints.len(), 2);
    // "bend" at t = 0.5 s: the arm is turned 45° about z around (0, 1, 0).
    // A = (0, 2, 0): (0, 1) from the joint → (−sin 45°, cos 45°).
    // B = (1, 2, 0): (1, 1) → (cos − sin, sin + cos) = (0, √2).
    // C = (0, 0.5, 0), half each: root leaves it; the arm takes (0, −0.5)
    //     from the joint to (0.5 sin 45°, −0.5 cos 45°); the mean of the two.
    let h = FRAC_1_SQRT_2;
    let c_arm = Vec3::new(0.5 * h, 1.0 - 0.5 * h, 0.0);
    let want = [
        Vec3::new(-h, 1.0 + h, 0.0),
        Vec3::new(0.0, 1.0 + 2.0 * h, 0.0),
        (Vec3::new(0.0, 0.5, 0.0) + c_arm) * 0.5,
    ];
    assert_close(&pose(&mesh, Some("bend"), 0.5), &want, 1e-5, "bend 45°");
    // 90° at the last key, approached from below (t = 1 wraps to 0).
    let near_end = pose(&mesh, Some("bend"), 0.999_999);
    assert_close(
        &near_end[..1],
        &[Vec3::new(-1.0, 1.0, 0.0)],
        1e-4,
        "bend 90°",
    );
    // Looping: t and t + k·duration give the same bits; t = 1 is t = 0.
    assert_eq!(
        pose(&mesh, Some("bend"), 0.25),
        pose(&mesh, Some("bend"), 3.25)
    );
    assert_eq!(
        pose(&mesh, Some("bend"), -0.75),
        pose(&mesh, Some("bend"), 0.25)
    );
    assert_close(
        &pose(&mesh, Some("bend"), 1.0),
        &mesh.bind.positions,
        1e-6,
        "loop start",
    );
}

#[test]
fn step_and_cubic_spline_sampling_follow_the_keys() {
    let mesh = load(&Rig::default()).expect("valid rig");
    // STEP holds the first key until the second.
    assert_close(
        &pose(&mesh, Some("snap"), 0.9),
        &mesh.bind.positions,
        1e-6,
        "snap",
    );
    // CUBICSPLINE, span 1 s, s = 0.5: h00 = h01 = 0.5, h10 = 0.125,
    // h11 = −0.125: x = 0 + 4·0.125 + 2·0.5 + 0 = 1.5; at s = 0.25:
    // 4·0.140625 + 2·0.15625 = 0.875. Everything moves with the root.
    for (t, x) in [(0.5, 1.5), (0.25, 0.875)] {
        let want: Vec<Vec3> = mesh
            .bind
            .positions
            .iter()
            .map(|p| *p + Vec3::X * x)
            .collect();
        assert_close(&pose(&mesh, Some("slide"), t), &want, 1e-5, "slide");
    }
    let slide = mesh.animation("slide").expect("exists");
    assert_eq!(slide.duration_s, 1.0);
    assert_eq!(slide.channels[0].values.len(), 6, "three values per key");
}

#[test]
fn the_rest_pose_reproduces_the_bind_mesh() {
    let mesh = load(&Rig::default()).expect("valid rig");
    assert_close(&pose(&mesh, None, 0.0), &mesh.bind.positions, 1e-6, "rig");

    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/meshes/walker.glb"
    );
    let walker = SkinnedMesh::load(std::path::Path::new(path)).expect("walker.glb loads");
    assert_eq!(walker.joints.len(), 13);
    assert!(
        walker.bind.triangle_count() > 2000,
        "a few thousand triangles"
    );
    assert!(walker.bind.is_closed(), "six closed parts");
    assert_close(
        &pose(&walker, None, 0.0),
        &walker.bind.positions,
        1e-5,
        "walker",
    );
    // The loader of plain meshes gives the same bind mesh.
    let plain = trample::object::load_mesh_file(std::path::Path::new(path)).expect("loads");
    assert_eq!(plain.positions, walker.bind.positions);
    assert_eq!(plain.indices, walker.bind.indices);
    // The walk moves the mesh, keeps it on its feet and loops.
    let walk = walker.animation("walk").expect("walk");
    assert!((walk.duration_s - 1.0).abs() < 1e-6);
    for k in 0..8 {
        let t = k as f32 / 8.0;
        let posed = pose(&walker, Some("walk"), t);
        let lowest = posed.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
        assert!(
            (-0.03..0.06).contains(&lowest),
            "t = {t}: lowest point at y = {lowest}"
        );
        assert_eq!(posed, pose(&walker, Some("walk"), t + 2.0), "t = {t}: loop");
    }
}

#[test]
fn bad_rigs_give_one_line_errors_naming_the_file_and_the_item() {
    let mesh = load(&Rig::default()).expect("valid rig");
    let e = mesh
        .animation("run")
        .expect_err("no such animation")
        .to_string();
    assert_eq!(
        e,
        r#"rig.glb: no animation named "run"; the file has "bend", "snap", "slide""#
    );

    let e = load(&Rig {
        joints: [[1, 0, 0, 0], [7, 0, 0, 0], [0, 1, 0, 0]],
        ..Rig::default()
    })
    .expect_err("joint 7 of 2")
    .to_string();
    assert_eq!(
        e,
        "rig.glb: mesh 0 primitive 0 vertex 1: JOINTS_0 names joint 7 (weight 1) but skin 0 has 2 joints; allowed: 0..2"
    );
    // An out-of-range joint with weight 0 is ignored (exporters write 0s).
    load(&Rig {
        joints: [[1, 9, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]],
        ..Rig::default()
    })
    .expect("weight 0: ignored");

    let e = load(&Rig {
        weights: [
            [1.0, 0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0, 0.0],
            [0.5, 0.2, 0.0, 0.0],
        ],
        ..Rig::default()
    })
    .expect_err("weights sum to 0.7")
    .to_string();
    assert!(
        e.starts_with(
            "rig.glb: mesh 0 primitive 0 vertex 2: WEIGHTS_0 [0.5, 0.2, 0.0, 0.0] sum to 0.7"
        ),
        "{e}"
    );
    assert!(
        e.ends_with("allowed: non-negative weights summing to 1 ± 0.01"),
        "{e}"
    );

    let e = load(&Rig {
        attributes: r#""POSITION": 0, "JOINTS_0": 1"#,
        ..Rig::default()
    })
    .expect_err("no weights")
    .to_string();
    assert_eq!(
        e,
        "rig.glb: mesh 0 primitive 0 is skinned (its node has skin 0) but has no WEIGHTS_0; allowed: JOINTS_0 and WEIGHTS_0 on every primitive of a skinned mesh"
    );
}

/// Groups the triangles of `mesh` by connected vertices (union-find).
fn components(mesh: &trample::object::TriMesh) -> Vec<Vec<[u32; 3]>> {
    let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for t in &mesh.indices {
        for k in 1..3 {
            let (a, b) = (
                root(&mut parent, t[0] as usize),
                root(&mut parent, t[k] as usize),
            );
            parent[a] = b;
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<[u32; 3]>> = Default::default();
    for t in &mesh.indices {
        groups
            .entry(root(&mut parent, t[0] as usize))
            .or_default()
            .push(*t);
    }
    groups.into_values().collect()
}

#[test]
fn the_walkers_six_closed_parts_never_touch_through_the_walk() {
    // Parity decides "inside" (DESIGN §4): overlapping closed parts would
    // make their overlap count as outside. Every edge of every part is
    // tested against every other part, exactly (crossing or inside).
    use trample::collision::segment_hits_exact;
    use trample::obb::{DEFAULT_MAX_DEPTH, ObbTree};
    use trample::object::TriMesh;
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/meshes/walker.glb"
    );
    let walker = SkinnedMesh::load(std::path::Path::new(path)).expect("walker.glb loads");
    let parts = components(&walker.bind);
    assert_eq!(parts.len(), 6, "torso, head, two legs, two arms");
    for k in 0..10 {
        let t = k as f32 / 10.0;
        let posed = pose(&walker, Some("walk"), t);
        let meshes: Vec<TriMesh> = parts
            .iter()
            .map(|tris| TriMesh {
                positions: posed.clone(),
                indices: tris.clone(),
            })
            .collect();
        let trees: Vec<ObbTree> = meshes
            .iter()
            .map(|m| ObbTree::build(m, DEFAULT_MAX_DEPTH))
            .collect();
        for (i, tree) in trees.iter().enumerate() {
            assert!(tree.closed, "part {i} is closed");
            for (j, other) in parts.iter().enumerate() {
                if i == j {
                    continue;
                }
                for tri in other {
                    for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                        let (p, q) = (posed[tri[a] as usize], posed[tri[b] as usize]);
                        assert!(
                            !segment_hits_exact(tree, p, q),
                            "t = {t}: an edge of part {j} ({p} {q}) touches part {i}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_rigid_node_without_a_skin_moves_with_its_node() {
    // A triangle under a translated, rotated node and no skin: the bind mesh
    // is what the plain loader gives, the rest pose reproduces it, and the
    // file has no animation to ask for.
    let nodes = r#"[{ "children": [1], "rotation": [0, 0.38268343, 0, 0.9238795] },
                    { "mesh": 0, "translation": [1, 2, 3] }]"#;
    let bin = buffer_bytes(&TRIANGLE, &[0, 1, 2]);
    let bytes = glb(&document(None, bin.len(), 3, 3, 4, nodes), Some(&bin));
    let plain = trample::object::gltf::parse_gltf(&bytes, None, "rigid.glb").expect("valid");
    let rig = SkinnedMesh::parse(&bytes, None, "rigid.glb").expect("valid");
    assert_eq!(rig.bind, plain);
    assert_eq!(rig.joints.len(), 1, "one joint for the rigid node");
    assert_close(&pose(&rig, None, 0.0), &plain.positions, 1e-6, "rigid");
    let e = rig.animation("walk").expect_err("none").to_string();
    assert_eq!(
        e,
        r#"rigid.glb: no animation named "walk"; the file has none"#
    );
}
