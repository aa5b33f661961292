//! `foveate`: render, plan and inspect stereo VR frames on Vulkan (lavapipe by default where no
//! GPU exists).

mod cli;
mod commands;
mod counts;
mod csv_out;
mod file_names;
mod fovea_table;
mod frame_args;
mod frontier;
mod gaze_arg;
mod progress;
mod side_by_side;
mod variants;
mod view_keys;

use clap::Parser;

fn main() -> std::process::ExitCode {
    // Diagnostics through `log`: warnings by default, more with RUST_LOG (e.g. RUST_LOG=info).
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = cli::Cli::parse();
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
