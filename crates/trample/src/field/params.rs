//! Field parameters as they appear in a scene file's `[field]` table.

use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Shape and size of the grass field. Every field has its unit, its default
/// and why. Defaults reproduce the paper's experiment: 16×16 patches of 32×32
/// cells, one blade per cell, 262,144 blades.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FieldParams {
    /// Patches along x and z. Default `[16, 16]` (paper §7).
    pub patches: [u32; 2],
    /// Cells along each side of a patch. Default 32 (paper §7).
    pub cells_per_patch: u32,
    /// Blades in each cell. Default 1 (paper §7: "each cell represents a grass blade").
    pub blades_per_cell: u32,
    /// Side of a cell, metres. Default 0.1 (ours): the field is 51.2 m square.
    pub cell_size_m: f32,
    /// Rigid segments per blade, `n`. Default 4; at most [`super::MAX_SEGMENTS`].
    pub segments: u32,
    /// Mean blade height at rest, metres. Default 0.45: knee-high meadow grass.
    pub blade_height_m: f32,
    /// Relative height jitter: heights are uniform in `h·(1 ± jitter)`. Default 0.3.
    pub height_jitter: f32,
    /// Mean blade width at the root, metres. Default 0.012.
    pub blade_width_m: f32,
    /// Relative width jitter. Default 0.3.
    pub width_jitter: f32,
    /// Largest lean of a blade's rest shape from vertical at the tip, radians.
    /// Default 0.35: grass is never quite straight.
    pub lean_jitter_rad: f32,
    /// How far a blade's root may move from its slot's centre, as a fraction
    /// of the slot. Default 0.8 (a regular grid reads as artificial).
    pub position_jitter: f32,
    /// Seed of the field's random generator. Same seed → same field, bit for bit.
    pub seed: u64,
    /// Ground under the field.
    pub terrain: TerrainParams,
    /// `[field.maps]`: where grass grows, how tall, what tint (grey images;
    /// see [`super::maps`]). Default: none (grass everywhere).
    pub maps: super::maps::GrassMapParams,
}

impl Default for FieldParams {
    fn default() -> Self {
        Self {
            patches: [16, 16],
            cells_per_patch: 32,
            blades_per_cell: 1,
            cell_size_m: 0.1,
            segments: 4,
            blade_height_m: 0.45,
            height_jitter: 0.3,
            blade_width_m: 0.012,
            width_jitter: 0.3,
            lean_jitter_rad: 0.35,
            position_jitter: 0.8,
            seed: 1,
            terrain: TerrainParams::default(),
            maps: super::maps::GrassMapParams::default(),
        }
    }
}

impl FieldParams {
    /// Total number of blades (`u64::MAX` when that overflows: no field
    /// that large is valid, see [`MAX_BLADES`]).
    #[must_use]
    pub fn blade_count(&self) -> u64 {
        self.cell_count()
            .saturating_mul(u64::from(self.blades_per_cell))
    }

    /// Total number of cells (`u64::MAX` when that overflows).
    #[must_use]
    pub fn cell_count(&self) -> u64 {
        let cpp = u64::from(self.cells_per_patch);
        [self.patches[1].into(), cpp, cpp]
            .into_iter()
            .fold(u64::from(self.patches[0]), u64::saturating_mul)
    }

    /// Side lengths of the field (x, z), metres.
    #[must_use]
    pub fn extent_m(&self) -> [f32; 2] {
        let patch = self.cells_per_patch as f32 * self.cell_size_m;
        [
            self.patches[0] as f32 * patch,
            self.patches[1] as f32 * patch,
        ]
    }
}

/// The ground under the field. The field is centred on the origin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TerrainParams {
    /// A plane at `height_m`.
    Flat {
        /// Height of the plane, metres. Default 0.
        #[serde(default)]
        height_m: f32,
    },
    /// Smooth value noise: rolling hills.
    Noise {
        /// Peak-to-mean height, metres.
        amplitude_m: f32,
        /// Typical distance between hills, metres.
        wavelength_m: f32,
        /// Seed of the noise.
        #[serde(default)]
        seed: u64,
    },
    /// A grey-scale image stretched over the whole field: black = 0, white =
    /// `height_scale_m`. The path is relative to the scene file's folder
    /// and must stay inside it ([`crate::paths`]).
    Heightmap {
        /// Image file (PNG), relative to the scene file's folder.
        path: PathBuf,
        /// Height of a white pixel, metres.
        height_scale_m: f32,
    },
}

impl Default for TerrainParams {
    fn default() -> Self {
        Self::Flat { height_m: 0.0 }
    }
}

