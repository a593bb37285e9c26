//! Scene text: `Scene::parse` (validation), then build and step small scenes.
//! The checks live in `trample::fuzz_targets::scene` (replayed by `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| trample::fuzz_targets::scene(data));
