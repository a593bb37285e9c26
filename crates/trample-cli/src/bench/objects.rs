//! `trample bench --objects`: step time against the number of objects
//! (issue 16, item 4): the scene's first 1, 2, 4, … objects up to all of
//! them (1 … 128 for `scenes/herd.toml`, 128 mixed objects over 16.8 M
//! blades), on the CPU path, the GPU path (`--backend gpu`) or both.
//!
//! Each point builds the scene with its first `n` objects (not timed; the
//! field is built again, so one field is in memory at a time) and times
//! `--frames` steps at each precision. Writes `objects.json` and
//! `objects.png` (step, broad-phase and narrow-phase medians against the
//! object count) and prints the table. Points the GPU path refuses are
//! skipped, and said so.

use super::chart::{COLORS, Chart, Series, line_chart};
use super::machine::Machine;
use super::{Setup, progress};
use crate::summary::{Stats, write_json};
use anyhow::Result;
use plotters::prelude::SeriesLabelPosition;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;
use trample::scene::Scene;

/// `objects.json`.
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
    blades: u64,
    /// `sim.far_every` of every run (1: every object every step).
    far_every: u32,
    /// `sim.far_outside_view` of every run (objects out of the camera's
    /// view take turns too).
    far_outside_view: bool,
    points: Vec<Point>,
    /// Points left out, and why.
    skipped: Vec<String>,
}

#[derive(Serialize)]
struct Point {
    /// `cpu` or `gpu`.
    backend: &'static str,
    objects: usize,
    /// Triangles of those objects, summed.
    triangles: usize,
    build_ms: f64,
    precision: u32,
    step_ms: Stats,
    /// Median of each stage, ms.
    stages_ms: BTreeMap<&'static str, f64>,
    dbg_blades_mean: f64,
    substeps_mean: f64,
}

/// The object counts of the series for a scene of `total` objects: powers
/// of two below it, then `total`.
fn counts(total: usize) -> Vec<usize> {
    let mut out: Vec<usize> = std::iter::successors(Some(1usize), |n| n.checked_mul(2))
        .take_while(|&n| n < total)
        .collect();
    if total > 0 {
        out.push(total);
    }
    out
}

/// Runs the series; writes `objects.json` and `objects.png`; prints the table.
pub fn run(scene: &Scene, setup: &Setup) -> Result<()> {
    let clock = Instant::now();
    let total = scene.file.objects.len();
    if total == 0 {
        anyhow::bail!("{}: --objects needs a scene with objects", scene.source);
    }
    let backends = setup.backends();
    let gpu = if backends.contains(&"gpu") {
        let g = trample_render::headless::create_device()?;
        eprintln!("trample bench --objects: GPU path on {}", g.adapter_name());
        crate::backend::note_far_turns(scene.file.sim.far_every);
        Some(g)
    } else {
        None
    };
    let counts = counts(total);
    let runs = setup.precisions.len() * backends.len();
    let bar = progress(setup.frames * (counts.len() * runs) as u64);
    let mut skipped = Vec::new();
    let mut points = Vec::new();
    for &n in &counts {
        let mut s = scene.clone();
        s.file.objects.truncate(n);
        if let Err(e) = s.validate() {
            skipped.push(format!("{n} objects: {e}"));
            bar.inc(setup.frames * runs as u64);
            continue;
        }
        bar.set_message(format!("{n} objects: building"));
        let t = Instant::now();
        let base = s.build()?;
        let build_ms = t.elapsed().as_secs_f64() * 1e3;
        let triangles = base
            .bodies
            .iter()
            .map(|b| b.object.mesh.triangle_count())
            .sum();
        let mut base = Some(base);
        for (i, (&precision, &backend)) in setup
            .precisions
            .iter()
            .flat_map(|p| backends.iter().map(move |b| (p, b)))
            .enumerate()
        {
            bar.set_message(format!("{n} objects, precision {precision}, {backend}"));
            // The last run takes the built simulation, the others a copy.
            let mut sim = if i + 1 == runs {
                base.take()
            } else {
                base.clone()
            }
            .expect("taken only by the last run");
            sim.params.precision = precision;
            let what = format!("{n} objects");
            let Some(rec) = super::time_on(
                backend,
                gpu.as_ref(),
                sim,
                setup.frames,
                &what,
                &mut skipped,
                &bar,
            )?
            else {
                continue;
            };
            let mean = |f: fn(&trample::StepTimings) -> f64| {
                rec.steps.iter().map(f).sum::<f64>() / rec.steps.len().max(1) as f64
            };
            points.push(Point {
                backend,
                objects: n,
                triangles,
                build_ms,
                precision,
                step_ms: rec.step_ms(),
                stages_ms: rec.stages_ms(),
                dbg_blades_mean: mean(|t| f64::from(t.dbg_blades)),
                substeps_mean: mean(|t| f64::from(t.substeps)),
            });
        }
    }
    bar.finish_and_clear();
    let report = Report {
        scene: scene.source.clone(),
        frames: setup.frames,
        threads: setup.threads,
        machine: Machine::read(),
        backend: setup.backend.name(),
        adapter: gpu
            .as_ref()
            .map(trample_render::headless::Gpu::adapter_name),
        blades: scene.file.field.blade_count(),
        far_every: scene.file.sim.far_every,
        far_outside_view: scene.file.sim.far_outside_view,
        points,
        skipped,
    };
    let json = setup.out.join("objects.json");
    write_json(&json, &report)?;
    chart(&report, setup)?;
    print_table(&report);
    eprintln!(
        "trample bench --objects: wrote {} and objects.png in {:.1} s",
        json.display(),
        clock.elapsed().as_secs_f64()
    );
    Ok(())
}

