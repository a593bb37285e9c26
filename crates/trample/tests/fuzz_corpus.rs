//! Replays the committed fuzz corpus (`fuzz/corpus/<target>/`) and the
//! inputs that once crashed a target (`fuzz/regressions/<target>/`) through
//! the same entry functions the fuzz targets call
//! (`trample::fuzz_targets`), so plain `cargo test` on stable Rust — and CI
//! — exercises every input the fuzzer kept, without nightly or cargo-fuzz.

use std::path::{Path, PathBuf};

/// A fuzz target's entry function.
type Entry = fn(&[u8]);

/// The fuzz targets and their entry functions.
const TARGETS: [(&str, Entry); 4] = [
    ("scene", trample::fuzz_targets::scene),
    ("obj", trample::fuzz_targets::obj),
    ("gltf", trample::fuzz_targets::gltf),
    ("mesh", trample::fuzz_targets::mesh),
];

fn fuzz_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

/// Files directly in `dir`, sorted (none when it does not exist).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    out
}

fn replay(kind: &str, min_files: usize) {
    for (target, entry) in TARGETS {
        let dir = fuzz_dir().join(kind).join(target);
        let inputs = files(&dir);
        assert!(
            inputs.len() >= min_files,
            "{}: {} files, expected at least {min_files}",
            dir.display(),
            inputs.len()
        );
        for input in &inputs {
            let bytes = std::fs::read(input).unwrap();
            let outcome = std::panic::catch_unwind(|| entry(&bytes));
            assert!(
                outcome.is_ok(),
                "fuzz target {target} panics on {} (reproduce: cargo +nightly fuzz run {target} {})",
                input.display(),
                input.display()
            );
        }
        println!("{target}: {} {kind} inputs replayed", inputs.len());
    }
}

#[test]
fn every_committed_corpus_input_passes_its_target() {
    replay("corpus", 3);
}

#[test]
fn every_input_that_once_crashed_a_target_passes_it_now() {
    replay("regressions", 0);
}
