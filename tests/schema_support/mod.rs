//! The scene schema crawled through the parser: an unknown key in a table
//! is answered with the list of keys the table takes, an unknown `type`
//! with the list of types, so from the top level every table, tagged table
//! and list of tables is found. Used by `scene_schema_messages.rs` (wrong
//! types) and `scene_file_keys.rs` (file-valued keys).
#![allow(dead_code)]

use brume::error::Error;
use std::collections::BTreeSet;
use std::path::Path;
use toml::{Table, Value};

/// A key the crawl probes with; no table takes it.
pub const PROBE: &str = "zz_probe";

/// One step from a table into a child table: `key = { type = tag, ... }`,
/// or `key = [{ type = tag, ... }]` when `list`.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub key: String,
    pub list: bool,
    pub tag: Option<String>,
}

/// The dotted path the error messages use for the table at `steps`.
fn field_of(steps: &[Step]) -> String {
    let parts: Vec<String> = steps
        .iter()
        .map(|s| format!("{}{}", s.key, if s.list { "[0]" } else { "" }))
        .collect();
    parts.join(".")
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// A scene with `leaf = value` in the table at `steps` (the camera's required keys given).
pub fn scene_with(steps: &[Step], leaf: &str, value: Value) -> String {
    let mut root: Table =
        toml::from_str("[camera]\nposition = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n")
            .unwrap();
    let mut table = &mut root;
    for step in steps {
        let mut inner = Table::new();
        if let Some(tag) = &step.tag {
            inner.insert("type".into(), Value::String(tag.clone()));
        }
        let fresh = match step.list {
            true => Value::Array(vec![Value::Table(inner)]),
            false => Value::Table(inner),
        };
        let entry = table.entry(step.key.clone()).or_insert(fresh);
        table = match entry {
            Value::Array(items) => items[0].as_table_mut().unwrap(),
            Value::Table(t) => t,
            other => panic!("{other:?} is not a table"),
        };
    }
    table.insert(leaf.into(), value);
    toml::to_string(&root).unwrap()
}

/// The (field, message) of the parse error of `text`, or `None` when it parses.
pub fn parse_error(text: &str) -> Option<(String, String)> {
    match brume::scene::parse(text, Path::new("s.toml")) {
        Ok(_) => None,
        Err(Error::Scene { field, message, .. }) => Some((field, message)),
        Err(other) => panic!("not a scene error: {other}\n{text}"),
    }
}

/// Words of serde and Rust that mean nothing to someone writing TOML.
const RUST_WORDS: &[&str] = &[
    "u8",
    "u16",
    "u32",
    "u64",
    "u128",
    "usize",
    "i8",
    "i16",
    "i32",
    "i64",
    "i128",
    "isize",
    "f32",
    "f64",
    "sequence",
    "map",
    "struct",
    "enum",
    "variant",
    "variants",
    "untagged",
    "newtype",
    "unit",
    "option",
    "borrowed",
    "field",
    "fields",
    "invalid",
    "floating",
    "deserialize",
    "serde",
];

/// The Rust-isms in `message`: words of [`RUST_WORDS`] and CamelCase type names.
pub fn rust_isms(message: &str) -> Vec<String> {
    message
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '$'))
        .filter(|w| {
            let lower = w.to_ascii_lowercase();
            let camel = w.len() > 2
                && w.starts_with(|c: char| c.is_ascii_uppercase())
                && w[1..].contains(|c: char| c.is_ascii_uppercase())
                && w.contains(|c: char| c.is_ascii_lowercase());
            RUST_WORDS.contains(&lower.as_str()) || camel || w.starts_with('$')
        })
        .map(str::to_string)
        .collect()
}

/// Fails with the message when it holds Rust-isms.
pub fn assert_user_words(field: &str, message: &str, text: &str) {
    let bad = rust_isms(message);
    assert!(
        bad.is_empty(),
        "{field}: {message}\n  uses {bad:?}, which are not the user's words; scene:\n{text}"
    );
}

/// The names between backticks in `message` after its first one (serde's
/// "unknown key `x`, expected one of `a`, `b`" lists).
pub fn listed_names(message: &str) -> Vec<String> {
    let names: Vec<String> = message
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    names.into_iter().skip(1).collect()
}

/// What the crawl learnt about the table at some steps.
enum Shape {
    /// A table with these keys.
    Table(Vec<String>),
    /// A table with a `type` chosen among these.
    Tagged(Vec<String>),
}

