//! `brume merge`: the pieces of a split render into the image of the whole.

use brume::error::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub(crate) struct MergeArgs {
    /// The pieces: EXR files written by `brume render` with --crop, --samples or --task-count.
    #[arg(required = true)]
    pieces: Vec<PathBuf>,
    /// The merged EXR.
    #[arg(long, short)]
    out: PathBuf,
    /// A PNG preview of the merged image.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Denoise the merged beauty into a `denoised` layer, guided by the merged albedo and normal
    /// (render the pieces with --denoise; needs a build with `--features denoise`).
    #[arg(long)]
    denoise: bool,
}

pub(crate) fn run_merge(args: MergeArgs) -> Result<i32> {
    let merged = brume::render::merge_pieces::merge_files(
        &args.pieces,
        &args.out,
        args.png.as_deref(),
        args.denoise,
    )?;
    for note in &merged.notes {
        eprintln!("{note}");
    }
    let p = &merged.film.provenance;
    let (w, h) = merged.film.display;
    let written = match &merged.written {
        Some(path) => path.display().to_string(),
        None => "not written".into(),
    };
    eprintln!(
        "merged {} pieces into {w}x{h} at {} spp{} -> {written}",
        args.pieces.len(),
        p.spp_held(),
        if p.complete() {
            ""
        } else {
            " (incomplete: some pieces were interrupted)"
        },
    );
    // Nothing saved (both files hold better images, said in a note above): not a success.
    Ok(if merged.written.is_some() { 0 } else { 1 })
}
