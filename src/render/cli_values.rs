//! Command-line values as bounded types: every flag's text is parsed by one
//! of these (as a clap value parser) before any work starts, so a bad value
//! is one line naming the flag, in the user's words, with exit code 2.
//!
//! The bounds are what brume can honour without overflow: durations that
//! `Instant` arithmetic can hold, frame lists of at most a million frames
//! whose numbers fit in 64 bits, exposures whose scale 2^stops is a normal
//! f32. Bounds that depend on the scene (a crop inside the image, a sample
//! range within its spp) are checked once the scene is loaded.

use crate::film::{Rect, SampleRange};
use crate::integrator::aov::Aov;
use std::time::Duration;

/// What a value parser returns: the value, or what was expected.
pub type Parsed<T> = Result<T, String>;

/// Largest accepted duration (`--time`, `--checkpoint`): a billion seconds,
/// about 31 years, far below what `Instant` can add.
pub const MAX_SECONDS: u64 = 1_000_000_000;

/// Largest accepted `--threads`: spawning a huge pool takes minutes and no machine needs it.
pub const MAX_THREADS: u64 = 1024;

/// `--set KEY=VALUE`: a scene key path and a TOML value (see [`crate::scene::Override`]).
pub fn set(text: &str) -> Parsed<crate::scene::Override> {
    text.parse()
}

/// `--threads N`: from 1 to [`MAX_THREADS`].
pub fn threads(text: &str) -> Parsed<usize> {
    whole(1, MAX_THREADS)(text).map(|n| n as usize)
}

/// Largest `--exposure` in stops either way: 2^64 is far beyond any use and
/// keeps the scale a normal f32.
pub const MAX_EXPOSURE: f32 = 64.0;

/// A whole number from `min` to `max` (ASCII digits, an optional sign).
pub fn whole<T>(min: T, max: T) -> impl Fn(&str) -> Parsed<T> + Clone + Send + Sync + 'static
where
    T: TryFrom<i128> + Into<i128> + Copy + std::fmt::Display + Send + Sync + 'static,
{
    move |text| {
        let expected = || format!("expected a whole number from {min} to {max}");
        let value = whole_i128(text).ok_or_else(expected)?;
        if value < min.into() || value > max.into() {
            return Err(expected());
        }
        T::try_from(value).map_err(|_| expected())
    }
}

/// `text` as a whole number, if it is one that fits in 128 bits.
fn whole_i128(text: &str) -> Option<i128> {
    let t = text.trim();
    let digits = t.strip_prefix(['-', '+']).unwrap_or(t);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    t.parse().ok()
}

/// A number of seconds above 0 and at most [`MAX_SECONDS`] (`--time`, `--checkpoint`);
/// below a nanosecond it rounds to zero, which both flags take as "after every pass".
pub fn seconds(text: &str) -> Parsed<Duration> {
    let expected = || {
        format!("expected a number of seconds above 0 and at most {MAX_SECONDS} (about 31 years)")
    };
    let value = number(text).ok_or_else(expected)?;
    if !(value > 0.0 && value <= MAX_SECONDS as f64) {
        return Err(expected());
    }
    Duration::try_from_secs_f64(value).map_err(|_| expected())
}

