//! The egui panel: every live simulation parameter, the settings applied at
//! the next reset, the camera and debug view, and the stats of the frame.

use crate::app::{App, MAX_BLADES_PER_CELL, MAX_PRECISION, ShapeChoice};
use crate::backend::BackendKind;
use crate::camera::CameraMode;
use egui::{RichText, Slider};
use trample_render::DebugView;

/// What the window measured for the panel's stats.
#[derive(Clone, Debug, Default)]
pub struct FrameStats {
    /// Wall time of a frame, milliseconds (smoothed).
    pub frame_ms: f64,
    /// Geometric blades drawn in the last frame.
    pub blades_drawn: usize,
    /// Billboards drawn in the last frame.
    pub billboards_drawn: usize,
    /// The last frame was drawn from the GPU path's buffers (its counts of
    /// blades and billboards stay on the GPU).
    pub drawn_on_gpu: bool,
    /// The adapter: name, backend, device type.
    pub adapter: String,
}

/// Tooltip of the wind controls.
const WIND: &str = "Wind is drawn, not simulated (DESIGN §6): it bends blades and \
                    billboards in the vertex stage; the interaction state is untouched.";
/// Tooltip of the backend choice.
const BACKEND: &str = "CPU: the reference path (rayon). GPU: every stage as wgpu compute \
                       on the window's device, drawn straight from its buffers. \
                       The field carries over both ways; a scene the GPU path refuses \
                       (a field too large for the device) stays on the CPU.";
/// Tooltip of the GPU choice without a device.
const NO_DEVICE: &str = "no GPU device was lent to the viewer";

/// Draws the panel on the left of `ui` (the root ui of the frame).
pub fn show(ui: &mut egui::Ui, app: &mut App, stats: &FrameStats) {
    // Set again below while the per-stage times are on screen.
    app.stage_times = false;
    if !app.show_panel {
        return;
    }
    egui::Panel::left("trample")
        .default_size(230.0)
        .resizable(false)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| contents(ui, app, stats));
        });
}

fn contents(ui: &mut egui::Ui, app: &mut App, stats: &FrameStats) {
    ui.heading("trample");
    ui.horizontal(|ui| {
        if ui
            .button(if app.paused { "run" } else { "pause" })
            .clicked()
        {
            app.paused = !app.paused;
        }
        if ui.button("step").clicked() {
            app.act(crate::input::Action::SingleStep);
        }
        if ui.button("reset field").clicked() {
            app.act(crate::input::Action::ResetField);
        }
        if ui
            .button("restart")
            .on_hover_text("objects start their paths again")
            .clicked()
        {
            app.restart_paths();
        }
    });
    let mut driving = app.driving;
    if ui
        .checkbox(&mut driving, "drive the first object (arrows)")
        .changed()
    {
        app.set_driving(driving);
    }
    ui.horizontal(|ui| {
        ui.label("camera");
        for mode in [CameraMode::Orbit, CameraMode::Fly, CameraMode::Scene] {
            ui.radio_value(&mut app.camera_mode, mode, mode.name());
        }
    });
    ui.horizontal(|ui| {
        ui.label("view");
        ui.radio_value(&mut app.debug, DebugView::None, "shaded");
        ui.radio_value(&mut app.debug, DebugView::Classes, "classes")
            .on_hover_text("DBG red, PBG blue by generation, billboards yellow");
        ui.radio_value(&mut app.debug, DebugView::Obb, "OBB nodes")
            .on_hover_text("the OBB-tree nodes at the current precision");
        ui.radio_value(&mut app.debug, DebugView::Patches, "patches")
            .on_hover_text("the patch grid");
    });
    if ui.button("screenshot (P)").clicked() {
        app.screenshot_requested = true;
    }

    egui::CollapsingHeader::new("simulation")
        .default_open(true)
        .show(ui, |ui| parameters(ui, app));
    egui::CollapsingHeader::new("next reset")
        .default_open(false)
        .show(ui, |ui| rebuild(ui, app));
    egui::CollapsingHeader::new("stats")
        .default_open(true)
        .show(ui, |ui| statistics(ui, app, stats));
    egui::CollapsingHeader::new("keys")
        .default_open(false)
        .show(ui, |ui| {
            ui.label(
                "arrows drive · G drive/path · WASD QE fly (Shift fast) · mouse drag turn · \
                 wheel zoom · C camera · Space pause · N step · R reset · T restart path · \
                 [ ] precision · V debug view · P screenshot · H panel · Esc quit",
            );
        });
    if !app.message.is_empty() {
        ui.separator();
        ui.label(&app.message);
    }
}

