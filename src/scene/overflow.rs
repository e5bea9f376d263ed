//! Values that are finite as written but overflow single precision once
//! combined: σt = σa + σs, density × density_scale × sigma_t_scale, the
//! source term σa·Le, texels × scale. brume computes in f32, where such a
//! product is +inf: tracking against an infinite majorant, a sampling
//! distribution of infinite total or an infinite radiance that every pixel
//! drops. Each is refused at load, naming the key and the product.

use super::validate::Check;
use crate::error::Result;
use crate::math::color::Rgb;

/// Refuses `value`, computed in f32 from the file's values, when it is not
/// finite; `what` says how it was formed (`sigma_a + sigma_s`) and `exact`
/// is the same computation in f64, shown in the message.
pub(super) fn fits(
    check: &Check,
    field: &str,
    value: f32,
    exact: f64,
    what: impl FnOnce() -> String,
) -> Result<()> {
    if value.is_finite() {
        return Ok(());
    }
    Err(check.error(
        field,
        format!(
            "{} is {exact:.3e}, which overflows single precision (above 3.4e38)",
            what()
        ),
    ))
}

/// Refuses colour `a` times colour `b` (per channel) when a channel overflows.
pub(super) fn product(
    check: &Check,
    field: &str,
    (a, a_name): (Rgb, &str),
    (b, b_name): (Rgb, &str),
) -> Result<()> {
    for c in 0..3 {
        fits(check, field, a[c] * b[c], a[c] as f64 * b[c] as f64, || {
            let which = channel(c, a, b);
            format!("{a_name} {} × {b_name} {}{which}", num(a[c]), num(b[c]))
        })?;
    }
    Ok(())
}

/// Refuses colour `a` plus colour `b` (per channel) when a channel overflows.
pub(super) fn sum(
    check: &Check,
    field: &str,
    (a, a_name): (Rgb, &str),
    (b, b_name): (Rgb, &str),
) -> Result<()> {
    for c in 0..3 {
        fits(check, field, a[c] + b[c], a[c] as f64 + b[c] as f64, || {
            let which = channel(c, a, b);
            format!("{a_name} {} + {b_name} {}{which}", num(a[c]), num(b[c]))
        })?;
    }
    Ok(())
}

/// ` (red)`, ` (green)`, ` (blue)`: which channel overflowed, when the colours are not grey.
fn channel(c: usize, a: Rgb, b: Rgb) -> &'static str {
    let grey = |x: Rgb| x.r == x.g && x.g == x.b;
    match grey(a) && grey(b) {
        true => "",
        false => [" (red)", " (green)", " (blue)"][c],
    }
}

/// A number as a user would write it: `1e30`, not thirty zeros.
pub(super) fn num(v: f32) -> String {
    if v != 0.0 && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// The largest value of each channel of `texels` (0 for none).
pub(super) fn brightest(texels: impl Iterator<Item = Rgb>) -> Rgb {
    texels.fold(Rgb::BLACK, |m, t| {
        Rgb::new(m.r.max(t.r), m.g.max(t.g), m.b.max(t.b))
    })
}
