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
}
const _: () = assert!(std::mem::size_of::<GpuStepParams>() == 160);

/// Counters of the last sub-step. Layout-compatible with `State` in `blade.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuCounters {
    /// Current generation of the propagation.
    pub g: u32,
    /// 1 once propagation has ended.
    pub stop: u32,
    /// Set by a gather pass that reached a blade.
    pub any: u32,
    /// Generations of children created (PBG generations).
    pub generations: u32,
    /// DBG blades.
    pub dbg: u32,
    /// PBG blades.
    pub pbg: u32,
    /// Blades still away from rest after recovery.
    pub displaced: u32,
    /// Cells that changed level of detail (transitions).
    pub transitions: u32,
    /// Cells at each level of detail after the sub-step's classification:
    /// geometry, billboard, texture.
    pub lod: [u32; 3],
    /// Blades the contact response moved (ours, DESIGN §5).
    pub contact: u32,
}
const _: () = assert!(std::mem::size_of::<GpuCounters>() == 48);

impl GpuCounters {
    /// Writes the counts into a step's timings: DBG, PBG, generations,
    /// transitions, displaced blades, contact blades, cells per level.
    pub fn apply_to(&self, t: &mut trample::StepTimings) {
        t.dbg_blades = self.dbg;
        t.pbg_blades = self.pbg;
        t.generations = self.generations;
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