/// What kind of table `steps` leads to, if it leads to a table at all.
fn probe(steps: &[Step]) -> Option<Shape> {
    let (last, parent) = steps.split_last().unwrap();
    let probe_table = |tag: Option<&str>| {
        let mut t = Table::new();
        match tag {
            Some(tag) => t.insert("type".into(), Value::String(tag.into())),
            None => t.insert(PROBE.into(), Value::Integer(1)),
        };
        if let (None, Some(own)) = (tag, &last.tag) {
            t.insert("type".into(), Value::String(own.clone()));
        }
        if last.list {
            Value::Array(vec![Value::Table(t)])
        } else {
            Value::Table(t)
        }
    };
    let (field, message) = parse_error(&scene_with(parent, &last.key, probe_table(None)))?;
    assert_user_words(&field, &message, "(probe)");
    if message.contains(&format!("`{PROBE}`")) {
        return Some(Shape::Table(listed_names(&message)));
    }
    if message.contains("missing key `type`") {
        let (field, message) =
            parse_error(&scene_with(parent, &last.key, probe_table(Some(PROBE))))?;
        assert_user_words(&field, &message, "(probe)");
        assert!(message.contains(PROBE), "{field}: {message}");
        return Some(Shape::Tagged(listed_names(&message)));
    }
    None
}

/// Values of every TOML type, each wrong for most keys.
pub fn wrong_values() -> Vec<Value> {
    let mut table = Table::new();
    table.insert("x".into(), Value::Integer(1));
    vec![
        Value::String("some text".into()),
        Value::Boolean(true),
        Value::Float(1.5),
        Value::Integer(-1),
        Value::Integer(i64::MAX),
        Value::Array(vec![]),
        Value::Array(vec![Value::Integer(1), Value::Integer(2)]),
        Value::Array(vec![Value::String("a".into())]),
        Value::Array(vec![Value::Array(vec![Value::Integer(1)])]),
        Value::Table(table),
        Value::Datetime("1979-05-27".parse().unwrap()),
    ]
}

/// The crawl's findings: every leaf key (dotted path) and how it answered.
#[derive(Default)]
pub struct Crawl {
    /// Every leaf key, as a dotted path (`shape[0].material.albedo.file`).
    pub leaves: BTreeSet<String>,
    /// How many tables were swept.
    pub tables: usize,
    /// Every leaf key with the steps to its table (tags included).
    pub leaf_steps: Vec<(Vec<Step>, String)>,
}

impl Crawl {
    /// Sweeps the keys of the table at `steps`, recursing into child tables.
    fn table(&mut self, steps: &[Step], keys: &[String]) {
        self.tables += 1;
        for key in keys {
            for list in [false, true] {
                let mut child = steps.to_vec();
                child.push(Step {
                    key: key.clone(),
                    list,
                    tag: None,
                });
                match probe(&child) {
                    Some(Shape::Table(keys)) => self.table(&child, &keys),
                    Some(Shape::Tagged(tags)) => {
                        for tag in tags {
                            let mut tagged = child.clone();
                            tagged.last_mut().unwrap().tag = Some(tag);
                            let Some(Shape::Table(keys)) = probe(&tagged) else {
                                panic!("{}: type {:?} has no keys", field_of(&tagged), tagged);
                            };
                            self.table(&tagged, &keys);
                        }
                    }
                    None if list => self.leaf(steps, key),
                    None => continue,
                }
                break;
            }
        }
    }

    /// Gives `key` every wrong value: each refusal must be in the user's words and name the key.
    fn leaf(&mut self, steps: &[Step], key: &str) {
        let field = join(&field_of(steps), key);
        let mut refused = 0;
        for value in wrong_values() {
            let text = scene_with(steps, key, value.clone());
            let Some((got_field, message)) = parse_error(&text) else {
                continue;
            };
            if !got_field.starts_with(&field) {
                // accepted: the parse went on to a key the probe scene leaves out
                assert!(
                    message.starts_with("missing key"),
                    "{value} for {field} is reported under {got_field}: {message}"
                );
                continue;
            }
            refused += 1;
            assert_user_words(&got_field, &message, &text);
            assert!(
                message.contains("expected") || message.contains("must"),
                "{got_field}: {message} does not say what to write"
            );
        }
        assert!(refused > 0, "{field} accepted every wrong value");
        self.leaves.insert(field);
        self.leaf_steps.push((steps.to_vec(), key.to_string()));
    }
}

/// Crawls the whole schema from the top level, sweeping every leaf with wrong values.
pub fn crawl() -> Crawl {
    let (field, message) = parse_error(&scene_with(&[], PROBE, Value::Integer(1))).unwrap();
    assert_user_words(&field, &message, "(top)");
    let top = listed_names(&message);
    assert!(top.contains(&"camera".to_string()), "{message}");
    let mut crawl = Crawl::default();
    crawl.table(&[], &top);
    crawl
}
