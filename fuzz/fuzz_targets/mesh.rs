//! Raw mesh bytes: sanitiser, OBB-tree build and validation, collision query properties.
//! The checks live in `trample::fuzz_targets::mesh` (replayed by `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| trample::fuzz_targets::mesh(data));
