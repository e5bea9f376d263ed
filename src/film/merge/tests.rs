use super::*;

fn piece(window: Rect, requested: SampleRange, held: SampleRange, value: f64) -> Film {
    let provenance = Provenance {
        seed: 1,
        scene_hash: 2,
        spp_total: 8,
        requested: vec![requested],
        held: if held.is_empty() { vec![] } else { vec![held] },
    };
    let mut film = Film::new((4, 2), window, provenance);
    film.counts.fill(held.len());
    film.layers[0].sums.fill(value * held.len() as f64);
    film
}

fn named(films: Vec<Film>) -> Vec<(PathBuf, Film)> {
    films
        .into_iter()
        .enumerate()
        .map(|(i, f)| (PathBuf::from(format!("p{i}.exr")), f))
        .collect()
}

const FULL: Rect = Rect {
    x0: 0,
    x1: 4,
    y0: 0,
    y1: 2,
};
const R: fn(u32, u32) -> SampleRange = SampleRange::new;

#[test]
fn sample_ranges_are_weighted_by_their_counts() {
    // An interrupted piece holding 2 samples of mean 4 and a whole piece of
    // 4 samples of mean 1: mean (8 + 4) / 6 = 2, not the (4 + 1) / 2 of the means.
    let pieces = named(vec![
        piece(FULL, R(0, 4), R(0, 2), 4.0),
        piece(FULL, R(4, 8), R(4, 8), 1.0),
    ]);
    let merged = merge(&pieces).unwrap();
    let beauty = &merged.film.layers[0];
    assert_eq!(merged.film.mean(beauty, 5, 1), 2.0);
    assert_eq!(merged.film.counts[5], 6);
    assert_eq!(merged.notes.len(), 1);
    assert!(merged.notes[0].contains("p0.exr") && merged.notes[0].contains("0..2 of 0..4"));
    assert_eq!(merged.film.provenance.held, vec![R(0, 2), R(4, 8)]);
    assert!(!merged.film.provenance.complete());
}

#[test]
fn crops_are_placed_in_the_display_window() {
    let left = Rect {
        x0: 0,
        x1: 1,
        y0: 0,
        y1: 2,
    };
    let right = Rect {
        x0: 1,
        x1: 4,
        y0: 0,
        y1: 2,
    };
    let pieces = named(vec![
        piece(right, R(0, 8), R(0, 8), 3.0),
        piece(left, R(0, 8), R(0, 8), 5.0),
    ]);
    let merged = merge(&pieces).unwrap();
    let film = &merged.film;
    let means: Vec<f32> = (0..8).map(|i| film.mean(&film.layers[0], i, 0)).collect();
    assert_eq!(means, [5.0, 3.0, 3.0, 3.0, 5.0, 3.0, 3.0, 3.0]);
    assert!(film.provenance.complete() && merged.notes.is_empty());
}

#[test]
fn refusals_say_what_differs() {
    let err = |films: Vec<Film>| merge(&named(films)).err().unwrap().to_string();
    let a = piece(FULL, R(0, 4), R(0, 4), 1.0);
    let overlap = err(vec![a.clone(), piece(FULL, R(3, 8), R(3, 8), 1.0)]);
    assert!(
        overlap.contains("p1.exr (samples 3..8") && overlap.contains("overlaps p0.exr"),
        "{overlap}"
    );
    let missing = err(vec![a.clone(), piece(FULL, R(4, 6), R(4, 6), 1.0)]);
    assert!(
        missing.contains("missing piece: no piece holds samples 6..8 of pixel 0,0"),
        "{missing}"
    );
    let mut other_seed = piece(FULL, R(4, 8), R(4, 8), 1.0);
    other_seed.provenance.seed = 9;
    assert!(err(vec![a.clone(), other_seed]).contains("p1.exr: seed 9 differs from p0.exr's 1"));
    let mut other_scene = piece(FULL, R(4, 8), R(4, 8), 1.0);
    other_scene.provenance.scene_hash = 3;
    assert!(err(vec![a.clone(), other_scene]).contains("scene hash"));
    let mut other_size = piece(FULL, R(4, 8), R(4, 8), 1.0);
    other_size.display = (5, 2);
    assert!(err(vec![a, other_size]).contains("display window 5x2 differs from p0.exr's 4x2"));
}

#[test]
fn a_crop_gap_is_reported_with_its_pixel() {
    let top = Rect {
        x0: 0,
        x1: 4,
        y0: 0,
        y1: 1,
    };
    let e = merge(&named(vec![piece(top, R(0, 8), R(0, 8), 1.0)]))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("samples 0..8 of pixel 0,1 (4 of 8 pixels"),
        "{e}"
    );
}
