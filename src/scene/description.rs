//! The serde description of a scene file, exactly as written in TOML.
//!
//! Every struct rejects unknown keys; defaults are documented in README.md.
//! Tables written as `{ type = "name", ... }` are read as serde's externally
//! tagged enums (see `retag` in the parent module), which keeps the path of
//! a bad field (`light[0].intensity[1]`) in error messages.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use std::path::PathBuf;

/// An RGB triple written either as `[r, g, b]` or as one number for grey.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color(pub [f32; 3]);

impl<'de> Deserialize<'de> for Color {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Color, D::Error> {
        struct ColorVisitor;
        impl<'de> Visitor<'de> for ColorVisitor {
            type Value = Color;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of three numbers [r, g, b]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Color, E> {
                Ok(Color([v as f32; 3]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Color, E> {
                Ok(Color([v as f32; 3]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Color, E> {
                Ok(Color([v as f32; 3]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Color, A::Error> {
                let mut c = [0.0f32; 3];
                for (i, slot) in c.iter_mut().enumerate() {
                    *slot = seq
                        .next_element::<f32>()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(Color(c))
            }
        }
        d.deserialize_any(ColorVisitor)
    }
}

/// A colour parameter written as a colour (number or `[r, g, b]`) or as a
/// texture table `{ type = "image", ... }` / `{ type = "checkerboard", ... }`.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorOrTexture {
    /// A constant colour.
    Color(Color),
    /// A texture.
    Texture(TextureDesc),
}

impl From<Color> for ColorOrTexture {
    fn from(c: Color) -> ColorOrTexture {
        ColorOrTexture::Color(c)
    }
}

impl ColorOrTexture {
    /// The file of an image texture.
    pub fn file(&self) -> Option<&std::path::Path> {
        match self {
            ColorOrTexture::Texture(t) => t.file.as_deref(),
            ColorOrTexture::Color(_) => None,
        }
    }
}

impl<'de> Deserialize<'de> for ColorOrTexture {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<ColorOrTexture, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = ColorOrTexture;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a number, an array [r, g, b] or a texture table like \
                     { type = \"image\", file = \"wood.png\" }",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ColorOrTexture, E> {
                Ok(ColorOrTexture::Color(Color([v as f32; 3])))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ColorOrTexture, E> {
                Ok(ColorOrTexture::Color(Color([v as f32; 3])))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ColorOrTexture, E> {
                Ok(ColorOrTexture::Color(Color([v as f32; 3])))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<ColorOrTexture, A::Error> {
                Color::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(ColorOrTexture::Color)
            }
            fn visit_map<A: de::MapAccess<'de>>(self, map: A) -> Result<ColorOrTexture, A::Error> {
                TextureDesc::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(ColorOrTexture::Texture)
            }
        }
        d.deserialize_any(V)
    }
}

/// A texture table; which keys apply depends on `type` (checked when the scene is built).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    /// `image` or `checkerboard`.
    #[serde(rename = "type")]
    pub kind: String,
    /// PNG or EXR file, relative to the scene file (image).
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// `repeat` (default), `mirror` or `clamp` (image).
    #[serde(default)]
    pub wrap: Option<String>,
    /// `bilinear` (default) or `nearest` (image).
    #[serde(default)]
    pub filter: Option<String>,
    /// `srgb` (PNG default) or `linear` (image).
    #[serde(default)]
    pub color_space: Option<String>,
    /// Factor on the texels (image; default 1).
    #[serde(default)]
    pub scale: Option<Color>,
    /// Colour of the square at the UV origin (checkerboard).
    #[serde(default)]
    pub a: Option<Color>,
    /// Colour of the other squares (checkerboard).
    #[serde(default)]
    pub b: Option<Color>,
    /// Factor on the texture coordinates: a number or `[su, sv]` (default 1).
    #[serde(default)]
    pub uv_scale: Option<UvScale>,
    /// Added to the scaled texture coordinates: `[du, dv]` (default 0).
    #[serde(default)]
    pub uv_offset: Option<[f32; 2]>,
}

/// `uv_scale`: one number for both axes or `[su, sv]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum UvScale {
    /// The same factor on u and v.
    Both(f32),
    /// Factors on u and v.
    Each([f32; 2]),
}

// By hand: an untagged enum's only message is "did not match any variant of UvScale".
impl<'de> Deserialize<'de> for UvScale {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<UvScale, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = UvScale;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of two numbers [su, sv]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<UvScale, E> {
                Ok(UvScale::Both(v as f32))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<UvScale, E> {
                Ok(UvScale::Both(v as f32))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<UvScale, E> {
                Ok(UvScale::Both(v as f32))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<UvScale, A::Error> {
                let mut s = [0.0f32; 2];
                for (i, slot) in s.iter_mut().enumerate() {
                    *slot = seq
                        .next_element::<f32>()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(3, &self));
                }
                Ok(UvScale::Each(s))
            }
        }
        d.deserialize_any(V)
    }
}

/// The whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// `[camera]`.
    pub camera: CameraDesc,
    /// `[integrator]`.
    #[serde(default)]
    pub integrator: IntegratorDesc,
    /// `[[light]]` entries.
    #[serde(default, rename = "light")]
    pub lights: Vec<LightDesc>,
    /// `[[shape]]` entries.
    #[serde(default, rename = "shape")]
    pub shapes: Vec<ShapeDesc>,
    /// `[[medium]]` entries (also accepted as `[[media]]`).
    #[serde(default, rename = "medium", alias = "media")]
    pub media: Vec<MediumDesc>,
    /// How the file spells the media key, `medium` or `media`, for messages.
    #[serde(skip, default = "default_media_key")]
    pub media_key: &'static str,
    /// `[animation]`: frame rate, frame offset, missing frames.
    #[serde(default)]
    pub animation: super::animation::AnimationDesc,
    /// `[film]`.
    #[serde(default)]
    pub film: FilmDesc,
    /// `[slab]`: the box `brume slab bake` records (see `scene::slab_keys`).
    #[serde(default)]
    pub slab: Option<SlabDesc>,
    /// Mitsuba's interface rule for the media, set by the importer only (no TOML key).
    #[serde(skip)]
    pub interfaces: Option<InterfaceDesc>,
}

/// Mitsuba's rule for the medium a ray is in, which an imported scene needs
/// where it differs from brume's containment: the medium is set by the last
/// surface crossed, to that shape's `interior` when the ray goes against its
/// normal, else to its `exterior`. The media are `media` (unbounded), never
/// added together.
#[derive(Clone, Debug, Default)]
pub struct InterfaceDesc {
    /// Each shape's `[interior, exterior]` as indices into `media` (`None`:
    /// vacuum), or `None` for a shape that changes no medium.
    pub shapes: Vec<Option<[Option<u32>; 2]>>,
    /// The medium the sensor is in.
    pub camera: Option<u32>,
}

/// `[slab]`: the box around the content to bake and the grid of lines recorded.
///
/// ```toml
/// [slab]
/// min = [-1, 0, -1]
/// max = [1, 2, 1]
/// spatial = 64   # nodes per position axis
/// angular = 16   # nodes per slope axis
/// ```
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlabDesc {
    /// Minimum corner of the box.
    pub min: [f32; 3],
    /// Maximum corner of the box.
    pub max: [f32; 3],
    /// Nodes per position axis on each slab's mid-plane.
    #[serde(default)]
    pub spatial: Option<u32>,
    /// Nodes per slope axis of each slab.
    #[serde(default)]
    pub angular: Option<u32>,
}

fn default_media_key() -> &'static str {
    "medium"
}

/// `[film]`: what the EXR holds beside the beauty.
///
/// ```toml
/// [film]
/// aovs = ["alpha", "depth", "normal", "albedo", "transmittance"]
/// ```
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilmDesc {
    /// AOV names, written as extra EXR layers.
    #[serde(default)]
    pub aovs: Vec<String>,
}

/// `[camera]`: a pinhole camera.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub position: [f32; 3],
    /// Point looked at.
    pub look_at: [f32; 3],
    /// Up hint.
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    #[serde(default = "default_fov")]
    pub fov: f32,
    /// Image size `[width, height]` in pixels.
    #[serde(default = "default_resolution")]
    pub resolution: [u32; 2],
    /// Shutter `[open, close]` in frames relative to the frame's time (motion blur).
    #[serde(default)]
    pub shutter: Option<[f32; 2]>,
    /// Image axis `fov` spans: "y"/"vertical" (default) or "x"/"horizontal".
    #[serde(default)]
    pub fov_axis: Option<String>,
    /// Thin-lens radius (0 = pinhole).
    #[serde(default)]
    pub aperture_radius: Option<f32>,
    /// Distance to the plane in focus (default: to `look_at`).
    #[serde(default)]
    pub focus_distance: Option<f32>,
    /// Rigid motion of the camera: `{ keyframes = [...] }` (translate and rotate only).
    #[serde(default)]
    pub transform: Option<TransformDesc>,
    /// How a pixel weighs the film around it: `{ type = "box" }` (default) or
    /// `{ type = "gaussian", stddev = 0.5 }`.
    #[serde(default)]
    pub pixel_filter: Option<PixelFilterDesc>,
}

/// `pixel_filter` of the camera.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PixelFilterDesc {
    /// `box` or `gaussian`.
    #[serde(rename = "type")]
    pub kind: String,
    /// Standard deviation of a Gaussian, in pixels (default 0.5; radius 4 × it).
    #[serde(default)]
    pub stddev: Option<f32>,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    40.0
}
fn default_resolution() -> [u32; 2] {
    [512, 512]
}

/// `[integrator]`: sampling settings.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegratorDesc {
    /// Estimator: path (the default), bdpt, mlt or sppm.
    #[serde(default = "default_integrator_type", rename = "type")]
    pub kind: String,
    /// Samples per pixel.
    #[serde(default = "default_spp")]
    pub spp: u32,
    /// Maximum number of scattering events (surface or medium) on a path.
    #[serde(default = "default_max_depth")]
    pub max_depth: u32,
    /// Maximum number of medium scattering events (1 = single scattering).
    #[serde(default)]
    pub max_scatter_depth: Option<u32>,
    /// Depth from which Russian roulette may end paths.
    #[serde(default = "default_rr_depth")]
    pub rr_depth: u32,
    /// Scene seed of the random streams.
    #[serde(default)]
    pub seed: u64,
    /// Shadow-ray transmittance estimator: auto, ratio, residual_ratio or delta.
    #[serde(default = "default_transmittance")]
    pub transmittance: String,
    /// Equiangular sampling toward point and spot lights in media (MIS with free flight).
    #[serde(default = "default_true")]
    pub equiangular: bool,
    /// Sample lights from a point drawn over each medium segment, not from the
    /// free flight's collision (default: on unless the camera is inside a medium
    /// or a light is at infinity).
    #[serde(default)]
    pub forced_scattering: Option<bool>,
    /// Share of the first medium scatterings' continuations drawn from the
    /// phase function's lobe toward the sun (default 0.1; 0 turns it off).
    #[serde(default)]
    pub sun_lobe: Option<f32>,
    /// Probability that the path tracer's light samples ask a constant or sky
    /// environment beside other lights (default: from the lights' powers).
    #[serde(default)]
    pub environment_share: Option<f32>,
    /// The environment as a control variate of the path tracer (default: on
    /// with a smooth environment and a medium; module `sky_control`).
    #[serde(default)]
    pub sky_control: Option<bool>,
    /// Random numbers of pixel samples: sobol (scrambled Sobol' points) or independent.
    #[serde(default = "default_sampler")]
    pub sampler: String,
    /// sppm: light paths traced per pass.
    #[serde(default)]
    pub photons: Option<u32>,
    /// sppm: gather radius of the first pass, in scene units.
    #[serde(default)]
    pub radius: Option<f32>,
    /// sppm: radius-reduction exponent α in (0, 1).
    #[serde(default)]
    pub alpha: Option<f32>,
    /// mlt: probability that a mutation draws a whole new path.
    #[serde(default)]
    pub large_step_probability: Option<f32>,
    /// mlt: standard deviation of a small step in primary sample space.
    #[serde(default)]
    pub small_step_size: Option<f32>,
    /// mlt: independent paths that estimate the image's brightness.
    #[serde(default)]
    pub bootstrap_samples: Option<u32>,
    /// mlt: Markov chains run side by side.
    #[serde(default)]
    pub chains: Option<u32>,
    /// Spread the samples over the pixels by a pilot's error estimates
    /// (default: on with a noise target, off without).
    #[serde(default)]
    pub adaptive: Option<bool>,
    /// Stop once the estimated relative error of the image reaches this.
    #[serde(default)]
    pub noise: Option<f32>,
    /// Path guiding of the path tracer (learned incident light, mixed with phase/BSDF sampling).
    #[serde(default)]
    pub guiding: bool,
}

fn default_integrator_type() -> String {
    "path".into()
}

fn default_sampler() -> String {
    "sobol".into()
}

fn default_true() -> bool {
    true
}

fn default_transmittance() -> String {
    "auto".into()
}

impl Default for IntegratorDesc {
    fn default() -> Self {
        IntegratorDesc {
            kind: default_integrator_type(),
            spp: default_spp(),
            max_depth: default_max_depth(),
            max_scatter_depth: None,
            rr_depth: default_rr_depth(),
            seed: 0,
            transmittance: default_transmittance(),
            equiangular: true,
            forced_scattering: None,
            sun_lobe: None,
            environment_share: None,
            sky_control: None,
            sampler: default_sampler(),
            photons: None,
            radius: None,
            alpha: None,
            large_step_probability: None,
            small_step_size: None,
            bootstrap_samples: None,
            chains: None,
            adaptive: None,
            noise: None,
            guiding: false,
        }
    }
}

fn default_spp() -> u32 {
    64
}
fn default_max_depth() -> u32 {
    64
}
fn default_rr_depth() -> u32 {
    5
}

/// `[[light]]`: one light.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LightDesc {
    /// Isotropic point light.
    Point {
        /// Position.
        position: [f32; 3],
        /// Radiant intensity (W/sr).
        intensity: Color,
    },
    /// Spot light.
    Spot {
        /// Position.
        position: [f32; 3],
        /// Point the spot aims at.
        look_at: [f32; 3],
        /// Radiant intensity on the axis (W/sr).
        intensity: Color,
        /// Half-angle of the cone in degrees.
        #[serde(default = "default_cone_angle")]
        cone_angle: f32,
        /// Width of the soft edge in degrees (inside the cone; default 5, or the whole cone if narrower).
        #[serde(default)]
        cone_falloff: Option<f32>,
        /// Shape of the edge: `smooth` (smoothstep in cosine, default) or `linear` (in angle, Mitsuba's).
        #[serde(default)]
        cone_edge: SpotEdgeDesc,
    },
    /// The sun: a distant disk.
    Sun {
        /// Direction the light travels (from the sun toward the scene).
        direction: [f32; 3],
        /// Irradiance on a plane facing the sun (W/m²).
        irradiance: Color,
        /// Angular radius in degrees (0 = a delta light).
        #[serde(default = "default_sun_radius")]
        angular_radius: f32,
    },
    /// Constant environment radiance.
    Environment {
        /// Radiance from every direction.
        radiance: Color,
    },
    /// Lat-long HDR environment map (EXR).
    EnvironmentMap {
        /// EXR file, relative to the scene file.
        file: PathBuf,
        /// Radiance multiplier (number or RGB).
        #[serde(default = "default_map_scale")]
        scale: Color,
        /// Rotation of the map in degrees about X, then Y, then Z.
        #[serde(default)]
        rotate: Option<[f32; 3]>,
        /// `"nearest"` (constant texels) or `"bilinear"`.
        #[serde(default)]
        filter: MapFilterDesc,
    },
    /// Sky gradient environment.
    Sky {
        /// Radiance at the zenith.
        zenith: Color,
        /// Radiance at the horizon.
        horizon: Color,
        /// Radiance from below the horizon.
        #[serde(default = "default_ground")]
        ground: Color,
        /// Up axis.
        #[serde(default = "default_up")]
        up: [f32; 3],
    },
}

fn default_map_scale() -> Color {
    Color([1.0; 3])
}
fn default_cone_angle() -> f32 {
    30.0
}
/// Soft edge of a spot light when `cone_falloff` is not given (at most the cone itself).
pub const DEFAULT_CONE_FALLOFF: f32 = 5.0;
fn default_sun_radius() -> f32 {
    0.265
}
fn default_ground() -> Color {
    Color([0.0; 3])
}

/// An affine placement: scale, then rotate (X, then Y, then Z, degrees), then translate.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformDesc {
    /// Translation.
    #[serde(default)]
    pub translate: Option<[f32; 3]>,
    /// Rotation angles in degrees about X, Y and Z, applied in that order.
    #[serde(default)]
    pub rotate: Option<[f32; 3]>,
    /// Uniform (number) or per-axis (array) scale.
    #[serde(default)]
    pub scale: Option<Color>,
    /// Keyframes instead of one placement (see `math::keyframes`).
    #[serde(default)]
    pub keyframes: Option<Vec<KeyframeDesc>>,
}

/// One key of `transform = { keyframes = [...] }`: a placement at a time.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeDesc {
    /// Time in frames relative to the frame's time (the unit of `camera.shutter`).
    pub time: f32,
    /// Translation.
    #[serde(default)]
    pub translate: Option<[f32; 3]>,
    /// Rotation angles in degrees about X, Y and Z, applied in that order.
    #[serde(default)]
    pub rotate: Option<[f32; 3]>,
    /// Uniform (number) or per-axis (array) scale.
    #[serde(default)]
    pub scale: Option<Color>,
}

