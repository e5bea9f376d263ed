//! Building the microfacet and dielectric materials of `material = { ... }`.

use super::description::{
    CoatingTransmittanceDesc, Color, ColorOrTexture, MaskingDesc, MaterialDesc, MicrofacetDesc,
};
use super::validate::Check;
use crate::error::Result;
use crate::material::albedo::ETA_MAX;
use crate::material::layered::{diffuse_fresnel, Plastic};
use crate::material::rough_plastic::CoatingTables;
use crate::material::{ConductorFresnel, Distribution, Material, MIN_ALPHA};
use crate::math::color::Rgb;

/// A microfacet α: 0 for a smooth surface, else in [MIN_ALPHA, 1].
fn alpha(check: &Check, field: &str, a: f32) -> Result<f32> {
    let a = check.finite(field, a)?;
    if a == 0.0 || (MIN_ALPHA..=1.0).contains(&a) {
        Ok(a)
    } else {
        Err(check.error(
            field,
            format!("must be 0 (smooth) or between {MIN_ALPHA} and 1, got {a}"),
        ))
    }
}

/// The roughness keys shared by rough materials.
#[derive(Clone, Copy)]
pub(super) struct Rough {
    /// Microfacet α as written.
    pub alpha: f32,
    /// `distribution` as written (default GGX).
    pub distribution: MicrofacetDesc,
    /// `multiscatter` as written (default true).
    pub multiscatter: bool,
    /// `masking` as written (default correlated).
    pub masking: MaskingDesc,
}

impl Rough {
    /// The keys as written.
    pub(super) fn of(
        alpha: f32,
        distribution: MicrofacetDesc,
        multiscatter: bool,
        masking: MaskingDesc,
    ) -> Rough {
        Rough {
            alpha,
            distribution,
            multiscatter,
            masking,
        }
    }

    /// The distribution, refusing energy compensation where brume has no
    /// albedo table for it (Beckmann): the user chooses single scattering.
    fn distribution(&self, check: &Check, field: &str) -> Result<Distribution> {
        let compensated = self.multiscatter && self.alpha > 0.0;
        match (self.distribution, self.masking) {
            (_, MaskingDesc::Separable) if compensated => Err(check.error(
                &format!("{field}.multiscatter"),
                "energy compensation is tabulated for correlated masking only: with `masking = \"separable\"` write `multiscatter = false`",
            )),
            (MicrofacetDesc::Ggx, MaskingDesc::Correlated) => Ok(Distribution::Ggx),
            (MicrofacetDesc::Ggx, MaskingDesc::Separable) => Ok(Distribution::GgxSeparable),
            (MicrofacetDesc::Beckmann, _) if compensated => Err(check.error(
                &format!("{field}.multiscatter"),
                "energy compensation is tabulated for GGX only: with `distribution = \"beckmann\"` write `multiscatter = false`",
            )),
            (MicrofacetDesc::Beckmann, MaskingDesc::Correlated) => Ok(Distribution::Beckmann),
            (MicrofacetDesc::Beckmann, MaskingDesc::Separable) => {
                Ok(Distribution::BeckmannSeparable)
            }
        }
    }
}

/// `{ type = "dielectric", ior, alpha, distribution, multiscatter }`.
pub(super) fn dielectric(check: &Check, field: &str, ior: f32, rough: Rough) -> Result<Material> {
    let ior = check.range(&format!("{field}.ior"), ior, 0.0, 10.0, false)?;
    let alpha = alpha(check, &format!("{field}.alpha"), rough.alpha)?;
    let distribution = rough.distribution(check, field)?;
    let multiscatter = rough.multiscatter && distribution == Distribution::Ggx;
    // The compensation's albedo tables cover index ratios 1/ETA_MAX..ETA_MAX.
    let tabulated = (1.0 / ETA_MAX..=ETA_MAX).contains(&ior);
    if multiscatter && alpha > 0.0 && !tabulated {
        return Err(check.error(
            &format!("{field}.ior"),
            format!(
                "{ior} is outside 1/{ETA_MAX}..{ETA_MAX}, where the energy compensation of a rough dielectric is tabulated; set `multiscatter = false` to use the single-scattering lobe alone"
            ),
        ));
    }
    Ok(Material::Dielectric {
        ior,
        alpha,
        distribution,
        multiscatter,
    })
}

