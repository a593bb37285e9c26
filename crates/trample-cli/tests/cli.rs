//! The `trample` command line: the flags and files the issues spell out are a
//! contract (summary.json keys, .npy shapes and dtypes, exit codes, one-line errors).

mod common;

use common::{dir, trample};
use std::path::Path;
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
    // The step times are statistics of 40 measured steps: ordered, not all
    // zero, and their sum within the run's wall time (no speed is asserted).
    let ms = |key: &str| s["step_ms"][key].as_f64().unwrap();
    let (min, median, mean, max) = (ms("min"), ms("median"), ms("mean"), ms("max"));
    let (p90, p99) = (ms("p90"), ms("p99"));
    assert!(
        min <= median && median <= max && min <= mean && mean <= max && max > 0.0,
        "step_ms {}",
        s["step_ms"]
    );
    assert!(
        median <= p90 && p90 <= p99 && p99 <= max,
        "step_ms {}",
        s["step_ms"]
    );
    let wall_ms = s["wall_s"].as_f64().unwrap() * 1e3;
    assert!(
        mean * 40.0 <= wall_ms,
        "40 steps of {mean} ms on average in a run of {wall_ms} ms"
    );
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
    assert_eq!(s["far_every"], 1);
    assert_eq!(s["far_bodies_mean"], 0.0);
    assert_eq!(
        s["far_turns"],
        serde_json::json!([]),
        "no turns at far_every 1"
    );
}