/// A field parameter out of range. The message names the scene key.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("field.{key} = {value}: {allowed}")]
pub struct FieldError {
    /// Key under `[field]`, e.g. `segments` or `terrain.wavelength_m`.
    pub key: &'static str,
    /// The offending value, as written.
    pub value: String,
    /// What is allowed.
    pub allowed: &'static str,
}

/// Most blades a field may have: 2^28 (268 M). Beyond, u32 indices of the
/// vertex buffers would overflow.
pub const MAX_BLADES: u64 = 1 << 28;

/// Most cells along a patch side: 2^14, so that one patch's cells (2^28)
/// fit [`MAX_BLADES`] and a `u32`.
pub const MAX_CELLS_PER_PATCH: u32 = 1 << 14;

impl FieldParams {
    /// Checks every value; the first bad one is reported.
    pub fn validate(&self) -> Result<(), FieldError> {
        let err = |key, value: String, allowed| {
            Err(FieldError {
                key,
                value,
                allowed,
            })
        };
        let pos = |x: f32| x.is_finite() && x > 0.0;
        if self.patches[0] == 0 || self.patches[1] == 0 {
            return err(
                "patches",
                format!("{:?}", self.patches),
                "both counts must be at least 1",
            );
        }
        if !(1..=MAX_CELLS_PER_PATCH).contains(&self.cells_per_patch) {
            return err(
                "cells_per_patch",
                self.cells_per_patch.to_string(),
                "must be 1..=16384 (one patch of more cells would exceed 2^28 blades)",
            );
        }
        if !(1..=64).contains(&self.blades_per_cell) {
            return err(
                "blades_per_cell",
                self.blades_per_cell.to_string(),
                "must be 1..=64",
            );
        }
        if self.blade_count() > MAX_BLADES {
            return err(
                "patches",
                format!("{:?}", self.patches),
                "the field would have more than 2^28 blades",
            );
        }
        if !pos(self.cell_size_m) {
            return err(
                "cell_size_m",
                self.cell_size_m.to_string(),
                "must be a finite number > 0",
            );
        }
        if !(1..=super::MAX_SEGMENTS as u32).contains(&self.segments) {
            return err("segments", self.segments.to_string(), "must be 1..=15");
        }
        if !pos(self.blade_height_m) {
            return err(
                "blade_height_m",
                self.blade_height_m.to_string(),
                "must be a finite number > 0",
            );
        }
        if !(0.0..1.0).contains(&self.height_jitter) {
            return err(
                "height_jitter",
                self.height_jitter.to_string(),
                "must be in [0, 1)",
            );
        }
        if !pos(self.blade_width_m) {
            return err(
                "blade_width_m",
                self.blade_width_m.to_string(),
                "must be a finite number > 0",
            );
        }
        if !(0.0..1.0).contains(&self.width_jitter) {
            return err(
                "width_jitter",
                self.width_jitter.to_string(),
                "must be in [0, 1)",
            );
        }
        if !(0.0..=1.2).contains(&self.lean_jitter_rad) {
            return err(
                "lean_jitter_rad",
                self.lean_jitter_rad.to_string(),
                "must be in [0, 1.2] radians",
            );
        }
        if !(0.0..=1.0).contains(&self.position_jitter) {
            return err(
                "position_jitter",
                self.position_jitter.to_string(),
                "must be in [0, 1]",
            );
        }
        self.maps.validate()?;
        match &self.terrain {
            TerrainParams::Flat { height_m } if !height_m.is_finite() => {
                err("terrain.height_m", height_m.to_string(), "must be finite")
            }
            TerrainParams::Noise { amplitude_m, .. }
                if !amplitude_m.is_finite() || *amplitude_m < 0.0 =>
            {
                err(
                    "terrain.amplitude_m",
                    amplitude_m.to_string(),
                    "must be a finite number >= 0",
                )
            }
            TerrainParams::Noise { wavelength_m, .. } if !pos(*wavelength_m) => err(
                "terrain.wavelength_m",
                wavelength_m.to_string(),
                "must be a finite number > 0",
            ),
            TerrainParams::Heightmap { height_scale_m, .. }
                if !height_scale_m.is_finite() || *height_scale_m < 0.0 =>
            {
                err(
                    "terrain.height_scale_m",
                    height_scale_m.to_string(),
                    "must be a finite number >= 0",
                )
            }
            _ => Ok(()),
        }
    }

