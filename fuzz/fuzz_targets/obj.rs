//! OBJ bytes: `parse_obj`, then sanitise, OBB tree and collision queries.
//! The checks live in `trample::fuzz_targets::obj` (replayed by `tests/fuzz_corpus.rs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| trample::fuzz_targets::obj(data));
