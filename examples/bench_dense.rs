//! Writes a float grid of an OpenVDB file as a dense array for the benchmark
//! harness (tools/bench.py), which hands it to Mitsuba's gridvolume:
//!
//!     cargo run --release --example bench_dense -- FILE GRID OUT.f32
//!
//! OUT.f32 holds little-endian f32 voxel values, x fastest, over the active
//! index box widened by one voxel each side (so the trilinear support of
//! every active voxel is inside and the border is the background). Mitsuba
//! puts texel centres at (i + 0.5)/n of its unit cube, brume (like OpenVDB)
//! at integer index coordinates, so the cube spans the index box widened by
//! half a voxel more; OUT.f32.json gives its resolution and world corners.

use std::io::Write;
use std::path::PathBuf;

use brume::volume::load_float_grid;
use glam::{DVec3, IVec3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [file, grid, out] = args.as_slice() else {
        return Err("usage: bench_dense FILE GRID OUT.f32".into());
    };
    let grid = load_float_grid(&PathBuf::from(file), grid)?;
    let (lo, hi) = grid
        .index_bbox_active()
        .ok_or("the grid has no active voxels")?;
    let (lo, hi) = (lo - IVec3::ONE, hi + IVec3::ONE);
    let res = hi - lo + IVec3::ONE;
    let mut bytes = Vec::with_capacity(res.element_product() as usize * 4);
    for z in lo.z..=hi.z {
        for y in lo.y..=hi.y {
            for x in lo.x..=hi.x {
                bytes.extend_from_slice(&grid.value(IVec3::new(x, y, z)).to_le_bytes());
            }
        }
    }
    std::fs::File::create(out)?.write_all(&bytes)?;
    let t = grid.transform();
    let w0 = t.index_to_world(lo.as_dvec3() - DVec3::splat(0.5));
    let w1 = t.index_to_world(hi.as_dvec3() + DVec3::splat(0.5));
    let json = format!(
        "{{\"resolution\": [{}, {}, {}], \"world_min\": [{}, {}, {}], \"world_max\": [{}, {}, {}], \"map\": \"{}\"}}\n",
        res.x, res.y, res.z, w0.x, w0.y, w0.z, w1.x, w1.y, w1.z, t.map_type()
    );
    std::fs::write(format!("{out}.json"), json)?;
    Ok(())
}
