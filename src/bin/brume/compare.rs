//! `brume compare A.exr B.exr`: an image against a reference.

use brume::error::Result;
use brume::film::image_io;
use brume::film::output_safety::Plan;
use brume::render::cli_values as values;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct CompareArgs {
    /// The image to judge (EXR).
    a: PathBuf,
    /// The reference image (EXR).
    b: PathBuf,
    /// Write a false-colour picture of the per-pixel error here (PNG).
    #[arg(long)]
    diff: Option<PathBuf>,
    /// Exit with code 1 when the RMSE is above this (or an image holds NaN or infinity).
    #[arg(long, allow_negative_numbers = true, value_name = "X", value_parser = values::rmse)]
    max_rmse: Option<f64>,
}

pub(crate) fn run_compare(args: CompareArgs) -> Result<i32> {
    if let Some(diff) = &args.diff {
        Plan::new("comparison")
            .input("image A", &args.a)
            .input("reference B", &args.b)
            .output("--diff", diff, None)
            .check()?;
    }
    let (c, a, b) = brume::film::compare::compare_files(&args.a, &args.b)?;
    print!("{}", c.report());
    if let Some(diff) = &args.diff {
        let scale = brume::film::compare::diff_scale(&a, &b);
        let rgb = brume::film::compare::false_colour(&a, &b, scale);
        let (w, h) = c.size;
        image_io::write_png_srgb8(diff, w as u32, h as u32, &rgb)?;
        println!(
            "wrote {} (saturates at a mean |A-B| of {scale:.4e})",
            diff.display()
        );
    }
    match args.max_rmse {
        Some(_) if c.nonfinite > 0 => {
            println!("FAIL: {} non-finite channel values", c.nonfinite);
            Ok(1)
        }
        Some(m) if c.rmse > m => {
            println!("FAIL: rmse {:.6e} above --max-rmse {m:e}", c.rmse);
            Ok(1)
        }
        _ => Ok(0),
    }
}
