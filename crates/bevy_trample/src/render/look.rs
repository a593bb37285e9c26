//! How the meadow is drawn between and within its levels of detail:
//! blend bands (no ring round the camera where blades give way to
//! billboards and billboards to the ground) and render density (more
//! blades drawn near the camera than simulated). The same settings, with
//! the same defaults, as trample-render's `RenderParams` (and its ambient
//! occlusion of grass, which makes a track read); the shader
//! functions are the core's (`trample::blade_shape`), so both renderers
//! draw the bands and copies alike.

use bevy::prelude::*;

/// Most drawn copies per simulated blade ([`GrassLook::near_density`]).
pub const MAX_NEAR_DENSITY: u32 = 64;

/// The meadow's look (a resource; the plugin inserts the default when the
/// app has none). Change it at any time: the next frame draws with it.
///
/// ```no_run
/// # use bevy::prelude::*;
/// # use bevy_trample::GrassLook;
/// # let mut app = App::new();
/// // The paper's hard switch between levels, one drawn blade a simulated one.
/// app.insert_resource(GrassLook { near_density: 1, ..GrassLook::without_blend_bands() });
/// ```
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct GrassLook {
    /// Width of the blend band past `lod.geometry_m`, metres (default 4):
    /// there the blades of Billboard-LOD cells are drawn too, a growing
    /// share of them shrinking away with distance, while the billboards
    /// fade in (a dithered share of their strands), so the grass changes
    /// level without a ring round the camera. 0 turns the band off (the
    /// paper's hard switch). At most half the billboard band
    /// ([`trample::field::lod::LodParams::blend_bands`]).
    pub lod_blend_m: f32,
    /// Width of the blend band before `lod.billboard_m`, metres (default
    /// 6): the billboards thin out over the ground, which shows alone past
    /// `lod.billboard_m`. 0 turns it off. At most half the billboard band.
    pub texture_blend_m: f32,
    /// Near the camera each simulated blade is drawn this many times
    /// (default 6; 1 draws the simulated blades alone, 0 counts as 1, at
    /// most [`MAX_NEAR_DENSITY`], as `trample run --near-density`): the
    /// copies are scattered within the blade spacing, follow their
    /// blade's bent shape (the track, the wind), each with its own facing,
    /// height and tint. The simulation and its cost are unchanged; drawing
    /// costs up to this many times the near blades' vertices. The paper's
    /// one blade per 10 cm cell reads as bare ground from a few metres.
    pub near_density: u32,
    /// How far from the camera the copies reach, metres (default 8; at
    /// most 0.6 · `lod.geometry_m`, so the grass is back to the simulated
    /// density well before cells change level): copy j of `near_density`
    /// is drawn to `reach · (1 − (j − 1) / near_density)` and shrinks to
    /// its root over the last fifth of that.
    pub near_density_m: f32,
    /// Strength of the grass's ambient occlusion (default 1; 0 turns it
    /// off): blades darken towards their roots and flattened blades as a
    /// whole (to 70 % of the light when lying), so a track reads even in
    /// the shade; billboards along their height and as their cell lies
    /// flatter. Shared with trample-render (`grass_ao_at` of
    /// `trample::blade_shape`); Bevy's own SSAO, if the app turns it on,
    /// darkens on top of it.
    pub ambient_occlusion: f32,
    /// How much a flattened cell darkens and browns the ground under it,
    /// in [0, 1] (default 0.8, trample-render's `track_darkening`; 0
    /// turns it off): the track shows on the ground at every level of
    /// detail, past the billboards too.
    pub track_darkening: f32,
    /// Whether the grass casts shadows (default false): the drawn blades
    /// (Geometry-LOD cells and the near blend band's) and billboards are
    /// drawn again into the shadow maps of every light that casts shadows
    /// (Bevy's `Shadow` phase: each cascade of a directional light, each
    /// face of a point light), so a blade shades the ground and the blades
    /// behind it, and a track reads by its missing shadows. A billboard
    /// casts the shadow of its strands (the cut-out of its colour pass,
    /// not its whole quads), so the shade goes on past the blades without
    /// a bright ring where the levels of detail meet. Costs the blades'
    /// vertices and the billboards once more for each shadow view.
    pub cast_shadows: bool,
}

impl Default for GrassLook {
    fn default() -> Self {
        Self {
            lod_blend_m: 4.0,
            texture_blend_m: 6.0,
            near_density: 6,
            near_density_m: 8.0,
            ambient_occlusion: 1.0,
            track_darkening: 0.8,
            cast_shadows: false,
        }
    }
}

impl GrassLook {
    /// The default look with both blend bands off: the paper's hard
    /// switch between levels of detail.
    #[must_use]
    pub fn without_blend_bands() -> Self {
        Self {
            lod_blend_m: 0.0,
            texture_blend_m: 0.0,
            ..Self::default()
        }
    }

    /// Drawn copies per simulated blade: `near_density` within
    /// 1..=[`MAX_NEAR_DENSITY`].
    #[must_use]
    pub fn copies(&self) -> u32 {
        self.near_density.clamp(1, MAX_NEAR_DENSITY)
    }

    /// The ambient occlusion drawn: `ambient_occlusion`, 0 for a negative
    /// or non-finite value (none).
    #[must_use]
    pub fn ambient_occlusion_in_use(&self) -> f32 {
        if self.ambient_occlusion.is_finite() {
            self.ambient_occlusion.max(0.0)
        } else {
            0.0
        }
    }

    /// The track's darkening drawn: `track_darkening` within [0, 1], 0 for
    /// a non-finite value (so that a NaN setting compares equal to itself
    /// and the ground is not redrawn every frame).
    #[must_use]
    pub fn track_darkening_in_use(&self) -> f32 {
        if self.track_darkening.is_finite() {
            self.track_darkening.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// How far the copies reach, metres: `near_density_m`, 0 for a
    /// negative or non-finite value (no copies).
    #[must_use]
    pub fn copies_reach_m(&self) -> f32 {
        if self.near_density_m.is_finite() {
            self.near_density_m.max(0.0)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_settings_are_drawn_as_none_and_compare_equal_to_themselves() {
        let bad = GrassLook {
            ambient_occlusion: f32::NAN,
            track_darkening: f32::NAN,
            near_density_m: f32::INFINITY,
            ..GrassLook::default()
        };
        assert_eq!(bad.ambient_occlusion_in_use(), 0.0);
        assert_eq!(bad.track_darkening_in_use(), 0.0);
        assert_eq!(bad.copies_reach_m(), 0.0);
        let big = GrassLook {
            track_darkening: 3.0,
            ambient_occlusion: -1.0,
            ..GrassLook::default()
        };
        assert_eq!(big.track_darkening_in_use(), 1.0);
        assert_eq!(big.ambient_occlusion_in_use(), 0.0);
        let d = GrassLook::default();
        assert_eq!(
            (d.track_darkening_in_use(), d.ambient_occlusion_in_use()),
            (0.8, 1.0)
        );
    }
}
