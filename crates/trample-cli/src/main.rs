//! `trample`: simulate a grass field bending under moving objects.
//!
//! Subcommands: `simulate` (run a scene without rendering, write a summary
//! and dumps), `run` (simulate and render headless to PNG/GIF), `collide`
//! (hit flags of every blade at rest at one instant), `check` (validate a
//! scene file and say what it describes), `bench` (the paper's pressure
//! test, collision accuracy, scaling), `view` (an interactive window).

mod backend;
mod bench;
mod check;
mod collide;
mod common;
mod gpu_run;
mod mp4;
mod output;
mod run;
mod simulate;
mod summary;
mod track;
mod view;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Grass that bends under moving objects of any shape (CPU reference path).
#[derive(Parser, Debug)]
#[command(name = "trample", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene without rendering; write DIR/summary.json and optional dumps.
    Simulate(simulate::Args),
    /// Simulate and render along the camera path: PNG frames, GIF, summary.json.
    Run(run::Args),
    /// Hit flags of every blade segment at rest with the objects posed at one time.
    Collide(collide::Args),
    /// Validate a scene file and print what it describes.
    Check(check::Args),
    /// The paper's pressure test (frame rate per precision, simulation alone),
    /// collision accuracy against the exact reference; --scaling: step time
    /// against blade and triangle counts.
    Bench(bench::Args),
    /// Open a window on the scene: drive, fly, tune every parameter live.
    View(view::Args),
}

fn main() -> ExitCode {
    // A bug must still end in one line, not a panic trace.
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| (*s).to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        // Output piped into a reader that stopped (`trample check s.toml |
        // head -1`): not a bug; end quietly, as a process killed by
        // SIGPIPE would (exit status 128 + 13).
        if msg.starts_with("failed printing to stdout") && msg.contains("Broken pipe") {
            std::process::exit(141);
        }
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!("trample: internal error{at}: {msg} (please report it)");
    }));
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            // One line, like every other error: clap's first line plus where to look.
            let text = e.render().to_string();
            let what: Vec<&str> = text
                .lines()
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            eprintln!("{} (see `trample --help`)", what.join(" "));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Simulate(a) => simulate::run(&a),
        Command::Run(a) => run::run(&a),
        Command::Collide(a) => collide::run(&a),
        Command::Check(a) => check::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::View(a) => view::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let chain: Vec<String> = e.chain().map(ToString::to_string).collect();
            eprintln!("error: {}", chain.join(": ").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
