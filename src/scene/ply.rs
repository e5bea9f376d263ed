//! Stanford PLY meshes (ASCII, binary little and big endian): vertex
//! positions, optional normals and texture coordinates, polygon faces
//! fan-triangulated. Every count in the header is checked against the bytes
//! that follow it and the memory limit before anything is allocated, so a
//! damaged file is one error line, never a panic or a huge allocation.

use crate::math::{Vec2, Vec3};

/// The mesh of a PLY file, in the file's own frame.
pub(crate) struct PlyMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (`nx ny nz`), if the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// Per-vertex texture coordinates (`u v`, `s t` or `texture_u texture_v`), if any.
    pub uvs: Option<Vec<Vec2>>,
    /// Triangles as vertex indices (checked in range).
    pub triangles: Vec<[u32; 3]>,
}

/// How the data after the header is written.
#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// The scalar types of PLY properties.
#[derive(Clone, Copy)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type named in a `property` line (both spellings of the standard).
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Bytes of one value in a binary file.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

/// One property of an element: a scalar, or a list with its count type.
struct Property {
    name: String,
    scalar: Scalar,
    list_count: Option<Scalar>,
}

/// One `element` of the header with its properties.
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

impl Element {
    /// The fewest bytes one record can take: each binary scalar (a list at
    /// least its count), or one digit and a separator per ASCII value.
    fn min_record_bytes(&self, encoding: Encoding) -> u64 {
        self.properties
            .iter()
            .map(|p| match encoding {
                Encoding::Ascii => 2,
                _ => p.list_count.unwrap_or(p.scalar).size() as u64,
            })
            .sum::<u64>()
            .max(1)
    }

    fn index(&self, name: &str) -> Option<usize> {
        self.properties.iter().position(|p| p.name == name)
    }
}

/// The parsed header: the encoding, the elements and where the data starts.
struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    data_start: usize,
}

/// Reads the header up to `end_header`.
fn header(bytes: &[u8]) -> Result<Header, String> {
    let end = find(bytes, b"end_header").ok_or("no `end_header` line: is it a PLY file?")?;
    let after = bytes[end..]
        .iter()
        .position(|&b| b == b'\n')
        .map(|i| end + i + 1)
        .ok_or("the header's last line has no line end")?;
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not text")?;
    let mut lines = text.lines().map(str::trim);
    if lines.next() != Some("ply") {
        return Err("does not start with `ply`".into());
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, _version] => {
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(format!("unknown format `{other}`")),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| format!("element {name}: bad count `{count}`"))?,
                properties: Vec::new(),
            }),
            ["property", rest @ ..] => {
                let element = elements.last_mut().ok_or("a property before any element")?;
                element.properties.push(property(rest, line)?);
            }
            _ => return Err(format!("header line `{line}` is not PLY")),
        }
    }
    let encoding = encoding.ok_or("the header has no `format` line")?;
    Ok(Header {
        encoding,
        elements,
        data_start: after,
    })
}

/// A `property` line's words after `property`.
fn property(words: &[&str], line: &str) -> Result<Property, String> {
    let bad = || format!("header line `{line}`: unknown property type");
    match words {
        ["list", count, item, name] => Ok(Property {
            name: name.to_string(),
            scalar: Scalar::parse(item).ok_or_else(bad)?,
            list_count: Some(Scalar::parse(count).ok_or_else(bad)?),
        }),
        [kind, name] => Ok(Property {
            name: name.to_string(),
            scalar: Scalar::parse(kind).ok_or_else(bad)?,
            list_count: None,
        }),
        _ => Err(format!("header line `{line}` is not a property")),
    }
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// Reads the values after the header, in order, as f64.
struct Values<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
}

