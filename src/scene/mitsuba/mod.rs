//! Mitsuba 3 XML scenes: `brume render scene.xml` reads a subset of
//! Mitsuba's format into brume's own [`SceneDesc`], so validation, building
//! and rendering are those of TOML scenes. Anything outside the subset is
//! refused with `FILE:LINE: <element>: ...` (see [`unsupported`]); nothing is
//! approximated silently. The supported subset is the table in README.md.

mod bsdf;
mod conductors;
mod emitter;
mod mechanics;
mod medium;
mod numbers;
mod sensor;
mod shape;
mod spectrum;
mod texture;
mod transform;
mod values;

use crate::error::{Error, Result};
use crate::scene::description::{FilmDesc, LightDesc, SceneDesc, ShapeDesc};
use mechanics::{Loader, Node};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use values::Props;

/// Whether `path` names a Mitsuba scene (by its `.xml` extension).
pub fn is_mitsuba(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// An imported scene: brume's description and where each part was written.
pub struct Imported {
    /// The scene as if written in TOML.
    pub desc: SceneDesc,
    /// Every XML file read (the scene and its includes).
    pub files: Vec<PathBuf>,
    /// Differences from Mitsuba that are valid but worth knowing.
    pub warnings: Vec<String>,
    /// What each element became, one line each, for `brume info`.
    pub summary: Vec<String>,
    origins: Vec<(String, Origin)>,
}

/// Where a part of the description came from.
#[derive(Clone)]
struct Origin {
    file: PathBuf,
    line: u32,
    element: String,
}

impl Imported {
    /// Names the XML element behind an error of the built description
    /// (`shape[2].radius` → the `<shape>` and its line), keeping brume's key.
    pub fn locate(&self, e: Error) -> Error {
        let Error::Scene { field, message, .. } = &e else {
            return e;
        };
        let found = self.origins.iter().find(|(prefix, _)| {
            field == prefix
                || field.starts_with(&format!("{prefix}."))
                || field.starts_with(&format!("{prefix}["))
        });
        match found {
            Some((_, o)) => Error::Import {
                file: o.file.clone(),
                line: o.line,
                element: o.element.clone(),
                message: format!("{message} (brume's `{field}`)"),
            },
            None => e,
        }
    }
}

/// Where each part of the description came from, and the summary lines.
#[derive(Default)]
struct Trace {
    origins: Vec<(String, Origin)>,
    summary: Vec<String>,
}

impl Trace {
    /// Records that `field` of the description was read from `node` (and says so in the summary).
    fn origin(&mut self, field: &str, node: &Node, summarize: bool) {
        if summarize {
            let line = format!("line {}: {} → {field}", node.line, node.what());
            self.summary.push(line);
        }
        let origin = Origin {
            file: node.file.as_ref().clone(),
            line: node.line,
            element: node.what(),
        };
        self.origins.push((field.to_string(), origin));
    }
}

/// What the element-readers share: the ids, the file finder and the warnings.
pub(crate) struct Ctx<'a> {
    ids: HashMap<String, &'a Node>,
    loader: &'a Loader,
    warnings: RefCell<Vec<String>>,
}

