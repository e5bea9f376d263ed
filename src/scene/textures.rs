//! Colour parameters written as textures: `{ type = "image", file = ... }`
//! and `{ type = "checkerboard", a, b }`, read and checked once at scene load.

use super::description::{Color, ColorOrTexture, TextureDesc, UvScale};
use super::files::{check_input, Format};
use super::resolve;
use super::validate::Check;
use crate::error::Result;
use crate::material::texture::{Filter, Image, Texture, Wrap};
use crate::math::color::{srgb_to_linear, Rgb};
use crate::math::Vec2;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Which values a colour parameter may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Range {
    /// A reflectance: every channel in [0, 1].
    Albedo,
    /// A radiance: every channel finite and ≥ 0.
    Radiance,
}

/// Largest texture file read.
pub(super) const MAX_TEXTURE_BYTES: u64 = 1 << 30;

/// Images already read in this scene, so that a file used twice is decoded once.
#[derive(Default)]
pub(super) struct ImageCache {
    images: Vec<((PathBuf, Wrap, bool), Arc<Image>)>,
}

/// Builds the colour parameter `value` written at `field`.
pub(super) fn build(
    check: &Check,
    field: &str,
    value: &ColorOrTexture,
    range: Range,
    base: &Path,
    cache: &mut ImageCache,
) -> Result<Texture> {
    let desc = match value {
        ColorOrTexture::Color(c) => return Ok(Texture::Constant(color(check, field, *c, range)?)),
        ColorOrTexture::Texture(t) => t,
    };
    let f = |key: &str| format!("{field}.{key}");
    reject_foreign_keys(check, field, desc, keys_of(check, field, desc)?)?;
    let uv_scale = uv_scale(check, &f("uv_scale"), desc.uv_scale)?;
    let uv_offset = uv_offset(check, &f("uv_offset"), desc.uv_offset)?;
    if desc.kind == "checkerboard" {
        let get = |key: &str, c: Option<Color>| {
            c.ok_or_else(|| check.error(&f(key), "missing"))
                .and_then(|c| color(check, &f(key), c, range))
        };
        return Ok(Texture::Checkerboard {
            a: get("a", desc.a)?,
            b: get("b", desc.b)?,
            uv_scale,
            uv_offset,
        });
    }
    let scale = match desc.scale {
        Some(s) => check.color(&f("scale"), s)?,
        None => Rgb::WHITE,
    };
    let image = image(check, field, desc, base, cache)?;
    check_scaled_overflow(check, field, desc, &image, scale)?;
    if range == Range::Albedo {
        check_albedo_texels(check, &f("file"), &image, scale, desc)?;
    }
    Ok(Texture::Image {
        image,
        scale,
        uv_scale,
        uv_offset,
        filter: filter(check, field, desc)?,
    })
}

/// The keys a texture of `desc.kind` reads (an unknown kind is refused).
fn keys_of(check: &Check, field: &str, desc: &TextureDesc) -> Result<&'static [&'static str]> {
    match desc.kind.as_str() {
        "image" => Ok(&[
            "file",
            "wrap",
            "filter",
            "color_space",
            "scale",
            "uv_scale",
            "uv_offset",
        ]),
        "checkerboard" => Ok(&["a", "b", "uv_scale", "uv_offset"]),
        other => Err(check.error(
            &format!("{field}.type"),
            format!("unknown texture type `{other}`, expected \"image\" or \"checkerboard\""),
        )),
    }
}

/// `uv_offset`: two finite numbers (zero when absent).
fn uv_offset(check: &Check, field: &str, offset: Option<[f32; 2]>) -> Result<Vec2> {
    match offset {
        Some([du, dv]) => Ok(Vec2::new(
            check.finite(&format!("{field}[0]"), du)?,
            check.finite(&format!("{field}[1]"), dv)?,
        )),
        None => Ok(Vec2::ZERO),
    }
}

/// A constant colour in `range`.
fn color(check: &Check, field: &str, c: Color, range: Range) -> Result<Rgb> {
    match range {
        Range::Albedo => check.albedo(field, c),
        Range::Radiance => check.color(field, c),
    }
}

fn reject_foreign_keys(
    check: &Check,
    field: &str,
    desc: &TextureDesc,
    used: &[&str],
) -> Result<()> {
    let present = [
        ("file", desc.file.is_some()),
        ("wrap", desc.wrap.is_some()),
        ("filter", desc.filter.is_some()),
        ("uv_offset", desc.uv_offset.is_some()),
        ("color_space", desc.color_space.is_some()),
        ("scale", desc.scale.is_some()),
        ("a", desc.a.is_some()),
        ("b", desc.b.is_some()),
        ("uv_scale", desc.uv_scale.is_some()),
    ];
    for (key, set) in present {
        if set && !used.contains(&key) {
            return Err(check.error(
                &format!("{field}.{key}"),
                format!("unknown key for a texture of type {}", desc.kind),
            ));
        }
    }
    Ok(())
}

