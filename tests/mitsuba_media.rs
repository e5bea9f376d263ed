//! Heterogeneous media from Mitsuba 3: the `.vol` reader against values a
//! small generator writes, its refusals of damaged files, `type = "vol"`
//! media against closed forms, and `<medium type="heterogeneous">` imported
//! into the same description a user would write (rendered bit for bit).

mod common;
mod twin_support;

use brume::math::color::Rgb;
use brume::math::{Ray, Vec3};
use brume::scene::description::{BoundsDesc, MediumDesc, PhaseDesc};
use brume::volume::VolFile;
use common::{assert_estimate, estimate_ray, scene_from_str, SceneText};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// Writes a version-3 float32 `.vol` file: `value(x, y, z, c)` for each cell and channel.
fn write_vol(
    path: &Path,
    res: [usize; 3],
    channels: usize,
    bbox: [f32; 6],
    value: impl Fn(usize, usize, usize, usize) -> f32,
) {
    let mut b = b"VOL".to_vec();
    b.push(3);
    for v in [1, res[0], res[1], res[2], channels] {
        b.extend_from_slice(&(v as i32).to_le_bytes());
    }
    for v in bbox {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for z in 0..res[2] {
        for y in 0..res[1] {
            for x in 0..res[0] {
                for c in 0..channels {
                    b.extend_from_slice(&value(x, y, z, c).to_le_bytes());
                }
            }
        }
    }
    std::fs::write(path, b).unwrap();
}

/// A made-up value per cell and channel (distinct everywhere).
fn pattern(x: usize, y: usize, z: usize, c: usize) -> f32 {
    1.0 + x as f32 + 10.0 * y as f32 + 100.0 * z as f32 + 0.25 * c as f32
}

#[test]
fn the_vol_reader_returns_the_values_the_generator_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.vol");
    let bbox = [-1.0, 0.0, 2.0, 1.0, 3.0, 6.0];
    write_vol(&path, [3, 4, 5], 3, bbox, pattern);
    let v = VolFile::read(&path).unwrap();
    assert_eq!((v.res, v.channels), ([3, 4, 5], 3));
    assert_eq!(v.bbox, [[-1.0, 0.0, 2.0], [1.0, 3.0, 6.0]]);
    for (x, y, z, c) in [(0, 0, 0, 0), (2, 1, 3, 2), (1, 3, 4, 1), (2, 3, 4, 2)] {
        assert_eq!(
            v.value(x, y, z, c),
            pattern(x, y, z, c),
            "cell {x},{y},{z}/{c}"
        );
    }
    // A channel as a grid: voxel centres at (i + 0.5)/res of the box, clamped at the edges.
    let t = v.index_to_local(true).unwrap();
    let g = v.channel_grid(Some(1), t.clone()).unwrap();
    let local = |i: [f64; 3]| t.index_to_world(DVec3::from_array(i));
    assert_eq!(local([0.0; 3]), DVec3::new(-1.0 + 1.0 / 3.0, 0.375, 2.4));
    let at = |x: f32, y: f32, z: f32| g.trilinear_index(Vec3::new(x, y, z));
    assert_eq!(at(2.0, 1.0, 3.0), pattern(2, 1, 3, 1));
    assert_eq!(
        at(0.5, 0.0, 0.0),
        0.5 * (pattern(0, 0, 0, 1) + pattern(1, 0, 0, 1))
    );
    assert_eq!(at(-0.5, -0.5, -0.5), pattern(0, 0, 0, 1), "clamped below");
    assert_eq!(at(2.5, 3.5, 4.5), pattern(2, 3, 4, 1), "clamped above");
    let max = v.channel_grid(None, t).unwrap();
    assert_eq!(
        max.trilinear_index(Vec3::new(1.0, 2.0, 3.0)),
        pattern(1, 2, 3, 2)
    );
}

/// The one-line error for `bytes` as a `.vol` file.
fn vol_error(bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.vol");
    std::fs::write(&path, bytes).unwrap();
    let e = VolFile::read(&path).unwrap_err().to_string();
    assert!(e.contains(&path.display().to_string()), "{e}");
    assert!(!e.contains('\n'), "{e}");
    e
}