/// `material = { ... }` of a shape.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialDesc {
    /// Lambertian.
    Diffuse {
        /// Reflectance in [0, 1].
        albedo: ColorOrTexture,
    },
    /// Normalized Phong glossy lobe.
    Phong {
        /// Reflectance in [0, 1].
        albedo: ColorOrTexture,
        /// Lobe exponent (≥ 0).
        exponent: f32,
    },
    /// Perfect mirror.
    Mirror {
        /// Reflectance in [0, 1].
        #[serde(default = "default_reflectance")]
        reflectance: ColorOrTexture,
    },
    /// Glass-like interface: smooth (alpha = 0) or GGX-rough.
    Dielectric {
        /// Index of refraction inside the shape.
        #[serde(default = "default_ior")]
        ior: f32,
        /// Microfacet α (0 = smooth).
        #[serde(default)]
        alpha: f32,
        /// Microfacet distribution of a rough surface: `ggx` (default) or `beckmann`.
        #[serde(default)]
        distribution: MicrofacetDesc,
        /// Energy compensation of a rough surface (false: single scattering only).
        #[serde(default = "default_true")]
        multiscatter: bool,
        /// Smith masking of a rough surface: `correlated` (default) or `separable`.
        #[serde(default)]
        masking: MaskingDesc,
    },
    /// Metal: smooth (alpha = 0) or GGX-rough, with a complex index or a Schlick F0.
    Conductor {
        /// Microfacet α (0 = smooth).
        #[serde(default)]
        alpha: f32,
        /// Microfacet distribution of a rough surface: `ggx` (default) or `beckmann`.
        #[serde(default)]
        distribution: MicrofacetDesc,
        /// Smith masking of a rough surface: `correlated` (default) or `separable`.
        #[serde(default)]
        masking: MaskingDesc,
        /// Real part of the complex index of refraction, per channel.
        #[serde(default)]
        eta: Option<Color>,
        /// Extinction coefficient, per channel.
        #[serde(default)]
        k: Option<Color>,
        /// Reflectance at normal incidence (Schlick), instead of eta and k.
        #[serde(default)]
        f0: Option<ColorOrTexture>,
        /// Energy compensation of a rough surface (false: single scattering only).
        #[serde(default = "default_true")]
        multiscatter: bool,
    },
    /// A thin dielectric sheet: reflects both faces' light, transmits unbent.
    ThinDielectric {
        /// Index of refraction of the sheet.
        #[serde(default = "default_ior")]
        ior: f32,
    },
    /// A diffuse base under a smooth (alpha = 0) or rough dielectric coating
    /// (Mitsuba's `plastic` and `roughplastic`).
    Plastic {
        /// Albedo of the base, in [0, 1].
        #[serde(default = "default_plastic_diffuse")]
        diffuse: ColorOrTexture,
        /// Factor on the coating's specular reflection, in [0, 1].
        #[serde(default = "default_plastic_specular")]
        specular: Color,
        /// Index of refraction of the coating.
        #[serde(default = "default_ior")]
        ior: f32,
        /// Sum the base's internal reflections as ρ / (1 − F_dr ρ) (true) or ρ / (1 − F_dr).
        #[serde(default)]
        nonlinear: bool,
        /// Microfacet α of the coating (0 = smooth).
        #[serde(default)]
        alpha: f32,
        /// Microfacet distribution of a rough coating: `ggx` (default) or `beckmann`.
        #[serde(default)]
        distribution: MicrofacetDesc,
        /// Smith masking of a rough coating: `correlated` (default) or `separable`.
        #[serde(default)]
        masking: MaskingDesc,
        /// Weights of a rough coating's diffuse term: `fresnel` (default) or
        /// `microfacet` (Mitsuba's `roughplastic` tables).
        #[serde(default)]
        transmittance: CoatingTransmittanceDesc,
    },
}

