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

/// A stand-in `ffmpeg` in a folder of its own: it records its arguments and
/// copies the raw frames it is sent to the output path (its last argument),
/// so the test sees exactly what `trample run --mp4` pipes.
fn fake_ffmpeg(dir: &std::path::Path) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::create_dir_all(dir).unwrap();
    let script = dir.join("ffmpeg");
    std::fs::write(
        &script,
        "#!/bin/sh\necho \"$@\" > \"$(/usr/bin/dirname \"$0\")/args.txt\"\nfor last in \"$@\"; do :; done\n/bin/cat > \"$last\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
}

#[test]
fn run_mp4_pipes_every_rendered_frame_to_ffmpeg() {
    let base = std::env::temp_dir().join(format!("trample-mp4-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let bin = base.join("bin");
    fake_ffmpeg(&bin);
    let out = base.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args([
            "run", "--frames", "4", "--every", "2", "--size", "64x36", "--mp4", "--out",
        ])
        .arg(&out)
        .env("PATH", &bin)
        .output()
        .expect("run trample");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "exit {:?}: {stderr}", o.status);
    let video = std::fs::read(out.join("run.mp4")).unwrap();
    // Frames 0 and 2, raw RGBA.
    assert_eq!(video.len(), 2 * 64 * 36 * 4);
    let args = std::fs::read_to_string(bin.join("args.txt")).unwrap();
    assert!(
        args.contains("-s 64x36") && args.contains("-pix_fmt rgba"),
        "{args}"
    );
    assert!(
        args.contains("libx264") && args.contains("-framerate 30.000"),
        "{args}"
    );
    // No temporary left behind.
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["mp4"], "run.mp4");
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn run_mp4_without_ffmpeg_fails_before_the_run_in_one_line() {
    let base = std::env::temp_dir().join(format!("trample-nompeg-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(base.join("empty")).unwrap();
    let out = base.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(["run", "--frames", "2", "--size", "64x36", "--mp4", "--out"])
        .arg(&out)
        .env("PATH", base.join("empty"))
        .output()
        .expect("run trample");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        stderr.contains("--mp4: ffmpeg is not on the PATH"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(!out.join("summary.json").exists());
    std::fs::remove_dir_all(&base).unwrap();
}
