//! `brume slab bake SCENE.toml --out FILE.slab`: record the light leaving
//! the scene's `[slab]` box, for `type = "slab"` shapes to show.

use brume::error::{Error, Result};
use brume::film::output_safety::Plan;
use brume::geometry::slab::SlabHeader;
use brume::render::cli_values as values;
use brume::render::slab_bake::{bake, bake_peak_bytes};
use brume::render::RenderOptions;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::interrupt::{self, EXIT_INTERRUPTED};

/// `brume slab ...`.
#[derive(clap::Args)]
pub(crate) struct SlabArgs {
    #[command(subcommand)]
    command: SlabCommand,
}

#[derive(clap::Subcommand)]
enum SlabCommand {
    /// Bake the light leaving the scene's [slab] box into a .slab file (see README "Light slabs").
    Bake(BakeArgs),
}

#[derive(clap::Args)]
struct BakeArgs {
    /// The scene file (TOML) with a [slab] table.
    scene: PathBuf,
    /// The slab file to write (replaced if it exists; never an input of the bake).
    #[arg(long)]
    out: PathBuf,
    /// Set a scene value before validation, as TOML (repeatable), as for `render`.
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = values::set)]
    set: Vec<brume::scene::Override>,
    /// Samples per recorded line (overrides the scene's integrator.spp).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::whole(1u32, u32::MAX))]
    spp: Option<u32>,
    /// Seed of the random streams (overrides integrator.seed). The file depends on it only.
    #[arg(long, allow_negative_numbers = true, value_name = "S", value_parser = values::whole(0u64, u64::MAX))]
    seed: Option<u64>,
    /// Worker threads (default: all cores). The file does not depend on it.
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::threads)]
    threads: Option<usize>,
    /// Bake passes of one sample per line until this many seconds are spent (--spp then caps it).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = values::seconds)]
    time: Option<Duration>,
    /// No progress bar and no summary (the size estimate too).
    #[arg(long, short)]
    quiet: bool,
}

pub(crate) fn run_slab(args: SlabArgs) -> Result<i32> {
    match args.command {
        SlabCommand::Bake(b) => run_bake(&b),
    }
}

fn run_bake(args: &BakeArgs) -> Result<i32> {
    // Before the scene's volumes are loaded: a refused run does no work.
    let mut plan = Plan::new("bake");
    brume::scene::inputs::add_to_plan(&mut plan, &args.scene, &args.set)?;
    plan.output("--out", &args.out, None);
    plan.check()?;
    let loaded = brume::scene::load_frame_with_overrides(&args.scene, None, &args.set)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    let spec = loaded.slab.ok_or_else(|| Error::Scene {
        file: args.scene.clone(),
        field: "slab".into(),
        message: "missing: brume slab bake needs a [slab] table with min and max (the box to bake)"
            .into(),
    })?;
    let scene = loaded.scene;
    let spp = args.spp.unwrap_or(scene.settings.spp);
    let header = SlabHeader {
        bounds: spec.bounds,
        grid: spec.grid,
        spp,
        seed: args.seed.unwrap_or(scene.settings.seed),
    };
    check_memory(&header, &args.scene)?;
    if !args.quiet {
        eprintln!("{}", estimate_line(&header, args.time.is_some()));
    }
    let options = RenderOptions {
        spp,
        time_budget: args.time,
        spp_is_cap: args.spp.is_some(),
        threads: args.threads,
        progress: !args.quiet && std::io::stderr().is_terminal(),
    };
    interrupt::saving(true);
    let out = bake(&scene, header, &options, interrupt::flag());
    let Some(slab) = &out.slab else {
        // Said even with --quiet: nothing was written.
        eprintln!(
            "interrupted: the bake was stopped; nothing written, {} left as it was",
            args.out.display()
        );
        return Ok(EXIT_INTERRUPTED);
    };
    brume::film::image_io::write_file_with(&args.out, |w| slab.write_to(w))?;
    if !args.quiet {
        report(&out, &args.out, slab.header());
    }
    if interrupt::requested() {
        eprintln!(
            "interrupted after the bake finished: the complete slab is in {}",
            args.out.display()
        );
        return Ok(EXIT_INTERRUPTED);
    }
    Ok(0)
}

/// The size estimate printed before baking.
fn estimate_line(h: &SlabHeader, timed: bool) -> String {
    let g = h.grid;
    let samples = match timed {
        true => "samples per line until the time is spent".to_string(),
        false => format!(
            "{} spp = {:.3e} path samples",
            h.spp,
            g.records() as f64 * h.spp as f64
        ),
    };
    format!(
        "slab: 6 slabs x {}^2 positions x {}^2 slopes = {} lines, file {}, {samples}",
        g.spatial,
        g.angular,
        g.records(),
        brume::error::limits::format_bytes(h.file_bytes() as u128),
    )
}

/// Refuses a bake whose sums and records exceed the memory limit, before any allocation.
fn check_memory(h: &SlabHeader, scene: &Path) -> Result<()> {
    let bytes = bake_peak_bytes(h.grid.records());
    brume::error::limits::check(bytes).map_err(|refusal| Error::Scene {
        file: scene.to_path_buf(),
        field: "slab.spatial".into(),
        message: format!(
            "a bake of {} x {} nodes needs {} of memory, {refusal}",
            h.grid.spatial,
            h.grid.angular,
            brume::error::limits::format_bytes(bytes)
        ),
    })
}

fn report(out: &brume::render::slab_bake::BakeOutput, path: &Path, h: &SlabHeader) {
    eprintln!(
        "baked {} lines at {} spp in {:.2} s -> {} ({})",
        h.grid.records(),
        out.spp,
        out.elapsed.as_secs_f64(),
        path.display(),
        brume::error::limits::format_bytes(h.file_bytes() as u128)
    );
    if out.nonfinite > 0 {
        eprintln!(
            "warning: {} NaN/infinite samples were left out of the slab",
            out.nonfinite
        );
    }
    if out.clamped > 0 {
        eprintln!(
            "warning: {} recorded values exceeded the half-float range and were clamped to 65504",
            out.clamped
        );
    }
}
