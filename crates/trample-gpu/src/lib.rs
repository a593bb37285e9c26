//! # trample-gpu — the stages of `Simulation::step` as wgpu compute
//!
//! The GPU path of DESIGN §7: the same stages as the CPU reference in
//! `trample` (which is the specification), one WGSL file per stage beside
//! the Rust file that dispatches it, and a parity test per stage. The
//! library never creates a device: every function takes a `&wgpu::Device`
//! and `&wgpu::Queue` (STYLE rule 3). Blade buffers live on the GPU in the
//! CPU's vertex-major layout ([`field::GpuField`]), so a renderer can draw
//! from them.
//!
//! ## Status (issue 4) — what is done and what is not
//!
//! | stage | status |
//! | --- | --- |
//! | poses | **CPU** (pure function of time), uploaded per sub-step for all objects in one write ([`object::GpuObjects::set_pose`]) |
//! | LOD per cell, billboards (Eq. 8), transitions (Eq. 9–13), billboard recovery | **done** ([`cells`]), whole-run parity-tested |
//! | broad phase | **done** ([`broad_phase`]): each object's rectangle of patches from the CPU's grid lookup, one thread per object and candidate patch (the CPU's SAT, twice its slack; a mark per patch lists it once), per-chunk lists, indirect dispatch of the narrow phase over the listed patches' blades; lists equal to the CPU's (`tests/broad_phase_parity.rs`) |
//! | narrow phase through the OBB tree, all levels in one dispatch | **done** ([`narrow_phase`]), parity-tested; one dispatch per chunk for all objects (the broad phase's per-patch object masks; the objects in one table, [`object::GpuObjects`]) |
//! | EqF (Eq. 2), several objects | **done**, in the narrow-phase kernel |
//! | propagation as generation passes (gather over each generation's candidates, listed by the last), bending with length preservation, recovery | **done** ([`propagation`], [`bend`], [`recovery`]), whole-run parity-tested |
//! | the whole step, one submission per sub-step | **done** ([`GpuSimulation::step`]) |
//! | the step recorded into the host's encoder | **done** ([`GpuSimulation::record_step`]; per-sub-step uploads staged in order with the passes, [`upload`]; `step` is a thin wrapper over the same loop) |
//! | a host's device | **done**: [`required_limits`] (the default limits, storage buffers per stage raised to what the stages bind, binding size raised only for fields over 128 MiB) and [`required_features`] (none); tested on a device made with exactly those (`tests/host_device.rs`); a device below them is refused with [`GpuError::Limit`] |
//! | chunking of fields over one storage binding | **done** ([`chunk`]): blade vertices in chunks of whole patches, one dispatch per chunk; the 16-byte-a-blade arrays stay whole-field (≈ 8.4 M blades on the software drivers, [`GpuError::TooLarge`] beyond); chunked = unchunked bit for bit (`tests/chunking.rs`) |
//! | terrain (flat, noise, height map) in the ground guard | **done** ([`terrain`], `guard.wgsl`): the core's `Terrain::height_at` over a table of the height map or of the noise lattice the core computes; whole-run parity on noise and height-map terrain (`tests/step_parity.rs`) |
//! | `--backend auto\|cpu\|gpu` on `simulate`, `run`, `collide` | **done** (in `trample-cli`) |
//! | the renderer draws straight from the GPU buffers | **done**: [`draw_lists`] builds the blade and billboard instance lists and indirect draws on the GPU; `trample-render`'s `Renderer::encode_gpu` draws each chunk's `pos`; frames identical to the CPU path's (`trample-render/tests/gpu_draw.rs`) |
//! | per-stage GPU times in `summary.json` | **done**: profiling mode ([`GpuSimulation::set_profiling`], [`profile`]) with timestamp queries read back once per step on a device with [`TIMESTAMP_FEATURES`] (lavapipe and llvmpipe/GL both have them through wgpu 29), else submit-and-wait per stage; `stage_timing` in `summary.json` says which; tested on both drivers |
//! | device loss / out of memory | caught by the CLI (uncaptured-error and device-lost callbacks), `auto` falls back to the CPU; not provoked in a test |
//! | on a real GPU | **measured** on an NVIDIA H200 through Vulkan (BENCHMARKS.md, "Session 16"; `scripts/real_gpu_bench.sh`, `scripts/real_gpu_stages.sh`): the default scene 2.8–3.0 ms a step waited for, the 128-object herd over 16.8 M blades 10.1 ms; not yet DESIGN §10's targets (1000 fps with a 1080p frame, 2 ms for the herd) |
//!
//! Parity tests (`tests/`): chunked against unchunked (bit for bit), narrow phase + EqF (hit flags identical at
//! precisions 1–7 on sphere, box, capsule, knot), propagation (generations
//! identical), bending + recovery, and whole runs (300 frames: vertices
//! within 1e-3 m, measured 1.3e-5 m on llvmpipe through GL and 1.0e-5 m on
//! lavapipe; classes, DBG/PBG counts and levels identical on both). CI
//! runs them on both Mesa drivers (`.ci/run`: GL, then Vulkan with only
//! lavapipe offered; `TRAMPLE_TEST_ADAPTER` makes a test on another
//! adapter fail, and no adapter fails them too).
//!
//! Lavapipe (Mesa 22.3) folds the uniform values that decide a branch or a
//! loop bound into a shader and compiles it again at every dispatch, with
//! no cache of the variants: a kernel whose branches read its uniform costs
//! seconds a dispatch there (the narrow phase did: 3–13 s, against ≈ 10 ms
//! for the dispatch itself). Read such values through a copy the compiler
//! cannot see as uniform (see `narrow_phase.wgsl`); `examples/stage_times.rs`
//! with `MESA_SHADER_CACHE_DISABLE=true` shows a recompiling stage.

