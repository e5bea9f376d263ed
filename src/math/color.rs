//! The `Rgb` radiance/throughput type, luminance and the sRGB transfer curve.

use std::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Sub};

/// Linear RGB triple (radiance, throughput or coefficients), f32 per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
}

impl Rgb {
    /// All channels zero.
    pub const BLACK: Rgb = Rgb::splat(0.0);
    /// All channels one.
    pub const WHITE: Rgb = Rgb::splat(1.0);

    /// A colour from three channels.
    pub const fn new(r: f32, g: f32, b: f32) -> Rgb {
        Rgb { r, g, b }
    }

    /// The same value in every channel.
    pub const fn splat(v: f32) -> Rgb {
        Rgb { r: v, g: v, b: v }
    }

    /// A colour from an array.
    pub const fn from_array(a: [f32; 3]) -> Rgb {
        Rgb::new(a[0], a[1], a[2])
    }

    /// The channels as an array.
    pub fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }

    /// Rec. 709 luminance.
    pub fn luminance(self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }

    /// Largest channel.
    pub fn max_channel(self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    /// The lesser of `self` and `other` in each channel.
    pub fn min_per_channel(self, other: Rgb) -> Rgb {
        Rgb::new(
            self.r.min(other.r),
            self.g.min(other.g),
            self.b.min(other.b),
        )
    }

    /// Smallest channel.
    pub fn min_channel(self) -> f32 {
        self.r.min(self.g).min(self.b)
    }

    /// Mean of the channels.
    pub fn average(self) -> f32 {
        (self.r + self.g + self.b) / 3.0
    }

    /// True when every channel is exactly zero.
    pub fn is_black(self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }

    /// True when every channel is finite.
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    /// Applies `f` to each channel.
    pub fn map(self, f: impl Fn(f32) -> f32) -> Rgb {
        Rgb::new(f(self.r), f(self.g), f(self.b))
    }

    /// Per-channel `exp(-self)`, the transmittance of an optical depth.
    pub fn exp_neg(self) -> Rgb {
        // Grey media are the common case: one exp instead of three.
        if self.r == self.g && self.g == self.b {
            return Rgb::splat((-self.r).exp());
        }
        self.map(|v| (-v).exp())
    }

    /// Optical depth of coefficients `self` over `length`, with 0·∞ taken as 0 (a clear channel stays clear).
    pub fn depth_over(self, length: f32) -> Rgb {
        self.map(|sigma| if sigma == 0.0 { 0.0 } else { sigma * length })
    }

    /// Per-channel division that yields 0 where the divisor is 0.
    pub fn safe_div(self, d: Rgb) -> Rgb {
        let f = |a: f32, b: f32| if b != 0.0 { a / b } else { 0.0 };
        Rgb::new(f(self.r, d.r), f(self.g, d.g), f(self.b, d.b))
    }
}

impl Index<usize> for Rgb {
    type Output = f32;
    fn index(&self, i: usize) -> &f32 {
        match i {
            0 => &self.r,
            1 => &self.g,
            _ => &self.b,
        }
    }
}

macro_rules! componentwise {
    ($trait:ident, $fn:ident, $op:tt, $assign_trait:ident, $assign_fn:ident) => {
        impl $trait for Rgb {
            type Output = Rgb;
            #[inline]
            fn $fn(self, o: Rgb) -> Rgb {
                Rgb::new(self.r $op o.r, self.g $op o.g, self.b $op o.b)
            }
        }
        impl $trait<f32> for Rgb {
            type Output = Rgb;
            #[inline]
            fn $fn(self, s: f32) -> Rgb {
                Rgb::new(self.r $op s, self.g $op s, self.b $op s)
            }
        }
        impl $assign_trait for Rgb {
            #[inline]
            fn $assign_fn(&mut self, o: Rgb) {
                *self = *self $op o;
            }
        }
        impl $assign_trait<f32> for Rgb {
            #[inline]
            fn $assign_fn(&mut self, s: f32) {
                *self = *self $op s;
            }
        }
    };
}

componentwise!(Add, add, +, AddAssign, add_assign);
componentwise!(Mul, mul, *, MulAssign, mul_assign);
componentwise!(Div, div, /, DivAssign, div_assign);

impl Sub for Rgb {
    type Output = Rgb;
    #[inline]
    fn sub(self, o: Rgb) -> Rgb {
        Rgb::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    #[inline]
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}

/// The sRGB opto-electronic transfer function for one linear value in [0, 1].
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse sRGB transfer function: an sRGB-encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grey shortcut of `exp_neg` takes only equal channels: each
    /// channel is its own exponential, grey or not (two equal, one apart too).
    #[test]
    fn exp_neg_is_per_channel_grey_or_not() {
        for depth in [
            Rgb::splat(0.7),
            Rgb::new(0.5, 0.5, 2.0),
            Rgb::new(2.0, 0.5, 0.5),
            Rgb::new(0.1, 0.2, 0.3),
        ] {
            let t = depth.exp_neg();
            for (got, d) in [(t.r, depth.r), (t.g, depth.g), (t.b, depth.b)] {
                assert_eq!(got, (-d).exp(), "{depth:?}");
            }
        }
    }

    #[test]
    fn arithmetic_and_helpers() {
        let a = Rgb::new(1.0, 2.0, 4.0);
        assert_eq!(a * 2.0, Rgb::new(2.0, 4.0, 8.0));
        assert_eq!(a / a, Rgb::WHITE);
        assert_eq!(a.max_channel(), 4.0);
        assert_eq!(
            Rgb::new(1.0, 0.0, 2.0).safe_div(Rgb::new(2.0, 0.0, 4.0)).g,
            0.0
        );
        assert!((Rgb::WHITE.luminance() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn srgb_endpoints() {
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        assert!((linear_to_srgb(0.18) - 0.4614).abs() < 1e-3);
    }

    #[test]
    fn srgb_decode_inverts_the_encode() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // 8-bit 128 is 21.6% linear, not 50%; 10/255 is on the linear segment.
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_861).abs() < 1e-5);
        assert!((srgb_to_linear(10.0 / 255.0) - 10.0 / 255.0 / 12.92).abs() < 1e-7);
        for i in 0..=255 {
            let v = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(v)) - v).abs() < 1e-5, "{i}");
        }
    }
}
