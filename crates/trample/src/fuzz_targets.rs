//! The entry points of the fuzz targets (`fuzz/fuzz_targets/*.rs`, run with
//! `cargo +nightly fuzz run NAME`; see `CONTRIBUTING.md`), kept in the
//! library so that `tests/fuzz_corpus.rs` replays the committed corpus
//! through exactly the same code on stable Rust.
//!
//! Each takes arbitrary bytes. A wrong input must give an `Err` — which is
//! fine — and a right one a result that keeps the library's invariants;
//! these functions **panic** when that is not so, which is what the fuzzer
//! looks for. They are test harnesses, not an API for applications.

use crate::collision::exact::segment_hits_exact;
use crate::collision::narrow_phase::collide_segment;
use crate::obb::ObbTree;
use crate::obb::build::DEFAULT_MAX_DEPTH;
use crate::object::{ShapeParams, TriMesh, sanitize};
use crate::scene::Scene;
use glam::Vec3;
use std::path::Path;

/// A folder that does not exist: the scene target's files resolve into it
/// and are never found, so fuzzing reads no file.
const NO_FOLDER: &str = "/nonexistent/trample-fuzz";

/// Largest field (blades) the scene target builds and steps; larger valid
/// scenes are only parsed and validated (keeps one run well under a
/// millisecond or so).
const MAX_FUZZ_BLADES: u64 = 4096;

/// Largest sphere subdivision level the scene target builds (level 4 =
/// 5,120 triangles; 7 would cost ~0.3 s a run).
const MAX_FUZZ_SUBDIVISIONS: u32 = 4;

/// Scene text → [`Scene::parse`] (validation included); for a valid scene
/// with built-in shapes only and at most `MAX_FUZZ_BLADES` blades, builds
/// the simulation (field, objects, OBB trees) and runs 4 steps of its `dt`,
/// then checks every blade vertex is finite and every segment keeps its
/// rest length (within 1e-3 relative). Mesh files and height maps resolve
/// into a folder that does not exist.
///
/// # Panics
/// When a step fails on a valid scene, a vertex is not finite, or a segment
/// length drifts.
pub fn scene(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = Scene::parse(text, "fuzz.toml", Path::new(NO_FOLDER)) else {
        return;
    };
    let f = &scene.file;
    let cheap = f.objects.iter().all(|o| match o.shape {
        ShapeParams::Sphere { subdivisions, .. } => subdivisions <= MAX_FUZZ_SUBDIVISIONS,
        ShapeParams::Mesh { .. } => false,
        _ => true,
    });
    if !cheap || f.field.blade_count() > MAX_FUZZ_BLADES {
        // Objects alone (meshes fail to load: no folder).
        let _ = scene.objects();
        return;
    }
    let Ok(mut sim) = scene.build() else {
        return;
    };
    for _ in 0..4 {
        sim.step(f.sim.dt_s)
            .expect("a valid scene's dt is accepted");
    }
    let bl = &sim.field.blades;
    for b in 0..bl.count {
        for k in 0..=bl.segments {
            let v = bl.vertex(b, k);
            assert!(v.is_finite(), "blade {b} vertex {k} is {v}");
            if k > 0 {
                let len = v.distance(bl.vertex(b, k - 1));
                let rest = bl.seg_len[b];
                assert!(
                    (len - rest).abs() <= 1e-3 * rest,
                    "blade {b} segment {k}: length {len}, rest {rest}"
                );
            }
        }
    }
}

/// OBJ bytes → [`crate::object::obj::parse_obj`] → [`mesh`]'s checks on the
/// result when it loads.
pub fn obj(data: &[u8]) {
    if let Ok(m) = crate::object::obj::parse_obj(data, "fuzz.obj") {
        check_mesh(m);
    }
}

/// glTF or GLB bytes → [`crate::object::gltf::parse_gltf`] (no folder:
/// external buffers are refused) → [`mesh`]'s checks on the result; and
/// [`crate::object::SkinnedMesh::parse`], posed at a few times.
pub fn gltf(data: &[u8]) {
    if let Ok(m) = crate::object::gltf::parse_gltf(data, None, "fuzz.gltf") {
        check_mesh(m);
    }
    // The same bytes as a rig: skin, skeleton, animations, posed at a few
    // times (object/skin.rs, object/animation.rs).
    if let Ok(rig) = crate::object::SkinnedMesh::parse(data, None, "fuzz.gltf") {
        let mut scratch = crate::object::skin::SkinScratch::default();
        let mut out = Vec::new();
        for t in [0.0, 0.37, -1.0, f32::NAN] {
            rig.pose_into(rig.animations.first(), t, &mut scratch, &mut out);
            assert_eq!(out.len(), rig.bind.positions.len());
        }
    }
}

