//! Numbers as Mitsuba writes them in attributes: one, a list (commas and/or
//! spaces), or a point's `x`, `y`, `z`. The lowest layer of the importer's
//! value readers.

use super::mechanics::Node;
use crate::error::Result;

/// A finite number written in `node`.
pub(crate) fn number(node: &Node, text: &str) -> Result<f64> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(node.error(format!("`{text}` is not a finite number"))),
    }
}

/// Numbers separated by commas and/or spaces.
pub(crate) fn numbers(node: &Node, text: &str) -> Result<Vec<f64>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| number(node, s))
        .collect()
}

/// `x`, `y`, `z` attributes (each defaulting to `fill`) or `value="x, y, z"`.
pub(crate) fn triple(node: &Node, fill: f64) -> Result<[f64; 3]> {
    if let Some(text) = node.attr("value") {
        return match numbers(node, text)?.as_slice() {
            [x, y, z] => Ok([*x, *y, *z]),
            _ => Err(node.error(format!("`{text}` is not three numbers"))),
        };
    }
    let mut out = [fill; 3];
    for (slot, key) in out.iter_mut().zip(["x", "y", "z"]) {
        if let Some(text) = node.attr(key) {
            *slot = number(node, text)?;
        }
    }
    Ok(out)
}
