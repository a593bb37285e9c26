//! Blade deformation on the GPU (paper §6.1, Eq. 5–7, Fig. 7): dispatches
//! `bend.wgsl` over the active patches' dirty patches
//! ([`crate::active_patches`]; every blade without a broad phase); those
//! with a force this sub-step (DBG or PBG) bend, as `trample::deform::bend::bend_blade` does, above the
//! terrain's ground guard (`guard.wgsl`).

use crate::active_patches::{List, dispatch_listed};
use crate::broad_phase::{BroadPhase, NoBroad};
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot};

/// The WGSL source as compiled (`blade.wgsl`, `guard.wgsl`, `chunk.wgsl`,
/// `broad_params.wgsl` and `active_chunk.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}\n{}\n{}",
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::CHUNK_WGSL,
        include_str!("broad_params.wgsl"),
        include_str!("active_chunk.wgsl"),
        include_str!("bend.wgsl")
    )
}

/// The compiled bending kernel.
pub struct Bend {
    kernel: Kernel,
    no_broad: NoBroad,
}

impl Bend {
    /// Compiles the kernel on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu bend",
                &source(),
                &[
                    Uniform, ReadWrite, Read, Read, ReadWrite, Uniform, Read, Uniform, ReadWrite,
                    ReadWrite,
                ],
                &["bend", "bend_active"],
            ),
            no_broad: NoBroad::new(device),
        }
    }

    /// Records the bending of every forced blade, one dispatch per chunk:
    /// over `broad`'s active bend lists (the active patches' `record_lists`
    /// recorded before, after propagation), or every blade without. A far
    /// pass counts the blades it moves from rest in `state` (the step's
    /// counters, [`crate::GpuCounters`]).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        broad: Option<&BroadPhase>,
    ) {
        let (broad_params, lists) = self.no_broad.or(broad);
        for (c, chunk) in field.chunks.iter().enumerate() {
            let group = self.kernel.bind(
                device,
                &[
                    params,
                    &chunk.pos,
                    &field.force,
                    &field.generation,
                    &field.displaced,
                    &chunk.uniform,
                    &field.ground,
                    broad_params,
                    lists,
                    state,
                ],
            );
            dispatch_listed(
                &self.kernel,
                encoder,
                &group,
                broad,
                List::Bend(c as u32),
                crate::kernel::run_grid(chunk.groups),
            );
        }
    }
}
