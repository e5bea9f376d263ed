//! Sun-lobe sampling: a share of a medium vertex's continuation drawn from
//! the phase function's lobe about the direction toward the sun.
//!
//! Under a sun (a delta one, or a disk of a fraction of a degree), next-event estimation at a medium vertex gives
//! p(d, ω_sun)·T·E, where d is the direction the path arrived in. With a
//! strongly forward phase function (a cloud's g ≈ 0.8) p spans three orders of
//! magnitude, and the rare paths that travel toward the sun gather most of
//! the light: the sunlit part of a cloud's image is mostly that variance
//! (measured: 97 % of the Cycles harness cloud's, for 19 % of its mean). Here
//! a vertex draws its next direction from the one-sample mixture
//! (1 − α)·p(d_in, ·) + α·p(ω_sun, ·), weighted p(d_in, d) / mixture, and every
//! MIS weight that counts on the continuation's density (light samples of
//! the environment and of a sun's disk, and escaped rays) uses the
//! mixture's: unbiased, as path guiding's mixtures are.
//!
//! Only the first [`SUN_LOBE_DEPTH`] medium scatterings of a path mix: in a
//! direction far from the sun's lobe the weight is 1/(1 − α), and along a
//! walk of hundreds of events those factors would compound into fireflies
//! (α = 0.2 at every event: 10× the error on the harness cloud).

use crate::light::Light;
use crate::math::color::Rgb;
use crate::math::{Vec2, Vec3};
use crate::medium::PhaseFunction;
use crate::sampling::Sampler;

/// Medium scatterings of a path (counted from 1) that draw from the mixture.
pub const SUN_LOBE_DEPTH: u32 = 6;

/// The mean cosine below which a phase function keeps plain sampling: its
/// light samples do not vary enough for the lobe to pay (g = 0.3 measured
/// neutral, g = 0.8 1.4× the efficiency).
pub const SUN_LOBE_MIN_G: f32 = 0.5;

/// The default share α of the sun's lobe in the mixture.
pub const DEFAULT_SHARE: f32 = 0.1;

/// The largest share a scene may ask for.
pub const MAX_SHARE: f32 = 0.5;

/// Where a path's medium vertices aim the lobe, and its share.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLobe {
    /// Unit direction toward the sun.
    pub to_sun: Vec3,
    /// The lobe's share α of the mixture, in (0, [`MAX_SHARE`]].
    pub share: f32,
}

impl SunLobe {
    /// The lobe toward the brightest sun among `lights` with share `share`;
    /// `None` without a sun or with a share of 0.
    pub fn choose(share: f32, lights: &[Light]) -> Option<SunLobe> {
        if share <= 0.0 {
            return None;
        }
        let mut best: Option<(f32, Vec3)> = None;
        for light in lights {
            if let Light::Sun {
                to_sun, irradiance, ..
            } = light
            {
                let power = irradiance.luminance();
                if power > best.map_or(0.0, |b| b.0) {
                    best = Some((power, *to_sun));
                }
            }
        }
        best.map(|(_, to_sun)| SunLobe { to_sun, share })
    }

    /// Whether the `depth`-th medium scattering of a path (from 1) with this
    /// phase function draws from the mixture.
    #[inline]
    pub fn applies(&self, phase: &PhaseFunction, depth: u32) -> bool {
        depth <= SUN_LOBE_DEPTH && phase.mean_cosine() >= SUN_LOBE_MIN_G
    }

    /// The mixture's density at `d`, given the phase function's own `phase_pdf` there.
    #[inline]
    pub fn mixture_pdf(&self, phase: &PhaseFunction, d: Vec3, phase_pdf: f32) -> f32 {
        (1.0 - self.share) * phase_pdf + self.share * phase.pdf(self.to_sun, d)
    }

    /// A continuation from the mixture for a path arriving along `dir_in`:
    /// direction, weight p(d_in, d) / mixture and the mixture's density.
    /// `None` ends the path.
    #[inline]
    pub fn sample(
        &self,
        phase: &PhaseFunction,
        dir_in: Vec3,
        sampler: &mut Sampler,
    ) -> Option<(Vec3, Rgb, f32)> {
        let pick = sampler.next_1d();
        self.sample_from(phase, dir_in, pick, sampler.next_2d())
    }

