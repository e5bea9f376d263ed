//! The Mitsuba 3 importer's file mechanics and unit conversions: what each
//! element and attribute becomes in brume's scene description.

use brume::scene::description::{
    CoatingTransmittanceDesc, ColorOrTexture, LightDesc, MapFilterDesc, MaskingDesc, MaterialDesc,
    MediumDesc, MicrofacetDesc, PhaseDesc, SceneDesc, ShapeType,
};
use brume::scene::mitsuba::import;
use std::path::{Path, PathBuf};

/// Writes `files` (name, text) into a fresh folder; returns it (kept alive) and the first file.
fn write(files: &[(&str, &str)]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        let path = dir.path().join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
    }
    let first = dir.path().join(files[0].0);
    (dir, first)
}

const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="45"/></sensor>"#;

/// A scene of `body` with a plain sensor (unless `body` has its own).
fn scene(body: &str) -> String {
    let sensor = if body.contains("<sensor") { "" } else { SENSOR };
    format!("<scene version=\"3.0.0\">{sensor}{body}</scene>")
}

fn load(body: &str, overrides: &[(&str, &str)]) -> SceneDesc {
    let (_dir, path) = write(&[("scene.xml", &scene(body))]);
    let overrides = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    import(&path, overrides)
        .unwrap_or_else(|e| panic!("{e}"))
        .desc
}

const SPHERE_R: &str = r#"<default name="r" value="2"/><default name="kind" value="sphere"/>
    <shape type="$kind"><float name="radius" value="$r"/></shape>"#;

#[test]
fn a_default_is_substituted_also_inside_type_and_the_command_line_wins() {
    assert_eq!(load(SPHERE_R, &[]).shapes[0].radius, Some(2.0));
    assert_eq!(load(SPHERE_R, &[("r", "3")]).shapes[0].radius, Some(3.0));
    let cube = load(
        r#"<default name="kind" value="sphere"/><shape type="$kind"/>"#,
        &[("kind", "cube")],
    );
    assert_eq!(cube.shapes[0].size, Some(vec![2.0; 3]));
}

