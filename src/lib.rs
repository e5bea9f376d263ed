//! brume: a physically based renderer for participating media.
//!
//! Fog, smoke, clouds and airlight, lit and shadowed together with ordinary
//! surfaces by one unbiased Monte Carlo radiance estimator.
//!
//! The module layout (14 rooms, bottom up) and the data flow of a render are
//! described in docs/architecture.md.

pub mod airlight;
pub mod camera;
pub mod error;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod medium;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod volume;

/// The test suite's one k (tests/common/k_sigma.rs), shared with the unit tests.
#[cfg(test)]
#[path = "../tests/common/k_sigma.rs"]
pub(crate) mod suite_k;