#[test]
fn damaged_vol_files_are_refused_by_name_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("g.vol");
    write_vol(&good, [2, 2, 2], 1, [0.0, 0.0, 0.0, 1.0, 1.0, 1.0], pattern);
    let bytes = std::fs::read(&good).unwrap();
    let e = vol_error(&bytes[..bytes.len() - 1]);
    assert!(e.contains("holds 79 bytes"), "truncated: {e}");
    let e = vol_error(&bytes[..20]);
    assert!(e.contains("shorter than the 48-byte header"), "{e}");
    let mut v2 = bytes.clone();
    v2[3] = 2;
    assert!(vol_error(&v2).contains("version 2"));
    let mut enc = bytes.clone();
    enc[4] = 2;
    assert!(vol_error(&enc).contains("encoding 2"));
    // 2³¹-1 cells per axis declared in a file of 80 bytes: refused on the
    // length, long before anything that size is allocated.
    let mut huge = bytes.clone();
    for axis in 0..3 {
        huge[8 + 4 * axis..12 + 4 * axis].copy_from_slice(&i32::MAX.to_le_bytes());
    }
    let e = vol_error(&huge);
    assert!(e.contains("2147483647×2147483647×2147483647×1"), "{e}");
    let mut six = bytes.clone();
    six[20] = 6;
    assert!(vol_error(&six).contains("6 channels"));
    let mut magic = bytes.clone();
    magic[..3].copy_from_slice(b"VDB");
    assert!(vol_error(&magic).contains("does not start with 'VOL'"));
}

/// A scene with an environment of 1 and `medium` (TOML lines of one `[[medium]]`).
fn scene_with(medium: &str) -> brume::integrator::Scene {
    let text = SceneText::furnace_view(2)
        .depths(100000, 100000)
        .environment(1.0)
        .medium(medium)
        .build();
    scene_from_str(&text)
}

/// Along +z through x = y = 0.5 of the unit cube: the optical depth of a
/// grid of `values` along z (voxel centres at (k + 0.5)/n, linear between,
/// clamped in the outer half voxels) times `scale`, by the trapezoid rule (exact here).
fn optical_depth_along_z(values: &[f64], scale: f64) -> f64 {
    let n = values.len() as f64;
    let inner: f64 = values.windows(2).map(|w| 0.5 * (w[0] + w[1]) / n).sum();
    scale * (inner + 0.5 / n * (values[0] + values[values.len() - 1]))
}

#[test]
fn an_absorbing_rgb_grid_transmits_its_closed_form_optical_depth() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ramp.vol");
    // Constant across x and y, a different ramp along z per channel.
    let value = |_: usize, _: usize, z: usize, c: usize| (1 + z) as f32 * [0.2, 0.5, 0.9][c];
    write_vol(&path, [2, 3, 6], 3, [0.0; 6], value);
    let scene = scene_with(&format!(
        "type = \"vol\"\nsigma_t_file = {:?}\nscale = 1.5\nalbedo = 0.0\n\
         transform = {{ translate = [-0.5, -0.5, -0.5] }}",
        path.display().to_string()
    ));
    let ray = Ray::new(Vec3::new(0.1, -0.2, -3.0), Vec3::Z);
    let est = estimate_ray(&scene, ray, 40_000, 5);
    let expected = [0, 1, 2].map(|c| {
        let column: Vec<f64> = (0..6).map(|z| value(0, 0, z, c) as f64).collect();
        (-optical_depth_along_z(&column, 1.5)).exp()
    });
    assert_estimate(&est, expected, "RGB .vol absorber along z");
    // Across the ramp at fixed z: σt is the interpolated value there (one
    // ray between voxel centres, one in the clamped outer half voxel).
    for (z_local, seed) in [(0.3f64, 6), (0.04, 7)] {
        let ray = Ray::new(Vec3::new(-3.0, 0.2, z_local as f32 - 0.5), Vec3::X);
        let est = estimate_ray(&scene, ray, 40_000, seed);
        let q = (z_local * 6.0 - 0.5).clamp(0.0, 5.0);
        let (k, f) = (q.floor() as usize, q.fract());
        let expected = [0, 1, 2].map(|c| {
            let v = |z: usize| value(0, 0, z.min(5), c) as f64;
            (-1.5 * ((1.0 - f) * v(k) + f * v(k + 1))).exp()
        });
        assert_estimate(
            &est,
            expected,
            &format!("RGB .vol absorber across z = {z_local}"),
        );
    }
}

