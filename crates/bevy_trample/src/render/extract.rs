//! What the render world needs of the simulation each frame, copied in
//! Bevy's extract step: the blades that changed since the last frame (only
//! those are uploaded), the cells drawn as blades, the billboards, and the
//! draw parameters (counts, wind, time).

use super::look::GrassLook;
use crate::field::TrampleField;
use bevy::prelude::*;
use bevy::render::MainWorld;
use bytemuck::{Pod, Zeroable};
use std::ops::Range;
use trample::deform::billboard::billboard_top;
use trample::field::generate::GROUND_CLEARANCE_M;
use trample::field::{BladeVertex, Lod, drawn_blade_cells, drawn_cells};

/// Billboard width / cell side, as trample-render draws them: "a bit longer
/// than the cell" (DESIGN §8), so neighbouring billboards overlap.
pub const WIDTH_OVER_CELL: f32 = 1.6;

/// Per-frame draw parameters. Layout-compatible with `Params` in blades.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GrassParams {
    /// Wind: xz unit direction, y steady tip displacement (m), w gust (m).
    pub wind: [f32; 4],
    /// Gusts: x period (s), y wavelength (m).
    pub gusts: [f32; 4],
    /// x blades, y segments per blade, z blades per cell, w drawn copies
    /// per simulated blade ([`GrassLook::copies`]).
    pub counts: [u32; 4],
    /// x simulated time (s, the wind's clock), y the blade spacing (m, over
    /// which the copies scatter), z how far the copies reach (m), w the
    /// strength of the grass's ambient occlusion (≥ 0).
    pub time: [f32; 4],
    /// xyz the eye that decides the levels of detail (the simulation's:
    /// the [`crate::TrampleCamera`]'s), w 1 when the blade instances are
    /// the GPU path's list of `(blade, colour)` pairs instead of cells
    /// ([`GrassFrame::gpu`]), else 0.
    pub eye: [f32; 4],
    /// x `lod.geometry_m`, y `lod.billboard_m`, z the near blend band, w
    /// the far one (m, [`trample::field::lod::LodParams::blend_bands`]).
    pub lod: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<GrassParams>() == 96);

/// One billboard. Layout-compatible with `Billboard` in blades.wgsl (and
/// with trample-render's `BillboardInstance`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BillboardInstance {
    /// xyz base centre (m), w half width (m).
    pub base: [f32; 4],
    /// xyz base → top edge, `normalize(slope) · height` (Eq. 8) kept above
    /// the ground; w unused.
    pub top: [f32; 4],
    /// x unused, y the cell (its random seed).
    pub extra: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<BillboardInstance>() == 48);

/// The render world's copy of this frame's field.
#[derive(Resource, Default)]
pub struct GrassFrame {
    /// Blades, segments per blade, blades per cell and blades per patch
    /// (the unit the vertices are cut at into chunks,
    /// [`trample::field::plan_chunks`]); `None` before a field exists.
    pub layout: Option<[u32; 4]>,
    /// Set when every blade is in `staging` (a new field): the buffers are
    /// made anew. Also carries each blade's `[width, tint]`.
    pub full: Option<Vec<[f32; 2]>>,
    /// Runs of changed vertices: `(first vertex, vertices)` in the core's
    /// layout (vertex k of blade b at `k * blades + b`), their data one
    /// after the other in `staging`.
    pub runs: Vec<(u32, u32)>,
    /// Vertex data of `runs` (the core's layout, `[x, y, z, 0]`).
    pub staging: Vec<BladeVertex>,
    /// Cells drawn as blades: the Geometry-LOD cells and the near blend
    /// band's Billboard-LOD cells ([`drawn_blade_cells`]), ascending (the
    /// draws cut the list at the chunks' borders).
    pub cells: Vec<u32>,
    /// Billboards drawn.
    pub billboards: Vec<BillboardInstance>,
    /// Draw parameters.
    pub params: GrassParams,
    /// Whether the blades are drawn into the lights' shadow maps
    /// ([`crate::render::look::GrassLook::cast_shadows`]).
    pub cast_shadows: bool,
    /// On the GPU path: the buffers the draws read in place of `runs`,
    /// `cells` and `billboards` (which then stay empty).
    #[cfg(feature = "gpu")]
    pub gpu: Option<crate::gpu_path::GpuDrawBuffers>,
    /// Blade runs taken this frame (scratch).
    blade_runs: Vec<Range<u32>>,
}

