//! The output-safety rule through the command line, as properties over
//! random arrangements of paths: for each writing command (render, render
//! --frames, merge, compare --diff) the outputs point at fresh files or at
//! the run's inputs, each spelled at random (plain, `./`, `sub/..`,
//! absolute, through a symbolic link, a hard link or a linked folder), and
//! the inputs are spelled at random too. Whatever the arrangement, no input
//! file's bytes change; the exit code is 2 (one `error:` line naming an
//! output flag, no output created) exactly when an output is an input or two
//! outputs are one file, and 0 (every output written) otherwise.

mod common;

use common::cli::{run_brume, Outcome};
use common::data::{crate_root, existing};
use common::paths::{spelling, Folder, Spelling};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use std::path::Path;
use std::sync::OnceLock;
use std::time::Duration;

const DEADLINE: Duration = Duration::from_secs(30);

/// What an output points at: a fresh file (by index) or an input of the run.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    Fresh(usize),
    Input(usize),
}

fn target(fresh: usize, inputs: usize) -> impl Strategy<Value = Target> {
    prop_oneof![
        (0..fresh).prop_map(Target::Fresh),
        (0..inputs).prop_map(Target::Input),
    ]
}

/// The file an output target names.
fn file<'a>(t: Target, fresh: &[&'a str], inputs: &[&'a str]) -> &'a str {
    match t {
        Target::Fresh(i) => fresh[i],
        Target::Input(i) => inputs[i],
    }
}

/// A clash: an output on an input, or two outputs on one file.
fn clash(targets: &[Target]) -> bool {
    let on_input = targets.iter().any(|t| matches!(t, Target::Input(_)));
    let twice = (0..targets.len()).any(|i| targets[i + 1..].contains(&targets[i]));
    on_input || twice
}

/// The bytes of the files `names` of `folder` (read through their real names).
fn bytes_of(folder: &Folder, names: &[&str]) -> Vec<Vec<u8>> {
    names
        .iter()
        .map(|n| std::fs::read(folder.path().join(n)).unwrap())
        .collect()
}

/// Asserts the rule on one run: inputs unchanged, exit code 2 with one line
/// naming an output flag and no fresh output created on a clash, else 0 with
/// every output written.
fn assert_rule(
    folder: &Folder,
    run: &Outcome,
    inputs: (&[&str], &[Vec<u8>]),
    fresh: &[&str],
    clash: bool,
) {
    let what = format!("clash {clash}: {}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{what}");
    assert_eq!(
        bytes_of(folder, inputs.0),
        inputs.1,
        "an input changed; {what}"
    );
    if clash {
        assert_eq!(run.code, Some(2), "{what}");
        let errors: Vec<&str> = run
            .stderr
            .lines()
            .filter(|l| l.starts_with("error:"))
            .collect();
        assert_eq!(errors.len(), 1, "{what}");
        let flags = ["--out:", "--png:", "-o:", "--diff:"];
        assert!(flags.iter().any(|f| errors[0].contains(f)), "{what}");
        for f in fresh {
            assert!(!folder.path().join(f).exists(), "{f} written; {what}");
        }
    } else {
        assert_eq!(run.code, Some(0), "{what}");
    }
}

const SCENE_INPUTS: [&str; 4] = ["s.toml", "m.obj", "t.png", "map.exr"];
const PIECES: [&str; 2] = ["p0.exr", "p1.exr"];

/// Writes the inputs of every command into `d`: a scene reading an OBJ, a
/// texture and an environment map (named in the scene as `refs`), and two
/// pieces of a render.
fn write_inputs(d: &Path, refs: [&str; 3]) {
    write_scene_files(d, refs);
    for (name, bytes) in PIECES.iter().zip(pieces()) {
        std::fs::write(d.join(name), bytes).unwrap();
    }
}

fn write_scene_files(d: &Path, refs: [&str; 3]) {
    let root = crate_root();
    std::fs::copy(
        existing(root.join("tests/data/meshes/cube.obj")),
        d.join("m.obj"),
    )
    .unwrap();
    let texture = existing(root.join("tests/data/textures/checker4x2.png"));
    std::fs::copy(texture, d.join("t.png")).unwrap();
    let map = brume::film::image_io::Image {
        width: 4,
        height: 2,
        pixels: vec![brume::math::color::Rgb::new(0.5, 0.6, 0.7); 8],
        spp: 1,
        partial: false,
    };
    brume::film::image_io::write_exr(&d.join("map.exr"), &map).unwrap();
    std::fs::write(d.join("s.toml"), scene(refs)).unwrap();
}

fn scene([obj, tex, map]: [&str; 3]) -> String {
    format!(
        r#"
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [4, 3]
[integrator]
spp = 2
[[light]]
type = "environment_map"
file = "{map}"
[[shape]]
type = "mesh"
file = "{obj}"
[[shape]]
type = "quad"
center = [0.0, -1.0, 0.0]
normal = [0.0, 1.0, 0.0]
size = [4.0, 4.0]
material = {{ type = "diffuse", albedo = {{ type = "image", file = "{tex}" }} }}
"#
    )
}

/// Two sample-range pieces of the scene, rendered once for all cases.
fn pieces() -> &'static [Vec<u8>; 2] {
    static PIECE_BYTES: OnceLock<[Vec<u8>; 2]> = OnceLock::new();
    PIECE_BYTES.get_or_init(|| {
        let d = tempfile::tempdir().unwrap();
        write_scene_files(d.path(), ["m.obj", "t.png", "map.exr"]);
        let piece = |range: &str, name: &str| {
            let args: Vec<String> = ["render", "s.toml", "--samples", range, "--out", name]
                .iter()
                .map(|s| s.to_string())
                .chain(["--png".into(), format!("{name}.png")])
                .collect();
            let run = run_brume(d.path(), &args, DEADLINE);
            assert_eq!(run.code, Some(0), "{}", run.stderr);
            std::fs::read(d.path().join(name)).unwrap()
        };
        [piece("0..1", "p0.exr"), piece("1..2", "p1.exr")]
    })
}