/// Bytes → a raw [`TriMesh`] (see [`mesh_from_bytes`]) → [`sanitize()`] → OBB
/// tree → collision queries, as [`check_mesh`] describes.
pub fn mesh(data: &[u8]) {
    check_mesh(mesh_from_bytes(data));
}

/// Decodes bytes as a small raw mesh: byte 0 picks the coordinate encoding
/// (even: 16-bit integers in millimetres, ±32.8 m; odd: raw `f32` bits, so
/// NaN, infinities and huge values occur), byte 1 the vertex count (0–63),
/// then the coordinates, then triangles of three bytes, each index taken
/// modulo `vertices + 2` (so some are out of range).
#[must_use]
pub fn mesh_from_bytes(data: &[u8]) -> TriMesh {
    let (Some(&mode), Some(&count)) = (data.first(), data.get(1)) else {
        return TriMesh::default();
    };
    let vertices = usize::from(count % 64);
    let width = if mode % 2 == 0 { 2 } else { 4 };
    let mut rest = &data[2..];
    let mut coordinate = || -> Option<f32> {
        let (head, tail) = rest.split_at_checked(width)?;
        rest = tail;
        Some(match *head {
            [a, b] => f32::from(i16::from_le_bytes([a, b])) * 1e-3,
            [a, b, c, d] => f32::from_le_bytes([a, b, c, d]),
            _ => unreachable!("width is 2 or 4"),
        })
    };
    let mut positions = Vec::with_capacity(vertices);
    for _ in 0..vertices {
        let (Some(x), Some(y), Some(z)) = (coordinate(), coordinate(), coordinate()) else {
            break;
        };
        positions.push(Vec3::new(x, y, z));
    }
    let modulus = positions.len() as u32 + 2;
    let indices = rest
        .chunks_exact(3)
        .map(|t| [0, 1, 2].map(|k| u32::from(t[k]) % modulus))
        .collect();
    TriMesh { positions, indices }
}

/// The checks every fuzzed mesh goes through: [`sanitize()`]; when it accepts
/// the mesh, the result is well formed (at least one triangle, every index
/// in range), its OBB tree passes [`ObbTree::validate`], and up to 19
/// segments around it (through the centre along the three axes, along the
/// four diagonals of its box, and vertically through the centroids of up to
/// 12 triangles) keep the narrow phase's
/// properties: hits at precision d+1 ⊆ hits at d (d = 1..7), and a segment
/// that [`segment_hits_exact`] says hits is hit at every precision.
///
/// # Panics
/// On any violated property.
pub fn check_mesh(raw: TriMesh) {
    let Ok((mesh, _report)) = sanitize(raw, "fuzz") else {
        return;
    };
    assert!(!mesh.indices.is_empty(), "sanitize kept no triangle");
    assert!(
        mesh.indices
            .iter()
            .flatten()
            .all(|&i| (i as usize) < mesh.positions.len()),
        "sanitize kept an index out of range"
    );
    let tree = ObbTree::build(&mesh, DEFAULT_MAX_DEPTH);
    if let Err(e) = tree.validate() {
        panic!("OBB tree is not well formed: {e}");
    }
    for (p0, p1) in probe_segments(&mesh) {
        let exact = segment_hits_exact(&tree, p0, p1);
        let mut above = true;
        for precision in 1..=7 {
            let hit = collide_segment(p0, p1, &tree, precision).is_some();
            assert!(
                !hit || above,
                "segment {p0}–{p1} hits at precision {precision} but not at {}",
                precision - 1
            );
            assert!(
                !exact || hit,
                "segment {p0}–{p1} hits exactly but not at precision {precision}"
            );
            above = hit;
        }
    }
}

/// Segments that probe a mesh: through its bounding box's centre along each
/// axis, along the box's diagonals, and vertical ones through the centroids
/// of up to 12 triangles (blades stand vertically).
fn probe_segments(mesh: &TriMesh) -> Vec<(Vec3, Vec3)> {
    let Some((lo, hi)) = mesh.bounds() else {
        return Vec::new();
    };
    let (c, h) = ((lo + hi) * 0.5, (hi - lo) * 0.5 + Vec3::splat(1e-3));
    let mut out: Vec<(Vec3, Vec3)> = [Vec3::X, Vec3::Y, Vec3::Z]
        .iter()
        .map(|&a| (c - a * h * 1.5, c + a * h * 1.5))
        .collect();
    for s in [
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(1.0, 1.0, -1.0),
    ] {
        out.push((c - s * h, c + s * h));
    }
    for t in 0..mesh.triangle_count().min(12) {
        let [a, b, d] = mesh.triangle(t);
        let g = (a + b + d) / 3.0;
        out.push((g - Vec3::Y * h.y, g + Vec3::Y * h.y));
    }
    out
}