impl GrassFrame {
    /// Whether the draws read the GPU path's buffers this frame.
    #[must_use]
    pub fn on_gpu_path(&self) -> bool {
        #[cfg(feature = "gpu")]
        {
            self.gpu.is_some()
        }
        #[cfg(not(feature = "gpu"))]
        {
            false
        }
    }
}

/// Copies this frame's field into the render world: the vertices of the
/// blades the steps since the last frame changed (all of them for a new
/// field), the drawn cells and billboards of the camera in charge, the
/// draw parameters.
pub fn extract_grass(mut main: ResMut<MainWorld>, mut frame: ResMut<GrassFrame>) {
    let frame = &mut *frame;
    frame.runs.clear();
    frame.staging.clear();
    frame.cells.clear();
    frame.billboards.clear();
    frame.full = None;
    let look = main
        .get_resource::<GrassLook>()
        .copied()
        .unwrap_or_default();
    frame.cast_shadows = look.cast_shadows;
    let Some(mut field) = main.get_resource_mut::<TrampleField>() else {
        frame.layout = None;
        #[cfg(feature = "gpu")]
        {
            frame.gpu = None;
        }
        return;
    };
    let field = &mut *field;
    if field.wants_gpu() && field.backend() == crate::TrampleBackend::Cpu {
        // To be handed to the GPU path once the main world has Bevy's
        // device (the first frame or two): nothing drawn until then (the
        // CPU path's uploads are not made for a field the device may only
        // hold in chunks).
        frame.layout = None;
        return;
    }
    let sim = &field.sim;
    let bl = &sim.field.blades;
    let layout = &sim.field.layout;
    let shape = [
        bl.count as u32,
        bl.segments as u32,
        layout.blades_per_cell,
        layout.cells_in_patch() as u32 * layout.blades_per_cell,
    ];
    if frame.layout != Some(shape) {
        field.changes.reset();
        frame.layout = Some(shape);
    }
    frame.blade_runs.clear();
    #[cfg(feature = "gpu")]
    {
        let gpu = field.gpu_draw_buffers();
        if frame.gpu.is_some() && gpu.is_none() {
            // Back on the CPU path (another field): every blade again.
            field.changes.reset();
        }
        frame.gpu = gpu;
    }
    let on_gpu = frame.on_gpu_path();
    if field.changes.take(sim, &mut frame.blade_runs) {
        frame.full = Some(
            bl.width
                .iter()
                .zip(&bl.tint)
                .map(|(&w, &t)| [w, t])
                .collect(),
        );
    }
    if on_gpu {
        // The GPU path's buffers hold the vertices and the lists.
        frame.params = grass_params(sim, &look);
        frame.params.eye[3] = 1.0;
        return;
    }
    let count = bl.count;
    for k in 0..=bl.segments {
        for r in &frame.blade_runs {
            let first = k * count + r.start as usize;
            let end = k * count + r.end as usize;
            frame.runs.push((first as u32, r.len() as u32));
            frame.staging.extend_from_slice(&bl.pos[first..end]);
        }
    }
    // The patches inside the camera in charge (the host's, when a
    // TrampleCamera handed its view in; else the scene's camera).
    let visible: &[bool] = if sim.host_view().is_some() {
        &sim.visible
    } else {
        &[]
    };
    let cells = &sim.field.cells;
    let [near_band, _] = sim.lod.blend_bands(look.lod_blend_m, look.texture_blend_m);
    frame.cells.extend(
        drawn_blade_cells(
            layout,
            cells,
            visible,
            sim.eye(),
            sim.lod.geometry_m,
            near_band,
        )
        .map(|c| c as u32),
    );
    let half = 0.5 * WIDTH_OVER_CELL * layout.cell_size;
    frame.billboards.extend(
        drawn_cells(layout, cells, visible, Lod::Billboard).map(|c| {
            // Eq. 8's top edge with the core's ground guard.
            let top = billboard_top(
                cells.base[c],
                cells.slope[c],
                cells.height[c],
                &sim.field.terrain,
                GROUND_CLEARANCE_M,
            ) - cells.base[c];
            BillboardInstance {
                base: cells.base[c].extend(half).to_array(),
                top: top.extend(0.0).to_array(),
                extra: [0, c as u32, 0, 0],
            }
        }),
    );
    frame.params = grass_params(sim, &look);
}

