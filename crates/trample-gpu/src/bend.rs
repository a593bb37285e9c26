//! Blade deformation on the GPU (paper §6.1, Eq. 5–7, Fig. 7): dispatches
//! `bend.wgsl` over the blades of the active patches' dirty patches
//! ([`crate::active_patches`]) that propagation reached, listed first
//! ([`crate::active_list`]; every blade without a broad phase); those
//! with a force this sub-step (DBG or PBG) bend, as `trample::deform::bend::bend_blade` does, above the
//! terrain's ground guard (`guard.wgsl`).

use crate::active_list::{ActiveList, Listed};
use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot};

/// The WGSL source as compiled (`blade.wgsl`, `guard.wgsl` and
/// `chunk.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}",
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::CHUNK_WGSL,
        include_str!("bend.wgsl")
    )
}

/// The compiled bending kernel and the list of its blades.
pub struct Bend {
    kernel: Kernel,
    list: ActiveList,
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
                    Uniform, ReadWrite, Read, Read, ReadWrite, Uniform, Read, ReadWrite, Read,
                ],
                &["bend", "bend_listed"],
            ),
            list: ActiveList::new(device),
        }
    }

    /// Records the bending of every forced blade, per chunk: over the
    /// blades of `broad`'s active bend lists (the active patches'
    /// `record_lists` recorded before, after propagation) with a
    /// generation, listed first (three dispatches), or every blade without
    /// (one). A far
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
                    state,
                    &field.near_blades,
                ],
            );
            self.list.record(
                device,
                encoder,
                field,
                c,
                broad,
                Listed::Bent,
                (&self.kernel, &group),
                crate::kernel::run_grid(chunk.groups),
            );
        }
    }
}