/// A σt grid of constant `st` and an albedo grid of constant `al` (1 or 3
/// channels) against the homogeneous medium of the same box, along one ray.
fn constant_grid_against_homogeneous(st: [f32; 3], al: &[f32], seed: u64) {
    let dir = tempfile::tempdir().unwrap();
    let sigma = dir.path().join("s.vol");
    let albedo = dir.path().join("a.vol");
    let box_ = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0];
    write_vol(&sigma, [3, 2, 4], 3, box_, |_, _, _, c| st[c]);
    write_vol(&albedo, [2, 2, 2], al.len(), box_, |_, _, _, c| al[c]);
    let grid = scene_with(&format!(
        "type = \"vol\"\nsigma_t_file = {:?}\nalbedo_file = {:?}\nuse_grid_bbox = true\n\
         phase = {{ type = \"hg\", g = 0.4 }}",
        sigma.display().to_string(),
        albedo.display().to_string()
    ));
    let al3 = [0, 1, 2].map(|c| al[c % al.len()]);
    let homogeneous = scene_with(&format!(
        "type = \"homogeneous\"\nsigma_t = {st:?}\nalbedo = {al3:?}\n\
         bounds = {{ type = \"box\", min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, 1.0] }}\n\
         phase = {{ type = \"hg\", g = 0.4 }}"
    ));
    // An albedo grid keeps the sky's light samples; the homogeneous twin takes
    // the sky as a control variate: two estimators of one mean.
    assert!(grid.sky_control.is_none() && homogeneous.sky_control.is_some());
    let ray = Ray::new(
        Vec3::new(0.2, 0.1, -4.0),
        Vec3::new(0.05, 0.0, 1.0).normalize(),
    );
    let a = estimate_ray(&grid, ray, 60_000, seed);
    let b = estimate_ray(&homogeneous, ray, 60_000, seed + 1);
    common::assert_same(
        &a,
        &b,
        &format!("constant .vol medium (albedo {al:?}) vs homogeneous"),
    );
    assert!(
        a.mean.iter().all(|&v| v < 0.95),
        "the medium must dim the environment: {:?}",
        a.mean
    );
}

/// An RGB σt grid with a constant albedo: the albedo is known everywhere,
/// so under a sky alone the sky is a control variate (module
/// `integrator::sky_control`), as for a homogeneous medium.
#[test]
fn a_sigma_t_grid_with_a_constant_albedo_takes_the_sky_as_a_control() {
    let dir = tempfile::tempdir().unwrap();
    let sigma = dir.path().join("s.vol");
    write_vol(
        &sigma,
        [3, 2, 4],
        3,
        [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0],
        pattern,
    );
    let scene = scene_with(&format!(
        "type = \"vol\"\nsigma_t_file = {:?}\nalbedo = 0.6\nuse_grid_bbox = true",
        sigma.display().to_string()
    ));
    assert!(scene.sky_control.is_some());
}

#[test]
fn a_constant_grid_medium_matches_the_homogeneous_one() {
    constant_grid_against_homogeneous([0.8, 1.6, 2.4], &[0.9, 0.5, 0.2], 11);
    constant_grid_against_homogeneous([1.2, 0.7, 2.0], &[0.6], 21);
}

/// A `.vol`-backed medium in a cube: σt RGB grid and a grey albedo grid.
fn write_smoke(dir: &Path) {
    let density = |x: usize, y: usize, z: usize, c: usize| {
        let r =
            ((x as f32 - 2.0).powi(2) + (y as f32 - 1.5).powi(2) + (z as f32 - 2.5).powi(2)).sqrt();
        (3.0 - r).max(0.0) * [1.0, 0.7, 0.4][c]
    };
    write_vol(&dir.join("smoke.vol"), [5, 4, 6], 3, [0.0; 6], density);
    let albedo = |x: usize, y: usize, z: usize, _: usize| 0.3 + 0.2 * ((x + y + z) % 3) as f32;
    write_vol(&dir.join("albedo.vol"), [3, 3, 3], 1, [0.0; 6], albedo);
}

const SMOKE_XML: &str = r#"<scene version="3.0.0">
  <integrator type="volpath"><integer name="max_depth" value="9"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 1, 5" target="0, 0.5, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <medium type="heterogeneous" id="smoke">
    <volume name="sigma_t" type="gridvolume">
      <string name="filename" value="smoke.vol"/>
      <transform name="to_world"><scale value="2"/><translate x="-1" y="-0.5" z="-1"/></transform>
    </volume>
    <volume name="albedo" type="gridvolume">
      <string name="filename" value="albedo.vol"/>
      <transform name="to_world"><scale value="2"/><translate x="-1" y="-0.5" z="-1"/></transform>
    </volume>
    <float name="scale" value="2.5"/>
    <phase type="hg"><float name="g" value="0.5"/></phase>
  </medium>
  <shape type="cube">
    <transform name="to_world"><translate y="0.5"/></transform>
    <bsdf type="null"/>
    <ref name="interior" id="smoke"/>
  </shape>
  <emitter type="constant"><rgb name="radiance" value="0.5, 0.6, 0.8"/></emitter>
  <emitter type="point"><point name="position" x="2" y="3" z="1"/><rgb name="intensity" value="10"/></emitter>
