//! The parameters of one Mitsuba plugin element: value tags (`<float>`,
//! `<rgb>`, `<transform>`, ...), nested plugins and `<ref>`s, each taken at
//! most once; whatever is left untaken is refused by [`Props::finish`].

use super::mechanics::Node;
use super::numbers::{number, numbers, triple};
use crate::error::Result;
use glam::{DMat4, DVec3};
use std::cell::Cell;
use std::collections::HashMap;

/// Elements that are plugins (objects), as opposed to values.
const PLUGIN_TAGS: [&str; 12] = [
    "bsdf",
    "medium",
    "phase",
    "texture",
    "volume",
    "emitter",
    "shape",
    "sensor",
    "film",
    "sampler",
    "rfilter",
    "integrator",
];

/// Value elements.
const VALUE_TAGS: [&str; 9] = [
    "float",
    "integer",
    "boolean",
    "string",
    "point",
    "vector",
    "rgb",
    "spectrum",
    "transform",
];

/// A nested plugin: the element (a `<ref>` resolved) and the name it was given.
#[derive(Clone, Copy)]
pub(crate) struct Obj<'a> {
    /// The plugin element.
    pub node: &'a Node,
    /// `name=` of the child or the `<ref>`.
    pub name: Option<&'a str>,
    /// Where it was written or referenced (for messages).
    pub at: &'a Node,
}

/// A colour parameter: a constant, or a texture plugin.
pub(crate) enum ColorParam<'a> {
    /// An RGB constant.
    Rgb([f64; 3]),
    /// A `<texture>` (or a reference to one).
    Texture(Obj<'a>),
}

