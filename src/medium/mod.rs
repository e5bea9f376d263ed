//! Participating media: phase functions (and, later, media).

pub mod phase;
