//! The paper's pressure test (§7, Fig. 12): the same field and object path
//! at precisions 1..7, N frames each, lowest / highest / average frame rate;
//! here of the simulation alone (frame rate = 1000 / step milliseconds).
//! Then the accuracy those precisions buy, against the exact reference, for
//! the bench's scene and the built-in complex shape.

use super::chart::{COLORS, Chart, Series, line_chart, thousands};
use super::machine::Machine;
use super::{Backend, Setup, Stepped, lap_frames, motion_end_s, progress, time_frames};
use crate::summary::{Recorder, Stats, write_json};
use anyhow::Result;
use plotters::prelude::SeriesLabelPosition;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;
use trample::accuracy::{Accuracy, measure_accuracy, sample_times};
use trample::scene::Scene;

/// The built-in complex shape's scene (`scenes/knot.toml`): the second
/// object of the accuracy test.
const KNOT_SCENE_TOML: &str = include_str!("../../../../scenes/knot.toml");

/// Times of each object's path at which accuracy is measured.
const ACCURACY_SAMPLES: usize = 8;

/// `bench.json`.
#[derive(Serialize)]
struct Report {
    scene: String,
    blades: usize,
    segments: usize,
    objects: Vec<ObjectInfo>,
    backend: &'static str,
    threads: usize,
    machine: Machine,
    frames: u64,
    dt_s: f32,
    /// Frames after which the run restarts from the first frame (the
    /// path's length); null when it never does.
    lap_frames: Option<u64>,
    build_ms: f64,
    /// The adapter that rendered (`--render`); null for the simulation alone.
    adapter: Option<String>,
    precisions: Vec<PrecisionRun>,
    accuracy: Vec<AccuracyRun>,
}

#[derive(Serialize)]
struct ObjectInfo {
    name: String,
    triangles: usize,
    tree_depth: u32,
}

/// One precision of the pressure test on one backend.
#[derive(Serialize)]
struct PrecisionRun {
    /// `cpu` or `gpu`.
    backend: &'static str,
    precision: u32,
    /// Frame rate of the simulation alone, 1000 / step ms: `min` from the
    /// slowest step, `max` from the fastest, `avg` = frames / total time.
    fps: Fps,
    step_ms: Stats,
    /// 99th percentile of the step times, ms: the slow tail without the
    /// single worst step (on a shared machine, often a scheduling stall).
    step_ms_p99: f64,
    /// Median of each stage, ms.
    stages_ms: BTreeMap<&'static str, f64>,
    /// Blades hit directly, mean per frame.
    dbg_blades_mean: f64,
    wall_s: f64,
    /// With `--render`: each frame also rendered offscreen and read back.
    render: Option<RenderRun>,
}

/// Simulation + rendering of one precision (`--render`), the paper's
/// measurement.
#[derive(Serialize)]
struct RenderRun {
    /// Image size, pixels.
    size: [u32; 2],
    /// Render time per frame (and the read-back, when `read_back`), ms.
    render_ms: Stats,
    /// Whether each frame was read back to the CPU (`--no-readback`: no).
    read_back: bool,
    /// Frame rate of step + render: `min` from the slowest frame, `max` from
    /// the fastest, `avg` = frames / total time.
    fps: Fps,
}

#[derive(Serialize, Clone, Copy)]
struct Fps {
    min: f64,
    avg: f64,
    max: f64,
}

/// Accuracy of one scene's objects.
#[derive(Serialize)]
struct AccuracyRun {
    scene: String,
    objects: Vec<ObjectInfo>,
    #[serde(flatten)]
    accuracy: Accuracy,
    /// `per_precision[i].false_positive_rate`, repeated for readers of the JSON.
    false_positive_rate: Vec<f64>,
}