/// `trample simulate SCENE --frames 40 --far-every 4 --out OUT` with
/// `extra` flags; it must succeed.
fn simulate_40_frames_far_every_4(
    scene: &Path,
    out: &Path,
    extra: &[&str],
) -> std::process::Output {
    let mut args = vec![
        "simulate",
        scene.to_str().unwrap(),
        "--frames",
        "40",
        "--far-every",
        "4",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = trample(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// `--far-every K` reaches the simulation and the summary says what it
/// did: the ball watched from 400 m takes its turn every fourth step.
#[test]
fn simulate_far_every_steps_far_objects_in_turns_and_says_so() {
    let d = dir("far");
    let scene = d.join("far.toml");
    let text = SCENE.replace("position = [0.0, 2.0, 4.0]", "position = [0.0, 3.0, 400.0]");
    assert_ne!(text, SCENE);
    std::fs::write(&scene, text).unwrap();
    let out = d.join("out");
    let o = simulate_40_frames_far_every_4(&scene, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("far objects every 4 steps: "), "{err}");
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["far_every"], 4);
    assert_eq!(
        s["far_bodies_mean"], 0.25,
        "one body, every fourth of 40 steps"
    );
    // Its turns, phase by phase: ten steps each, the ball in one of them.
    let turns = s["far_turns"].as_array().unwrap();
    assert_eq!(turns.len(), 4, "{turns:?}");
    let mut with_ball = 0;
    for (k, t) in turns.iter().enumerate() {
        assert_eq!(
            (t["phase"].as_u64(), t["steps"].as_u64()),
            (Some(k as u64), Some(10))
        );
        assert!(t["step_ms"]["median"].as_f64().unwrap() > 0.0, "{t}");
        match t["far_bodies_mean"].as_f64().unwrap() {
            1.0 => with_ball += 1,
            m => assert_eq!(m, 0.0, "{t}"),
        }
    }
    assert_eq!(with_ball, 1, "{turns:?}");
    assert!(err.contains("turns' median steps "), "{err}");
    assert!(
        s["classes"]["direct"].as_u64().unwrap() > 0,
        "the ball hit blades"
    );
}

/// `--far-outside-view` reaches the simulation and the summary says what
/// it did: the ball 4 m from the camera, which looks away from it, takes
/// its turn every fourth step with the flag and every step without it.
#[test]
fn simulate_far_outside_view_steps_unseen_objects_in_turns_and_says_so() {
    let d = dir("unseen");
    let scene = d.join("unseen.toml");
    let text = SCENE.replace("at = [0.0, 0.0, 0.0]", "at = [0.0, 0.0, 10.0]");
    assert_ne!(text, SCENE);
    std::fs::write(&scene, text).unwrap();
    for (flag, turns) in [(true, 0.25), (false, 0.0)] {
        let out = d.join(format!("out_{flag}"));
        let extra: &[&str] = if flag { &["--far-outside-view"] } else { &[] };
        let o = simulate_40_frames_far_every_4(&scene, &out, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        let says = if flag {
            "far and unseen objects every 4 steps: "
        } else {
            "far objects every 4 steps: "
        };
        assert!(err.contains(says), "{err}");
        let s: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
        assert_eq!(s["far_outside_view"], flag);
        assert_eq!(s["far_bodies_mean"], turns, "{flag}");
        assert!(
            s["classes"]["direct"].as_u64().unwrap() > 0,
            "the ball hit blades"
        );
    }
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

/// `collide scenes/{walker,tractor}.toml --time T --dump-object` (issue 13
/// contract): every object's triangles as posed and deformed at T, float32
/// (triangles, 3, 3) — the walker's skinned mesh, the tractor's body and
/// its four wheels — and the exact hits there are found.
#[test]
fn collide_dumps_animated_and_articulated_objects_posed_at_t() {
    let d = dir("rigs");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for name in ["walker", "tractor"] {
        let scene = scenes.join(format!("{name}.toml"));
        let loaded = trample::scene::Scene::load(&scene).unwrap();
        let objects = loaded.objects().unwrap();
        let triangles: usize = objects
            .iter()
            .map(|o| {
                o.mesh.triangle_count()
                    + o.parts
                        .parts
                        .iter()
                        .map(|p| p.mesh.triangle_count())
                        .sum::<usize>()
            })
            .sum();
        let mut dumps = Vec::new();
        for t in ["1.0", "1.5"] {
            let (hits, obj) = (
                d.join(format!("{name}_hits_{t}.npy")),
                d.join(format!("{name}_obj_{t}.npy")),
            );
            let o = trample(&[
                "collide",
                scene.to_str().unwrap(),
                "--time",
                t,
                "--exact",
                "--dump-hits",
                hits.to_str().unwrap(),
                "--dump-object",
                obj.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let o = npy(&obj);
            assert_eq!(
                (o.dtype, o.shape.clone()),
                (Dtype::F32, vec![triangles, 3, 3]),
                "{name}"
            );
            assert!(
                npy(&hits).data.contains(&1),
                "{name}: no exact hit at t = {t}"
            );
            dumps.push(o.data);
        }
        assert_ne!(
            dumps[0], dumps[1],
            "{name}: the same triangles at two times"
        );
    }
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
    // An open mesh: its rim, and with the winding rule its grid.
    let o = trample(&["check", repo.join("parked_car.toml").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("open (inside by its winding number; 343 rim edges, a winding grid of 51 × 125 × 43 voxels)"),
        "{text}"
    );
}

/// Output into a pipe whose reader has gone (`trample check s.toml |
/// head -1` once `head` is done) ends quietly with SIGPIPE's status, not
/// with "internal error … please report it".
#[test]
fn output_into_a_closed_pipe_ends_quietly() {
    let d = dir("pipe");
    let scene = scene_in(&d);
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(["check", &scene])
        .stdout(writer)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(141), "{err}");
    assert!(err.is_empty(), "{err}");
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
            "simulate".into(),
            scene.clone(),
            "--threads".into(),
            "100000".into(),
            "--frames".into(),
            "1".into(),
        ],
        vec![
            "simulate".into(),
            scene.clone(),
            "--far-every".into(),
            "0".into(),
        ],
        vec![
            "run".into(),
            scene.clone(),
            "--far-every".into(),
            "65".into(),
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
        // A blend band is a distance >= 0; strengths are numbers in range.
        vec![
            "run".into(),
            scene.clone(),
            "--lod-blend".into(),
            "-2".into(),
        ],
        vec![
            "run".into(),
            scene.clone(),
            "--shadows".into(),
            "1.5".into(),
        ],
        vec![
            "run".into(),
            scene.clone(),
            "--shadows".into(),
            "NaN".into(),
        ],
        vec![
            "run".into(),
            scene.clone(),
            "--ambient-occlusion".into(),
            "-1".into(),
        ],
        // --out names a file, not a folder.
        vec![
            "simulate".into(),
            scene.clone(),
            "--frames".into(),
            "1".into(),
            "--out".into(),
            scene.clone(),
        ],
        // `check` reads the height map as a run does.
        vec!["check".into(), {
            let p = d.join("no_height_map.toml");
            std::fs::write(
                &p,
                "[field]\npatches = [2, 2]\nterrain = { kind = \"heightmap\", path = \"missing.png\", height_scale_m = 1.0 }\n",
            )
            .unwrap();
            p.display().to_string()
        }],
        // A mesh path that leaves the scene's folder.
        vec!["check".into(), {
            let p = d.join("escape.toml");
            std::fs::write(
                &p,
                SCENE.replace(
                    r#"shape = { kind = "sphere", radius_m = 0.4 }"#,
                    r#"shape = { kind = "mesh", path = "../x.obj" }"#,
                ),
            )
            .unwrap();
            p.display().to_string()
        }],
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

/// Files in `d` (names), sorted.
fn listing(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Asserts a failed run: non-zero exit, one line starting `error: `.
fn assert_one_line_error(o: &Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!o.status.success(), "{what} succeeded");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "{what}: not one line: {err}"
    );
    assert!(err.starts_with("error: "), "{what}: {err}");
    err
}

#[test]
fn an_output_that_cannot_be_written_stops_the_run_before_it_starts() {
    let d = dir("unwritable");
    let scene = scene_in(&d);
    let out = d.join("out");
    let o = trample(&[
        "simulate",
        &scene,
        "--frames",
        "5",
        "--out",
        out.to_str().unwrap(),
        "--dump-blades",
        d.join("no/such/folder/b.npy").to_str().unwrap(),
    ]);
    let err = assert_one_line_error(&o, "dump into a missing folder");
    assert!(
        err.contains("--dump-blades") && err.contains("does not exist"),
        "{err}"
    );
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("frames in"),
        "the run must not start"
    );
    assert!(
        listing(&out).is_empty(),
        "nothing in --out: {:?}",
        listing(&out)
    );

    // A folder given as the file, and the same file twice.
    let o = trample(&[
        "collide",
        &scene,
        "--time",
        "0",
        "--exact",
        "--dump-hits",
        d.to_str().unwrap(),
    ]);
    assert!(assert_one_line_error(&o, "folder as file").contains("is a folder"));
    let same = d.join("same.npy");
    let o = trample(&[
        "collide",
        &scene,
        "--time",
        "0",
        "--exact",
        "--dump-hits",
        same.to_str().unwrap(),
        "--dump-blades",
        same.to_str().unwrap(),
    ]);
    assert!(assert_one_line_error(&o, "same file twice").contains("same path"));
    assert_eq!(listing(&d), ["out", "scene.toml"], "nothing else written");
}

/// When writing fails after some outputs are already done (here: a
/// file-size limit lets the 4 KiB hit flags through and stops the 60 KiB
/// blades), no destination is touched — an older hits.npy stays as it was —
/// and no temporary file is left. SIGXFSZ is ignored so that the write
/// fails with EFBIG instead of killing the process.
#[test]
fn a_write_that_fails_after_other_outputs_leaves_every_destination_untouched() {
    let d = dir("partial");
    let scene = scene_in(&d);
    let (hits, blades) = (d.join("hits.npy"), d.join("blades.npy"));
    std::fs::write(&hits, b"old").unwrap();
    let cmd = format!(
        "trap '' XFSZ; ulimit -f 32; exec '{}' collide '{scene}' --time 0.5 --precision 3 --dump-hits '{}' --dump-blades '{}'",
        env!("CARGO_BIN_EXE_trample"),
        hits.display(),
        blades.display()
    );
    let o = Command::new("bash").args(["-c", &cmd]).output().unwrap();
    let err = assert_one_line_error(&o, "write past the file-size limit");
    assert!(err.contains("blades.npy: cannot write"), "{err}");
    assert_eq!(std::fs::read(&hits).unwrap(), b"old", "hits.npy untouched");
    assert_eq!(
        listing(&d),
        ["hits.npy", "scene.toml"],
        "no temporaries, no blades.npy"
    );

    // The same run without the limit writes both.
    let o = trample(&[
        "collide",
        &scene,
        "--time",
        "0.5",
        "--precision",
        "3",
        "--dump-hits",
        hits.to_str().unwrap(),
        "--dump-blades",
        blades.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(npy(&hits).shape, vec![1024, 4]);
    assert_eq!(listing(&d), ["blades.npy", "hits.npy", "scene.toml"]);
}

/// Runs `trample args` as the unprivileged user `nobody` when this process
/// is root (through util-linux `setpriv`), else as itself. `None` when root
/// and `setpriv` is missing.
fn trample_unprivileged(args: &[&str]) -> Option<Output> {
    let root = Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false);
    if !root {
        return Some(trample(args));
    }
    Command::new("setpriv")
        .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
        .arg(env!("CARGO_BIN_EXE_trample"))
        .args(args)
        .output()
        .ok()
}

#[test]
fn unreadable_mesh_is_refused_when_run_as_an_unprivileged_user() {
    use std::os::unix::fs::PermissionsExt;
    let d = dir("unreadable");
    std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o755)).unwrap();
    let mesh = d.join("m.obj");
    std::fs::write(&mesh, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::set_permissions(&mesh, std::fs::Permissions::from_mode(0o000)).unwrap();
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        "[field]\npatches = [1, 1]\ncells_per_patch = 4\n[[objects]]\nname = \"m\"\nshape = { kind = \"mesh\", path = \"m.obj\" }\npath = { kind = \"static\", position = [0.0, 0.5, 0.0] }\n",
    )
    .unwrap();
    std::fs::set_permissions(&scene, std::fs::Permissions::from_mode(0o644)).unwrap();
    let Some(o) = trample_unprivileged(&["check", scene.to_str().unwrap()]) else {
        println!("skipped: running as root without setpriv, mode 000 cannot be shown");
        return;
    };
    let err = assert_one_line_error(&o, "unreadable mesh");
    assert!(
        err.contains("objects[0] (m)")
            && err.contains(&format!(
                "{}: cannot read the file: Permission denied",
                mesh.display()
            )),
        "{err}"
    );
}

#[test]
fn memory_limit_flag_overrides_the_scene() {
    let d = dir("memory");
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        format!("{SCENE}[sim]\nmemory_limit_gib = 0.00001\n"),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let out = d.join("out");
    let o = trample(&[
        "simulate",
        scene,
        "--frames",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = assert_one_line_error(&o, "field over the scene's limit");
    assert!(
        err.contains("sim.memory_limit_gib = 0.00001 allows less"),
        "{err}"
    );
    let o = trample(&[
        "simulate",
        scene,
        "--frames",
        "0",
        "--out",
        out.to_str().unwrap(),
        "--memory-limit-gib",
        "1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert!(s["memory_estimate_mib"].as_f64().unwrap() > 0.0);
    assert!(s["peak_rss_mib"].as_f64().unwrap() > 0.0);
    for bad in ["0", "nan", "-3"] {
        let o = trample(&[
            "collide",
            scene,
            "--time",
            "0",
            "--exact",
            "--memory-limit-gib",
            bad,
            "--dump-hits",
            d.join("h.npy").to_str().unwrap(),
        ]);
        let err = assert_one_line_error(&o, bad);
        assert!(err.contains("--memory-limit-gib"), "{err}");
    }
    assert!(!d.join("h.npy").exists());
}

#[test]
fn an_object_too_fast_for_max_substeps_warns_once_and_is_counted() {
    let d = dir("fast");
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        SCENE.replace("duration_s = 1.0", "duration_s = 0.05") + "[sim]\nmax_substeps = 2\n",
    )
    .unwrap();
    let out = d.join("out");
    let o = trample(&[
        "simulate",
        scene.to_str().unwrap(),
        "--frames",
        "10",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(warnings[0].contains("\"ball\"") && warnings[0].contains("sim.max_substeps = 2"));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert!(s["substeps_clamped_steps"].as_u64().unwrap() >= 2, "{s}");
    assert!(
        s["first_substep_clamp"]
            .as_str()
            .unwrap()
            .contains("frame 0")
    );
}

/// A scene of `patches`² patches of `cells`² cells with a flat box over the
/// whole field moving sideways at 1 m/s: every blade is hit and bent each
/// step (the worst case of `FieldParams::memory_estimate_bytes`).
fn whole_field_scene(patches: u32, cells: u32) -> String {
    let half = f64::from(patches * cells) * 0.1 / 2.0 + 1.0;
    format!(
        r#"[field]
patches = [{patches}, {patches}]
cells_per_patch = {cells}
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
recovery_s = 2.0
[camera]
path = {{ kind = "static", position = [0.0, 50.0, 1.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "slab"
shape = {{ kind = "box", half_extents_m = [{half}, 0.1, {half}] }}
path = {{ kind = "line", from = [-0.5, 0.3, 0.0], to = [0.5, 0.3, 0.0], duration_s = 1.0 }}
"#
    )
}

/// (blades, estimate MiB, peak RSS MiB) of `trample simulate` on `scene`,
/// on one worker thread: with two, the peak depends on how the threads are
/// scheduled (measured 2026-11-26 on the 65,536-blade worst case: 34.5 ±
/// 0.1 MiB on one thread whatever the load; 38.7–46.3 MiB on two, four
/// runs at once, and once in CI 8 MiB above the estimate's quarter), and a
/// test must not pass or fail with the machine's load.
fn measured_memory(d: &Path, name: &str, scene: &str, frames: &str) -> (u64, f64, f64) {
    let path = d.join(format!("{name}.toml"));
    std::fs::write(&path, scene).unwrap();
    let out = d.join(name);
    let o = trample(&[
        "simulate",
        path.to_str().unwrap(),
        "--frames",
        frames,
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    (
        s["blades"].as_u64().unwrap(),
        s["memory_estimate_mib"].as_f64().unwrap(),
        s["peak_rss_mib"].as_f64().unwrap(),
    )
}

/// The memory estimate against the measured peak resident memory of whole
/// runs (less that of a 4-blade run: the program itself): within a quarter
/// in the worst case it describes, and above a typical run's peak.
fn check_memory_estimate(sizes: &[(u32, u32)]) {
    let d = dir(&format!("memory-estimate-{}", sizes.len()));
    let (_, _, baseline) = measured_memory(&d, "tiny", &whole_field_scene(1, 2), "3");
    for &(patches, cells) in sizes {
        let (blades, estimate, peak) =
            measured_memory(&d, "worst", &whole_field_scene(patches, cells), "3");
        let used = peak - baseline;
        println!(
            "{blades} blades, every blade bent: estimate {estimate:.1} MiB, measured {used:.1} MiB ({:+.0} %)",
            (used / estimate - 1.0) * 100.0
        );
        assert!(
            (used - estimate).abs() <= 0.25 * estimate,
            "{blades} blades: estimate {estimate:.1} MiB, measured {used:.1} MiB"
        );
        // A ball rolling through the same field: far below the worst case.
        let typical = SCENE.replace(
            "patches = [2, 2]\ncells_per_patch = 16",
            &format!("patches = [{patches}, {patches}]\ncells_per_patch = {cells}"),
        );
        let (_, estimate, peak) = measured_memory(&d, "typical", &typical, "30");
        println!(
            "{blades} blades, a ball: measured {:.1} MiB",
            peak - baseline
        );
        assert!(peak - baseline < estimate);
    }
}

#[test]
fn memory_estimate_is_within_a_quarter_of_the_measured_peak() {
    check_memory_estimate(&[(8, 32)]);
}

#[test]
#[ignore = "about a minute: 262,144 and 1,048,576 blades; figures in RELIABILITY.md"]
fn memory_estimate_is_within_a_quarter_of_the_measured_peak_up_to_a_million_blades() {
    check_memory_estimate(&[(8, 32), (16, 32), (32, 32)]);
}
