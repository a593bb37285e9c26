//! Force propagation on the GPU (paper §5.2, Eq. 4; DESIGN §5): dispatches
//! `propagation.wgsl` as generation passes, a gather with a fixed
//! neighbour order (no float atomics), all in the caller's encoder. Matches
//! `trample::force::propagation::propagate_forces` on grids whose neighbour
//! relation is mutual (every field layout's is).
//!
//! Without a read-back the host does not know when propagation ends, so it
//! records the first [`WIDE_GENERATIONS`] generations as indirect
//! dispatches whose size `advance` writes (zero workgroups once a
//! generation reached no blade, or at the cap) — generation 1 a gather and
//! a commit pass, generation 2 a single pass (`gather_commit`) — and the
//! rest up to the cap (32) as one dispatch of one workgroup, `finish`,
//! which loops over the generations with a barrier where the wide passes
//! take a dispatch. Every dispatch, empty or not, costs a barrier (and an
//! indirect one wgpu's validation pass): the default scene's push ends
//! after two generations, and the 60 dispatches it recorded for the other
//! 30 made most of the stage's time on a real GPU (session 24, H200: the
//! default scene's propagation 0.30–0.34 ms with them, 0.07 ms with
//! `finish`). The passes run over a generation's candidates only,
//! not the field: `seed` lists the blades next to generation 0, each blade
//! that joins a generation lists its neighbours for the next (once each: a
//! bit a blade), and `advance` sizes the next pass by that list
//! (`GpuField::frontier`). Without a broad phase `seed` goes over every
//! blade (it clears the lists' bits and the generations); with one
//! (`broad` given to [`Propagation::record`]) it goes over the active
//! patches' seed list — the patches next to those listed — and
//! [`Propagation::record_tidy`], before the narrow phase, puts back the
//! state of the patches the broad phase no longer lists
//! ([`crate::active_patches`]): the herd's 16.8 M blades are almost all far
//! from every object (session 24, H200: `seed` over all of them was most of
//! its 0.68 ms of propagation).

use crate::active_patches::List;
use crate::broad_phase::{BroadPhase, NoBroad};
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, begin_pass};

/// The WGSL source as compiled (`blade.wgsl` and `broad_params.wgsl`
/// prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}",
        crate::BLADE_WGSL,
        include_str!("broad_params.wgsl"),
        include_str!("propagation.wgsl")
    )
}

const BEGIN: usize = 0;
const SEED: usize = 1;
const GATHER: usize = 2;
const COMMIT: usize = 3;
const ADVANCE: usize = 4;
const GATHER_COMMIT: usize = 5;
const PRIME: usize = 6;
const FINISH: usize = 7;
const TIDY: usize = 8;
const SEED_ACTIVE: usize = 9;

/// Generations recorded as wide (indirect) passes before `finish` takes
/// the rest in one workgroup: the first generations' candidate lists are
/// the push's whole rim (thousands of blades on the herd), the later ones
/// its faint edges.
pub const WIDE_GENERATIONS: u32 = 2;
/// The compiled propagation kernels and the indirect arguments of the
/// gather passes.
pub struct Propagation {
    kernel: Kernel,
    next_gather: wgpu::Buffer,
    /// Stands in for `next_gather` in the gather passes' bind group: a
    /// buffer may not be storage and indirect arguments in one dispatch.
    unused_args: wgpu::Buffer,
    /// Stand in for the broad phase's uniform and lists where none is
    /// given: a zero uniform, so `seed` runs over every blade.
    no_broad: NoBroad,
}