/// The parameters of `owner`, each marked when taken.
pub(crate) struct Props<'a> {
    /// The plugin element.
    pub owner: &'a Node,
    values: Vec<(&'a Node, Cell<bool>)>,
    objects: Vec<(Obj<'a>, Cell<bool>)>,
}

impl<'a> Props<'a> {
    /// Sorts the children of `owner` into values and plugins, resolving `<ref>`s.
    pub fn new(owner: &'a Node, ids: &HashMap<String, &'a Node>) -> Result<Props<'a>> {
        let mut props = Props {
            owner,
            values: Vec::new(),
            objects: Vec::new(),
        };
        for child in &owner.children {
            let tag = child.tag.as_str();
            if VALUE_TAGS.contains(&tag) {
                child.required("name")?;
                props.values.push((child, Cell::new(false)));
            } else if tag == "ref" {
                let id = child.required("id")?;
                let target = ids.get(id).ok_or_else(|| {
                    child.error(format!("no element has id `{id}` (ids must be defined)"))
                })?;
                let obj = Obj {
                    node: target,
                    name: child.attr("name"),
                    at: child,
                };
                props.objects.push((obj, Cell::new(false)));
            } else if PLUGIN_TAGS.contains(&tag) {
                let obj = Obj {
                    node: child,
                    name: child.attr("name"),
                    at: child,
                };
                props.objects.push((obj, Cell::new(false)));
            } else {
                return Err(child.error(format!("unknown element inside {}", owner.what())));
            }
        }
        Ok(props)
    }

    /// The value element named `name`, marked as taken.
    fn take(&self, name: &str) -> Option<&'a Node> {
        let (node, used) = self
            .values
            .iter()
            .find(|(n, _)| n.attr("name") == Some(name))?;
        used.set(true);
        Some(node)
    }

    /// `<float name>` (an `<integer>` too).
    pub fn float(&self, name: &str) -> Result<Option<f64>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        match node.tag.as_str() {
            "float" | "integer" => number(node, node.required("value")?).map(Some),
            _ => Err(node.error("expected a <float>")),
        }
    }

    /// `<integer name>`.
    pub fn int(&self, name: &str) -> Result<Option<i64>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        let value = node.required("value")?;
        match node.tag.as_str() {
            "integer" => value
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| node.error(format!("`{value}` is not a whole number"))),
            _ => Err(node.error("expected an <integer>")),
        }
    }

    /// `<boolean name>`.
    pub fn bool(&self, name: &str) -> Result<Option<bool>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        match (node.tag.as_str(), node.required("value")?.trim()) {
            ("boolean", "true") => Ok(Some(true)),
            ("boolean", "false") => Ok(Some(false)),
            ("boolean", other) => Err(node.error(format!("`{other}` is not true or false"))),
            _ => Err(node.error("expected a <boolean>")),
        }
    }

    /// `<string name>`, with its element (for messages about the value).
    pub fn string(&self, name: &str) -> Result<Option<(&'a str, &'a Node)>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        match node.tag.as_str() {
            "string" => Ok(Some((node.required("value")?, node))),
            _ => Err(node.error("expected a <string>")),
        }
    }

    /// `<point name>` or `<vector name>`.
    pub fn point(&self, name: &str) -> Result<Option<DVec3>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        match node.tag.as_str() {
            "point" | "vector" => triple(node, 0.0).map(|v| Some(DVec3::from_array(v))),
            _ => Err(node.error("expected a <point> or <vector>")),
        }
    }

    /// `<transform name>`: its operations composed in order.
    pub fn transform(&self, name: &str) -> Result<Option<DMat4>> {
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        match node.tag.as_str() {
            "transform" => super::transform::compose(node).map(Some),
            _ => Err(node.error("expected a <transform>")),
        }
    }

    /// A colour: `<float>`, `<rgb>`, `<spectrum>` or a `<texture>` named `name`.
    pub fn color(&self, name: &str) -> Result<Option<ColorParam<'a>>> {
        if let Some(texture) = self.object("texture", Some(name)) {
            return Ok(Some(ColorParam::Texture(texture)));
        }
        let Some(node) = self.take(name) else {
            return Ok(None);
        };
        if node.tag == "spectrum" && node.attr("filename").is_some() {
            return Err(super::unsupported(
                node,
                "spectra read from files (give an <rgb> instead)",
            ));
        }
        let value = node.required("value")?;
        let rgb = match node.tag.as_str() {
            "float" | "integer" => [number(node, value)?; 3],
            "rgb" => rgb(node, value)?,
            "spectrum" => super::spectrum::to_rgb(node, value)?,
            _ => return Err(node.error("expected an <rgb>, <spectrum> or <float>")),
        };
        Ok(Some(ColorParam::Rgb(rgb)))
    }

    /// The element of value `name` if written (not marked as taken), for messages.
    pub fn node_of(&self, name: &str) -> Option<&'a Node> {
        self.values
            .iter()
            .find(|(n, _)| n.attr("name") == Some(name))
            .map(|(n, _)| *n)
    }

    /// The first nested plugin of kind `tag` (with `name`, if given), taken.
    pub fn object(&self, tag: &str, name: Option<&str>) -> Option<Obj<'a>> {
        let (obj, used) = self
            .objects
            .iter()
            .find(|(o, _)| o.node.tag == tag && (name.is_none() || o.name == name))?;
        used.set(true);
        Some(*obj)
    }

    /// Every nested plugin of kind `tag`, taken.
    pub fn objects(&self, tag: &str) -> Vec<Obj<'a>> {
        self.objects
            .iter()
            .filter(|(o, _)| o.node.tag == tag)
            .map(|(o, used)| {
                used.set(true);
                *o
            })
            .collect()
    }

    /// Refuses what no step took: a parameter brume does not import is never ignored.
    pub fn finish(self) -> Result<()> {
        let owner = self.owner.what();
        if let Some((node, _)) = self.values.iter().find(|(_, used)| !used.get()) {
            return Err(super::unsupported(
                node,
                &format!("this parameter of {owner}"),
            ));
        }
        if let Some((obj, _)) = self.objects.iter().find(|(_, used)| !used.get()) {
            return Err(super::unsupported(
                obj.at,
                &format!("{} inside {owner}", obj.node.what()),
            ));
        }
        Ok(())
    }
}

/// `<rgb value>`: three numbers, or one for grey.
fn rgb(node: &Node, text: &str) -> Result<[f64; 3]> {
    match numbers(node, text)?.as_slice() {
        [v] => Ok([*v; 3]),
        [r, g, b] => Ok([*r, *g, *b]),
        _ => Err(node.error(format!("`{text}` is not one or three numbers"))),
    }
}
