//! Sizes declared by files, read under a counting allocator: EXR and PNG
//! headers declaring any size (through every reader brume has), and velocity
//! scales moving a medium any distance (through scene loading).
//!
//! Properties, each over random headers:
//! - a file too short for what its header declares (even at the best ratio
//!   its compression allows, from the formats' own limits) is refused, and
//!   refusing it allocates almost nothing (no allocation larger than the
//!   input needs);
//! - an image whose decoded size is over the memory limit is refused;
//! - nothing read ever allocates more than a small multiple of the limit.
//!
//! Every test in this binary takes `SERIAL`, so that one measures at a time.

mod limits_support;

use limits_support::{exr, exr_ratio_bound, png, tiny_rgb_exr, tiny_rgb_png};
use proptest::prelude::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(size: usize) {
    let now = CURRENT.fetch_add(size, Ordering::SeqCst) + size;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

// SAFETY: every call is forwarded to the system allocator unchanged; the
// counters only observe sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        System.dealloc(p, layout);
        CURRENT.fetch_sub(layout.size(), Ordering::SeqCst);
    }
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let q = System.realloc(p, layout, new_size);
        if !q.is_null() {
            CURRENT.fetch_sub(layout.size(), Ordering::SeqCst);
            grew(new_size);
        }
        q
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

static SERIAL: Mutex<()> = Mutex::new(());

/// The memory limit of every test here (64 MB).
const LIMIT: usize = 64_000_000;
/// What reading a header, refusing it and reporting costs.
const SMALL: usize = 1 << 20;

fn serial() -> std::sync::MutexGuard<'static, ()> {
    brume::error::limits::set_memory_limit(LIMIT as u64);
    SERIAL.lock().unwrap_or_else(|p| p.into_inner())
}

/// `f`'s result and the most it held allocated at once beyond what was allocated before.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = CURRENT.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = f();
    (out, PEAK.load(Ordering::SeqCst).saturating_sub(base))
}

type Reader = fn(&Path) -> Result<(), String>;

/// brume's three EXR readers (environment maps and compare; textures; merge pieces).
const EXR_READERS: [(&str, Reader); 3] = [
    ("read_exr", |p| {
        brume::film::image_io::read_exr(p)
            .map(drop)
            .map_err(|e| e.to_string())
    }),
    ("read_exr_channels", |p| {
        brume::film::image_io::read_exr_channels(p)
            .map(drop)
            .map_err(|e| e.to_string())
    }),
    ("read_film_exr", |p| {
        brume::film::image_io::read_film_exr(p)
            .map(drop)
            .map_err(|e| e.to_string())
    }),
];

fn read_png(p: &Path) -> Result<(), String> {
    brume::film::image_io::read_png(p)
        .map(drop)
        .map_err(|e| e.to_string())
}

/// Writes `bytes` to a fresh file and returns each reader's result and peak allocation.
fn read_all(
    bytes: &[u8],
    name: &str,
    readers: &[(&str, Reader)],
) -> Vec<(String, Result<(), String>, usize)> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    readers
        .iter()
        .map(|(reader, read)| {
            let (result, peak) = peak_during(|| read(&path));
            (reader.to_string(), result, peak)
        })
        .collect()
}

#[test]
fn a_few_hundred_bytes_declaring_a_huge_image_is_refused_by_every_reader_without_allocating_it() {
    let _serial = serial();
    for (w, h) in [(60000, 60000), (20000, 20000), (8000, 8000)] {
        let file = tiny_rgb_exr(w, h);
        assert!(file.len() < 400);
        for (reader, result, peak) in read_all(&file, "sky.exr", &EXR_READERS) {
            let e = result.expect_err(&reader);
            let declares = format!("sky.exr: declares {w}x{h} pixels (");
            assert!(
                e.contains(&declares) && e.contains("truncated or damaged"),
                "{reader}: {e}"
            );
            assert!(peak < SMALL, "{reader} allocated {peak} bytes for {w}x{h}");
        }
        let file = tiny_rgb_png(w as u32, h as u32);
        let (_, result, peak) = read_all(&file, "t.png", &[("read_png", read_png)]).remove(0);
        let e = result.unwrap_err();
        assert!(
            e.contains(&format!("t.png: declares {w}x{h} pixels (")),
            "{e}"
        );
        assert!(peak < SMALL, "read_png allocated {peak} bytes for {w}x{h}");
    }
}

