//! `brume info`: a text or JSON report of a VDB file's grids.

use std::fmt::Write as _;
use std::path::Path;

use glam::{DVec3, IVec3};
use serde_json::{json, Value};

use super::{AnyGrid, GridTransform, VdbFile, VolumeError};

/// Describes every grid of a file: type, transform, active voxels, bounds,
/// value range and memory once loaded. Grids that cannot be loaded are
/// listed with the reason; only an unreadable file is an error.
pub fn info_report(path: &Path, json: bool) -> Result<String, VolumeError> {
    let file = VdbFile::open(path)?;
    let grids: Vec<Value> = file.grids().iter().map(|d| grid_json(&file, d)).collect();
    let report = json!({
        "file": path.display().to_string(),
        "file_format_version": file.file_version(),
        "library_version": [file.library_version().0, file.library_version().1],
        "grids": grids,
    });
    if json {
        return Ok(serde_json::to_string_pretty(&report).unwrap_or_default());
    }
    Ok(render_text(&report))
}

fn ivec(v: IVec3) -> Value {
    json!([v.x, v.y, v.z])
}

fn dvec(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// World box of the cells of an inclusive index box (voxel centres ±0.5).
fn world_bbox(transform: &GridTransform, (lo, hi): (IVec3, IVec3)) -> (DVec3, DVec3) {
    let (a, b) = (lo.as_dvec3() - 0.5, hi.as_dvec3() + 0.5);
    let mut min = DVec3::INFINITY;
    let mut max = DVec3::NEG_INFINITY;
    for c in 0..8 {
        let p = DVec3::new(
            if c & 1 == 0 { a.x } else { b.x },
            if c & 2 == 0 { a.y } else { b.y },
            if c & 4 == 0 { a.z } else { b.z },
        );
        let w = transform.index_to_world(p);
        min = min.min(w);
        max = max.max(w);
    }
    (min, max)
}

fn grid_json(file: &VdbFile, d: &super::GridDescriptor) -> Value {
    let mut g = json!({
        "name": d.name,
        "grid_type": d.grid_type,
        "value_type": d.value_type,
        "saved_as_half": d.half,
    });
    if let Ok(h) = file.grid_header(&d.name) {
        g["class"] = json!(h.meta("class").unwrap_or("unknown"));
        g["compression"] = json!(compression_names(h.compression));
    }
    match file.load_grid(&d.name) {
        Err(e) => g["error"] = json!(e.to_string()),
        Ok(AnyGrid::Float(grid)) => {
            let facts = Facts {
                transform: grid.transform(),
                active: grid.active_voxel_count(),
                leaves: grid.leaf_count(),
                tiles: grid.active_tile_count(),
                bbox: grid.index_bbox_active(),
                bytes: grid.memory_bytes(),
            };
            facts.write(&mut g);
            g["background"] = num(grid.background());
            let (lo, hi) = grid.value_range();
            g["value_range"] = json!([num(lo), num(hi)]);
            write_census(&mut g, &[grid.value_census()]);
        }
        Ok(AnyGrid::Vec3(grid)) => {
            let facts = Facts {
                transform: grid.transform(),
                active: grid.active_voxel_count(),
                leaves: grid.leaf_count(),
                tiles: grid.active_tile_count(),
                bbox: grid.index_bbox_active(),
                bytes: grid.memory_bytes(),
            };
            facts.write(&mut g);
            g["background"] = json!(grid.background().to_array().map(num));
            let ranges = grid.component_ranges();
            g["component_ranges"] = json!(ranges.map(|(lo, hi)| [num(lo), num(hi)]));
            g["max_abs_lookup"] = json!(grid.max_abs_lookup().to_array().map(num));
            let census = [0, 1, 2].map(|axis| grid.component(axis).value_census());
            write_census(&mut g, &census);
        }
    }
    g
}

/// What every loaded grid reports, whatever its value type.
struct Facts<'a> {
    transform: &'a GridTransform,
    active: u64,
    leaves: usize,
    tiles: usize,
    bbox: Option<(IVec3, IVec3)>,
    bytes: usize,
}

impl Facts<'_> {
    fn write(&self, g: &mut Value) {
        let t = self.transform;
        let m = t.index_to_world_matrix();
        let rows: Vec<Value> = (0..4).map(|r| json!(m.row(r).to_array())).collect();
        g["transform"] = json!({
            "map_type": t.map_type(),
            "voxel_size": dvec(t.voxel_size()),
            "index_to_world": rows,
        });
        g["active_voxel_count"] = json!(self.active);
        g["leaf_count"] = json!(self.leaves);
        g["active_tile_count"] = json!(self.tiles);
        if let Some(bb) = self.bbox {
            let (wmin, wmax) = world_bbox(t, bb);
            g["index_bbox_active"] = json!({"min": ivec(bb.0), "max": ivec(bb.1)});
            g["world_bbox"] = json!({"min": dvec(wmin), "max": dvec(wmax)});
        }
        g["memory_bytes"] = json!(self.bytes);
        g["bytes_per_active_voxel"] = json!(self.bytes as f64 / self.active.max(1) as f64);
    }
}

