//! A recovering blade's relaxation (`recovery.rs`, DESIGN §6): one blade
//! at a time (`recover_blade`) against four at a time
//! (`recovery_wide::recover_blades_wide`, the same bits), on one thread,
//! over blades brushed aside by seeded amounts (from barely to flattened,
//! 4 segments of 0.1 m, flat ground, `recovery_s = 6`, `trail = 2`, the
//! crowd example's settings). Each iteration copies the displaced blades
//! and relaxes them by one step of 1/60 s. Small mode: 4,000 blades
//! instead of 100,000.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3A;
use std::hint::black_box;
use trample::field::Terrain;
use trample::field::generate::GROUND_CLEARANCE_M;
use trample::recovery::{RecoveryParams, recover_blade};
use trample::recovery_wide::{LANES, Lane, recover_blades_wide};

const SEGMENTS: usize = 4;

/// `count` displaced blades and their rest shapes, vertices of blade `b`
/// at `b * (SEGMENTS + 1) ..` (seeded xorshift).
fn blades(count: usize) -> (Vec<Vec3A>, Vec<Vec3A>) {
    let mut next = common::uniform(0x5eed_0035);
    let (mut now, mut rest) = (Vec::new(), Vec::new());
    for _ in 0..count {
        let root = Vec3A::new(next() * 100.0, 0.0, next() * 100.0);
        let push = Vec3A::new(next() * 2.0 - 1.0, -0.3 * next(), next() * 2.0 - 1.0);
        let amount = 0.01 + next() * next();
        for k in 0..=SEGMENTS {
            let r = root + Vec3A::Y * (0.1 * k as f32);
            rest.push(r);
            now.push(r + push * (amount * k as f32 / SEGMENTS as f32));
        }
    }
    (now, rest)
}

fn bench(c: &mut Criterion) {
    let count = if common::small() { 4_000 } else { 100_000 };
    let (now, rest) = blades(count);
    let terrain = Terrain::Flat(0.0);
    let p = RecoveryParams {
        recovery_s: 6.0,
        trail: 2.0,
    };
    let (dt, n1) = (1.0 / 60.0, SEGMENTS + 1);
    let mut group = c.benchmark_group("recovery");
    group.throughput(Throughput::Elements(count as u64));
    let mut work = now.clone();
    group.bench_function(BenchmarkId::new("one_at_a_time", count), |b| {
        b.iter(|| {
            work.copy_from_slice(&now);
            for (v, r) in work.chunks_mut(n1).zip(rest.chunks(n1)) {
                black_box(recover_blade(
                    v,
                    r,
                    0.1,
                    dt,
                    &p,
                    &terrain,
                    GROUND_CLEARANCE_M,
                ));
            }
        });
    });
    let mut wide = now.clone();
    group.bench_function(BenchmarkId::new("four_at_a_time", count), |b| {
        b.iter(|| {
            wide.copy_from_slice(&now);
            for (v, r) in wide.chunks_mut(LANES * n1).zip(rest.chunks(LANES * n1)) {
                let mut slots = v.chunks_mut(n1);
                let mut rests = r.chunks(n1);
                let lanes = std::array::from_fn(|_| Lane {
                    verts: slots.next().expect("four blades"),
                    rest: rests.next().expect("four blades"),
                    seg_len: 0.1,
                    dt,
                    params: &p,
                });
                black_box(recover_blades_wide(lanes, &terrain, GROUND_CLEARANCE_M));
            }
        });
    });
    group.finish();
    // The same bits both ways.
    assert_eq!(work, wide, "four at a time must give the scalar bits");
}

criterion_group!(benches, bench);
criterion_main!(benches);
