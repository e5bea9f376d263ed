//! Live preview in the tev image viewer over its TCP protocol (`--display HOST:PORT`).
//!
//! tev's protocol frames every packet as a little-endian `u32` length (which
//! counts itself), a `u8` packet type and the payload; strings are
//! NUL-terminated, integers little-endian. brume sends two kinds:
//!
//! - `CreateImage` (4): grab focus `u8`, image name, width `i32`, height `i32`,
//!   channel count `i32`, channel names.
//! - `UpdateImageV3` (6): grab focus `u8`, image name, channel count `i32`,
//!   channel names, x, y, width, height (`i32`), one `i64` offset and one `i64`
//!   stride per channel into the interleaved `f32` pixels that follow.
//!
//! The image is sent in bands of rows so that no packet grows large.

use crate::error::{Error, Result};
use crate::film::image_io::Image;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

/// tev's packet type numbers.
const CREATE_IMAGE: u8 = 4;
const UPDATE_IMAGE_V3: u8 = 6;
/// The channels brume sends.
const CHANNELS: [&str; 3] = ["R", "G", "B"];
/// Most pixels in one update packet (12 bytes each: about 3 MB).
const PIXELS_PER_PACKET: usize = 1 << 18;

/// A connection to a tev viewer showing one image.
pub struct Display {
    stream: TcpStream,
    name: String,
    created: bool,
}

/// A packet under construction: the length is patched in when it is finished.
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8) -> Packet {
        let mut bytes = vec![0u8; 4];
        bytes.push(kind);
        Packet(bytes)
    }
    fn u8(&mut self, v: u8) -> &mut Self {
        self.0.push(v);
        self
    }
    fn i32(&mut self, v: i32) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn i64(&mut self, v: i64) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn str(&mut self, s: &str) -> &mut Self {
        // A NUL inside a name would end it early in tev: drop it.
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
        self
    }
    fn finish(mut self) -> Vec<u8> {
        let len = self.0.len() as u32;
        self.0[..4].copy_from_slice(&len.to_le_bytes());
        self.0
    }
}

/// The `CreateImage` packet for an RGB image `name` of `width`×`height`.
pub fn create_image_packet(name: &str, width: usize, height: usize) -> Vec<u8> {
    let mut p = Packet::new(CREATE_IMAGE);
    p.u8(0)
        .str(name)
        .i32(width as i32)
        .i32(height as i32)
        .i32(CHANNELS.len() as i32);
    for c in CHANNELS {
        p.str(c);
    }
    p.finish()
}

/// The `UpdateImageV3` packet for rows `y0..y1` of `image` (interleaved RGB).
pub fn update_image_packet(name: &str, image: &Image, y0: usize, y1: usize) -> Vec<u8> {
    let w = image.width;
    let mut p = Packet::new(UPDATE_IMAGE_V3);
    p.u8(0).str(name).i32(CHANNELS.len() as i32);
    for c in CHANNELS {
        p.str(c);
    }
    p.i32(0).i32(y0 as i32).i32(w as i32).i32((y1 - y0) as i32);
    for offset in 0..CHANNELS.len() {
        p.i64(offset as i64);
    }
    for _ in CHANNELS {
        p.i64(CHANNELS.len() as i64);
    }
    p.0.reserve(w * (y1 - y0) * 12);
    for c in &image.pixels[y0 * w..y1 * w] {
        for v in [c.r, c.g, c.b] {
            p.0.extend_from_slice(&v.to_le_bytes());
        }
    }
    p.finish()
}

impl Display {
    /// Connects to tev at `address` (HOST:PORT), which will show the image as `name`.
    pub fn connect(address: &str, name: &str) -> Result<Display> {
        let bad = |message: String| Error::Argument {
            argument: "--display".into(),
            message,
        };
        let addrs: Vec<_> = address
            .to_socket_addrs()
            .map_err(|e| bad(format!("{address} is not a HOST:PORT address: {e}")))?
            .collect();
        let mut last = None;
        for addr in addrs {
            match TcpStream::connect_timeout(&addr, Duration::from_secs(5)) {
                Ok(stream) => {
                    let _ = stream.set_nodelay(true);
                    let _ = stream.set_write_timeout(Some(Duration::from_secs(10)));
                    return Ok(Display {
                        stream,
                        name: name.to_string(),
                        created: false,
                    });
                }
                Err(e) => last = Some(e),
            }
        }
        Err(bad(match last {
            Some(e) => format!("cannot connect to tev at {address}: {e}"),
            None => format!("{address} names no address"),
        }))
    }

    /// Sends `image` (creating it in tev first, the first time).
    pub fn show(&mut self, image: &Image) -> std::io::Result<()> {
        if !self.created {
            let packet = create_image_packet(&self.name, image.width, image.height);
            self.stream.write_all(&packet)?;
            self.created = true;
        }
        let rows = (PIXELS_PER_PACKET / image.width.max(1)).max(1);
        let mut y0 = 0;
        while y0 < image.height {
            let y1 = (y0 + rows).min(image.height);
            self.stream
                .write_all(&update_image_packet(&self.name, image, y0, y1))?;
            y0 = y1;
        }
        self.stream.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::color::Rgb;

    #[test]
    fn create_image_packet_has_tevs_layout() {
        let p = create_image_packet("ab", 3, 2);
        let mut expected = Vec::new();
        let body: Vec<u8> = [
            vec![CREATE_IMAGE, 0, b'a', b'b', 0],
            3i32.to_le_bytes().to_vec(),
            2i32.to_le_bytes().to_vec(),
            3i32.to_le_bytes().to_vec(),
            b"R\0G\0B\0".to_vec(),
        ]
        .concat();
        expected.extend_from_slice(&(body.len() as u32 + 4).to_le_bytes());
        expected.extend_from_slice(&body);
        assert_eq!(p, expected);
    }

    #[test]
    fn update_packet_carries_the_rows_interleaved() {
        let image = Image {
            width: 2,
            height: 2,
            pixels: (0..4).map(|i| Rgb::splat(i as f32)).collect(),
            spp: 1,
            partial: true,
        };
        let p = update_image_packet("x", &image, 1, 2);
        assert_eq!(
            u32::from_le_bytes(p[..4].try_into().unwrap()) as usize,
            p.len()
        );
        assert_eq!(p[4], UPDATE_IMAGE_V3);
        // Header: type, focus, "x\0", count, "R\0G\0B\0", 4 i32, 3 + 3 i64.
        let header = 4 + 1 + 1 + 2 + 4 + 6 + 16 + 48;
        assert_eq!(p.len(), header + 2 * 3 * 4);
        let floats: Vec<f32> = p[header..]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, vec![2.0, 2.0, 2.0, 3.0, 3.0, 3.0]);
        let y = i32::from_le_bytes(p[22..26].try_into().unwrap());
        assert_eq!(y, 1);
    }
}
