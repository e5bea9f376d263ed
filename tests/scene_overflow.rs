//! Scales and coefficients near the top of single precision: every numeric
//! key of a medium (homogeneous, height fog, VDB with constant, blackbody and
//! grid emission), of an environment map and of an image texture — found by
//! crawling the schema, not listed here — set to 3e38 or 1e30, alone and in
//! pairs. Each scene either renders without a single non-finite sample or is
//! refused under a key of the same table, in the user's words, saying
//! "overflows single precision" when an overflow is the reason; never
//! "black everywhere", never a panic.

#[path = "schema_support/mod.rs"]
mod schema_support;

use brume::error::Error;
use schema_support::{rust_isms, Step};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use toml::{Table, Value};

/// Values near the top of f32 (3.4e38): alone finite, combined often not.
const HUGE: [f64; 2] = [3e38, 1e30];

/// A valid scene and the steps from its top to the table under test.
struct Template {
    name: &'static str,
    text: String,
    steps: Vec<Step>,
}

fn step(key: &str, list: bool, tag: Option<&str>) -> Step {
    Step {
        key: key.into(),
        list,
        tag: tag.map(str::to_string),
    }
}

fn templates(dir: &Path) -> Vec<Template> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let vol = |name: &str| root.join("volumes").join(name).display().to_string();
    let camera = "[camera]\nposition = [0.0, 0.5, 4.0]\nlook_at = [0.0, 0.5, 0.0]\nresolution = [6, 6]\n[[light]]\ntype = \"point\"\nposition = [1.0, 3.0, 2.0]\nintensity = 20.0\n";
    let medium = |tag: &str, body: String| Template {
        name: "",
        text: format!("{camera}[[medium]]\ntype = \"{tag}\"\n{body}"),
        steps: vec![step("medium", true, Some(tag))],
    };
    let map = dir.join("map.exr");
    let image = brume::film::image_io::Image {
        width: 4,
        height: 2,
        pixels: vec![brume::math::color::Rgb::new(0.5, 1.0, 2.0); 8],
        spp: 1,
        partial: false,
    };
    brume::film::image_io::write_exr(&map, &image).unwrap();
    let texture = root.join("textures/checker4x2.png").display().to_string();
    let named = |name, t: Template| Template { name, ..t };
    vec![
        named("homogeneous", medium("homogeneous", "sigma_a = 0.5\nsigma_s = 0.5\nemission = 0.2\nbounds = { type = \"sphere\", radius = 1.0 }\n".into())),
        named("height fog", medium("height_fog", "sigma_a = 0.1\nsigma_s = 0.2\nemission = 0.1\nscale_height = 1.0\n".into())),
        named("vdb, constant emission", medium("vdb", format!("file = \"{}\"\ndensity_scale = 2.0\nalbedo = 0.5\nemission = 0.5\n", vol("sphere_fog.vdb")))),
        named("vdb, blackbody", medium("vdb", format!("file = \"{}\"\ndensity_scale = 2.0\nalbedo = 0.5\ntemperature_grid = \"temperature\"\n", vol("smoke_plume.vdb")))),
        named("vdb, emission grid", medium("vdb", format!("file = \"{}\"\ndensity_scale = 2.0\nalbedo = 0.5\nemission_grid = \"temperature\"\nemission_scale = 1.0\n", vol("smoke_plume.vdb")))),
        Template {
            name: "environment map",
            text: format!("{camera}[[light]]\ntype = \"environment_map\"\nfile = \"{}\"\n[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.5, 0.0]\nradius = 0.5\n", map.display()),
            steps: vec![step("light", true, Some("environment_map"))],
        },
        Template {
            name: "image texture",
            text: format!("{camera}[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.5, 0.0]\nradius = 0.5\nemission = {{ type = \"image\", file = \"{texture}\" }}\n"),
            steps: vec![step("shape", true, None), step("emission", false, None)],
        },
    ]
}

/// The TOML table at `steps` (the light or medium is the second [[light]] or first [[medium]]).
fn table_at<'a>(root: &'a mut Table, steps: &[Step]) -> &'a mut Table {
    let mut table = root;
    for s in steps {
        table = match table.get_mut(&s.key).unwrap() {
            Value::Array(items) => items.last_mut().unwrap().as_table_mut().unwrap(),
            Value::Table(t) => t,
            other => panic!("{other:?}"),
        };
    }
    table
}