/// Runs the pressure test and the accuracy measurement; writes
/// `bench.json`, `bench.png` and `accuracy.png`; prints the tables.
pub fn run(scene: &Scene, setup: &Setup) -> Result<()> {
    let machine = Machine::read();
    let clock = Instant::now();
    let base = scene.build()?;
    let build_ms = clock.elapsed().as_secs_f64() * 1e3;
    let mut accuracy_scenes = vec![scene.clone()];
    let knot = Scene::parse(KNOT_SCENE_TOML, "scenes/knot.toml", Path::new("."))?;
    if knot.file.objects != scene.file.objects {
        accuracy_scenes.push(knot);
    }
    eprintln!(
        "trample bench: {} — {} blades x {} segments, {} object(s); precisions {:?}, {} frames each, {} thread(s), backend {}",
        scene.source,
        base.field.blades.count,
        base.field.blades.segments,
        base.bodies.len(),
        setup.precisions,
        setup.frames,
        setup.threads,
        setup.backend.name()
    );
    let p = setup.precisions.len() as u64;
    let accuracy_queries = accuracy_scenes.len() as u64 * ACCURACY_SAMPLES as u64 * (p + 1);
    let backends = setup.backends();
    let bar = progress(setup.frames * p * backends.len() as u64 + accuracy_queries);

    let gpu = if setup.render.is_some() || setup.backend != Backend::Cpu {
        Some(trample_render::headless::create_device()?)
    } else {
        None
    };
    if let (Some(g), true) = (&gpu, setup.backend != Backend::Cpu) {
        eprintln!("trample bench: GPU path on {}", g.adapter_name());
        crate::backend::note_far_turns(scene.file.sim.far_every);
    }
    if let (Some(g), Some((w, h))) = (&gpu, setup.render) {
        eprintln!(
            "trample bench: rendering every frame at {w}x{h} on {}",
            g.adapter_name()
        );
    }
    let mut runs = Vec::new();
    for (&backend, &precision) in backends
        .iter()
        .flat_map(|b| std::iter::repeat(b).zip(&setup.precisions))
    {
        bar.set_message(format!(
            "{backend} precision {precision}: timing {} frames",
            setup.frames
        ));
        let mut sim = base.clone();
        sim.params.precision = precision;
        let mut renderer = match (&gpu, setup.render) {
            (Some(g), Some((width, height))) => {
                let params = trample_render::RenderParams {
                    width,
                    height,
                    samples: g.msaa(4),
                    ..Default::default()
                };
                Some(trample_render::Renderer::new(
                    &g.device, &g.queue, &sim, params,
                )?)
            }
            _ => None,
        };
        let (mut render_ms, mut frame_ms) = (Vec::new(), Vec::new());
        let clock = Instant::now();
        let tick = |stepped: Stepped<'_>, t: &trample::StepTimings| -> Result<()> {
            if let (Some(r), Some(g)) = (renderer.as_mut(), &gpu) {
                let c = Instant::now();
                // The GPU path is drawn straight from its buffers.
                match (stepped, setup.read_back) {
                    (Stepped::Cpu(sim), true) => drop(r.render(&g.device, &g.queue, sim)?),
                    (Stepped::Gpu(s), true) => drop(r.render_gpu(&g.device, &g.queue, s)?),
                    (Stepped::Cpu(sim), false) => drop(r.draw_and_wait(&g.device, &g.queue, sim)?),
                    (Stepped::Gpu(s), false) => r.draw_gpu_and_wait(&g.device, &g.queue, s)?,
                }
                let ms = c.elapsed().as_secs_f64() * 1e3;
                render_ms.push(ms);
                frame_ms.push(t.total_ms + ms);
            }
            bar.inc(1);
            Ok(())
        };
        let steps = match (backend, &gpu) {
            ("gpu", Some(g)) => super::time_frames_gpu(g, sim, setup.frames, tick)?,
            _ => time_frames(sim, setup.frames, tick)?,
        };
        let rec = Recorder { steps };
        let render = setup.render.map(|(w, h)| {
            let frames = Stats::of(&frame_ms);
            RenderRun {
                size: [w, h],
                render_ms: Stats::of(&render_ms),
                read_back: setup.read_back,
                fps: Fps {
                    min: 1000.0 / frames.max,
                    avg: 1000.0 / frames.mean,
                    max: 1000.0 / frames.min,
                },
            }
        });
        let step_ms = rec.step_ms();
        runs.push(PrecisionRun {
            backend,
            precision,
            fps: Fps {
                min: 1000.0 / step_ms.max,
                avg: 1000.0 / step_ms.mean,
                max: 1000.0 / step_ms.min,
            },
            step_ms,
            step_ms_p99: percentile(&rec, 0.99),
            stages_ms: rec.stages_ms(),
            dbg_blades_mean: rec
                .steps
                .iter()
                .map(|t| f64::from(t.dbg_blades))
                .sum::<f64>()
                / rec.steps.len() as f64,
            wall_s: clock.elapsed().as_secs_f64(),
            render,
        });
    }

    let mut accuracy = Vec::new();
    for s in &accuracy_scenes {
        bar.set_message(format!("accuracy: {}", s.source));
        let sim = s.build()?;
        let span = motion_end_s(&sim).unwrap_or(s.file.run.frames as f32 * sim.params.dt_s);
        let times = sample_times(span, ACCURACY_SAMPLES);
        let acc = measure_accuracy(&sim, &times, &setup.precisions, || bar.inc(1));
        // Fewer times than planned (a static scene): keep the bar honest.
        bar.inc((ACCURACY_SAMPLES - times.len()) as u64 * (p + 1));
        accuracy.push(AccuracyRun {
            scene: s.source.clone(),
            objects: objects(&sim),
            false_positive_rate: acc
                .per_precision
                .iter()
                .map(|a| a.false_positive_rate())
                .collect(),
            accuracy: acc,
        });
    }
    bar.finish_and_clear();

    let report = Report {
        scene: scene.source.clone(),
        blades: base.field.blades.count,
        segments: base.field.blades.segments,
        objects: objects(&base),
        backend: setup.backend.name(),
        threads: setup.threads,
        machine,
        frames: setup.frames,
        dt_s: base.params.dt_s,
        lap_frames: lap_frames(&base).filter(|&l| l < setup.frames),
        build_ms,
        adapter: gpu
            .as_ref()
            .map(trample_render::headless::Gpu::adapter_name),
        precisions: runs,
        accuracy,
    };
    let json = setup.out.join("bench.json");
    write_json(&json, &report)?;
    fps_chart(&report, &setup.out.join("bench.png"))?;
    accuracy_chart(&report, &setup.out.join("accuracy.png"))?;
    print_tables(&report);
    eprintln!(
        "trample bench: wrote {}, bench.png, accuracy.png in {:.1} s",
        json.display(),
        clock.elapsed().as_secs_f64()
    );
    let misses: usize = report
        .accuracy
        .iter()
        .flat_map(|a| &a.accuracy.per_precision)
        .map(|p| p.false_negatives)
        .sum();
    if misses > 0 {
        anyhow::bail!(
            "{misses} exact hit(s) missed by the OBB-tree test (must be 0; see bench.json first_false_negative)"
        );
    }
    Ok(())
}

