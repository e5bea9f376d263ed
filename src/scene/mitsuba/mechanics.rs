//! File mechanics of a Mitsuba 3 scene: reading the XML (roxmltree), `<default>`
//! and `$name` substitution, `<include>` (relative to the including file,
//! with a cycle and depth guard), `<path>` search folders and ids.
//!
//! The result is one owned tree of [`Node`]s, each remembering its file and
//! line, so that every later step can name what the user wrote.

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Largest XML file read, as for TOML scenes (meshes go in OBJ files).
pub(crate) const MAX_XML_BYTES: u64 = 16 << 20;

/// Deepest chain of `<include>`s followed (a guard against runaway nesting).
pub(crate) const MAX_INCLUDE_DEPTH: usize = 16;

/// One XML element after substitution, with where it was written.
#[derive(Clone, Debug)]
pub(crate) struct Node {
    /// Element name (`shape`, `float`, ...).
    pub tag: String,
    /// Attributes in document order, `$name`s substituted.
    pub attrs: Vec<(String, String)>,
    /// Child elements (includes spliced in, `<default>` and `<path>` removed).
    pub children: Vec<Node>,
    /// The file that holds the element.
    pub file: Rc<PathBuf>,
    /// Its line in that file (1-based).
    pub line: u32,
}

impl Node {
    /// The value of attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The element as the user wrote it, for messages: `<shape type="sphere">`.
    pub fn what(&self) -> String {
        let keys: String = ["type", "name", "id"]
            .iter()
            .filter_map(|k| self.attr(k).map(|v| format!(" {k}=\"{v}\"")))
            .collect();
        format!("<{}{keys}>", self.tag)
    }

    /// An error about this element.
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::Import {
            file: self.file.as_ref().clone(),
            line: self.line,
            element: self.what(),
            message: message.into(),
        }
    }

    /// Attribute `name`, or an error saying it is missing.
    pub fn required(&self, name: &str) -> Result<&str> {
        self.attr(name)
            .ok_or_else(|| self.error(format!("the attribute `{name}` is missing")))
    }
}

/// Reads a scene and everything it includes into one tree.
pub(crate) struct Loader {
    /// `<default>` values, the command line's first (they win).
    params: HashMap<String, String>,
    /// `<path>` folders, the latest first.
    search: Vec<PathBuf>,
    /// The include chain being read (canonical paths), for the cycle guard.
    chain: Vec<PathBuf>,
    /// Every XML file read.
    pub files: Vec<PathBuf>,
    /// The folder of the scene file itself: Mitsuba's file resolver searches
    /// it for every file, also for files named in included XML.
    scene_dir: PathBuf,
}

impl Loader {
    /// A loader whose `$name`s are first taken from `overrides` (`name=value`).
    pub fn new(overrides: Vec<(String, String)>) -> Loader {
        Loader {
            params: overrides.into_iter().collect(),
            search: Vec::new(),
            chain: Vec::new(),
            files: Vec::new(),
            scene_dir: PathBuf::from("."),
        }
    }

    /// The `<scene>` element of `path` with its includes spliced in.
    pub fn load(&mut self, path: &Path) -> Result<Node> {
        self.scene_dir = folder(path);
        self.read(path, None)
    }

    /// Parses `path` (reached from `from`, an `<include>`) into its `<scene>` node.
    fn read(&mut self, path: &Path, from: Option<&Node>) -> Result<Node> {
        let problem = |message: String| match from {
            Some(node) => node.error(format!("{}: {message}", path.display())),
            None => Error::Input {
                path: path.to_path_buf(),
                message,
            },
        };
        if let Some(p) = crate::error::input_file_problem(path, MAX_XML_BYTES) {
            return Err(problem(format!("cannot read scene file: {p}")));
        }
        let canonical = path.canonicalize().map_err(|e| problem(e.to_string()))?;
        if self.chain.contains(&canonical) {
            return Err(problem("includes itself (an include cycle)".into()));
        }
        if self.chain.len() >= MAX_INCLUDE_DEPTH {
            return Err(problem(format!(
                "includes nest deeper than {MAX_INCLUDE_DEPTH} files"
            )));
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| problem(format!("cannot read scene file: {e}")))?;
        let file = Rc::new(path.to_path_buf());
        let doc = roxmltree::Document::parse(&text).map_err(|e| {
            let pos = e.pos();
            Error::Import {
                file: path.to_path_buf(),
                line: pos.row,
                element: "XML".into(),
                message: xml_message(&e),
            }
        })?;
        self.files.push(path.to_path_buf());
        self.chain.push(canonical);
        let root = doc.root_element();
        let scene = self.element(root, &file, &doc)?;
        self.chain.pop();
        if scene.tag != "scene" {
            return Err(scene.error("the root element must be <scene version=\"3.0.0\">"));
        }
        check_version(&scene)?;
        Ok(scene)
    }