pub mod active_list;
pub mod active_patches;
pub mod bend;
pub mod broad_phase;
pub mod cells;
pub mod chunk;
pub mod contact;
pub mod draw_lists;
pub mod error;
pub mod field;
mod kernel;
pub mod limits;
mod lod_settle;
pub mod narrow_phase;
pub mod object;
pub mod profile;
pub mod propagation;
pub mod query;
pub mod readback;
pub mod recovery;
pub mod simulation;
pub mod step_params;
pub mod terrain;
pub mod track_owners;
pub mod upload;

pub use chunk::{GpuChunk, GpuChunkParams};
pub use error::GpuError;
pub use field::{GpuField, GpuForce};
pub use kernel::bind_groups_made;
pub use limits::{required_features, required_limits};
pub use narrow_phase::NarrowPhase;
pub use object::{GpuNode, GpuObjectParams, GpuObjects, TableLayout};
pub use profile::{StageTiming, TIMESTAMP_FEATURES};
pub use simulation::GpuSimulation;
pub use step_params::{GpuCounters, GpuStepParams};
/// The wgpu this crate is built against (the workspace pins one major version).
pub use wgpu;

/// `blade.wgsl`: step parameters, counters and length preservation, shared
/// by the step stages (prepended to their sources; not a stage itself).
pub const BLADE_WGSL: &str = include_str!("blade.wgsl");

/// `chunk.wgsl`: the chunk of patches a dispatch runs over, shared by the
/// stages that touch blade vertices (prepended; not a stage itself).
pub const CHUNK_WGSL: &str = include_str!("chunk.wgsl");

/// `guard.wgsl`: the terrain's height, the ground guard and length
/// preservation, shared by bending, recovery and the per-cell stages
/// (prepended; not a stage itself).
pub const GUARD_WGSL: &str = include_str!("guard.wgsl");

/// `billboard.wgsl`: a billboard's top edge above the ground guard, shared
/// by the per-cell stages and the draw lists (prepended; not a stage itself).
pub const BILLBOARD_WGSL: &str = include_str!("billboard.wgsl");

/// `segment_obb.wgsl`: the segment–OBB test, shared by the narrow phase and
/// the billboards (prepended; not a stage itself).
pub const SEGMENT_OBB_WGSL: &str = include_str!("segment_obb.wgsl");

/// `object.wgsl`: one object's tree, pose and mesh queries (inside test,
/// closest point, contact test), shared by the narrow phase and the
/// contact response (prepended; not a stage itself).
pub const OBJECT_WGSL: &str = include_str!("object.wgsl");

/// `cell.wgsl`: the cell state's bits, shared by the per-cell stages
/// (prepended; not a stage itself).
pub const CELL_WGSL: &str = include_str!("cell.wgsl");

/// Every WGSL stage of the crate as compiled, by file name (for the naga
/// validation test). `blade.wgsl` is part of each step stage.
#[must_use]
pub fn shader_sources() -> Vec<(&'static str, String)> {
    vec![
        ("broad_phase.wgsl", broad_phase::source()),
        ("active_patches.wgsl", active_patches::source()),
        ("active_list.wgsl", active_list::source()),
        ("draw_lists.wgsl", draw_lists::source()),
        ("narrow_phase.wgsl", narrow_phase::source()),
        ("contact.wgsl", contact::source()),
        ("classify.wgsl", cells::source(cells::Stage::Classify)),
        ("billboards.wgsl", cells::source(cells::Stage::Billboards)),
        ("transitions.wgsl", cells::source(cells::Stage::Transitions)),
        ("slopes.wgsl", cells::source(cells::Stage::Slopes)),
        ("follow.wgsl", cells::source(cells::Stage::Follow)),
        ("propagation.wgsl", propagation::source()),
        ("bend.wgsl", bend::source()),
        ("recovery.wgsl", recovery::source()),
        ("track_owners.wgsl", track_owners::source()),
    ]
}

/// The value of `const NAME: f32 = …;` in `wgsl` (for the tests that check
/// a shader's constants against the CPU's, bit for bit).
#[cfg(test)]
pub(crate) fn wgsl_f32_const(wgsl: &str, name: &str) -> f32 {
    let at = wgsl
        .find(&format!("const {name}: f32 = "))
        .unwrap_or_else(|| panic!("no const {name}"));
    let rest = &wgsl[at..];
    let text = rest[rest.find('=').unwrap() + 1..rest.find(';').unwrap()].trim();
    text.parse()
        .unwrap_or_else(|e| panic!("{name} = {text}: {e}"))
}
