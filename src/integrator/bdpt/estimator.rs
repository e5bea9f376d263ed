//! The bidirectional integrator as the driver's [`Estimator`]: the film adds
//! its light-tracing splats like every other integrator's.

use super::{sample_with_streams, BdptArena};
use crate::film::Splat;
use crate::integrator::estimator::Estimator;
use crate::integrator::Scene;
use crate::math::color::Rgb;
use crate::sampling::PixelStreams;

/// Bidirectional path tracing (`[integrator] type = "bdpt"`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Bdpt;

impl Estimator for Bdpt {
    type Arena = BdptArena;

    fn arena(&self) -> BdptArena {
        BdptArena::new()
    }

    fn splats(&self) -> bool {
        true
    }

    #[inline]
    fn sample(
        &self,
        scene: &Scene,
        (x, y): (u32, u32),
        streams: &PixelStreams,
        s: u32,
        arena: &mut BdptArena,
        splats: &mut Vec<Splat>,
    ) -> Rgb {
        sample_with_streams(scene, x, y, streams, s, arena, splats)
    }
}
