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
use crate::chunk::GpuChunk;
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

/// What a stage lists, in chunk `c`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Listed {
    /// The blades of the chunk's dirty patches with a generation (the bend).
    Bent(u32),
    /// The displaced blades of the chunk's dirty and kept patches (the
    /// recovery).
    Displaced(u32),
}

impl Listed {
    /// The list of active patches it runs over.
    fn patches(self) -> List {
        match self {
            Self::Bent(c) => List::Bend(c),
            Self::Displaced(c) => List::Recover(c),
        }
    }

    /// Its entry point (`list_bent`, `list_displaced`).
    fn entry(self) -> usize {
        match self {
            Self::Bent(_) => 0,
            Self::Displaced(_) => 1,
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

/// A stage that works over the listed blades of a chunk: its kernel, its
/// entry point over every blade of the chunk (no broad phase) and over the
/// list, and its bind group (which binds [`GpuField::near_blades`], the
/// list, read-only).
pub(crate) struct ListedWork<'a> {
    pub(crate) kernel: &'a Kernel,
    pub(crate) every: usize,
    pub(crate) listed: usize,
    pub(crate) group: &'a wgpu::BindGroup,
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

    /// Records `work` over chunk `chunk` of `field`: with `broad`, the
    /// blades `what` names listed (`flags`: the generations for
    /// [`Listed::Bent`], the displaced marks for [`Listed::Displaced`]), the
    /// list's size, then `work.listed` over the list; without (the stage
    /// tests), `work.every` over the chunk's `full` workgroups.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        chunk: &GpuChunk,
        broad: Option<&BroadPhase>,
        what: Listed,
        flags: &wgpu::Buffer,
        work: &ListedWork<'_>,
        full: (u32, u32),
    ) {
        let Some(broad) = broad else {
            work.kernel.dispatch(encoder, work.every, work.group, full);
            return;
        };
        let group = self.kernel.bind(
            device,
            &[
                &broad.params,
                &broad.lists,
                &chunk.uniform,
                flags,
                &field.near_blades,
                &self.args,
            ],
        );
        encoder.clear_buffer(&field.near_blades, 0, Some(4));
        let mut pass = begin_pass(encoder);
        self.kernel.dispatch_indirect_at(
            &mut pass,
            what.entry(),
            &group,
            &broad.args,
            broad.list_args_offset(what.patches()),
        );
        self.kernel
            .dispatch_in(&mut pass, LISTED_ARGS, &group, (1, 1));
        work.kernel
            .dispatch_indirect_in(&mut pass, work.listed, work.group, &self.args);
    }
}