/// `masking` of a rough surface: the Smith masking–shadowing of its facets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MaskingDesc {
    /// Height-correlated, 1 / (1 + Λ(wo) + Λ(wi)) (Heitz 2014; brume's default).
    #[default]
    Correlated,
    /// Separable, G1(wo) · G1(wi): Mitsuba 3's; single scattering only.
    Separable,
}

impl<'de> Deserialize<'de> for MaskingDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<MaskingDesc, D::Error> {
        let i = super::messages::one_of(d, &["correlated", "separable"])?;
        Ok([MaskingDesc::Correlated, MaskingDesc::Separable][i])
    }
}

/// `transmittance` of a plastic: how light crossing a rough coating to and
/// from the base is weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CoatingTransmittanceDesc {
    /// The smooth interface's Fresnel transmittance at the macro angles and
    /// its diffuse Fresnel reflectance inside.
    #[default]
    Fresnel,
    /// The rough interface's single-scattering transmittance and internal
    /// reflectance, tabulated as Mitsuba 3's `roughplastic` does (loses
    /// what the microfacets mask).
    Microfacet,
}

impl<'de> Deserialize<'de> for CoatingTransmittanceDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<CoatingTransmittanceDesc, D::Error> {
        let i = super::messages::one_of(d, &["fresnel", "microfacet"])?;
        Ok([
            CoatingTransmittanceDesc::Fresnel,
            CoatingTransmittanceDesc::Microfacet,
        ][i])
    }
}

