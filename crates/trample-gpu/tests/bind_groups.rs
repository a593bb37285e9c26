//! A steady step makes no bind groups (`kernel::BindCache`): every stage
//! binds the same buffers step after step, so after the first steps the
//! kernels' caches answer every bind. On a field of many chunks a stage
//! binds more sets a step than a cache holds at first (two or three per
//! chunk); a fixed size of eight made 10 groups a step again on five
//! chunks and 180 on eighteen. One test in this binary: the count is
//! process-wide.

mod common;

use trample_gpu::{GpuSimulation, bind_groups_made};
use trample_testkit::scenes;

/// Two patches of 256 blades × 5 vertices × 16 bytes: the LOD scene's 36
/// patches in 18 chunks.
const CHUNK_BYTES: u64 = 2 * 256 * 5 * 16;

#[test]
fn a_steady_step_makes_no_bind_groups() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    for (limit, chunks) in [(None, 1), (Some(CHUNK_BYTES), 18)] {
        let sim = scenes::simulation(scenes::LOD);
        let mut g = GpuSimulation::new_chunked(device, queue, sim, limit).unwrap();
        assert_eq!(g.field.chunks.len(), chunks);
        let mut made = Vec::new();
        for _ in 0..12 {
            let before = bind_groups_made();
            g.step(device, queue, 1.0 / 60.0).unwrap();
            made.push(bind_groups_made() - before);
        }
        assert!(made[0] > 0, "{chunks} chunks: the first step made no group");
        // The caches grow within the first steps; from then on none.
        assert!(
            made[6..].iter().all(|&m| m == 0),
            "{chunks} chunks: groups made a step {made:?}"
        );
    }
}