/// Sets up a case folder with every input, spelling the scene's references.
fn case_folder(refs: [Spelling; 3]) -> Folder {
    let mut folder = Folder::new();
    let spelled = [
        folder.spell("m.obj", refs[0]),
        folder.spell("t.png", refs[1]),
        folder.spell("map.exr", refs[2]),
    ];
    write_inputs(folder.path(), [&spelled[0], &spelled[1], &spelled[2]]);
    folder
}

fn config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(0x0062_7275_6d65),
        max_shrink_iters: 32,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config(40))]

    #[test]
    fn render_never_writes_over_its_inputs_or_twice_to_one_file(
        out in (target(2, 4), spelling()),
        png in (target(2, 4), spelling()),
        scene_spelling in spelling(),
        refs in [spelling(), spelling(), spelling()],
    ) {
        let fresh = ["o0.exr", "o1.png"];
        let mut folder = case_folder(refs);
        let mut args = vec!["render".to_string(), folder.spell("s.toml", scene_spelling)];
        for (flag, (t, how)) in [("--out", out), ("--png", png)] {
            args.push(flag.into());
            args.push(folder.spell(file(t, &fresh, &SCENE_INPUTS), how));
        }
        let before = bytes_of(&folder, &SCENE_INPUTS);
        let run = run_brume(folder.path(), &args, DEADLINE);
        let clash = clash(&[out.0, png.0]);
        assert_rule(&folder, &run, (&SCENE_INPUTS, &before), &fresh, clash);
        if !clash {
            for t in [out.0, png.0] {
                prop_assert!(folder.path().join(file(t, &fresh, &SCENE_INPUTS)).is_file());
            }
        }
    }

    #[test]
    fn merge_never_writes_over_a_piece_or_twice_to_one_file(
        out in (target(2, 2), spelling()),
        png in proptest::option::of((target(2, 2), spelling())),
        piece_spellings in [spelling(), spelling()],
    ) {
        let fresh = ["m0.exr", "m1.png"];
        let mut folder = case_folder([Spelling::Plain; 3]);
        let mut args = vec!["merge".to_string()];
        for (name, how) in PIECES.iter().zip(piece_spellings) {
            args.push(folder.spell(name, how));
        }
        args.push("-o".into());
        args.push(folder.spell(file(out.0, &fresh, &PIECES), out.1));
        let mut targets = vec![out.0];
        if let Some((t, how)) = png {
            args.push("--png".into());
            args.push(folder.spell(file(t, &fresh, &PIECES), how));
            targets.push(t);
        }
        let before = bytes_of(&folder, &PIECES);
        let run = run_brume(folder.path(), &args, DEADLINE);
        assert_rule(&folder, &run, (&PIECES, &before), &fresh, clash(&targets));
    }

    #[test]
    fn compare_never_writes_its_diff_over_a_compared_image(
        diff in (target(1, 2), spelling()),
        spellings in [spelling(), spelling()],
    ) {
        let fresh = ["d.png"];
        let mut folder = case_folder([Spelling::Plain; 3]);
        let mut args = vec!["compare".to_string()];
        for (name, how) in PIECES.iter().zip(spellings) {
            args.push(folder.spell(name, how));
        }
        args.push("--diff".into());
        args.push(folder.spell(file(diff.0, &fresh, &PIECES), diff.1));
        let before = bytes_of(&folder, &PIECES);
        let run = run_brume(folder.path(), &args, DEADLINE);
        assert_rule(&folder, &run, (&PIECES, &before), &fresh, clash(&[diff.0]));
    }
}