fn uv_scale(check: &Check, field: &str, s: Option<UvScale>) -> Result<Vec2> {
    let [su, sv] = match s {
        None => return Ok(Vec2::ONE),
        Some(UvScale::Both(v)) => [v; 2],
        Some(UvScale::Each(v)) => v,
    };
    for (i, v) in [su, sv].into_iter().enumerate() {
        let name = match s {
            Some(UvScale::Each(_)) => format!("{field}[{i}]"),
            _ => field.to_string(),
        };
        if check.finite(&name, v)? == 0.0 {
            return Err(check.error(&name, "must not be 0"));
        }
    }
    Ok(Vec2::new(su, sv))
}

/// The image of an `image` texture, from the cache or its file.
fn image(
    check: &Check,
    field: &str,
    desc: &TextureDesc,
    base: &Path,
    cache: &mut ImageCache,
) -> Result<Arc<Image>> {
    let file_field = format!("{field}.file");
    let file = desc
        .file
        .as_ref()
        .ok_or_else(|| check.error(&file_field, "missing"))?;
    let path = resolve(base, file);
    let wrap = wrap_mode(check, field, desc)?;
    // what the path is comes first: `/dev/zero` is a device whatever its name
    if let Some(problem) = crate::error::input_file_problem(&path, MAX_TEXTURE_BYTES) {
        return Err(check.error(
            &file_field,
            format!("cannot read texture {}: {problem}", path.display()),
        ));
    }
    let format = image_format(check, &file_field, &path)?;
    let srgb = is_srgb(
        check,
        field,
        desc,
        !matches!(format, Format::Png | Format::Jpeg),
    )?;
    let key = (path.clone(), wrap, srgb);
    if let Some((_, image)) = cache.images.iter().find(|(k, _)| *k == key) {
        return Ok(image.clone());
    }
    let read_error = |message: String| {
        check.error(
            &file_field,
            format!("cannot read texture {}: {message}", path.display()),
        )
    };
    check_input(
        check,
        &file_field,
        "texture",
        &path,
        format,
        MAX_TEXTURE_BYTES,
    )?;
    let (width, height, texels) = read_texels(format, &path, srgb).map_err(read_error)?;
    check_finite_texels(check, &file_field, &path, width, &texels)?;
    let image = Arc::new(
        Image::new(width, height, texels, wrap)
            .ok_or_else(|| read_error("the image is empty".into()))?,
    );
    cache.images.push((key, image.clone()));
    Ok(image)
}

/// Refuses a `scale` that would overflow single precision on the brightest texel of `image`.
fn check_scaled_overflow(
    check: &Check,
    field: &str,
    desc: &TextureDesc,
    image: &Image,
    scale: Rgb,
) -> Result<()> {
    let texels = (0..image.height()).flat_map(|j| (0..image.width()).map(move |i| (i, j)));
    let brightest = super::overflow::brightest(texels.map(|(i, j)| image.texel(i, j)));
    let scale_field = match desc.scale {
        Some(_) => format!("{field}.scale"),
        None => format!("{field}.file"),
    };
    super::overflow::product(
        check,
        &scale_field,
        (brightest, "the brightest texel"),
        (scale, "scale"),
    )
}

/// The image format of the texture at `path`, by its extension; other files are refused.
fn image_format(check: &Check, file_field: &str, path: &Path) -> Result<Format> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    match ext.to_ascii_lowercase().as_str() {
        "exr" => Ok(Format::Exr),
        "png" => Ok(Format::Png),
        "hdr" | "pic" => Ok(Format::Hdr),
        "jpg" | "jpeg" => Ok(Format::Jpeg),
        _ => Err(check.error(
            file_field,
            format!(
                "texture {} is not a .png, .jpg, .exr or .hdr file",
                path.display()
            ),
        )),
    }
}

/// The `filter` of an image texture (bilinear when absent).
fn filter(check: &Check, field: &str, desc: &TextureDesc) -> Result<Filter> {
    match desc.filter.as_deref() {
        None | Some("bilinear") => Ok(Filter::Bilinear),
        Some("nearest") => Ok(Filter::Nearest),
        Some(other) => Err(check.error(
            &format!("{field}.filter"),
            format!("unknown filter `{other}`, expected \"bilinear\" or \"nearest\""),
        )),
    }
}

/// The `wrap` mode of an image texture (repeat when absent).
fn wrap_mode(check: &Check, field: &str, desc: &TextureDesc) -> Result<Wrap> {
    match desc.wrap.as_deref() {
        None | Some("repeat") => Ok(Wrap::Repeat),
        Some("clamp") => Ok(Wrap::Clamp),
        Some("mirror") => Ok(Wrap::Mirror),
        Some(other) => Err(check.error(
            &format!("{field}.wrap"),
            format!("unknown wrap mode `{other}`, expected \"repeat\", \"mirror\" or \"clamp\""),
        )),
    }
}

