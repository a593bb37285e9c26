//! `trample collide` on the GPU: which segments of the blades at rest the
//! objects hit at one instant, at a precision. The GPU counterpart of
//! `trample::Simulation::segment_hits_at_rest` with `HitMode::Precision`
//! (the exact mode stays on the CPU: it needs f64 triangle tests).

use trample::Simulation;
use trample::field::Lod;

use crate::error::GpuError;
use crate::field::GpuField;
use crate::narrow_phase::NarrowPhase;
use crate::object::GpuObjects;

/// One byte per segment, blade-major (`flags[b * n + k]`): 1 where segment
/// k of blade b at rest hits an object posed at time `t`, at `precision`.
/// Every cell counts as geometric, as in the CPU query.
///
/// # Errors
/// From the uploads and the read-back.
pub fn segment_hits_at_rest(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    sim: &Simulation,
    t: f32,
    precision: u32,
) -> Result<Vec<u8>, GpuError> {
    let f = &sim.field;
    let mut blades = f.blades.clone();
    blades.pos.clone_from(&blades.rest);
    let lod = vec![Lod::Geometry; f.cells.lod.len()];
    let field = GpuField::new(
        device,
        &blades,
        &lod,
        f.layout.blades_per_cell,
        &f.layout.neighbours,
    )?;
    // The bodies posed at t (skins posed, trees refitted, parts posed):
    // one object per collider.
    let posed = sim.bodies_at(t);
    let colliders: Vec<_> = posed.iter().flat_map(trample::Body::colliders).collect();
    let trees: Vec<_> = colliders.iter().map(|c| c.tree).collect();
    let mut objects = GpuObjects::new(device, &trees, (0, 0))?;
    for (i, c) in colliders.iter().enumerate() {
        objects.set_pose(i, c.pose);
    }
    let n = blades.segments;
    if objects.is_empty() {
        return Ok(vec![0; blades.count * n]);
    }
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("trample-gpu collide"),
    });
    NarrowPhase::new(device).record(
        device,
        queue,
        &mut crate::upload::Uploads::new(),
        &mut encoder,
        &field,
        &mut objects,
        precision,
        None,
    );
    queue.submit([encoder.finish()]);
    let masks = field.read_hit_masks(device, queue)?;
    Ok(masks
        .iter()
        .flat_map(|m| (0..n).map(move |k| u8::from(m & (1 << k) != 0)))
        .collect())
}
