//! `<bsdf>`: diffuse, null, dielectric, thindielectric, roughdielectric,
//! conductor, roughconductor, plastic, roughplastic, twosided; the rest is refused by name.

use super::texture::UvFrame;
use super::values::{ColorParam, Obj, Props};
use super::{unsupported, Ctx};
use crate::error::Result;
use crate::scene::description::{
    CoatingTransmittanceDesc, Color, ColorOrTexture, MaskingDesc, MaterialDesc, MicrofacetDesc,
};

/// Mitsuba's named indices of refraction (its `dielectric` table).
const NAMED_IOR: [(&str, f64); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// What a shape's `<bsdf>` becomes.
pub(crate) struct Surface {
    /// brume's material; `None` for `null` (no surface: only a medium boundary).
    pub material: Option<MaterialDesc>,
    /// Mitsuba's BSDF is black from behind (not wrapped in `twosided`, not a dielectric or null).
    pub one_sided: bool,
    /// Light passes through (null, dielectric).
    pub transmissive: bool,
}

/// The surface of a shape's `<bsdf>` (or `<ref>` to one).
/// `frame` relates Mitsuba's texture coordinates on the shape to brume's.
pub(crate) fn read(ctx: &Ctx, obj: Obj, frame: UvFrame) -> Result<Surface> {
    let node = obj.node;
    let kind = node.required("type")?;
    if kind == "twosided" {
        let p = ctx.props(node)?;
        let inner = p.objects("bsdf");
        p.finish()?;
        return match inner.as_slice() {
            [one] if one.node.attr("type") == Some("twosided") => {
                Err(node.error("a twosided inside a twosided"))
            }
            [one] => read(ctx, *one, frame).map(|s| Surface {
                one_sided: false,
                ..s
            }),
            [] => Err(node.error("holds no <bsdf>")),
            _ => Err(unsupported(node, "a different BSDF on each side")),
        };
    }
    let p = ctx.props(node)?;
    let surface = match kind {
        "null" => Surface {
            material: None,
            one_sided: false,
            transmissive: true,
        },
        "diffuse" => opaque(MaterialDesc::Diffuse {
            albedo: color(ctx, &p, "reflectance", 0.5, frame)?,
        }),
        "dielectric" | "roughdielectric" => Surface {
            material: Some(dielectric(&p, kind == "roughdielectric")?),
            one_sided: false,
            transmissive: true,
        },
        "conductor" | "roughconductor" => opaque(conductor(&p, kind == "roughconductor")?),
        "thindielectric" => Surface {
            material: Some(MaterialDesc::ThinDielectric {
                ior: relative_ior(&p)?,
            }),
            one_sided: false,
            transmissive: true,
        },
        "plastic" => opaque(plastic(ctx, &p, false, frame)?),
        "roughplastic" => opaque(plastic(ctx, &p, true, frame)?),
        _ => return Err(unsupported(node, "this BSDF")),
    };
    p.finish()?;
    Ok(surface)
}

/// An opaque, one-sided surface.
fn opaque(material: MaterialDesc) -> Surface {
    Surface {
        material: Some(material),
        one_sided: true,
        transmissive: false,
    }
}

/// An index of refraction: a number or one of Mitsuba's names.
fn ior(p: &Props, key: &str, default: f64) -> Result<f64> {
    let named = p.node_of(key).is_some_and(|n| n.tag == "string");
    if let Some((name, at)) = if named { p.string(key)? } else { None } {
        let lower = name.to_lowercase().replace('-', " ");
        return NAMED_IOR
            .iter()
            .find(|(n, _)| *n == lower)
            .map(|(_, v)| *v)
            .ok_or_else(|| at.error(format!("unknown material `{name}` (give a number or one of Mitsuba's names, e.g. \"water\", \"bk7\", \"air\")")));
    }
    let v = p.float(key)?.unwrap_or(default);
    if v <= 0.0 {
        return Err(p.node_of(key).unwrap_or(p.owner).error("must be positive"));
    }
    Ok(v)
}

/// A rough BSDF's microfacet model: `distribution` (Mitsuba's default
/// `beckmann`, or `ggx`) and `alpha` (default 0.1), or `alpha_u` and
/// `alpha_v` when they are equal (brume's distributions are isotropic).
fn roughness(p: &Props) -> Result<(f32, MicrofacetDesc)> {
    let distribution = match p.string("distribution")? {
        Some(("ggx", _)) => MicrofacetDesc::Ggx,
        Some(("beckmann", _)) | None => MicrofacetDesc::Beckmann,
        Some((_, at)) => {
            return Err(unsupported(
                at,
                "this microfacet distribution (Mitsuba's are beckmann and ggx)",
            ))
        }
    };
    for key in ["alpha", "alpha_u", "alpha_v"] {
        if let Some(at) = p.node_of(key).filter(|n| n.tag == "texture") {
            return Err(unsupported(at, "a roughness texture"));
        }
    }
    p.bool("sample_visible")?; // a sampling choice, not a look
    let alpha = match (p.float("alpha_u")?, p.float("alpha_v")?) {
        (None, None) => p.float("alpha")?.unwrap_or(0.1),
        (Some(u), Some(v)) if u == v && p.node_of("alpha").is_none() => u,
        (Some(_), Some(_)) if p.node_of("alpha").is_none() => {
            return Err(unsupported(
                p.node_of("alpha_v").unwrap_or(p.owner),
                "anisotropic roughness (alpha_u different from alpha_v)",
            ))
        }
        _ => {
            return Err(p
                .owner
                .error("give either alpha or both alpha_u and alpha_v"))
        }
    };
    if alpha <= 0.0 {
        let at = p
            .node_of("alpha")
            .or(p.node_of("alpha_u"))
            .unwrap_or(p.owner);
        return Err(at.error("must be positive"));
    }
    Ok((alpha as f32, distribution))
}

/// int_ior / ext_ior with Mitsuba's defaults (bk7 in air): brume's outside
/// index is 1, so the relative index is what it takes.
fn relative_ior(p: &Props) -> Result<f32> {
    let int = ior(p, "int_ior", 1.5046)?;
    let ext = ior(p, "ext_ior", 1.000277)?;
    Ok((int / ext) as f32)
}

/// `plastic` / `roughplastic`: diffuse_reflectance (0.5, or a texture),
/// specular_reflectance (1; roughplastic takes 1 only), int_ior
/// (polypropylene) over ext_ior (air), `nonlinear` (false), and for the
/// rough one `distribution` (beckmann) and `alpha` (0.1).
fn plastic(ctx: &Ctx, p: &Props, rough: bool, frame: UvFrame) -> Result<MaterialDesc> {
    let int = ior(p, "int_ior", 1.49)?;
    let ext = ior(p, "ext_ior", 1.000277)?;
    let specular = match p.color("specular_reflectance")? {
        None => Color([1.0; 3]),
        Some(ColorParam::Rgb(c)) if !rough || c == [1.0; 3] => Color(c.map(|v| v as f32)),
        Some(ColorParam::Rgb(_)) => {
            return Err(unsupported(
                p.node_of("specular_reflectance").unwrap_or(p.owner),
                "a roughplastic specular_reflectance other than 1",
            ))
        }
        Some(ColorParam::Texture(t)) => {
            return Err(unsupported(t.at, "a textured specular_reflectance"))
        }
    };
    let (alpha, distribution) = if rough {
        roughness(p)?
    } else {
        (0.0, MicrofacetDesc::Ggx)
    };
    Ok(MaterialDesc::Plastic {
        diffuse: color(ctx, p, "diffuse_reflectance", 0.5, frame)?,
        specular,
        ior: (int / ext) as f32,
        nonlinear: p.bool("nonlinear")?.unwrap_or(false),
        alpha,
        distribution,
        masking: MITSUBA_MASKING,
        transmittance: if rough {
            CoatingTransmittanceDesc::Microfacet
        } else {
            CoatingTransmittanceDesc::Fresnel
        },
    })
}

/// `dielectric` / `roughdielectric`, with the relative index of [`relative_ior`].
fn dielectric(p: &Props, rough: bool) -> Result<MaterialDesc> {
    let ior = relative_ior(p)?;
    for key in ["specular_reflectance", "specular_transmittance"] {
        if let Some(c) = p.color(key)? {
            if !matches!(c, ColorParam::Rgb([1.0, 1.0, 1.0])) {
                return Err(unsupported(
                    p.node_of(key).unwrap_or(p.owner),
                    "a tinted dielectric",
                ));
            }
        }
    }
    let (alpha, distribution) = if rough {
        roughness(p)?
    } else {
        (0.0, MicrofacetDesc::Ggx)
    };
    Ok(MaterialDesc::Dielectric {
        ior,
        alpha,
        distribution,
        multiscatter: MITSUBA_MULTISCATTER,
        masking: MITSUBA_MASKING,
    })
}

/// Mitsuba's rough conductors and dielectrics model single scattering between
/// microfacets only: imported scenes keep brume's energy compensation off to match.
const MITSUBA_MULTISCATTER: bool = false;

/// Mitsuba's microfacet models mask and shadow separably, G1(wi) · G1(wo).
const MITSUBA_MASKING: MaskingDesc = MaskingDesc::Separable;

/// `conductor` / `roughconductor`: a named material (Mitsuba's RGB η and k
/// for it), "none" (a perfect reflector) or `eta`/`k` as RGB.
fn conductor(p: &Props, rough: bool) -> Result<MaterialDesc> {
    let named = p.string("material")?;
    let eta = p.color("eta")?;
    let k = p.color("k")?;
    let tint = p.color("specular_reflectance")?;
    let (alpha, distribution) = if rough {
        roughness(p)?
    } else {
        (0.0, MicrofacetDesc::Ggx)
    };
    let rgb = |c: Option<ColorParam>, key: &str| -> Result<Option<Color>> {
        match c {
            None => Ok(None),
            Some(ColorParam::Rgb(v)) => Ok(Some(Color(v.map(|x| x as f32)))),
            Some(ColorParam::Texture(t)) => Err(unsupported(t.at, &format!("a textured {key}"))),
        }
    };
    if tint.is_some_and(|t| !matches!(t, ColorParam::Rgb([1.0, 1.0, 1.0]))) {
        return Err(unsupported(
            p.node_of("specular_reflectance").unwrap_or(p.owner),
            "a tinted conductor (specular_reflectance other than 1)",
        ));
    }
    // The reflectance: a complex index, or f0 = 1 (a perfect reflector).
    let (eta, k, f0) = match (named, eta.is_some() || k.is_some()) {
        (Some(_), true) => {
            return Err(p.owner.error("give either material or eta and k, not both"))
        }
        (Some((name, at)), false) if name != "none" => {
            let (eta, k) = super::conductors::named(name).ok_or_else(|| {
                at.error(format!("unknown conductor material `{name}` (Mitsuba's names, e.g. Au, Ag, Cu, Al, Cr)"))
            })?;
            (Some(Color(eta)), Some(Color(k)), None)
        }
        // "none" (the default without eta/k): reflects everything at every angle.
        (_, false) => (None, None, Some(ColorOrTexture::Color(Color([1.0; 3])))),
        (None, true) => (
            Some(rgb(eta, "eta")?.unwrap_or(Color([0.0; 3]))),
            Some(rgb(k, "k")?.unwrap_or(Color([1.0; 3]))),
            None,
        ),
    };
    Ok(MaterialDesc::Conductor {
        alpha,
        distribution,
        eta,
        k,
        f0,
        multiscatter: MITSUBA_MULTISCATTER,
        masking: MITSUBA_MASKING,
    })
}

/// A colour or a `bitmap`/`checkerboard` texture, with Mitsuba's default `grey`.
fn color(ctx: &Ctx, p: &Props, key: &str, grey: f32, frame: UvFrame) -> Result<ColorOrTexture> {
    match p.color(key)? {
        None => Ok(ColorOrTexture::Color(Color([grey; 3]))),
        Some(ColorParam::Rgb(c)) => Ok(ColorOrTexture::Color(Color(c.map(|v| v as f32)))),
        Some(ColorParam::Texture(t)) => {
            super::texture::read(ctx, t.node, frame).map(ColorOrTexture::Texture)
        }
    }
}
