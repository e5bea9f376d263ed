//! `<spectrum>` in Mitsuba's RGB mode.

use super::mechanics::Node;
use super::numbers::number;
use crate::error::Result;

/// The RGB of `<spectrum value>`: one number is a flat spectrum (grey);
/// wavelength:value pairs are refused until the CIE conversion is in.
pub(crate) fn to_rgb(node: &Node, value: &str) -> Result<[f64; 3]> {
    if !value.contains(':') {
        return Ok([number(node, value)?; 3]);
    }
    Err(super::unsupported(
        node,
        "wavelength:value spectra (give an <rgb>, or one number for a flat spectrum)",
    ))
}
