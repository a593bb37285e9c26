//! Bad input (DESIGN §9): every wrong scene or mesh gives one clear line that
//! names the file, the key or index, and what is allowed — never a panic.
//! The messages are snapshotted in `tests/snapshots/bad_input.txt`; run with
//! `UPDATE_SNAPSHOTS=1` to rewrite it after an intended change, and review the diff.

use std::path::{Path, PathBuf};
use trample::scene::Scene;

const GOOD_OBJECT: &str = r#"
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.5 }
path = { kind = "static", position = [0.0, 0.5, 0.0] }
"#;

const SMALL: &str = "[field]\npatches = [2, 2]\ncells_per_patch = 8\n";

fn tmpdir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("trample-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `files` into a fresh folder, loads `scene.toml` from it and builds
/// the simulation; returns the error line with the folder replaced by `<dir>`.
fn error_of(scene: &str, files: &[(&str, &[u8])]) -> String {
    let dir = tmpdir().join(format!(
        "case{}",
        COUNTER.fetch_add(1, std::sync::atomic::Ordering::SeqCst)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let msg = match Scene::load(&path).and_then(|s| s.build().map(|_| ())) {
        Ok(()) => "NO ERROR".to_string(),
        Err(e) => e.to_string(),
    };
    assert!(!msg.contains('\n'), "message must be one line: {msg}");
    msg.replace(&dir.display().to_string(), "<dir>")
}

static COUNTER: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

fn cases() -> Vec<(&'static str, String)> {
    let obj = |body: &str| {
        format!(
            "{SMALL}[[objects]]\nname = \"thing\"\nshape = {{ kind = \"mesh\", path = \"m.obj\" }}\npath = {{ kind = \"static\", position = [0.0, 0.5, 0.0] }}\n# {body}"
        )
    };
    let with_obj = |text: &str, mesh: &str| error_of(&obj(text), &[("m.obj", mesh.as_bytes())]);
    vec![
        ("missing scene file", {
            match Scene::load(Path::new("/nonexistent/scene.toml")) {
                Err(e) => e.to_string(),
                Ok(_) => "NO ERROR".into(),
            }
        }),
        ("malformed toml", error_of("[sim\nprecision = 3\n", &[])),
        ("unknown key", error_of("[sim]\nprecison = 3\n", &[])),
        (
            "unknown table",
            error_of("[simulation]\nprecision = 3\n", &[]),
        ),
        ("wrong type", error_of("[sim]\nprecision = \"high\"\n", &[])),
        ("dt zero", error_of("[sim]\ndt_s = 0.0\n", &[])),
        ("dt negative", error_of("[sim]\ndt_s = -0.01\n", &[])),
        ("dt nan", error_of("[sim]\ndt_s = nan\n", &[])),
        ("precision zero", error_of("[sim]\nprecision = 0\n", &[])),
        ("precision 1000", error_of("[sim]\nprecision = 1000\n", &[])),
        ("att above one", error_of("[sim]\natt = 1.5\n", &[])),
        (
            "recovery negative",
            error_of("[sim]\nrecovery_s = -1.0\n", &[]),
        ),
        ("zero patches", error_of("[field]\npatches = [0, 4]\n", &[])),
        (
            "zero cell size",
            error_of("[field]\ncell_size_m = 0.0\n", &[]),
        ),
        ("zero segments", error_of("[field]\nsegments = 0\n", &[])),
        (
            "too many segments",
            error_of("[field]\nsegments = 40\n", &[]),
        ),
        (
            "negative blade height",
            error_of("[field]\nblade_height_m = -0.2\n", &[]),
        ),
        (
            "lod not increasing",
            error_of("[lod]\ngeometry_m = 20.0\nbillboard_m = 10.0\n", &[]),
        ),
        (
            "field too large for memory",
            error_of("[field]\npatches = [512, 512]\n", &[]),
        ),
        (
            "unknown terrain kind",
            error_of("[field]\nterrain = { kind = \"mountains\" }\n", &[]),
        ),
        (
            "missing height map",
            error_of(
                &format!(
                    "{SMALL}terrain = {{ kind = \"heightmap\", path = \"h.png\", height_scale_m = 2.0 }}\n"
                ),
                &[],
            ),
        ),
        (
            "unknown shape kind",
            error_of(
                &format!(
                    "{SMALL}[[objects]]\nname = \"x\"\nshape = {{ kind = \"teapot\" }}\npath = {{ kind = \"static\", position = [0.0, 0.0, 0.0] }}\n"
                ),
                &[],
            ),
        ),
        (
            "sphere radius zero",
            error_of(
                &GOOD_OBJECT.replace("radius_m = 0.5", "radius_m = 0.0"),
                &[],
            ),
        ),
        (
            "duplicate object names",
            error_of(&format!("{SMALL}{GOOD_OBJECT}{GOOD_OBJECT}"), &[]),
        ),
        (
            "camera follows unknown object",
            error_of(
                &format!(
                    "{SMALL}[camera]\nlook_at = {{ kind = \"object\", name = \"truck\" }}\n{GOOD_OBJECT}"
                ),
                &[],
            ),
        ),
        (
            "path with one point",
            error_of(
                &format!(
                    "{SMALL}[[objects]]\nname = \"x\"\nshape = {{ kind = \"sphere\", radius_m = 0.5 }}\npath = {{ kind = \"polyline\", points = [[0.0, 0.0, 0.0]], speed_m_s = 1.0 }}\n"
                ),
                &[],
            ),
        ),
        (
            "line duration zero",
            error_of(
                &format!(
                    "{SMALL}[[objects]]\nname = \"x\"\nshape = {{ kind = \"sphere\", radius_m = 0.5 }}\npath = {{ kind = \"line\", from = [0.0, 0.0, 0.0], to = [1.0, 0.0, 0.0], duration_s = 0.0 }}\n"
                ),
                &[],
            ),
        ),
        ("mesh file missing", error_of(&obj(""), &[])),
        (
            "mesh unsupported extension",
            error_of(
                &format!(
                    "{SMALL}[[objects]]\nname = \"x\"\nshape = {{ kind = \"mesh\", path = \"m.stl\" }}\npath = {{ kind = \"static\", position = [0.0, 0.0, 0.0] }}\n"
                ),
                &[("m.stl", b"solid x")],
            ),
        ),
        ("mesh empty", with_obj("empty", "# nothing here\n")),
        (
            "mesh index out of range",
            with_obj("oob", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        ),
        (
            "mesh nan coordinate",
            with_obj("nan", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"),
        ),
        (
            "mesh absurd size",
            with_obj("huge", "v 0 0 0\nv 1e9 0 0\nv 0 1e9 0\nf 1 2 3\n"),
        ),
        (
            "mesh all degenerate",
            with_obj("flat", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
        ),
    ]
}

#[test]
fn every_bad_input_gives_its_clear_one_line_error() {
    let mut text = String::new();
    for (name, msg) in cases() {
        assert_ne!(msg, "NO ERROR", "case '{name}' was accepted");
        text.push_str(&format!("{name}: {msg}\n"));
    }
    let snap = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots/bad_input.txt");
    if std::env::var_os("UPDATE_SNAPSHOTS").is_some() {
        std::fs::write(&snap, &text).unwrap();
    }
    let want = std::fs::read_to_string(&snap).unwrap_or_else(|_| {
        panic!(
            "{} is missing: run with UPDATE_SNAPSHOTS=1 and review it\n{text}",
            snap.display()
        )
    });
    assert_eq!(
        text, want,
        "messages changed; review, then UPDATE_SNAPSHOTS=1"
    );
    let _ = std::fs::remove_dir_all(tmpdir());
}