/// `x` written as the key takes numbers: one number, or an array of 2 or 3 (None: not numeric).
fn numeric(text: &str, steps: &[Step], key: &str, x: f64) -> Option<Value> {
    let shapes = [
        Value::Float(x),
        Value::Array(vec![Value::Float(x); 3]),
        Value::Array(vec![Value::Float(x); 2]),
    ];
    shapes.into_iter().find(|v| {
        let mut root: Table = toml::from_str(text).unwrap();
        table_at(&mut root, steps).insert(key.into(), v.clone());
        let text = toml::to_string(&root).unwrap();
        brume::scene::parse(&text, Path::new("s.toml")).is_ok()
    })
}

/// Loads and renders `text`; panics unless it renders finitely or is refused under `table`.
fn try_scene(dir: &Path, text: &str, table: &str, what: &str, radiance_overflows: bool) -> bool {
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    let scene = match brume::scene::load(&path) {
        Ok(scene) => scene,
        Err(Error::Scene { field, message, .. }) => {
            assert!(
                field.starts_with(table),
                "{what}: refused under {field}: {message}"
            );
            assert!(rust_isms(&message).is_empty(), "{what}: {field}: {message}");
            assert!(
                !message.contains("black everywhere"),
                "{what}: {field}: {message}"
            );
            if message.contains("overflow") {
                assert!(message.contains("single precision"), "{what}: {message}");
            }
            return false;
        }
        Err(other) => panic!("{what}: {other}"),
    };
    let options = brume::render::RenderOptions {
        spp: 4,
        time_budget: None,
        spp_is_cap: false,
        threads: Some(1),
        progress: false,
    };
    let out = brume::render::render(&scene, &options, &AtomicBool::new(false));
    // A radiance of 3e38 times any estimator weight above 1.13 is inf in f32:
    // such samples are counted, left out and reported. Any other value renders finitely.
    if out.nonfinite_samples > 0 {
        eprintln!(
            "{what}: accepted; {} of {} samples are not finite",
            out.nonfinite_samples, out.samples
        );
    }
    assert!(
        radiance_overflows || out.nonfinite_samples == 0,
        "{what}: accepted, but {} of {} samples are not finite",
        out.nonfinite_samples,
        out.samples
    );
    true
}

#[test]
fn huge_scales_and_coefficients_render_finitely_or_are_refused_naming_the_overflow() {
    let crawl = schema_support::crawl();
    let dir = tempfile::tempdir().unwrap();
    let (mut accepted, mut refused) = (0, 0);
    for t in templates(dir.path()) {
        let keys: Vec<&String> = crawl
            .leaf_steps
            .iter()
            .filter(|(steps, _)| *steps == t.steps)
            .map(|(_, key)| key)
            .collect();
        assert!(keys.len() >= 3, "{}: the crawl found only {keys:?}", t.name);
        let table = {
            let s = &t.steps;
            let i = match s[0].key.as_str() {
                // the light under test comes after the camera's point light
                "light" => 1,
                _ => 0,
            };
            let mut f = format!("{}[{i}]", s[0].key);
            for step in &s[1..] {
                f = format!("{f}.{}", step.key);
            }
            f
        };
        let numeric_keys: Vec<&String> = keys
            .into_iter()
            .filter(|k| numeric(&t.text, &t.steps, k, 1.0).is_some())
            .collect();
        let mut sets: Vec<Vec<&String>> = numeric_keys.iter().map(|k| vec![*k]).collect();
        for (i, a) in numeric_keys.iter().enumerate() {
            for b in &numeric_keys[i + 1..] {
                sets.push(vec![*a, *b]);
            }
        }
        for x in HUGE {
            for set in &sets {
                let mut root: Table = toml::from_str(&t.text).unwrap();
                for key in set {
                    let v = numeric(&t.text, &t.steps, key, x).unwrap();
                    table_at(&mut root, &t.steps).insert((*key).clone(), v);
                }
                let text = toml::to_string(&root).unwrap();
                let what = format!("{}: {set:?} = {x:e}", t.name);
                let radiance = set.iter().any(|k| k.contains("emission") || *k == "scale");
                match try_scene(dir.path(), &text, &table, &what, radiance && x > 1e37) {
                    true => accepted += 1,
                    false => refused += 1,
                }
            }
        }
    }
    eprintln!("{accepted} scenes rendered finitely, {refused} refused");
    assert!(accepted > 0 && refused > 0);
}
