//! Which cells a renderer draws at a level of detail: the cells of that
//! level in the patches the last step found inside the view frustum
//! (DESIGN §8). Geometry-LOD cells are drawn as their blades, Billboard-LOD
//! cells as billboards; a host that draws the field asks here.

use super::{Cells, FieldLayout, Lod};
use glam::Vec3;

/// Indices of the cells whose level of detail is `lod` in patches marked
/// visible (`visible[p]`; a patch past the end of `visible` counts as
/// visible, as before the first cull), ascending: patch by patch, cells
/// row-major inside a patch. Cell `c`'s blades are
/// `c * blades_per_cell .. (c + 1) * blades_per_cell`.
///
/// A patch whose cells all share another level (`cells.patch_lod`, kept by
/// [`super::classify_cells`]) is skipped without looking at its cells, so
/// the cost follows the patches at that level and the band edges, not the
/// field's size (a renderer asks every frame). The same list as
/// [`drawn_cells_by_cell`], which looks at every cell (tested). Whoever
/// writes `cells.lod` other than by the classification calls
/// [`Cells::levels_written`], as the classification itself needs.
pub fn drawn_cells<'a>(
    layout: &'a FieldLayout,
    cells: &'a Cells,
    visible: &'a [bool],
    lod: Lod,
) -> impl Iterator<Item = usize> + 'a {
    let lods = &cells.lod;
    visible_cells(layout, visible, move |p| {
        shared_level(cells, p).is_none_or(|l| l == lod)
    })
    .filter(move |&c| lods.get(c) == Some(&lod))
}

/// [`drawn_cells`] looking at every cell of the visible patches: the
/// reference it is tested and benchmarked against (what it did before it
/// skipped patches).
pub fn drawn_cells_by_cell<'a>(
    layout: &'a FieldLayout,
    lods: &'a [Lod],
    visible: &'a [bool],
    lod: Lod,
) -> impl Iterator<Item = usize> + 'a {
    visible_cells(layout, visible, |_| true).filter(move |&c| lods.get(c) == Some(&lod))
}

/// The level all of patch `p`'s cells share, if the classification found
/// one (`None` for a mixed patch, or a patch it has no entry for).
fn shared_level(cells: &Cells, p: usize) -> Option<Lod> {
    cells.patch_lod.get(p).copied().flatten()
}

/// Every cell of the patches marked visible (`visible[p]`; a patch past
/// the end counts as visible) for which `wanted(p)` holds, ascending.
fn visible_cells<'a>(
    layout: &'a FieldLayout,
    visible: &'a [bool],
    wanted: impl Fn(usize) -> bool + 'a,
) -> impl Iterator<Item = usize> + 'a {
    let per_patch = layout.cells_in_patch();
    layout
        .patch_list
        .iter()
        .enumerate()
        .filter(move |(p, _)| visible.get(*p).copied().unwrap_or(true) && wanted(*p))
        .flat_map(move |(_, patch)| {
            let first = patch.first_cell as usize;
            first..first + per_patch
        })
}

/// Indices of the cells a renderer draws as blades (DESIGN §8): the
/// Geometry-LOD cells of the visible patches ([`drawn_cells`]) and, with
/// a near blend band (`band_m` > 0, [`super::lod::LodParams::blend_bands`]),
/// the Billboard-LOD cells of those patches whose base (`cells.base[c]`)
/// lies nearer than `geometry_m + band_m` to `eye`: their blades are drawn
/// too and thinned out with distance as the billboards fade in, so the
/// level changes without a ring round the camera. Ascending, as
/// [`drawn_cells`], whose patch skipping it shares: a patch wholly at the
/// Texture level, or wholly at the Billboard level with its cells' bases
/// (`cells.patch_bounds`) all beyond the band, is not looked into.
pub fn drawn_blade_cells<'a>(
    layout: &'a FieldLayout,
    cells: &'a Cells,
    visible: &'a [bool],
    eye: Vec3,
    geometry_m: f32,
    band_m: f32,
) -> impl Iterator<Item = usize> + 'a {
    let reach = geometry_m + band_m.max(0.0);
    // Whether any base of patch p can lie in the band: its bounds' nearest
    // point to the eye does (conservative: the cells are still asked one
    // by one).
    let band_reaches = move |p: usize| {
        band_m > 0.0
            && cells
                .patch_bounds
                .get(p)
                .is_none_or(|&(lo, hi)| eye.clamp(lo, hi).distance_squared(eye) < reach * reach)
    };
    let wanted = move |p: usize| match shared_level(cells, p) {
        Some(Lod::Texture) => false,
        Some(Lod::Billboard) => band_reaches(p),
        _ => true,
    };
    visible_cells(layout, visible, wanted).filter(blade_cell(
        &cells.lod,
        &cells.base,
        eye,
        geometry_m,
        band_m,
    ))
}