/// The `q`-quantile of the step times (nearest rank), ms.
fn percentile(rec: &Recorder, q: f64) -> f64 {
    let mut v: Vec<f64> = rec.steps.iter().map(|t| t.total_ms).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let rank = ((q * v.len() as f64).ceil() as usize).clamp(1, v.len());
    v[rank - 1]
}

fn objects(sim: &trample::Simulation) -> Vec<ObjectInfo> {
    sim.bodies
        .iter()
        .map(|b| ObjectInfo {
            name: b.object.name.clone(),
            triangles: b.object.mesh.triangle_count(),
            tree_depth: b.tree.max_depth,
        })
        .collect()
}

/// Objects named in the label of a crowd ([`object_label`]).
const LABELLED_OBJECTS: usize = 3;

/// The objects as the tables and the accuracy chart's legend name them:
/// each with its triangle count, or, past [`LABELLED_OBJECTS`] + 1, their
/// number, their triangles and the first few names (a 128-object scene in
/// a legend's line, not a paragraph).
fn object_label(objects: &[ObjectInfo]) -> String {
    let name = |o: &ObjectInfo| format!("{} ({} triangles)", o.name, thousands(o.triangles as u64));
    if objects.len() <= LABELLED_OBJECTS + 1 {
        return objects.iter().map(name).collect::<Vec<_>>().join(", ");
    }
    let total: u64 = objects.iter().map(|o| o.triangles as u64).sum();
    let first: Vec<&str> = objects[..LABELLED_OBJECTS]
        .iter()
        .map(|o| o.name.as_str())
        .collect();
    format!(
        "{} objects ({} triangles: {}, …)",
        objects.len(),
        thousands(total),
        first.join(", ")
    )
}

