//! `foveate`: render, plan and inspect stereo VR frames on Vulkan (lavapipe by default where no
//! GPU exists).

mod cli;
mod commands;
mod compared_frame;
mod counts;
mod csv_out;
mod file_names;
mod fovea_table;
mod frame_args;
mod frontier;
mod gaze_arg;
mod history_table;
mod interrupt;
mod metric;
mod outputs;
mod progress;
mod region_maps;
mod side_by_side;
mod tile_pricer;
mod tile_trace;
mod variants;
mod view_keys;

use clap::{CommandFactory, FromArgMatches};

fn main() -> std::process::ExitCode {
    // Diagnostics through `log`: warnings by default, more with RUST_LOG (e.g. RUST_LOG=info).
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let matches = negative_numbers(cli::Cli::command()).get_matches();
    let cli = cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Every option that takes a value takes a negative number as written (`--ipd-mm -64`,
/// `--cant -2`), not only as `--ipd-mm=-64`: no option of foveate's has a name that looks like
/// a number, so nothing else can be meant.
fn negative_numbers(command: clap::Command) -> clap::Command {
    command
        .mut_args(|a| {
            if a.get_action().takes_values() {
                a.allow_negative_numbers(true)
            } else {
                a
            }
        })
        .mut_subcommands(negative_numbers)
}