/// Whether cell `c` is drawn as blades ([`drawn_blade_cells`]): a
/// Geometry-LOD cell, or a Billboard-LOD cell whose base lies in the near
/// band.
fn blade_cell<'a>(
    lods: &'a [Lod],
    bases: &'a [Vec3],
    eye: Vec3,
    geometry_m: f32,
    band_m: f32,
) -> impl Fn(&usize) -> bool + 'a {
    let reach = geometry_m + band_m.max(0.0);
    move |&c| match lods.get(c) {
        Some(Lod::Geometry) => true,
        Some(Lod::Billboard) => {
            band_m > 0.0
                && bases
                    .get(c)
                    .is_some_and(|b| b.distance_squared(eye) < reach * reach)
        }
        _ => false,
    }
}

/// [`drawn_blade_cells`] looking at every cell of the visible patches:
/// the reference it is tested and benchmarked against.
pub fn drawn_blade_cells_by_cell<'a>(
    layout: &'a FieldLayout,
    lods: &'a [Lod],
    bases: &'a [Vec3],
    visible: &'a [bool],
    eye: Vec3,
    geometry_m: f32,
    band_m: f32,
) -> impl Iterator<Item = usize> + 'a {
    visible_cells(layout, visible, |_| true)
        .filter(blade_cell(lods, bases, eye, geometry_m, band_m))
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
            let drawn: Vec<usize> = drawn_cells(layout, &sim.field.cells, &visible, lod).collect();
            let expected: Vec<usize> = (0..layout.cell_count())
                .filter(|&c| {
                    let patch = c / layout.cells_in_patch();
                    visible[patch] && sim.field.cells.lod[c] == lod
                })
                .collect();
            assert_eq!(drawn, expected, "{lod:?}");
        }
        // The default viewpoint sees blades near it: the list is not empty.
        assert!(drawn_cells(layout, &sim.field.cells, &[], Lod::Geometry).count() > 0);
        sim.field.cells.lod.fill(Lod::Texture);
        sim.field.cells.levels_written(&sim.field.layout);
        assert_eq!(
            drawn_cells(&sim.field.layout, &sim.field.cells, &[], Lod::Geometry).count(),
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
        let geometry: Vec<usize> = drawn_cells(layout, cells, &visible, Lod::Geometry).collect();
        let blade_cells = |band: f32| -> Vec<usize> {
            drawn_blade_cells(layout, cells, &visible, eye, geometry_m, band).collect()
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

    /// Skipping the patches the classification found wholly at another
    /// level changes no list: from viewpoints across and beyond the field
    /// (each classified by `classify_cells`, so patches and strips are
    /// settled, mixed and re-settled), with every patch visible and with
    /// a third hidden, each level's cells and the blade cells for bands of
    /// 0, 1, 4 and 40 m are those of the references that look at every
    /// cell; and the skipping is not empty (most patches are settled).
    #[test]
    fn skipping_settled_patches_gives_the_lists_of_every_cell() {
        use crate::field::lod::{LodParams, classify_cells};
        let mut sim = Scene::default_scene().unwrap().build().unwrap();
        let params = LodParams {
            geometry_m: 6.0,
            billboard_m: 14.0,
        };
        let patches = sim.field.layout.patch_list.len();
        let some_hidden: Vec<bool> = (0..patches).map(|p| p % 3 != 1).collect();
        let mut settled = 0;
        for k in 0..12 {
            let t = k as f32 / 11.0;
            let eye = Vec3::new(-40.0 + 80.0 * t, 1.7, 25.0 * (t * 7.0).sin());
            let field = &mut sim.field;
            classify_cells(
                &field.layout,
                &mut field.cells,
                eye,
                &params,
                &mut Vec::new(),
            );
            let (layout, cells) = (&field.layout, &field.cells);
            settled += cells.patch_lod.iter().filter(|l| l.is_some()).count();
            for visible in [&[][..], &some_hidden[..]] {
                for lod in [Lod::Geometry, Lod::Billboard, Lod::Texture] {
                    let got: Vec<usize> = drawn_cells(layout, cells, visible, lod).collect();
                    let want: Vec<usize> =
                        drawn_cells_by_cell(layout, &cells.lod, visible, lod).collect();
                    assert_eq!(got, want, "eye {eye}, {lod:?}");
                }
                for band in [0.0, 1.0, 4.0, 40.0] {
                    let got: Vec<usize> =
                        drawn_blade_cells(layout, cells, visible, eye, params.geometry_m, band)
                            .collect();
                    let want: Vec<usize> = drawn_blade_cells_by_cell(
                        layout,
                        &cells.lod,
                        &cells.base,
                        visible,
                        eye,
                        params.geometry_m,
                        band,
                    )
                    .collect();
                    assert_eq!(got, want, "eye {eye}, band {band}");
                }
            }
        }
        assert!(settled > 12 * patches / 2, "{settled} settled patches");
    }
}
