//! `trample check`: validate a scene file and print what it describes.

use anyhow::Result;
use std::path::PathBuf;
use trample::obb::ObbTree;
use trample::obb::build::DEFAULT_MAX_DEPTH;
use trample::scene::{Scene, SceneError};

/// Arguments of `trample check`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML).
    pub scene: PathBuf,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let scene = Scene::load(&a.scene)?;
    let f = &scene.file;
    // The height map and the grass-map images, as a run reads them.
    let builder = scene.builder();
    let (_, maps) = builder
        .load_ground()
        .map_err(|e| SceneError::invalid(&scene.source, e))?;
    let objects = scene.objects()?;
    let [ex, ez] = f.field.extent_m();
    println!("{}: ok", scene.source);
    if !f.name.is_empty() {
        println!(
            "  name: {}{}",
            f.name,
            if f.description.is_empty() {
                String::new()
            } else {
                format!(" — {}", f.description)
            }
        );
    }
    println!(
        "  field: {} x {} patches of {} x {} cells, {} blade(s) per cell = {} blades x {} segments, {:.1} x {:.1} m",
        f.field.patches[0],
        f.field.patches[1],
        f.field.cells_per_patch,
        f.field.cells_per_patch,
        f.field.blades_per_cell,
        f.field.blade_count(),
        f.field.segments,
        ex,
        ez
    );
    println!(
        "  memory: about {:.1} MiB (limit {} GiB)",
        builder.memory_estimate_bytes_with(&maps) as f64 / (1024.0 * 1024.0),
        f.sim.memory_limit_gib
    );
    println!(
        "  lod: geometry < {} m, billboards < {} m, texture beyond",
        f.lod.geometry_m, f.lod.billboard_m
    );
    println!(
        "  sim: dt {} s, precision {}, att {}, threshold {} m/s, recovery {} s",
        f.sim.dt_s, f.sim.precision, f.sim.att, f.sim.threshold, f.sim.recovery_s
    );
    println!("  objects: {}", objects.len());
    for (i, o) in objects.iter().enumerate() {
        let tree = ObbTree::build(&o.mesh, DEFAULT_MAX_DEPTH);
        let dropped = o.report.degenerate_dropped + o.report.duplicate_dropped;
        println!(
            "    [{i}] {}: {} triangles{}, OBB tree depth {} ({} nodes){}",
            o.name,
            o.mesh.triangle_count(),
            describe_inside(o.closed, o.track.open_inside, &tree),
            tree.max_depth,
            tree.nodes.len(),
            if dropped > 0 {
                format!(
                    "; dropped {} degenerate and {} duplicate triangles",
                    o.report.degenerate_dropped, o.report.duplicate_dropped
                )
            } else {
                String::new()
            }
        );
    }
    println!("  run: {} frames", f.run.frames);
    Ok(())
}

/// How `tree`'s mesh is closed, and for an open one its rim (the edges its
/// triangles do not close) and, with the winding rule, the size of its
/// winding grid (`trample::collision::winding_grid`, built by the
/// simulation, not here).
fn describe_inside(closed: bool, rule: trample::object::OpenInside, tree: &ObbTree) -> String {
    if closed {
        return ", closed".into();
    }
    let rim = tree.features.rims().len();
    match rule {
        trample::object::OpenInside::Sheet => format!(", open ({rim} rim edges)"),
        trample::object::OpenInside::Winding => {
            let grid = tree
                .nodes
                .first()
                .and_then(|n| trample::collision::winding_grid::grid_voxels(n.obb.half))
                .map_or_else(
                    || "no winding grid: a flat box".to_string(),
                    |v| format!("a winding grid of {} × {} × {} voxels", v.x, v.y, v.z),
                );
            format!(", open (inside by its winding number; {rim} rim edges, {grid})")
        }
    }
}
