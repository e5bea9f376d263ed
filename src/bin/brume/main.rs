//! The `brume` command line: `render`, and the tools around it. Each
//! subcommand lives in a file of its own, with its clap arguments beside it.

use clap::{Parser, Subcommand};

mod airlight;
mod compare;
mod debug_pixel;
mod debug_strategies;
mod frames_cli;
mod info;
mod interrupt;
mod merge;
mod mlt_cli;
mod render;
mod render_args;
mod render_job;
mod slab;

use airlight::AirlightArgs;
use compare::CompareArgs;
use info::InfoArgs;
use merge::MergeArgs;
use render_args::RenderArgs;

/// brume: a physically based renderer for participating media.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Largest image, grid or file brume allocates, in GB (default: half of
    /// this machine's memory, or BRUME_MEMORY_LIMIT); see docs/robustness.md "Limits".
    #[arg(long, global = true, value_name = "GB", allow_negative_numbers = true, value_parser = brume::error::limits::parse_gb)]
    memory_limit: Option<u64>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to EXR (linear) and PNG (sRGB preview).
    Render(Box<RenderArgs>),
    /// Describe the grids of an OpenVDB file: types, transform, voxel counts, bounds, values, memory.
    Info(InfoArgs),
    /// Render the airlight demo: targets fading with distance in haze, compared with Koschmieder's law.
    Airlight(AirlightArgs),
    /// Merge the pieces of a split render (crops, sample ranges) into the image of the whole render.
    Merge(MergeArgs),
    /// Compare A.exr with the reference B.exr: RMSE, relative MSE, means, max difference.
    Compare(CompareArgs),
    /// Light slabs: `brume slab bake SCENE.toml --out FILE.slab` records the light leaving a box.
    Slab(slab::SlabArgs),
}

fn main() {
    restore_default_sigpipe();
    interrupt::install();
    let cli = parse_command_line();
    let result = match cli.memory_limit {
        Some(bytes) => {
            brume::error::limits::set_memory_limit(bytes);
            Ok(())
        }
        None => brume::error::limits::check_setting().map(|_| ()),
    };
    let result = result.and_then(|()| match cli.command {
        Command::Render(args) => render::run_render(*args),
        Command::Info(args) => info::run_info(args),
        Command::Airlight(args) => airlight::run_airlight(args),
        Command::Merge(args) => merge::run_merge(args),
        Command::Compare(args) => compare::run_compare(args),
        Command::Slab(args) => slab::run_slab(args),
    });
    match result {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(e.exit_code());
        }
    }
}

/// The command line, or exit: help and version as clap prints them; a bad
/// flag value as one line naming the flag and what it expects, exit code 2.
fn parse_command_line() -> Cli {
    use clap::error::ErrorKind;
    let e = match Cli::try_parse() {
        Ok(cli) => return cli,
        Err(e) => e,
    };
    match e.kind() {
        ErrorKind::ValueValidation | ErrorKind::InvalidValue => {
            // clap's first paragraph says it (with the possible values of a
            // choice on a line of their own); the rest points to --help.
            let text = e.render().to_string();
            let first: Vec<&str> = text
                .lines()
                .take_while(|l| !l.is_empty())
                .map(str::trim)
                .collect();
            eprintln!("{}", first.join(" "));
            std::process::exit(2);
        }
        _ => e.exit(),
    }
}

/// Lets a closed pipe end the process silently, as it ends `cat` or `grep`.
///
/// Rust ignores SIGPIPE, so `println!` into a reader that has gone away (`brume
/// compare a b | head -1`) panics. Every file brume writes is written before its
/// report is printed (and atomically, through a temporary), so dying at a print
/// never leaves a half-written image.
fn restore_default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a
    // valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
