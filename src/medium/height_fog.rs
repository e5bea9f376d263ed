//! Exponential height fog: σt(h) = σt0·exp(-(h - h0)/H) along a world up axis.
//!
//! ```toml
//! [[medium]]
//! type = "height_fog"
//! visibility = 800.0          # metres at height h0 (or sigma_t = [..] / sigma_a, sigma_s)
//! albedo = [0.95, 0.95, 0.95]
//! height = 0.0                # h0
//! scale_height = 25.0         # H
//! up = [0.0, 1.0, 0.0]
//! phase = { type = "hg", g = 0.7 }
//! ```
//!
//! The optical depth along any ray has a closed form, and the majorant is the
//! density itself (an exponential in t, see `MajorantSegment`, with 0.1%
//! headroom against rounding), so grey fog is tracked with almost no null
//! collisions. To stay inside floating-point range the
//! density exponent x = -(h - h0)/H is limited: above x = -`MAX_EXPONENT_UP`
//! (thousands of times thinner than f32 can resolve against σt0) the fog is
//! empty, and below x = `MAX_EXPONENT_DOWN` it stays constant. Both the
//! coefficients and the closed forms use this same truncated density, so every
//! estimator agrees with the optical depth exactly.

use super::{MajorantSegment, MediumProperties, PhaseFunction};
use crate::math::color::Rgb;
use crate::math::{Ray, Vec3};

/// Above this many scale heights over h0 the fog is treated as empty (e^-40 ≈ 4e-18).
pub const MAX_EXPONENT_UP: f64 = 40.0;
/// Below this many scale heights under h0 the density stops growing (e^30 ≈ 1e13).
pub const MAX_EXPONENT_DOWN: f64 = 30.0;

/// Relative headroom of the majorant over the density.
///
/// The tracker evaluates the majorant in f32 from the segment start while
/// `properties` evaluates the density at the f32 point: the two differ by
/// ~1e-5 relatively, and a majorant below σt would make spectral-tracking
/// weights slightly negative. 0.1% headroom costs 0.1% null collisions.
pub const MAJORANT_SLACK: f32 = 1.001;

/// Exponential height fog filling all space.
#[derive(Clone, Debug)]
pub struct HeightFog {
    /// Absorption coefficient at height h0.
    pub sigma_a: Rgb,
    /// Scattering coefficient at height h0.
    pub sigma_s: Rgb,
    /// Emitted radiance Le (source term σa·Le, so it follows the density).
    pub emission: Rgb,
    /// Phase function.
    pub phase: PhaseFunction,
    /// Unit up axis.
    pub up: Vec3,
    /// Reference height h0 (along `up`).
    pub height: f32,
    /// Scale height H > 0.
    pub scale_height: f32,
}

/// Up to three majorant pieces: constant (below), exponential (slab), nothing above.
#[derive(Clone, Copy, Debug)]
pub struct FogSegments {
    segments: [MajorantSegment; 2],
    next: u8,
    count: u8,
}

impl Iterator for FogSegments {
    type Item = MajorantSegment;
    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        (self.next < self.count).then(|| {
            self.next += 1;
            self.segments[self.next as usize - 1]
        })
    }
}

impl HeightFog {
    /// Extinction σa + σs at height h0.
    pub fn sigma_t(&self) -> Rgb {
        self.sigma_a + self.sigma_s
    }

    /// The density exponent x = -(h - h0)/H at world point `p`, in f64.
    #[inline]
    fn exponent(&self, p: Vec3) -> f64 {
        -((p.dot(self.up) - self.height) as f64) / self.scale_height as f64
    }

    /// Relative density e^x with the truncation described in the module doc.
    #[inline]
    fn density(x: f64) -> f64 {
        if x < -MAX_EXPONENT_UP {
            0.0
        } else {
            x.min(MAX_EXPONENT_DOWN).exp()
        }
    }

    /// Coefficients at `p`.
    #[inline]
    pub fn properties(&self, p: Vec3) -> MediumProperties {
        let k = Self::density(self.exponent(p)) as f32;
        MediumProperties {
            sigma_a: self.sigma_a * k,
            sigma_s: self.sigma_s * k,
            emission: self.emission,
            phase: self.phase,
        }
    }

