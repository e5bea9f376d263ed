//! Value checks that turn bad numbers into errors naming the file and field.

use crate::error::Error;
use crate::math::color::Rgb;
use crate::math::Vec3;
use crate::scene::description::Color;
use std::path::{Path, PathBuf};

/// Checks values of one scene file.
pub(crate) struct Check {
    file: PathBuf,
    warnings: std::cell::RefCell<Vec<String>>,
    /// The time keyframe times are measured from, in frames: the frame
    /// number under `animation.keyframe_time = "absolute"`, else 0.
    key_time_origin: f32,
}

impl Check {
    /// Checks for values of `file`.
    pub fn new(file: &Path) -> Check {
        Check {
            file: file.to_path_buf(),
            warnings: Default::default(),
            key_time_origin: 0.0,
        }
    }

    /// The same checks, with keyframe times measured from `origin` (frames).
    pub fn with_key_time_origin(mut self, origin: f32) -> Check {
        self.key_time_origin = origin;
        self
    }

    /// The time keyframe times are measured from (see `with_key_time_origin`).
    pub fn key_time_origin(&self) -> f32 {
        self.key_time_origin
    }

    /// Records a warning about `field`: valid, but probably not what the user meant.
    pub fn warn(&self, field: &str, message: impl Into<String>) {
        self.warnings.borrow_mut().push(format!(
            "{}: {field}: {}",
            self.file.display(),
            message.into()
        ));
    }

    /// The warnings recorded so far.
    pub fn take_warnings(&self) -> Vec<String> {
        std::mem::take(&mut self.warnings.borrow_mut())
    }

    /// An error about `field`.
    pub fn error(&self, field: &str, message: impl Into<String>) -> Error {
        Error::Scene {
            file: self.file.clone(),
            field: field.to_string(),
            message: message.into(),
        }
    }

    /// A finite number.
    pub fn finite(&self, field: &str, v: f32) -> Result<f32, Error> {
        if v.is_finite() {
            Ok(v)
        } else if v.is_infinite() {
            // 1e39 as written reads as inf: say so rather than "got inf"
            Err(self.error(
                field,
                "must be a finite number between -3.4e38 and 3.4e38 (single precision), \
                 got one beyond it (or inf)",
            ))
        } else {
            Err(self.error(field, format!("must be a finite number, got {v}")))
        }
    }

    /// A number in `(lo, hi)`, or `[lo, hi]` when `inclusive`.
    pub fn range(
        &self,
        field: &str,
        v: f32,
        lo: f32,
        hi: f32,
        inclusive: bool,
    ) -> Result<f32, Error> {
        let v = self.finite(field, v)?;
        let ok = if inclusive {
            v >= lo && v <= hi
        } else {
            v > lo && v < hi
        };
        if ok {
            Ok(v)
        } else {
            let (a, b) = if inclusive { ("[", "]") } else { ("(", ")") };
            let (lo, hi, v) = (user_number(lo), user_number(hi), user_number(v));
            Err(self.error(field, format!("must be in {a}{lo}, {hi}{b}, got {v}")))
        }
    }

    /// A number > 0.
    pub fn positive(&self, field: &str, v: f32) -> Result<f32, Error> {
        let v = self.finite(field, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.error(field, format!("must be positive, got {}", user_number(v))))
        }
    }

    /// An integer > 0.
    pub fn positive_int(&self, field: &str, v: u32) -> Result<u32, Error> {
        if v > 0 {
            Ok(v)
        } else {
            Err(self.error(field, "must be at least 1"))
        }
    }

    /// A finite point or vector.
    pub fn vec3(&self, field: &str, a: [f32; 3]) -> Result<Vec3, Error> {
        for (i, &v) in a.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), v)?;
        }
        Ok(Vec3::from_array(a))
    }

    /// A non-zero vector, normalized.
    pub fn direction(&self, field: &str, a: [f32; 3]) -> Result<Vec3, Error> {
        self.vec3(field, a)?
            .try_normalize()
            .ok_or_else(|| self.error(field, "must be a non-zero vector"))
    }

    /// A colour with finite, non-negative channels.
    pub fn color(&self, field: &str, c: Color) -> Result<Rgb, Error> {
        for (i, &v) in c.0.iter().enumerate() {
            let v = self.finite(&format!("{field}[{i}]"), v)?;
            if v < 0.0 {
                return Err(self.error(
                    field,
                    format!("must not be negative, got {v} in channel {i}"),
                ));
            }
        }
        Ok(Rgb::from_array(c.0))
    }

    /// A reflectance or albedo: channels in [0, 1].
    pub fn albedo(&self, field: &str, c: Color) -> Result<Rgb, Error> {
        let rgb = self.color(field, c)?;
        if rgb.max_channel() > 1.0 {
            return Err(self.error(
                field,
                format!("must be at most 1 in every channel, got {:?}", c.0),
            ));
        }
        Ok(rgb)
    }
}

/// `v` as a user writes it: plain digits for everyday magnitudes (`180`,
/// `0.5`), exponent notation for tiny and huge ones (`1e-30`, not thirty zeros).
pub fn user_number(v: f32) -> String {
    let magnitude = v.abs();
    if magnitude == 0.0 || (1e-4..1e7).contains(&magnitude) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::user_number;

    #[test]
    fn numbers_read_as_written() {
        assert_eq!(user_number(180.0), "180");
        assert_eq!(user_number(0.5), "0.5");
        assert_eq!(user_number(0.0), "0");
        assert_eq!(user_number(1e-30), "1e-30");
        assert_eq!(user_number(1e18), "1e18");
        assert_eq!(user_number(-2e-9), "-2e-9");
    }
}
