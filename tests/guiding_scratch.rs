mod common;
use brume::integrator::guiding::GuidedPathTracer;
use brume::render::train_guide;
use common::*;
use std::sync::atomic::AtomicBool;
#[test]
fn scratch() {
    let medium = "[[medium]]\ntype = \"homogeneous\"\nsigma_t = 4.0\nalbedo = 1.0\nphase = { type = \"hg\", g = 0.8 }\nbounds = { type = \"sphere\", radius = 1.0 }\n";
    let scene = scene_from_str(&furnace_scene(medium, 1.0));
    let guide = train_guide(&scene, &AtomicBool::new(false)).unwrap();
    eprintln!("guide {:?}", guide.size());
    let tracer = GuidedPathTracer { guide: &guide };
    let mut acc = Accumulator::default();
    let mut maxv = 0.0f32;
    let mut hist = [0u64; 8];
    for s in 0..20000 {
        let v = tracer.pixel_sample(&scene, 3, 2, s);
        maxv = maxv.max(v.r);
        let b = if v.r <= 0.0 { 0 } else { ((v.r.log2() + 4.0).max(0.0) as usize).min(7) };
        hist[b] += 1;
        acc.add(v);
    }
    let e = acc.estimate();
    eprintln!("mean {:?} se {:?} max {maxv} hist {:?}", e.mean, e.std_error, hist);
}
