//! `trample bench --scaling`: step time against the number of blades and
//! against the object's number of triangles, on the CPU path, the GPU path
//! (`--backend gpu`) or both side by side (`--backend both`).
//!
//! Blades, two series from the scene's field (×¼, ×1, ×4, ×16, ×64 blades;
//! 65 k … 16.8 M for the default field):
//! - **larger field**: more patches of the same cells (the object's path is
//!   unchanged, so it touches the same grass: this shows what the untouched
//!   field costs);
//! - **denser field**: the same ground with more blades per cell (×¼: cells
//!   twice as wide), so the object touches proportionally more blades.
//!
//! Triangles: the scene's first object, which must be a sphere, as an
//! icosphere of 20 × 4^s triangles for s = 0..=7 (20 … 327,680; the
//! library's largest), plus one more 4-split built here (1,310,720).
//! Also records the OBB-tree build time of each mesh.
//!
//! Points whose memory estimate passes the scene's `sim.memory_limit_gib`
//! or half of this machine's memory, points over `--max-blades` /
//! `--max-triangles`, and GPU points the adapter refuses (a field whose
//! whole-field arrays pass one storage binding) are skipped, and said so.

use super::chart::{COLORS, Chart, Series, line_chart};
use super::machine::Machine;
use super::{Setup, progress};
use crate::summary::{Recorder, Stats, write_json};
use anyhow::{Result, bail};
use glam::Vec3;
use plotters::prelude::SeriesLabelPosition;
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::time::Instant;
use trample::obb::build::DEFAULT_MAX_DEPTH;
use trample::object::{ShapeParams, TriMesh};
use trample::scene::Scene;
use trample::step::Body;

/// Blade-count factors of both series.
const BLADE_FACTORS: [(&str, u32); 5] =
    [("x1/4", 0), ("x1", 1), ("x4", 4), ("x16", 16), ("x64", 64)];
/// Icosphere subdivisions of the triangle series; 8 is refined here.
const SUBDIVISIONS: std::ops::RangeInclusive<u32> = 0..=8;

/// `scaling.json`.
#[derive(Serialize)]
struct Report {
    scene: String,
    frames: u64,
    threads: usize,
    machine: Machine,
    /// `cpu`, `gpu` or `both`.
    backend: &'static str,
    /// The GPU adapter, when the GPU path was timed.
    adapter: Option<String>,
    blades: Vec<BladePoint>,
    triangles: Vec<TrianglePoint>,
    /// Points left out, and why.
    skipped: Vec<String>,
}

#[derive(Serialize, Clone)]
struct BladePoint {
    /// `larger field` or `denser field`.
    series: &'static str,
    /// `cpu` or `gpu`.
    backend: &'static str,
    blades: u64,
    patches: [u32; 2],
    cells_per_patch: u32,
    cell_size_m: f32,
    blades_per_cell: u32,
    memory_estimate_gib: f64,
    build_ms: f64,
    precision: u32,
    step_ms: Stats,
    narrow_ms_median: f64,
    /// Median of each stage, ms.
    stages_ms: BTreeMap<&'static str, f64>,
    dbg_blades_mean: f64,
}

#[derive(Serialize, Clone)]
struct TrianglePoint {
    /// `cpu` or `gpu`.
    backend: &'static str,
    subdivisions: u32,
    triangles: usize,
    tree_build_ms: f64,
    tree_depth: u32,
    tree_nodes: usize,
    precision: u32,
    step_ms: Stats,
    narrow_ms_median: f64,
}

