//! What the Mitsuba importer refuses: one line `FILE:LINE: <element>: why`,
//! exit code 2, never a panic (also for mangled files).

use proptest::prelude::*;
use std::path::PathBuf;

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const SENSOR: &str = r#"<sensor type="perspective"/>"#;

/// The import error of a scene whose `body` follows a sensor on line 2.
fn error(body: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let sensor = if body.contains("<sensor") { "" } else { SENSOR };
    let text = format!("<scene version=\"3.0.0\">\n{sensor}\n{body}\n</scene>");
    let path = write(&dir, "bad.xml", &text);
    match brume::scene::mitsuba::import(&path, vec![]) {
        Ok(_) => panic!("accepted: {body}"),
        Err(e) => {
            let message = e.to_string();
            let shown = message.replace(&dir.path().display().to_string(), "DIR");
            assert!(!shown.contains('\n'), "more than one line: {shown}");
            shown
        }
    }
}

#[track_caller]
fn refuses(body: &str, line: u32, element: &str, words: &str) {
    let shown = error(body);
    let head = format!("DIR/bad.xml:{line}: {element}: ");
    assert!(shown.starts_with(&head), "want `{head}...`, got `{shown}`");
    assert!(shown.contains(words), "want `{words}` in `{shown}`");
}

#[test]
fn elements_outside_the_subset_are_refused_by_element_and_line() {
    refuses(
        r#"<shape type="sphere">
        <bsdf type="pplastic"/></shape>"#,
        4,
        r#"<bsdf type="pplastic">"#,
        "not supported",
    );
    refuses(
        r#"<shape type="ply"><string name="filename" value="bad.xml"/><boolean name="face_normals" value="true"/></shape>"#,
        3,
        r#"<shape type="ply">"#,
        "face_normals",
    );
    refuses(
        r#"<shape type="ply"><string name="filename" value="bad.xml"/><boolean name="flip_tex_coords" value="true"/></shape>"#,
        3,
        r#"<boolean name="flip_tex_coords">"#,
        "flip_tex_coords",
    );
    refuses(
        r#"<shape type="serialized"/>"#,
        3,
        r#"<shape type="serialized">"#,
        "not supported",
    );
    refuses(
        r#"<emitter type="spot"><float name="beam_width" value="40"/></emitter>"#,
        3,
        r#"<float name="beam_width">"#,
        "must lie between 0 and cutoff_angle",
    );
    refuses(
        r#"<shape type="sphere"><bsdf type="roughconductor"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/></bsdf></shape>"#,
        3,
        r#"<float name="alpha_v">"#,
        "anisotropic",
    );
    refuses(
        r#"<shape type="sphere"><bsdf type="roughdielectric"><string name="distribution" value="phong"/></bsdf></shape>"#,
        3,
        r#"<string name="distribution">"#,
        "beckmann and ggx",
    );
    // Mitsuba builds a rotation from its axis as written: a non-unit axis
    // also scales and shears, which no brume placement is.
    refuses(
        r#"<shape type="cube"><transform name="to_world"><rotate x="1" y="2" z="3" angle="25"/></transform></shape>"#,
        3,
        r#"<transform name="to_world">"#,
        "shear",
    );
    refuses(
        r#"<integrator type="direct"/><medium type="homogeneous" id="fog"/>
        <shape type="sphere"><bsdf type="null"/><ref name="interior" id="fog"/></shape>"#,
        3,
        r#"<integrator type="direct">"#,
        "direct integrator in a scene with media",
    );
    refuses(
        r#"<integrator type="direct"><integer name="bsdf_samples" value="-1"/></integrator>"#,
        3,
        r#"<integer name="bsdf_samples">"#,
        "must be 0 or more",
    );
    refuses(
        r#"<integrator type="direct"><boolean name="hide_emitters" value="true"/></integrator>"#,
        3,
        r#"<integrator type="direct">"#,
        "hide_emitters",
    );
    refuses(
        r#"<emitter type="constant"><spectrum name="radiance" filename="d65.spd"/></emitter>"#,
        3,
        r#"<spectrum name="radiance">"#,
        "not supported",
    );
}