/// A frame sequence's output pattern: fresh, or onto its inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pattern {
    /// `o.####.exr`, `p.####.png` or `v.####.exr` (near the input sequence, not in it).
    Fresh(usize),
    /// `v.####.vdb`: the VDB sequence the scene reads.
    Sequence,
    /// The scene file, without a pattern.
    Scene,
}

fn pattern() -> impl Strategy<Value = Pattern> {
    prop_oneof![
        (0..3usize).prop_map(Pattern::Fresh),
        Just(Pattern::Sequence),
        Just(Pattern::Scene),
    ]
}

/// Spellings that keep a frame pattern in the file name.
fn pattern_spelling() -> impl Strategy<Value = Spelling> {
    use Spelling::*;
    prop_oneof![
        Just(Plain),
        Just(Dot),
        Just(Up),
        Just(Absolute),
        Just(LinkedFolder)
    ]
}

const FRESH_PATTERNS: [&str; 3] = ["o.####.exr", "p.####.png", "v.####.exr"];

/// Frames 1-3 of a scene reading `v.####.vdb` (files 1 to 5, frame offset `offset`, missing frames held).
fn sequence_folder(offset: i64, vdb: Spelling) -> (Folder, Vec<&'static str>) {
    let mut folder = Folder::new();
    let plume = |i: u32| crate_root().join(format!("tests/data/anim/plume.000{}.vdb", i.min(3)));
    let names = vec![
        "seq.toml",
        "v.0001.vdb",
        "v.0002.vdb",
        "v.0003.vdb",
        "v.0004.vdb",
        "v.0005.vdb",
    ];
    for i in 1..=5u32 {
        std::fs::copy(existing(plume(i)), folder.path().join(names[i as usize])).unwrap();
    }
    let file = folder.spell("v.####.vdb", vdb);
    let text = format!(
        "[camera]\nposition = [0.0, 0.6, 2.5]\nlook_at = [0.0, 0.6, 0.0]\nresolution = [4, 3]\n\
         [integrator]\nspp = 1\n[[light]]\ntype = \"environment\"\nradiance = 0.5\n\
         [[medium]]\ntype = \"vdb\"\nfile = \"{file}\"\ndensity_scale = 20.0\n\
         [animation]\nframe_offset = {offset}\nmissing_frames = \"hold\"\n"
    );
    std::fs::write(folder.path().join("seq.toml"), text).unwrap();
    (folder, names)
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn a_sequence_never_writes_over_any_frames_input_or_twice_to_one_file(
        out in (pattern(), pattern_spelling()),
        png in (pattern(), pattern_spelling()),
        offset in prop_oneof![Just(-1i64), Just(0), Just(2)],
        vdb in pattern_spelling(),
    ) {
        let (mut folder, inputs) = sequence_folder(offset, vdb);
        let mut args: Vec<String> = ["render", "seq.toml", "--frames", "1-3"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        for (flag, (p, how)) in [("--out", out), ("--png", png)] {
            let name = match p {
                Pattern::Fresh(i) => FRESH_PATTERNS[i],
                Pattern::Sequence => "v.####.vdb",
                Pattern::Scene => "seq.toml",
            };
            args.push(flag.into());
            args.push(folder.spell(name, how));
        }
        let before = bytes_of(&folder, &inputs);
        let run = run_brume(folder.path(), &args, DEADLINE);
        let onto_inputs = [out.0, png.0].iter().any(|p| !matches!(p, Pattern::Fresh(_)));
        let clash = onto_inputs || out.0 == png.0;
        let written: Vec<String> = [out.0, png.0]
            .iter()
            .filter_map(|p| match p {
                Pattern::Fresh(i) => Some(FRESH_PATTERNS[*i]),
                _ => None,
            })
            .flat_map(|p| (1..=3).map(move |f| p.replace("####", &format!("{f:04}"))))
            .collect();
        let fresh: Vec<&str> = written.iter().map(String::as_str).collect();
        assert_rule(&folder, &run, (&inputs, &before), &fresh, clash);
        if !clash {
            for f in &fresh {
                prop_assert!(folder.path().join(f).is_file(), "{} missing", f);
            }
        }
    }
}