/// Runs both series; writes `scaling.json`, `scaling_blades.png` and
/// `scaling_triangles.png`; prints the tables.
pub fn run(scene: &Scene, setup: &Setup) -> Result<()> {
    let clock = Instant::now();
    let mut skipped = Vec::new();
    let machine = Machine::read();
    let memory_gib = machine.memory_gib;
    let backends = setup.backends();
    let gpu = if backends.contains(&"gpu") {
        let g = trample_render::headless::create_device()?;
        eprintln!("trample bench --scaling: GPU path on {}", g.adapter_name());
        crate::backend::note_far_turns(scene.file.sim.far_every);
        Some(g)
    } else {
        None
    };
    let mut blade_scenes = Vec::new();
    for series in ["larger field", "denser field"] {
        for (name, factor) in BLADE_FACTORS {
            match blade_scene(scene, series, factor, memory_gib, setup.precisions.len())
                .and_then(|s| within(s.file.field.blade_count(), setup.max_blades, "blades", s))
            {
                Ok(s) => blade_scenes.push((series, s)),
                Err(why) => skipped.push(format!("{series} {name}: {why}")),
            }
        }
    }
    let radius = match scene.file.objects.first().map(|o| &o.shape) {
        Some(&ShapeParams::Sphere { radius_m, .. }) => Some(radius_m),
        _ => {
            skipped.push(
                "triangles: the scene's first object is not a sphere (the default scene's is)"
                    .into(),
            );
            None
        }
    };
    let levels: Vec<u32> = if radius.is_some() {
        SUBDIVISIONS
            .filter(|&s| {
                let t = 20usize << (2 * s);
                let keep = setup.max_triangles.is_none_or(|m| t <= m);
                if !keep {
                    skipped.push(format!("triangles {t}: over --max-triangles"));
                }
                keep
            })
            .collect()
    } else {
        Vec::new()
    };
    let runs = setup.precisions.len() * backends.len();
    let bar = progress(setup.frames * ((blade_scenes.len() + levels.len()) * runs) as u64);
    // Times `sim` on `backend`; `None` (and a line in `skipped`) when the
    // GPU path refuses the scene.
    let time = |sim: trample::Simulation,
                backend: &str,
                what: &str,
                skipped: &mut Vec<String>|
     -> Result<Option<Recorder>> {
        super::time_on(
            backend,
            gpu.as_ref(),
            sim,
            setup.frames,
            what,
            skipped,
            &bar,
        )
    };

    let mut blades = Vec::new();
    for (series, s) in &blade_scenes {
        let f = &s.file.field;
        bar.set_message(format!("{series}: {} blades, building", f.blade_count()));
        let t = Instant::now();
        let mut base = Some(s.build()?);
        let build_ms = t.elapsed().as_secs_f64() * 1e3;
        // The estimate the build made (once a scene, not a run).
        let memory_estimate_gib = gib(base
            .as_ref()
            .and_then(|sim| sim.memory_estimate_bytes)
            .map_or_else(|| s.builder().memory_estimate_bytes(), Ok)?);
        for (i, (&precision, &backend)) in setup
            .precisions
            .iter()
            .flat_map(|p| backends.iter().map(move |b| (p, b)))
            .enumerate()
        {
            bar.set_message(format!(
                "{series}: {} blades, precision {precision}, {backend}",
                f.blade_count()
            ));
            let mut sim = last_or_clone(&mut base, i + 1 == runs);
            sim.params.precision = precision;
            let what = format!("{series}, {} blades", f.blade_count());
            let Some(rec) = time(sim, backend, &what, &mut skipped)? else {
                continue;
            };
            blades.push(BladePoint {
                series,
                backend,
                blades: f.blade_count(),
                patches: f.patches,
                cells_per_patch: f.cells_per_patch,
                cell_size_m: f.cell_size_m,
                blades_per_cell: f.blades_per_cell,
                memory_estimate_gib,
                build_ms,
                precision,
                step_ms: rec.step_ms(),
                narrow_ms_median: rec.stages_ms().get("narrow").copied().unwrap_or(0.0),
                stages_ms: rec.stages_ms(),
                dbg_blades_mean: mean_dbg(&rec),
            });
        }
    }

    let mut triangles = Vec::new();
    if let Some(radius) = radius {
        for subdivisions in levels {
            let mut s = scene.clone();
            s.file.objects[0].shape = ShapeParams::Sphere {
                radius_m: radius,
                subdivisions: subdivisions.min(7),
            };
            bar.set_message(format!(
                "triangles: icosphere level {subdivisions}, building"
            ));
            let mut base = s.build()?;
            let mut object = base.bodies[0].object.clone();
            if subdivisions > 7 {
                object.mesh = refine_sphere(&object.mesh, radius);
            }
            // The tree is built again, timed, for every level alike.
            let t = Instant::now();
            let body = Body::new(object, DEFAULT_MAX_DEPTH);
            let tree_build_ms = t.elapsed().as_secs_f64() * 1e3;
            let (tri_count, depth, nodes) = (
                body.object.mesh.triangle_count(),
                body.tree.max_depth,
                body.tree.nodes.len(),
            );
            base.bodies[0] = body;
            for &precision in &setup.precisions {
                for &backend in backends {
                    bar.set_message(format!(
                        "triangles: {tri_count}, precision {precision}, {backend}"
                    ));
                    let mut sim = base.clone();
                    sim.params.precision = precision;
                    let what = format!("{tri_count} triangles");
                    let Some(rec) = time(sim, backend, &what, &mut skipped)? else {
                        continue;
                    };
                    triangles.push(TrianglePoint {
                        backend,
                        subdivisions,
                        triangles: tri_count,
                        tree_build_ms,
                        tree_depth: depth,
                        tree_nodes: nodes,
                        precision,
                        step_ms: rec.step_ms(),
                        narrow_ms_median: rec.stages_ms().get("narrow").copied().unwrap_or(0.0),
                    });
                }
            }
        }
    }
    bar.finish_and_clear();

    let report = Report {
        scene: scene.source.clone(),
        frames: setup.frames,
        threads: setup.threads,
        machine,
        backend: setup.backend.name(),
        adapter: gpu
            .as_ref()
            .map(trample_render::headless::Gpu::adapter_name),
        blades,
        triangles,
        skipped,
    };
    let json = setup.out.join("scaling.json");
    write_json(&json, &report)?;
    blades_chart(&report, setup)?;
    triangles_chart(&report, setup)?;
    print_tables(&report);
    eprintln!(
        "trample bench --scaling: wrote {}, scaling_blades.png, scaling_triangles.png in {:.1} s",
        json.display(),
        clock.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The last user of `base` takes it; the others get a copy: one field in
/// memory less (16.8 M blades are ~4 GiB).
fn last_or_clone(base: &mut Option<trample::Simulation>, last: bool) -> trample::Simulation {
    let b = if last { base.take() } else { base.clone() };
    b.expect("taken only by the last precision")
}

fn gib(bytes: u64) -> f64 {
    bytes as f64 / 1024f64.powi(3)
}

fn mean_dbg(rec: &Recorder) -> f64 {
    rec.steps
        .iter()
        .map(|t| f64::from(t.dbg_blades))
        .sum::<f64>()
        / rec.steps.len().max(1) as f64
}

/// `s` when `n` is within `max` (or no maximum), else why not.
fn within(n: u64, max: Option<u64>, what: &str, s: Scene) -> Result<Scene> {
    match max {
        Some(m) if n > m => bail!("{n} {what}, over --max-{what} {m}"),
        _ => Ok(s),
    }
}

/// The scene with its field scaled to `factor` × the blades (0 = ¼), or why
/// not.
fn blade_scene(
    scene: &Scene,
    series: &str,
    factor: u32,
    memory_gib: f64,
    copies: usize,
) -> Result<Scene> {
    let mut s = scene.clone();
    let f = &mut s.file.field;
    match (series, factor) {
        ("larger field", 0) => {
            if f.patches.iter().any(|&p| !p.is_multiple_of(2)) {
                bail!("{:?} patches cannot be halved", f.patches);
            }
            f.patches = f.patches.map(|p| p / 2);
        }
        ("larger field", k) => {
            let side = k.isqrt();
            f.patches = f.patches.map(|p| p * side);
        }
        (_, 0) => {
            if !f.cells_per_patch.is_multiple_of(2) {
                bail!("{} cells per patch cannot be halved", f.cells_per_patch);
            }
            f.cells_per_patch /= 2;
            f.cell_size_m *= 2.0;
        }
        (_, k) => {
            f.blades_per_cell *= k;
            if f.blades_per_cell > 64 {
                bail!("{} blades per cell (at most 64)", f.blades_per_cell);
            }
        }
    }
    // Two copies at once when several precisions share one build. The
    // builder's estimate: the field's, with the strides' clock.
    let single = gib(s.builder().memory_estimate_bytes()?);
    let need = single * if copies > 1 { 2.0 } else { 1.0 };
    if memory_gib > 0.0 && need > 0.5 * memory_gib {
        bail!("needs about {need:.1} GiB, more than half of this machine's {memory_gib:.1} GiB");
    }
    // The machine check above guards a series; the derived scene's own
    // limit (`sim.memory_limit_gib`) follows its estimate.
    let limit = &mut s.file.sim.memory_limit_gib;
    if f64::from(*limit) < single {
        *limit = single.ceil() as f32;
    }
    s.validate()?;
    Ok(s)
}

/// One more level of icosphere subdivision: each triangle split in four at
/// its edge midpoints, which are pushed onto the sphere of `radius` about
/// the origin (the shape's centre). Keeps the mesh closed and outward.
fn refine_sphere(mesh: &TriMesh, radius: f32) -> TriMesh {
    let mut positions = mesh.positions.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let p = (positions[a as usize] + positions[b as usize]).normalize() * radius;
            positions.push(p);
            (positions.len() - 1) as u32
        })
    };
    let mut indices = Vec::with_capacity(mesh.indices.len() * 4);
    for &[a, b, c] in &mesh.indices {
        let (ab, bc, ca) = (
            mid(a, b, &mut positions),
            mid(b, c, &mut positions),
            mid(c, a, &mut positions),
        );
        indices.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    TriMesh { positions, indices }
}

