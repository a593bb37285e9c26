//! The per-step uniform and the GPU-side counters shared by the step
//! kernels (`blade.wgsl`).

use bytemuck::{Pod, Zeroable};

/// Step parameters. Layout-compatible with `StepParams` in `blade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuStepParams {
    /// Sub-step h (s), att (Eq. 4), threshold L (m/s), ground height (m).
    pub a: [f32; 4],
    /// Ground clearance (m), `[sim]` recovery_s (0 for ∞) and trail (the
    /// paper's billboard recovery), recovery on for some track owner (1) /
    /// off (0).
    pub b: [f32; 4],
    /// P(1) … P(15) of Eq. 7 (`trample::deform::bend::weights`), zero beyond n.
    pub weights: [[f32; 4]; 4],
    /// Blade count, segments, generation passes (cap), workgroups in x.
    pub counts: [u32; 4],
    /// LOD viewpoint xyz (the camera eye of the sub-step), `geometry_m`.
    pub eye: [f32; 4],
    /// `billboard_m`; propagation's `threshold_fade` and `hold_weight`
    /// (`trample::force::propagation::PropagationParams`; the simulation's
    /// are `THRESHOLD_FADE` and `stages::HOLD_WEIGHT`); 1 when the cells
    /// are not classified this sub-step (the counts per level of the last
    /// classification are kept; `lod_settle.rs`), else 0.
    pub lod: [f32; 4],
    /// Cell count, blades per cell, object count, track everywhere (1) or
    /// the paper's geometric cells only (0) (per-chunk cell dispatches take
    /// their workgroups from the chunk's uniform).
    pub cells: [u32; 4],
    /// How this sub-step's counts join the step's, as `trample::StepTimings`
    /// counts them (`trample::step::stages`): x = 1 in a far pass
    /// (`trample::step::passes`: its DBG, PBG, contact and newly displaced
    /// blades add to the step's, its generations to their largest), 0 in
    /// the main pass (each sub-step counts anew; the last one's stand);
    /// y = 1 on the step's first sub-step (the transitions, summed over
    /// the step's sub-steps, start from zero); z = the bits of `[sim]`
    /// `recovery_stride_m` (slow blades recover in strides, `recovery.wgsl`;
    /// 0 for none).
    pub far: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuStepParams>() == 176);

/// The step's counters so far: those of the main pass's last sub-step,
/// plus the far passes' (see [`GpuStepParams::far`]), as the CPU's
/// `trample::StepTimings` counts them. Layout-compatible with `State` in
/// `blade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuCounters {
    /// Current generation of the propagation.
    pub g: u32,
    /// 1 once propagation has ended.
    pub stop: u32,
    /// Set by a gather pass that reached a blade.
    pub any: u32,
    /// Generations of children created (PBG generations) this sub-step.
    pub generations: u32,
    /// DBG blades.
    pub dbg: u32,
    /// PBG blades.
    pub pbg: u32,
    /// Blades away from rest: those left after the main pass's recovery,
    /// plus those the far passes moved from rest.
    pub displaced: u32,
    /// Cells that changed level of detail (transitions), over the step's
    /// sub-steps.
    pub transitions: u32,
    /// Cells at each level of detail after the sub-step's classification:
    /// geometry, billboard, texture.
    pub lod: [u32; 3],
    /// Blades the contact response moved (ours, DESIGN §5).
    pub contact: u32,
    /// The most generations of the step's sub-steps before this one
    /// (from the main pass's last; 0 without far passes).
    pub earlier_generations: u32,
}
const _: () = assert!(std::mem::size_of::<GpuCounters>() == 52);

impl GpuCounters {
    /// Writes the counts into a step's timings: DBG, PBG, generations,
    /// transitions, displaced blades, contact blades, cells per level.
    pub fn apply_to(&self, t: &mut trample::StepTimings) {
        t.dbg_blades = self.dbg;
        t.pbg_blades = self.pbg;
        t.generations = self.generations.max(self.earlier_generations);
        t.transitions = self.transitions;
        t.displaced_blades = self.displaced;
        t.contact_blades = self.contact;
        t.lod = trample::field::LodCounts {
            geometry: self.lod[0],
            billboard: self.lod[1],
            texture: self.lod[2],
        };
    }
}