/// What the recovery stride does (`SimParams::recovery_stride_m`).
const STRIDE: &str = "slow blades are relaxed only every few frames, about this far at a time \
(0: every recovering blade every frame)";

fn parameters(ui: &mut egui::Ui, app: &mut App) {
    let p = &mut app.sim_mut().params;
    ui.add(Slider::new(&mut p.precision, 1..=MAX_PRECISION).text("precision"))
        .on_hover_text("depth of the OBB tree the collision test goes down to (root = 1)");
    ui.add(Slider::new(&mut p.att, 0.0..=1.0).text("att"))
        .on_hover_text("decay of propagation per generation (Eq. 4)");
    ui.add(
        Slider::new(&mut p.threshold, 0.01..=2.0)
            .logarithmic(true)
            .text("threshold L, m/s"),
    );
    ui.add(Slider::new(&mut p.weight_a, 0.1..=5.0).text("weight a"))
        .on_hover_text("P(x) = a·sqrt(1 + x²/b²) − a (Eq. 7)");
    ui.add(Slider::new(&mut p.weight_b, 0.1..=10.0).text("weight b"));
    let mut lasting = p.recovery_s.is_infinite();
    if ui
        .checkbox(&mut lasting, "lasting track (no recovery)")
        .changed()
    {
        p.recovery_s = if lasting { f32::INFINITY } else { 3.0 };
    }
    if !lasting {
        ui.add(
            Slider::new(&mut p.recovery_s, 0.2..=60.0)
                .logarithmic(true)
                .text("recovery τ, s"),
        );
        let mut stride_mm = p.recovery_stride_m * 1e3;
        if ui
            .add(Slider::new(&mut stride_mm, 0.0..=5.0).text("recovery stride, mm"))
            .on_hover_text(STRIDE)
            .changed()
        {
            p.recovery_stride_m = stride_mm * 1e-3;
        }
    }
    ui.add(Slider::new(&mut p.trail, 0.0..=5.0).text("trail"));
    let lod = &mut app.sim_mut().lod;
    ui.add(Slider::new(&mut lod.geometry_m, 1.0..=60.0).text("blades up to, m"));
    let low = lod.geometry_m + 0.5;
    lod.billboard_m = lod.billboard_m.max(low);
    ui.add(Slider::new(&mut lod.billboard_m, low..=200.0).text("billboards up to, m"));

    let wind = &mut app.sim_mut().wind;
    ui.add(Slider::new(&mut wind.direction_deg, 0.0..=360.0).text("wind direction, °"))
        .on_hover_text(WIND);
    ui.add(Slider::new(&mut wind.strength_m, 0.0..=0.5).text("wind lean, m"))
        .on_hover_text(WIND);
    ui.add(Slider::new(&mut wind.gust_m, 0.0..=0.5).text("gusts, m"))
        .on_hover_text(WIND);
    ui.add(
        Slider::new(&mut wind.gust_period_s, 0.5..=10.0)
            .text("gust period, s")
            .logarithmic(true),
    )
    .on_hover_text(WIND);
    ui.horizontal(|ui| {
        ui.label("backend").on_hover_text(BACKEND);
        let now = app.backend().kind();
        let mut wanted = now;
        ui.radio_value(&mut wanted, BackendKind::Cpu, BackendKind::Cpu.name())
            .on_hover_text(BACKEND);
        let gpu = BackendKind::Gpu;
        let why_not = match (app.gpu_device(), app.gpu_failed()) {
            (None, _) => Some(NO_DEVICE.to_string()),
            (Some(_), Some(failed)) => {
                Some(format!("the GPU path failed on this device: {failed}"))
            }
            (Some(_), None) => None,
        };
        if ui
            .add_enabled(
                why_not.is_none(),
                egui::RadioButton::new(now == gpu, gpu.name()),
            )
            .on_hover_text(BACKEND)
            .on_disabled_hover_text(why_not.unwrap_or_default())
            .clicked()
        {
            wanted = gpu;
        }
        if wanted != now {
            // The outcome (or why not) goes to the panel's message.
            let _ = app.set_backend(wanted);
        }
    });
}

