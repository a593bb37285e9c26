//! What the benches share: the size switch, seeded inputs taken from the
//! project's scenes, the parry3d peers of our queries, and the ratio report.
#![allow(dead_code)] // each bench uses a part

pub mod peer;

use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::SystemTime;
use trample::Simulation;
use trample::collision::{patches_hit, segment_hits_obb, world_obb};
use trample::scene::Scene;

/// True when `TRAMPLE_BENCH_SMALL=1`: smaller inputs, so CI can compile and
/// smoke-run every bench in seconds.
pub fn small() -> bool {
    std::env::var("TRAMPLE_BENCH_SMALL").is_ok_and(|v| v == "1")
}

/// A scene of `scenes/` (`default.toml`, `knot.toml`); in small mode its
/// field is cut to 4 × 4 patches around the centre, where the sampled poses are.
pub fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let mut s = Scene::load(&path).expect("scene loads");
    if small() {
        s.file.field.patches = [4, 4];
    }
    s
}

/// A seeded xorshift generator of floats in [0, 1) (24 bits): the benches'
/// random inputs, the same on every run.
pub fn uniform(seed: u64) -> impl FnMut() -> f32 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Builds `scene(name)`.
pub fn sim(name: &str) -> Simulation {
    scene(name).build().expect("scene builds")
}

/// Times at which the objects of both scenes are over the middle of the field.
pub fn pose_times() -> &'static [f32] {
    if small() { &[6.0] } else { &[4.0, 6.0, 8.0] }
}

/// Blade segments at rest, in the local frame of `sim`'s first object posed
/// at each of `times`: every segment of every blade in a patch the broad
/// phase keeps (what the narrow phase sees in a step). Seeded by the scene.
pub fn field_segments(sim: &Simulation, times: &[f32]) -> Vec<(Vec3, Vec3)> {
    let body = &sim.bodies[0];
    let bl = &sim.field.blades;
    let mut out = Vec::new();
    let mut patches = Vec::new();
    for &t in times {
        let pose = body.object.pose_at(t);
        let root = world_obb(&body.tree.nodes[0].obb, &pose);
        patches_hit(&sim.field.layout.patch_list, &root, &mut patches);
        for &p in &patches {
            let patch = &sim.field.layout.patch_list[p as usize];
            for b in patch.first_blade..patch.first_blade + patch.blades {
                for k in 0..bl.segments {
                    let v = |k: usize| pose.to_local(Vec3::from(bl.rest_vertex(b as usize, k)));
                    out.push((v(k), v(k + 1)));
                }
            }
        }
    }
    out
}

/// The segments of `segments` that meet the root box of `sim`'s first
/// object: the ones that walk down the tree (the others cost one box test).
pub fn near_segments(sim: &Simulation, segments: &[(Vec3, Vec3)]) -> Vec<(Vec3, Vec3)> {
    let root = &sim.bodies[0].tree.nodes[0].obb;
    segments
        .iter()
        .copied()
        .filter(|&(a, b)| segment_hits_obb(a, b, root))
        .collect()
}

/// Where criterion writes its results (as criterion finds it:
/// `CRITERION_HOME`, else `CARGO_TARGET_DIR/criterion`, else the target
/// folder this bench binary was built in).
fn criterion_home() -> PathBuf {
    if let Some(h) = std::env::var_os("CRITERION_HOME") {
        return h.into();
    }
    if let Some(t) = std::env::var_os("CARGO_TARGET_DIR") {
        return PathBuf::from(t).join("criterion");
    }
    // target/<profile>/deps/<bench binary>
    std::env::current_exe()
        .ok()
        .and_then(|e| Some(e.parent()?.parent()?.parent()?.join("criterion")))
        .unwrap_or_else(|| "target/criterion".into())
}

/// Median time per iteration of one criterion benchmark written at or
/// after `since` (this run), ns.
fn median_ns(id: &str, since: SystemTime) -> Option<f64> {
    let path = criterion_home().join(id).join("new/estimates.json");
    if std::fs::metadata(&path).ok()?.modified().ok()? < since {
        return None;
    }
    let text = std::fs::read_to_string(path).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    v["median"]["point_estimate"].as_f64()
}

/// Prints, for each `(ours, peer)` pair of benchmark ids (`group/function/input`),
/// both medians and peer / ours: how many times faster ours is. Silent for
/// pairs criterion did not measure in this run, which started at `since`
/// (`--test`, filters).
pub fn print_ratios(pairs: &[(String, String)], since: SystemTime) {
    for (ours, peer) in pairs {
        if let (Some(a), Some(b)) = (median_ns(ours, since), median_ns(peer, since)) {
            println!(
                "ratio {ours}: {} vs {peer}: {} per iteration (medians) -> ours is {:.1}x faster",
                duration(a),
                duration(b),
                b / a
            );
        }
    }
}

/// `ns` nanoseconds as a short text: 950 ns, 12.3 µs, 4.56 ms.
fn duration(ns: f64) -> String {
    if ns < 1e3 {
        format!("{ns:.0} ns")
    } else if ns < 1e6 {
        format!("{:.3} µs", ns / 1e3)
    } else {
        format!("{:.3} ms", ns / 1e6)
    }
}

/// A point near the surface of `tree`'s mesh and the triangle it was made
/// from: a seeded triangle, a point on it, moved along its normal by up to
/// ±4 % of the mesh's size (`next`: [`uniform`]'s draws, four a point).
pub fn point_near_surface(
    tree: &trample::obb::ObbTree,
    next: &mut impl FnMut() -> f32,
) -> (Vec3, [Vec3; 3]) {
    let size = tree.nodes[0].obb.half.max_element();
    let t = (next() * tree.triangles.len() as f32) as usize % tree.triangles.len();
    let tri = tree.triangles[t];
    let (mut u, mut v) = (next(), next());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
    let p = tri[0]
        + (tri[1] - tri[0]) * u
        + (tri[2] - tri[0]) * v
        + normal * ((next() * 2.0 - 1.0) * 0.04 * size);
    (p, tri)
}
