//! Collision accuracy on the paper's field (262,144 blades at rest) against
//! the exact reference, for the built-in sphere and the complex shape (the
//! knot) at sampled times of their paths: no exact hit is ever missed, hits
//! shrink with depth, and false positives fall. Run with `--nocapture` for
//! the table recorded in BENCHMARKS.md.

use std::path::Path;
use trample::scene::Scene;
use trample::step::query::HitMode;

fn measure(scene: &str, times: &[f32]) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(scene);
    let sim = Scene::load(&path).unwrap().build().unwrap();
    let (mut exact_total, mut hits) = (0usize, [0usize; 11]);
    for &t in times {
        let exact = sim.segment_hits_at_rest(t, HitMode::Exact);
        exact_total += exact.iter().filter(|&&h| h == 1).count();
        let mut previous: Option<Vec<u8>> = None;
        for d in 1..=10u32 {
            let at = sim.segment_hits_at_rest(t, HitMode::Precision(d));
            for (i, (&e, &a)) in exact.iter().zip(&at).enumerate() {
                assert!(
                    e == 0 || a == 1,
                    "{scene} t={t}: segment {i} hit exactly but missed at depth {d}"
                );
            }
            if let Some(prev) = &previous {
                for (i, (&p, &a)) in prev.iter().zip(&at).enumerate() {
                    assert!(
                        a <= p,
                        "{scene} t={t}: segment {i} hit at depth {d} but not at depth {}",
                        d - 1
                    );
                }
            }
            hits[d as usize] += at.iter().filter(|&&h| h == 1).count();
            previous = Some(at);
        }
    }
    assert!(
        exact_total > 100,
        "{scene}: the object must touch the grass"
    );
    print!(
        "{scene}: exact hits {exact_total} over {} times; false positives per depth (share of reported hits):",
        times.len()
    );
    for d in 1..=10 {
        let fp = hits[d] - exact_total;
        print!(" d{d}={:.1}%", 100.0 * fp as f64 / hits[d] as f64);
        if d > 1 {
            assert!(hits[d] <= hits[d - 1]);
        }
    }
    println!();
}

#[test]
fn sphere_on_the_papers_field_never_misses_and_false_positives_fall() {
    measure("default.toml", &[1.0, 4.0, 6.0, 9.0]);
}

#[test]
fn knot_on_the_papers_field_never_misses_and_false_positives_fall() {
    measure("knot.toml", &[2.0, 4.0, 6.0, 8.0]);
}
