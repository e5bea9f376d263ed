//! The environment as a control variate of the path tracer
//! (`integrator.sky_control`).
//!
//! Under a constant environment of radiance U, the radiance field is
//! L = U + L′: a uniform field U everywhere, plus the deviation L′ that the
//! scene's absorption, shadowing and other lights make. Along any one path
//! the sky light the path tracer gathers, U·β at the escape (β the
//! throughput there, 0 for a path that ends at a vertex), telescopes into U
//! (the camera's start, β₀ = 1) plus U·Δβ for every change of the
//! throughput on the way, minus U·β where the path ends without escaping.
//! Booking each change as it happens gives the same estimate for every
//! path; the control variate books Russian roulette's changes by their
//! expectation, which is nothing (a survivor's 1/q and a killed path's loss
//! cancel on average). So a path that roulette ends costs the sky nothing,
//! and the sky light of a long walk in a bright medium no longer rides on
//! whether the walk survives: on the airlight fog (an albedo-1 layer under a
//! sun and a sky) the image's variance falls 1.7× (BENCHMARKS.md, "The sky
//! as a control variate").
//!
//! The environment itself is then not light-sampled, and the estimate
//! stays unbiased for any material, medium and depth limit: every change
//! but roulette's is booked as it happened. The identity holds for any
//! constant U′ booked in place of U, an escape then adding what the
//! booking leaves out, β·(U − U′): where light samples would ask the sky
//! (a sky alone), the scene books the share of it that a deep medium of
//! its albedo returns (`scene::lights::sky_control`), closer to the light
//! the walks meet than U itself, and the sky's shadow rays are saved. Nor
//! need the environment be constant: under a gradient sky or a smooth map
//! the path books a constant U′ at most the environment's floor (its least
//! radiance), and an escape along ω adds β·(L(ω) − U′), never negative.
//!
//! A sample can be negative (a path roulette let through that then ends at
//! a vertex gives back sky light it was never booked): a dark pixel of few
//! samples can fall below 0.

use crate::math::color::Rgb;

/// The sky light one path has booked so far.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SkyBook {
    /// The constant radiance U′ booked.
    sky: Rgb,
    /// The throughput whose sky light U·β is booked.
    booked: Rgb,
}

impl SkyBook {
    /// A camera path under the constant radiance `sky`, which books U at its start (β₀ = 1).
    pub(crate) fn start(sky: Rgb) -> SkyBook {
        SkyBook {
            sky,
            booked: Rgb::WHITE,
        }
    }

    /// The radiance that books the throughput's changes since the last booking.
    #[inline]
    pub(crate) fn book(&mut self, throughput: Rgb) -> Rgb {
        let delta = self.sky * (throughput - self.booked);
        self.booked = throughput;
        delta
    }

    /// Russian roulette rescaled the throughput: its change is booked by its expectation, 0.
    #[inline]
    pub(crate) fn rescaled(&mut self, throughput: Rgb) {
        self.booked = throughput;
    }

    /// The radiance to add where the path ends at a vertex with `throughput`,
    /// not by escaping and not by roulette: the escape it will never make.
    #[inline]
    pub(crate) fn end(&mut self, throughput: Rgb) -> Rgb {
        self.book(throughput) - self.sky * throughput
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal within 10⁻⁶ in every channel.
    fn close(a: Rgb, b: Rgb) -> bool {
        (a - b).map(f32::abs).max_channel() < 1e-6
    }

    /// A path that escapes books U·β at its escape, one that ends at a
    /// vertex books 0, and roulette's rescaling books nothing.
    #[test]
    fn booking_telescopes_to_the_sky_light_at_the_escape() {
        let sky = Rgb::new(0.5, 1.0, 2.0);
        let beta = Rgb::new(0.4, 0.8, 0.2);
        let (mut book, mut total) = (SkyBook::start(sky), sky);
        total += book.book(Rgb::splat(0.8));
        total += book.book(beta);
        assert!(close(total, sky * beta), "{total:?}");
        let mut ends = book;
        let ended = total + ends.end(Rgb::splat(0.1));
        assert!(close(ended, Rgb::BLACK), "{ended:?}");
        book.rescaled(beta * 2.0);
        total += book.book(beta * 2.0);
        assert!(close(total, sky * beta), "{total:?}");
    }
}
