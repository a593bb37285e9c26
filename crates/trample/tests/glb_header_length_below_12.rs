//! Guards the second crash the fuzz target `gltf` found: a GLB whose header
//! declares a total length below its own 12 bytes made the `gltf` crate
//! (1.4, `Glb::from_slice`) subtract with overflow — a panic wherever debug
//! assertions are on (tests, the dev profile, fuzzing). It must be an
//! ordinary error naming the file and the length, with no panic on the way.

use std::sync::atomic::{AtomicBool, Ordering};
use trample::object::gltf::parse_gltf;

static PANICKED: AtomicBool = AtomicBool::new(false);

#[test]
fn glb_header_length_below_12_is_an_error_without_a_panic() {
    std::panic::set_hook(Box::new(|_| PANICKED.store(true, Ordering::SeqCst)));
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(0u32.to_le_bytes());
    glb.extend(b"\x02\x00\x00\x00JSON{}");
    let err = parse_gltf(&glb, None, "h.glb").expect_err("refused");
    assert_eq!(
        err.to_string(),
        "h.glb: not a valid glTF file: GLB header declares a total length of 0 bytes; at least its own 12 are needed"
    );
    // The input the fuzzer found.
    let found = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fuzz/regressions/gltf/glb-length-below-header.glb"),
    )
    .unwrap();
    assert!(parse_gltf(&found, None, "found.glb").is_err());
    // A length of exactly 12 is left to the parser (it reports the missing chunk).
    let mut twelve = b"glTF".to_vec();
    twelve.extend(2u32.to_le_bytes());
    twelve.extend(12u32.to_le_bytes());
    assert!(parse_gltf(&twelve, None, "t.glb").is_err());
    let _ = std::panic::take_hook();
    assert!(
        !PANICKED.load(Ordering::SeqCst),
        "a panic happened on the way"
    );
}
