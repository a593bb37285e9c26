//! The cells a renderer draws each frame (`field::drawn_cells`,
//! `field::drawn_blade_cells`, DESIGN §8): skipping the patches the LOD
//! classification found wholly at another level, against the references
//! that look at every cell. The default scene's field at 64 × 64 patches
//! (4,194,304 cells of one blade, 204.8 m square; small mode: 16 × 16),
//! no object, the eye 1.7 m above the centre, the default LOD distances
//! (12 m, 30 m) and a 4 m near blend band; every patch visible.

mod common;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use trample::field::{
    Lod, classify_cells, drawn_blade_cells, drawn_blade_cells_by_cell, drawn_cells,
    drawn_cells_by_cell,
};

fn bench(c: &mut Criterion) {
    let mut scene = common::scene("default.toml");
    let side = if common::small() { 16 } else { 64 };
    scene.file.field.patches = [side, side];
    scene.file.objects.clear();
    let mut sim = scene.build().expect("scene builds");
    let eye = Vec3::new(0.0, 1.7, 0.0);
    let lod = sim.lod.clone();
    let field = &mut sim.field;
    classify_cells(&field.layout, &mut field.cells, eye, &lod, &mut Vec::new());
    let (layout, cells) = (&field.layout, &field.cells);
    let band = 4.0;
    let mut group = c.benchmark_group("drawn_cells");
    group.throughput(Throughput::Elements(layout.cell_count() as u64));
    let n = layout.cell_count();
    group.bench_function(BenchmarkId::new("billboards_every_cell", n), |b| {
        b.iter(|| black_box(drawn_cells_by_cell(layout, &cells.lod, &[], Lod::Billboard).count()))
    });
    group.bench_function(BenchmarkId::new("billboards_skipping", n), |b| {
        b.iter(|| black_box(drawn_cells(layout, cells, &[], Lod::Billboard).count()))
    });
    group.bench_function(BenchmarkId::new("blades_every_cell", n), |b| {
        b.iter(|| {
            black_box(
                drawn_blade_cells_by_cell(
                    layout,
                    &cells.lod,
                    &cells.base,
                    &[],
                    eye,
                    lod.geometry_m,
                    band,
                )
                .count(),
            )
        })
    });
    group.bench_function(BenchmarkId::new("blades_skipping", n), |b| {
        b.iter(|| {
            black_box(drawn_blade_cells(layout, cells, &[], eye, lod.geometry_m, band).count())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