</scene>"#;

/// What the importer must make of `SMOKE_XML`: the user's TOML.
const SMOKE_TOML: &str = r#"[camera]
position = [0.0, 1.0, 5.0]
look_at = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
fov_axis = "x"
resolution = [24, 16]

[integrator]
spp = 8
sampler = "independent"
max_depth = 8

[[shape]]
type = "box"
center = [0.0, 0.0, 0.0]
size = [2.0, 2.0, 2.0]
transform = { translate = [0.0, 0.5, 0.0] }
interior = { type = "vol", sigma_t_file = "smoke.vol", albedo_file = "albedo.vol", scale = 2.5, phase = { type = "hg", g = 0.5 }, transform = { translate = [-1.0, -0.5, -1.0], scale = 2.0 } }

[[light]]
type = "environment"
radiance = [0.5, 0.6, 0.8]

[[light]]
type = "point"
position = [2.0, 3.0, 1.0]
intensity = 10.0
"#;

/// The pixels of `scene` (with its seed moved by `offset`), as bits; never all black.
fn render_bits(scene: &Path, offset: u64) -> Vec<[u32; 3]> {
    let pixels = twin_support::render(scene, offset);
    assert!(pixels.iter().any(|p: &Rgb| p.max_channel() > 0.0));
    twin_support::bits(&pixels)
}

#[test]
fn a_heterogeneous_scene_renders_like_its_toml_twin() {
    let dir = tempfile::tempdir().unwrap();
    write_smoke(dir.path());
    let xml = dir.path().join("smoke.xml");
    let toml = dir.path().join("smoke.toml");
    std::fs::write(&xml, SMOKE_XML).unwrap();
    std::fs::write(&toml, SMOKE_TOML).unwrap();
    let a = render_bits(&xml, 0);
    assert_eq!(a, render_bits(&toml, 0), "XML and TOML twin differ");
    assert_ne!(
        a,
        render_bits(&xml, 1),
        "another seed renders the same bits"
    );
}

/// Imports `medium` (an XML `<medium id="m">`) inside a null cube, in a folder holding smoke.vol.
fn import_medium(medium: &str) -> brume::error::Result<MediumDesc> {
    let dir = tempfile::tempdir().unwrap();
    write_smoke(dir.path());
    let text = format!(
        r#"<scene version="3.0.0"><sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform></sensor>{medium}
<shape type="cube"><bsdf type="null"/><ref name="interior" id="m"/></shape></scene>"#
    );
    let path = dir.path().join("m.xml");
    std::fs::write(&path, text).unwrap();
    let imported = brume::scene::mitsuba::import(&path, Vec::new())?;
    Ok(imported
        .desc
        .shapes
        .into_iter()
        .next()
        .unwrap()
        .interior
        .unwrap())
}

const GRID: &str =
    r#"<volume name="sigma_t" type="gridvolume"><string name="filename" value="smoke.vol"/>"#;

#[test]
fn heterogeneous_media_import_with_mitsubas_defaults_and_parameters() {
    let m = import_medium(&format!(
        r#"<medium type="heterogeneous" id="m">{GRID}</volume></medium>"#
    ));
    let MediumDesc::Vol(v) = m.unwrap() else {
        panic!("not a vol medium")
    };
    assert!(v.sigma_t_file.ends_with("smoke.vol"));
    assert_eq!((v.scale, v.use_grid_bbox), (Some(1.0), false));
    assert_eq!(
        v.albedo.map(|c| c.0),
        Some([0.75; 3]),
        "Mitsuba's default albedo"
    );
    assert!(v.albedo_file.is_none() && v.phase.is_none() && v.transform.is_none());
    let m = import_medium(&format!(
        r#"<medium type="heterogeneous" id="m">{GRID}<boolean name="use_grid_bbox" value="true"/>
        <transform name="to_world"><translate x="1"/></transform></volume>
        <volume name="albedo" type="constvolume"><rgb name="value" value="0.1, 0.2, 0.3"/></volume>
        <float name="scale" value="4"/><phase type="hg"/></medium>"#
    ));
    let MediumDesc::Vol(v) = m.unwrap() else {
        panic!("not a vol medium")
    };
    assert_eq!((v.scale, v.use_grid_bbox), (Some(4.0), true));
    assert_eq!(v.albedo.map(|c| c.0), Some([0.1, 0.2, 0.3]));
    assert_eq!(v.transform.and_then(|t| t.translate), Some([1.0, 0.0, 0.0]));
    assert!(matches!(v.phase, Some(PhaseDesc::Hg { g }) if g == 0.8));
}

