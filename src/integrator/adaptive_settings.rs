//! What a render asks of adaptive sampling (`--adaptive`, `--noise`): the
//! settings the scene and the command line fill in, beside the integrator's
//! other settings; the sampling itself is the render driver's
//! (`render::adaptive`).

/// How a render spreads its samples over the pixels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AdaptiveSettings {
    /// Spread the samples by the pilot's error estimates (false: the same
    /// count in every pixel).
    pub adaptive: bool,
    /// Stop once the estimated relative error of the image reaches this.
    pub noise: Option<f32>,
    /// Neither was asked for: take a pilot and spread the samples only when
    /// it predicts enough less error (`render::adaptive::AUTO_GAIN`), else
    /// render exactly the uniform image.
    pub auto: bool,
}

impl AdaptiveSettings {
    /// True when the render takes a pilot pass (adaptive, or a noise target).
    pub fn piloted(&self) -> bool {
        self.adaptive || self.noise.is_some()
    }
}

/// Noise targets are below this relative error.
pub const MAX_NOISE: f32 = 1.0;

/// The fewest spp a piloted render may have (twice the smallest pilot).
pub const MIN_SPP: u32 = 8;
