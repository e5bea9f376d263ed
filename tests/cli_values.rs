//! Property tests over command-line values: every parser takes any text to a
//! value within its bounds or to one line saying what it expected (no panic,
//! no Rust type names), and the binary, given extreme or malformed values for
//! its flags, exits with 0 or 2 within a bounded time and never panics.

use brume::integrator::aov::Aov;
use brume::render::cli_values as values;
use proptest::prelude::*;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Words that would mean the message speaks Rust rather than the user's words.
const RUST_WORDS: [&str; 8] = [
    "u32",
    "u64",
    "i64",
    "usize",
    "ParseIntError",
    "ParseFloatError",
    "invalid digit",
    "Duration",
];

fn plain(message: &str) {
    plain_echoing(message, "");
}

/// Every parser on `text`: none panics, each error is one plain line.
fn all_parsers(text: &str) {
    let errors = [
        values::threads(text).err(),
        values::whole(0u32, u32::MAX)(text).err(),
        values::seconds(text).err(),
        values::rmse(text).err(),
        values::exposure(text).err(),
        values::frames(text).err(),
        values::crop(text).err(),
        values::samples(text).err(),
        values::aovs(text).err(),
        values::pixel(text).err(),
        values::host_port(text).err(),
    ];
    for e in errors.into_iter().flatten() {
        plain_echoing(&e, text);
    }
}

/// [`plain`], except for words the user's own `text` holds: a message may
/// quote what was written (a random text once held `u64`).
fn plain_echoing(message: &str, text: &str) {
    assert!(!message.contains('\n'), "not one line: {message}");
    for word in RUST_WORDS.iter().filter(|w| !text.contains(**w)) {
        assert!(!message.contains(word), "`{word}` in: {message}");
    }
}

