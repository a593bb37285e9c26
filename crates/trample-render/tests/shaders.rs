//! Every WGSL file of the crate parses and passes naga's validator (as
//! compiled: with the shared globals prepended). Needs no GPU.

use wgpu::naga;

#[test]
fn every_wgsl_file_validates() {
    let sources = trample_render::shader_sources();
    // Guard against a shader added on disk but not listed.
    let on_disk = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/src"))
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            let name = name.to_string_lossy();
            name.ends_with(".wgsl") && name != "globals.wgsl"
        })
        .count();
    assert_eq!(
        on_disk,
        sources.len(),
        "a .wgsl file is missing from shader_sources()"
    );
    for (name, src) in sources {
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
    }
}

#[test]
fn a_broken_shader_is_caught() {
    // The check above can fail: an undefined name does not parse.
    let src = trample_render::globals::shader_source("fn f() -> f32 { return undefined_name; }");
    assert!(naga::front::wgsl::parse_str(&src).is_err());
}
