//! `trample run`: the default scene renders 10 frames at 320×180 to PNGs, a
//! GIF and a summary on whatever adapter `WGPU_BACKEND` gives (GL on
//! llvmpipe in CI). No adapter = failure, not a skip.

use std::process::Command;

#[test]
fn run_default_scene_writes_frames_gif_and_summary() {
    let out = std::env::temp_dir().join(format!("trample-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args([
            "run", "--frames", "10", "--every", "1", "--size", "320x180", "--gif", "--out",
        ])
        .arg(&out)
        .output()
        .expect("run trample");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "exit {:?}: {stderr}", o.status);
    assert!(
        stderr.contains("rendering 320x180 on "),
        "names the adapter: {stderr}"
    );

    let mut pngs: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("frame_") && n.ends_with(".png"))
        .collect();
    pngs.sort();
    assert_eq!(pngs.len(), 10, "{pngs:?}");
    assert_eq!(pngs[0], "frame_0000.png");
    let img = image::open(out.join(&pngs[9])).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (320, 180));
    // Not a blank frame: sky above, grass below.
    let top = img.get_pixel(160, 2);
    let bottom = img.get_pixel(160, 177);
    assert!(
        top[2] > top[1] && bottom[1] > bottom[2],
        "top {top:?} bottom {bottom:?}"
    );

    let gif = std::fs::read(out.join("run.gif")).unwrap();
    assert!(
        gif.starts_with(b"GIF89a") && gif.len() > 10_000,
        "{} bytes",
        gif.len()
    );

    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["frames"], 10);
    assert_eq!(s["blades"], 262_144);
    assert_eq!(s["pngs_written"], 10);
    assert!(s["step_ms"]["median"].as_f64().unwrap() > 0.0);
    assert!(s["render_ms"]["median"].as_f64().unwrap() > 0.0);
    assert_eq!(s["render_ms_per_frame"].as_array().unwrap().len(), 10);
    let fps = &s["fps"];
    let (min, avg, max) = (
        fps["min"].as_f64().unwrap(),
        fps["avg"].as_f64().unwrap(),
        fps["max"].as_f64().unwrap(),
    );
    assert!(0.0 < min && min <= avg && avg <= max, "{fps}");
    assert!(s["adapter"].as_str().unwrap().len() > 3);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn run_bad_size_is_one_line() {
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(["run", "--size", "320by180"])
        .output()
        .expect("run trample");
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    assert!(e.contains("WIDTHxHEIGHT"), "{e}");
}