    /// The exponent along `ray` as x(t) = x0 + slope·t.
    #[inline]
    fn line(&self, ray: &Ray) -> (f64, f64) {
        let x0 = self.exponent(ray.origin);
        let slope = -(ray.direction.dot(self.up) as f64) / self.scale_height as f64;
        (x0, slope)
    }

    /// Sub-intervals of `[t0, t1]` where x(t) lies in the exponential slab and below it.
    ///
    /// Returns ((slab start, slab end), (below start, below end)); empty intervals have start ≥ end.
    fn pieces(x0: f64, slope: f64, t0: f64, t1: f64) -> ((f64, f64), (f64, f64)) {
        if slope == 0.0 {
            // Horizontal: one height only.
            return if x0 < -MAX_EXPONENT_UP {
                ((t0, t0), (t0, t0))
            } else if x0 <= MAX_EXPONENT_DOWN {
                ((t0, t1), (t0, t0))
            } else {
                ((t0, t0), (t0, t1))
            };
        }
        // Parameters where x crosses the slab's two boundaries.
        let t_up = (-MAX_EXPONENT_UP - x0) / slope;
        let t_down = (MAX_EXPONENT_DOWN - x0) / slope;
        let clip = |a: f64, b: f64| (a.max(t0), b.min(t1));
        if slope > 0.0 {
            // Going down: x grows from top, through the slab, into the constant part.
            (clip(t_up, t_down), clip(t_down, f64::INFINITY))
        } else {
            // Going up: constant part first, then the slab.
            (clip(t_down, t_up), clip(f64::NEG_INFINITY, t_down))
        }
    }

    /// Relative optical depth ∫ density dt over `[t0, t1]` (multiply by σt0), in f64.
    pub fn relative_depth(&self, ray: &Ray, t0: f32, t1: f32) -> f64 {
        if t1 <= t0 {
            return 0.0;
        }
        let (x0, slope) = self.line(ray);
        let ((a, b), (c, d)) = Self::pieces(x0, slope, t0 as f64, t1 as f64);
        let mut depth = 0.0;
        if c < d {
            depth += MAX_EXPONENT_DOWN.exp() * (d - c);
        }
        if a < b {
            let xa = x0 + slope * a;
            if slope == 0.0 {
                depth += xa.exp() * (b - a);
            } else if b.is_infinite() {
                // Only rays going up reach t = ∞ inside the slab, and x → -∞ there.
                depth += xa.exp() / -slope;
            } else {
                // ∫ e^{xa + s(t-a)} dt = e^{xa}·expm1(s(b-a))/s: exact for tiny slopes too.
                let span = slope * (b - a);
                depth += xa.exp() * (b - a) * exp_m1_ratio(span);
            }
        }
        depth
    }

    /// Optical depth ∫σt over `[t0, t1]` of `ray`, per channel (∞ where it overflows).
    pub fn optical_depth(&self, ray: &Ray, t0: f32, t1: f32) -> Rgb {
        let depth = self.relative_depth(ray, t0, t1);
        // A zero channel stays zero even for an infinite depth (0·∞ would be NaN).
        self.sigma_t().map(|s| {
            if s == 0.0 {
                0.0
            } else {
                (s as f64 * depth) as f32
            }
        })
    }