#[test]
fn heterogeneous_media_outside_the_subset_are_refused_by_element() {
    let refused = |body: &str, words: &str| {
        let e = import_medium(body).expect_err("refused").to_string();
        assert!(e.contains(words) && !e.contains('\n'), "{e}");
    };
    let m = |inner: &str| format!(r#"<medium type="heterogeneous" id="m">{inner}</medium>"#);
    refused(
        &m(
            r#"<volume name="sigma_t" type="constvolume"><transform name="to_world"><rotate y="1" angle="30"/><scale value="4"/></transform></volume>"#,
        ),
        "rotates, shears or flattens",
    );
    refused(
        &m(
            r#"<volume name="albedo" type="gridvolume"><string name="filename" value="albedo.vol"/></volume>"#,
        ),
        "an albedo grid with a constant sigma_t",
    );
    refused(
        &m(&format!(
            r#"{GRID}<string name="filter_type" value="nearest"/></volume>"#
        )),
        "filter_type",
    );
    refused(
        &m(&format!(
            r#"{GRID}<string name="wrap_mode" value="repeat"/></volume>"#
        )),
        "wrap_mode",
    );
    refused(
        &m(&format!(
            r#"{GRID}</volume><volume name="albedo" type="gridvolume"><string name="filename" value="albedo.vol"/><boolean name="use_grid_bbox" value="true"/></volume>"#
        )),
        "albedo grid placed differently",
    );
    refused(
        &m(&format!(
            r#"{GRID}<float name="density" value="2"/></volume>"#
        )),
        "<float name=\"density\"",
    );
    refused(
        r#"<medium type="heterogeneous" id="m"><volume name="sigma_t" type="gridvolume"><string name="filename" value="none.vol"/></volume></medium>"#,
        "none.vol",
    );
}

/// A constant σt over a constvolume's box: inside a shape the box holds it
/// is a plain homogeneous interior (σt × scale, albedo, phase), the box's
/// corners ordered whatever the signs of the scale.
#[test]
fn a_constant_sigma_t_inside_a_shape_its_box_holds_is_a_homogeneous_interior() {
    let m = import_medium(
        r#"<medium type="heterogeneous" id="m"><volume name="sigma_t" type="constvolume"><rgb name="value" value="0.5, 1, 1.5"/>
        <transform name="to_world"><scale x="-2" y="2" z="2"/><translate x="1" y="-1" z="-1"/></transform></volume>
        <float name="albedo" value="0.6"/><float name="scale" value="3"/><phase type="hg"/></medium>"#,
    );
    let MediumDesc::Homogeneous {
        sigma_t,
        albedo,
        phase,
        bounds,
        global,
        transform,
        ..
    } = m.unwrap()
    else {
        panic!("not a homogeneous medium")
    };
    assert_eq!(sigma_t.map(|c| c.0), Some([1.5, 3.0, 4.5]));
    assert_eq!(albedo.map(|c| c.0), Some([0.6; 3]));
    assert!(matches!(phase, Some(PhaseDesc::Hg { g }) if g == 0.8));
    assert!(bounds.is_none() && !global && transform.is_none());
}

/// A constant σt whose box does not hold its shape: Mitsuba clips the
/// medium to the box, which brume's interiors cannot, so Mitsuba's
/// interface rule is kept with the medium in its box (σt 2 over the unit
/// cube [0, 1]³, inside the cube [-1, 1]³).
#[test]
fn a_constant_sigma_t_whose_box_does_not_hold_its_shape_keeps_mitsubas_rule_in_its_box() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.xml");
    std::fs::write(
        &path,
        r#"<scene version="3.0.0"><sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform></sensor>
<medium type="heterogeneous" id="m"><float name="sigma_t" value="2"/></medium>
<shape type="cube"><bsdf type="null"/><ref name="interior" id="m"/></shape></scene>"#,
    )
    .unwrap();
    let desc = brume::scene::mitsuba::import(&path, Vec::new())
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    let rule = desc.interfaces.expect("interface rule");
    assert_eq!(rule.shapes, vec![Some([Some(0), None])]);
    let [MediumDesc::Homogeneous {
        sigma_t,
        bounds: Some(BoundsDesc::Box { min, max }),
        ..
    }] = &desc.media[..]
    else {
        panic!("not one boxed homogeneous medium: {:?}", desc.media)
    };
    assert_eq!(sigma_t.map(|c| c.0), Some([2.0; 3]));
    assert_eq!((*min, *max), ([0.0; 3], [1.0; 3]));
    assert!(desc.shapes[0].interior.is_none());
}

