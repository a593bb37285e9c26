//! Track owners renumbered on the GPU when bodies leave a running
//! simulation (issue 14: bodies at any time, on both paths). The blades'
//! track owners (bits 8–15 of `GpuField::class`) hold 1 + a body's index;
//! when a body is removed the CPU renumbers its own copy
//! (`Simulation::remove_body`) and `track_owners.wgsl` does the same to the
//! GPU's, with the table both take from
//! [`trample::step::bodies::renumbered_owners`].

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, grid};

/// The WGSL source as compiled.
#[must_use]
pub fn source() -> String {
    include_str!("track_owners.wgsl").to_string()
}

/// `Renumber` in `track_owners.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GpuRenumber {
    /// Blades, workgroups along x, unused ×2.
    counts: [u32; 4],
    /// New number of old owner `o` at `[o / 4][o % 4]`.
    table: [[u32; 4]; 64],
}

/// The compiled renumbering kernel (made when a body first leaves).
pub struct TrackOwners {
    kernel: Kernel,
}

impl TrackOwners {
    /// Compiles the kernel on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu track owners",
                &source(),
                &[Slot::Uniform, Slot::ReadWrite],
                &["renumber_owners"],
            ),
        }
    }

    /// Records the renumbering of every blade's track owner by `table`
    /// (`table[old] = new`) into `encoder`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        table: &[u8; 256],
    ) {
        let max = device.limits().max_compute_workgroups_per_dimension;
        let groups = grid(field.count, max);
        let mut packed = [[0u32; 4]; 64];
        for (o, &n) in table.iter().enumerate() {
            packed[o / 4][o % 4] = u32::from(n);
        }
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("trample-gpu track owner table"),
            contents: bytemuck::bytes_of(&GpuRenumber {
                counts: [field.count, groups.0, 0, 0],
                table: packed,
            }),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // A uniform of its own each time: a group not kept.
        let group = self.kernel.make_group(device, &[&uniform, &field.class]);
        self.kernel.dispatch(encoder, 0, &group, groups);
    }
}
