//! Taking over a field written from outside the step (ours): the GPU path
//! (`trample_gpu::GpuSimulation::sync_to_cpu`) writes blade positions and
//! billboard slopes straight into [`Simulation::field`], but recovery
//! (DESIGN §6) only relaxes the blades and billboards the CPU step itself
//! marked as displaced. [`Simulation::rescan_displaced`] marks them again
//! from the field, so a simulation handed back from the GPU goes on
//! recovering exactly as if the CPU had bent those blades. It also lists
//! as touched every blade with a generation ([`Simulation::generation`],
//! read back too): the next sub-step clears the generations of the blades
//! it lists, and force propagation counts on every other blade being
//! untouched (`NO_GENERATION`); a generation left over from the GPU's last
//! sub-step would stop propagation at that blade.

use super::simulation::Simulation;

impl Simulation {
    /// Rebuilds the sets of displaced blades (any vertex not bit for bit at
    /// rest) and bent billboards (slope not at its origin) from the field,
    /// and adds every blade with a generation to the blades the latest
    /// sub-step touched (see the module docs). Call it after writing
    /// `field.blades.pos`, `field.cells.slope` or `generation` from outside
    /// [`Simulation::step`]. Costs one pass over every vertex.
    pub fn rescan_displaced(&mut self) {
        let s = &mut self.scratch;
        s.touched.extend(
            self.generation
                .iter()
                .enumerate()
                .filter(|(_, g)| **g != crate::force::propagation::NO_GENERATION)
                .map(|(b, _)| b as u32),
        );
        s.touched.sort_unstable();
        s.touched.dedup();
        let blades = &self.field.blades;
        let s = &mut self.scratch;
        s.displaced_flag.clear();
        s.displaced_flag
            .extend((0..blades.count).map(|b| !blades.is_at_rest(b)));
        s.displaced.clear();
        s.displaced.extend(
            s.displaced_flag
                .iter()
                .enumerate()
                .filter(|(_, d)| **d)
                .map(|(b, _)| b as u32),
        );
        s.displaced_sorted = s.displaced.len();
        // Strides start again: every displaced blade recovers at the next step.
        s.recover_clock.clear();
        let cells = &self.field.cells;
        s.bent_flag.clear();
        s.bent_flag
            .extend((0..cells.slope.len()).map(|c| !cells.slope_at_rest(c)));
        s.bent_cells.clear();
        s.bent_cells.extend(
            s.bent_flag
                .iter()
                .enumerate()
                .filter(|(_, b)| **b)
                .map(|(c, _)| c as u32),
        );
        s.bent_sorted = s.bent_cells.len();
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;

    const SCENE: &str = r#"
[field]
patches = [2, 2]
cells_per_patch = 16
[sim]
recovery_s = 0.5
# Every displaced blade every step: a rescan starts the strides' clocks
# again, which the run it is compared with kept.
recovery_stride_m = 0.0
[lod]
geometry_m = 2.0
billboard_m = 40.0
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.3 }
path = { kind = "line", from = [-1.5, 0.2, 0.0], to = [1.5, 0.2, 0.0], duration_s = 1.0 }
[camera]
path = { kind = "line", from = [-1.5, 1.0, 1.5], to = [1.5, 1.0, 1.5], duration_s = 1.0 }
"#;

    /// A simulation whose displaced sets are stale (as after a GPU
    /// read-back into it) recovers like the original once rescanned, and
    /// not without.
    #[test]
    fn a_field_written_from_outside_recovers_after_a_rescan() {
        let scene = Scene::parse(SCENE, "rescan", std::path::Path::new(".")).unwrap();
        let mut a = scene.build().unwrap();
        a.run(40).unwrap();
        assert!(a.blades_away_from_rest() > 0);
        assert!(!a.scratch.bent_cells.is_empty());
        let mut stale = a.clone();
        let s = &mut stale.scratch;
        s.displaced.clear();
        s.displaced_sorted = 0;
        s.displaced_flag.iter_mut().for_each(|d| *d = false);
        s.bent_cells.clear();
        s.bent_sorted = 0;
        s.bent_flag.iter_mut().for_each(|d| *d = false);
        let mut b = stale.clone();
        b.rescan_displaced();
        // The same sets, in order (a's as its recovery left them, the
        // cells bent since merged in).
        a.scratch.sort_displaced();
        a.scratch.sort_bent();
        assert_eq!(b.scratch.displaced, a.scratch.displaced);
        assert_eq!(b.scratch.displaced_flag, a.scratch.displaced_flag);
        assert_eq!(b.scratch.bent_cells, a.scratch.bent_cells);
        assert_eq!(b.scratch.bent_flag, a.scratch.bent_flag);
        for _ in 0..30 {
            a.step(a.params.dt_s).unwrap();
            b.step(b.params.dt_s).unwrap();
            stale.step(stale.params.dt_s).unwrap();
        }
        assert_eq!(a.blade_vertices(), b.blade_vertices());
        assert_eq!(a.field.cells.slope, b.field.cells.slope);
        assert_ne!(a.blade_vertices(), stale.blade_vertices());
    }
}
