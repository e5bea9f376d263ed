//! brume's reader agrees with OpenVDB on the animated test plume
//! (tests/data/anim, made by make_anim_plume.py with OpenVDB 10.0.1): the
//! `vel` vec3s grid and the `density` float grid of every frame, full and
//! half float, against the sidecars OpenVDB computed: counts, bounds,
//! per-component ranges, voxel probes and BoxSampler values at world points.

use std::path::{Path, PathBuf};

use brume::volume::{info_report, VdbFile};
use glam::{DVec3, IVec3, Vec3};
use serde_json::Value;

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/anim")
}

fn files() -> Vec<PathBuf> {
    [
        "plume.0001.vdb",
        "plume.0002.vdb",
        "plume.0003.vdb",
        "plume_half.vdb",
    ]
    .iter()
    .map(|f| data().join(f))
    .collect()
}

fn sidecar(vdb: &Path) -> Value {
    let text = std::fs::read_to_string(vdb.with_extension("vdb.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn ivec(v: &Value) -> IVec3 {
    let c = |i: usize| v[i].as_i64().unwrap() as i32;
    IVec3::new(c(0), c(1), c(2))
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Values brume must reproduce: voxel values exactly (f32), trilinear values
/// to the rounding of an f32 BoxSampler against OpenVDB's double sums.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(1.0)
}

#[test]
fn vec3_velocity_grids_match_openvdb() {
    for path in files() {
        let side = sidecar(&path);
        let file = VdbFile::open(&path).unwrap();
        let g = side["grids"]
            .as_array()
            .unwrap()
            .iter()
            .find(|g| g["name"] == "vel")
            .unwrap();
        let vel = file.load_vec3_grid("vel").unwrap();
        let name = path.display();
        assert_eq!(
            vel.active_voxel_count(),
            g["active_voxel_count"].as_u64().unwrap(),
            "{name}"
        );
        assert_eq!(
            vel.leaf_count() as u64,
            g["leaf_count"].as_u64().unwrap(),
            "{name}"
        );
        let bb = &g["index_bbox_active"];
        assert_eq!(
            vel.index_bbox_active(),
            Some((ivec(&bb["min"]), ivec(&bb["max"]))),
            "{name}"
        );
        let bg = floats(&g["background"]);
        assert_eq!(
            vel.background(),
            Vec3::new(bg[0] as f32, bg[1] as f32, bg[2] as f32)
        );
        let (lo, hi) = (floats(&g["component_min"]), floats(&g["component_max"]));
        for (axis, (a, b)) in vel.component_ranges().iter().enumerate() {
            assert_eq!(
                (*a, *b),
                (lo[axis] as f32, hi[axis] as f32),
                "{name} axis {axis}"
            );
        }
        let bound = vel.max_abs_lookup();
        assert!(bound.length() as f64 >= g["max_magnitude"].as_f64().unwrap() * (1.0 - 1e-7));
        for probe in g["voxel_probes"].as_array().unwrap() {
            let ijk = ivec(&probe["ijk"]);
            let want = floats(&probe["value"]);
            let got = vel.value(ijk);
            for axis in 0..3 {
                assert_eq!(
                    got[axis], want[axis] as f32,
                    "{name} voxel {ijk} axis {axis}"
                );
            }
            assert_eq!(
                vel.is_active(ijk),
                probe["active"].as_bool().unwrap(),
                "{name} {ijk}"
            );
        }
        for sample in g["samples"].as_array().unwrap() {
            let w = floats(&sample["world"]);
            let want = floats(&sample["trilinear_value"]);
            let got = vel.trilinear_world(DVec3::new(w[0], w[1], w[2]));
            for axis in 0..3 {
                assert!(
                    close(got[axis] as f64, want[axis]),
                    "{name} trilinear at {w:?} axis {axis}: {} vs {}",
                    got[axis],
                    want[axis]
                );
            }
        }
    }
}

#[test]
fn density_grids_of_the_plume_frames_match_openvdb() {
    for path in files() {
        let side = sidecar(&path);
        let g = side["grids"]
            .as_array()
            .unwrap()
            .iter()
            .find(|g| g["name"] == "density")
            .unwrap();
        let density = VdbFile::open(&path)
            .unwrap()
            .load_float_grid("density")
            .unwrap();
        let name = path.display();
        assert_eq!(
            density.active_voxel_count(),
            g["active_voxel_count"].as_u64().unwrap()
        );
        let (lo, hi) = density.value_range();
        assert_eq!(lo, floats(&g["component_min"])[0] as f32, "{name}");
        assert_eq!(hi, floats(&g["component_max"])[0] as f32, "{name}");
        for probe in g["voxel_probes"].as_array().unwrap() {
            let ijk = ivec(&probe["ijk"]);
            assert_eq!(
                density.value(ijk),
                floats(&probe["value"])[0] as f32,
                "{name} {ijk}"
            );
        }
        for sample in g["samples"].as_array().unwrap() {
            let w = floats(&sample["world"]);
            let got = density.trilinear_world(DVec3::new(w[0], w[1], w[2]));
            assert!(
                close(got as f64, floats(&sample["trilinear_value"])[0]),
                "{name} {w:?}"
            );
        }
    }
}

#[test]
fn a_vec3_grid_is_not_a_density_and_info_lists_it() {
    let path = data().join("plume.0001.vdb");
    let file = VdbFile::open(&path).unwrap();
    let err = file.load_float_grid("vel").unwrap_err().to_string();
    assert!(err.contains("vel") && err.contains("vec3"), "{err}");
    let err = file.load_vec3_grid("density").unwrap_err().to_string();
    assert!(
        err.contains("density") && err.contains("float grid"),
        "{err}"
    );
    let text = info_report(&path, false).unwrap();
    assert!(
        text.contains("type: vec3s")
            && text.contains("y range: 0.6000000238418579 .. 0.6000000238418579"),
        "{text}"
    );
    assert!(!text.contains("not loadable"), "{text}");
    let json: Value = serde_json::from_str(&info_report(&path, true).unwrap()).unwrap();
    let vel = &json["grids"][1];
    assert_eq!(vel["name"], "vel");
    assert_eq!(vel["active_voxel_count"], 1769);
}