/// Text made of the characters flag values are made of, often near a limit.
fn flag_like() -> impl Strategy<Value = String> {
    prop_oneof![
        "[-+0-9.,:e]{0,24}",
        any::<i128>().prop_map(|n| n.to_string()),
        any::<f64>().prop_map(|v| format!("{v:e}")),
        any::<f64>().prop_map(|v| v.to_string()),
        (any::<i64>(), any::<i64>()).prop_map(|(a, b)| format!("{a}-{b}")),
        (any::<u64>(), any::<u64>()).prop_map(|(a, b)| format!("{a}..{b}")),
        (any::<u64>(), any::<u64>()).prop_map(|(a, b)| format!("{a},{b}")),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn any_text_parses_or_says_what_was_expected(text in prop_oneof![any::<String>(), flag_like()]) {
        all_parsers(&text);
    }

    #[test]
    fn whole_numbers_are_accepted_exactly_within_bounds(n in any::<i128>(), lo in any::<u32>(), hi in any::<u32>()) {
        let (lo, hi) = (lo.min(hi), lo.max(hi));
        let parsed = values::whole(lo, hi)(&n.to_string());
        let inside = n >= lo as i128 && n <= hi as i128;
        prop_assert_eq!(parsed.is_ok(), inside, "{} in {}..={}: {:?}", n, lo, hi, parsed);
        if inside {
            prop_assert_eq!(parsed.unwrap() as i128, n);
        }
    }

    #[test]
    fn seconds_are_a_duration_of_at_most_a_billion_seconds(v in any::<f64>(), exp in any::<bool>()) {
        let text = if exp { format!("{v:e}") } else { v.to_string() };
        match values::seconds(&text) {
            Ok(d) => {
                prop_assert!(v > 0.0 && v <= values::MAX_SECONDS as f64, "{}", text);
                prop_assert!(d <= Duration::from_secs(values::MAX_SECONDS));
                prop_assert!((d.as_secs_f64() - v).abs() <= 1e-9 + 1e-12 * v, "{} -> {:?}", text, d);
                // What the render does with it: a deadline from now.
                prop_assert!(Instant::now().checked_add(d).is_some());
            }
            Err(e) => {
                prop_assert!(!(v > 0.0 && v <= values::MAX_SECONDS as f64), "{} refused", text);
                plain(&e);
            }
        }
    }

    #[test]
    fn exposures_give_a_normal_finite_scale(v in any::<f64>()) {
        if let Ok(stops) = values::exposure(&v.to_string()) {
            let scale = 2f32.powf(stops);
            prop_assert!(scale.is_normal(), "{} stops: scale {}", v, scale);
        }
    }

    #[test]
    fn frame_ranges_count_exactly_or_are_refused(a in any::<i64>(), span in prop_oneof![0i64..2000, any::<i64>()], far in any::<Option<i64>>(), step in prop_oneof![1i64..50, any::<i64>()]) {
        // A last frame anywhere (b - a beyond i64 too), or near the first.
        let b = far.unwrap_or(a.saturating_add(span));
        let text = format!("{a}-{b}:{step}");
        match values::frames(&text) {
            Ok(values::Frames(frames)) => {
                let count = (b as i128 - a as i128) / step as i128 + 1;
                prop_assert!(step >= 1 && a <= b);
                prop_assert_eq!(frames.len() as i128, count);
                prop_assert!(frames.len() <= brume::scene::animation::MAX_FRAMES);
                prop_assert_eq!(frames[0], a);
                prop_assert!(frames.windows(2).all(|w| w[1] - w[0] == step));
                prop_assert!(*frames.last().unwrap() <= b);
            }
            Err(e) => {
                let count = (b as i128 - a as i128) / (step.max(1) as i128) + 1;
                let fits = count <= brume::scene::animation::MAX_FRAMES as i128;
                prop_assert!(step < 1 || b < a || !fits, "{} refused: {}", text, e);
                plain(&e);
            }
        }
    }

    #[test]
    fn crops_and_sample_ranges_are_ordered_and_fit(x0 in any::<u64>(), x1 in any::<u64>(), y0 in 0u64..70_000, y1 in 0u64..70_000) {
        let fits = |v: u64| v <= u32::MAX as u64;
        let crop = values::crop(&format!("{x0},{x1},{y0},{y1}"));
        prop_assert_eq!(crop.is_ok(), fits(x0) && fits(x1) && x0 < x1 && y0 < y1, "{:?}", crop);
        if let Ok(r) = crop {
            prop_assert_eq!((r.x0 as u64, r.x1 as u64, r.y0 as u64, r.y1 as u64), (x0, x1, y0, y1));
        }
        let samples = values::samples(&format!("{x0}..{x1}"));
        prop_assert_eq!(samples.is_ok(), fits(x0) && fits(x1) && x0 < x1, "{:?}", samples);
    }

    #[test]
    fn aov_lists_keep_each_known_name_once_in_order(picks in proptest::collection::vec(0usize..5, 1..12)) {
        let names: Vec<_> = picks.iter().map(|&i| Aov::ALL[i].name()).collect();
        let values::Aovs(aovs) = values::aovs(&names.join(",")).unwrap();
        let mut expected: Vec<Aov> = Vec::new();
        for &i in &picks {
            if !expected.contains(&Aov::ALL[i]) {
                expected.push(Aov::ALL[i]);
            }
        }
        prop_assert_eq!(aovs, expected);
    }
}

/// Numbers at and past the limits of the types behind the flags (none
/// between 2 and 2^32: a frame list `0-1000` would render a thousand frames).
const EXTREMES: [&str; 20] = [
    "0",
    "1",
    "-1",
    "2",
    "4294967295",
    "4294967296",
    "-4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "1e9",
    "1e20",
    "1e300",
    "1e-300",
    "-0",
    "nan",
    "inf",
    "",
];

fn extreme() -> impl Strategy<Value = String> {
    prop::sample::select(&EXTREMES[..]).prop_map(str::to_string)
}

/// A flag of `brume render` and a value for it: extremes alone or joined the way the flag's syntax joins them.
fn render_flag() -> impl Strategy<Value = (&'static str, String)> {
    let pair =
        |sep: &'static str| (extreme(), extreme()).prop_map(move |(a, b)| format!("{a}{sep}{b}"));
    let four = (extreme(), extreme(), extreme(), extreme())
        .prop_map(|(a, b, c, d)| format!("{a},{b},{c},{d}"));
    let numeric = prop::sample::select(
        &[
            "--spp",
            "--max-depth",
            "--seed",
            "--threads",
            "--time",
            "--checkpoint",
            "--exposure",
            "--task-count",
        ][..],
    );
    prop_oneof![
        (numeric, extreme()),
        (
            Just("--frames"),
            prop_oneof![
                extreme(),
                pair("-"),
                (pair("-"), extreme()).prop_map(|(r, s)| format!("{r}:{s}"))
            ]
        ),
        (Just("--crop"), four),
        (Just("--samples"), pair("..")),
        (Just("--debug-pixel"), pair(",")),
        (Just("--task-index"), pair(" ")),
        (Just("--aovs"), "[a-z,]{0,20}"),
        (Just("--tonemap"), "[a-z]{0,6}"),
        (Just("--split"), "[a-z]{0,6}"),
    ]
}

/// The arguments of one run: the flag under test, and what keeps the render short.
fn render_args(flag: &'static str, value: &str) -> Vec<String> {
    let mut args: Vec<String> = vec!["render".into(), "s.toml".into(), "--quiet".into()];
    match flag {
        // Both cap the work when the other is huge.
        "--spp" => args.extend(["--time".into(), "1".into()]),
        "--time" => args.extend(["--spp".into(), "2".into()]),
        // --task-index I J: I as the index, J as the count.
        "--task-index" => {
            let (i, n) = value.split_once(' ').unwrap();
            args.extend([format!("--task-index={i}"), format!("--task-count={n}")]);
            return args;
        }
        _ => {}
    }
    // One argument, so that a value starting with '-' is never read as a flag.
    args.push(format!("{flag}={value}"));
    args
}

/// Runs brume in `dir`, killing it past `limit`; returns (exit code, stderr, time taken).
fn run(dir: &Path, args: &[String], limit: Duration) -> (Option<i32>, String, Duration) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_brume"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() && start.elapsed() < limit {
        std::thread::sleep(Duration::from_millis(5));
    }
    let took = start.elapsed();
    let _ = child.kill();
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        took,
    )
}