impl Propagation {
    /// Compiles the kernels on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu propagation",
                &source(),
                &[
                    Uniform, ReadWrite, ReadWrite, ReadWrite, ReadWrite, Read, ReadWrite,
                    ReadWrite, ReadWrite, ReadWrite, Uniform, ReadWrite,
                ],
                &[
                    "begin",
                    "seed",
                    "gather",
                    "commit",
                    "advance",
                    "gather_commit",
                    "prime",
                    "finish",
                    "tidy",
                    "seed_active",
                ],
            ),
            unused_args: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu gather dispatch (unused)"),
                size: 12,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            no_broad: NoBroad::new(device),
            next_gather: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu gather dispatch"),
                size: 12,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
                mapped_at_creation: false,
            }),
        }
    }

    /// Records the reset of the counters and of the propagation state: the
    /// first pass of every sub-step.
    pub fn record_reset(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
    ) {
        let group = self.bind(device, field, params, state, &self.next_gather, None);
        self.kernel.dispatch(encoder, BEGIN, &group, (1, 1));
    }

    /// Records `tidy` over `broad`'s active tidy list (the patches dirty
    /// from the last sub-step that the broad phase did not list now: their forces,
    /// contacts, generations and candidate bits put back to none), after
    /// the active patches' `record_seed` and before the narrow phase, which
    /// then writes the listed patches' forces and contacts alone.
    pub fn record_tidy(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        broad: &BroadPhase,
    ) {
        let group = self.bind(device, field, params, state, &self.next_gather, Some(broad));
        self.kernel.dispatch_indirect_at(
            &mut begin_pass(encoder),
            TIDY,
            &group,
            &broad.args,
            broad.list_args_offset(List::Tidy),
        );
    }

    /// The stage's bind group: the field's propagation arrays, with `args`
    /// at the indirect-arguments slot (the next gather's, or an unused
    /// buffer while the gather reads them), and `broad`'s uniform and lists
    /// (stand-ins without one).
    fn bind(
        &self,
        device: &wgpu::Device,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        args: &wgpu::Buffer,
        broad: Option<&BroadPhase>,
    ) -> wgpu::BindGroup {
        let (broad_params, lists) = self.no_broad.or(broad);
        self.kernel.bind(
            device,
            &[
                params,
                state,
                &field.force,
                &field.generation,
                &field.class,
                &field.neighbours,
                args,
                &field.touch,
                &field.next,
                &field.frontier,
                broad_params,
                lists,
            ],
        )
    }

    /// Records generation 0 (every blade touched, DBG from `DBG_WEIGHT`)
    /// from the narrow phase's contacts and the list of its neighbours,
    /// then at most `passes` generations (Eq. 4) over the candidates: gather
    /// and commit for the first, `gather_commit` for the second, `finish`
    /// for the others. [`Propagation::record_reset`] must come first in
    /// the sub-step. With `broad` (recorded earlier in the sub-step with
    /// the active patches' `record_seed`, then [`Propagation::record_tidy`]
    /// and the narrow phase over its lists), `seed` runs over the patches
    /// next to those `broad` listed (no other blade or neighbour of one was
    /// touched: the same results); without, over every blade.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        groups: (u32, u32),
        passes: u32,
        broad: Option<&BroadPhase>,
    ) {
        let group = self.bind(device, field, params, state, &self.next_gather, broad);
        let gather_group = self.bind(device, field, params, state, &self.unused_args, broad);
        // One compute pass for the stage's dispatches.
        let mut cpass = begin_pass(encoder);
        let k = &self.kernel;
        match broad {
            Some(b) => k.dispatch_indirect_at(
                &mut cpass,
                SEED_ACTIVE,
                &group,
                &b.args,
                b.list_args_offset(List::Seed),
            ),
            None => k.dispatch_in(&mut cpass, SEED, &group, groups),
        }
        k.dispatch_in(&mut cpass, PRIME, &group, (1, 1));
        for pass in 0..passes.min(WIDE_GENERATIONS) {
            if pass == 0 {
                k.dispatch_indirect_in(&mut cpass, GATHER, &gather_group, &self.next_gather);
                k.dispatch_indirect_in(&mut cpass, COMMIT, &gather_group, &self.next_gather);
            } else {
                k.dispatch_indirect_in(&mut cpass, GATHER_COMMIT, &gather_group, &self.next_gather);
            }
            k.dispatch_in(&mut cpass, ADVANCE, &group, (1, 1));
        }
        if passes > WIDE_GENERATIONS {
            k.dispatch_in(&mut cpass, FINISH, &group, (1, 1));
        }
    }
}
