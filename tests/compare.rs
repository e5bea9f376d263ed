//! `brume compare` on images whose differences are known exactly.

use brume::film::image_io::{write_exr, Image};
use brume::math::color::Rgb;
use std::path::Path;

fn write(path: &Path, width: usize, pixels: Vec<Rgb>) {
    let height = pixels.len() / width;
    let image = Image {
        width,
        height,
        pixels,
        spp: 1,
        partial: false,
    };
    write_exr(path, &image).unwrap();
}

fn brume() -> assert_cmd::Command {
    assert_cmd::Command::cargo_bin("brume").unwrap()
}

/// A 16×8 reference of 0.5 against a copy whose left half is 0.5 + 0.2 in
/// green only: one value in six is off by 0.2, so RMSE = 0.2/√6.
#[test]
fn compare_reports_the_known_rmse_and_enforces_the_threshold() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
    let reference = vec![Rgb::splat(0.5); 16 * 8];
    let test: Vec<Rgb> = (0..16 * 8)
        .map(|i| {
            if i % 16 < 8 {
                Rgb::new(0.5, 0.7, 0.5)
            } else {
                Rgb::splat(0.5)
            }
        })
        .collect();
    write(&a, 16, test);
    write(&b, 16, reference);
    let rmse = 0.2 / 6f64.sqrt();
    let diff = dir.path().join("diff.png");
    let out = brume()
        .arg("compare")
        .args([&a, &b])
        .arg("--diff")
        .arg(&diff)
        .arg("--max-rmse")
        .arg(format!("{}", rmse * 1.01))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let line = stdout.lines().find(|l| l.starts_with("rmse")).unwrap();
    let value: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    assert!((value - rmse).abs() < 1e-6 * rmse, "{value} vs {rmse}");
    assert!(
        stdout.contains("mean A (R G B)  0.500000 0.600000 0.500000"),
        "{stdout}"
    );
    assert!(stdout.contains("max difference  2.0000"), "{stdout}");
    let reader = png::Decoder::new(std::fs::File::open(&diff).unwrap())
        .read_info()
        .unwrap();
    assert_eq!((reader.info().width, reader.info().height), (16, 8));
    // Just under the RMSE: exit 1, usable in CI.
    brume()
        .arg("compare")
        .args([&a, &b])
        .arg("--max-rmse")
        .arg(format!("{}", rmse * 0.99))
        .assert()
        .code(1);
    // An image against itself is identical.
    brume()
        .arg("compare")
        .args([&b, &b])
        .args(["--max-rmse", "0"])
        .assert()
        .code(0);
}

#[test]
fn compare_rejects_images_of_different_sizes_and_missing_files() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
    write(&a, 4, vec![Rgb::BLACK; 8]);
    write(&b, 2, vec![Rgb::BLACK; 8]);
    let out = brume().arg("compare").args([&a, &b]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("only images of one size"));
    brume()
        .arg("compare")
        .arg(&a)
        .arg(dir.path().join("missing.exr"))
        .assert()
        .code(2);
    brume()
        .arg("compare")
        .args([&a, &a])
        .args(["--max-rmse", "-1"])
        .assert()
        .code(2);
}