/// Around the camera and every shape, a constant σt is a `[[medium]]`
/// bounded by the constvolume's unit cube under its `to_world`.
#[test]
fn a_constant_sigma_t_around_everything_is_bounded_by_its_volumes_box() {
    let path = twin_support::data("const_fog.xml");
    let desc = brume::scene::mitsuba::import(&path, Vec::new())
        .unwrap()
        .desc;
    let [MediumDesc::Homogeneous {
        sigma_t,
        bounds: Some(BoundsDesc::Box { min, max }),
        global: false,
        ..
    }] = &desc.media[..]
    else {
        panic!("not one bounded homogeneous medium: {:?}", desc.media)
    };
    assert_eq!(sigma_t.map(|c| c.0), Some([1.2, 0.8, 0.6]));
    assert_eq!((*min, *max), ([-1.5, 0.0, -1.0], [1.5, 1.5, 1.0]));
    assert!(desc.interfaces.is_none());
}

#[test]
fn a_constant_sigma_t_scene_renders_like_its_toml_twin() {
    twin_support::assert_twins("const_fog");
}

#[test]
fn a_damaged_vol_in_a_scene_is_named_with_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.vol");
    write_vol(&path, [2, 2, 2], 1, [0.0; 6], pattern);
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..60]).unwrap();
    let text = SceneText::furnace_view(2)
        .medium(&format!(
            "type = \"vol\"\nsigma_t_file = {:?}",
            path.display().to_string()
        ))
        .build();
    let file: PathBuf = dir.path().join("s.toml");
    let desc = brume::scene::parse(&text, &file).unwrap();
    let e = brume::scene::build(&desc, &file, dir.path())
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.contains("medium[0].sigma_t_file") && e.contains("cut.vol"),
        "{e}"
    );
}

/// The radiance of a constant emitter whose colour is `spectrum` (a `value`).
fn imported_spectrum(spectrum: &str) -> brume::error::Result<[f32; 3]> {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        r#"<scene version="3.0.0"><sensor type="perspective"/><emitter type="constant"><spectrum name="radiance" value="{spectrum}"/></emitter></scene>"#
    );
    let path = dir.path().join("s.xml");
    std::fs::write(&path, text).unwrap();
    let desc = brume::scene::mitsuba::import(&path, Vec::new())?.desc;
    match &desc.lights[0] {
        brume::scene::description::LightDesc::Environment { radiance } => Ok(radiance.0),
        other => panic!("not an environment: {other:?}"),
    }
}

#[test]
fn wavelength_lists_are_projected_through_the_cie_functions_to_linear_srgb() {
    assert_eq!(
        imported_spectrum("0.5").unwrap(),
        [0.5; 3],
        "a flat spectrum is grey"
    );
    // Equal energy over the CIE range: XYZ ≈ (½, ½, ½) (illuminant E, Y
    // normalised by ∫ȳ), whose linear sRGB is ½ · M·(1, 1, 1), M the
    // XYZ → sRGB matrix of IEC 61966-2-1 (row sums 1.2049, 0.9484, 0.9087).
    let rgb = imported_spectrum("360:0.5, 830:0.5").unwrap();
    let expected = [1.2049, 0.9484, 0.9087].map(|s: f32| 0.5 * s);
    for c in 0..3 {
        assert!(
            (rgb[c] - expected[c]).abs() < 2e-3,
            "{rgb:?} vs {expected:?}"
        );
    }
    // Zero outside the list: the blue half of the range is blue.
    let blue = imported_spectrum("380:1, 480:1").unwrap();
    assert!(blue[2] > 5.0 * blue[0].max(blue[1]).max(0.0), "{blue:?}");
    let e = imported_spectrum("500:1, 450:2").unwrap_err().to_string();
    assert!(e.contains("must increase") && e.contains("s.xml"), "{e}");
    let e = imported_spectrum("500:1, 0.3").unwrap_err().to_string();
    assert!(e.contains("`0.3` is not wavelength:value"), "{e}");
}
