//! Every WGSL stage of the crate parses and passes naga's validator, as
//! compiled (with the shared `blade.wgsl` / `segment_obb.wgsl` /
//! `broad_params.wgsl` / `active_chunk.wgsl` prepended).
//! Needs no GPU.

use wgpu::naga;

#[test]
fn every_wgsl_file_validates() {
    let sources = trample_gpu::shader_sources();
    let on_disk = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/src"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .file_name()
                .to_string_lossy()
                .ends_with(".wgsl")
                && ![
                    "active_chunk.wgsl",
                    "billboard.wgsl",
                    "blade.wgsl",
                    "broad_params.wgsl",
                    "cell.wgsl",
                    "chunk.wgsl",
                    "guard.wgsl",
                    "object.wgsl",
                    "segment_obb.wgsl",
                ]
                .contains(&e.as_ref().unwrap().file_name().to_string_lossy().as_ref())
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
