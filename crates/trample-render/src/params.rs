//! Render settings: what the frame shows (debug views), light, fog and
//! the optional layers around the grass.

use glam::Vec3;

/// What the frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DebugView {
    /// The shaded scene.
    #[default]
    None,
    /// Colour by class: DBG red, PBG blue (darker each generation), blades
    /// touched in earlier frames dark red / dark blue, untouched green,
    /// billboards yellow, Texture-LOD ground grey.
    Classes,
    /// The shaded scene with each object's OBB-tree nodes at the current
    /// precision drawn over it (yellow; orange: leaves above the precision).
    Obb,
    /// The shaded scene with the patch grid over it (patch borders white,
    /// cell lines grey on small grids).
    Patches,
}

impl DebugView {
    /// Every view, in the order a viewer cycles through them.
    pub const ALL: [DebugView; 4] = [Self::None, Self::Classes, Self::Obb, Self::Patches];

    /// The view after this one in [`DebugView::ALL`], wrapping round.
    #[must_use]
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|&v| v == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }
}

impl std::str::FromStr for DebugView {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Self::None),
            "classes" => Ok(Self::Classes),
            "obb" => Ok(Self::Obb),
            "patches" => Ok(Self::Patches),
            _ => Err(format!(
                "unknown debug view {s:?}: expected none, classes, obb or patches"
            )),
        }
    }
}

/// Render settings (`RenderParams`, STYLE rule 4). `width`, `height` and
/// `samples` size the offscreen frame of [`crate::Renderer`]; a
/// [`crate::FieldRenderer`] drawing into a host's pass takes those from the
/// host ([`crate::TargetFormat`], [`crate::FrameCamera`]) and uses the rest.
#[derive(Clone, Copy, Debug)]
pub struct RenderParams {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// MSAA samples: 4 by default; ask the adapter first
    /// ([`crate::headless::supported_msaa`]), 1 where it cannot.
    pub samples: u32,
    /// Debug view.
    pub debug: DebugView,
    /// Direction towards the sun (normalised on use). Default: high behind
    /// the default camera's left shoulder, so the blades facing it are lit.
    pub sun_dir: Vec3,
    /// Fog starts at this distance, metres (default 25: past the billboards' near edge).
    pub fog_start_m: f32,
    /// Fog is complete at this distance, metres (default 140).
    pub fog_end_m: f32,
    /// How much a fully flattened cell darkens (and browns) the ground
    /// under it, in [0, 1] (default 0.8; the effect grows with the square
    /// root of the flatness): the track at every level of
    /// detail, drawn from `Cells::flatness` — cells at ground-texture
    /// level show where an object went. Faded in across the billboard band
    /// (`lod.geometry_m` to `lod.billboard_m`): nearer, the blades and
    /// billboards show the track themselves. 0 turns it off.
    pub track_darkening: f32,
    /// Which of the scene's surroundings are drawn besides the grass
    /// (default: all; a host drawing its own world turns them off).
    pub layers: Layers,
    /// Render density beyond the simulation's (issue 15 item 2): near the
    /// camera each simulated blade is drawn this many times (≥ 1; 1 draws
    /// the simulated blades alone), the copies scattered within the blade
    /// spacing around it, following its deformation (its bent shape,
    /// moved), each with its own facing, height and tint. The simulation,
    /// its dumps and its cost are unchanged; drawing costs up to this many
    /// times the blades' vertices. Default 6: the paper's one blade per
    /// 10 cm cell reads as bare ground from a few metres.
    pub near_density: u32,
    /// How far from the eye the copies reach, metres (default 8; at most
    /// 0.6 · `lod.geometry_m`, so that the grass is back to the simulated
    /// density well before cells change level): copy j of `near_density`
    /// is drawn to `reach · (1 − (j − 1) / near_density)` and shrinks to
    /// its root over the last fifth of that, so the grass thins smoothly.
    pub near_density_m: f32,
    /// Width of the blend band past `lod.geometry_m`, metres (issue 15
    /// item 1; default 4): there the blades of Billboard-LOD cells are
    /// drawn too, a growing share of them shrinking away with distance,
    /// while the billboards fade in (a dithered share of each), so the
    /// drawn grass changes level without a ring round the camera. 0 turns
    /// the band off (the paper's hard switch). At most half the billboard
    /// band (`lod.billboard_m − lod.geometry_m`).
    pub lod_blend_m: f32,
    /// Width of the blend band before `lod.billboard_m`, metres (default
    /// 6): the billboards thin out over the ground texture, which shows
    /// alone past `lod.billboard_m`. 0 turns it off. At most half the
    /// billboard band.
    pub texture_blend_m: f32,
    /// How dark the bodies' shadows are on the grass, the ground and the
    /// bodies, in [0, 1] (issue 15 item 3; default 1: in a shadow only the
    /// sky's ambient light is left, the sun's direct light is gone). 0
    /// turns shadows off: no shadow pass, no shadow-map lookups. The sun's
    /// shadow map ([`crate::shadows`]) holds the bodies only: they shadow
    /// the grass; grass does not cast (its own darkening is
    /// [`RenderParams::ambient_occlusion`]). Cost on llvmpipe, default
    /// scene at 1280×720: about +8 % render time (the blades and billboards
    /// look the map up per vertex); about as much with shadows off (a
    /// software rasteriser runs the lookup under a false branch too).
    pub shadow_strength: f32,
    /// Side of the shadow map, texels (default 2048, `Depth32Float`: 16
    /// MiB; with the default `shadow_m` a texel is 4 cm, well under a
    /// ball's size; the pass draws the bodies alone, so its cost hardly
    /// depends on this). Clamped to the adapter's texture limit.
    pub shadow_map_size: u32,
    /// Half the side of the square of ground around the eye that the
    /// shadow map covers, metres (default 40: past the fog's start and the
    /// default billboard distance, 30; a body farther than this from the
    /// eye casts no shadow). Larger reaches farther with coarser shadows.
    pub shadow_m: f32,
    /// Strength of the grass's ambient occlusion (default 1; 0 turns it
    /// off): blades darken towards their roots (to 45 % at the root of a
    /// standing blade) and flattened blades darken as a whole (to 70 % of
    /// the light when lying), so a track reads even in the shade; the
    /// billboards the same along their height and with their slope, and
    /// the ground among geometric blades as under their roots. A stand-in
    /// for the grass's shadows on itself (not in the shadow map), at no
    /// cost.
    pub ambient_occlusion: f32,
}