fn default_plastic_diffuse() -> ColorOrTexture {
    ColorOrTexture::Color(Color([0.5; 3]))
}

fn default_plastic_specular() -> Color {
    Color([1.0; 3])
}

/// `filter` of an environment map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MapFilterDesc {
    /// Radiance constant over a texel.
    #[default]
    Nearest,
    /// Bilinear between texel centres (Mitsuba 3's `envmap`).
    Bilinear,
}

impl<'de> Deserialize<'de> for MapFilterDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<MapFilterDesc, D::Error> {
        let i = super::messages::one_of(d, &["nearest", "bilinear"])?;
        Ok([MapFilterDesc::Nearest, MapFilterDesc::Bilinear][i])
    }
}

/// `cone_edge` of a spot light.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpotEdgeDesc {
    /// A smoothstep in the cosine.
    #[default]
    Smooth,
    /// Linear in the angle from the axis (Mitsuba 3's spot).
    Linear,
}

impl<'de> Deserialize<'de> for SpotEdgeDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<SpotEdgeDesc, D::Error> {
        let i = super::messages::one_of(d, &["smooth", "linear"])?;
        Ok([SpotEdgeDesc::Smooth, SpotEdgeDesc::Linear][i])
    }
}

/// `distribution` of a rough dielectric or conductor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MicrofacetDesc {
    /// GGX (Trowbridge–Reitz), with energy compensation available.
    #[default]
    Ggx,
    /// Beckmann (Mitsuba 3's default), single scattering only.
    Beckmann,
}

