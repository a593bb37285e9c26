//! Collision accuracy on the paper's field (262,144 blades at rest) against
//! the exact reference, for the built-in sphere and the complex shape (the
//! knot) at sampled times of their paths: no exact hit is ever missed, hits
//! shrink with depth, and false positives fall. Run with `--nocapture` for
//! the table recorded in BENCHMARKS.md. The counting is
//! `trample::accuracy::measure_accuracy`, which `trample bench` also uses.
//! Also measured: what `ObbTree::nest_boxes` (parents grown to contain
//! their children) costs.

use std::path::Path;
use trample::Simulation;
use trample::accuracy::{Accuracy, measure_accuracy};
use trample::scene::Scene;

/// `max_fp_at_7`: the share of false positives allowed at precision 7 (the
/// tree's splits and fit decide it; BENCHMARKS.md has the table).
fn measure(scene: &str, times: &[f32], max_fp_at_7: f64) -> Accuracy {
    measure_sim(scene, &sim(scene), times, max_fp_at_7)
}

fn sim(scene: &str) -> Simulation {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(scene);
    Scene::load(&path).unwrap().build().unwrap()
}

fn measure_sim(scene: &str, sim: &Simulation, times: &[f32], max_fp_at_7: f64) -> Accuracy {
    let depths: Vec<u32> = (1..=10).collect();
    let acc = measure_accuracy(sim, times, &depths, || {});
    assert_eq!(acc.per_precision.len(), depths.len());
    assert!(
        acc.first_false_negative.is_none(),
        "{scene}: an exact hit was missed: {:?}",
        acc.first_false_negative
    );
    assert!(
        acc.first_not_in_previous.is_none(),
        "{scene}: a segment hit at a depth but not at the one before: {:?}",
        acc.first_not_in_previous
    );
    assert!(
        acc.exact_hits > 100,
        "{scene}: the object must touch the grass"
    );
    print!(
        "{scene}: exact hits {} over {} times; false positives per depth (share of reported hits):",
        acc.exact_hits,
        times.len()
    );
    for (i, d) in acc.per_precision.iter().enumerate() {
        assert_eq!(d.false_negatives, 0);
        assert_eq!(d.reported, acc.exact_hits + d.false_positives);
        print!(" d{}={:.1}%", d.precision, 100.0 * d.false_positive_rate());
        if i > 0 {
            assert!(d.reported <= acc.per_precision[i - 1].reported);
        }
    }
    println!();
    let at7 = acc.per_precision[6].false_positive_rate();
    assert!(
        at7 <= max_fp_at_7,
        "{scene}: {:.1} % false positives at precision 7, allowed {:.1} %",
        100.0 * at7,
        100.0 * max_fp_at_7
    );
    let (first, last) = (&acc.per_precision[0], &acc.per_precision[9]);
    assert!(
        last.false_positives < first.false_positives,
        "{scene}: depth 10 must be more exact than depth 1"
    );
    acc
}

#[test]
fn sphere_on_the_papers_field_never_misses_and_false_positives_fall() {
    // 5.6 % measured (6.5 % before the split between pieces and the wider
    // orientation search, issue 16; its goal of 5 % is not reached).
    measure("default.toml", &[1.0, 4.0, 6.0, 9.0], 0.06);
}

#[test]
fn knot_on_the_papers_field_never_misses_and_false_positives_fall() {
    // 18.4 % measured (59.7 % before the split between pieces, issue 16's
    // goal is 20 %).
    measure("knot.toml", &[2.0, 4.0, 6.0, 8.0], 0.20);
}

#[test]
fn nested_boxes_never_miss_and_report_more() {
    for (scene, times) in [
        ("default.toml", [1.0, 4.0, 6.0, 9.0]),
        ("knot.toml", [2.0, 4.0, 6.0, 8.0]),
    ] {
        let mut sim = sim(scene);
        let tight = measure_accuracy(&sim, &times, &(1..=10).collect::<Vec<_>>(), || {});
        for body in &mut sim.bodies {
            std::sync::Arc::make_mut(&mut body.tree).nest_boxes();
            body.tree.assert_well_formed();
        }
        let label = format!("{scene} with nested boxes");
        let nested = measure_sim(&label, &sim, &times, 1.0);
        // Boxes that grew report every hit they reported before, and more.
        for (t, n) in tight.per_precision.iter().zip(&nested.per_precision) {
            assert!(n.reported >= t.reported, "{scene}: {t:?} vs {n:?}");
        }
        assert!(nested.per_precision[6].false_positives > tight.per_precision[6].false_positives);
    }
}
