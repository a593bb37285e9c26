//! Per-stage timers and counts of one step (rapier-style counters).

use crate::field::LodCounts;
use serde::Serialize;
use std::fmt;

/// Wall-clock milliseconds spent in each stage of the last step (DESIGN §7
/// order), and what the step did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StepTimings {
    /// Object poses and sub-step planning.
    pub poses_ms: f64,
    /// LOD per cell and frustum culling per patch.
    pub lod_ms: f64,
    /// Broad phase (patches against object root boxes).
    pub broad_ms: f64,
    /// Narrow phase (segments through the OBB tree).
    pub narrow_ms: f64,
    /// DBG forces (Eq. 2).
    pub forces_ms: f64,
    /// Propagation (Eq. 4).
    pub propagation_ms: f64,
    /// Blade bending and billboard slopes (Eq. 5–8).
    pub deformation_ms: f64,
    /// The contact response (ours, DESIGN §5): blades moved out of objects.
    pub contact_ms: f64,
    /// LOD transitions (Eq. 9–13).
    pub transitions_ms: f64,
    /// Recovery towards rest.
    pub recovery_ms: f64,
    /// The whole step.
    pub total_ms: f64,
    /// Blades hit directly (DBG), summed over sub-steps' last.
    pub dbg_blades: u32,
    /// Blades reached by propagation only (PBG).
    pub pbg_blades: u32,
    /// Generations of propagation in the last sub-step.
    pub generations: u32,
    /// Candidate blades of the narrow phase: those in the tiles it took up
    /// ([`StepTimings::narrow_tiles`]), tested or reused, over the step's
    /// sub-steps.
    pub narrow_candidates: u32,
    /// Tiles of blades (`TILE_CELLS`² cells) the narrow phase took up,
    /// tested or reused ([`StepTimings::reused_tiles`]), over the step's
    /// sub-steps.
    pub narrow_tiles: u32,
    /// Billboards deflected by an object (BBG, Eq. 8, the paper's mode), or
    /// cells whose billboard and flatness followed their blades (ours,
    /// `sim.track_everywhere`).
    pub bbg_cells: u32,
    /// Blades the contact response moved out of an object in the last
    /// sub-step (ours, DESIGN §5).
    pub contact_blades: u32,
    /// Cells that changed level of detail.
    pub transitions: u32,
    /// Blades away from rest (being recovered).
    pub displaced_blades: u32,
    /// Sub-steps this step was split into near the camera: the most that
    /// its main pass or a pass of faster near bodies took
    /// ([`crate::step::passes`]).
    pub substeps: u32,
    /// Bodies that touched the grass in far passes this step (ours,
    /// `sim.far_every > 1`: far bodies taking their turn, and bodies
    /// catching up; [`crate::step::passes`]); 0 when every body steps every
    /// step.
    pub far_bodies: u32,
    /// Tiles whose narrow phase a collider at rest took from what it kept
    /// instead of testing them again, over the step's sub-steps (ours,
    /// `sim.reuse_at_rest`; `step::at_rest`).
    pub reused_tiles: u32,
    /// Blades the contact response of a collider at rest left without a
    /// query (kept at their fixed point), over the step's sub-steps.
    pub reused_blades: u32,
    /// Sub-steps the fastest object needed; more than `substeps` when
    /// `sim.max_substeps` clamped them (see `SubstepClamp`).
    pub substeps_needed: u32,
    /// Patches in the view frustum.
    pub visible_patches: u32,
    /// Cells per level of detail.
    pub lod: LodCounts,
}

impl StepTimings {
    /// (name, milliseconds) of each stage, in step order.
    #[must_use]
    pub fn stages(&self) -> [(&'static str, f64); 10] {
        [
            ("poses", self.poses_ms),
            ("lod", self.lod_ms),
            ("broad", self.broad_ms),
            ("narrow", self.narrow_ms),
            ("forces", self.forces_ms),
            ("propagation", self.propagation_ms),
            ("deformation", self.deformation_ms),
            ("contact", self.contact_ms),
            ("transitions", self.transitions_ms),
            ("recovery", self.recovery_ms),
        ]
    }
}

impl fmt::Display for StepTimings {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "step {:.3} ms (", self.total_ms)?;
        for (i, (name, ms)) in self.stages().iter().enumerate() {
            write!(f, "{}{name} {ms:.3}", if i > 0 { ", " } else { "" })?;
        }
        write!(
            f,
            "); DBG {}, PBG {}, generations {}, sub-steps {}",
            self.dbg_blades, self.pbg_blades, self.generations, self.substeps
        )?;
        if self.substeps_needed > self.substeps {
            write!(f, " (clamped; {} needed)", self.substeps_needed)?;
        }
        Ok(())
    }
}