impl<'de> Deserialize<'de> for MicrofacetDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<MicrofacetDesc, D::Error> {
        let i = super::messages::one_of(d, &["ggx", "beckmann"])?;
        Ok([MicrofacetDesc::Ggx, MicrofacetDesc::Beckmann][i])
    }
}

fn default_ior() -> f32 {
    1.5
}

fn default_reflectance() -> ColorOrTexture {
    ColorOrTexture::Color(Color([1.0; 3]))
}

/// `[[shape]]`: geometry with a material and optional emission.
///
/// One flat table per shape; which geometric keys apply depends on `type`
/// (checked when the scene is built, so a stray key is named in the error).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeDesc {
    /// `sphere`, `quad`, `box`, `mesh` or `slab`.
    #[serde(rename = "type")]
    pub kind: ShapeType,
    /// Centre (sphere, quad, box).
    #[serde(default)]
    pub center: Option<[f32; 3]>,
    /// Radius (sphere, disk).
    #[serde(default)]
    pub radius: Option<f32>,
    /// Front-facing normal (quad, disk).
    #[serde(default)]
    pub normal: Option<[f32; 3]>,
    /// Side lengths: `[u, v]` for a quad, `[x, y, z]` for a box.
    #[serde(default)]
    pub size: Option<Vec<f32>>,
    /// Direction of the quad's first side, or of a disk's polar angle 0 (default: any tangent).
    #[serde(default)]
    pub u_axis: Option<[f32; 3]>,
    /// OBJ file, relative to the scene file (mesh).
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// Surface material (default: diffuse, albedo 0.5).
    #[serde(default)]
    pub material: Option<MaterialDesc>,
    /// Emitted radiance (a colour or a texture): makes the shape an area light.
    #[serde(default)]
    pub emission: Option<ColorOrTexture>,
    /// Emit from both sides.
    #[serde(default)]
    pub two_sided: bool,
    /// Placement applied to the shape.
    #[serde(default)]
    pub transform: Option<TransformDesc>,
    /// A medium filling the (closed) shape: homogeneous or vdb, see `scene::interior`.
    #[serde(default)]
    pub interior: Option<MediumDesc>,
    /// How a slab answers lines between its records: `quadrilinear` (default) or `nearest` (slab).
    #[serde(default)]
    pub filter: Option<String>,
    /// A sphere's texture axes: `{ pole, seam }` (default +Y and +X).
    #[serde(default)]
    pub uv_axes: Option<UvAxesDesc>,
    /// A box's face coordinates: `brume` (default) or `mitsuba` (its cube's).
    #[serde(default)]
    pub face_uv: Option<String>,
}