/// This frame's draw parameters for `sim` drawn with `look`: the wind and
/// its clock, the counts (drawn copies at least 1), the blade spacing and
/// the copies' reach, the eye that decides the levels of detail (the
/// simulation's), the level-of-detail distances and the blend bands in use
/// ([`trample::field::lod::LodParams::blend_bands`]).
#[must_use]
pub fn grass_params(sim: &trample::Simulation, look: &GrassLook) -> GrassParams {
    let bl = &sim.field.blades;
    let layout = &sim.field.layout;
    let wind = &sim.wind;
    let d = wind.direction();
    let [near_band, far_band] = sim.lod.blend_bands(look.lod_blend_m, look.texture_blend_m);
    let spacing = layout.cell_size / (layout.blades_per_cell.max(1) as f32).sqrt();
    GrassParams {
        wind: [d.x, wind.strength_m, d.z, wind.gust_m],
        gusts: [wind.gust_period_s, wind.gust_wavelength_m, 0.0, 0.0],
        counts: [
            bl.count as u32,
            bl.segments as u32,
            layout.blades_per_cell,
            look.copies(),
        ],
        time: [
            sim.time as f32,
            spacing,
            look.copies_reach_m(),
            look.ambient_occlusion_in_use(),
        ],
        eye: sim.eye().extend(0.0).to_array(),
        lod: [sim.lod.geometry_m, sim.lod.billboard_m, near_band, far_band],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trample::scene::Scene;

    #[test]
    fn the_params_carry_the_look_the_bands_in_use_and_the_eye() {
        let sim = Scene::default_scene().unwrap().build().unwrap();
        let p = grass_params(&sim, &GrassLook::default());
        assert_eq!(p.counts[3], 6);
        assert_eq!(p.eye, sim.eye().extend(0.0).to_array());
        assert_eq!(p.lod[..2], [sim.lod.geometry_m, sim.lod.billboard_m]);
        assert_eq!(p.lod[2..], sim.lod.blend_bands(4.0, 6.0));
        assert!(p.lod[2] > 0.0 && p.lod[3] > 0.0);
        // One blade a cell of 0.1 m in the default scene: 0.1 m apart.
        let layout = &sim.field.layout;
        let spacing = layout.cell_size / (layout.blades_per_cell as f32).sqrt();
        assert_eq!(p.time[1], spacing);
        assert_eq!(p.time[2], 8.0);
        assert_eq!(p.time[3], 1.0);
        // Bad settings: clamped, never NaN in the shader.
        let bad = GrassLook {
            near_density: u32::MAX,
            near_density_m: f32::NAN,
            ..GrassLook::default()
        };
        let p = grass_params(&sim, &bad);
        assert_eq!((p.counts[3], p.time[2]), (64, 0.0));
        for (ao, want) in [(f32::NAN, 0.0), (-1.0, 0.0), (0.5, 0.5)] {
            let look = GrassLook {
                ambient_occlusion: ao,
                ..GrassLook::default()
            };
            assert_eq!(grass_params(&sim, &look).time[3], want, "{ao}");
        }
        // The paper's hard switch, and no density asked: one drawn blade.
        let hard = GrassLook {
            near_density: 0,
            ..GrassLook::without_blend_bands()
        };
        let p = grass_params(&sim, &hard);
        assert_eq!(p.counts[3], 1);
        assert_eq!(p.lod[2..], [0.0, 0.0]);
        // A band wider than the room between the levels is cut to half of it.
        let wide = GrassLook {
            lod_blend_m: 1e6,
            ..GrassLook::default()
        };
        let p = grass_params(&sim, &wide);
        assert_eq!(p.lod[2], 0.5 * (sim.lod.billboard_m - sim.lod.geometry_m));
    }
}