fn rebuild(ui: &mut egui::Ui, app: &mut App) {
    ui.add(
        Slider::new(&mut app.pending.blades_per_cell, 1..=MAX_BLADES_PER_CELL)
            .text("blades per cell"),
    );
    egui::ComboBox::from_label("shape")
        .selected_text(app.pending.shape.name())
        .show_ui(ui, |ui| {
            for s in ShapeChoice::ALL {
                ui.selectable_value(&mut app.pending.shape, s, s.name());
            }
        });
    if app.pending.shape == ShapeChoice::MeshFile {
        ui.horizontal(|ui| {
            ui.label("mesh");
            ui.text_edit_singleline(&mut app.pending.mesh_path)
                .on_hover_text(".obj, .gltf or .glb, relative to the scene's folder");
        });
    }
    if ui.button("reset field now (R)").clicked() {
        app.act(crate::input::Action::ResetField);
    }
}

fn statistics(ui: &mut egui::Ui, app: &mut App, stats: &FrameStats) {
    let fps = if stats.frame_ms > 0.0 {
        1000.0 / stats.frame_ms
    } else {
        0.0
    };
    ui.label(format!("frame {:.1} ms ({fps:.1} fps)", stats.frame_ms));
    let on_gpu = app.backend().adapter().map(str::to_owned);
    ui.label(match &on_gpu {
        Some(adapter) => format!("simulating on the GPU: {adapter}"),
        None => format!(
            "simulating on the CPU ({} threads)",
            std::thread::available_parallelism().map_or(1, usize::from)
        ),
    });
    let sim = app.sim();
    let t = &sim.timings;
    let gpu = app.backend().gpu_stats();
    let step = match gpu.map(|g| g.profiled) {
        None => "step",
        Some(true) => "GPU step (stages timed one by one)",
        Some(false) => "GPU step recorded",
    };
    ui.label(format!(
        "{step} {:.2} ms, t = {:.2} s, frame {}",
        t.total_ms, sim.time, sim.frame
    ));
    if let Some(g) = gpu {
        // Without per-stage timing the step only records: the read-back
        // also waits for the GPU to finish it.
        let wait = if g.profiled {
            ""
        } else {
            " (with the wait for the step)"
        };
        ui.label(format!(
            "counters read back {:.2} ms{wait}; drawn from the GPU buffers",
            g.readback_ms
        ));
    }
    let stages = egui::CollapsingHeader::new("time per stage")
        .default_open(true)
        .show(ui, |ui| {
            egui::Grid::new("stages").num_columns(2).show(ui, |ui| {
                for (name, ms) in t.stages() {
                    ui.label(name);
                    ui.label(format!("{ms:.3} ms"));
                    ui.end_row();
                }
            });
        });
    let shown = stages.body_returned.is_some();
    ui.label(format!(
        "DBG {} · PBG {} · generations {}",
        t.dbg_blades, t.pbg_blades, t.generations
    ));
    ui.label(format!(
        "cells: blades {} · billboards {} · texture {}",
        t.lod.geometry, t.lod.billboard, t.lod.texture
    ));
    if stats.drawn_on_gpu {
        ui.label(format!(
            "drawn on the GPU from its lists; {} patches visible",
            t.visible_patches
        ));
    } else {
        ui.label(format!(
            "drawn: {} blades, {} billboards; {} patches visible",
            stats.blades_drawn, stats.billboards_drawn, t.visible_patches
        ));
    }
    ui.label(format!(
        "field: {} blades, camera {}",
        sim.field.blades.count,
        app.camera_mode.name()
    ));
    ui.label(RichText::new(&stats.adapter).small());
    // The GPU path times its stages only while they are on screen.
    app.stage_times = shown;
}
