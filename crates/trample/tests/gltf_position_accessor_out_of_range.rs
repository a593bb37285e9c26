//! Guards the first crash the fuzz target `gltf` found: a primitive whose
//! POSITION names an accessor the file does not have made the `gltf` crate's
//! validation index out of bounds and panic (gltf-json 1.4,
//! `primitive_validate_hook`). It must be an ordinary error naming the mesh,
//! the primitive and the allowed range — and no panic at all may happen on
//! the way (a caught one still reaches the CLI's panic hook, which prints an
//! "internal error" line, and aborts a `panic = "abort"` build).

use std::sync::atomic::{AtomicBool, Ordering};
use trample::object::gltf::parse_gltf;

static PANICKED: AtomicBool = AtomicBool::new(false);

#[test]
fn gltf_position_accessor_out_of_range_is_an_error_without_a_panic() {
    std::panic::set_hook(Box::new(|_| PANICKED.store(true, Ordering::SeqCst)));
    let minimal = br#"{ "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }] }"#;
    let err = parse_gltf(minimal, None, "p.gltf").expect_err("refused");
    assert_eq!(
        err.to_string(),
        "p.gltf: mesh 0 primitive 0: POSITION refers to accessor 0 but the file has 0; allowed: 0..0"
    );
    // The input the fuzzer found: "accessors" misspelt, so there are none.
    let found = std::fs::read(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../fuzz/regressions/gltf/position-accessor-out-of-range.gltf"),
    )
    .unwrap();
    let err = parse_gltf(&found, None, "found.gltf").expect_err("refused");
    assert!(
        err.to_string()
            .contains("POSITION refers to accessor 0 but the file has 0"),
        "{err}"
    );
    let _ = std::panic::take_hook();
    assert!(
        !PANICKED.load(Ordering::SeqCst),
        "a panic happened on the way"
    );
}
