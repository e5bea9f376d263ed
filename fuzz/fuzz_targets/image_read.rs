//! Image bytes → every EXR reader and the PNG reader: a header may declare
//! any size; errors are fine, allocations beyond what the file can hold (or
//! the memory limit), panics, aborts and hangs are not.
#![no_main]

#[path = "../harness.rs"]
mod harness;

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder for the input written as a file (the readers take paths), made once.
fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("brume-fuzz-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        dir
    })
}

fuzz_target!(|data: &[u8]| harness::image_read(data, dir()));