    /// Majorant segments over `[0, t_max)`: the density's max channel, exponential in t.
    pub fn majorants(&self, ray: &Ray, t_max: f32) -> FogSegments {
        let mut out = FogSegments {
            segments: [MajorantSegment {
                t0: 0.0,
                t1: 0.0,
                sigma_maj: 0.0,
                decay: 0.0,
                sigma_control: Rgb::BLACK,
            }; 2],
            next: 0,
            count: 0,
        };
        let sigma_max = self.sigma_t().max_channel() * MAJORANT_SLACK;
        if sigma_max <= 0.0 || t_max <= 0.0 {
            return out;
        }
        let (x0, slope) = self.line(ray);
        let ((a, b), (c, d)) = Self::pieces(x0, slope, 0.0, t_max as f64);
        let below = (c < d).then(|| MajorantSegment {
            t0: c as f32,
            t1: d as f32,
            sigma_maj: sigma_max * MAX_EXPONENT_DOWN.exp() as f32,
            decay: 0.0,
            sigma_control: self.sigma_t() * MAX_EXPONENT_DOWN.exp() as f32,
        });
        let slab = (a < b).then(|| {
            let xa = x0 + slope * a;
            MajorantSegment {
                t0: a as f32,
                t1: b as f32,
                sigma_maj: sigma_max * xa.exp() as f32,
                decay: (-slope) as f32,
                // No lower bound is needed: varying segments use plain ratio tracking.
                sigma_control: Rgb::BLACK,
            }
        });
        // Increasing t: going up the constant part comes first.
        let ordered = if slope < 0.0 {
            [below, slab]
        } else {
            [slab, below]
        };
        for seg in ordered.into_iter().flatten() {
            if seg.t0 < seg.t1 {
                out.segments[out.count as usize] = seg;
                out.count += 1;
            }
        }
        out
    }
}

/// expm1(x)/x, equal to 1 at x = 0 and accurate near it.
#[inline]
fn exp_m1_ratio(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        1.0 + 0.5 * x
    } else {
        x.exp_m1() / x
    }
}

