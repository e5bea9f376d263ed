//! Each bidirectional strategy (s, t) alone, unweighted, estimates every
//! path of its length: on scenes where it can sample them all, its image
//! matches the path tracer's paths of exactly that length.

mod bdpt_support;

use bdpt_support::*;

/// Direct light (2 segments) and one bounce (3 segments) in the diffuse
/// box: camera hits (s = 0), next-event estimation (s = 1), connections and
/// light tracing (t = 1) each alone give the path tracer's image.
#[test]
fn every_strategy_alone_matches_the_path_tracer_in_a_diffuse_box() {
    let text = |d: u32| diffuse_box(d, 1.6, DIFFUSE_SPHERE);
    for segments in [2u32, 3] {
        let path = path_tracer_length(text, segments, 1024);
        let scene = scene_from_str(&text(segments - 1));
        let k = segments as usize;
        let wanted: Vec<(usize, usize)> = (0..=k).map(|s| (s, k + 1 - s)).collect();
        for ((s, t), est) in unweighted_pixels(&scene, 1024, &wanted) {
            eprintln!(
                "({s},{t}) {:?} vs path {:?}",
                image_mean(&est),
                image_mean(&path)
            );
            assert_agree(&est, &path, &format!("unweighted ({s}, {t})"));
        }
    }
}
