//! `trample view`: under Xvfb the default scene opens a window, draws 30
//! frames and saves the last one (scene and panel) as a PNG that is not
//! blank; with no display the command fails with one line that points to
//! `trample run`. `--backend gpu|auto|cpu` picks the simulation path (a
//! scene the GPU path refuses runs on the CPU and says why). Without
//! `xvfb-run` the window tests are skipped locally and fail under CI (`CI`
//! set): CI must install it (`.ci/run` does).

use std::process::Command;

fn xvfb_run() -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join("xvfb-run"))
        .find(|p| p.is_file())
}

#[test]
fn view_default_scene_under_xvfb_saves_a_screenshot() {
    let Some(xvfb) = xvfb_run() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "xvfb-run is missing (CI is set): apt-get install -y xvfb"
        );
        eprintln!("skipped: xvfb-run is not installed (apt-get install -y xvfb)");
        return;
    };
    let dir = std::env::temp_dir().join(format!("trample-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("shot.png");
    let _ = std::fs::remove_file(&shot);
    let o = Command::new(xvfb)
        .args(["-a", "-s", "-screen 0 1280x720x24"])
        .arg(env!("CARGO_BIN_EXE_trample"))
        .args([
            "view",
            "--frames",
            "30",
            "--size",
            "480x270",
            "--screenshot",
        ])
        .arg(&shot)
        .output()
        .expect("run xvfb-run");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "exit {:?}: {stderr}", o.status);
    let img = image::open(&shot).unwrap().to_rgba8();
    let (w, h) = img.dimensions();
    assert_eq!((w, h), (480, 270));
    // Right of the panel: sky above (blue over green), grass below (green
    // over blue and red).
    let sky = img.get_pixel(w - 8, 4);
    let grass = img.get_pixel(w - 8, h - 4);
    assert!(sky[2] > sky[1] && sky[2] > sky[0], "sky {sky:?}");
    assert!(
        grass[1] > grass[2] && grass[1] > grass[0],
        "grass {grass:?}"
    );
    // The panel is drawn on the left: egui's theme is grey (sky and grass
    // are not), so most of that strip is grey.
    let strip: Vec<_> = (0..h)
        .flat_map(|y| (0..150).map(move |x| (x, y)))
        .map(|(x, y)| img.get_pixel(x, y))
        .collect();
    let grey = strip
        .iter()
        .filter(|p| p[0].abs_diff(p[1]).max(p[1].abs_diff(p[2])) < 10)
        .count();
    assert!(
        grey * 10 > strip.len() * 8,
        "{grey} of {} grey",
        strip.len()
    );
    // Many distinct colours: a picture, not a cleared frame.
    let mut colours: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 500, "{} colours", colours.len());
}

#[test]
fn view_without_a_display_says_so_in_one_line() {
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .expect("run trample");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.contains("XDG_RUNTIME_DIR"))
        .collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].starts_with("error: cannot open a window") && lines[0].contains("trample run"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// A small scene (1,024 blades) in a fresh folder; `terrain` goes under `[field]`.
fn small_scene(name: &str, terrain: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("trample-view-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        format!(
            r#"
[field]
patches = [2, 2]
cells_per_patch = 16
terrain = {terrain}
[camera]
path = {{ kind = "static", position = [0.0, 2.0, 4.0] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.4 }}
orientation = "rolling"
path = {{ kind = "line", from = [-2.0, 0.4, 0.0], to = [2.0, 0.4, 0.0], duration_s = 1.0 }}
"#
        ),
    )
    .unwrap();
    scene
}

#[test]
fn view_backend_flag_picks_the_simulation_path_under_xvfb() {
    let Some(xvfb) = xvfb_run() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "xvfb-run is missing (CI is set): apt-get install -y xvfb"
        );
        eprintln!("skipped: xvfb-run is not installed (apt-get install -y xvfb)");
        return;
    };
    let flat = small_scene("flat", r#"{ kind = "flat" }"#);
    let hills = small_scene(
        "hills",
        // 10 µm hills: the GPU's table of the noise lattice passes a binding.
        r#"{ kind = "noise", amplitude_m = 0.2, wavelength_m = 0.00001 }"#,
    );
    let view = |scene: &std::path::Path, backend: &str| {
        let shot = scene.with_file_name(format!("shot-{backend}.png"));
        let o = Command::new(&xvfb)
            .args(["-a", "-s", "-screen 0 1280x720x24"])
            .arg(env!("CARGO_BIN_EXE_trample"))
            .arg("view")
            .arg(scene)
            .args(["--backend", backend, "--frames", "8", "--size", "480x270"])
            .arg("--screenshot")
            .arg(&shot)
            .output()
            .expect("run xvfb-run");
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(
            o.status.success(),
            "{backend}: exit {:?}: {stderr}",
            o.status
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
        let img = image::open(&shot).unwrap().to_rgba8();
        let grass = img.get_pixel(img.width() - 8, img.height() - 4);
        assert!(grass[1] > grass[2] && grass[1] > grass[0], "{grass:?}");
        stderr
    };
    // gpu: the GPU path on the window's device, whatever the adapter.
    let said = view(&flat, "gpu");
    assert!(said.contains("trample: GPU path on "), "{said}");
    // A scene the GPU path refuses runs on the CPU, and says why.
    let said = view(&hills, "gpu");
    assert!(
        said.contains("GPU path refused") && said.contains("noise lattice"),
        "{said}"
    );
    // auto: the GPU on a hardware adapter, the CPU on a software one.
    let said = view(&flat, "auto");
    assert!(
        said.contains("trample: GPU path on ") || said.contains("software adapter: CPU path"),
        "{said}"
    );
    // cpu (the default) says nothing about it.
    let said = view(&flat, "cpu");
    assert!(!said.contains("GPU path"), "{said}");
}

#[test]
fn view_backend_flag_refuses_an_unknown_path() {
    let o = Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(["view", "--backend", "tpu", "--frames", "1"])
        .output()
        .expect("run trample");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("'tpu'") && stderr.contains("auto, cpu, gpu"),
        "{stderr}"
    );
}
