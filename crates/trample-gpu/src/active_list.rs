//! The blades that bend or recover, listed before the work (ours;
//! `active_list.wgsl`): the bend and the recovery ran one thread a blade of
//! every active patch ([`crate::active_patches`]), most of which have no
//! work (no generation, not displaced). On the software drivers, which run
//! every branch of a kernel whether a lane takes it or not, the work cost
//! every one of them (BENCHMARKS.md, "Session 55" found the same for the
//! transitions, the narrow phase and the contact response). Each stage now
//! lists its blades first (an atomic append), writes the indirect arguments
//! of its work in a one-thread pass, then works over the list alone. The
//! same results bit for bit: each blade's work reads and writes that blade
//! alone.

use crate::active_patches::List;
use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, args_buffer, begin_pass};

/// The WGSL source as compiled (`chunk.wgsl`, `broad_params.wgsl` and
/// `active_chunk.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}",
        crate::CHUNK_WGSL,
        include_str!("broad_params.wgsl"),
        include_str!("active_chunk.wgsl"),
        include_str!("active_list.wgsl")
    )
}

/// What a stage lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Listed {
    /// The blades of the chunk's dirty patches with a generation (the bend).
    Bent,
    /// The displaced blades of the chunk's dirty and kept patches (the
    /// recovery).
    Displaced,
}

impl Listed {
    /// The list of active patches it runs over, in chunk `c`.
    fn patches(self, c: u32) -> List {
        match self {
            Self::Bent => List::Bend(c),
            Self::Displaced => List::Recover(c),
        }
    }

    /// Its entry point (`list_bent`, `list_displaced`).
    fn entry(self) -> usize {
        match self {
            Self::Bent => 0,
            Self::Displaced => 1,
        }
    }

    /// The per-blade flags its entry point reads: the generations, or the
    /// displaced marks.
    fn flags(self, field: &GpuField) -> &wgpu::Buffer {
        match self {
            Self::Bent => &field.generation,
            Self::Displaced => &field.displaced,
        }
    }
}

/// `listed_args`'s entry point.
const LISTED_ARGS: usize = 2;

/// The listing kernels and the indirect arguments of the work over the
/// list (one buffer: the chunks take turns with it, in the
/// encoder's order, as with the list itself: the field's `near_blades`).
pub struct ActiveList {
    kernel: Kernel,
    args: wgpu::Buffer,
}

impl ActiveList {
    /// Compiles the kernels on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu active list",
                &source(),
                &[Uniform, ReadWrite, Uniform, Read, ReadWrite, ReadWrite],
                &["list_bent", "list_displaced", "listed_args"],
            ),
            args: args_buffer(
                device,
                "trample-gpu active list dispatch",
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            ),
        }
    }

    /// Records a stage's work over chunk `c` of `field`: with `broad`, the
    /// blades `what` names listed, the list's size, then entry point 1 of
    /// `kernel` over the list; without (the stage tests), its entry point 0
    /// over the chunk's `full` workgroups. `group` is the stage's bind
    /// group (with the field's `near_blades`, the list, read-only).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        c: usize,
        broad: Option<&BroadPhase>,
        what: Listed,
        (kernel, group): (&Kernel, &wgpu::BindGroup),
        full: (u32, u32),
    ) {
        let Some(broad) = broad else {
            kernel.dispatch(encoder, 0, group, full);
            return;
        };
        let chunk = &field.chunks[c];
        let list_group = self.kernel.bind(
            device,
            &[
                &broad.params,
                &broad.lists,
                &chunk.uniform,
                what.flags(field),
                &field.near_blades,
                &self.args,
            ],
        );
        encoder.clear_buffer(&field.near_blades, 0, Some(4));
        let mut pass = begin_pass(encoder);
        self.kernel.dispatch_indirect_at(
            &mut pass,
            what.entry(),
            &list_group,
            &broad.args,
            broad.list_args_offset(what.patches(c as u32)),
        );
        self.kernel
            .dispatch_in(&mut pass, LISTED_ARGS, &list_group, (1, 1));
        kernel.dispatch_indirect_in(&mut pass, 1, group, &self.args);
    }
}