    /// [`Self::sample`] from its random numbers: `pick` chooses the lobe, `u` the direction in it.
    fn sample_from(
        &self,
        phase: &PhaseFunction,
        dir_in: Vec3,
        pick: f32,
        u: Vec2,
    ) -> Option<(Vec3, Rgb, f32)> {
        let toward = match pick < self.share {
            true => self.to_sun,
            false => dir_in,
        };
        let dir = phase.sample(toward, u)?.direction;
        let f = phase.eval(dir_in, dir);
        let pdf = self.mixture_pdf(phase, dir, phase.pdf(dir_in, dir));
        (pdf > 0.0 && pdf.is_finite()).then(|| (dir, Rgb::splat(f / pdf), pdf))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sun(to_sun: Vec3, irradiance: f32, cos_max: f32) -> Light {
        Light::Sun {
            to_sun,
            irradiance: Rgb::splat(irradiance),
            cos_max,
        }
    }

    #[test]
    fn the_lobe_aims_at_the_brightest_sun() {
        let lights = [
            sun(Vec3::Y, 2.0, 1.0),
            sun(Vec3::X, 5.0, 1.0),
            sun(Vec3::Z, 1.0, 0.99999),
        ];
        let lobe = SunLobe::choose(0.1, &lights).unwrap();
        assert_eq!(lobe.to_sun, Vec3::X);
        assert_eq!(SunLobe::choose(0.1, &lights[2..]).unwrap().to_sun, Vec3::Z);
        assert_eq!(SunLobe::choose(0.0, &lights), None);
        assert_eq!(SunLobe::choose(0.1, &[]), None);
        // A dark sun aims nothing; of two equal suns the first is kept.
        assert_eq!(SunLobe::choose(0.1, &[sun(Vec3::Y, 0.0, 1.0)]), None);
        let equal = [sun(Vec3::Y, 4.0, 1.0), sun(Vec3::X, 4.0, 1.0)];
        assert_eq!(SunLobe::choose(0.1, &equal).unwrap().to_sun, Vec3::Y);
    }

    #[test]
    fn only_the_first_scatterings_of_forward_media_mix() {
        let lobe = SunLobe {
            to_sun: Vec3::Y,
            share: 0.1,
        };
        let cloud = PhaseFunction::HenyeyGreenstein { g: 0.8 };
        assert!(lobe.applies(&cloud, 1));
        assert!(lobe.applies(&cloud, SUN_LOBE_DEPTH));
        assert!(!lobe.applies(&cloud, SUN_LOBE_DEPTH + 1));
        assert!(!lobe.applies(&PhaseFunction::HenyeyGreenstein { g: 0.3 }, 1));
        assert!(!lobe.applies(&PhaseFunction::Isotropic, 1));
    }

    /// The mixture's directions follow `mixture_pdf` (chi-square through the
    /// suite's harness), and each weight times that density is the phase function.
    #[test]
    fn mixture_samples_follow_their_density_and_weigh_the_phase_function() {
        let phase = PhaseFunction::HenyeyGreenstein { g: 0.8 };
        let dir_in = Vec3::new(0.0, 0.6, -0.8);
        for (to_sun, share) in [(Vec3::new(0.6, 0.0, 0.8), 0.25), (Vec3::Z, 0.1)] {
            let lobe = SunLobe { to_sun, share };
            let mut picks = Sampler::from_seed(3);
            let result = crate::sampling::chi2::SphereChi2::new(200_000, 11).run(
                |u| {
                    let (d, w, pdf) = lobe.sample_from(&phase, dir_in, picks.next_1d(), u)?;
                    let f = phase.eval(dir_in, d);
                    assert!((w[0] * pdf - f).abs() <= 1e-4 * f, "{w:?} {pdf} {f}");
                    Some(d)
                },
                |d| lobe.mixture_pdf(&phase, d, phase.pdf(dir_in, d)),
            );
            assert!(result.passes(0.01, 4), "toward {to_sun}: {result}");
        }
    }
}
