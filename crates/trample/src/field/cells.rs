//! Per-cell state: level of detail and the billboard that stands for the
//! cell's blades at mid distance (paper §3.1, §6.2–6.3).

use super::changes::ChangeSet;
use super::lod::Lod;
use glam::Vec3;

/// Structure-of-arrays over cells, in storage order (see [`super::FieldLayout`]).
#[derive(Clone, Debug)]
pub struct Cells {
    /// Current level of detail of each cell.
    pub lod: Vec<Lod>,
    /// Centre of the cell on the ground (billboard base centre), metres.
    pub base: Vec<Vec3>,
    /// Billboard height: the mean rest height of the cell's blades, metres.
    pub height: Vec<f32>,
    /// Rest slope of the billboard, `slope_origin_b`: the mean rest
    /// `(Vn − V0) / height` of the cell's blades (dimensionless, length ≈ 1).
    pub slope_origin: Vec<Vec3>,
    /// Current billboard slope `slope_b` (Eq. 8, 12), dimensionless direction.
    pub slope: Vec<Vec3>,
    /// How flattened the cell's blades are, in [0, 1] (ours, DESIGN §2): the
    /// mean over its blades of `1 − (tip height above root) / (rest tip
    /// height above root)`, clamped. 0 at rest. Kept up to date wherever
    /// blades move when `sim.track_everywhere` is on, so a renderer can show
    /// the track on ground-texture cells (darker, flatter ground).
    pub flatness: Vec<f32>,
    /// Per patch: the level shared by all its cells, if they share one
    /// (lets [`super::lod::classify_cells`] skip settled patches).
    pub patch_lod: Vec<Option<Lod>>,
    /// Per patch: bounds (min, max) of its cells' base centres.
    pub patch_bounds: Vec<(Vec3, Vec3)>,
    /// Cells whose level or slope the last step set
    /// ([`super::Field::changed_cells`]).
    pub(crate) changed: ChangeSet,
    /// Per strip of patches ([`super::strips`]): the level shared by all its
    /// patches' cells, if they share one (lets
    /// [`super::lod::classify_cells`] skip settled strips).
    pub strip_lod: Vec<Option<Lod>>,
    /// Per strip: bounds of its patches' `patch_bounds`.
    pub strip_bounds: Vec<(Vec3, Vec3)>,
    /// The viewpoint, distances and counts of the last
    /// [`super::lod::classify_cells`]: called again with the same
    /// viewpoint and distances it returns the counts without a pass (a
    /// still camera costs nothing). Keyed by the viewpoint and the
    /// distances themselves, so whatever moves the eye (scene camera or
    /// host view) or changes the distances makes the next call classify.
    /// Writing `lod` any other way must call [`Cells::levels_written`].
    pub(crate) last_classified: Option<(Vec3, super::lod::LodParams, super::lod::LodCounts)>,
}

impl Cells {
    /// True when cell `c`'s billboard is exactly at its rest slope.
    #[must_use]
    pub fn slope_at_rest(&self, c: usize) -> bool {
        self.slope[c] == self.slope_origin[c]
    }

    /// After `lod` was written other than by
    /// [`super::lod::classify_cells`] (e.g. read back from the GPU): forgets
    /// the last classification and recomputes the levels each patch and
    /// strip shares from the cells themselves, so the next classification
    /// skips only what is really settled. `layout` is the field's. O(cells).
    pub fn levels_written(&mut self, layout: &super::FieldLayout) {
        self.last_classified = None;
        let shared = |levels: &mut dyn Iterator<Item = Option<Lod>>| {
            let first = levels.next().flatten();
            let mut all = first.is_some();
            for l in levels {
                all &= l == first;
            }
            first.filter(|_| all)
        };
        for (uniform, lod) in self
            .patch_lod
            .iter_mut()
            .zip(self.lod.chunks(layout.cells_in_patch()))
        {
            *uniform = shared(&mut lod.iter().map(|l| Some(*l)));
        }
        for (uniform, range) in self
            .strip_lod
            .iter_mut()
            .zip(super::strips::strip_ranges(layout.patches))
        {
            *uniform = shared(&mut self.patch_lod[range].iter().copied());
        }
    }

    /// Sets cell `c`'s billboard slope and records the cell as changed in
    /// this step ([`super::Field::changed_cells`]).
    pub fn set_slope(&mut self, c: usize, slope: Vec3) {
        self.slope[c] = slope;
        self.changed.mark(c);
    }
}