fn blades_chart(r: &Report, setup: &Setup) -> Result<()> {
    let mut series = Vec::new();
    let backends = setup.backends();
    for (k, &backend) in backends.iter().enumerate() {
        for (i, name) in ["larger field", "denser field"].into_iter().enumerate() {
            for (j, &precision) in setup.precisions.iter().enumerate() {
                let points: Vec<(f64, f64)> = r
                    .blades
                    .iter()
                    .filter(|b| {
                        b.backend == backend && b.series == name && b.precision == precision
                    })
                    .map(|b| (b.blades as f64, b.step_ms.median))
                    .collect();
                if !points.is_empty() {
                    series.push(Series {
                        name: format!("{backend}, {name}, precision {precision}: step median"),
                        points,
                        // A colour per series, precision and path.
                        color: COLORS[(i + 2 * (j + setup.precisions.len() * k)) % COLORS.len()],
                    });
                }
            }
        }
    }
    let title = format!(
        "Step time vs blade count ({}, {} frames a point)",
        backends_title(r),
        r.frames
    );
    line_chart(
        &setup.out.join("scaling_blades.png"),
        &Chart {
            title: &title,
            x_label: "blades",
            y_label: "step time, ms (median)",
            x_log: true,
            y_log: true,
            x_integers: false,
            legend: SeriesLabelPosition::UpperLeft,
        },
        &series,
    )
}