/// σt0 that gives meteorological visual range `visibility` (Koschmieder: V = ln 50 / σt).
pub fn sigma_t_from_visibility(visibility: f32) -> f32 {
    50f32.ln() / visibility
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fog() -> HeightFog {
        HeightFog {
            sigma_a: Rgb::splat(0.01),
            sigma_s: Rgb::new(0.02, 0.05, 0.1),
            emission: Rgb::BLACK,
            phase: PhaseFunction::Isotropic,
            up: Vec3::Y,
            height: 2.0,
            scale_height: 10.0,
        }
    }

    #[test]
    fn extreme_rays_stay_finite_and_ordered() {
        let f = fog();
        for (o, d) in [
            (Vec3::new(0.0, 1e6, 0.0), Vec3::NEG_Y),
            (Vec3::new(0.0, -1e6, 0.0), Vec3::Y),
            (
                Vec3::new(0.0, 5.0, 0.0),
                Vec3::new(1.0, 1e-9, 0.0).normalize(),
            ),
            (Vec3::new(0.0, -1e4, 0.0), Vec3::X),
            (Vec3::new(0.0, 1e4, 0.0), Vec3::X),
        ] {
            let ray = Ray::new(o, d);
            let segs: Vec<_> = f.majorants(&ray, f32::INFINITY).collect();
            let mut last = 0.0;
            for s in &segs {
                assert!(
                    s.t0 >= last && s.t0 < s.t1 && s.sigma_maj.is_finite(),
                    "{s:?}"
                );
                last = s.t1;
            }
            let tau = f.optical_depth(&ray, 0.0, 1e3);
            assert!(!tau.r.is_nan() && tau.r >= 0.0, "{tau:?}");
        }
        // Far above, horizontal: empty; far below, horizontal: opaque.
        let high = Ray::new(Vec3::new(0.0, 1e4, 0.0), Vec3::X);
        assert_eq!(f.majorants(&high, f32::INFINITY).count(), 0);
        let low = Ray::new(Vec3::new(0.0, -1e4, 0.0), Vec3::X);
        assert!(f.optical_depth(&low, 0.0, f32::INFINITY).r.is_infinite());
    }

    #[test]
    fn coefficients_and_closed_form_share_the_truncation() {
        // σ = 1 at h0 = 0 with H = 1: the exponent at height y is exactly -y, and
        // both sides compute e^x in f64 and round it to f32 once, so a horizontal
        // ray of length 1 has the point's coefficient as its depth, to the bit.
        let f = HeightFog {
            sigma_a: Rgb::splat(1.0),
            sigma_s: Rgb::BLACK,
            height: 0.0,
            scale_height: 1.0,
            ..fog()
        };
        for y in [-31.0, -30.0, -29.5, 0.0, 39.5, 40.0, 41.0] {
            let p = Vec3::new(3.0, y, -2.0);
            let coefficient = f.properties(p).sigma_a.r;
            let depth = f.relative_depth(&Ray::new(p, Vec3::X), 0.0, 1.0) as f32;
            assert_eq!(coefficient, depth, "height {y}");
            // Empty strictly above the top, e^-40 at it, e^30 from the bottom down.
            let expected = if y > 40.0 {
                0.0
            } else {
                (-y.max(-30.0) as f64).exp() as f32
            };
            assert_eq!(coefficient, expected, "height {y}");
        }
    }

    #[test]
    fn majorants_bound_the_density_within_their_headroom() {
        // Rays through both truncation heights (40 scale heights above h0, 30 below)
        // and horizontal ones in each part. Inside every segment the majorant is
        // the max-channel density times MAJORANT_SLACK, up to the f32 rounding of
        // the point and of exp along the segment (~1e-5, see MAJORANT_SLACK).
        let f = HeightFog {
            height: 0.0,
            scale_height: 1.0,
            ..fog()
        };
        let slope = Vec3::new(0.6, 0.8, 0.0);
        for (o, d, t_max) in [
            (Vec3::new(0.0, -35.0, 0.0), Vec3::Y, 80.0),
            (Vec3::new(0.0, 45.0, 1.0), -slope, 110.0),
            (Vec3::new(0.0, -31.0, 0.0), slope, f32::INFINITY),
            (Vec3::new(0.0, -32.0, 0.0), Vec3::X, 5.0),
            (Vec3::new(0.0, 10.0, 0.0), Vec3::X, 5.0),
        ] {
            let ray = Ray::new(o, d);
            let segments: Vec<_> = f.majorants(&ray, t_max).collect();
            assert!(!segments.is_empty(), "{ray:?}");
            for seg in segments {
                let end = seg.t1.min(seg.t0 + 100.0);
                for i in 0..16 {
                    let t = seg.t0 + (i as f32 + 0.5) / 16.0 * (end - seg.t0);
                    let density = f.properties(ray.at(t));
                    let local = density.sigma_a + density.sigma_s;
                    let majorant = seg.majorant_at(t);
                    let max = local.max_channel();
                    assert!(
                        max <= majorant && majorant <= MAJORANT_SLACK * max * (1.0 + 1e-4),
                        "{ray:?} at t = {t}: majorant {majorant} for σt {local:?}"
                    );
                    // Below the bottom (y < -30) the control is the constant density;
                    // elsewhere none is given (black). Both up to the rounding of
                    // σa·k + σs·k against (σa + σs)·k.
                    let below = ray.at(t).y < -30.0;
                    for c in 0..3 {
                        let (control, s) = (seg.sigma_control[c], local[c]);
                        let want = if below { s } else { 0.0 };
                        assert!(
                            (control - want).abs() <= 1e-6 * s,
                            "{ray:?} at t = {t}: control {:?} for σt {local:?}",
                            seg.sigma_control
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn pieces_spanning_under_1e12_scale_heights_keep_their_depth() {
        // Where the exponent changes by less than 1e-12 across a piece, the depth is
        // e^x·length to far below f32 precision (the next term is x-span/2 relative).
        let f = HeightFog {
            height: 0.0,
            scale_height: 1.0,
            ..fog()
        };
        let (y, length) = (-3.0, 5.0);
        let level = (3.0f64).exp();
        let nearly_level = Ray::new(
            Vec3::new(0.0, y, 0.0),
            Vec3::new(1.0, 1e-13, 0.0).normalize(),
        );
        let got = f.relative_depth(&nearly_level, 0.0, length);
        assert_eq!(got as f32, (level * length as f64) as f32);
        let short = Ray::new(Vec3::new(0.0, y, 0.0), Vec3::new(0.6, -0.8, 0.0));
        let got = f.relative_depth(&short, 0.0, 1e-12);
        assert_eq!(got as f32, (level * 1e-12f32 as f64) as f32);
    }

    #[test]
    fn visibility_gives_two_percent_contrast() {
        let s = sigma_t_from_visibility(1000.0);
        assert!(((-s * 1000.0).exp() - 0.02).abs() < 1e-6);
    }
}