    /// Bytes a simulation of this field needs at most, estimated before
    /// anything is allocated (checked against `sim.memory_limit_gib`).
    ///
    /// The worst case: one step in which every blade is under an object.
    /// Per blade (n segments, n + 1 vertices):
    /// - state, 32(n+1) + 40: current and rest vertices (16 B each), rest
    ///   length, width, tint, force (12), contact weight, owner weight and
    ///   segment mask (4 each), generation, class, track owner and
    ///   displaced flag (1 each);
    /// - one step's work, 32(n+1) + 216: two copies of the vertices of
    ///   every bent or recovering blade (the bend's work slots and the
    ///   recovery's, which are kept from step to step), the contacts of the
    ///   narrow phase (24 B, gathered from the worker threads), the index
    ///   lists (narrow-phase candidates, touched, DBG, forced, moved by
    ///   contact, displaced; the recovery's blades due, their state, the
    ///   blades staying and those stored) and the contact response's
    ///   per-vertex memos — the constant 216 fitted to the measured peaks
    ///   (below), not itemised further;
    ///
    /// per cell, 62: the neighbour table (16), LOD, billboard base, height,
    /// rest and current slope, flatness, bent flag; plus
    /// [`FIXED_OVERHEAD_BYTES`]. (Until 2026-11-25 the sum was raised by a
    /// quarter for what the allocator keeps mapped; the step's memory has
    /// fallen since, and the quarter put the estimate 25 % over the
    /// measured worst case.) The builder adds the recovery strides' clock
    /// (`SimulationBuilder::memory_estimate_bytes`).
    ///
    /// Measured (peak RSS of `trample simulate` less that of a 4-blade run,
    /// every blade hit and bent, n = 4; RELIABILITY.md, and the CLI test
    /// `memory_estimate_is_within_a_quarter_of_the_measured_peak`), release
    /// build after contact (issue 12), 2026-11-23: 65,536 blades 38.8 MiB
    /// (estimate 39.7), 262,144 blades 137.8 MiB (141.0). Before contact:
    /// 30.9 MiB (31.1), 130.5 MiB (124.4), 1,048,576 blades 509.9 MiB
    /// (497.5). Re-measured 2026-11-25 (debug build, as the CI test runs):
    /// 65,536 blades 29.7–36.1 MiB, 262,144 blades 104.9 MiB — estimates
    /// now 33.0 and 114.0 MiB (+9 to +11 %; with the quarter they were
    /// 39.8 and 141.0, −24 to −26 %, and the CI test failed). A run where a
    /// ball touches a small part of the field peaks at about half the
    /// estimate (65,536 blades: 17.5 MiB). Re-measured 2026-11-30 (one
    /// thread, release and debug builds alike): 38.0 / 157.9 / 642.1 MiB at
    /// 65,536 / 262,144 / 1,048,576 blades — 645 bytes a blade, where the
    /// formula then counted 432 (work 16(n+1) + 90) and the estimates were
    /// 14–36 % under; the work term is now 32(n+1) + 216: estimates 46.4 /
    /// 167.5 / 652.0 MiB with the strides' clock (−18 / −6 / −2 %).
    ///
    /// Every blade is counted as growing; see
    /// [`FieldParams::memory_estimate_bytes_for`] for a field whose grass
    /// maps leave blades out.
    #[must_use]
    pub fn memory_estimate_bytes(&self) -> u64 {
        self.memory_estimate_bytes_for(self.blade_count())
    }

    /// [`FieldParams::memory_estimate_bytes`] of a field in which only
    /// `growing` blades grow (the rest left out by its grass maps; see
    /// [`super::generate::growing_blades`]): every blade keeps its state
    /// (absent blades keep their slots, [`super::maps`]), but only growing
    /// blades can be under an object, so only they count for one step's
    /// work. `growing` is capped at the blade count.
    ///
    /// Not itemised: the sets of blades and cells a step wrote
    /// ([`super::ChangeSet`], about 0.2 bytes a blade or cell).
    #[must_use]
    pub fn memory_estimate_bytes_for(&self, growing: u64) -> u64 {
        let verts = u64::from(self.segments) + 1;
        let (state, work) = (32 * verts + 40, 32 * verts + 216);
        let per_cell = 62;
        let exact = self.blade_count() * state
            + growing.min(self.blade_count()) * work
            + self.cell_count() * per_cell;
        exact + FIXED_OVERHEAD_BYTES
    }
}

/// What a run takes beyond its per-blade and per-cell terms in
/// [`FieldParams::memory_estimate_bytes`], bytes: 6 MiB, the offset of a line
/// through the measured peaks at 65,536 and 262,144 blades (the worker
/// threads' stacks and the allocator's arenas, which a 4-blade run does not
/// touch).
pub const FIXED_OVERHEAD_BYTES: u64 = 6 << 20;
