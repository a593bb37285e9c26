//! When the GPU's level-of-detail pass (`classify.wgsl`, paper Fig. 1) has
//! nothing to do: as the CPU's `trample::field::classify_cells`, which
//! returns at once for the viewpoint and distances of its last call, the
//! pass and the transitions after it (Eq. 9–13, which act only on the
//! cells a classification changed) are left out of a main sub-step whose
//! viewpoint and distances are those of the last classification, bit for
//! bit: every cell's level would come out the same. The level each cell had
//! before, which the pass also writes, is read by the transitions alone,
//! so it may stay as the last pass left it. The counts per level stay
//! those of the last pass (`begin` in `propagation.wgsl` keeps them when
//! the step uniform's `lod.w` is 1).

use crate::step_params::GpuStepParams;

/// The viewpoint and distances of the last classification.
#[derive(Debug, Default)]
pub struct LodSettle {
    last: Option<[u32; 8]>,
}

impl LodSettle {
    /// Whether the main sub-step with step uniform `params` (its `eye`:
    /// viewpoint and `geometry_m`; its `lod`: `billboard_m` and the
    /// propagation constants) must classify the cells: unless these values
    /// are, bit for bit, those of the last classification.
    pub fn needs_classify(&mut self, params: &GpuStepParams) -> bool {
        let mut key = [0u32; 8];
        for (k, v) in key
            .iter_mut()
            .zip(params.eye.iter().chain(&params.lod[..3]))
        {
            *k = v.to_bits();
        }
        let changed = self.last != Some(key);
        self.last = Some(key);
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(eye: [f32; 4], billboard: f32) -> GpuStepParams {
        GpuStepParams {
            eye,
            lod: [billboard, 0.5, 0.25, 0.0],
            ..bytemuck::Zeroable::zeroed()
        }
    }

    #[test]
    fn a_still_viewpoint_classifies_once() {
        let mut s = LodSettle::default();
        let p = params([1.0, 2.0, 3.0, 10.0], 40.0);
        let runs: Vec<bool> = (0..4).map(|_| s.needs_classify(&p)).collect();
        assert_eq!(runs, [true, false, false, false]);
    }

    #[test]
    fn any_change_of_viewpoint_or_distance_classifies_again() {
        let mut s = LodSettle::default();
        let p = params([1.0, 2.0, 3.0, 10.0], 40.0);
        s.needs_classify(&p);
        // One ulp along x.
        let moved = params([f32::from_bits(1.0f32.to_bits() + 1), 2.0, 3.0, 10.0], 40.0);
        assert!(s.needs_classify(&moved));
        assert!(!s.needs_classify(&moved));
        // Another billboard distance, then another geometry distance.
        assert!(s.needs_classify(&params([1.0, 2.0, 3.0, 10.0], 41.0)));
        assert!(s.needs_classify(&params([1.0, 2.0, 3.0, 11.0], 41.0)));
        // Back to a viewpoint seen before.
        assert!(s.needs_classify(&p));
        assert!(!s.needs_classify(&p));
    }
}
