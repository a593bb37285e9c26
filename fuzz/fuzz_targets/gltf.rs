//! glTF/GLB bytes: `parse_gltf` (embedded buffers only), then sanitise, OBB tree and queries.
//! The checks live in `trample::fuzz_targets::gltf` (replayed by `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| trample::fuzz_targets::gltf(data));
