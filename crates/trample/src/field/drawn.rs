//! Which cells a renderer draws at a level of detail: the cells of that
//! level in the patches the last step found inside the view frustum
//! (DESIGN §8). Geometry-LOD cells are drawn as their blades, Billboard-LOD
//! cells as billboards; a host that draws the field asks here.

use super::{FieldLayout, Lod};

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
        .filter(move |&c| lods.get(c) == Some(&lod))
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
}
