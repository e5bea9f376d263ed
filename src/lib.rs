//! brume: a physically based renderer for participating media.
pub mod volume;
