//! The active patches (ours; `active_patches.wgsl`): the passes that went
//! over every blade of the field each sub-step — the clearing of the forces
//! and contacts, propagation's `seed`, `bend`, `recover` and `follow` — go
//! over the patches where something happens: the patches near those the
//! broad phase listed, those propagation reached, and those holding
//! displaced blades. Their cost follows the objects and their tracks, not
//! the field (issue 16; on an H200 the herd's step, 16.8 M blades and 128
//! objects, went from 4.7 to 4.1 ms: BENCHMARKS.md, "Session 28"); the
//! results are the same bits, since every other patch holds the state of
//! no contact and no displaced blade.
//!
//! Each patch carries two marks in the broad phase's lists
//! (`broad_params.wgsl`'s `ACTIVE_*` region): dirty (a blade may hold the
//! last sub-step's force, contact, generation or candidate bit: put back to
//! none by `tidy` once the broad phase no longer lists the patch) and kept
//! (a blade may be displaced: `recover` visits it, and clears the mark when
//! none is left). Both start set on every patch, so the first sub-step
//! visits the whole field once.

use crate::broad_phase::BroadPhase;
use crate::kernel::{Kernel, Slot, begin_pass, grid};
use crate::readback::read_buffer;

/// The WGSL source as compiled (`broad_params.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}",
        include_str!("broad_params.wgsl"),
        include_str!("active_patches.wgsl")
    )
}

const PLAN_SEED: usize = 0;
const PLAN_MAIN: usize = 1;
const PLAN_FAR: usize = 2;
const LIST_ARGS: usize = 3;

/// A list of active patches, in the order of its count in the lists
/// (`broad_params.wgsl`'s `ACTIVE_COUNTS`) and of its indirect dispatch in
/// the broad phase's indirect arguments ([`BroadPhase::list_args_offset`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum List {
    /// The dirty patches the broad phase did not list (`tidy`).
    Tidy,
    /// The patches near those the broad phase listed (`seed`).
    Seed,
    /// Chunk c's dirty patches (`bend`).
    Bend(u32),
    /// Chunk c's dirty and kept patches (`recover`).
    Recover(u32),
}

impl List {
    /// Its index among the lists: tidy, seed, bend's per chunk, recover's
    /// per chunk (of `chunks`).
    #[must_use]
    pub fn index(self, chunks: u32) -> u32 {
        match self {
            Self::Tidy => 0,
            Self::Seed => 1,
            Self::Bend(c) => 2 + c,
            Self::Recover(c) => 2 + chunks + c,
        }
    }
}

/// Words of the active patches' region of the lists for `patches` patches
/// in `chunks` chunks: two marks and four lists a patch, then the lists'
/// counts.
#[must_use]
pub fn region_words(patches: u32, chunks: u32) -> u64 {
    6 * u64::from(patches) + 2 + 2 * u64::from(chunks)
}

/// The compiled planning kernels.
pub struct ActivePatches {
    kernel: Kernel,
}

impl ActivePatches {
    /// Compiles the kernels on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu active patches",
                &source(),
                &[Uniform, ReadWrite, ReadWrite],
                &["plan_seed", "plan_main", "plan_far", "list_args"],
            ),
        }
    }

    /// Records, after `broad` (in the same sub-step), the tidy and seed
    /// lists and their dispatches; the patches near a listed one become
    /// dirty, the others clean once tidied.
    pub fn record_seed(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        broad: &BroadPhase,
    ) {
        let (first, _) = broad.active_counts(List::Tidy);
        encoder.clear_buffer(&broad.lists, first, Some(8));
        self.plan(device, encoder, broad, PLAN_SEED);
    }

    /// Records, after propagation, bend's and recover's lists and their
    /// dispatches. `recovering`: recovery runs in this sub-step (it marks
    /// the patches it leaves displaced blades in kept again).
    pub fn record_lists(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        broad: &BroadPhase,
        recovering: bool,
    ) {
        let (first, bytes) = broad.active_counts(List::Bend(0));
        encoder.clear_buffer(&broad.lists, first, Some(bytes));
        self.plan(
            device,
            encoder,
            broad,
            if recovering { PLAN_MAIN } else { PLAN_FAR },
        );
    }

    fn plan(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        broad: &BroadPhase,
        entry: usize,
    ) {
        let group = self
            .kernel
            .bind(device, &[&broad.params, &broad.lists, &broad.args]);
        let max = device.limits().max_compute_workgroups_per_dimension;
        let mut pass = begin_pass(encoder);
        self.kernel
            .dispatch_in(&mut pass, entry, &group, grid(broad.patch_count(), max));
        self.kernel.dispatch_in(
            &mut pass,
            LIST_ARGS,
            &group,
            grid(2 + 2 * broad.chunk_count(), max),
        );
    }
}

/// The active patches as the GPU holds them after a step, beside what the
/// field's blades hold (tests: the marks must cover every blade's state).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ActiveState {
    /// Per patch: marked dirty.
    pub dirty: Vec<bool>,
    /// Per patch: marked kept.
    pub kept: Vec<bool>,
    /// Patches on the last sub-step's recover lists (all chunks).
    pub recover_listed: u32,
    /// Per patch: a blade holds a force, a contact or a generation.
    pub touched: Vec<bool>,
    /// Per patch: a blade is displaced.
    pub displaced: Vec<bool>,
}

impl ActiveState {
    /// Reads back `broad`'s marks and `field`'s per-blade state.
    ///
    /// # Errors
    /// [`crate::GpuError::ReadBack`] when mapping fails.
    pub fn read(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        broad: &BroadPhase,
        field: &crate::GpuField,
    ) -> Result<Self, crate::GpuError> {
        let words: Vec<u32> = read_buffer(device, queue, &broad.lists, "active patches")?;
        let patches = broad.patch_count() as usize;
        let chunks = broad.chunk_count();
        let first = broad.active_first() as usize;
        let mark = |block: usize| -> Vec<bool> {
            words[first + block * patches..first + (block + 1) * patches]
                .iter()
                .map(|&w| w != 0)
                .collect()
        };
        let counts = first + 6 * patches;
        let recover_listed = (0..chunks)
            .map(|c| words[counts + List::Recover(c).index(chunks) as usize])
            .sum();
        let per = (field.count as usize / patches.max(1)).max(1);
        let forces = field.read_forces(device, queue)?;
        let masks = field.read_hit_masks(device, queue)?;
        let generation = field.read_u32(device, queue, &field.generation)?;
        let displaced = field.read_u32(device, queue, &field.displaced)?;
        let by_patch = |f: &dyn Fn(usize) -> bool| -> Vec<bool> {
            (0..patches)
                .map(|p| (p * per..(p + 1) * per).any(f))
                .collect()
        };
        Ok(Self {
            dirty: mark(0),
            kept: mark(1),
            recover_listed,
            touched: by_patch(&|b| {
                forces[b].force != [0.0; 3]
                    || forces[b].num != 0.0
                    || masks[b] != 0
                    || generation[b] != u32::from(NO_GENERATION)
            }),
            displaced: by_patch(&|b| displaced[b] != 0),
        })
    }
}

/// `blade.wgsl`'s `NO_GENERATION`.
const NO_GENERATION: u8 = 255;
