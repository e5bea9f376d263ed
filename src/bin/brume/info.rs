//! `brume info FILE.vdb`: the grids of an OpenVDB file; `brume info scene.xml`:
//! what a Mitsuba 3 scene was imported as.

use brume::error::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct InfoArgs {
    /// The .vdb file (or a Mitsuba 3 .xml scene).
    file: PathBuf,
    /// Machine-readable JSON instead of text.
    #[arg(long)]
    json: bool,
}

pub(crate) fn run_info(args: InfoArgs) -> Result<i32> {
    if brume::scene::mitsuba::is_mitsuba(&args.file) {
        if args.json {
            return Err(brume::error::Error::Argument {
                argument: "--json".into(),
                message: "is for .vdb files; a Mitsuba scene's summary is text".into(),
            });
        }
        print!("{}", brume::scene::mitsuba_info(&args.file)?);
        return Ok(0);
    }
    let report = brume::volume::info_report(&args.file, args.json)?;
    print!("{report}");
    if !report.ends_with('\n') {
        println!();
    }
    // The report lists damaged grids beside the good ones; scripts still need a
    // failing exit code for a damaged file (an unsupported grid type is fine).
    let file = brume::volume::VdbFile::open(&args.file)?;
    for name in file.grid_names() {
        if let Err(e @ brume::volume::VolumeError::CorruptGrid { .. }) = file.load_grid(&name) {
            return Err(e.into());
        }
    }
    Ok(0)
}
