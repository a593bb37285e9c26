//! `--backend` (issue 4): the GPU path of `collide` and `simulate` gives
//! the CPU path's answers, `auto` picks the CPU on a software adapter, and
//! the exact reference refuses the GPU. Needs an adapter: CI runs these
//! with `WGPU_BACKEND=gl` (Mesa llvmpipe) and `=vulkan` (lavapipe); without
//! one, `--backend gpu` fails and so do these tests (they do not skip).
//! `TRAMPLE_TEST_ADAPTER` (comma-separated words the adapter's name must
//! contain, as in `trample-gpu`'s tests) pins the driver.

mod common;

use common::{dir, ok, trample};
use std::process::Command;

const SCENE: &str = r#"
name = "backend"
[field]
patches = [3, 3]
cells_per_patch = 16
[lod]
geometry_m = 2.0
billboard_m = 4.0
[sim]
precision = 5
recovery_s = 1.5
[camera]
path = { kind = "line", from = [-3.0, 1.5, 1.0], to = [3.0, 1.5, 1.0], duration_s = 2.0 }
look_at = { kind = "object", name = "ball" }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "line", from = [-2.0, 0.4, 0.0], to = [2.0, 0.4, 0.0], duration_s = 2.0 }
"#;

/// The adapter a GPU summary names, checked against `TRAMPLE_TEST_ADAPTER`.
fn check_adapter(summary: &serde_json::Value) {
    let name = summary["adapter"]
        .as_str()
        .expect("a GPU summary names its adapter");
    trample_testkit::adapter::check_adapter_name(name);
}

#[test]
fn collide_on_the_gpu_gives_the_cpu_hit_flags_at_every_precision() {
    let d = dir("collide");
    for p in 1..=7 {
        let mut hits = Vec::new();
        for backend in ["gpu", "cpu"] {
            let f = d.join(format!("{backend}{p}.npy"));
            let o = trample(&[
                "collide",
                "--time",
                "6",
                "--precision",
                &p.to_string(),
                "--backend",
                backend,
                "--dump-hits",
                f.to_str().unwrap(),
            ]);
            ok(&o);
            hits.push(std::fs::read(&f).unwrap());
        }
        assert_eq!(
            hits[0], hits[1],
            "precision {p}: GPU and CPU hit flags differ"
        );
    }
}

