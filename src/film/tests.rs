use super::*;

fn provenance(held: Vec<SampleRange>) -> Provenance {
    Provenance {
        seed: 0,
        scene_hash: 0,
        spp_total: 4,
        requested: vec![SampleRange::new(0, 4)],
        held,
    }
}

fn crop() -> Rect {
    Rect {
        x0: 2,
        x1: 5,
        y0: 1,
        y1: 3,
    }
}

#[test]
fn pixels_index_the_data_window_of_the_display() {
    let film = Film::new((8, 6), crop(), provenance(vec![]));
    assert_eq!(film.index(2, 1), Some(0));
    assert_eq!(film.index(4, 2), Some(5));
    assert_eq!(film.index(5, 2), None);
    assert_eq!(film.index(1, 1), None);
    assert_eq!(film.position(5), (4, 2));
    assert!(!film.provenance.complete());
}

#[test]
fn aov_layers_have_unique_names_and_their_own_counts() {
    let mut film = Film::new((2, 2), Rect::full(2, 2), provenance(vec![]));
    assert!(film.add_aov(Aov::Albedo).is_some());
    assert!(film.add_aov(Aov::Albedo).is_none());
    let albedo = film.layer("albedo").unwrap();
    assert_eq!(albedo.sums.len(), 12);
    assert_eq!(albedo.channel_name(1), "albedo.G");
    assert_eq!(film.layers[0].channel_name(2), "B");
    film.add_aov(Aov::Depth);
    film.counts[0] = 3;
    // The depth of a pixel no sample hit is +∞ whatever the beauty's count.
    let depth = film.layer("depth").unwrap();
    assert_eq!(film.mean(depth, 0, 0), f32::INFINITY);
    assert_eq!(film.layer("alpha"), None);
}

/// A pixel is (sum of its samples)/count + (splat sum)/(samples per pixel
/// held): 2 finite samples summing to 3 and a splat sum of 2 over 4 held samples.
#[test]
fn a_pixel_is_its_mean_plus_its_splats_over_the_samples_per_pixel() {
    let mut film = Film::new((8, 6), crop(), provenance(vec![SampleRange::new(0, 4)]));
    film.add_splats();
    film.counts[5] = 2;
    film.nonfinite[5] = 2;
    film.layers[0].sums[15..18].copy_from_slice(&[3.0, 0.0, 1.0]);
    film.splats.as_mut().unwrap().add(&[Splat {
        x: 4,
        y: 2,
        radiance: Rgb::new(2.0, 1.0, 0.0),
    }]);
    assert_eq!(film.pixel(5), Rgb::new(1.5 + 0.5, 0.25, 0.5));
    assert_eq!(film.mean(&film.layers[0], 5, 0), 1.5);
    // Pixel 0 has no finite sample and no splat: black, not NaN.
    assert_eq!(film.pixel(0), Rgb::BLACK);
    assert_eq!(film.beauty_image().pixels[5], film.pixel(5));
}

#[test]
fn layer_means_are_the_means_of_every_channel() {
    // Over two tasks of pixels, with pixels of no samples (the empty value),
    // a layer with its own counts (depth) and one on the film's (normal).
    let (w, h) = (200, 170);
    let mut film = Film::new((w, h), Rect::full(w, h), provenance(vec![]));
    film.add_aov(Aov::Depth);
    film.add_aov(Aov::Normal);
    let n = (w * h) as usize;
    for i in 0..n {
        film.counts[i] = (i % 5) as u32;
    }
    for layer in film.layers.iter_mut() {
        let k = layer.channels.len();
        for (j, s) in layer.sums.iter_mut().enumerate() {
            *s = (j as f64).sin() * 7.0 + (j / k) as f64;
        }
        if let Some(counts) = layer.counts.as_mut() {
            for (i, c) in counts.iter_mut().enumerate() {
                *c = (i % 3) as u32;
            }
        }
    }
    for layer in &film.layers[1..] {
        let means = film.layer_means(layer);
        assert_eq!(means.len(), layer.channels.len());
        for (c, values) in means.iter().enumerate() {
            assert_eq!(values.len(), n);
            for (i, &v) in values.iter().enumerate() {
                assert_eq!(
                    v.to_bits(),
                    film.mean(layer, i, c).to_bits(),
                    "{} {c} {i}",
                    layer.name
                );
            }
        }
    }
}
