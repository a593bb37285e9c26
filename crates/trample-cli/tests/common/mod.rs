//! Helpers shared by the CLI's integration tests: a fresh scratch folder,
//! running the built `trample`, its stderr.

#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

/// An empty folder for test `name`, unique to this test binary and process
/// (removed first if a previous run left it).
pub fn dir(name: &str) -> PathBuf {
    let binary = std::env::current_exe()
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_else(|| "tests".into());
    let d = std::env::temp_dir().join(format!("trample-{binary}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the `trample` binary of this build with `args`.
pub fn trample(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trample"))
        .args(args)
        .output()
        .expect("run trample")
}

/// `o`'s stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts `o` succeeded, showing its stderr when not.
pub fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}
