//! `trample bench`: the pressure test writes a valid bench.json and charts,
//! the accuracy numbers in it are sane (no false negatives, false positives
//! never grow with precision), `--render` adds simulation + rendering frame
//! rates, `--backend both` times the GPU path beside the CPU path on the
//! same frames, `--scaling --backend both` puts GPU points beside the CPU
//! ones, `--objects --backend both` times the step against the object
//! count on both paths, and bad flags fail in one line.

mod common;

use common::{dir, stderr, trample};

/// Asserts `path` is a PNG of the charts' size, not blank.
fn assert_chart(path: &std::path::Path) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    assert_eq!(img.dimensions(), (960, 600), "{}", path.display());
    let dark = img
        .pixels()
        .filter(|p| p.0.iter().all(|&c| c < 100))
        .count();
    assert!(dark > 500, "{}: only {dark} dark pixels", path.display());
}

#[test]
fn bench_writes_json_and_charts_with_sane_numbers() {
    let d = dir("pressure");
    let out = d.join("out");
    let o = trample(&[
        "bench",
        "--frames",
        "20",
        "--precisions",
        "1..3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("fps avg"), "{table}");
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    assert_eq!(r["blades"], 262_144);
    assert_eq!(r["segments"], 4);
    assert_eq!(r["frames"], 20);
    assert_eq!(r["backend"], "cpu");
    assert_eq!(r["objects"][0]["triangles"], 1280);
    for key in ["cpu", "cores", "memory_gib", "os", "date"] {
        assert!(!r["machine"][key].is_null(), "machine.{key}");
    }

    let runs = r["precisions"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    for (i, p) in runs.iter().enumerate() {
        assert_eq!(p["precision"], i as u64 + 1);
        let fps = |k: &str| p["fps"][k].as_f64().unwrap();
        let ms = |k: &str| p["step_ms"][k].as_f64().unwrap();
        assert!(fps("min") > 0.0 && fps("min") <= fps("avg") && fps("avg") <= fps("max"));
        assert!(ms("min") > 0.0 && ms("min") <= ms("median") && ms("median") <= ms("max"));
        // fps are the step times inverted.
        assert!((fps("min") - 1000.0 / ms("max")).abs() < 1e-6 * fps("min"));
        assert!((fps("avg") - 1000.0 / ms("mean")).abs() < 1e-6 * fps("avg"));
        assert!(p["stages_ms"]["narrow"].as_f64().unwrap() >= 0.0);
        // The ball starts on the grass: every frame bends some.
        assert!(p["dbg_blades_mean"].as_f64().unwrap() > 10.0, "{p}");
        assert!(p["wall_s"].as_f64().unwrap() > 0.0);
    }

    // Accuracy: the default scene's ball and the knot.
    let acc = r["accuracy"].as_array().unwrap();
    assert_eq!(acc.len(), 2);
    assert_eq!(acc[0]["objects"][0]["name"], "ball");
    assert_eq!(acc[1]["objects"][0]["name"], "knot");
    for a in acc {
        let exact = a["exact_hits"].as_u64().unwrap();
        assert!(exact > 100, "{a}");
        assert_eq!(a["times_s"].as_array().unwrap().len(), 8);
        assert!(a["first_false_negative"].is_null(), "{a}");
        let per = a["per_precision"].as_array().unwrap();
        assert_eq!(per.len(), 3);
        let mut last_fp = u64::MAX;
        for (i, p) in per.iter().enumerate() {
            let n = |k: &str| p[k].as_u64().unwrap();
            assert_eq!(n("precision"), i as u64 + 1);
            assert_eq!(n("false_negatives"), 0, "{p}");
            assert_eq!(n("not_in_previous"), 0, "{p}");
            assert_eq!(n("reported"), exact + n("false_positives"), "{p}");
            assert!(n("false_positives") <= last_fp, "false positives grew: {a}");
            last_fp = n("false_positives");
            let rate = a["false_positive_rate"][i].as_f64().unwrap();
            let want = n("false_positives") as f64 / n("reported") as f64;
            assert!((rate - want).abs() < 1e-12 && (0.0..1.0).contains(&rate));
        }
    }
    assert_chart(&out.join("bench.png"));
    assert_chart(&out.join("accuracy.png"));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn paths_not_built_yet_and_bad_flags_fail_in_one_line() {
    let d = dir("errors");
    let out = d.join("out");
    let out = out.to_str().unwrap();
    let cases: [(&[&str], &str); 9] = [
        (&["--render", "--scaling"], "--render: not with --scaling"),
        (
            &["--render", "--objects"],
            "--render: not with --scaling or --objects",
        ),
        (&["--scaling", "--objects"], "--objects"),
        (
            &["--max-blades", "1000"],
            "--max-blades / --max-triangles: only with --scaling",
        ),
        (&["--backend", "tpu"], "--backend"),
        (&["--precisions", "0..3"], "--precisions \"0..3\""),
        (&["--precisions", "7..1"], "the range 7..1 is empty"),
        (&["--precisions", "x"], "--precisions \"x\""),
        (&["--frames", "0"], "--frames 0"),
    ];
    for (args, want) in cases {
        let mut all = vec!["bench", "--out", out];
        all.extend_from_slice(args);
        let o = trample(&all);
        let e = stderr(&o);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(e.contains(want), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
        assert!(!e.contains("panic"), "{args:?}: {e}");
    }
    // Nothing was measured, so nothing was written.
    assert!(!d.join("out").join("bench.json").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn bench_render_adds_the_frame_rate_with_rendering() {
    let d = dir("render");
    let out = d.join("out");
    // Both paths: the GPU path's frames are drawn from its own buffers.
    let o = trample(&[
        "bench",
        "--frames",
        "3",
        "--precisions",
        "2,3",
        "--backend",
        "both",
        "--render",
        "--size",
        "160x90",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("Simulation + rendering on"), "{table}");
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    assert!(r["adapter"].as_str().is_some_and(|a| !a.is_empty()), "{r}");
    let runs = r["precisions"].as_array().unwrap();
    assert_eq!(runs.len(), 4, "{r}");
    for p in runs {
        let x = &p["render"];
        assert_eq!(x["size"], serde_json::json!([160, 90]));
        let render_ms = x["render_ms"]["median"].as_f64().unwrap();
        assert!(render_ms > 0.0, "{x}");
        // With rendering a frame takes longer than its step alone.
        let fps = |k: &str| x["fps"][k].as_f64().unwrap();
        assert!(fps("min") <= fps("avg") && fps("avg") <= fps("max"), "{x}");
        assert!(fps("avg") < p["fps"]["avg"].as_f64().unwrap(), "{p}");
        assert_eq!(x["read_back"], serde_json::json!(true), "{x}");
    }
    assert_chart(&out.join("bench.png"));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn bench_render_without_readback_waits_for_each_frame() {
    let d = dir("render_no_readback");
    let out = d.join("out");
    let o = trample(&[
        "bench",
        "--frames",
        "3",
        "--precisions",
        "2",
        "--backend",
        "both",
        "--render",
        "--no-readback",
        "--size",
        "160x90",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("not read back"), "{table}");
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    let runs = r["precisions"].as_array().unwrap();
    assert_eq!(runs.len(), 2, "{r}");
    for p in runs {
        let x = &p["render"];
        assert_eq!(x["read_back"], serde_json::json!(false), "{x}");
        assert!(x["render_ms"]["median"].as_f64().unwrap() > 0.0, "{x}");
    }
    // The flag means nothing without --render: refused, naming both.
    let o = trample(&["bench", "--no-readback", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("--render"), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn bench_both_backends_time_the_same_frames() {
    let d = dir("both");
    let out = d.join("out");
    let o = trample(&[
        "bench",
        "--frames",
        "3",
        "--precisions",
        "2,3",
        "--backend",
        "both",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    assert_eq!(r["backend"], "both");
    assert!(r["adapter"].as_str().is_some_and(|a| !a.is_empty()), "{r}");
    let runs = r["precisions"].as_array().unwrap();
    let order: Vec<(String, u64)> = runs
        .iter()
        .map(|p| {
            (
                p["backend"].as_str().unwrap().to_string(),
                p["precision"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        order,
        [("cpu", 2), ("cpu", 3), ("gpu", 2), ("gpu", 3)].map(|(b, p)| (b.to_string(), p))
    );
    for (cpu, gpu) in runs[..2].iter().zip(&runs[2..]) {
        // The GPU path agrees with the CPU path (trample-gpu's parity
        // tests): the same blades are hit directly in the same frames.
        assert_eq!(
            cpu["dbg_blades_mean"], gpu["dbg_blades_mean"],
            "{cpu} {gpu}"
        );
        let ms = gpu["step_ms"]["median"].as_f64().unwrap();
        assert!(ms > 0.0, "{gpu}");
    }
    assert_chart(&out.join("bench.png"));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn scaling_with_both_backends_has_gpu_points_beside_the_cpu_ones() {
    let d = dir("scaling");
    let out = d.join("out");
    // The two ¼-size fields (65,536 blades) and icospheres of 20, 80 and
    // 320 triangles on the default field: small enough for CI.
    let o = trample(&[
        "bench",
        "--scaling",
        "--frames",
        "3",
        "--precisions",
        "3",
        "--backend",
        "both",
        "--max-blades",
        "70000",
        "--max-triangles",
        "400",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("scaling.json")).unwrap()).unwrap();
    assert_eq!(r["backend"], "both");
    assert!(r["adapter"].as_str().is_some_and(|a| !a.is_empty()), "{r}");
    let points = |key: &str| -> Vec<(String, u64, f64, f64)> {
        r[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                let n = if key == "blades" {
                    "blades"
                } else {
                    "triangles"
                };
                (
                    p["backend"].as_str().unwrap().to_string(),
                    p[n].as_u64().unwrap(),
                    p["step_ms"]["median"].as_f64().unwrap(),
                    p.get("dbg_blades_mean")
                        .and_then(serde_json::Value::as_f64)
                        .unwrap_or(0.0),
                )
            })
            .collect()
    };
    let blades = points("blades");
    assert_eq!(blades.len(), 4, "{blades:?}");
    for pair in blades.chunks(2) {
        assert_eq!((pair[0].0.as_str(), pair[1].0.as_str()), ("cpu", "gpu"));
        assert_eq!(pair[0].1, 65_536);
        assert_eq!(pair[0].1, pair[1].1);
        // The same frames on both paths: the same blades hit directly.
        assert_eq!(pair[0].3, pair[1].3, "{pair:?}");
        assert!(pair[1].2 > 0.0, "{pair:?}");
    }
    let tris = points("triangles");
    let want: Vec<(&str, u64)> = [20, 80, 320]
        .into_iter()
        .flat_map(|t| [("cpu", t), ("gpu", t)])
        .collect();
    let got: Vec<(&str, u64)> = tris.iter().map(|t| (t.0.as_str(), t.1)).collect();
    assert_eq!(got, want);
    let skipped = r["skipped"].as_array().unwrap();
    assert!(
        skipped
            .iter()
            .any(|s| s.as_str().unwrap().contains("over --max-blades")),
        "{skipped:?}"
    );
    assert_chart(&out.join("scaling_blades.png"));
    assert_chart(&out.join("scaling_triangles.png"));
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn objects_series_times_each_count_on_both_paths() {
    let d = dir("objects");
    let out = d.join("out");
    let scene = d.join("three.toml");
    // Three objects circling in the grass near the camera.
    std::fs::write(
        &scene,
        r#"
name = "three"
[field]
patches = [6, 6]
cells_per_patch = 8
[lod]
geometry_m = 100.0
billboard_m = 200.0
[sim]
precision = 3
[camera]
path = { kind = "static", position = [0.0, 3.0, -4.0] }
look_at = { kind = "point", at = [0.0, 0.0, 0.0] }
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.3 }
orientation = "rolling"
path = { kind = "circle", center = [-1.0, 0.3, 0.0], radius_m = 0.6, period_s = 2.0 }
[[objects]]
name = "crate"
shape = { kind = "box", half_extents_m = [0.2, 0.2, 0.3] }
orientation = "face_motion"
path = { kind = "circle", center = [1.0, 0.2, 0.5], radius_m = 0.5, period_s = 2.5 }
[[objects]]
name = "knot"
shape = { kind = "knot", size_m = 0.8 }
path = { kind = "circle", center = [0.0, 0.25, -1.2], radius_m = 0.5, period_s = 3.0 }
"#,
    )
    .unwrap();
    let o = trample(&[
        "bench",
        scene.to_str().unwrap(),
        "--objects",
        "--frames",
        "6",
        "--backend",
        "both",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("Step time against objects"), "{table}");
    let r: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("objects.json")).unwrap()).unwrap();
    assert_eq!(r["backend"], "both");
    assert_eq!(r["blades"], 6 * 6 * 64);
    let points = r["points"].as_array().unwrap();
    let got: Vec<(&str, u64)> = points
        .iter()
        .map(|p| {
            (
                p["backend"].as_str().unwrap(),
                p["objects"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            ("cpu", 1),
            ("gpu", 1),
            ("cpu", 2),
            ("gpu", 2),
            ("cpu", 3),
            ("gpu", 3)
        ]
    );
    let mut last_tris = 0;
    for pair in points.chunks(2) {
        // The same frames on both paths: the same blades hit directly.
        assert_eq!(
            pair[0]["dbg_blades_mean"], pair[1]["dbg_blades_mean"],
            "{pair:?}"
        );
        assert!(
            pair[0]["dbg_blades_mean"].as_f64().unwrap() > 0.0,
            "{pair:?}"
        );
        assert_eq!(pair[0]["precision"], 7, "the series' default precision");
        for p in pair {
            assert!(p["step_ms"]["median"].as_f64().unwrap() > 0.0, "{p}");
        }
        let tris = pair[0]["triangles"].as_u64().unwrap();
        assert!(tris > last_tris);
        last_tris = tris;
    }
    assert_chart(&out.join("objects.png"));
    assert_eq!(r["far_every"], 1);

    // `--far-every` reaches every run, and the report says so; with the
    // camera moved 400 m away every object takes turns, and fewer blades a
    // step are hit directly than when all step every frame.
    std::fs::write(
        &scene,
        std::fs::read_to_string(&scene).unwrap().replace(
            "position = [0.0, 3.0, -4.0]",
            "position = [0.0, 3.0, -400.0]",
        ),
    )
    .unwrap();
    let far_out = d.join("far");
    let mut dbg = Vec::new();
    for k in ["1", "4"] {
        let o = trample(&[
            "bench",
            scene.to_str().unwrap(),
            "--objects",
            "--frames",
            "12",
            "--far-every",
            k,
            "--out",
            far_out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let table = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            table.contains("far objects every 4 steps"),
            k == "4",
            "{table}"
        );
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(far_out.join("objects.json")).unwrap()).unwrap();
        assert_eq!(r["far_every"].to_string(), k);
        dbg.push(r["points"][2]["dbg_blades_mean"].as_f64().unwrap());
    }
    assert!(dbg[1] < dbg[0], "DBG blades a step: {dbg:?}");
    std::fs::remove_dir_all(&d).unwrap();
}
