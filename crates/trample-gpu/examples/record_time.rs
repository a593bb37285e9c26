//! Measures the host's side of the GPU step: the time
//! `GpuSimulation::record_step` takes to record one step into an encoder
//! (poses, uploads, bind groups, passes), apart from the GPU's work (a
//! measurement, not a test: it prints, it asserts nothing about speed).
//! Each step is submitted and waited for before the next is recorded, so
//! the GPU's work (on a software driver, the CPU's) never overlaps the
//! recording being timed.
//!
//! ```text
//! WGPU_BACKEND=vulkan cargo run --release -p trample-gpu --example record_time -- [FRAMES] [SCENE.toml]
//! ```
//!
//! Default: 100 frames of the embedded default scene (the paper's field,
//! one ball). Prints the median and quartiles of the recording time from
//! the third frame on.

use trample::scene::Scene;
use trample_gpu::GpuSimulation;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let frames: usize = args.next().map_or(Ok(100), |s| s.parse())?;
    let sim = match args.next() {
        Some(path) => {
            let text = std::fs::read_to_string(&path)?;
            let dir = std::path::Path::new(&path)
                .parent()
                .unwrap_or(std::path::Path::new("."))
                .to_path_buf();
            Scene::parse(&text, &path, &dir)?.build()?
        }
        None => Scene::default_scene()?.build()?,
    };
    let gpu = trample_testkit::gpu::create_device(trample_gpu::wgpu::Features::empty())?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    println!("adapter: {}", gpu.adapter_name());
    let dt = sim.params.dt_s;
    let blades = sim.field.blades.count;
    let mut g = GpuSimulation::new(device, queue, sim)?;
    let mut times = Vec::with_capacity(frames);
    for _ in 0..frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        let start = std::time::Instant::now();
        g.record_step(device, queue, &mut encoder, dt)?;
        let buffer = encoder.finish();
        times.push(start.elapsed().as_secs_f64() * 1e3);
        queue.submit([buffer]);
        device.poll(trample_gpu::wgpu::PollType::wait_indefinitely())?;
    }
    let mut t: Vec<f64> = times.iter().skip(2).copied().collect();
    t.sort_by(f64::total_cmp);
    let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
    println!(
        "{blades} blades, {frames} frames: record_step {:.3} ms median (quartiles {:.3} / {:.3})",
        at(0.5),
        at(0.25),
        at(0.75)
    );
    Ok(())
}