/// `bench.png`: lowest, average and highest frame rate against precision,
/// as in the paper's Fig. 12.
fn fps_chart(r: &Report, path: &Path) -> Result<()> {
    let backends: Vec<&str> = ["cpu", "gpu"]
        .into_iter()
        .filter(|b| r.precisions.iter().any(|p| p.backend == *b))
        .collect();
    let mut series = Vec::new();
    for (k, &backend) in backends.iter().enumerate() {
        let suffix = if backends.len() > 1 {
            format!(" ({backend})")
        } else {
            String::new()
        };
        let line = |name: &str, color, f: fn(&Fps) -> f64| Series {
            name: format!("{name}{suffix}"),
            points: r
                .precisions
                .iter()
                .filter(|p| p.backend == backend)
                .map(|p| (f64::from(p.precision), f(&p.fps)))
                .collect(),
            color,
        };
        // Second backend: the same colours shifted, so the lines differ.
        let c = |i: usize| COLORS[(i + 3 * k) % COLORS.len()];
        series.push(line("highest", c(2), |f| f.max));
        series.push(line("average", c(0), |f| f.avg));
        series.push(line("lowest", c(1), |f| f.min));
    }
    // With --render: the paper's measurement, simulation + rendering.
    let rendered = |name: &str, color, f: fn(&Fps) -> f64| Series {
        name: name.into(),
        points: r
            .precisions
            .iter()
            .filter_map(|p| Some((f64::from(p.precision), f(&p.render.as_ref()?.fps))))
            .collect(),
        color,
    };
    if r.precisions.iter().any(|p| p.render.is_some()) {
        series.push(rendered("average, with rendering", COLORS[3], |f| f.avg));
        series.push(rendered("lowest, with rendering", COLORS[4], |f| f.min));
    }
    // The fastest steps (the object off the grass) can be 100x the slowest:
    // a log axis keeps all lines readable.
    let (lo, hi) = series
        .iter()
        .flat_map(|s| &s.points)
        .fold((f64::MAX, 0.0f64), |(lo, hi), &(_, y)| {
            (lo.min(y), hi.max(y))
        });
    let title = format!(
        "Frame rate vs precision: {} blades, {} frames each, {}, {} threads",
        thousands(r.blades as u64),
        thousands(r.frames),
        r.backend.to_uppercase(),
        r.threads
    );
    line_chart(
        path,
        &Chart {
            title: &title,
            x_label: "collision precision (OBB-tree depth)",
            y_label: "frames per second",
            x_log: false,
            y_log: hi > 20.0 * lo,
            x_integers: true,
            legend: SeriesLabelPosition::UpperRight,
        },
        &series,
    )
}

/// `accuracy.png`: false-positive rate against precision, one line per scene.
fn accuracy_chart(r: &Report, path: &Path) -> Result<()> {
    let series: Vec<Series> = r
        .accuracy
        .iter()
        .enumerate()
        .map(|(i, a)| Series {
            name: object_label(&a.objects),
            points: a
                .accuracy
                .per_precision
                .iter()
                .map(|p| (f64::from(p.precision), 100.0 * p.false_positive_rate()))
                .collect(),
            color: COLORS[i % COLORS.len()],
        })
        .collect();
    let misses: usize = r
        .accuracy
        .iter()
        .flat_map(|a| &a.accuracy.per_precision)
        .map(|p| p.false_negatives)
        .sum();
    let title = format!(
        "Collision accuracy vs exact reference ({} blades at rest; false negatives: {misses})",
        thousands(r.blades as u64)
    );
    line_chart(
        path,
        &Chart {
            title: &title,
            x_label: "collision precision (OBB-tree depth)",
            y_label: "false positives, % of reported segment hits",
            x_log: false,
            y_log: false,
            x_integers: true,
            legend: SeriesLabelPosition::LowerLeft,
        },
        &series,
    )
}

