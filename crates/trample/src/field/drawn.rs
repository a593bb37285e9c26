//! Which cells a renderer draws at a level of detail: the cells of that
//! level in the patches the last step found inside the view frustum
//! (DESIGN §8). Geometry-LOD cells are drawn as their blades, Billboard-LOD
//! cells as billboards; a host that draws the field asks here.

use super::{FieldLayout, Lod};
use glam::Vec3;

/// Indices of the cells whose level of detail is `lod` in patches marked
/// visible (`visible[p]`; a patch past the end of `visible` counts as
/// visible, as before the first cull), ascending: patch by patch, cells
/// row-major inside a patch. Cell `c`'s blades are
/// `c * blades_per_cell .. (c + 1) * blades_per_cell`.
pub fn drawn_cells<'a>(
    layout: &'a FieldLayout,
    lods: &'a [Lod],
    visible: &'a [bool],
    lod: Lod,
) -> impl Iterator<Item = usize> + 'a {
    visible_cells(layout, visible).filter(move |&c| lods.get(c) == Some(&lod))
}

/// Every cell of the patches marked visible (`visible[p]`; a patch past
/// the end counts as visible), ascending.
fn visible_cells<'a>(
    layout: &'a FieldLayout,
    visible: &'a [bool],
) -> impl Iterator<Item = usize> + 'a {
    let per_patch = layout.cells_in_patch();
    layout
        .patch_list
        .iter()
        .enumerate()
        .filter(move |(p, _)| visible.get(*p).copied().unwrap_or(true))
        .flat_map(move |(_, patch)| {
            let first = patch.first_cell as usize;
            first..first + per_patch
        })
}

/// Indices of the cells a renderer draws as blades (DESIGN §8): the
/// Geometry-LOD cells of the visible patches ([`drawn_cells`]) and, with
/// a near blend band (`band_m` > 0, [`super::lod::LodParams::blend_bands`]),
/// the Billboard-LOD cells of those patches whose base (`bases[c]`) lies
/// nearer than `geometry_m + band_m` to `eye`: their blades are drawn too
/// and thinned out with distance as the billboards fade in, so the level
/// changes without a ring round the camera. Ascending, as [`drawn_cells`].
pub fn drawn_blade_cells<'a>(
    layout: &'a FieldLayout,
    lods: &'a [Lod],
    bases: &'a [Vec3],
    visible: &'a [bool],
    eye: Vec3,
    geometry_m: f32,
    band_m: f32,
) -> impl Iterator<Item = usize> + 'a {
    let reach = geometry_m + band_m.max(0.0);
    let in_band = move |c: usize| {
        band_m > 0.0
            && bases
                .get(c)
                .is_some_and(|b| b.distance_squared(eye) < reach * reach)
    };
    visible_cells(layout, visible).filter(move |&c| match lods.get(c) {
        Some(Lod::Geometry) => true,
        Some(Lod::Billboard) => in_band(c),
        _ => false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn drawn_cells_are_the_visible_cells_of_the_level_and_nothing_else() {
        let mut sim = Scene::default_scene().unwrap().build().unwrap();
        let layout = &sim.field.layout;
        // Hide every other patch.
        let visible: Vec<bool> = (0..layout.patch_list.len()).map(|p| p % 2 == 0).collect();
        for lod in [Lod::Geometry, Lod::Billboard, Lod::Texture] {
            let drawn: Vec<usize> =
                drawn_cells(layout, &sim.field.cells.lod, &visible, lod).collect();
            let expected: Vec<usize> = (0..layout.cell_count())
                .filter(|&c| {
                    let patch = c / layout.cells_in_patch();
                    visible[patch] && sim.field.cells.lod[c] == lod
                })
                .collect();
            assert_eq!(drawn, expected, "{lod:?}");
        }
        // The default viewpoint sees blades near it: the list is not empty.
        assert!(drawn_cells(layout, &sim.field.cells.lod, &[], Lod::Geometry).count() > 0);
        sim.field.cells.lod.fill(Lod::Texture);
        assert_eq!(
            drawn_cells(&sim.field.layout, &sim.field.cells.lod, &[], Lod::Geometry).count(),
            0
        );
    }

    #[test]
    fn blade_cells_are_the_geometry_cells_and_the_billboard_cells_in_the_near_band() {
        let sim = Scene::default_scene().unwrap().build().unwrap();
        let (layout, cells) = (&sim.field.layout, &sim.field.cells);
        let visible: Vec<bool> = (0..layout.patch_list.len()).map(|p| p % 3 != 0).collect();
        let eye = sim.eye();
        let geometry_m = sim.lod.geometry_m;
        let geometry: Vec<usize> =
            drawn_cells(layout, &cells.lod, &visible, Lod::Geometry).collect();
        let blade_cells = |band: f32| -> Vec<usize> {
            drawn_blade_cells(
                layout,
                &cells.lod,
                &cells.base,
                &visible,
                eye,
                geometry_m,
                band,
            )
            .collect()
        };
        // No band: the Geometry-LOD cells alone.
        assert_eq!(blade_cells(0.0), geometry);
        let band = 4.0;
        let with_band = blade_cells(band);
        let reach = geometry_m + band;
        let expected: Vec<usize> = (0..layout.cell_count())
            .filter(|&c| {
                visible[c / layout.cells_in_patch()]
                    && match cells.lod[c] {
                        Lod::Geometry => true,
                        Lod::Billboard => cells.base[c].distance(eye) < reach,
                        Lod::Texture => false,
                    }
            })
            .collect();
        assert_eq!(with_band, expected);
        // The band adds billboard cells, and only billboard cells.
        assert!(
            with_band.len() > geometry.len(),
            "{} cells",
            with_band.len()
        );
        assert!(
            with_band
                .iter()
                .filter(|c| !geometry.contains(c))
                .all(|&c| cells.lod[c] == Lod::Billboard)
        );
    }
}
