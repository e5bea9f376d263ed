use super::*;
use crate::film::{SampleRange, Splat};
use crate::math::color::Rgb;

fn piece() -> Film {
    let provenance = Provenance {
        seed: u64::MAX - 3,
        scene_hash: 0xfeed_beef_0123_4567,
        spp_total: 64,
        requested: vec![SampleRange::new(16, 32)],
        held: vec![SampleRange::new(16, 24)],
    };
    let window = Rect {
        x0: 2,
        x1: 5,
        y0: 1,
        y1: 3,
    };
    let mut film = Film::new((7, 4), window, provenance);
    for i in 0..6 {
        film.counts[i] = 8 - i as u32 % 2;
        film.nonfinite[i] = i as u32 % 2;
        for c in 0..3 {
            film.layers[0].sums[3 * i + c] = 1.0 / 3.0 + i as f64 * 1e-3 + c as f64;
        }
    }
    let albedo = film.add_aov(Aov::Albedo).unwrap();
    albedo
        .sums
        .iter_mut()
        .enumerate()
        .for_each(|(i, s)| *s = 0.1 * i as f64);
    albedo.counts = Some(vec![8, 7, 0, 8, 8, 8]);
    film.add_aov(Aov::Depth).unwrap().counts = Some(vec![3, 0, 0, 1, 8, 8]);
    film
}

/// Writes `film` and reads it back.
fn round_trip(film: &Film) -> Film {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("piece.exr");
    write_film_exr(&path, film).unwrap();
    read_film_exr(&path).unwrap()
}

/// Windows, provenance and counts come back exactly; every mean comes back
/// as the f32 it was written as, and a second round trip changes nothing.
#[test]
fn a_film_round_trips_its_windows_header_counts_and_means() {
    let film = piece();
    let back = round_trip(&film);
    assert_eq!((back.display, back.window), (film.display, film.window));
    assert_eq!(back.provenance, film.provenance);
    assert_eq!(
        (&back.counts, &back.nonfinite),
        (&film.counts, &film.nonfinite)
    );
    assert_eq!(back.layers.len(), 3);
    for (a, b) in film.layers.iter().zip(&back.layers) {
        assert_eq!(
            (&a.name, &a.channels, &a.counts),
            (&b.name, &b.channels, &b.counts)
        );
        for i in 0..6 {
            for c in 0..a.channels.len() {
                assert_eq!(film.mean(a, i, c).to_bits(), back.mean(b, i, c).to_bits());
            }
        }
    }
    // Sums are the f32 means times the counts: within f32 rounding of the render's.
    for (a, b) in film.layers[0].sums.iter().zip(&back.layers[0].sums) {
        assert!((a - b).abs() <= a.abs() * f32::EPSILON as f64, "{a} vs {b}");
    }
    assert_eq!(round_trip(&back), back);
    // The depth of a pixel no sample met is +∞ and its sum 0, not NaN.
    let depth = back.layer("depth").unwrap();
    assert_eq!(back.mean(depth, 1, 0), f32::INFINITY);
    assert_eq!(depth.sums[1], 0.0);
}

/// A render's EXR holds the image channels only: R, G, B and the AOVs.
#[test]
fn the_exr_holds_only_image_channels() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("piece.exr");
    let mut film = piece();
    film.add_aov(Aov::Alpha);
    write_film_exr(&path, &film).unwrap();
    let (w, h, channels) = super::super::read_exr_channels(&path).unwrap();
    assert_eq!((w, h), (3, 2));
    let mut names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(
        names,
        ["A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z"]
    );
    // Viewers and the RGB reader see the beauty of the data window.
    let (_, _, pixels) = super::super::read_exr(&path).unwrap();
    assert_eq!(pixels, film.beauty_image().pixels);
}

/// Splats outside the data window come back through the `splats` part, and
/// each pixel's mean is its pixel less its splat part.
#[test]
fn splats_round_trip_over_the_display_window() {
    let mut film = piece();
    film.add_splats();
    let splat = |x, y, v| Splat {
        x,
        y,
        radiance: Rgb::new(v, 0.0, 2.0 * v),
    };
    // One inside the crop (pixel 4,2 = index 5), one outside it.
    film.splats
        .as_mut()
        .unwrap()
        .add(&[splat(4, 2, 4.0), splat(6, 3, 0.5)]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("splats.exr");
    write_film_exr(&path, &film).unwrap();
    let back = read_film_exr(&path).unwrap();
    let splats = back.splats.as_ref().unwrap();
    assert_eq!(splats.at(6, 3), [0.5, 0.0, 1.0]);
    assert_eq!(splats.at(4, 2), [4.0, 0.0, 8.0]);
    assert_eq!(back.pixel(5), film.pixel(5));
    assert_eq!(back.pixel(5).r, film.mean(&film.layers[0], 5, 0) + 0.5);
    // The mean comes back as the f32 pixel less the f32 splat part: within
    // one f32 step of the pixel.
    let (mean, was) = (
        back.mean(&back.layers[0], 5, 0),
        film.mean(&film.layers[0], 5, 0),
    );
    assert!(
        (mean - was).abs() <= f32::EPSILON * film.pixel(5).r,
        "{mean} vs {was}"
    );
    let (_, _, pixels) = super::super::read_exr(&path).unwrap();
    assert_eq!(pixels, film.beauty_image().pixels);
    assert_eq!(round_trip(&back), back);
}

#[test]
fn an_exr_without_brume_header_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plain.exr");
    let image = super::super::Image {
        width: 2,
        height: 2,
        pixels: vec![Rgb::BLACK; 4],
        spp: 1,
        partial: false,
    };
    super::super::write_exr(&path, &image).unwrap();
    let err = read_film_exr(&path).unwrap_err().to_string();
    assert!(
        err.contains("plain.exr") && err.contains("not a brume film"),
        "{err}"
    );
}