    /// Converts `el` and its children, in document order (a `<default>` applies below it).
    fn element(
        &mut self,
        el: roxmltree::Node,
        file: &Rc<PathBuf>,
        doc: &roxmltree::Document,
    ) -> Result<Node> {
        let line = doc.text_pos_at(el.range().start).row;
        let mut node = Node {
            tag: el.tag_name().name().to_string(),
            attrs: Vec::new(),
            children: Vec::new(),
            file: file.clone(),
            line,
        };
        for a in el.attributes() {
            let value = self.substitute(a.value(), &node)?;
            node.attrs.push((a.name().to_string(), value));
        }
        for child in el.children().filter(|c| c.is_element()) {
            let converted = self.element(child, file, doc)?;
            match converted.tag.as_str() {
                "default" => self.default(&converted)?,
                "path" => self.path(&converted)?,
                "include" => node.children.extend(self.include(&converted)?),
                _ => node.children.push(converted),
            }
        }
        Ok(node)
    }

    /// `$name` → its value; an undefined name is an error naming it.
    fn substitute(&self, value: &str, node: &Node) -> Result<String> {
        let mut out = String::with_capacity(value.len());
        let mut rest = value;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..len];
            let Some(v) = self.params.get(name).filter(|_| !name.is_empty()) else {
                return Err(node.error(format!(
                    "`${name}` is not defined: add <default name=\"{name}\" value=\"...\"/> \
                     before it, or give --set {name}=VALUE"
                )));
            };
            out.push_str(v);
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// `<default name value>`: defines `$name` unless the command line did.
    fn default(&mut self, node: &Node) -> Result<()> {
        let name = node.required("name")?.to_string();
        let value = node.required("value")?.to_string();
        self.params.entry(name).or_insert(value);
        Ok(())
    }

    /// `<path value>`: a folder searched first for files named later.
    fn path(&mut self, node: &Node) -> Result<()> {
        let value = Path::new(node.required("value")?);
        let dir = match value.is_absolute() {
            true => value.to_path_buf(),
            false => folder(&node.file).join(value),
        };
        if !dir.is_dir() {
            return Err(node.error(format!("{} is not a folder", dir.display())));
        }
        self.search.insert(0, dir);
        Ok(())
    }

    /// `<include filename>`: the children of the included file's `<scene>`.
    fn include(&mut self, node: &Node) -> Result<Vec<Node>> {
        let name = node.required("filename")?;
        let path = self.find(name, node, true)?;
        let scene = self.read(&path, Some(node))?;
        Ok(scene.children)
    }

    /// A file named in the scene: the `<path>` folders (latest first), then
    /// the folder of the file that names it, then the scene file's folder.
    pub fn find_file(&self, name: &str, node: &Node) -> Result<PathBuf> {
        self.find(name, node, false)
    }

    /// As [`Loader::find_file`]; an include (`includer_first`) looks in its
    /// own file's folder first, as Mitsuba's parser does. The file is
    /// returned absolute because brume resolves a relative path in the
    /// description against the scene's folder, which would add it twice.
    fn find(&self, name: &str, node: &Node, includer_first: bool) -> Result<PathBuf> {
        let written = Path::new(name);
        if written.is_absolute() {
            return Ok(written.to_path_buf());
        }
        let own = folder(&node.file);
        let mut folders: Vec<&Path> = self.search.iter().map(PathBuf::as_path).collect();
        folders.insert(if includer_first { 0 } else { folders.len() }, &own);
        folders.push(&self.scene_dir);
        folders.dedup();
        let candidates: Vec<PathBuf> = folders.iter().map(|d| d.join(written)).collect();
        match candidates.iter().find(|c| c.is_file()) {
            Some(found) => std::path::absolute(found)
                .map_err(|e| node.error(format!("{}: {e}", found.display()))),
            None => Err(node.error(format!(
                "file `{name}` not found (looked in {})",
                candidates
                    .iter()
                    .map(|c| c.parent().unwrap_or(Path::new(".")).display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))),
        }
    }
}

/// The folder of `file`, `.` for a bare name.
fn folder(file: &Path) -> PathBuf {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// roxmltree's message without its trailing position (the line is given apart).
fn xml_message(e: &roxmltree::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at ") {
        Some(i) => text[..i].to_string(),
        None => text,
    }
}

/// Mitsuba 2 and 3 share the parameter names brume reads; 0.x used others.
fn check_version(scene: &Node) -> Result<()> {
    let version = scene.required("version")?;
    let major = version.split('.').next().unwrap_or("");
    if major == "2" || major == "3" {
        return Ok(());
    }
    Err(scene.error(format!(
        "version {version}: brume reads Mitsuba 3 scenes (version 2.x or 3.x); \
         older scenes use other parameter names"
    )))
}

/// Every element with an `id`, by id; an id given twice is an error.
pub(crate) fn collect_ids<'a>(node: &'a Node, ids: &mut HashMap<String, &'a Node>) -> Result<()> {
    for child in &node.children {
        if child.tag != "ref" {
            if let Some(id) = child.attr("id") {
                if let Some(first) = ids.insert(id.to_string(), child) {
                    return Err(child.error(format!(
                        "id `{id}` is already used at {}:{}",
                        first.file.display(),
                        first.line
                    )));
                }
            }
        }
        collect_ids(child, ids)?;
    }
    Ok(())
}