impl Values<'_> {
    /// The next value, of type `scalar`.
    fn next(&mut self, scalar: Scalar) -> Result<f64, String> {
        if self.encoding == Encoding::Ascii {
            return self.next_word();
        }
        let n = scalar.size();
        let raw = self
            .bytes
            .get(self.at..self.at + n)
            .ok_or("the file ends inside its data (truncated?)")?;
        self.at += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.encoding == Encoding::Big {
            b[..n].reverse();
        }
        Ok(match scalar {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// The next whitespace-separated number of an ASCII file.
    fn next_word(&mut self) -> Result<f64, String> {
        let rest = &self.bytes[self.at..];
        let start = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .ok_or("the file ends inside its data (truncated?)")?;
        let len = rest[start..]
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len() - start);
        self.at += start + len;
        let word = std::str::from_utf8(&rest[start..start + len]).unwrap_or("?");
        word.parse()
            .map_err(|_| format!("`{word}` is not a number"))
    }
}

/// Which vertex properties hold what, by index.
struct VertexLayout {
    position: [usize; 3],
    normal: Option<[usize; 3]>,
    uv: Option<[usize; 2]>,
}

impl VertexLayout {
    fn of(e: &Element) -> Result<VertexLayout, String> {
        let three = |a, b, c| Some([e.index(a)?, e.index(b)?, e.index(c)?]);
        let position = three("x", "y", "z").ok_or("its vertices lack x, y or z")?;
        let uv = [("u", "v"), ("s", "t"), ("texture_u", "texture_v")]
            .iter()
            .find_map(|(u, v)| Some([e.index(u)?, e.index(v)?]));
        if e.properties.iter().any(|p| p.list_count.is_some()) {
            return Err("a list property in its vertices".into());
        }
        Ok(VertexLayout {
            position,
            normal: three("nx", "ny", "nz"),
            uv,
        })
    }
}

/// Parses a PLY file's bytes (messages without the file name: the caller adds it).
pub(crate) fn parse(bytes: &[u8]) -> Result<PlyMesh, String> {
    let header = header(bytes)?;
    // An ASCII file's last value needs no separator after it.
    let slack = u128::from(header.encoding == Encoding::Ascii);
    let mut remaining = (bytes.len() - header.data_start) as u128 + slack;
    for e in &header.elements {
        let least = e.count as u128 * e.min_record_bytes(header.encoding) as u128;
        if least > remaining {
            return Err(format!(
                "its header declares {} {} records, more than its {} bytes of data can hold (truncated or damaged?)",
                e.count,
                e.name,
                bytes.len() - header.data_start
            ));
        }
        remaining -= least;
    }
    let vertex = header.elements.iter().find(|e| e.name == "vertex");
    let vertex = vertex.ok_or("no `element vertex` in its header")?;
    let layout = VertexLayout::of(vertex)?;
    let faces = header.elements.iter().find(|e| e.name == "face");
    // Each vertex takes at most 8 floats, each face at least one triangle.
    let need = vertex.count as u128 * 32 + faces.map_or(0, |f| f.count as u128) * 12;
    crate::error::limits::check(need).map_err(|r| format!("{r}"))?;
    let mut values = Values {
        bytes,
        at: header.data_start,
        encoding: header.encoding,
    };
    let mut mesh = PlyMesh {
        positions: Vec::with_capacity(vertex.count as usize),
        normals: layout
            .normal
            .map(|_| Vec::with_capacity(vertex.count as usize)),
        uvs: layout.uv.map(|_| Vec::with_capacity(vertex.count as usize)),
        triangles: Vec::new(),
    };
    for e in &header.elements {
        match e.name.as_str() {
            "vertex" => read_vertices(e, &layout, &mut values, &mut mesh)?,
            "face" => read_faces(e, &mut values, &mut mesh)?,
            _ => skip(e, &mut values)?,
        }
    }
    if mesh.triangles.is_empty() {
        return Err("holds no faces with 3 or more vertices".into());
    }
    Ok(mesh)
}

fn read_vertices(
    e: &Element,
    layout: &VertexLayout,
    values: &mut Values,
    mesh: &mut PlyMesh,
) -> Result<(), String> {
    let mut record = vec![0.0f64; e.properties.len()];
    for _ in 0..e.count {
        for (slot, p) in record.iter_mut().zip(&e.properties) {
            *slot = values.next(p.scalar)?;
        }
        let v3 =
            |[a, b, c]: [usize; 3]| Vec3::new(record[a] as f32, record[b] as f32, record[c] as f32);
        let p = v3(layout.position);
        if !p.is_finite() {
            return Err("a non-finite vertex".into());
        }
        mesh.positions.push(p);
        if let (Some(n), Some(normals)) = (layout.normal, mesh.normals.as_mut()) {
            normals.push(v3(n));
        }
        if let (Some([u, v]), Some(uvs)) = (layout.uv, mesh.uvs.as_mut()) {
            let uv = Vec2::new(record[u] as f32, record[v] as f32);
            if !uv.is_finite() {
                return Err("a non-finite texture coordinate".into());
            }
            uvs.push(uv);
        }
    }
    Ok(())
}

/// The faces' `vertex_indices` (or `vertex_index`) lists, fan-triangulated.
fn read_faces(e: &Element, values: &mut Values, mesh: &mut PlyMesh) -> Result<(), String> {
    let list = e
        .index("vertex_indices")
        .or(e.index("vertex_index"))
        .filter(|&i| e.properties[i].list_count.is_some())
        .ok_or("its faces have no `vertex_indices` list")?;
    let vertices = mesh.positions.len() as f64;
    let mut polygon: Vec<u32> = Vec::new();
    for _ in 0..e.count {
        for (i, p) in e.properties.iter().enumerate() {
            let Some(count_type) = p.list_count else {
                values.next(p.scalar)?;
                continue;
            };
            let n = values.next(count_type)?;
            polygon.clear();
            for _ in 0..n as u64 {
                let v = values.next(p.scalar)?;
                if i == list {
                    if !(0.0..vertices).contains(&v) || v.fract() != 0.0 {
                        return Err(format!("face vertex index {v} out of range"));
                    }
                    polygon.push(v as u32);
                }
            }
            if i == list {
                for k in 1..polygon.len().saturating_sub(1) {
                    mesh.triangles
                        .push([polygon[0], polygon[k], polygon[k + 1]]);
                }
            }
        }
    }
    Ok(())
}

/// Reads past the records of an element brume does not use.
fn skip(e: &Element, values: &mut Values) -> Result<(), String> {
    for _ in 0..e.count {
        for p in &e.properties {
            let n = match p.list_count {
                Some(c) => values.next(c)? as u64,
                None => 1,
            };
            for _ in 0..n {
                values.next(p.scalar)?;
            }
        }
    }
    Ok(())
}
