//! How a blade looks when drawn, as WGSL every renderer of the field shares
//! (DESIGN §8): the strip's facing, taper and normal, the wind bend
//! ([`crate::wind::tip_offset`] is its specification), the colour
//! gradient and the billboards' axes and wind-leaned top edge. `trample-render` (wgpu 29) prepends it to its shaders;
//! `bevy_trample` (Bevy's renderer) registers it as the shader library
//! `trample::blade_shape`. The core has no GPU dependency: this is text.

/// The shared WGSL (`blade_shape.wgsl`): plain functions, no bindings.
pub const WGSL: &str = include_str!("blade_shape.wgsl");
