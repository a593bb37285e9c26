//! What the GPU path needs of a host's device (issue 14 item 4): a host
//! that creates its own device asks for [`required_limits`] and
//! [`required_features`] in its `wgpu::DeviceDescriptor`, and nothing
//! else; the library never creates a device (STYLE rule 3).
//!
//! The limits are `wgpu::Limits::default()` raised only where the GPU path
//! needs more: storage buffers per shader stage (counted from the WGSL the
//! stages compile, [`storage_buffers_per_stage`]) and, for fields whose
//! whole-field arrays or objects exceed the default 128 MiB, the storage
//! binding and buffer sizes ([`required_limits`]). Blade positions are
//! chunked to whatever binding size the device has, so they never raise
//! it.

use trample::Simulation;

/// The most storage buffers any of the GPU path's compute stages binds in
/// one shader stage, counted from the sources as compiled
/// ([`crate::shader_sources`]: every binding a stage declares is in its
/// explicit layout). `with_draw_lists`: count the draw lists too
/// ([`crate::draw_lists`], made only for a renderer that draws from the
/// GPU buffers), else the step's stages only.
#[must_use]
pub fn storage_buffers_per_stage(with_draw_lists: bool) -> u32 {
    crate::shader_sources()
        .iter()
        .filter(|(name, _)| with_draw_lists || *name != "draw_lists.wgsl")
        .map(|(_, source)| source.matches("var<storage").count() as u32)
        .max()
        .unwrap_or(0)
}

/// The largest single storage binding `sim` needs on the GPU path, bytes:
/// the whole-field arrays ([`crate::GpuField::whole_field_binding`]: 16
/// bytes a blade, 32 a cell), the draw lists'
/// ([`crate::draw_lists::largest_binding`]: 48 bytes a cell), the object
/// table ([`crate::object::TableLayout`]: every collider, parts included)
/// and the broad phase's lists and masks.
#[must_use]
pub fn largest_binding(sim: &Simulation) -> u64 {
    let (blades, cells) = (
        sim.field.blades.count as u64,
        sim.field.cells.lod.len() as u64,
    );
    let field = crate::GpuField::whole_field_binding(blades, cells)
        .0
        .max(crate::draw_lists::largest_binding(blades, cells).0);
    let objects = crate::object::TableLayout::of_simulation(sim).bytes();
    let patches = sim.field.layout.patch_list.len() as u32;
    // At most one chunk a patch.
    let lists = crate::broad_phase::lists_words(patches, patches, sim.bodies.len() as u32) * 4;
    field.max(objects).max(lists)
}

/// The device limits the GPU path needs for `sim` (with the draw lists):
/// `wgpu::Limits::default()` with `max_storage_buffers_per_shader_stage`
/// raised to [`storage_buffers_per_stage`]`(true)`, and
/// `max_storage_buffer_binding_size` / `max_buffer_size` raised to
/// [`largest_binding`] where that is over the default. Put them in the
/// host's `DeviceDescriptor::required_limits` (check them against
/// `Adapter::limits()` first).
#[must_use]
pub fn required_limits(sim: &Simulation) -> wgpu::Limits {
    let mut l = wgpu::Limits::default();
    l.max_storage_buffers_per_shader_stage = l
        .max_storage_buffers_per_shader_stage
        .max(storage_buffers_per_stage(true));
    let binding = largest_binding(sim);
    l.max_storage_buffer_binding_size = l.max_storage_buffer_binding_size.max(binding);
    l.max_buffer_size = l.max_buffer_size.max(binding);
    l
}

/// The device features the GPU path needs: none. (The profiling mode uses
/// [`crate::TIMESTAMP_FEATURES`] where the device has them, and measures
/// wall time where it does not.)
#[must_use]
pub fn required_features() -> wgpu::Features {
    wgpu::Features::empty()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-patch field (64 blades) and a body whose parts' meshes (two
    /// finely tessellated balls) outweigh everything else: the object table
    /// is the largest binding, and it holds the parts (it failed when only
    /// each body's own tree was counted).
    #[test]
    fn the_largest_binding_counts_every_collider_of_every_body() {
        let text = r#"
            [field]
            patches = [1, 1]
            cells_per_patch = 8
            [[objects]]
            name = "carrier"
            shape = { kind = "box", half_extents_m = [0.5, 0.5, 0.5] }
            path = { kind = "static", position = [0.0, 2.0, 0.0] }
            [[objects.parts]]
            name = "left"
            shape = { kind = "sphere", radius_m = 0.4, subdivisions = 5 }
            offset_m = [1.0, 0.0, 0.0]
            [[objects.parts]]
            name = "right"
            shape = { kind = "sphere", radius_m = 0.3, subdivisions = 5 }
            offset_m = [-1.0, 0.0, 0.0]
        "#;
        let scene = trample::scene::Scene::parse(text, "test", std::path::Path::new("."))
            .expect("valid scene");
        let sim = scene.build().expect("builds");
        let own_trees_only = crate::object::table_bytes(sim.bodies.iter().map(|b| &*b.tree));
        let every_collider = crate::object::TableLayout::of_simulation(&sim).bytes();
        assert!(
            every_collider > 10 * own_trees_only,
            "{every_collider} {own_trees_only}"
        );
        assert_eq!(largest_binding(&sim), every_collider);
    }
}
