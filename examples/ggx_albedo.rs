//! Writes the albedo tables of the energy compensation of rough materials
//! (src/material/albedo.rs): every entry estimated by
//! `brume::material::albedo_estimate`, as little-endian f32.
//!
//! cargo run --release --example ggx_albedo -- src/material/ggx_albedo.bin

use std::io::Write;

fn main() -> std::io::Result<()> {
    let Some(out) = std::env::args().nth(1) else {
        eprintln!("usage: ggx_albedo OUTPUT.bin");
        std::process::exit(2);
    };
    let start = std::time::Instant::now();
    let table = brume::material::albedo_estimate::table();
    let bytes: Vec<u8> = table.iter().flat_map(|v| v.to_le_bytes()).collect();
    // Written beside the target and renamed, so a failed run leaves the old table.
    let tmp = format!("{out}.partial");
    std::fs::File::create(&tmp)?.write_all(&bytes)?;
    std::fs::rename(&tmp, &out)?;
    eprintln!(
        "{} entries in {:.1} s -> {out}",
        table.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
