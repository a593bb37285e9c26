//! Collision accuracy of the variable-precision OBB-tree test (paper §4.2)
//! against the exact reference (DESIGN §4): over the field at rest and the
//! objects posed at sampled times, how many segment hits each precision
//! reports that the exact test does not (false positives), and how many
//! exact hits it misses (false negatives; the method guarantees none).
//!
//! The paper calls its precision "variable" but never measured what it buys;
//! this is that measurement. `tests/collision_accuracy.rs` and
//! `trample bench` both call [`measure_accuracy`].

use crate::step::Simulation;
use crate::step::query::HitMode;
use serde::Serialize;

/// The counts of one precision, summed over the sampled times.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PrecisionAccuracy {
    /// OBB-tree depth of the test (root = 1).
    pub precision: u32,
    /// Segment hits the test reported.
    pub reported: usize,
    /// Reported hits that the exact reference does not have.
    pub false_positives: usize,
    /// Exact hits that the test missed. Boxes contain their triangles and a
    /// segment inside a closed mesh is caught by the inside test, so this is
    /// 0 unless something is broken.
    pub false_negatives: usize,
    /// Segments hit at this precision but not at the previous (lower) one in
    /// the list: 0, since hits at depth d+1 ⊆ hits at depth d. Always 0 for
    /// the first precision.
    pub not_in_previous: usize,
}

impl PrecisionAccuracy {
    /// Share of the reported hits that are false positives, in [0, 1] (0 when
    /// nothing was reported): how much more grass the test bends than the
    /// exact shape would. (A false discovery rate: the true negatives, the
    /// many segments far from the object, would make a classic
    /// false-positive rate meaninglessly small.)
    #[must_use]
    pub fn false_positive_rate(&self) -> f64 {
        if self.reported == 0 {
            0.0
        } else {
            self.false_positives as f64 / self.reported as f64
        }
    }
}

/// The first false negative found, for a message that points at it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Miss {
    /// Sampled time, seconds.
    pub time_s: f32,
    /// Segment index `b * n + k` (blade b, segment k), as in
    /// [`Simulation::segment_hits_at_rest`].
    pub segment: usize,
    /// Precision that missed it.
    pub precision: u32,
}

/// Accuracy of several precisions over the same sampled times.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Accuracy {
    /// The sampled times, seconds.
    pub times_s: Vec<f32>,
    /// Segments tested at each time (blades × segments per blade).
    pub segments_per_time: usize,
    /// Segment hits of the exact reference, summed over the times.
    pub exact_hits: usize,
    /// One entry per precision, ascending, without repeats.
    pub per_precision: Vec<PrecisionAccuracy>,
    /// The first false negative, if any (time order, then precision order).
    pub first_false_negative: Option<Miss>,
    /// The first segment hit at a precision but not at the previous one, if any.
    pub first_not_in_previous: Option<Miss>,
}

/// Measures the precisions `precisions` (sorted and deduplicated here)
/// against the exact reference on `sim`'s field at rest, with the objects
/// posed at each of `times_s` ([`Simulation::segment_hits_at_rest`], every
/// blade whatever its level of detail). Calls `after_query` after each of
/// the `times_s.len() × (precisions + 1)` queries, for a progress bar.
///
/// Cost: one exact query and one query per precision at each time, each
/// over the blades of the patches under an object; parallel inside a query.
#[must_use]
pub fn measure_accuracy(
    sim: &Simulation,
    times_s: &[f32],
    precisions: &[u32],
    mut after_query: impl FnMut(),
) -> Accuracy {
    let mut depths = precisions.to_vec();
    depths.sort_unstable();
    depths.dedup();
    let mut out = Accuracy {
        times_s: times_s.to_vec(),
        segments_per_time: sim.field.blades.count * sim.field.blades.segments,
        per_precision: depths
            .iter()
            .map(|&precision| PrecisionAccuracy {
                precision,
                ..PrecisionAccuracy::default()
            })
            .collect(),
        ..Accuracy::default()
    };
    for &t in times_s {
        let exact = sim.segment_hits_at_rest(t, HitMode::Exact);
        after_query();
        out.exact_hits += exact.iter().filter(|&&h| h != 0).count();
        let mut previous: Option<Vec<u8>> = None;
        for acc in &mut out.per_precision {
            let at = sim.segment_hits_at_rest(t, HitMode::Precision(acc.precision));
            after_query();
            let miss = |segment| Miss {
                time_s: t,
                segment,
                precision: acc.precision,
            };
            for (i, (&e, &a)) in exact.iter().zip(&at).enumerate() {
                match (e != 0, a != 0) {
                    (true, false) => {
                        acc.false_negatives += 1;
                        out.first_false_negative.get_or_insert(miss(i));
                    }
                    (false, true) => acc.false_positives += 1,
                    _ => {}
                }
                acc.reported += usize::from(a != 0);
            }
            if let Some(prev) = &previous {
                for (i, (&p, &a)) in prev.iter().zip(&at).enumerate() {
                    if a != 0 && p == 0 {
                        acc.not_in_previous += 1;
                        out.first_not_in_previous.get_or_insert(miss(i));
                    }
                }
            }
            previous = Some(at);
        }
    }
    out
}

/// `count` times spread evenly over `[0, span_s]` (the midpoints of `count`
/// equal intervals, so neither end, where an object may still be outside
/// the field, is sampled). Empty for `count` 0 or a span that is not a
/// finite number > 0.
#[must_use]
pub fn sample_times(span_s: f32, count: usize) -> Vec<f32> {
    if !(span_s.is_finite() && span_s > 0.0) {
        return Vec::new();
    }
    (0..count)
        .map(|i| span_s * (i as f32 + 0.5) / count as f32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_is_the_share_of_reported_hits() {
        let a = PrecisionAccuracy {
            precision: 3,
            reported: 8,
            false_positives: 2,
            ..PrecisionAccuracy::default()
        };
        assert_eq!(a.false_positive_rate(), 0.25);
        assert_eq!(PrecisionAccuracy::default().false_positive_rate(), 0.0);
    }

    #[test]
    fn sample_times_are_interval_midpoints() {
        assert_eq!(sample_times(8.0, 4), vec![1.0, 3.0, 5.0, 7.0]);
        assert!(sample_times(f32::INFINITY, 4).is_empty());
        assert!(sample_times(0.0, 4).is_empty());
        assert!(sample_times(1.0, 0).is_empty());
    }
}
