//! Small image files whose headers declare whatever a test asks: EXR and PNG
//! written byte by byte (the encoders refuse what these tests need to write).
#![allow(dead_code)]

/// OpenEXR compression codes (the `compression` attribute).
pub const EXR_COMPRESSIONS: [(u8, &str); 10] = [
    (0, "none"),
    (1, "rle"),
    (2, "zips"),
    (3, "zip"),
    (4, "piz"),
    (5, "pxr24"),
    (6, "b44"),
    (7, "b44a"),
    (8, "dwaa"),
    (9, "dwab"),
];

/// The most bytes one compressed byte can stand for, per EXR compression
/// code, from each format's own limits (deflate: a 258-byte match in two
/// bits; RLE: 128 bytes in 2; DWA: deflate of an 8×8 block's DC and end
/// code, 4 bytes for 256), independent of brume's table and looser.
pub fn exr_ratio_bound(compression: u8) -> u64 {
    match compression {
        0 => 1,
        1 => 64,
        2..=5 => 1400,
        6 | 7 => 11,
        _ => 140_000,
    }
}

fn attribute(out: &mut Vec<u8>, name: &str, kind: &str, data: &[u8]) {
    out.extend(name.as_bytes());
    out.push(0);
    out.extend(kind.as_bytes());
    out.push(0);
    out.extend((data.len() as i32).to_le_bytes());
    out.extend(data);
}

/// An EXR of one scan-line part: data window `[x0, x1] × [y0, y1]`,
/// `channels` (name, pixel type: 0 u32, 1 half, 2 float), `compression`,
/// then `tail` where the offset table and chunks belong.
pub fn exr(window: [i32; 4], compression: u8, channels: &[(&str, i32)], tail: &[u8]) -> Vec<u8> {
    let mut out = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    let mut list = Vec::new();
    for (name, kind) in channels {
        list.extend(name.as_bytes());
        list.push(0);
        list.extend(kind.to_le_bytes());
        list.extend([0, 0, 0, 0]);
        list.extend(1i32.to_le_bytes());
        list.extend(1i32.to_le_bytes());
    }
    list.push(0);
    attribute(&mut out, "channels", "chlist", &list);
    attribute(&mut out, "compression", "compression", &[compression]);
    let bounds: Vec<u8> = window.iter().flat_map(|v| v.to_le_bytes()).collect();
    attribute(&mut out, "dataWindow", "box2i", &bounds);
    attribute(&mut out, "displayWindow", "box2i", &bounds);
    attribute(&mut out, "lineOrder", "lineOrder", &[0]);
    attribute(&mut out, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attribute(&mut out, "screenWindowCenter", "v2f", &[0; 8]);
    attribute(&mut out, "screenWindowWidth", "float", &1f32.to_le_bytes());
    out.push(0);
    out.extend(tail);
    out
}

/// An RGB float EXR of `width` × `height` pixels with ZIP compression and
/// nothing after the header: a few hundred bytes however large it claims to be.
pub fn tiny_rgb_exr(width: i32, height: i32) -> Vec<u8> {
    let rgb = [("B", 2), ("G", 2), ("R", 2)];
    exr([0, 0, width - 1, height - 1], 3, &rgb, &[0; 64])
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend((data.len() as u32).to_be_bytes());
    let mut crc = flate2::Crc::new();
    crc.update(kind);
    crc.update(data);
    out.extend(kind);
    out.extend(data);
    out.extend(crc.sum().to_be_bytes());
}

/// A PNG whose IHDR declares `width` × `height` at `bit_depth` and
/// `colour` (PNG colour type), interlaced or not, followed by one IDAT
/// holding `idat` and IEND.
pub fn png(
    width: u32,
    height: u32,
    bit_depth: u8,
    colour: u8,
    interlaced: bool,
    idat: &[u8],
) -> Vec<u8> {
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut ihdr = Vec::new();
    ihdr.extend(width.to_be_bytes());
    ihdr.extend(height.to_be_bytes());
    ihdr.extend([bit_depth, colour, 0, 0, interlaced as u8]);
    chunk(&mut out, b"IHDR", &ihdr);
    if colour == 3 {
        chunk(&mut out, b"PLTE", &[0, 0, 0, 255, 255, 255]);
    }
    chunk(&mut out, b"IDAT", idat);
    chunk(&mut out, b"IEND", &[]);
    out
}

/// An 8-bit RGB PNG declaring `width` × `height` with a few bytes of zlib data.
pub fn tiny_rgb_png(width: u32, height: u32) -> Vec<u8> {
    let zeros = [0u8; 256];
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    std::io::Write::write_all(&mut z, &zeros).unwrap();
    png(width, height, 8, 2, false, &z.finish().unwrap())
}
