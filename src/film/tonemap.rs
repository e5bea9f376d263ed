//! Tone curves from linear radiance to display values in [0, 1] for the PNG
//! preview (the EXR is never tone mapped).
//!
//! - `Clip`: scale and clamp at 1, the identity below 1. Exact for images
//!   inside [0, 1], harsh on highlights.
//! - `Aces`: Narkowicz's (2015) rational fit of the ACES reference rendering
//!   and output transforms, per channel: a filmic toe and a shoulder that rolls
//!   highlights off smoothly to white instead of clipping them.

use crate::math::color::linear_to_srgb;

/// How the PNG preview maps linear radiance to display values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Tonemap {
    /// Filmic ACES-like curve (the default for previews).
    #[default]
    Aces,
    /// Hard clip at 1.
    Clip,
}

impl Tonemap {
    /// Parses `aces` or `clip`, the names used on the command line.
    pub fn from_name(name: &str) -> Option<Tonemap> {
        match name {
            "aces" => Some(Tonemap::Aces),
            "clip" => Some(Tonemap::Clip),
            _ => None,
        }
    }

    /// Display-linear value in [0, 1] of the linear value `v` (already exposed).
    pub fn apply(self, v: f32) -> f32 {
        match self {
            Tonemap::Clip => v.clamp(0.0, 1.0),
            Tonemap::Aces => aces_fit(v),
        }
    }

    /// The 8-bit sRGB code of linear value `v` after exposure scale `scale`.
    pub fn srgb8(self, v: f32, scale: f32) -> u8 {
        // NaN maps to 0 through the clamps and the saturating cast.
        (linear_to_srgb(self.apply(v * scale)) * 255.0 + 0.5) as u8
    }
}

/// Narkowicz's fit x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped to [0, 1].
fn aces_fit(x: f32) -> f32 {
    let x = x.max(0.0);
    let y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    y.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_is_the_identity_below_one_and_clamps_above() {
        assert_eq!(Tonemap::Clip.apply(0.25), 0.25);
        assert_eq!(Tonemap::Clip.apply(7.0), 1.0);
        assert_eq!(Tonemap::Clip.apply(-1.0), 0.0);
        assert_eq!(Tonemap::Clip.srgb8(0.18, 1.0), 118);
    }

    #[test]
    fn aces_rises_from_black_and_rolls_off_highlights() {
        let t = Tonemap::Aces;
        assert_eq!(t.apply(0.0), 0.0);
        assert_eq!(t.apply(f32::NAN.max(0.0)), 0.0);
        // Values of the published fit.
        assert!((t.apply(0.18) - 0.2669).abs() < 1e-3, "{}", t.apply(0.18));
        assert!((t.apply(1.0) - 0.8038).abs() < 1e-3, "{}", t.apply(1.0));
        // Highlights above 1 still differ (no clip) and reach white only far above.
        assert!(t.apply(2.0) > t.apply(1.0) && t.apply(2.0) < 1.0);
        assert!(t.apply(4.0) > t.apply(2.0));
        assert_eq!(t.apply(1e4), 1.0);
        let mut prev = 0.0;
        for i in 1..2000 {
            let y = t.apply(i as f32 * 0.01);
            assert!(y >= prev, "not monotonic at {}", i as f32 * 0.01);
            prev = y;
        }
        assert_eq!(t.srgb8(f32::NAN, 1.0), 0);
    }

    #[test]
    fn names_parse() {
        assert_eq!(Tonemap::from_name("aces"), Some(Tonemap::Aces));
        assert_eq!(Tonemap::from_name("clip"), Some(Tonemap::Clip));
        assert_eq!(Tonemap::from_name("reinhard"), None);
    }
}