/// `uv_axes` of a sphere: where its latitude–longitude texture coordinates
/// have their pole (v = 1) and their seam (u = 0), as world directions.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct UvAxesDesc {
    /// Direction of the pole where v = 1 (brume's default +Y).
    pub pole: [f32; 3],
    /// Direction, perpendicular to the pole, where u = 0 (default +X); u
    /// grows toward seam × pole.
    pub seam: [f32; 3],
}

impl ShapeDesc {
    /// The colour parameters of the shape that may hold a texture, with their keys.
    pub fn colors(&self) -> Vec<(&'static str, &ColorOrTexture)> {
        let mut out = Vec::new();
        match &self.material {
            Some(MaterialDesc::Diffuse { albedo }) | Some(MaterialDesc::Phong { albedo, .. }) => {
                out.push(("material.albedo", albedo))
            }
            Some(MaterialDesc::Mirror { reflectance }) => {
                out.push(("material.reflectance", reflectance))
            }
            Some(MaterialDesc::Conductor { f0: Some(f0), .. }) => out.push(("material.f0", f0)),
            _ => {}
        }
        if let Some(e) = &self.emission {
            out.push(("emission", e));
        }
        out
    }

    /// The image files of the shape's textures (as written).
    pub fn texture_files(&self) -> Vec<&std::path::Path> {
        self.colors()
            .into_iter()
            .filter_map(|(_, c)| c.file())
            .collect()
    }
}

