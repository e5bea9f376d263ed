//! The airlight demo in its exact configuration: an absorbing, emitting
//! global medium (σs = 0, emission Le) and emissive targets, where
//! Koschmieder's law L(d) = L0·e^(-σa·d) + Le·(1 - e^(-σa·d)) holds exactly.
//!
//! Each camera sample either reaches the target (value L0, probability
//! T = e^(-σa·d)) or is absorbed on the way (value Le), so a target's mean over
//! N samples has standard error |L0 - Le|·√(T(1-T)/N): the targets are one
//! family of the shared `assert_within` (tests/common/stats.rs), and the fitted
//! σt is compared within the fit's own standard error the same way.

mod common;

use brume::airlight::{koschmieder, run, AirlightMode, AirlightOptions, AirlightReport};
use common::assert_within;

/// The fit used enough targets, and its σt lies within its own standard error (the one k) of `sigma`.
fn assert_fits_the_true_extinction(report: &AirlightReport, sigma: f64) {
    assert!(report.fit_rows >= 4, "{}", report.table);
    assert_within(
        report.sigma_t_fit,
        report.sigma_t_fit_std_error,
        sigma,
        1,
        &format!("fitted σt vs true\n{}", report.table),
    );
}

#[test]
fn exact_airlight_measurements_follow_koschmieder() {
    let dir = tempfile::tempdir().unwrap();
    let spp = 16;
    let options = AirlightOptions {
        out: Some(dir.path().to_path_buf()),
        visibility: 800.0,
        spp,
        width: 192,
        mode: AirlightMode::EmissionAbsorption,
        seed: 5,
        threads: None,
        progress: false,
    };
    let report = run(&options).expect("demo runs");
    let (l0_bright, l0_dark, le) = report.exact.expect("exact mode");
    let sigma = report.sigma_t_true;
    assert!((sigma - 50f64.ln() / 800.0).abs() < 1e-12);
    // The horizon is the medium's own emission: every sample is absorbed before escaping.
    assert!(report.horizon.pixels > 50, "{report:?}");
    assert!(
        (report.horizon.mean.luminance() as f64 - le).abs() < 1e-5,
        "{}",
        report.table
    );
    let checks = 2 * report.rows.len();
    for row in &report.rows {
        for (m, l0) in [(&row.bright, l0_bright), (&row.dark, l0_dark)] {
            assert!(
                m.pixels >= 20,
                "too few pixels at {} m: {}",
                row.distance,
                m.pixels
            );
            let t = (-sigma * m.distance).exp();
            let want = koschmieder(l0, le, sigma, m.distance);
            let n = (m.pixels * spp as usize) as f64;
            let se = (l0 - le).abs() * (t * (1.0 - t) / n).sqrt();
            let got = m.mean.luminance() as f64;
            let what = format!(
                "target at {} m (L0 = {l0}) vs Koschmieder\n{}",
                row.distance, report.table
            );
            assert_within(got, se, want, checks, &what);
        }
    }
    assert_fits_the_true_extinction(&report, sigma);
    for name in [
        "airlight.exr",
        "airlight.png",
        "airlight.csv",
        "airlight_plot.png",
        "airlight.toml",
    ] {
        assert!(dir.path().join(name).is_file(), "{name} missing");
    }
    let csv = std::fs::read_to_string(dir.path().join("airlight.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + report.rows.len());
}

#[test]
fn bad_airlight_options_are_rejected() {
    let base = AirlightOptions {
        out: None,
        ..AirlightOptions::default()
    };
    for options in [
        AirlightOptions {
            visibility: 0.0,
            ..base.clone()
        },
        AirlightOptions {
            visibility: f32::NAN,
            ..base.clone()
        },
        AirlightOptions {
            spp: 0,
            ..base.clone()
        },
    ] {
        assert!(run(&options).is_err());
    }
}

/// The `brume airlight` subcommand writes its files and rejects a bad visibility with exit code 2.
#[test]
fn airlight_subcommand_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let output = assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .args([
            "airlight", "--exact", "--width", "64", "--spp", "2", "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    assert!(String::from_utf8_lossy(&output.stdout).contains("sigma_t fitted"));
    let plot = std::fs::File::open(out.join("airlight_plot.png")).unwrap();
    let reader = png::Decoder::new(plot).read_info().unwrap();
    assert_eq!((reader.info().width, reader.info().height), (900, 720));
    assert_cmd::Command::cargo_bin("brume")
        .unwrap()
        .args(["airlight", "--visibility", "-5", "--out"])
        .arg(dir.path().join("bad"))
        .assert()
        .code(2);
}

/// The single-scattering configuration: a zenith sun over a scattering slab,
/// one scattering event per path. On a horizontal line of sight at the eye's
/// height the source σs p E e^(-σt h_top) is constant, so Koschmieder holds
/// exactly with L_air = α E/(4π) e^(-σt h_top) (isotropic phase): the horizon
/// must show that value, and the fitted σt must lie within 4 of its standard
/// errors of the true one.
#[test]
fn single_scattering_airlight_fits_the_true_extinction() {
    use brume::airlight::{SLAB_TOP, SS_ALBEDO, SS_IRRADIANCE};
    let options = AirlightOptions {
        out: None,
        visibility: 1000.0,
        spp: 16,
        width: 256,
        mode: AirlightMode::SingleScattering,
        seed: 9,
        threads: None,
        progress: false,
    };
    let report = run(&options).expect("demo runs");
    let sigma = report.sigma_t_true;
    let l_air = SS_ALBEDO as f64 * SS_IRRADIANCE as f64 / (4.0 * std::f64::consts::PI)
        * (-sigma * SLAB_TOP as f64).exp();
    let horizon = report.horizon.mean.luminance() as f64;
    let horizon_se = report.horizon.std_error;
    assert_within(
        horizon,
        horizon_se,
        l_air,
        1,
        &format!("L_air\n{}", report.table),
    );
    assert_fits_the_true_extinction(&report, sigma);
}

/// `--out` is checked by the output-safety rule before rendering: an
/// existing file that is not a folder, an output that is a folder, and two
/// outputs that are one file are refused with exit code 2, and nothing is
/// written (the user's file stays as it was).
#[test]
fn airlight_refuses_unsafe_outputs_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    std::fs::create_dir_all(d.join("folder_output/airlight.toml")).unwrap();
    std::fs::create_dir(d.join("linked")).unwrap();
    std::os::unix::fs::symlink("airlight.csv", d.join("linked/airlight.png")).unwrap();
    for (out, needle) in [
        ("notes.txt", "notes.txt exists and is not a folder"),
        ("folder_output", "airlight.toml: is a directory"),
        ("linked", "is the same file as --out"),
    ] {
        let output = assert_cmd::Command::cargo_bin("brume")
            .unwrap()
            .current_dir(d)
            .args(["airlight", "--width", "64", "--spp", "1", "--out", out])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{out}: {stderr}");
        assert!(
            stderr.starts_with("error: invalid argument --out: ") && stderr.contains(needle),
            "{out}: {stderr}"
        );
        assert!(
            !d.join(out).join("airlight.exr").exists(),
            "{out}: rendered"
        );
    }
    assert_eq!(
        std::fs::read_to_string(d.join("notes.txt")).unwrap(),
        "mine"
    );
}