/// `text` as a finite decimal number (`1.5`, `-2`, `1e3`; not `inf` or `nan`).
fn number(text: &str) -> Option<f64> {
    let t = text.trim();
    // Rust also reads `inf`, `nan` and `infinity`: refuse them as words, not numbers.
    if t.bytes()
        .any(|b| b.is_ascii_alphabetic() && b != b'e' && b != b'E')
    {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// A finite number from `min` to `max`, in `unit` (e.g. "stops", "metres").
pub fn decimal(
    min: f64,
    max: f64,
    unit: &'static str,
) -> impl Fn(&str) -> Parsed<f64> + Clone + Send + Sync + 'static {
    move |text| {
        let expected = || format!("expected a number of {unit} from {min} to {max}");
        let value = number(text).ok_or_else(expected)?;
        if value < min || value > max {
            return Err(expected());
        }
        Ok(value)
    }
}

/// `compare --max-rmse X`: a finite number at or above 0.
pub fn rmse(text: &str) -> Parsed<f64> {
    let expected = || "expected a number at or above 0, e.g. 0.01".to_string();
    number(text).filter(|v| *v >= 0.0).ok_or_else(expected)
}

/// `--exposure STOPS`: from -[`MAX_EXPOSURE`] to [`MAX_EXPOSURE`].
pub fn exposure(text: &str) -> Parsed<f32> {
    let max = MAX_EXPOSURE as f64;
    decimal(-max, max, "stops")(text).map(|v| v as f32)
}

/// `--noise TARGET`: a relative error above 0 and below 1 (e.g. 0.02).
pub fn noise(text: &str) -> Parsed<f32> {
    let expected = || {
        format!(
            "expected a relative error above 0 and below {} (e.g. 0.02 for 2 %)",
            crate::render::adaptive::MAX_NOISE
        )
    };
    let value = number(text).ok_or_else(expected)?;
    if !(value > 0.0 && value < crate::render::adaptive::MAX_NOISE as f64) {
        return Err(expected());
    }
    Ok(value as f32)
}

/// `--adaptive on|off`.
pub fn on_off(text: &str) -> Parsed<bool> {
    match text.trim() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err("expected on or off".into()),
    }
}

/// The frames of `--frames`, in the order written (one value: clap takes a `Vec` field for many).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frames(pub Vec<i64>);

/// `--frames LIST`: at most [`MAX_FRAMES`](crate::scene::animation::MAX_FRAMES)
/// frames (see [`crate::scene::animation::parse_frames`]).
pub fn frames(text: &str) -> Parsed<Frames> {
    crate::scene::animation::parse_frames(text).map(Frames)
}

/// `--crop X0,X1,Y0,Y1`: pixel bounds with x0 < x1 and y0 < y1 (the image's size is checked later).
pub fn crop(text: &str) -> Parsed<Rect> {
    let expected = || {
        "expected X0,X1,Y0,Y1: four whole numbers with X0 < X1 and Y0 < Y1 \
         (pixel bounds, X1 and Y1 excluded), e.g. 0,64,0,32"
            .to_string()
    };
    let values: Vec<u32> = text
        .split(',')
        .map(|v| whole(0u32, u32::MAX)(v).map_err(|_| expected()))
        .collect::<Parsed<_>>()?;
    let [x0, x1, y0, y1] = values[..] else {
        return Err(expected());
    };
    if x0 >= x1 || y0 >= y1 {
        return Err(expected());
    }
    Ok(Rect { x0, x1, y0, y1 })
}

/// `--samples START..END`: sample indices with START < END (the spp is checked later).
pub fn samples(text: &str) -> Parsed<SampleRange> {
    let expected =
        || "expected START..END: two whole numbers with START < END, e.g. 0..16".to_string();
    let (a, b) = text.split_once("..").ok_or_else(expected)?;
    let index = whole(0u32, u32::MAX);
    let (start, end) = (
        index(a).map_err(|_| expected())?,
        index(b).map_err(|_| expected())?,
    );
    if start >= end {
        return Err(expected());
    }
    Ok(SampleRange::new(start, end))
}

/// The AOVs of `--aovs`, each once, in the order written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Aovs(pub Vec<Aov>);

/// `--aovs LIST`: known AOV names, comma-separated, each kept once; `none` for none.
pub fn aovs(text: &str) -> Parsed<Aovs> {
    let mut aovs = Vec::new();
    if text.trim() == "none" {
        return Ok(Aovs(aovs));
    }
    for name in text.split(',').map(str::trim) {
        let aov = Aov::from_name(name).ok_or_else(|| {
            let known: Vec<_> = Aov::ALL.iter().map(|a| a.name()).collect();
            format!(
                "unknown AOV `{name}`, expected none or a list of {}",
                known.join(", ")
            )
        })?;
        if !aovs.contains(&aov) {
            aovs.push(aov);
        }
    }
    Ok(Aovs(aovs))
}

