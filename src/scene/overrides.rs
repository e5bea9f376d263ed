//! `--set KEY=VALUE`: scene values given on the command line, applied to the
//! parsed TOML before validation, so every error names the key as written.

use std::fmt;

/// One `--set KEY=VALUE`: a key path into the scene and a TOML value.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The key path as the user wrote it, e.g. `shape[2].material.albedo`.
    pub key: String,
    /// The steps of `key`: table keys and array indices.
    steps: Vec<Step>,
    /// The value, parsed as TOML (a bare word that is not TOML is a string).
    pub value: toml::Value,
}

/// One step of a key path.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    /// A key of a table.
    Key(String),
    /// An element of an array of tables (`shape[2]`).
    Index(usize),
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "--set {}={}", self.key, self.value)
    }
}

impl std::str::FromStr for Override {
    type Err = String;

    /// Parses `KEY=VALUE`; the value in TOML syntax (`64`, `[640, 360]`,
    /// `"bdpt"`, `{ type = "hg", g = 0.3 }`), or a bare word taken as a string.
    fn from_str(arg: &str) -> Result<Override, String> {
        let (key, text) = arg
            .split_once('=')
            .ok_or_else(|| format!("expected KEY=VALUE (e.g. integrator.spp=64), got `{arg}`"))?;
        let key = key.trim();
        let steps = parse_key(key)?;
        Ok(Override {
            key: key.to_string(),
            steps,
            value: parse_value(text.trim())?,
        })
    }
}

/// The steps of a key path: dot-separated keys, each optionally followed by `[N]`.
fn parse_key(key: &str) -> Result<Vec<Step>, String> {
    let bad = |why: &str| format!("key `{key}`: {why} (e.g. camera.fov or shape[0].radius)");
    if key.is_empty() {
        return Err(bad("empty"));
    }
    let mut steps = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        let plain = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if name.is_empty() || !name.chars().all(plain) {
            return Err(bad("each part must be a name of letters, digits, _ or -"));
        }
        steps.push(Step::Key(name.to_string()));
        while !rest.is_empty() {
            let close = rest.find(']').ok_or_else(|| bad("a [ without its ]"))?;
            let index = rest[1..close]
                .parse::<usize>()
                .map_err(|_| bad("an index must be a whole number, as in shape[2]"))?;
            steps.push(Step::Index(index));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return Err(bad("text after ]"));
            }
        }
    }
    Ok(steps)
}

/// A TOML value; a bare word (no quotes, not a number, boolean, array or
/// table) is taken as the string it spells, so `integrator.type=bdpt` works.
fn parse_value(text: &str) -> Result<toml::Value, String> {
    if text.is_empty() {
        return Err("the value after = is empty".into());
    }
    let doc = format!("v = {text}");
    match toml::from_str::<toml::Table>(&doc) {
        Ok(mut table) => Ok(table.remove("v").expect("the one key parsed")),
        Err(e) => {
            let bare = |c: char| c.is_ascii_alphanumeric() || "_-./".contains(c);
            if text.chars().all(bare) && text.starts_with(|c: char| c.is_ascii_alphabetic()) {
                Ok(toml::Value::String(text.to_string()))
            } else {
                Err(format!(
                    "value `{text}` is not TOML: {}",
                    e.message().trim().replace('\n', " ")
                ))
            }
        }
    }
}

/// Applies `overrides` in order to the scene's top table: each replaces the
/// value at its key, creating the tables on the way when they are missing.
/// Errors are `(key as written, message)`.
pub fn apply(table: &mut toml::Table, overrides: &[Override]) -> Result<(), (String, String)> {
    for o in overrides {
        set(table, o).map_err(|message| (o.key.clone(), format!("{message} (in {o})")))?;
    }
    Ok(())
}

/// `e` with the `--set` that wrote its field named, when one did (the last
/// such, as it is the one that took effect).
pub fn name_the_set(e: crate::error::Error, overrides: &[Override]) -> crate::error::Error {
    match e {
        crate::error::Error::Scene {
            file,
            field,
            message,
        } => {
            // The set wrote the field, a value inside it, or a table it became.
            let within = |inner: &str, outer: &str| {
                inner == outer
                    || inner
                        .strip_prefix(outer)
                        .is_some_and(|rest| rest.starts_with(['.', '[']))
            };
            let set_it = overrides
                .iter()
                .rev()
                .find(|o| within(&field, &o.key) || within(&o.key, &field));
            let message = match set_it {
                Some(o) if !message.contains("(in --set") => format!("{message} (in {o})"),
                _ => message,
            };
            crate::error::Error::Scene {
                file,
                field,
                message,
            }
        }
        other => other,
    }
}

