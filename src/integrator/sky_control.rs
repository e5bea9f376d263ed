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
//! Booked ahead: where a segment aims at a diffuse surface through media
//! whose transmittance T has a closed form, the change the surface makes,
//! β·(ρ − 1)·U′ for a path that gets there, is booked before the flight by
//! its expectation T·β·(ρ − 1)·U′ (`integrator::book_surface_ahead`); a
//! path that gets there books only what tracking changed on the way. The
//! sky's deficit at the ground then no longer rides on whether a walk
//! reaches it: the airlight fog's variance falls to 0.73× for 3 % more time.
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
    /// The change at the surface the current segment aims at was booked
    /// ahead, by its expectation ([`SkyBook::ahead`]).
    ahead: bool,
}

impl SkyBook {
    /// A camera path under the constant radiance `sky`, which books U at its start (β₀ = 1).
    pub(crate) fn start(sky: Rgb) -> SkyBook {
        SkyBook {
            sky,
            booked: Rgb::WHITE,
            ahead: false,
        }
    }

    /// The radiance that books, ahead, the change a diffuse surface of albedo
    /// ρ makes to the throughput of a path that reaches it along the current
    /// segment, β·T·(ρ − 1) times U′ (β the throughput at the segment's start,
    /// T an unbiased estimate of the segment's transmittance). The surface's
    /// own booking is then skipped if the path gets there ([`SkyBook::arrived`],
    /// [`SkyBook::book`], [`SkyBook::end`]); [`SkyBook::missed`] where the
    /// segment ends before.
    #[inline]
    pub(crate) fn ahead(&mut self, throughput: Rgb, transmittance: Rgb, albedo: Rgb) -> Rgb {
        self.ahead = true;
        self.sky * throughput * transmittance * (albedo - Rgb::WHITE)
    }

    /// The path reached the surface booked ahead with `throughput`: the
    /// radiance that books the segment's own changes (tracking weights), not the surface's.
    #[inline]
    pub(crate) fn arrived(&mut self, throughput: Rgb) -> Rgb {
        match self.ahead {
            true => self.change(throughput),
            false => Rgb::BLACK,
        }
    }

    /// The segment booked ahead ended before its surface (a collision, an absorption).
    #[inline]
    pub(crate) fn missed(&mut self) {
        self.ahead = false;
    }

    /// The radiance that books the throughput's changes since the last booking.
    #[inline]
    pub(crate) fn book(&mut self, throughput: Rgb) -> Rgb {
        if self.ahead {
            // The surface's change was booked ahead by its expectation.
            self.ahead = false;
            self.booked = throughput;
            return Rgb::BLACK;
        }
        self.change(throughput)
    }

    /// The radiance of the throughput's change since the last booking, now booked.
    #[inline]
    fn change(&mut self, throughput: Rgb) -> Rgb {
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
        if self.ahead {
            // At the surface booked ahead (its arrival booked): its change, to β = 0 here, was.
            self.ahead = false;
            self.booked = Rgb::BLACK;
            return Rgb::BLACK;
        }
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

    /// Booked ahead with a certain arrival (T = 1) at a surface whose weight
    /// is ρ, a path books what it would have booked there; one that ends
    /// there books its end; one that misses books its next change in full.
    #[test]
    fn booking_ahead_with_a_certain_arrival_is_booking_on_arrival() {
        let sky = Rgb::new(0.5, 1.0, 2.0);
        let beta = Rgb::new(0.4, 0.8, 0.2);
        let rho = Rgb::new(0.3, 0.6, 0.9);
        let (mut plain, mut ahead) = (SkyBook::start(sky), SkyBook::start(sky));
        let start = sky + plain.book(beta);
        assert!(close(start, sky + ahead.book(beta)));
        let mut ends = ahead;
        let mut missed = ahead;
        let booked = start + ahead.ahead(beta, Rgb::WHITE, rho);
        let total = booked + ahead.arrived(beta) + ahead.book(beta * rho);
        assert!(close(total, start + plain.book(beta * rho)), "{total:?}");
        // A later change is booked as it comes.
        assert!(close(ahead.book(beta), plain.book(beta)));
        let ended =
            start + ends.ahead(beta, Rgb::WHITE, Rgb::BLACK) + ends.arrived(beta) + ends.end(beta);
        assert!(close(ended, Rgb::BLACK), "{ended:?}");
        missed.ahead(beta, Rgb::WHITE, rho);
        missed.missed();
        assert!(close(missed.book(beta * 0.5), sky * beta * -0.5));
    }
}