/// The kinds of shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShapeType {
    /// A sphere: `center`, `radius`.
    Sphere,
    /// A rectangle: `center`, `normal`, `size = [u, v]`, optional `u_axis`.
    Quad,
    /// An axis-aligned box before its transform: `center`, `size = [x, y, z]`.
    Box,
    /// A flat disk: `center`, `normal`, `radius`, optional `u_axis` (where its polar angle starts).
    Disk,
    /// A triangle mesh from a Wavefront OBJ `file`.
    Mesh,
    /// A baked light slab from a `.slab` `file` (`brume slab bake`).
    Slab,
}

impl<'de> Deserialize<'de> for ShapeType {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<ShapeType, D::Error> {
        const KINDS: [ShapeType; 6] = [
            ShapeType::Sphere,
            ShapeType::Quad,
            ShapeType::Box,
            ShapeType::Disk,
            ShapeType::Mesh,
            ShapeType::Slab,
        ];
        let i = super::messages::one_of(d, &["sphere", "quad", "box", "disk", "mesh", "slab"])?;
        Ok(KINDS[i])
    }
}

/// `[[medium]]`: one participating medium.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MediumDesc {
    /// Constant coefficients inside a bounding shape, or everywhere.
    Homogeneous {
        /// Absorption coefficient (1/m).
        #[serde(default)]
        sigma_a: Option<Color>,
        /// Scattering coefficient (1/m).
        #[serde(default)]
        sigma_s: Option<Color>,
        /// Extinction coefficient (1/m), with `albedo` instead of sigma_a/sigma_s.
        #[serde(default)]
        sigma_t: Option<Color>,
        /// Single-scattering albedo, with `sigma_t`.
        #[serde(default)]
        albedo: Option<Color>,
        /// Emitted radiance Le (the source term is σa·Le).
        #[serde(default)]
        emission: Option<Color>,
        /// Phase function.
        #[serde(default)]
        phase: Option<PhaseDesc>,
        /// Region: a box or a sphere; omit with `global = true`.
        #[serde(default)]
        bounds: Option<BoundsDesc>,
        /// Fill all of space.
        #[serde(default)]
        global: bool,
        /// Placement of the bounds.
        #[serde(default)]
        transform: Option<TransformDesc>,
    },
    /// Exponential height fog σt(h) = σt0·exp(-(h - height)/scale_height), everywhere.
    HeightFog {
        /// Absorption coefficient at `height` (1/m).
        #[serde(default)]
        sigma_a: Option<Color>,
        /// Scattering coefficient at `height` (1/m).
        #[serde(default)]
        sigma_s: Option<Color>,
        /// Extinction coefficient at `height` (1/m), with `albedo`.
        #[serde(default)]
        sigma_t: Option<Color>,
        /// Meteorological visual range at `height` (m): σt0 = ln(50)/visibility, grey.
        #[serde(default)]
        visibility: Option<f32>,
        /// Single-scattering albedo, with `sigma_t` or `visibility` (default 1).
        #[serde(default)]
        albedo: Option<Color>,
        /// Emitted radiance Le (the source term is σa·Le).
        #[serde(default)]
        emission: Option<Color>,
        /// Phase function.
        #[serde(default)]
        phase: Option<PhaseDesc>,
        /// Reference height h0 along `up` (m).
        #[serde(default)]
        height: f32,
        /// Scale height H (m): the density falls by e every H upward.
        scale_height: f32,
        /// Up axis (default [0, 1, 0]).
        #[serde(default = "default_up")]
        up: [f32; 3],
    },
    /// Density from an OpenVDB grid (see `scene::vdb`).
    Vdb(VdbDesc),
    /// σt (and albedo) from Mitsuba `.vol` grids (see `scene::vol`).
    Vol(VolDesc),
}