/// `--debug-pixel X,Y`: a column and a row (whether it lies in the image is checked later).
pub fn pixel(text: &str) -> Parsed<(u32, u32)> {
    let expected = || "expected X,Y: a column and a row, e.g. 120,64".to_string();
    let (x, y) = text.split_once(',').ok_or_else(expected)?;
    let coordinate = whole(0u32, u32::MAX);
    Ok((
        coordinate(x).map_err(|_| expected())?,
        coordinate(y).map_err(|_| expected())?,
    ))
}

/// `--display HOST:PORT`: a host name or address and a port from 1 to 65535
/// (the name is looked up when connecting).
pub fn host_port(text: &str) -> Parsed<String> {
    let expected = || {
        "expected HOST:PORT with a port from 1 to 65535, e.g. 127.0.0.1:14158 \
         ([::1]:14158 for an IPv6 address)"
            .to_string()
    };
    let (host, port) = text.rsplit_once(':').ok_or_else(expected)?;
    whole(1u16, u16::MAX)(port).map_err(|_| expected())?;
    if host.is_empty() || host.chars().any(char::is_whitespace) {
        return Err(expected());
    }
    Ok(text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_keep_to_their_bounds() {
        let threads = whole(1u64, MAX_THREADS);
        assert_eq!(threads("4"), Ok(4));
        assert_eq!(threads(" 1024 "), Ok(1024));
        for bad in [
            "0",
            "1025",
            "-1",
            "1e3",
            "",
            "+",
            "four",
            "99999999999999999999999999999999999999999",
        ] {
            let err = threads(bad).unwrap_err();
            assert_eq!(err, "expected a whole number from 1 to 1024", "{bad}");
        }
        assert_eq!(whole(0u64, u64::MAX)("18446744073709551615"), Ok(u64::MAX));
        assert!(whole(0u64, u64::MAX)("18446744073709551616").is_err());
    }

    #[test]
    fn seconds_are_positive_finite_and_bounded() {
        assert_eq!(seconds("1.5"), Ok(Duration::from_millis(1500)));
        assert_eq!(seconds("1e9"), Ok(Duration::from_secs(MAX_SECONDS)));
        for bad in [
            "0", "-1", "1e20", "1e300", "nan", "inf", "infinity", "", "1s",
        ] {
            assert!(seconds(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn structured_values_parse_or_say_what_they_expect() {
        assert_eq!(
            crop("1,7,2,6"),
            Ok(Rect {
                x0: 1,
                x1: 7,
                y0: 2,
                y1: 6
            })
        );
        for bad in ["3,3,0,6", "0,1,0", "0,1,0,1,2", "a,b,c,d", "0,-1,0,1"] {
            assert!(
                crop(bad).unwrap_err().starts_with("expected X0,X1,Y0,Y1"),
                "{bad}"
            );
        }
        assert_eq!(samples("16..48"), Ok(SampleRange::new(16, 48)));
        for bad in ["8..4", "4..4", "0-4", "..4", "0..4294967296"] {
            assert!(samples(bad).is_err(), "{bad}");
        }
        assert_eq!(pixel("3,4"), Ok((3, 4)));
        assert!(pixel("3;4").is_err());
        assert_eq!(
            aovs("depth, alpha,depth"),
            Ok(Aovs(vec![Aov::Depth, Aov::Alpha]))
        );
        assert_eq!(aovs("none"), Ok(Aovs(vec![])));
        assert!(aovs("alpha,gloss").unwrap_err().contains("`gloss`"));
        assert!(host_port("localhost:14158").is_ok());
        assert!(host_port("[::1]:14158").is_ok());
        for bad in ["localhost", ":14158", "h:0", "h:65536", "h:x"] {
            assert!(host_port(bad).is_err(), "{bad}");
        }
        assert_eq!(exposure("-2.5"), Ok(-2.5));
        for bad in ["65", "-64.5", "inf", "nan", "1e40"] {
            assert!(exposure(bad).is_err(), "{bad}");
        }
    }
}