/// `{ type = "conductor", alpha, distribution, eta + k | f0, multiscatter }`.
pub(super) fn conductor(
    check: &Check,
    field: &str,
    rough: Rough,
    eta: Option<Color>,
    k: Option<Color>,
    f0: Option<Rgb>,
) -> Result<Material> {
    let f = |key: &str| format!("{field}.{key}");
    let fresnel = match (eta, k, f0) {
        (Some(eta), Some(k), None) => {
            let eta = check.color(&f("eta"), eta)?;
            if eta.min_channel() <= 0.0 {
                return Err(check.error(&f("eta"), "must be positive in every channel"));
            }
            ConductorFresnel::Complex {
                eta,
                k: check.color(&f("k"), k)?,
            }
        }
        // f0 was checked (as a reflectance or texture) by the caller.
        (None, None, Some(f0)) => ConductorFresnel::Schlick { f0 },
        (Some(_), None, None) => return Err(check.error(&f("k"), "missing (eta needs k)")),
        (None, Some(_), None) => return Err(check.error(&f("eta"), "missing (k needs eta)")),
        (None, None, None) => {
            return Err(check.error(
                field,
                "a conductor needs `eta` and `k` (complex index of refraction) or `f0` (reflectance at normal incidence)",
            ))
        }
        _ => {
            return Err(check.error(
                &f("f0"),
                "give either `eta` and `k` or `f0`, not both",
            ))
        }
    };
    let distribution = rough.distribution(check, field)?;
    Ok(Material::Conductor {
        alpha: alpha(check, &f("alpha"), rough.alpha)?,
        fresnel,
        distribution,
        multiscatter: rough.multiscatter && distribution == Distribution::Ggx,
    })
}

/// The material of `material = { ... }`, with `color` reading a colour
/// parameter (a constant, or a texture it keeps aside).
pub(super) fn material(
    desc: &MaterialDesc,
    check: &Check,
    field: &str,
    color: &mut dyn FnMut(&str, &ColorOrTexture) -> Result<Rgb>,
) -> Result<Material> {
    Ok(match desc {
        MaterialDesc::Diffuse { albedo } => Material::Diffuse {
            albedo: color("albedo", albedo)?,
        },
        MaterialDesc::Phong { albedo, exponent } => Material::Phong {
            albedo: color("albedo", albedo)?,
            exponent: check.range(&format!("{field}.exponent"), *exponent, 0.0, 1e6, true)?,
        },
        MaterialDesc::Mirror { reflectance } => Material::Mirror {
            reflectance: color("reflectance", reflectance)?,
        },
        MaterialDesc::Dielectric {
            ior,
            alpha,
            distribution,
            multiscatter,
            masking,
        } => {
            let rough = Rough::of(*alpha, *distribution, *multiscatter, *masking);
            dielectric(check, field, *ior, rough)?
        }
        MaterialDesc::Conductor {
            alpha,
            distribution,
            eta,
            k,
            f0,
            multiscatter,
            masking,
        } => {
            let f0 = f0.as_ref().map(|f0| color("f0", f0)).transpose()?;
            let rough = Rough::of(*alpha, *distribution, *multiscatter, *masking);
            conductor(check, field, rough, *eta, *k, f0)?
        }
        MaterialDesc::ThinDielectric { ior } => thin_dielectric(check, field, *ior)?,
        MaterialDesc::Plastic { diffuse, .. } => {
            plastic(check, field, color("diffuse", diffuse)?, coating_of(desc))?
        }
    })
}

