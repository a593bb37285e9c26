//! The `trample` command line: the flags and files the issues spell out are a
//! contract (summary.json keys, .npy shapes and dtypes, exit codes, one-line errors).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use trample::npy::{Dtype, decode};

const SCENE: &str = r#"
[field]
patches = [2, 2]
cells_per_patch = 16
[lod]
geometry_m = 100.0
billboard_m = 200.0
[camera]
path = { kind = "static", position = [0.0, 2.0, 4.0] }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.4 }
orientation = "rolling"
path = { kind = "line", from = [-2.0, 0.4, 0.0], to = [2.0, 0.4, 0.0], duration_s = 1.0 }
"#;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trample-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn trample(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(args)
        .output()
        .expect("run trample")
}

fn scene_in(d: &Path) -> String {
    let p = d.join("scene.toml");
    std::fs::write(&p, SCENE).unwrap();
    p.display().to_string()
}

fn npy(p: &Path) -> trample::npy::NpyArray {
    decode(&std::fs::read(p).unwrap()).unwrap()
}

#[test]
fn simulate_writes_summary_and_dumps() {
    let d = dir("simulate");
    let scene = scene_in(&d);
    let out = d.join("out");
    let (blades, classes) = (d.join("blades.npy"), d.join("classes.npy"));
    let o = trample(&[
        "simulate",
        &scene,
        "--frames",
        "40",
        "--precision",
        "4",
        "--threads",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--dump-blades",
        blades.to_str().unwrap(),
        "--dump-classes",
        classes.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    for key in [
        "blades",
        "segments",
        "frames",
        "precision",
        "backend",
        "step_ms",
        "stages_ms",
        "dbg_blades",
        "pbg_blades",
    ] {
        assert!(s.get(key).is_some(), "summary.json lacks {key}");
    }
    for key in ["min", "median", "mean", "max"] {
        assert!(s["step_ms"][key].as_f64().unwrap() >= 0.0);
    }
    assert_eq!(s["blades"], 1024);
    assert_eq!(s["frames"], 40);
    assert_eq!(s["precision"], 4);
    assert_eq!(s["backend"], "cpu");
    let b = npy(&blades);
    assert_eq!((b.dtype, b.shape.clone()), (Dtype::F32, vec![1024, 5, 3]));
    let c = npy(&classes);
    assert_eq!((c.dtype, c.shape.clone()), (Dtype::U8, vec![1024]));
    assert!(c.data.iter().all(|&v| v <= 2));
    assert!(c.data.contains(&1), "the ball must hit blades");
}

#[test]
fn frames_zero_dumps_the_rest_state_and_collide_agrees() {
    let d = dir("rest");
    let scene = scene_in(&d);
    let (a, b, hits, exact, obj) = (
        d.join("a.npy"),
        d.join("b.npy"),
        d.join("hits.npy"),
        d.join("exact.npy"),
        d.join("obj.npy"),
    );
    let o = trample(&[
        "simulate",
        &scene,
        "--frames",
        "0",
        "--out",
        d.to_str().unwrap(),
        "--dump-blades",
        a.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = trample(&[
        "collide",
        &scene,
        "--time",
        "0.5",
        "--precision",
        "7",
        "--dump-hits",
        hits.to_str().unwrap(),
        "--dump-blades",
        b.to_str().unwrap(),
        "--dump-object",
        obj.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        "rest state differs between simulate and collide"
    );
    let o = trample(&[
        "collide",
        &scene,
        "--time",
        "0.5",
        "--exact",
        "--dump-hits",
        exact.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (h, e) = (npy(&hits), npy(&exact));
    assert_eq!((h.dtype, h.shape.clone()), (Dtype::U8, vec![1024, 4]));
    assert_eq!(e.shape, h.shape);
    assert!(e.data.contains(&1));
    // No exact hit is missed at precision 7.
    for (i, (&x, &p)) in e.data.iter().zip(&h.data).enumerate() {
        assert!(
            x == 0 || p == 1,
            "segment {i} hit exactly but not at precision 7"
        );
    }
    let t = npy(&obj);
    assert_eq!(t.dtype, Dtype::F32);
    assert_eq!(&t.shape[1..], &[3, 3]);
    assert!(t.shape[0] > 100);
}

#[test]
fn check_describes_the_scene() {
    let d = dir("check");
    let scene = scene_in(&d);
    let o = trample(&["check", &scene]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("1024 blades"), "{text}");
    assert!(text.contains("ball"), "{text}");
    assert!(text.contains("triangles"), "{text}");
    assert!(text.contains("MiB"), "{text}");
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for s in ["default.toml", "knot.toml", "car.toml"] {
        let o = trample(&["check", repo.join(s).to_str().unwrap()]);
        assert!(
            o.status.success(),
            "{s}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn bad_input_exits_non_zero_with_one_line() {
    let d = dir("bad");
    let scene = scene_in(&d);
    let cases: Vec<Vec<String>> = vec![
        vec!["simulate".into(), d.join("nope.toml").display().to_string()],
        vec![
            "simulate".into(),
            scene.clone(),
            "--precision".into(),
            "0".into(),
            "--frames".into(),
            "1".into(),
        ],
        vec![
            "simulate".into(),
            scene.clone(),
            "--dt".into(),
            "-1".into(),
            "--frames".into(),
            "1".into(),
        ],
        vec![
            "simulate".into(),
            scene.clone(),
            "--threads".into(),
            "0".into(),
        ],
        vec![
            "collide".into(),
            scene.clone(),
            "--time".into(),
            "0".into(),
            "--precision".into(),
            "1000".into(),
            "--dump-hits".into(),
            d.join("h.npy").display().to_string(),
        ],
        vec!["check".into(), d.display().to_string()],
    ];
    for args in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = trample(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{args:?}: not one line: {err}"
        );
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    assert!(!d.join("h.npy").exists(), "nothing is written on error");
}
