//! VDB bytes → open → load every grid → lookups: errors are fine, panics,
//! aborts, huge allocations and hangs are not.
#![no_main]

#[path = "../harness.rs"]
mod harness;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| harness::vdb_load(data));
