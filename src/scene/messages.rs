//! serde's messages about a scene file, put in the words of someone writing
//! TOML: `expected u32` becomes `expected a whole number from 0 to
//! 4294967295`, `invalid type: sequence` becomes `got an array`.
//!
//! serde forms its messages from fixed templates (`invalid type: {what was
//! found}, expected {what the visitor expects}`, `missing field`, ...) and
//! the visitors' `expecting` texts, which for the primitive types are the
//! Rust type names. The templates are rewritten as a whole and the type
//! names replaced; a visitor of this crate already says what it expects in
//! TOML terms (`a number or an array of three numbers [r, g, b]`) and is
//! kept as written.

use serde::de::{self, Deserializer, Visitor};

/// `message`, a serde error about a scene value, in the user's words.
pub(crate) fn user_words(message: &str) -> String {
    let message = message.trim().replace('\n', " ");
    if let Some(rest) = message.strip_prefix("invalid type: ") {
        return found_expected(rest);
    }
    if let Some(rest) = message.strip_prefix("invalid value: ") {
        return found_expected(rest);
    }
    if let Some(rest) = message.strip_prefix("invalid length ") {
        if let Some((n, expected)) = rest.split_once(", expected ") {
            let found = match n {
                "0" => "an empty array".to_string(),
                "1" => "1 value".to_string(),
                n => format!("{n} values"),
            };
            return format!("expected {}, got {found}", expected_words(expected));
        }
    }
    if let Some(rest) = message.strip_prefix("unknown field ") {
        return match rest.split_once(", ") {
            Some((key, "there are no fields")) => {
                format!("unknown key {key}: this table takes no other key")
            }
            Some((key, list)) => format!("unknown key {key}, {}", allowed(list)),
            None => format!("unknown key {rest}"),
        };
    }
    if let Some(rest) = message.strip_prefix("unknown variant ") {
        return match rest.split_once(", ") {
            Some((name, list)) => format!("unknown value {name}, {}", allowed(list)),
            None => format!("unknown value {rest}"),
        };
    }
    if let Some(key) = message.strip_prefix("missing field ") {
        return format!("missing key {key}");
    }
    if let Some(key) = message.strip_prefix("duplicate field ") {
        return format!("key {key} is given twice");
    }
    message
}

/// serde's list of allowed names (`expected one of `a`, `b``, `expected `a` or `b``).
fn allowed(list: &str) -> String {
    match list.strip_prefix("expected one of ") {
        Some(names) => format!("expected one of {names}"),
        None => list.to_string(),
    }
}

/// "{found}, expected {expected}" as "expected ..., got ...".
fn found_expected(rest: &str) -> String {
    // what was found may quote the user's text, so split at the last separator
    match rest.rsplit_once(", expected ") {
        Some((found, expected)) => format!(
            "expected {}, got {}",
            expected_words(expected),
            found_words(found)
        ),
        None => rest.to_string(),
    }
}

/// A visitor's `expecting` text in TOML terms.
fn expected_words(expected: &str) -> String {
    let whole = |lo: i128, hi: i128| format!("a whole number from {lo} to {hi}");
    match expected {
        "u8" => whole(0, u8::MAX.into()),
        "u16" => whole(0, u16::MAX.into()),
        "u32" => whole(0, u32::MAX.into()),
        "u64" => whole(0, u64::MAX.into()),
        "usize" => whole(0, usize::MAX as i128),
        "i8" => whole(i8::MIN.into(), i8::MAX.into()),
        "i16" => whole(i16::MIN.into(), i16::MAX.into()),
        "i32" => whole(i32::MIN.into(), i32::MAX.into()),
        "i64" => whole(i64::MIN.into(), i64::MAX.into()),
        "isize" => whole(isize::MIN as i128, isize::MAX as i128),
        "f32" | "f64" => "a number".into(),
        "a boolean" => "true or false".into(),
        "a string" | "a borrowed string" | "string only" | "a character" => {
            "a string in quotes".into()
        }
        "path string" => "a file path in quotes".into(),
        "a sequence" => "an array [...]".into(),
        "a map" | "map" => "a table { ... }".into(),
        other => {
            if let Some(n) = other
                .strip_prefix("an array of length ")
                .or_else(|| other.strip_prefix("a tuple of size "))
            {
                return format!("an array of {n} numbers");
            }
            if other.starts_with("struct ") {
                return "a table { ... }".into();
            }
            if other.starts_with("enum ") || other.starts_with("variant ") {
                return "a name in quotes".into();
            }
            other.to_string()
        }
    }
}