fn triangles_chart(r: &Report, setup: &Setup) -> Result<()> {
    let backends = setup.backends();
    let mut series: Vec<Series> = backends
        .iter()
        .flat_map(|&backend| setup.precisions.iter().map(move |&p| (backend, p)))
        .enumerate()
        .map(|(j, (backend, precision))| Series {
            name: format!("{backend}, step median, precision {precision}"),
            points: r
                .triangles
                .iter()
                .filter(|t| t.backend == backend && t.precision == precision)
                .map(|t| (t.triangles as f64, t.step_ms.median))
                .collect(),
            color: COLORS[j % COLORS.len()],
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    let mut build: Vec<(f64, f64)> = r
        .triangles
        .iter()
        .map(|t| (t.triangles as f64, t.tree_build_ms))
        .collect();
    build.dedup_by(|a, b| a.0 == b.0);
    series.push(Series {
        name: "OBB-tree build (once per mesh)".into(),
        points: build,
        color: COLORS[(setup.precisions.len() * backends.len()) % COLORS.len()],
    });
    let title = format!(
        "Step time vs the object's triangles (icosphere, {})",
        backends_title(r)
    );
    line_chart(
        &setup.out.join("scaling_triangles.png"),
        &Chart {
            title: &title,
            x_label: "triangles of the object",
            y_label: "milliseconds",
            x_log: true,
            y_log: true,
            x_integers: false,
            legend: SeriesLabelPosition::UpperLeft,
        },
        &series,
    )
}

/// "CPU, 2 threads", "GPU, llvmpipe …" or both, for chart titles.
fn backends_title(r: &Report) -> String {
    let cpu = format!("CPU, {} threads", r.threads);
    let gpu = format!(
        "GPU, {}",
        r.adapter
            .as_deref()
            .and_then(|a| a.split(" (").next())
            .unwrap_or("no adapter")
    );
    match r.backend {
        "gpu" => gpu,
        "both" => format!("{cpu} / {gpu}"),
        _ => cpu,
    }
}

fn print_tables(r: &Report) {
    println!(
        "Step time against blade count ({}, {} frames a point, {} thread(s))",
        r.scene, r.frames, r.threads
    );
    println!(
        "{:>4} {:>13} {:>10} {:>9} {:>6} {:>8} {:>5} {:>9} {:>10} {:>10} {:>10} {:>10} {:>8} {:>9}",
        "path",
        "series",
        "blades",
        "patches",
        "cells",
        "cell m",
        "b/c",
        "mem GiB",
        "build ms",
        "median ms",
        "max ms",
        "narrow ms",
        "LOD ms",
        "DBG/step"
    );
    for b in &r.blades {
        println!(
            "{:>4} {:>13} {:>10} {:>9} {:>6} {:>8.2} {:>5} {:>9.2} {:>10.0} {:>10.3} {:>10.3} {:>10.3} {:>8.3} {:>9.0}  (precision {})",
            b.backend,
            b.series,
            b.blades,
            format!("{}x{}", b.patches[0], b.patches[1]),
            b.cells_per_patch,
            b.cell_size_m,
            b.blades_per_cell,
            b.memory_estimate_gib,
            b.build_ms,
            b.step_ms.median,
            b.step_ms.max,
            b.narrow_ms_median,
            b.stages_ms.get("lod").copied().unwrap_or(0.0),
            b.dbg_blades_mean,
            b.precision
        );
    }
    println!();
    println!("Step time against the object's triangles (icosphere)");
    println!(
        "{:>4} {:>5} {:>10} {:>12} {:>6} {:>10} {:>10} {:>10} {:>10}",
        "path",
        "level",
        "triangles",
        "tree ms",
        "depth",
        "precision",
        "median ms",
        "max ms",
        "narrow ms"
    );
    for t in &r.triangles {
        println!(
            "{:>4} {:>5} {:>10} {:>12.1} {:>6} {:>10} {:>10.3} {:>10.3} {:>10.3}",
            t.backend,
            t.subdivisions,
            t.triangles,
            t.tree_build_ms,
            t.tree_depth,
            t.precision,
            t.step_ms.median,
            t.step_ms.max,
            t.narrow_ms_median
        );
    }
    for s in &r.skipped {
        println!("skipped: {s}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refined_icosphere_is_closed_and_on_the_sphere() {
        let coarse = trample::object::shapes::sphere(2.0, 1);
        let fine = refine_sphere(&coarse, 2.0);
        assert_eq!(fine.triangle_count(), 4 * coarse.triangle_count());
        assert!(fine.is_closed());
        assert!(fine.signed_volume() > coarse.signed_volume());
        for p in &fine.positions {
            assert!((p.length() - 2.0).abs() < 1e-5);
        }
        // Same as the library's next level, up to vertex order.
        let next = trample::object::shapes::sphere(2.0, 2);
        assert_eq!(fine.positions.len(), next.positions.len());
        assert!((fine.signed_volume() - next.signed_volume()).abs() < 1e-4);
    }

    #[test]
    fn blade_series_scale_the_count_by_the_factor() {
        let scene = Scene::default_scene().unwrap();
        let base = scene.file.field.blade_count();
        for series in ["larger field", "denser field"] {
            for (_, k) in BLADE_FACTORS {
                let s = blade_scene(&scene, series, k, 0.0, 1).unwrap();
                let want = if k == 0 {
                    base / 4
                } else {
                    base * u64::from(k)
                };
                assert_eq!(s.file.field.blade_count(), want, "{series} x{k}");
            }
        }
        // The denser field keeps the ground: same extent.
        let d = blade_scene(&scene, "denser field", 0, 0.0, 1).unwrap();
        assert_eq!(d.file.field.extent_m(), scene.file.field.extent_m());
    }
}