/// One override: walks the steps, then replaces the last one's value.
fn set(top: &mut toml::Table, o: &Override) -> Result<(), String> {
    let mut here = TableOrArray::Table(top);
    let mut walked = String::new();
    for (i, step) in o.steps.iter().enumerate() {
        let last = i + 1 == o.steps.len();
        here = match (here, step) {
            (TableOrArray::Table(t), Step::Key(k)) => {
                if last {
                    t.insert(k.clone(), o.value.clone());
                    return Ok(());
                }
                let next_is_index = matches!(o.steps[i + 1], Step::Index(_));
                let entry = t
                    .entry(k.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                walked = join(&walked, k);
                descend(entry, next_is_index, &walked)?
            }
            (TableOrArray::Array(a), Step::Index(n)) => {
                let len = a.len();
                let element = a.get_mut(*n).ok_or_else(|| {
                    format!(
                        "{walked} has {len} entries (indices 0 to {}), no [{n}]",
                        len.saturating_sub(1)
                    )
                })?;
                walked = format!("{walked}[{n}]");
                if last {
                    *element = o.value.clone();
                    return Ok(());
                }
                match element {
                    toml::Value::Table(t) => TableOrArray::Table(t),
                    toml::Value::Array(a) => TableOrArray::Array(a),
                    other => return Err(format!("{walked} is {}, not a table", kind(other))),
                }
            }
            (TableOrArray::Table(_), Step::Index(n)) => {
                return Err(format!("{walked} is a table, it has no [{n}]"))
            }
            (TableOrArray::Array(_), Step::Key(k)) => {
                return Err(format!(
                    "{walked} is a list: name an entry, as in {walked}[0].{k}"
                ))
            }
        };
    }
    unreachable!("a key path has at least one step")
}

/// Steps into `entry` (at `walked`), which must be a list when the next step is an index, else a table.
fn descend<'a>(
    entry: &'a mut toml::Value,
    next_is_index: bool,
    walked: &str,
) -> Result<TableOrArray<'a>, String> {
    match (entry, next_is_index) {
        (toml::Value::Table(t), false) => Ok(TableOrArray::Table(t)),
        (toml::Value::Array(a), true) => Ok(TableOrArray::Array(a)),
        (other, _) => {
            let wanted = if next_is_index { "a list" } else { "a table" };
            Err(format!("{walked} is {}, not {wanted}", kind(other)))
        }
    }
}

/// Where a key path walk stands.
enum TableOrArray<'a> {
    Table(&'a mut toml::Table),
    Array(&'a mut Vec<toml::Value>),
}

/// `a.b` from `a` and `b` (just `b` at the top).
fn join(walked: &str, key: &str) -> String {
    if walked.is_empty() {
        key.to_string()
    } else {
        format!("{walked}.{key}")
    }
}

/// A TOML value's kind in words.
fn kind(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "a string",
        toml::Value::Integer(_) => "a whole number",
        toml::Value::Float(_) => "a number",
        toml::Value::Boolean(_) => "true or false",
        toml::Value::Datetime(_) => "a date",
        toml::Value::Array(_) => "a list",
        toml::Value::Table(_) => "a table",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> toml::Table {
        toml::from_str(
            "[camera]\nfov = 40.0\n[[shape]]\ntype = \"sphere\"\nradius = 1.0\n[[shape]]\ntype = \"quad\"\n",
        )
        .unwrap()
    }

    fn set_all(args: &[&str]) -> Result<toml::Table, (String, String)> {
        let mut t = scene();
        let overrides: Vec<Override> = args.iter().map(|a| a.parse().unwrap()).collect();
        apply(&mut t, &overrides).map(|()| t)
    }

    #[test]
    fn values_of_every_toml_type_replace_or_create_keys() {
        let t = set_all(&[
            "camera.fov=55",
            "camera.resolution=[640, 360]",
            "integrator.type=bdpt",
            "integrator.seed=7",
            "film.aovs=[\"depth\", \"normal\"]",
            "shape[1].material={ type = \"mirror\" }",
            "shape[0].radius=0.25",
            "integrator.equiangular=false",
        ])
        .unwrap();
        assert_eq!(t["camera"]["fov"].as_integer(), Some(55));
        assert_eq!(t["camera"]["resolution"].as_array().unwrap().len(), 2);
        assert_eq!(t["integrator"]["type"].as_str(), Some("bdpt"));
        assert_eq!(t["film"]["aovs"][1].as_str(), Some("normal"));
        assert_eq!(t["shape"][1]["material"]["type"].as_str(), Some("mirror"));
        assert_eq!(t["shape"][0]["radius"].as_float(), Some(0.25));
        assert_eq!(t["integrator"]["equiangular"].as_bool(), Some(false));
    }

    #[test]
    fn later_overrides_win() {
        let t = set_all(&["camera.fov=10", "camera.fov=20"]).unwrap();
        assert_eq!(t["camera"]["fov"].as_integer(), Some(20));
    }

    #[test]
    fn walks_that_cannot_be_made_name_the_key_as_written() {
        let (key, message) = set_all(&["shape[5].radius=1"]).unwrap_err();
        assert_eq!(key, "shape[5].radius");
        assert!(message.contains("shape has 2 entries"), "{message}");
        let (_, message) = set_all(&["camera.fov.x=1"]).unwrap_err();
        assert!(
            message.contains("camera.fov is a number, not a table"),
            "{message}"
        );
        let (_, message) = set_all(&["shape.radius=1"]).unwrap_err();
        assert!(message.contains("shape is a list"), "{message}");
        let (_, message) = set_all(&["camera[0]=1"]).unwrap_err();
        assert!(
            message.contains("camera is a table, not a list"),
            "{message}"
        );
    }

    #[test]
    fn bad_arguments_say_what_is_expected() {
        for (arg, words) in [
            ("integrator.spp", "expected KEY=VALUE"),
            ("=3", "empty"),
            ("a..b=1", "each part must be a name"),
            ("shape[x].radius=1", "whole number"),
            ("shape[1.radius=1", "without its ]"),
            ("camera.fov=", "empty"),
            ("camera.fov=[1,", "is not TOML"),
            ("camera.fov=4 0", "is not TOML"),
        ] {
            let e = arg.parse::<Override>().unwrap_err();
            assert!(e.contains(words), "{arg}: {e}");
        }
    }

    #[test]
    fn bare_words_are_strings_but_numbers_stay_numbers() {
        let o: Override = "integrator.type=bdpt".parse().unwrap();
        assert_eq!(o.value, toml::Value::String("bdpt".into()));
        let o: Override = "camera.fov=1e2".parse().unwrap();
        assert_eq!(o.value, toml::Value::Float(100.0));
        let o: Override = "integrator.equiangular=true".parse().unwrap();
        assert_eq!(o.value, toml::Value::Boolean(true));
    }
}
