//! The names of the outputs beside the beauty (AOVs): what the film keeps a
//! layer for and what its EXR channels are called. How each is estimated
//! lives in `integrator::aov`.

/// An output beside the beauty.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// Coverage: 1 − transmittance of the camera ray to the background.
    Alpha,
    /// Camera-space depth of the first vertex.
    Depth,
    /// Shading normal at the first vertex.
    Normal,
    /// Albedo × throughput at the first vertex.
    Albedo,
    /// Transmittance of the camera ray to its first surface.
    Transmittance,
}

impl Aov {
    /// Every AOV, in the order the names are documented.
    pub const ALL: [Aov; 5] = [
        Aov::Alpha,
        Aov::Depth,
        Aov::Normal,
        Aov::Albedo,
        Aov::Transmittance,
    ];

    /// The AOV called `name` in scene files and on the command line.
    pub fn from_name(name: &str) -> Option<Aov> {
        Aov::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Its name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Alpha => "alpha",
            Aov::Depth => "depth",
            Aov::Normal => "normal",
            Aov::Albedo => "albedo",
            Aov::Transmittance => "transmittance",
        }
    }

    /// The value of a pixel where no sample has one: +∞ for the depth
    /// (nothing met), 0 for the others.
    pub fn empty_value(self) -> f32 {
        match self {
            Aov::Depth => f32::INFINITY,
            _ => 0.0,
        }
    }

    /// Its EXR channel names (OpenEXR layer naming).
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Aov::Alpha => &["A"],
            Aov::Depth => &["depth.Z"],
            Aov::Normal => &["normal.X", "normal.Y", "normal.Z"],
            Aov::Albedo => &["albedo.R", "albedo.G", "albedo.B"],
            Aov::Transmittance => &["transmittance.R", "transmittance.G", "transmittance.B"],
        }
    }
}
