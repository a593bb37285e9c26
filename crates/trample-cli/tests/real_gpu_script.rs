//! `scripts/real_gpu_bench.sh`, the prepared run for a lent GPU (issue 16
//! item 6), keeps working: run in its QUICK mode on this machine's adapter
//! (CI: llvmpipe), small test scenes in place of the paper's field and the
//! herd, every step must finish and leave its results where the device
//! tool collects them.

mod common;

use common::dir;
use std::path::Path;
use std::process::Command;

#[test]
fn the_real_gpu_script_runs_every_step() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scenes = root.join("crates/trample-testkit/scenes");
    let d = dir("real-gpu");
    let out = d.join("out");
    let o = Command::new("bash")
        .arg("scripts/real_gpu_bench.sh")
        .current_dir(&root)
        .env("QUICK", "1")
        .env("OUT", &out)
        .env("TRAMPLE", env!("CARGO_BIN_EXE_trample"))
        .env("SCENE", scenes.join("rolling_ball.toml"))
        .env("HERD", scenes.join("busy.toml"))
        .output()
        .expect("run bash");
    let log = std::fs::read_to_string(out.join("log.txt")).unwrap_or_default();
    assert!(
        o.status.success(),
        "{}\n{log}",
        String::from_utf8_lossy(&o.stderr)
    );
    for step in ["default", "default_1080p", "herd", "herd_1080p", "objects"] {
        assert!(
            log.contains(&format!("== {step}: exit 0 ")),
            "step {step} failed:\n{log}"
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join(format!("{step}.json"))).unwrap())
                .unwrap();
        assert!(json.is_object(), "{step}: {json}");
    }
    // What the steps measured: both paths, and the frame with rendering.
    let herd: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("herd.json")).unwrap()).unwrap();
    let backends: Vec<&str> = herd["precisions"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|p| p["backend"].as_str())
        .collect();
    assert_eq!(backends, ["cpu", "gpu"], "{herd}");
    let render: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("herd_1080p.json")).unwrap()).unwrap();
    assert_eq!(
        render["precisions"][0]["render"]["size"],
        serde_json::json!([1920, 1080])
    );
    // At most eight files: the device tool brings back no more.
    let files = std::fs::read_dir(&out).unwrap().count();
    assert!(
        (7..=8).contains(&files),
        "{files} files in {}",
        out.display()
    );
    assert!(out.join("adapter.txt").exists() && out.join("objects.png").exists());
    std::fs::remove_dir_all(&d).unwrap();
}