/// What a [`crate::FieldRenderer`] draws besides the grass (blades and
/// billboards, always drawn). A host with its own sky, ground or meshes
/// turns the matching layer off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layers {
    /// The sky gradient and sun disc, at the far plane: fills only the
    /// pixels nothing else was drawn on (depth test at 1.0). Default on.
    pub sky: bool,
    /// The textured ground over the field's terrain (and one field size
    /// around it): what shows between blades and at ground-texture level.
    /// Default on.
    pub terrain: bool,
    /// The simulation's bodies, flat-shaded with a checker. Default on;
    /// off for a host that draws its own meshes for them.
    pub objects: bool,
}

impl Default for Layers {
    fn default() -> Self {
        Self {
            sky: true,
            terrain: true,
            objects: true,
        }
    }
}

impl Default for RenderParams {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            samples: 4,
            debug: DebugView::None,
            sun_dir: Vec3::new(-0.35, 0.75, 0.55),
            fog_start_m: 25.0,
            fog_end_m: 140.0,
            track_darkening: 0.8,
            layers: Layers::default(),
            near_density: 6,
            near_density_m: 8.0,
            lod_blend_m: 4.0,
            texture_blend_m: 6.0,
            shadow_strength: 1.0,
            shadow_map_size: 2048,
            shadow_m: 40.0,
            ambient_occlusion: 1.0,
        }
    }
}

impl RenderParams {
    /// These settings with both blend bands off: the paper's hard switch
    /// between levels of detail ([`RenderParams::lod_blend_m`] and
    /// [`RenderParams::texture_blend_m`] at 0).
    #[must_use]
    pub fn without_blend_bands(self) -> Self {
        Self {
            lod_blend_m: 0.0,
            texture_blend_m: 0.0,
            ..self
        }
    }

    /// The blend bands in use for `lod`'s distances, metres: `[near, far]`
    /// ([`RenderParams::lod_blend_m`], [`RenderParams::texture_blend_m`]),
    /// each at most half the billboard band, 0 for a non-finite or
    /// negative setting (the core's
    /// [`trample::field::lod::LodParams::blend_bands`], which bevy_trample
    /// draws with too).
    #[must_use]
    pub fn blend_bands(&self, lod: &trample::field::lod::LodParams) -> [f32; 2] {
        lod.blend_bands(self.lod_blend_m, self.texture_blend_m)
    }
}
