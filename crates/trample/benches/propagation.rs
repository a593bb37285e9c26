//! Force propagation (Eq. 4, `force/propagation.rs`) on the paper's field:
//! the blades under a 1 m ball's footprint (roots within 1 m of the field's
//! centre) are the DBG, each pushed outwards at 3 m/s (the default ball's
//! speed); default `att` 0.5 and threshold 0.25 m/s. Small mode: a 4 × 4
//! patch field. Throughput: blades reached (DBG + PBG).

mod common;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use trample::force::propagation::{NO_GENERATION, PropagationParams, propagate_forces};

fn bench(c: &mut Criterion) {
    let sim = common::sim("default.toml");
    let bl = &sim.field.blades;
    let neighbours = &sim.field.layout.neighbours;
    let mut force = vec![Vec3::ZERO; bl.count];
    let dbg: Vec<u32> = (0..bl.count as u32)
        .filter(|&b| {
            let r = Vec3::from(bl.rest_vertex(b as usize, 0));
            let out = Vec3::new(r.x, 0.0, r.z);
            let hit = out.length() < 1.0;
            if hit {
                force[b as usize] = out.normalize_or(Vec3::X) * 3.0;
            }
            hit
        })
        .collect();
    let generation = vec![NO_GENERATION; bl.count];
    let params = PropagationParams {
        att: sim.params.att,
        threshold: sim.params.threshold,
        max_generations: sim.params.max_generations,
        threshold_fade: 0.0,
        hold_weight: 0.0,
    };
    let (mut f, mut g) = (force.clone(), generation.clone());
    let reached = propagate_forces(&dbg, neighbours, &mut f, &mut g, &[], &params);
    eprintln!(
        "propagation: {} DBG blades reach {} PBG in {} generations",
        dbg.len(),
        reached.pbg.len(),
        reached.generations
    );
    let mut group = c.benchmark_group("propagation");
    group.throughput(Throughput::Elements((dbg.len() + reached.pbg.len()) as u64));
    group.bench_function("ball_footprint", |b| {
        b.iter_batched_ref(
            || (force.clone(), generation.clone()),
            |(f, g)| propagate_forces(&dbg, neighbours, f, g, &[], &params),
            BatchSize::LargeInput,
        );
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