/// Value counts (summed over a vec3 grid's components): stored, NaN, infinite, negative.
fn write_census(g: &mut Value, census: &[super::ValueCensus]) {
    let sum = |f: fn(&super::ValueCensus) -> u64| census.iter().map(f).sum::<u64>();
    g["stored_values"] = json!(sum(|c| c.stored));
    g["nan_values"] = json!(sum(|c| c.nan));
    g["infinite_values"] = json!(sum(|c| c.pos_inf + c.neg_inf));
    g["negative_values"] = json!(sum(|c| c.negative));
}

/// A number, or its name ("inf", "-inf", "NaN") where JSON has none (it would print null).
fn num(v: f32) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        json!(v.to_string())
    }
}

/// A JSON value as text, strings without their quotes.
fn plain(v: &Value) -> String {
    match v.as_str() {
        Some(s) => s.to_string(),
        None => v.to_string(),
    }
}

fn compression_names(c: u32) -> String {
    let names: Vec<&str> = [(1, "zip"), (4, "blosc"), (2, "active mask")]
        .iter()
        .filter(|(bit, _)| c & bit != 0)
        .map(|(_, n)| *n)
        .collect();
    if names.is_empty() {
        "none".into()
    } else {
        names.join(" + ")
    }
}

fn render_text(r: &Value) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "file: {}", r["file"].as_str().unwrap_or(""));
    let _ = writeln!(
        s,
        "format: OpenVDB file version {}, library {}.{}",
        r["file_format_version"], r["library_version"][0], r["library_version"][1]
    );
    let grids = r["grids"].as_array().cloned().unwrap_or_default();
    let _ = writeln!(s, "grids: {}", grids.len());
    for g in &grids {
        grid_text(&mut s, g);
    }
    s
}

/// A JSON value as text, with a space after each comma.
fn spaced(x: &Value) -> String {
    x.to_string().replace(',', ", ")
}

/// One grid's section of the text report: kind, then (if it loaded) placement and values.
fn grid_text(s: &mut String, g: &Value) {
    let name = g["name"].as_str().unwrap_or("");
    let half = if g["saved_as_half"] == json!(true) {
        ", stored as half"
    } else {
        ""
    };
    let _ = writeln!(s, "\ngrid '{name}'");
    let _ = writeln!(
        s,
        "  type: {} ({}{half})",
        g["value_type"].as_str().unwrap_or(""),
        g["grid_type"].as_str().unwrap_or("")
    );
    if let Some(c) = g["class"].as_str() {
        let comp = g["compression"].as_str().unwrap_or("");
        let _ = writeln!(s, "  class: {c}, compression: {comp}");
    }
    if let Some(e) = g["error"].as_str() {
        let _ = writeln!(s, "  not loadable: {e}");
        return;
    }
    grid_placement_text(s, g);
    grid_values_text(s, g);
}

/// Transform, background, voxel and leaf counts, bounding boxes.
fn grid_placement_text(s: &mut String, g: &Value) {
    let t = &g["transform"];
    let _ = writeln!(
        s,
        "  transform: {}, voxel size {}",
        t["map_type"].as_str().unwrap_or(""),
        spaced(&t["voxel_size"])
    );
    for row in t["index_to_world"].as_array().into_iter().flatten() {
        let _ = writeln!(s, "    {}", spaced(row));
    }
    let _ = writeln!(s, "  background: {}", plain(&g["background"]));
    let _ = writeln!(s, "  active voxels: {}", g["active_voxel_count"]);
    let _ = writeln!(
        s,
        "  leaves: {}, active tiles: {}",
        g["leaf_count"], g["active_tile_count"]
    );
    match g.get("index_bbox_active") {
        Some(bb) => {
            let _ = writeln!(
                s,
                "  index bbox: {} -> {}",
                spaced(&bb["min"]),
                spaced(&bb["max"])
            );
            let wb = &g["world_bbox"];
            let _ = writeln!(
                s,
                "  world bbox: {} -> {}",
                spaced(&wb["min"]),
                spaced(&wb["max"])
            );
        }
        None => {
            let _ = writeln!(s, "  index bbox: empty");
        }
    }
}

/// Value ranges, value counts by kind, memory.
fn grid_values_text(s: &mut String, g: &Value) {
    if let Some(r) = g.get("value_range") {
        let _ = writeln!(s, "  value range: {} .. {}", plain(&r[0]), plain(&r[1]));
    }
    if let Some(r) = g["component_ranges"].as_array() {
        for (axis, range) in ["x", "y", "z"].iter().zip(r) {
            let _ = writeln!(
                s,
                "  {axis} range: {} .. {}",
                plain(&range[0]),
                plain(&range[1])
            );
        }
        let _ = writeln!(
            s,
            "  largest |component| a lookup returns: {}",
            spaced(&g["max_abs_lookup"])
        );
    }
    let _ = writeln!(
        s,
        "  stored values: {}, NaN: {}, infinite: {}, negative: {}",
        g["stored_values"], g["nan_values"], g["infinite_values"], g["negative_values"]
    );
    let _ = writeln!(
        s,
        "  memory: {} bytes ({:.2} bytes per active voxel)",
        g["memory_bytes"],
        g["bytes_per_active_voxel"].as_f64().unwrap_or(0.0)
    );
}
