//! `brume airlight`: the airlight demo (targets fading with distance in haze).

use brume::error::Result;
use brume::render::cli_values as values;
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct AirlightArgs {
    /// Output folder for airlight.exr/.png, airlight.csv, airlight_plot.png and airlight.toml.
    #[arg(long, default_value = "airlight")]
    out: PathBuf,
    /// Meteorological visual range in metres (sigma_t = ln 50 / visibility).
    #[arg(long, allow_negative_numbers = true, value_name = "METRES", default_value = "1000", value_parser = visibility)]
    visibility: f32,
    /// Samples per pixel.
    #[arg(long, allow_negative_numbers = true, value_name = "N", default_value = "64", value_parser = values::whole(1u32, u32::MAX))]
    spp: u32,
    /// Image width in pixels (height = width / 5).
    #[arg(long, allow_negative_numbers = true, value_name = "PIXELS", default_value = "768", value_parser = values::whole(64u32, 32768))]
    width: u32,
    /// Emission–absorption air and emissive targets, where Koschmieder's law is exact.
    #[arg(long, conflicts_with = "single")]
    exact: bool,
    /// A zenith sun over a scattering slab with single scattering only, where Koschmieder's law is exact too.
    #[arg(long)]
    single: bool,
    /// Worker threads (default: all cores).
    #[arg(long, allow_negative_numbers = true, value_name = "N", value_parser = values::threads)]
    threads: Option<usize>,
}

/// `airlight --visibility`: from a millimetre to a million kilometres, so that
/// sigma_t = ln 50 / visibility stays a normal number in the demo's scene.
fn visibility(text: &str) -> values::Parsed<f32> {
    values::decimal(1e-3, 1e9, "metres")(text).map(|v| v as f32)
}

pub(crate) fn run_airlight(args: AirlightArgs) -> Result<i32> {
    use brume::airlight::{AirlightMode, AirlightOptions};
    let report = brume::airlight::run(&AirlightOptions {
        out: Some(args.out),
        visibility: args.visibility,
        spp: args.spp,
        width: args.width,
        mode: if args.exact {
            AirlightMode::EmissionAbsorption
        } else if args.single {
            AirlightMode::SingleScattering
        } else {
            AirlightMode::Sky
        },
        seed: 0,
        threads: args.threads,
        progress: std::io::stderr().is_terminal(),
    })?;
    print!("{}", report.table);
    println!("rendered in {:.2} s", report.render_seconds);
    for f in &report.files {
        println!("wrote {}", f.display());
    }
    Ok(0)
}
