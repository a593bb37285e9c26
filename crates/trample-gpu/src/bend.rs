//! Blade deformation on the GPU (paper §6.1, Eq. 5–7, Fig. 7): dispatches
//! `bend.wgsl` over every blade; those with a force this sub-step (DBG or
//! PBG) bend, as `trample::deform::bend::bend_blade` does, above the
//! terrain's ground guard (`guard.wgsl`).

use crate::field::GpuField;
use crate::kernel::{Kernel, Slot};

/// The WGSL source as compiled (`blade.wgsl`, `guard.wgsl` and `chunk.wgsl`
/// prepended).
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

/// The compiled bending kernel.
pub struct Bend {
    kernel: Kernel,
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
                &[Uniform, ReadWrite, Read, Read, ReadWrite, Uniform, Read],
                &["bend"],
            ),
        }
    }

    /// Records the bending of every forced blade, one dispatch per chunk.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
    ) {
        for chunk in &field.chunks {
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
                ],
            );
            self.kernel
                .dispatch(encoder, 0, &group, crate::kernel::run_grid(chunk.groups));
        }
    }
}