/// Whether the texels are sRGB-encoded: `color_space`, else PNG yes and EXR no.
fn is_srgb(check: &Check, field: &str, desc: &TextureDesc, linear: bool) -> Result<bool> {
    match (desc.color_space.as_deref(), linear) {
        (None, linear) => Ok(!linear),
        (Some("linear"), _) => Ok(false),
        (Some("srgb"), false) => Ok(true),
        (Some("srgb"), true) => Err(check.error(
            &format!("{field}.color_space"),
            "EXR and Radiance HDR files hold linear values; color_space = \"srgb\" applies to PNG and JPEG only",
        )),
        (Some(other), _) => Err(check.error(
            &format!("{field}.color_space"),
            format!("unknown colour space `{other}`, expected \"srgb\" or \"linear\""),
        )),
    }
}

/// Refuses an image with a negative or non-finite texel, naming the first one.
pub(super) fn check_finite_texels(
    check: &Check,
    file_field: &str,
    path: &Path,
    width: usize,
    texels: &[Rgb],
) -> Result<()> {
    match texels
        .iter()
        .position(|t| !t.is_finite() || t.min_channel() < 0.0)
    {
        Some(i) => Err(check.error(
            file_field,
            format!(
                "texel ({}, {}) of {} is negative or not finite",
                i % width,
                i / width,
                path.display()
            ),
        )),
        None => Ok(()),
    }
}

/// The linear texels of the image at `path`, by its format.
fn read_texels(
    format: Format,
    path: &Path,
    srgb: bool,
) -> std::result::Result<(usize, usize, Vec<Rgb>), String> {
    let message = super::files::input_message;
    match format {
        Format::Exr => read_exr_texels(path),
        Format::Hdr => crate::film::image_io::read_hdr(path).map_err(message),
        Format::Jpeg => read_jpeg_texels(path, srgb).map_err(message),
        _ => read_png_texels(path, srgb),
    }
}

/// Linear texels of a JPEG (8-bit, decoded to RGB).
fn read_jpeg_texels(path: &Path, srgb: bool) -> Result<(usize, usize, Vec<Rgb>)> {
    let (width, height, pixels) = crate::film::image_io::read_jpeg(path)?;
    let decode = |v: f32| if srgb { srgb_to_linear(v) } else { v };
    let texels = pixels
        .iter()
        .map(|p| Rgb::new(decode(p[0]), decode(p[1]), decode(p[2])))
        .collect();
    Ok((width, height, texels))
}

/// Linear texels of a PNG: grey or RGB, an alpha channel only if opaque everywhere.
fn read_png_texels(
    path: &Path,
    srgb: bool,
) -> std::result::Result<(usize, usize, Vec<Rgb>), String> {
    let png = crate::film::image_io::read_png(path).map_err(|e| match e {
        crate::error::Error::Input { message, .. } => message,
        other => other.to_string(),
    })?;
    let c = png.channels;
    let colour = if c <= 2 { 1 } else { 3 };
    if c == 2 || c == 4 {
        if let Some(i) = png.values.chunks_exact(c).position(|p| p[c - 1] < 1.0) {
            return Err(format!(
                "pixel ({}, {}) is not opaque: alpha (transparency) is not supported, save the PNG without it",
                i % png.width,
                i / png.width
            ));
        }
    }
    let decode = |v: f32| if srgb { srgb_to_linear(v) } else { v };
    let texels = png
        .values
        .chunks_exact(c)
        .map(|p| {
            let v = |k: usize| decode(p[k.min(colour - 1)]);
            Rgb::new(v(0), v(1), v(2))
        })
        .collect();
    Ok((png.width, png.height, texels))
}

/// Texels of an EXR: channels R, G, B, or Y alone for grey.
fn read_exr_texels(path: &Path) -> std::result::Result<(usize, usize, Vec<Rgb>), String> {
    let (width, height, channels) =
        crate::film::image_io::read_exr_channels(path).map_err(|e| match e {
            crate::error::Error::Input { message, .. } => message,
            other => other.to_string(),
        })?;
    let find = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, v)| v);
    let planes = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => [r, g, b],
        (None, None, None, Some(y)) => [y, y, y],
        _ => {
            let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
            return Err(format!(
                "needs channels R, G and B (or Y for grey), found [{}]",
                names.join(", ")
            ));
        }
    };
    if planes.iter().any(|p| p.len() != width * height) {
        return Err("channel sizes do not match the image".into());
    }
    let texels = (0..width * height)
        .map(|i| Rgb::new(planes[0][i], planes[1][i], planes[2][i]))
        .collect();
    Ok((width, height, texels))
}

/// An albedo texture's texels times `scale` must stay within [0, 1].
fn check_albedo_texels(
    check: &Check,
    field: &str,
    image: &Image,
    scale: Rgb,
    desc: &TextureDesc,
) -> Result<()> {
    for j in 0..image.height() {
        for i in 0..image.width() {
            let v = image.texel(i, j) * scale;
            if v.max_channel() > 1.0 {
                let scaled = if desc.scale.is_some() {
                    " times scale"
                } else {
                    ""
                };
                let file = desc.file.as_deref().unwrap_or(Path::new("")).display();
                return Err(check.error(
                    field,
                    format!(
                        "texel ({i}, {j}) of {file}{scaled} is {:?}, above 1: a reflectance must be at most 1 in every channel",
                        v.to_array()
                    ),
                ));
            }
        }
    }
    Ok(())
}
