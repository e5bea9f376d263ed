//! brume: a physically based renderer for participating media.
//!
//! Fog, smoke, clouds and airlight, lit and shadowed together with ordinary
//! surfaces by one unbiased Monte Carlo radiance estimator.
//!
//! Modules are listed in dependency order: each uses only those above it.

pub mod math;
pub mod color;
pub mod sampling;
pub mod camera;
pub mod geometry;
pub mod material;
pub mod light;
pub mod volume;
pub mod integrator;
pub mod scene;
pub mod render;
pub mod image_io;
pub mod error;