/// `bitmap` and `checkerboard` parameters brume has no match for: a
/// turned to_uv, unknown filters and wraps, a nested texture.
#[test]
fn textures_brume_cannot_match_are_refused_by_element_and_line() {
    let on = |shape: &str, texture: &str| {
        format!(
            r#"<shape type="{shape}"><bsdf type="diffuse"><texture name="reflectance" {texture}</texture></bsdf></shape>"#
        )
    };
    let bitmap = |extra: &str| {
        on(
            "rectangle",
            &format!(r#"type="bitmap"><string name="filename" value="bad.xml"/>{extra}"#),
        )
    };
    let cases = [
        (
            on(
                "rectangle",
                r#"type="checkerboard"><transform name="to_uv"><rotate z="1" angle="30"/></transform>"#,
            ),
            r#"<transform name="to_uv">"#,
            "rotation or shear",
        ),
        (
            bitmap(r#"<string name="filter_type" value="cubic"/>"#),
            r#"<string name="filter_type">"#,
            "unknown filter_type `cubic`",
        ),
        (
            bitmap(r#"<string name="wrap_mode" value="tile"/>"#),
            r#"<string name="wrap_mode">"#,
            "unknown wrap_mode `tile`",
        ),
        (
            on(
                "rectangle",
                r#"type="checkerboard"><float name="gamma" value="2"/>"#,
            ),
            r#"<float name="gamma">"#,
            "this parameter",
        ),
        (
            on(
                "rectangle",
                r#"type="checkerboard"><texture type="checkerboard" name="color0"/>"#,
            ),
            r#"<texture type="checkerboard" name="color0">"#,
            "a texture inside a checkerboard",
        ),
        (
            on("rectangle", r#"type="mesh_attribute">"#),
            r#"<texture type="mesh_attribute" name="reflectance">"#,
            "this texture",
        ),
    ];
    for (body, element, words) in cases {
        refuses(&body, 3, element, words);
    }
}

/// Disks and `flip_normals` where brume would render something else than
/// Mitsuba: an elliptic disk, and closed shapes turned inside out that emit,
/// hold a medium or have a one-sided BSDF.
#[test]
fn disks_and_flipped_closed_shapes_brume_cannot_map_are_refused() {
    refuses(
        r#"<shape type="disk"><transform name="to_world"><scale x="2" y="1"/></transform></shape>"#,
        3,
        r#"<transform name="to_world">"#,
        "an ellipse",
    );
    let flipped = |inner: &str| {
        format!(
            r#"<shape type="sphere"><boolean name="flip_normals" value="true"/>{inner}</shape>"#
        )
    };
    refuses(
        &flipped(r#"<bsdf type="diffuse"/>"#),
        3,
        r#"<shape type="sphere">"#,
        "one-sided BSDF",
    );
    refuses(
        &flipped(""),
        3,
        r#"<shape type="sphere">"#,
        "one-sided BSDF",
    );
    refuses(
        &flipped(
            r#"<bsdf type="twosided"><bsdf type="diffuse"/></bsdf><emitter type="area"><rgb name="radiance" value="1"/></emitter>"#,
        ),
        3,
        r#"<shape type="sphere">"#,
        "emits",
    );
    refuses(
        &flipped(r#"<bsdf type="null"/><medium type="homogeneous" name="interior"/>"#),
        3,
        r#"<shape type="sphere">"#,
        "holding a medium",
    );
    refuses(
        r#"<shape type="cube"><boolean name="flip_normals" value="true"/><bsdf type="conductor"/></shape>"#,
        3,
        r#"<shape type="cube">"#,
        "one-sided BSDF",
    );
    // A medium behind a disk is no longer refused: it is one of the
    // arrangements imported under Mitsuba's interface rule.
}

#[test]
fn a_parameter_nothing_reads_is_refused_not_ignored() {
    refuses(
        r#"<shape type="sphere">
        <float name="radiuss" value="2"/></shape>"#,
        4,
        r#"<float name="radiuss">"#,
        r#"this parameter of <shape type="sphere">"#,
    );
}

#[test]
fn mistakes_in_the_file_mechanics_name_their_element() {
    refuses(
        r#"<shape type="sphere"><float name="radius" value="$r"/></shape>"#,
        3,
        r#"<float name="radius">"#,
        "`$r` is not defined",
    );
    refuses(
        r#"<shape type="sphere"><ref id="nope"/></shape>"#,
        3,
        "<ref id=\"nope\">",
        "no element has id",
    );
    refuses(
        r#"<shape type="sphere"><float name="radius" value="two"/></shape>"#,
        3,
        r#"<float name="radius">"#,
        "not a finite number",
    );
    refuses(
        r#"<shape type="sphere"><transform name="to_world"><shear/></transform></shape>"#,
        3,
        "<shear>",
        "unknown transform operation",
    );
    refuses(
        r#"<shape type="cube"><transform name="to_world"><scale x="-1"/></transform></shape>"#,
        3,
        r#"<transform name="to_world">"#,
        "mirroring",
    );
    refuses(
        r#"<integrator type="path"><integer name="max_depth" value="0"/></integrator>"#,
        3,
        r#"<integer name="max_depth">"#,
        "renders nothing",
    );
    refuses(
        r#"<bsdf type="diffuse" id="a"/><bsdf type="diffuse" id="a"/>"#,
        3,
        r#"<bsdf type="diffuse" id="a">"#,
        "already used",
    );
    refuses(
        r#"<shape type="sphere"><emitter type="area"/><emitter type="point"/></shape>"#,
        3,
        r#"<emitter type="point">"#,
        "not supported",
    );
    let shown = error("<shape type=\"sphere\">\n<float name=\"radius\" value=\"1\">\n</shape>");
    assert!(shown.starts_with("DIR/bad.xml:5: XML: "), "{shown}");
}

#[test]
fn includes_that_loop_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let a = write(
        &dir,
        "a.xml",
        &format!("<scene version=\"3.0.0\">{SENSOR}\n<include filename=\"b.xml\"/></scene>"),
    );
    write(
        &dir,
        "b.xml",
        "<scene version=\"3.0.0\">\n\n<include filename=\"a.xml\"/></scene>",
    );
    let e = brume::scene::mitsuba::import(&a, vec![])
        .err()
        .expect("a cycle was accepted")
        .to_string();
    assert!(
        e.contains("b.xml:3: <include>") && e.contains("include cycle"),
        "{e}"
    );
}

#[test]
fn the_command_line_prints_one_line_and_exits_with_2() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir, "s.xml", &format!("<scene version=\"3.0.0\">{SENSOR}\n<shape type=\"sphere\"><bsdf type=\"pplastic\"/></shape></scene>"));
    let out = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .current_dir(dir.path())
        .args(["render", "s.xml", "--out", "o.exr", "--png", "o.png"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("s.xml:2: <bsdf type=\"pplastic\">"),
        "{stderr}"
    );
    assert!(!dir.path().join("o.exr").exists());
}

const GOOD: &str = include_str!("data/mitsuba/fog_box.xml");

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]
    /// Cut or overwritten anywhere, a scene is imported or refused, never a panic.
    #[test]
    fn mangled_scenes_never_panic(at in 0usize..GOOD.len(), byte in 0u8..128, cut in any::<bool>()) {
        let mut text = GOOD.as_bytes().to_vec();
        if cut { text.truncate(at) } else { text[at] = byte }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.xml");
        std::fs::write(&path, &text).unwrap();
        let _ = brume::scene::mitsuba::import(&path, vec![]);
    }
}

#[test]
fn a_value_brume_rejects_when_building_is_reported_at_its_element() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        &dir,
        "b.xml",
        &format!("<scene version=\"3.0.0\">{SENSOR}\n\n<shape type=\"sphere\"><float name=\"radius\" value=\"-1\"/></shape></scene>"),
    );
    let e = brume::scene::load_with_inputs(&path)
        .err()
        .expect("a negative radius was accepted")
        .to_string();
    assert!(e.contains("b.xml:3: <shape type=\"sphere\">: "), "{e}");
    assert!(e.contains("(brume's `shape[0].radius`)"), "{e}");
}
