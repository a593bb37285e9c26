//! The colours of the classes debug view (`--debug-view classes`, a
//! contract: untouched green, DBG red, PBG blue, billboards yellow, ground
//! grey), packed as the shaders read them.

use glam::Vec3;
use trample::Simulation;
use trample::force::propagation::NO_GENERATION;
use trample::step::BladeClass;

/// Packs a linear colour as WGSL `unpack4x8unorm` reads it (alpha 255, so never 0).
pub(crate) fn pack(c: Vec3) -> u32 {
    let b = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u32;
    b(c.x) | (b(c.y) << 8) | (b(c.z) << 16) | (255 << 24)
}

/// Classes view: DBG this step.
pub(crate) const DBG_NOW: Vec3 = Vec3::new(1.0, 0.03, 0.02);
/// Classes view: PBG this step at generation 1, fading by [`PBG_FADE`] a
/// generation (down to 30 %).
pub(crate) const PBG_NOW: Vec3 = Vec3::new(0.05, 0.35, 1.0);
/// Classes view: how much darker each PBG generation is.
pub(crate) const PBG_FADE: f32 = 0.1;
/// Classes view: DBG at an earlier step.
pub(crate) const DBG_EARLIER: Vec3 = Vec3::new(0.35, 0.02, 0.02);
/// Classes view: PBG at an earlier step.
pub(crate) const PBG_EARLIER: Vec3 = Vec3::new(0.02, 0.06, 0.35);
/// Classes view: untouched blades (green, a contract).
pub(crate) const UNTOUCHED: Vec3 = Vec3::new(0.08, 0.45, 0.06);
/// Classes view: billboards (yellow, a contract).
pub(crate) const BILLBOARD_DEBUG: Vec3 = Vec3::new(0.9, 0.75, 0.05);

/// Debug colour of blade `b` for [`crate::DebugView::Classes`] (packed).
pub(crate) fn class_colour(sim: &Simulation, b: usize) -> u32 {
    let g = sim.generation[b];
    let c = if g == 0 {
        DBG_NOW
    } else if g != NO_GENERATION {
        PBG_NOW * (1.0 - PBG_FADE * f32::from(g - 1)).max(0.3)
    } else if sim.class[b] == BladeClass::Direct {
        DBG_EARLIER
    } else if sim.class[b] == BladeClass::Propagated {
        PBG_EARLIER
    } else {
        UNTOUCHED
    };
    pack(c)
}

/// Classes view colour of a blade drawn in the near blend band (its cell at
/// Billboard level, [`crate::RenderParams::lod_blend_m`]): an untouched one
/// is a billboard cell's (yellow, `billboard`), a touched one keeps its
/// class colour (the track); blades of Geometry-LOD cells keep `colour`.
pub(crate) fn band_colour(colour: u32, level: trample::field::Lod, billboard: u32) -> u32 {
    if level == trample::field::Lod::Billboard && colour == pack(UNTOUCHED) {
        billboard
    } else {
        colour
    }
}