fn chart(r: &Report, setup: &Setup) -> Result<()> {
    let mut series = Vec::new();
    for &backend in setup.backends() {
        for &precision in &setup.precisions {
            for what in ["step", "broad", "narrow", "contact"] {
                let points: Vec<(f64, f64)> = r
                    .points
                    .iter()
                    .filter(|p| p.backend == backend && p.precision == precision)
                    .map(|p| {
                        let ms = match what {
                            "step" => p.step_ms.median,
                            stage => p.stages_ms.get(stage).copied().unwrap_or(0.0),
                        };
                        (p.objects as f64, ms)
                    })
                    .collect();
                if !points.is_empty() {
                    series.push(Series {
                        name: format!("{backend}, precision {precision}: {what} median"),
                        points,
                        color: COLORS[series.len() % COLORS.len()],
                    });
                }
            }
        }
    }
    let far = far_words(r);
    let title = format!(
        "Step time vs objects ({} blades, {} frames a point{far})",
        r.blades, r.frames
    );
    line_chart(
        &setup.out.join("objects.png"),
        &Chart {
            title: &title,
            x_label: "objects",
            y_label: "milliseconds (median)",
            x_log: true,
            y_log: true,
            x_integers: false,
            legend: SeriesLabelPosition::UpperLeft,
        },
        &series,
    )
}

/// What the title and the table say of the far turns: `, far objects every
/// K steps` (`far and unseen` with `far_outside_view`), or nothing.
fn far_words(r: &Report) -> String {
    if r.far_every > 1 {
        let unseen = if r.far_outside_view {
            " and unseen"
        } else {
            ""
        };
        format!(", far{unseen} objects every {} steps", r.far_every)
    } else {
        String::new()
    }
}

fn print_table(r: &Report) {
    let far = far_words(r);
    println!(
        "Step time against objects ({}, {} blades, {} frames a point, {} thread(s){far})",
        r.scene, r.blades, r.frames, r.threads
    );
    println!(
        "{:>4} {:>8} {:>10} {:>10} {:>10} {:>10} {:>9} {:>10} {:>10} {:>8} {:>9} {:>9}",
        "path",
        "objects",
        "triangles",
        "build ms",
        "median ms",
        "max ms",
        "broad ms",
        "narrow ms",
        "contact ms",
        "LOD ms",
        "DBG/step",
        "substeps"
    );
    for p in &r.points {
        let stage = |s: &str| p.stages_ms.get(s).copied().unwrap_or(0.0);
        println!(
            "{:>4} {:>8} {:>10} {:>10.0} {:>10.3} {:>10.3} {:>9.3} {:>10.3} {:>10.3} {:>8.3} {:>9.0} {:>9.2}  (precision {})",
            p.backend,
            p.objects,
            p.triangles,
            p.build_ms,
            p.step_ms.median,
            p.step_ms.max,
            stage("broad"),
            stage("narrow"),
            stage("contact"),
            stage("lod"),
            p.dbg_blades_mean,
            p.substeps_mean,
            p.precision
        );
    }
    for s in &r.skipped {
        println!("skipped: {s}");
    }
}

#[cfg(test)]
mod tests {
    use super::counts;

    #[test]
    fn counts_are_powers_of_two_then_all() {
        assert_eq!(counts(128), vec![1, 2, 4, 8, 16, 32, 64, 128]);
        assert_eq!(counts(5), vec![1, 2, 4, 5]);
        assert_eq!(counts(1), vec![1]);
        assert!(counts(0).is_empty());
    }
}