/// A 2×2 sky, one sample per pixel: any time beyond a fraction of a second is the flag's doing.
fn tiny_scene(dir: &Path) {
    std::fs::write(
        dir.join("s.toml"),
        "[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n\
         resolution = [2, 2]\n[integrator]\nspp = 1\n\
         [[light]]\ntype = \"environment\"\nradiance = [0.8, 0.9, 1.0]\n",
    )
    .unwrap();
}

/// The bound for a hang; runs here take well under a second or two.
const HANG: Duration = Duration::from_secs(20);

fn assert_answered(args: &[String], code: Option<i32>, err: &str, took: Duration) {
    assert!(took < HANG, "{args:?} still running after {took:?}: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "{args:?} panicked: {err}"
    );
    assert!(
        matches!(code, Some(0) | Some(2)),
        "{args:?} exited {code:?}: {err}"
    );
    if code == Some(2) {
        let line = err.lines().find(|l| l.starts_with("error:")).unwrap_or("");
        assert!(
            !line.is_empty(),
            "{args:?}: exit 2 with no error line: {err}"
        );
        plain(line);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn render_with_extreme_flag_values_exits_0_or_2_promptly((flag, value) in render_flag()) {
        let dir = tempfile::tempdir().unwrap();
        tiny_scene(dir.path());
        let args = render_args(flag, &value);
        let (code, err, took) = run(dir.path(), &args, HANG);
        assert_answered(&args, code, &err, took);
    }

    #[test]
    fn compare_and_airlight_refuse_bad_values_by_name(which in 0usize..4, value in extreme()) {
        let dir = tempfile::tempdir().unwrap();
        let (flag, valid) = [
            ("--max-rmse", values::rmse(&value).is_ok()),
            ("--visibility", (1e-3..=1e9).contains(&value.parse::<f64>().unwrap_or(f64::NAN))),
            ("--spp", values::whole(1u32, u32::MAX)(&value).is_ok()),
            ("--width", values::whole(64u32, 32768)(&value).is_ok()),
        ][which];
        if flag == "--max-rmse" {
            // Identical images: RMSE 0, within any bound the parser accepts.
            tiny_scene(dir.path());
            let (code, err, _) = run(dir.path(), &["render".into(), "s.toml".into(), "--quiet".into()], HANG);
            assert_eq!(code, Some(0), "{err}");
            let args = vec!["compare".into(), "s.exr".into(), "s.exr".into(), format!("--max-rmse={value}")];
            let (code, err, took) = run(dir.path(), &args, HANG);
            assert_answered(&args, code, &err, took);
            prop_assert_eq!(code == Some(0), valid, "{:?}: {}", args, err);
        } else if !valid {
            // The airlight demo renders for minutes at valid values: only the refusals are run.
            let args = vec!["airlight".into(), "--out".into(), "a".into(), format!("{flag}={value}")];
            let (code, err, took) = run(dir.path(), &args, HANG);
            assert_answered(&args, code, &err, took);
            prop_assert_eq!(code, Some(2));
            prop_assert!(err.contains(flag), "{}", err);
            prop_assert!(!dir.path().join("a").exists(), "airlight wrote before refusing");
        }
    }
}

/// The random text that once failed the property above: it holds `u64`,
/// which the frame-step message quotes back.
#[test]
fn a_text_holding_a_rust_word_may_be_quoted_back() {
    all_parsers("Y&$¥ୃ:t𐴗𑏌eu64𐨖'N𑽉𐭔EG=¥ᏺ<Ѩ");
}
