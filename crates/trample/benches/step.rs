//! One full `Simulation::step` (DESIGN §7) of the default scene — the
//! paper's 262,144-blade field and the rolling 1 m ball — at precision 3
//! (the paper's setting) and 7 (DESIGN §10's target: ≤ 1 ms median on 2
//! cores). The run restarts from the first frame when the ball's 12 s path
//! ends, outside the timing. Small mode: a 4 × 4 patch field. Throughput:
//! blades in the field.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::time::{Duration, Instant};

fn bench(c: &mut Criterion) {
    let start = common::sim("default.toml");
    let dt = start.params.dt_s;
    let lap = (12.0 / dt).ceil() as u64;
    let mut group = c.benchmark_group("step");
    group.throughput(Throughput::Elements(start.field.blades.count as u64));
    for precision in [3u32, 7] {
        let mut first = start.clone();
        first.params.precision = precision;
        let mut sim = first.clone();
        group.bench_function(BenchmarkId::new("default_scene", precision), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    if sim.frame >= lap {
                        sim.clone_from(&first);
                    }
                    let t = Instant::now();
                    sim.step(dt).expect("valid dt");
                    total += t.elapsed();
                }
                total
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