/// serde's `Unexpected` (what the file holds) in TOML terms.
fn found_words(found: &str) -> String {
    let quoted = |prefix: &str| {
        found
            .strip_prefix(prefix)
            .and_then(|s| s.strip_prefix('`'))
            .and_then(|s| s.strip_suffix('`'))
            .map(str::to_string)
    };
    if let Some(v) = quoted("integer ")
        .or_else(|| quoted("floating point "))
        .or_else(|| quoted("boolean "))
    {
        return v;
    }
    if let Some(s) = found.strip_prefix("string ") {
        return format!("the string {s}");
    }
    match found {
        "sequence" => "an array".into(),
        "map" => "a table".into(),
        "unit value" | "unit" | "Option value" => "nothing".into(),
        "unit variant" | "newtype variant" | "tuple variant" | "struct variant" | "enum" => {
            "a value of another kind".into()
        }
        other => other.to_string(),
    }
}

/// One of `names` written as a string, for enums of plain names: serde's
/// derived visitor answers a number with `expected string only`, without the
/// names.
pub(crate) fn one_of<'de, D: Deserializer<'de>>(
    d: D,
    names: &'static [&'static str],
) -> Result<usize, D::Error> {
    struct Names(&'static [&'static str]);
    impl Visitor<'_> for Names {
        type Value = usize;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            let list: Vec<String> = self.0.iter().map(|n| format!("\"{n}\"")).collect();
            write!(f, "one of {}", list.join(", "))
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<usize, E> {
            self.0
                .iter()
                .position(|n| *n == v)
                .ok_or_else(|| E::unknown_variant(v, self.0))
        }
    }
    d.deserialize_str(Names(names))
}

#[cfg(test)]
mod tests {
    use super::user_words;

    #[test]
    fn serde_templates_become_toml_words() {
        for (serde, user) in [
            (
                "invalid value: integer `-1`, expected u32",
                "expected a whole number from 0 to 4294967295, got -1",
            ),
            (
                "invalid type: floating point `1000.0`, expected i64",
                "expected a whole number from -9223372036854775808 to 9223372036854775807, got 1000.0",
            ),
            (
                "invalid type: string \"a, expected b\", expected f32",
                "expected a number, got the string \"a, expected b\"",
            ),
            (
                "invalid type: integer `3`, expected a sequence",
                "expected an array [...], got 3",
            ),
            (
                "invalid length 2, expected an array of length 3",
                "expected an array of 3 numbers, got 2 values",
            ),
            (
                "invalid type: map, expected a boolean",
                "expected true or false, got a table",
            ),
            (
                "unknown field `g`, there are no fields",
                "unknown key `g`: this table takes no other key",
            ),
            (
                "unknown field `zz`, expected `position` or `intensity`",
                "unknown key `zz`, expected `position` or `intensity`",
            ),
            (
                "unknown variant `laser`, expected one of `point`, `sun`",
                "unknown value `laser`, expected one of `point`, `sun`",
            ),
            ("missing field `position`", "missing key `position`"),
            (
                "invalid type: integer `3`, expected path string",
                "expected a file path in quotes, got 3",
            ),
            (
                "invalid type: integer `3`, expected struct KeyframeDesc",
                "expected a table { ... }, got 3",
            ),
        ] {
            assert_eq!(user_words(serde), user, "from {serde}");
        }
    }
}