impl<'a> Ctx<'a> {
    /// The parameters of `node`.
    fn props(&self, node: &'a Node) -> Result<Props<'a>> {
        Props::new(node, &self.ids)
    }

    /// A file named in `node`, found as Mitsuba finds it.
    fn file(&self, name: &str, node: &Node) -> Result<PathBuf> {
        self.loader.find_file(name, node)
    }

    /// Records a difference from Mitsuba about `node`.
    fn warn(&self, node: &Node, message: impl Into<String>) {
        self.warnings.borrow_mut().push(format!(
            "{}:{}: {}: {}",
            node.file.display(),
            node.line,
            node.what(),
            message.into()
        ));
    }
}

/// The one refusal of what brume cannot represent, so the subset can be widened in one place.
pub(crate) fn unsupported(node: &Node, what: &str) -> Error {
    node.error(format!(
        "not supported by brume's Mitsuba importer: {what} (see README.md, \"Mitsuba 3 scenes\")"
    ))
}

/// Reads the Mitsuba scene in `path`; `overrides` are `name=value` pairs
/// that win over its `<default>`s.
pub fn import(path: &Path, overrides: Vec<(String, String)>) -> Result<Imported> {
    let mut loader = Loader::new(overrides);
    let root = loader.load(path)?;
    let mut ids = HashMap::new();
    mechanics::collect_ids(&root, &mut ids)?;
    let ctx = Ctx {
        ids,
        loader: &loader,
        warnings: RefCell::new(Vec::new()),
    };
    let mut scene = Builder::default();
    for child in &root.children {
        scene.element(&ctx, child)?;
    }
    let mut imported = scene.finish(&ctx, &root)?;
    imported.files = loader.files.clone();
    imported.warnings = ctx.warnings.take();
    Ok(imported)
}

/// The parts of the description as the scene's elements are read.
#[derive(Default)]
struct Builder<'a> {
    integrator: Option<&'a Node>,
    sensor: Option<sensor::Sensor<'a>>,
    lights: Vec<(LightDesc, &'a Node)>,
    shapes: Vec<shape::Imported<'a>>,
}

impl<'a> Builder<'a> {
    /// One child of `<scene>`.
    fn element(&mut self, ctx: &Ctx<'a>, node: &'a Node) -> Result<()> {
        match node.tag.as_str() {
            "integrator" if self.integrator.is_some() => {
                Err(node.error("a second <integrator>: give one"))
            }
            "integrator" => {
                self.integrator = Some(node);
                Ok(())
            }
            "sensor" if self.sensor.is_some() => Err(unsupported(node, "a second <sensor>")),
            "sensor" => {
                self.sensor = Some(sensor::read(ctx, node)?);
                Ok(())
            }
            "emitter" => {
                self.lights.push((emitter::read(ctx, node)?, node));
                Ok(())
            }
            "shape" => {
                self.shapes.push(shape::read(ctx, node)?);
                Ok(())
            }
            "bsdf" | "medium" | "texture" | "phase" | "volume" | "spectrum" | "rgb"
                if node.attr("id").is_some() =>
            {
                Ok(()) // a declaration, read where a <ref> uses it
            }
            "bsdf" | "medium" | "texture" | "phase" | "volume" => Err(node.error(
                "declared in <scene> without an id: give it id=\"...\" and <ref> it where it is used",
            )),
            _ => Err(unsupported(node, "this element at the top of <scene>")),
        }
    }

    /// The description, once every element is read.
    fn finish(self, ctx: &Ctx<'a>, root: &'a Node) -> Result<Imported> {
        let sensor = self
            .sensor
            .ok_or_else(|| root.error("the scene has no <sensor> (brume needs a camera)"))?;
        let mut trace = Trace::default();
        let (mut integrator, direct) = sensor::integrator(ctx, self.integrator)?;
        sensor.settings(&mut integrator);
        trace.summary.push(sensor.summary(&integrator));
        trace.origin("camera", sensor.node, false);
        trace.origin("integrator", self.integrator.unwrap_or(sensor.node), false);
        let media = medium::place(ctx, &self.shapes, sensor.medium, sensor.camera.position)?;
        if let Some(direct) = direct.filter(|_| !media.media.is_empty()) {
            return Err(unsupported(
                direct,
                "the direct integrator in a scene with media (Mitsuba's direct does not trace them: use volpath)",
            ));
        }
        let mut shapes: Vec<ShapeDesc> = Vec::new();
        for ((i, s), interior) in self.shapes.into_iter().enumerate().zip(media.interiors) {
            trace.origin(&format!("shape[{i}]"), s.node, true);
            shapes.push(ShapeDesc { interior, ..s.desc });
        }
        let mut lights = Vec::new();
        for (i, (light, node)) in self.lights.into_iter().enumerate() {
            trace.origin(&format!("light[{i}]"), node, true);
            lights.push(light);
        }
        for (i, (_, node)) in media.media.iter().enumerate() {
            trace.origin(&format!("medium[{i}]"), node, true);
        }
        let Trace { origins, summary } = trace;
        let desc = SceneDesc {
            camera: sensor.camera,
            integrator,
            lights,
            shapes,
            media: media.media.into_iter().map(|(m, _)| m).collect(),
            media_key: "medium",
            animation: Default::default(),
            film: FilmDesc::default(),
            slab: None,
            interfaces: media.interfaces,
        };
        Ok(Imported {
            desc,
            files: Vec::new(),
            warnings: Vec::new(),
            summary,
            origins,
        })
    }
}
