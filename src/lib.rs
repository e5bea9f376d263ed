//! brume: a physically based renderer for participating media.
//!
//! Fog, smoke, clouds and airlight, lit and shadowed together with ordinary
//! surfaces by one unbiased Monte Carlo radiance estimator.

pub mod color;
pub mod math;
pub mod medium;
pub mod sampling;