/// The coating keys of a `plastic` description as written.
fn coating_of(desc: &MaterialDesc) -> Coating {
    let MaterialDesc::Plastic {
        specular,
        ior,
        nonlinear,
        alpha,
        distribution,
        masking,
        transmittance,
        ..
    } = *desc
    else {
        unreachable!("coating_of is asked of plastics only")
    };
    Coating {
        specular,
        ior,
        nonlinear,
        // Mitsuba's roughplastic is single scattering only; there is no compensation key.
        rough: Rough::of(alpha, distribution, false, masking),
        transmittance,
    }
}

/// `{ type = "thin_dielectric", ior }`.
pub(super) fn thin_dielectric(check: &Check, field: &str, ior: f32) -> Result<Material> {
    let ior = check.range(&format!("{field}.ior"), ior, 0.0, 10.0, false)?;
    Ok(Material::ThinDielectric { ior })
}

/// The coating keys of a plastic as written.
pub(super) struct Coating {
    /// `specular` (default 1).
    pub specular: Color,
    /// `ior` of the coating.
    pub ior: f32,
    /// `nonlinear` (default false).
    pub nonlinear: bool,
    /// `alpha` (0: smooth) and `distribution` (default GGX).
    pub rough: Rough,
    /// `transmittance` (default fresnel).
    pub transmittance: CoatingTransmittanceDesc,
}

/// `{ type = "plastic", diffuse, specular, ior, nonlinear, alpha, distribution }`;
/// `diffuse` was checked (as a reflectance or texture) by the caller.
pub(super) fn plastic(
    check: &Check,
    field: &str,
    diffuse: Rgb,
    coating: Coating,
) -> Result<Material> {
    let ior = check.range(&format!("{field}.ior"), coating.ior, 0.0, 10.0, false)?;
    let alpha = alpha(check, &format!("{field}.alpha"), coating.rough.alpha)?;
    let distribution = coating.rough.distribution(check, field)?;
    let tables = match coating.transmittance {
        CoatingTransmittanceDesc::Fresnel => None,
        CoatingTransmittanceDesc::Microfacet if alpha == 0.0 => {
            return Err(check.error(
                &format!("{field}.transmittance"),
                "\"microfacet\" weighs a rough coating: give `alpha` > 0, or leave it out for a smooth one",
            ))
        }
        CoatingTransmittanceDesc::Microfacet => Some(CoatingTables::of(distribution, alpha, ior)),
    };
    Ok(Material::Plastic(Plastic {
        diffuse,
        specular: check.albedo(&format!("{field}.specular"), coating.specular)?,
        ior,
        fdr_int: diffuse_fresnel(1.0 / ior),
        nonlinear: coating.nonlinear,
        alpha,
        distribution,
        tables,
    }))
}

/// Thin sheets and plastic are refused by the other estimators: plastic
/// mixes a delta lobe with a diffuse one, which bdpt's per-vertex delta flag
/// cannot express, and neither has been checked against bdpt, mlt or sppm.
pub(super) fn path_tracer_only(
    material: &Material,
    integrator: &str,
    field: &str,
    check: &Check,
) -> Result<()> {
    let name = match material {
        Material::ThinDielectric { .. } => "thin_dielectric",
        Material::Plastic(_) => "plastic",
        _ => return Ok(()),
    };
    if integrator == "path" {
        return Ok(());
    }
    Err(check.error(
        &format!("{field}.material"),
        format!("`{name}` is supported by the path tracer only (integrator.type = \"path\"), not by `{integrator}`"),
    ))
}

#[cfg(test)]
mod tests {
    use crate::material::ConductorFresnel;
    use crate::math::color::Rgb;

    #[test]
    fn f0_of_one_is_a_perfect_reflector_at_every_angle() {
        let f = ConductorFresnel::Schlick { f0: Rgb::WHITE };
        for c in [0.0, 0.3, 1.0] {
            assert_eq!(f.eval(c), Rgb::WHITE);
        }
    }
}
