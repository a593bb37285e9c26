//! Measures `GpuSimulation::step` stage by stage on the adapter that
//! `WGPU_BACKEND` picks (a measurement, not a test: it prints, it asserts
//! nothing about speed).
//!
//! ```text
//! WGPU_BACKEND=vulkan cargo run -p trample-gpu --example stage_times -- [FRAMES] [SCENE.toml]
//! ```
//!
//! Default: 100 frames of a 4,096-blade field with a rolling ball (the test
//! kit's rolling-ball scene, `crates/trample-testkit/scenes/rolling_ball.toml`,
//! which `tests/step_parity.rs` runs too), in profiling mode
//! (`GpuSimulation::set_profiling`). Prints each frame's stage times and the
//! median narrow phase from the third frame on (the first dispatches
//! include the driver's compilation). Stage times come from timestamp
//! queries where the adapter has them; `TRAMPLE_STAGE_TIMING=wall` asks for
//! the wall-time way instead. Set `MESA_SHADER_CACHE_DISABLE=true` to see
//! compilations the on-disk shader cache would otherwise hide.

use trample::scene::Scene;
use trample_gpu::GpuSimulation;
use trample_testkit::scenes;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let frames: u32 = args.next().map_or(Ok(100), |s| s.parse())?;
    // A scene file's meshes are found beside it.
    let (text, source, dir) = match args.next() {
        Some(path) => {
            let dir = std::path::Path::new(&path)
                .parent()
                .unwrap_or(std::path::Path::new("."))
                .to_path_buf();
            (std::fs::read_to_string(&path)?, path, dir)
        }
        None => (
            scenes::ROLLING_BALL.to_string(),
            "rolling_ball.toml".to_string(),
            std::path::PathBuf::from("."),
        ),
    };
    // Timestamp queries where the adapter has them, unless told otherwise.
    let wall = std::env::var("TRAMPLE_STAGE_TIMING").is_ok_and(|v| v == "wall");
    let features = if wall {
        trample_gpu::wgpu::Features::empty()
    } else {
        trample_gpu::TIMESTAMP_FEATURES
    };
    // The test kit's device (no TRAMPLE_TEST_ADAPTER check: a measurement
    // runs on whatever adapter WGPU_BACKEND picks).
    let gpu = trample_testkit::gpu::create_device(features)?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    println!("adapter: {}", gpu.adapter_name());
    let ts = trample_gpu::wgpu::Features::TIMESTAMP_QUERY
        | trample_gpu::wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
        | trample_gpu::wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
    println!(
        "adapter timestamp features: {:?}; timestamp period {} ns",
        gpu.adapter.features() & ts,
        queue.get_timestamp_period()
    );
    let sim = Scene::parse(&text, &source, &dir)?.build()?;
    let dt = sim.params.dt_s;
    let mut g = GpuSimulation::new(device, queue, sim)?;
    g.set_profiling(true);
    println!("stage timing: {}", g.stage_timing().name());
    let mut narrow = Vec::new();
    for f in 0..frames {
        let start = std::time::Instant::now();
        g.step(device, queue, dt)?;
        let c = g.read_counters(device, queue)?;
        let wall = start.elapsed().as_secs_f64() * 1e3;
        let t = &g.sim.timings;
        println!(
            "frame {f}: {wall:.1} ms wall; lod {:.2} narrow {:.2} propagation {:.2} deformation {:.2} contact {:.2} transitions {:.2} recovery {:.2} ms; DBG {}",
            t.lod_ms,
            t.narrow_ms,
            t.propagation_ms,
            t.deformation_ms,
            t.contact_ms,
            t.transitions_ms,
            t.recovery_ms,
            c.dbg
        );
        if f >= 2 {
            narrow.push(t.narrow_ms);
        }
    }
    narrow.sort_by(f64::total_cmp);
    if let Some(m) = narrow.get(narrow.len() / 2) {
        println!(
            "narrow phase: median {m:.2} ms over {} frames",
            narrow.len()
        );
    }
    Ok(())
}