#[test]
fn includes_are_found_relative_to_the_including_file_and_path_folders_are_searched() {
    let (_dir, path) = write(&[
        ("scene.xml", &scene(r#"<include filename="parts/a.xml"/>"#)),
        (
            "parts/a.xml",
            &scene(r#"<include filename="b.xml"/><shape type="sphere"/>"#).replace(SENSOR, ""),
        ),
        (
            "parts/b.xml",
            r#"<scene version="3.0.0"><path value="meshes"/><shape type="obj"><string name="filename" value="m.obj"/></shape></scene>"#,
        ),
        ("parts/meshes/m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    ]);
    let imported = import(&path, vec![]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(imported.files.len(), 3);
    let shapes = &imported.desc.shapes;
    assert_eq!(shapes.len(), 2);
    let mesh = shapes[0].file.as_ref().unwrap();
    assert!(mesh.ends_with("parts/meshes/m.obj"), "{}", mesh.display());
}

#[test]
fn a_ply_shape_is_a_mesh_of_its_file_placed_by_to_world() {
    let (_dir, path) = write(&[
        (
            "scene.xml",
            &scene(
                r#"<shape type="ply"><string name="filename" value="m.ply"/><transform name="to_world"><translate x="2"/></transform></shape>"#,
            ),
        ),
        ("m.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
    ]);
    let desc = import(&path, vec![]).unwrap_or_else(|e| panic!("{e}")).desc;
    let mesh = &desc.shapes[0];
    assert_eq!(mesh.kind, ShapeType::Mesh);
    assert!(mesh.file.as_ref().unwrap().ends_with("m.ply"));
    assert_eq!(
        mesh.transform.as_ref().unwrap().translate,
        Some([2.0, 0.0, 0.0])
    );
}

#[test]
fn transforms_compose_in_the_order_written() {
    let placed = |ops: &str| {
        let desc = load(
            &format!(
                r#"<shape type="sphere"><transform name="to_world">{ops}</transform></shape>"#
            ),
            &[],
        );
        let t = desc.shapes[0].transform.as_ref().unwrap();
        (t.translate, t.scale.map(|s| s.0))
    };
    // translate, then scale: the translation is scaled too.
    assert_eq!(
        placed(r#"<translate x="1"/><scale value="2"/>"#),
        (Some([2.0, 0.0, 0.0]), Some([2.0; 3]))
    );
    assert_eq!(
        placed(r#"<scale value="2"/><translate x="1"/>"#),
        (Some([1.0, 0.0, 0.0]), Some([2.0; 3]))
    );
    // a matrix is row-major, like Mitsuba's
    assert_eq!(
        placed(r#"<matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>"#),
        (Some([5.0, 6.0, 7.0]), None)
    );
}

#[test]
fn rotations_are_right_handed_and_a_rectangle_faces_its_turned_z() {
    let desc = load(
        r#"<shape type="rectangle"><transform name="to_world"><scale x="2" y="3"/><rotate y="1" angle="90"/><translate z="4"/></transform></shape>"#,
        &[],
    );
    let quad = &desc.shapes[0];
    assert_eq!(
        quad.normal,
        Some([1.0, 0.0, 0.0]),
        "+Z turned 90° about +Y is +X"
    );
    assert_eq!(
        quad.u_axis,
        Some([0.0, 0.0, -1.0]),
        "+X turned 90° about +Y is -Z"
    );
    assert_eq!(quad.size, Some(vec![4.0, 6.0]));
    assert_eq!(quad.center, Some([0.0, 0.0, 4.0]));
    let flipped = load(
        r#"<shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>"#,
        &[],
    );
    assert_eq!(flipped.shapes[0].normal, Some([0.0, 0.0, -1.0]));
}

#[test]
fn a_disk_is_the_unit_disk_placed_by_to_world_and_flip_normals_turns_it_over() {
    let desc = load(
        r#"<shape type="disk"><transform name="to_world"><scale value="2"/><rotate y="1" angle="90"/><translate z="4"/></transform></shape>
        <shape type="disk"><boolean name="flip_normals" value="true"/></shape>"#,
        &[],
    );
    let disk = &desc.shapes[0];
    assert_eq!(disk.kind, ShapeType::Disk);
    assert_eq!(disk.normal, Some([1.0, 0.0, 0.0]), "+Z turned 90° about +Y");
    assert_eq!(
        disk.u_axis,
        Some([0.0, 0.0, -1.0]),
        "+X turned 90° about +Y"
    );
    assert_eq!(disk.radius, Some(2.0));
    assert_eq!(disk.center, Some([0.0, 0.0, 4.0]));
    assert_eq!(desc.shapes[1].normal, Some([0.0, 0.0, -1.0]));
    assert_eq!(desc.shapes[1].radius, Some(1.0));
}

#[test]
fn flipping_a_glass_sphere_inverts_its_relative_index_and_leaves_two_sided_ones_alone() {
    let desc = load(
        r#"<shape type="sphere"><boolean name="flip_normals" value="true"/><bsdf type="dielectric"><float name="int_ior" value="2"/><float name="ext_ior" value="1"/></bsdf></shape>
        <shape type="sphere"><boolean name="flip_normals" value="true"/><bsdf type="thindielectric"><float name="int_ior" value="2"/><float name="ext_ior" value="1"/></bsdf></shape>
        <shape type="cube"><boolean name="flip_normals" value="true"/><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>"#,
        &[],
    );
    assert!(
        matches!(desc.shapes[0].material, Some(MaterialDesc::Dielectric { ior, .. }) if ior == 0.5)
    );
    assert!(
        matches!(desc.shapes[1].material, Some(MaterialDesc::ThinDielectric { ior }) if ior == 2.0)
    );
    assert!(matches!(
        desc.shapes[2].material,
        Some(MaterialDesc::Diffuse { .. })
    ));
}

/// The camera's fov in brume's terms for `params` on a `w`×`h` film.
fn camera(params: &str, w: u32, h: u32) -> (f32, String) {
    let desc = load(
        &format!(
            r#"<sensor type="perspective">{params}<film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/></film></sensor>"#
        ),
        &[],
    );
    (desc.camera.fov, desc.camera.fov_axis.unwrap())
}

#[test]
fn the_field_of_view_is_converted_from_each_axis_and_from_a_focal_length() {
    let fov = |axis: &str| {
        camera(
            &format!(r#"<float name="fov" value="50"/><string name="fov_axis" value="{axis}"/>"#),
            200,
            100,
        )
    };
    assert_eq!(
        camera(r#"<float name="fov" value="50"/>"#, 200, 100),
        (50.0, "x".into()),
        "x is Mitsuba's default axis"
    );
    assert_eq!(fov("y"), (50.0, "y".into()));
    assert_eq!(fov("smaller"), (50.0, "y".into()));
    assert_eq!(fov("larger"), (50.0, "x".into()));
    // diagonal: tan(x/2) = tan(d/2)·w/√(w²+h²)
    let want = 2.0
        * ((25f64.to_radians().tan()) * 200.0 / 50000f64.sqrt())
            .atan()
            .to_degrees();
    let (got, axis) = fov("diagonal");
    assert_eq!(axis, "x");
    assert!((got as f64 - want).abs() < 1e-4, "{got} vs {want}");
    // 50mm (Mitsuba's default) on a 36×24 mm frame: the diagonal fov, then as above
    let diagonal = 2.0 * (1872f64.sqrt() / 100.0).atan();
    let want = 2.0
        * ((diagonal / 2.0).tan() * 200.0 / 50000f64.sqrt())
            .atan()
            .to_degrees();
    for params in ["", r#"<string name="focal_length" value="50mm"/>"#] {
        let (got, _) = camera(params, 200, 100);
        assert!(
            (got as f64 - want).abs() < 1e-4,
            "{params}: {got} vs {want}"
        );
    }
}

#[test]
fn max_depth_counts_segments_in_mitsuba_and_scattering_events_in_brume() {
    let depth = |d: &str| {
        load(
            &format!(
                r#"<integrator type="volpath"><integer name="max_depth" value="{d}"/></integrator>"#
            ),
            &[],
        )
        .integrator
        .max_depth
    };
    assert_eq!(depth("1"), 0, "1: only emitters seen directly");
    assert_eq!(depth("2"), 1, "2: direct lighting");
    assert_eq!(depth("-1"), u32::MAX);
    assert_eq!(
        load("", &[]).integrator.max_depth,
        u32::MAX,
        "Mitsuba's default is unlimited"
    );
    // `direct`: emitters seen directly and one reflection, whatever its sample counts.
    for direct in [
        r#"<integrator type="direct"/>"#,
        r#"<integrator type="moment"><integrator type="direct"><integer name="emitter_samples" value="4"/><integer name="bsdf_samples" value="0"/></integrator></integrator>"#,
    ] {
        assert_eq!(load(direct, &[]).integrator.max_depth, 1, "{direct}");
    }
}

#[test]
fn sampler_film_and_named_iors_map_to_their_values() {
    let desc = load(
        r#"<sensor type="perspective"><sampler type="independent"><integer name="sample_count" value="9"/><integer name="seed" value="4"/></sampler></sensor>
        <shape type="sphere"><bsdf type="dielectric"><string name="int_ior" value="diamond"/><float name="ext_ior" value="1.2"/></bsdf></shape>
        <shape type="sphere"><bsdf type="dielectric"/></shape>"#,
        &[],
    );
    assert_eq!((desc.integrator.spp, desc.integrator.seed), (9, 4));
    assert_eq!(desc.integrator.sampler, "independent");
    assert_eq!(desc.camera.resolution, [768, 576], "hdrfilm's default size");
    let ior = |i: usize| match &desc.shapes[i].material {
        Some(MaterialDesc::Dielectric { ior, .. }) => *ior,
        other => panic!("{other:?}"),
    };
    assert_eq!(ior(0), (2.419f64 / 1.2) as f32);
    assert_eq!(
        ior(1),
        (1.5046f64 / 1.000277) as f32,
        "bk7 in air by default"
    );
}

#[test]
fn colours_medium_coefficients_and_phase_defaults_follow_mitsuba() {
    let desc = load(
        r#"<medium type="homogeneous" id="m"><spectrum name="sigma_t" value="2"/><float name="scale" value="0.5"/><phase type="hg"/></medium>
        <shape type="sphere"><point name="center" z="-5"/><bsdf type="null"/><ref name="interior" id="m"/></shape>"#,
        &[],
    );
    match &desc.shapes[0].interior {
        Some(MediumDesc::Homogeneous {
            sigma_t,
            albedo,
            phase,
            ..
        }) => {
            assert_eq!(sigma_t.unwrap().0, [1.0; 3], "scale × sigma_t");
            assert_eq!(albedo.unwrap().0, [0.75; 3], "Mitsuba's default albedo");
            assert!(
                matches!(phase, Some(PhaseDesc::Hg { g }) if *g == 0.8),
                "{phase:?}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(
        desc.shapes[0].material.is_none(),
        "null: an index-matched boundary"
    );
}

#[test]
fn emitters_take_mitsubas_defaults_and_the_envmap_turns_a_quarter() {
    let desc = load(
        r#"<emitter type="point"/><emitter type="spot"><float name="cutoff_angle" value="30"/><float name="beam_width" value="30"/></emitter>
        <emitter type="directional"/>"#,
        &[],
    );
    assert!(
        matches!(desc.lights[0], LightDesc::Point { position: [0.0, 0.0, 0.0], intensity } if intensity.0 == [1.0; 3])
    );
    match &desc.lights[1] {
        LightDesc::Spot {
            look_at,
            cone_angle,
            cone_falloff,
            ..
        } => {
            assert_eq!(
                (*look_at, *cone_angle, *cone_falloff),
                ([0.0, 0.0, 1.0], 30.0, Some(0.0))
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(
        matches!(desc.lights[2], LightDesc::Sun { direction: [0.0, 0.0, 1.0], angular_radius, .. } if angular_radius == 0.0)
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/sky.exr");
    let xml = format!(
        r#"<emitter type="envmap"><string name="filename" value="{}"/><transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>"#,
        root.display()
    );
    let (_dir, path) = write(&[("scene.xml", &scene(&xml))]);
    let imported = import(&path, vec![]).unwrap_or_else(|e| panic!("{e}"));
    // Mitsuba's envmap is bilinear, and so is the imported map: no warning.
    assert!(imported.warnings.is_empty(), "{:?}", imported.warnings);
    let env = imported.desc;
    match &env.lights[0] {
        // Rx(90°)·Ry(90°): brume's rotate about X, then Y, then Z.
        LightDesc::EnvironmentMap {
            rotate: Some(r),
            filter,
            ..
        } => {
            assert_eq!(*filter, MapFilterDesc::Bilinear);
            let q = glam::Quat::from_rotation_z(r[2].to_radians())
                * glam::Quat::from_rotation_y(r[1].to_radians())
                * glam::Quat::from_rotation_x(r[0].to_radians());
            let want = glam::Quat::from_rotation_x(90f32.to_radians())
                * glam::Quat::from_rotation_y(90f32.to_radians());
            assert!(q.dot(want).abs() > 1.0 - 1e-6, "{r:?}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_medium_outside_every_shape_becomes_global() {
    let desc = load(
        r#"<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.1"/></medium>
        <sensor type="perspective"><ref id="fog"/></sensor>
        <shape type="sphere"><ref name="exterior" id="fog"/></shape>"#,
        &[],
    );
    assert!(matches!(
        desc.media[0],
        MediumDesc::Homogeneous { global: true, .. }
    ));
    assert!(desc.shapes[0].interior.is_none());
}

/// Where containment and Mitsuba's rule read a scene alike it is placed by
/// containment (no interface rule); the arrangements where they differ keep
/// Mitsuba's rule: each medium once, unbounded, and each shape's
/// [interior, exterior] and the sensor's medium as indices.
#[test]
fn arrangements_where_the_rules_differ_keep_mitsubas_interfaces() {
    let agree = load(
        r#"<medium type="homogeneous" id="m"/>
        <shape type="cube"><transform name="to_world"><translate z="5"/></transform><bsdf type="null"/><ref name="interior" id="m"/></shape>"#,
        &[],
    );
    assert!(agree.interfaces.is_none() && agree.shapes[0].interior.is_some());
    // a sphere poking into a smoke cube without saying it is in the smoke
    let poking = load(
        r#"<medium type="homogeneous" id="m"/>
        <shape type="cube"><transform name="to_world"><translate z="-5"/></transform><bsdf type="null"/><ref name="interior" id="m"/></shape>
        <shape type="sphere"><point name="center" z="-4"/></shape>"#,
        &[],
    );
    let rule = poking.interfaces.expect("interface rule");
    assert_eq!(rule.shapes, vec![Some([Some(0), None]), None]);
    assert_eq!(rule.camera, None);
    assert!(poking.shapes.iter().all(|s| s.interior.is_none()));
    assert!(matches!(
        poking.media[..],
        [MediumDesc::Homogeneous { global: true, .. }]
    ));
    // camera in fog, one shape without the fog outside it
    let fog_and_vacuum = load(
        r#"<medium type="homogeneous" id="fog"/><sensor type="perspective"><ref id="fog"/></sensor>
        <shape type="sphere"><point name="center" z="-4"/><ref name="exterior" id="fog"/></shape>
        <shape type="sphere"><point name="center" z="4"/></shape>"#,
        &[],
    );
    let rule = fog_and_vacuum.interfaces.expect("interface rule");
    assert_eq!(rule.shapes, vec![Some([None, Some(0)]), None]);
    assert_eq!(rule.camera, Some(0));
    // fog around a shape while the camera is in vacuum; a second medium inside
    let two = load(
        r#"<medium type="homogeneous" id="fog"/><medium type="homogeneous" id="in"/>
        <shape type="sphere"><point name="center" z="-4"/><ref name="interior" id="in"/><ref name="exterior" id="fog"/></shape>"#,
        &[],
    );
    let rule = two.interfaces.expect("interface rule");
    assert_eq!(rule.shapes, vec![Some([Some(0), Some(1)])]);
    assert_eq!((rule.camera, two.media.len()), (None, 2));
}

#[test]
fn roughplastic_maps_onto_a_rough_plastic_and_refuses_a_tinted_coating() {
    let desc = load(
        r#"<shape type="sphere"><bsdf type="roughplastic"/></shape>
        <shape type="sphere"><bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><float name="int_ior" value="1.6"/><float name="ext_ior" value="1.2"/><rgb name="diffuse_reflectance" value="0.1, 0.2, 0.3"/><rgb name="specular_reflectance" value="1, 1, 1"/><boolean name="nonlinear" value="true"/></bsdf></shape>"#,
        &[],
    );
    // Mitsuba's defaults: beckmann, α 0.1, polypropylene in air, grey 0.5, linear.
    let Some(MaterialDesc::Plastic {
        diffuse,
        specular,
        ior,
        nonlinear,
        alpha,
        distribution,
        masking,
        transmittance,
    }) = &desc.shapes[0].material
    else {
        panic!("{:?}", desc.shapes[0].material)
    };
    assert_eq!(
        (*alpha, *distribution, *nonlinear, *masking, *transmittance),
        (
            0.1,
            MicrofacetDesc::Beckmann,
            false,
            MaskingDesc::Separable,
            CoatingTransmittanceDesc::Microfacet
        )
    );
    assert!((ior - (1.49 / 1.000277) as f32).abs() < 1e-6, "{ior}");
    assert_eq!(specular.0, [1.0; 3]);
    assert!(matches!(diffuse, ColorOrTexture::Color(c) if c.0 == [0.5; 3]));
    let Some(MaterialDesc::Plastic {
        diffuse,
        ior,
        nonlinear,
        alpha,
        distribution,
        ..
    }) = &desc.shapes[1].material
    else {
        panic!("{:?}", desc.shapes[1].material)
    };
    assert_eq!(
        (*alpha, *distribution, *nonlinear),
        (0.3, MicrofacetDesc::Ggx, true)
    );
    assert!((ior - 1.6 / 1.2).abs() < 1e-6, "{ior}");
    assert!(matches!(diffuse, ColorOrTexture::Color(c) if c.0 == [0.1, 0.2, 0.3]));
    // A smooth plastic stays smooth.
    let smooth = load(
        r#"<shape type="sphere"><bsdf type="plastic"/></shape>"#,
        &[],
    );
    assert!(matches!(
        smooth.shapes[0].material,
        Some(MaterialDesc::Plastic {
            alpha,
            transmittance: CoatingTransmittanceDesc::Fresnel,
            ..
        }) if alpha == 0.0
    ));
    for (bsdf, words) in [
        (
            r#"<rgb name="specular_reflectance" value="0.5, 1, 1"/>"#,
            "specular_reflectance other than 1",
        ),
        (
            r#"<string name="distribution" value="phong"/>"#,
            "microfacet distribution",
        ),
        (
            r#"<float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/>"#,
            "anisotropic",
        ),
        (r#"<float name="alpha" value="0"/>"#, "must be positive"),
    ] {
        let body =
            format!(r#"<shape type="sphere"><bsdf type="roughplastic">{bsdf}</bsdf></shape>"#);
        let (_dir, path) = write(&[("scene.xml", &scene(&body))]);
        let err = import(&path, Default::default())
            .err()
            .expect("refused")
            .to_string();
        assert!(err.contains(words), "want `{words}` in `{err}`");
        assert!(!err.contains('\n'), "{err}");
    }
}

/// Mitsuba's file resolver holds the scene's own folder and the `<path>`
/// folders for every file, also those named in included XML, and brume
/// must find them when the scene is named by a relative path.
#[test]
fn files_are_found_through_the_scene_folder_and_path_folders_from_a_relative_scene_path() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (dir, _) = write(&[
        (
            "set/a/scene.xml",
            &scene(r#"<path value="../../common"/><include filename="inc/base.xml"/>"#),
        ),
        (
            "set/a/inc/base.xml",
            r#"<scene version="3.0.0"><include filename="inc/light.xml"/><shape type="obj"><string name="filename" value="meshes/m.obj"/></shape></scene>"#,
        ),
        (
            "set/a/inc/light.xml",
            r#"<scene version="3.0.0"><emitter type="constant"/></scene>"#,
        ),
        ("common/meshes/m.obj", obj),
    ]);
    let out = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["info", "set/a/scene.xml"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
}

/// A mesh's bounds come from its file: a small medium mesh inside a larger
/// one with the same interior is an overlap (leaving the small one, Mitsuba
/// puts a ray in its exterior, vacuum), so Mitsuba's rule is kept.
#[test]
fn nested_medium_meshes_keep_mitsubas_interfaces() {
    let cube = |h: f32| {
        let mut text = String::new();
        for i in 0..8 {
            let c = |bit: i32| if i & bit == 0 { -h } else { h };
            text += &format!("v {} {} {}\n", c(1), c(2), c(4));
        }
        // the twelve outward triangles of the cube
        text + "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n\
                f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n"
    };
    let shape = |file: &str| {
        format!(
            r#"<shape type="obj"><string name="filename" value="{file}"/><bsdf type="null"/><ref name="interior" id="m"/><transform name="to_world"><translate z="-5"/></transform></shape>"#
        )
    };
    let body = format!(
        r#"<medium type="homogeneous" id="m"/>{}{}"#,
        shape("small.obj"),
        shape("big.obj")
    );
    let (_dir, path) = write(&[
        ("scene.xml", &scene(&body)),
        ("small.obj", &cube(0.5)),
        ("big.obj", &cube(1.0)),
    ]);
    let desc = import(&path, vec![]).unwrap_or_else(|e| panic!("{e}")).desc;
    let rule = desc.interfaces.expect("interface rule");
    assert_eq!(rule.shapes, vec![Some([Some(0), None]); 2]);
}

/// The film's reconstruction filter: Mitsuba's default (none given, or no
/// film) is its Gaussian of stddev 0.5; a box stays a box; a Gaussian keeps
/// its stddev.
#[test]
fn the_films_filter_becomes_the_cameras_pixel_filter() {
    let filter = |film: &str| {
        load(
            &format!(r#"<sensor type="perspective">{film}</sensor>"#),
            &[],
        )
        .camera
        .pixel_filter
        .map(|f| (f.kind, f.stddev))
    };
    let gaussian = |s: Option<f32>| Some(("gaussian".to_string(), s));
    assert_eq!(filter(""), gaussian(None));
    assert_eq!(filter(r#"<film type="hdrfilm"/>"#), gaussian(None));
    assert_eq!(
        filter(r#"<film type="hdrfilm"><rfilter type="box"/></film>"#),
        None
    );
    assert_eq!(
        filter(
            r#"<film type="hdrfilm"><rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter></film>"#
        ),
        gaussian(Some(0.25))
    );
}

/// A named conductor takes the η and k Mitsuba's RGB variants use for it
/// (gold and a-C, as its scalar_rgb variant printed them); an unknown name
/// and a name beside eta are refused at their element.
#[test]
fn named_conductors_take_mitsubas_rgb_index() {
    let index = |name: &str| {
        let desc = load(
            &format!(
                r#"<shape type="sphere"><bsdf type="roughconductor"><string name="material" value="{name}"/></bsdf></shape>"#
            ),
            &[],
        );
        match &desc.shapes[0].material {
            Some(MaterialDesc::Conductor {
                eta: Some(eta),
                k: Some(k),
                f0: None,
                ..
            }) => (eta.0, k.0),
            other => panic!("{other:?}"),
        }
    };
    let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5);
    let (eta, k) = index("Au");
    assert!(
        close(eta, [0.14303598, 0.37530708, 1.4420453])
            && close(k, [3.982997, 2.3855565, 1.6033592]),
        "Au: {eta:?} {k:?}"
    );
    let (eta, k) = index("a-C");
    assert!(
        close(eta, [2.9440458, 2.2271364, 1.9681617]) && close(k, [0.8874649, 0.7992985, 0.81529]),
        "a-C: {eta:?} {k:?}"
    );
    for (body, words) in [
        (
            r#"<bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf>"#,
            "unknown conductor material `Unobtainium`",
        ),
        (
            r#"<bsdf type="conductor"><string name="material" value="Au"/><rgb name="eta" value="1"/></bsdf>"#,
            "not both",
        ),
    ] {
        let (_dir, path) = write(&[(
            "scene.xml",
            &scene(&format!("<shape type=\"sphere\">{body}</shape>")),
        )]);
        let e = import(&path, vec![]).err().expect("refused").to_string();
        assert!(e.contains(words) && !e.contains('\n'), "{e}");
    }
}