/// The fields of a `type = "vol"` medium.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VolDesc {
    /// `.vol` file of σt (1 or 3 channels), relative to the scene file.
    pub sigma_t_file: PathBuf,
    /// Factor on the σt values (1/m per unit value, default 1).
    #[serde(default)]
    pub scale: Option<f32>,
    /// Constant single-scattering albedo (default 1), without `albedo_file`.
    #[serde(default)]
    pub albedo: Option<Color>,
    /// `.vol` file of the albedo (1 or 3 channels).
    #[serde(default)]
    pub albedo_file: Option<PathBuf>,
    /// Place each grid in its file's bounding box instead of the unit cube.
    #[serde(default)]
    pub use_grid_bbox: bool,
    /// Phase function (default isotropic).
    #[serde(default)]
    pub phase: Option<PhaseDesc>,
    /// Placement of the grids' box.
    #[serde(default)]
    pub transform: Option<TransformDesc>,
}

/// `phase = { ... }` of a medium.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PhaseDesc {
    /// Isotropic.
    Isotropic {},
    /// Henyey–Greenstein with asymmetry g in (-1, 1).
    Hg {
        /// Mean cosine (read in f64 so that a value that rounds to ±1 in f32 is reported as written).
        g: f64,
    },
    /// Rayleigh.
    Rayleigh {},
    /// Two HG lobes: weight·HG(g_forward) + (1-weight)·HG(g_back).
    DoubleHg {
        /// Forward lobe asymmetry.
        g_forward: f64,
        /// Backward lobe asymmetry.
        g_back: f64,
        /// Weight of the forward lobe in [0, 1].
        weight: f32,
    },
}

/// Region of a bounded medium.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum BoundsDesc {
    /// Axis-aligned box before the transform.
    Box {
        /// Minimum corner.
        min: [f32; 3],
        /// Maximum corner.
        max: [f32; 3],
    },
    /// Sphere before the transform.
    Sphere {
        /// Centre.
        #[serde(default)]
        center: [f32; 3],
        /// Radius.
        radius: f32,
    },
}

/// The fields of a `type = "vdb"` medium.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VdbDesc {
    /// OpenVDB file, relative to the scene file.
    pub file: PathBuf,
    /// Name of the density grid.
    #[serde(default = "default_grid")]
    pub grid: String,
    /// Extinction per unit density (1/m).
    #[serde(default = "default_density_scale")]
    pub density_scale: f32,
    /// Per-channel factor on `density_scale` (chromatic extinction).
    #[serde(default)]
    pub sigma_t_scale: Option<Color>,
    /// Single-scattering albedo σs/σt (default 1).
    #[serde(default)]
    pub albedo: Option<Color>,
    /// Phase function (default isotropic).
    #[serde(default)]
    pub phase: Option<PhaseDesc>,
    /// Placement after the file's own index → world map.
    #[serde(default)]
    pub transform: Option<TransformDesc>,
    /// Constant emitted radiance Le.
    #[serde(default)]
    pub emission: Option<Color>,
    /// Temperature grid for blackbody emission.
    #[serde(default)]
    pub temperature_grid: Option<String>,
    /// Kelvin per unit of temperature-grid value.
    #[serde(default)]
    pub temperature_scale: Option<f32>,
    /// Grid whose value times `emission_scale` is Le.
    #[serde(default)]
    pub emission_grid: Option<String>,
    /// Factor on grid-driven emission (default 1).
    #[serde(default)]
    pub emission_scale: Option<Color>,
    /// `"grid"` (default) or `"global"`.
    #[serde(default)]
    pub majorant: Option<String>,
    /// Majorant cell size in voxels (default: from the volume's size and density).
    #[serde(default)]
    pub majorant_cell: Option<u32>,
    /// Name of a vec3s velocity grid (file world units per second) for motion blur.
    #[serde(default)]
    pub velocity_grid: Option<String>,
    /// Factor on the velocities (default 1).
    #[serde(default)]
    pub velocity_scale: Option<f32>,
}

fn default_grid() -> String {
    "density".into()
}
fn default_density_scale() -> f32 {
    1.0
}