#[test]
fn exact_collide_refuses_the_gpu() {
    let d = dir("exact");
    let f = d.join("hits.npy");
    let o = trample(&[
        "collide",
        "--time",
        "1",
        "--exact",
        "--backend",
        "gpu",
        "--dump-hits",
        f.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("CPU only"));
}

#[test]
fn simulate_on_the_gpu_touches_the_blades_the_cpu_touches() {
    let d = dir("simulate");
    let scene = d.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let mut summaries = Vec::new();
    for backend in ["gpu", "cpu"] {
        let out = d.join(backend);
        let o = trample(&[
            "simulate",
            scene.to_str().unwrap(),
            "--frames",
            "60",
            "--backend",
            backend,
            "--out",
            out.to_str().unwrap(),
        ]);
        ok(&o);
        let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
        summaries.push(serde_json::from_str::<serde_json::Value>(&text).unwrap());
    }
    let (g, c) = (&summaries[0], &summaries[1]);
    assert_eq!(g["backend"], "gpu");
    check_adapter(g);
    assert_eq!(c["backend"], "cpu");
    // Per-stage GPU times (issue 4), and how they were taken.
    assert!(
        matches!(g["stage_timing"].as_str(), Some("timestamp" | "wall")),
        "stage_timing {}",
        g["stage_timing"]
    );
    assert!(
        g["stages_ms"]["narrow"].as_f64().unwrap() > 0.0,
        "{}",
        g["stages_ms"]
    );
    assert_eq!(c["stage_timing"], "wall");
    assert!(c["classes"]["direct"].as_u64().unwrap() > 0);
    assert_eq!(g["classes"], c["classes"], "blade classes differ");
    assert_eq!(g["lod_cells"], c["lod_cells"], "levels of detail differ");
}

#[test]
fn auto_takes_the_cpu_on_a_software_adapter() {
    let d = dir("auto");
    let out = d.join("out");
    let o = trample(&[
        "simulate",
        "--frames",
        "2",
        "--backend",
        "auto",
        "--out",
        out.to_str().unwrap(),
    ]);
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    if err.contains("software adapter") || err.contains("no GPU adapter") {
        assert_eq!(s["backend"], "cpu", "{err}");
    } else {
        assert_eq!(s["backend"], "gpu", "{err}");
    }
}

#[test]
fn run_on_the_gpu_renders_and_says_so() {
    let d = dir("run");
    let scene = d.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let out = d.join("out");
    let o = trample(&[
        "run",
        scene.to_str().unwrap(),
        "--frames",
        "20",
        "--every",
        "10",
        "--size",
        "64x64",
        "--backend",
        "gpu",
        "--out",
        out.to_str().unwrap(),
    ]);
    ok(&o);
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(s["backend"], "gpu");
    check_adapter(&s);
    assert_eq!(
        s["stage_timing"], "none",
        "run does not time the GPU stages"
    );
    assert!(out.join("frame_0010.png").exists());
}

#[test]
fn a_lost_gpu_device_falls_back_to_the_cpu_path_with_a_message() {
    // Issue 6: a device lost mid-run (injected: the device is destroyed
    // before frame 5) ends the GPU run with a message, and the CPU path runs
    // the scene from frame 0: the same blades as a CPU run, no crash.
    let d = dir("lost");
    let scene = d.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let run = |backend: &str, fault: bool| {
        let out = d.join(format!("{backend}-{fault}"));
        let blades = out.join("blades.npy");
        std::fs::create_dir_all(&out).unwrap();
        let mut c = Command::new(env!("CARGO_BIN_EXE_trample"));
        c.args(["simulate", scene.to_str().unwrap(), "--frames", "20"])
            .args(["--backend", backend, "--out", out.to_str().unwrap()])
            .args(["--dump-blades", blades.to_str().unwrap()]);
        if fault {
            c.env("TRAMPLE_FAULT_GPU_LOST_AFTER", "5");
        }
        let o = c.output().expect("run trample");
        (o, out)
    };
    let (o, lost) = run("gpu", true);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("device lost") && err.contains("falling back to the CPU path"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(lost.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["backend"], "cpu", "{err}");
    assert_eq!(s["frames"], 20);
    let (o, cpu) = run("cpu", false);
    assert!(o.status.success());
    assert_eq!(
        std::fs::read(lost.join("blades.npy")).unwrap(),
        std::fs::read(cpu.join("blades.npy")).unwrap(),
        "the fallback must give the CPU path's blades"
    );
}

/// Far objects taking turns on the GPU path get a note (they split the
/// step into more sub-steps, each a chain of dispatches: slower on a real
/// GPU, BENCHMARKS.md session 70); every object every step gets none.
#[test]
fn far_turns_on_the_gpu_path_come_with_a_note() {
    let d = dir("far-note");
    let scene = d.join("scene.toml");
    std::fs::write(&scene, SCENE).unwrap();
    for far_every in ["1", "4"] {
        let out = d.join(far_every);
        let o = trample(&[
            "simulate",
            scene.to_str().unwrap(),
            "--frames",
            "2",
            "--backend",
            "gpu",
            "--far-every",
            far_every,
            "--out",
            out.to_str().unwrap(),
        ]);
        ok(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        let noted = err.contains("note: far objects take turns (far_every 4)")
            && err.contains("far_every 1 is usually faster there");
        assert_eq!(noted, far_every == "4", "far_every {far_every}: {err}");
    }
}
