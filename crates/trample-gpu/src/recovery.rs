//! Recovery on the GPU (ours, DESIGN §6): dispatches `recovery.wgsl` over
//! every blade; displaced ones relax towards rest as
//! `trample::recovery::recover_blade` does, and are counted. Billboard
//! slopes do not recover here yet (billboards are not on the GPU yet).

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
        include_str!("recovery.wgsl")
    )
}

/// The compiled recovery kernel.
pub struct Recovery {
    kernel: Kernel,
}

impl Recovery {
    /// Compiles the kernel on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu recovery",
                &source(),
                &[
                    Uniform, ReadWrite, ReadWrite, Read, Read, ReadWrite, Uniform, Read,
                ],
                &["recover"],
            ),
        }
    }

    /// Records the recovery of every displaced blade, one dispatch per chunk.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
    ) {
        for chunk in &field.chunks {
            let group = self.kernel.bind(
                device,
                &[
                    params,
                    state,
                    &chunk.pos,
                    &chunk.rest,
                    &field.seg_len,
                    &field.displaced,
                    &chunk.uniform,
                    &field.ground,
                ],
            );
            self.kernel.dispatch(encoder, 0, &group, chunk.groups);
        }
    }
}