/// Bytes a header's channels hold before compression, and after decoding to 4-byte values.
fn exr_sizes(window: [i32; 4], channels: &[(&str, i32)]) -> (u128, u128) {
    let w = (window[2] as i64 - window[0] as i64 + 1).max(0) as u128;
    let h = (window[3] as i64 - window[1] as i64 + 1).max(0) as u128;
    let raw: u128 = channels
        .iter()
        .map(|(_, t)| if *t == 1 { 2 } else { 4 })
        .sum();
    (w * h * raw, w * h * 4 * channels.len() as u128)
}

fn side() -> impl Strategy<Value = i32> {
    prop_oneof![1..64i32, 64..100_000i32, 100_000..i32::MAX]
}

/// An EXR header to write: data window, compression code, channels (name,
/// sample type) and the bytes after the header.
type ExrCase = ([i32; 4], u8, Vec<(&'static str, i32)>, Vec<u8>);

fn exr_case() -> impl Strategy<Value = ExrCase> {
    let names = ["A", "B", "G", "R", "Y"];
    (
        (-1000..1000i32, -1000..1000i32, side(), side()),
        prop_oneof![0..10u8, Just(10u8), Just(11u8)],
        proptest::sample::subsequence(names.to_vec(), 1..=5),
        proptest::collection::vec(0..3i32, 5),
        proptest::collection::vec(any::<u8>(), 0..2048),
    )
        .prop_map(|((x0, y0, w, h), c, names, kinds, tail)| {
            let window = [x0, y0, x0.saturating_add(w - 1), y0.saturating_add(h - 1)];
            let channels = names.into_iter().zip(kinds).collect();
            (window, c, channels, tail)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn exr_headers_of_any_size_are_refused_or_read_within_the_limit(
        (window, compression, channels, tail) in exr_case()
    ) {
        let _serial = serial();
        let file = exr(window, compression, &channels, &tail);
        let (raw, decoded) = exr_sizes(window, &channels);
        let too_short = raw > file.len() as u128 * exr_ratio_bound(compression) as u128;
        for (reader, result, peak) in read_all(&file, "x.exr", &EXR_READERS) {
            if too_short {
                prop_assert!(result.is_err(), "{}: {} bytes declaring {} read", reader, file.len(), raw);
                prop_assert!(peak < SMALL, "{}: {} bytes allocated refusing {} bytes", reader, peak, file.len());
            }
            if decoded > LIMIT as u128 {
                prop_assert!(result.is_err(), "{}: {} decoded bytes read", reader, decoded);
            }
            prop_assert!(peak < 4 * LIMIT + SMALL, "{}: {} bytes allocated", reader, peak);
        }
    }

    #[test]
    fn png_headers_of_any_size_are_refused_or_read_within_the_limit(
        (w, h) in (side(), side()),
        (depth, colour) in prop_oneof![
            Just((8u8, 0u8)), Just((1, 0)), Just((16, 0)), Just((8, 2)), Just((16, 2)),
            Just((1, 3)), Just((8, 3)), Just((8, 4)), Just((8, 6)), Just((16, 6))
        ],
        interlaced in any::<bool>(),
        idat in proptest::collection::vec(any::<u8>(), 0..2048),
    ) {
        let _serial = serial();
        let file = png(w as u32, h as u32, depth, colour, interlaced, &idat);
        let samples = [1u128, 0, 3, 1, 2, 0, 4][colour as usize];
        let raw = h as u128 * (1 + (w as u128 * samples * depth as u128).div_ceil(8));
        let expanded = if colour == 3 { 3 } else { samples };
        let decoded = w as u128 * h as u128 * expanded * 4;
        let (_, result, peak) = read_all(&file, "x.png", &[("read_png", read_png)]).remove(0);
        if raw > file.len() as u128 * 1032 {
            prop_assert!(result.is_err(), "{} bytes declaring {} read", file.len(), raw);
            prop_assert!(peak < SMALL, "{} bytes allocated refusing {} bytes", peak, file.len());
        }
        if decoded > LIMIT as u128 {
            prop_assert!(result.is_err(), "{} decoded bytes read", decoded);
        }
        prop_assert!(peak < 4 * LIMIT + SMALL, "{} bytes allocated", peak);
    }
}

/// A moving plume: `velocity_scale` and the shutter are the test's.
fn moving_plume(velocity_scale: f64, shutter: f64) -> String {
    let plume = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/anim/plume.0001.vdb");
    format!(
        r#"
        [camera]
        position = [0.0, 0.6, 2.5]
        look_at = [0.0, 0.6, 0.0]
        resolution = [4, 4]
        shutter = [{open}, {shutter}]
        [animation]
        fps = 24.0
        [[light]]
        type = "sun"
        direction = [-0.5, -1.0, -0.3]
        irradiance = [4.0, 4.0, 4.0]
        [[medium]]
        type = "vdb"
        file = "{}"
        density_scale = 30.0
        velocity_grid = "vel"
        velocity_scale = {velocity_scale:e}
        "#,
        plume.display(),
        open = -shutter,
    )
}

/// Loads a scene; the error text when it is refused.
fn load(text: &str) -> Result<(), String> {
    let file = Path::new("moving.toml");
    let desc = brume::scene::parse(text, file).map_err(|e| e.to_string())?;
    brume::scene::build(&desc, file, Path::new("."))
        .map(drop)
        .map_err(|e| e.to_string())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    /// Any velocity scale, however extreme: the motion-dilated majorant grid
    /// is built within the limit or refused on the key, never allocated past it.
    #[test]
    fn any_velocity_scale_builds_within_the_limit_or_names_the_key(
        // Half the cases where the plume's grid crosses the limit (scales of 100 to 30000).
        exponent in prop_oneof![-3.0..38.0f64, 2.0..4.5f64],
        sign in prop_oneof![Just(1.0), Just(-1.0)],
        shutter in prop_oneof![Just(0.5), Just(1.0), Just(1e-6)],
    ) {
        let _serial = serial();
        let (_, still) = peak_during(|| load(&moving_plume(0.0, shutter)));
        let scale = sign * 10f64.powf(exponent);
        let (result, peak) = peak_during(|| load(&moving_plume(scale, shutter)));
        if let Err(e) = &result {
            prop_assert!(e.starts_with("moving.toml: medium[0].velocity_scale: "), "{}", e);
            prop_assert!(e.contains("majorant grid needs"), "{}", e);
        }
        prop_assert!(peak <= still + LIMIT, "velocity_scale {:e}: {} bytes, {} still", scale, peak, still);
    }
}

#[test]
fn a_velocity_scale_of_1e30_is_refused_at_once_with_the_key_and_the_grid() {
    let _serial = serial();
    let started = std::time::Instant::now();
    let (result, peak) = peak_during(|| load(&moving_plume(1e30, 0.5)));
    let e = result.unwrap_err();
    assert!(
        e.starts_with("moving.toml: medium[0].velocity_scale: over the shutter [-0.5, 0.5] the medium moves up to "),
        "{e}"
    );
    assert!(
        e.contains("its majorant grid needs more cells than can be counted"),
        "{e}"
    );
    assert!(peak < 16 * SMALL, "{peak}");
    assert!(started.elapsed().as_secs_f64() < 5.0);
}
