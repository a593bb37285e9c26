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
//! the third frame on, the medians of the submission and of the wait for
//! the GPU, then the time a step takes when FRAMES steps are recorded and
//! submitted back to back and waited for once (the host and the GPU
//! overlapping, as in an engine that does not wait for the simulation),
//! and last the round trip of an empty submission (the driver's share of
//! the wait).

use trample::scene::Scene;
use trample_gpu::GpuSimulation;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let frames: usize = args.next().map_or(Ok(100), |s| s.parse())?;
    if frames < 3 {
        return Err(
            format!("FRAMES is {frames}: give 3 or more (the first two are not counted)").into(),
        );
    }
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
    // Each step recorded, submitted and waited for: the three times apart.
    let (mut record, mut submit, mut wait) = (Vec::new(), Vec::new(), Vec::new());
    let ms = |t: std::time::Instant| t.elapsed().as_secs_f64() * 1e3;
    for _ in 0..frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        let start = std::time::Instant::now();
        g.record_step(device, queue, &mut encoder, dt)?;
        let buffer = encoder.finish();
        record.push(ms(start));
        let start = std::time::Instant::now();
        queue.submit([buffer]);
        submit.push(ms(start));
        let start = std::time::Instant::now();
        device.poll(trample_gpu::wgpu::PollType::wait_indefinitely())?;
        wait.push(ms(start));
    }
    // Then the same number of steps recorded and submitted back to back,
    // waited for once at the end (a host that does not wait for the
    // simulation): the time a step costs when the GPU's work and the
    // host's recording overlap.
    let start = std::time::Instant::now();
    for _ in 0..frames {
        let mut encoder = device.create_command_encoder(&Default::default());
        g.record_step(device, queue, &mut encoder, dt)?;
        queue.submit([encoder.finish()]);
    }
    device.poll(trample_gpu::wgpu::PollType::wait_indefinitely())?;
    let pipelined = ms(start) / frames as f64;
    let quartiles = |times: &[f64]| {
        let mut t: Vec<f64> = times.iter().skip(2).copied().collect();
        t.sort_by(f64::total_cmp);
        let at = |q: f64| t[((t.len() - 1) as f64 * q).round() as usize];
        (at(0.25), at(0.5), at(0.75))
    };
    let (q1, median, q3) = quartiles(&record);
    println!(
        "{blades} blades, {frames} frames: record_step {median:.3} ms median (quartiles {q1:.3} / {q3:.3})"
    );
    let (_, s, _) = quartiles(&submit);
    let (_, w, _) = quartiles(&wait);
    println!("  submit {s:.3} ms median, wait for the GPU {w:.3} ms median");
    println!("  {frames} steps submitted back to back, one wait: {pipelined:.3} ms a step");
    // What a submission and its wait cost with no work in it: the part of
    // "wait for the GPU" that is the driver's round trip, not the step.
    let mut empty = Vec::new();
    for _ in 0..frames {
        let encoder = device.create_command_encoder(&Default::default());
        let start = std::time::Instant::now();
        queue.submit([encoder.finish()]);
        device.poll(trample_gpu::wgpu::PollType::wait_indefinitely())?;
        empty.push(ms(start));
    }
    let (_, e, _) = quartiles(&empty);
    println!("  an empty submission and its wait: {e:.3} ms median");
    Ok(())
}