fn print_tables(r: &Report) {
    println!(
        "Pressure test (paper Fig. 12), simulation alone: {}, {} blades, {}, {} frames per precision, {} thread(s){}",
        r.scene,
        r.blades,
        object_label(&r.objects),
        r.frames,
        r.threads,
        r.adapter
            .as_deref()
            .map(|a| format!(", GPU path on {a}"))
            .unwrap_or_default()
    );
    println!(
        "{:>7} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>9} {:>9} {:>10}",
        "backend",
        "precision",
        "fps min",
        "fps avg",
        "fps max",
        "median ms",
        "mean ms",
        "p99 ms",
        "max ms",
        "narrow ms"
    );
    for p in &r.precisions {
        println!(
            "{:>7} {:>9} {:>9.0} {:>9.0} {:>9.0} {:>10.3} {:>9.3} {:>9.3} {:>9.3} {:>10.3}",
            p.backend,
            p.precision,
            p.fps.min,
            p.fps.avg,
            p.fps.max,
            p.step_ms.median,
            p.step_ms.mean,
            p.step_ms_p99,
            p.step_ms.max,
            p.stages_ms.get("narrow").copied().unwrap_or(0.0)
        );
    }
    if r.precisions.iter().any(|p| p.render.is_some()) {
        println!();
        let read_back = r
            .precisions
            .iter()
            .filter_map(|p| p.render.as_ref())
            .any(|x| x.read_back);
        println!(
            "Simulation + rendering on {} ({}):",
            r.adapter.as_deref().unwrap_or("?"),
            if read_back {
                "each frame read back"
            } else {
                "each frame drawn and waited for, not read back"
            }
        );
        println!(
            "{:>9} {:>11} {:>9} {:>9} {:>9} {:>16}",
            "precision", "size", "fps min", "fps avg", "fps max", "render median ms"
        );
        for p in &r.precisions {
            if let Some(x) = &p.render {
                println!(
                    "{:>9} {:>11} {:>9.1} {:>9.1} {:>9.1} {:>16.1}",
                    p.precision,
                    format!("{}x{}", x.size[0], x.size[1]),
                    x.fps.min,
                    x.fps.avg,
                    x.fps.max,
                    x.render_ms.median
                );
            }
        }
    }
    println!();
    println!(
        "Accuracy against the exact reference (false positives as % of reported hits; FN = exact hits missed)"
    );
    for a in &r.accuracy {
        println!(
            "  {} — {}: {} exact segment hits over {} times",
            a.scene,
            object_label(&a.objects),
            a.accuracy.exact_hits,
            a.accuracy.times_s.len()
        );
        for p in &a.accuracy.per_precision {
            println!(
                "    precision {:>2}: {:>6} reported, {:>6} false positives ({:>5.1} %), FN {}",
                p.precision,
                p.reported,
                p.false_positives,
                100.0 * p.false_positive_rate(),
                p.false_negatives
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(name: &str, triangles: usize) -> ObjectInfo {
        ObjectInfo {
            name: name.into(),
            triangles,
            tree_depth: 7,
        }
    }

    /// A few objects are all named; a crowd is named in part and counted
    /// (the herd's 128 objects made a 6,000-character line and legend).
    #[test]
    fn a_crowd_of_objects_is_counted_not_listed() {
        let few: Vec<ObjectInfo> = (0..4).map(|i| info(&format!("o{i}"), 1000)).collect();
        assert_eq!(
            object_label(&few),
            "o0 (1,000 triangles), o1 (1,000 triangles), o2 (1,000 triangles), o3 (1,000 triangles)"
        );
        let many: Vec<ObjectInfo> = (0..128).map(|i| info(&format!("o{i}"), 12 + i)).collect();
        assert_eq!(
            object_label(&many),
            "128 objects (9,664 triangles: o0, o1, o2, …)"
        );
    }
}
