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
//! The image is sent in bands of rows so that no packet grows large, from a
//! writer thread fed through a bounded queue: a viewer that accepts the
//! connection and never reads cannot slow the render, its exit or its
//! answer to Ctrl-C/SIGTERM.

use crate::error::{Error, Result};
use crate::film::image_io::Image;
use std::collections::VecDeque;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// tev's packet type numbers.
const CREATE_IMAGE: u8 = 4;
const UPDATE_IMAGE_V3: u8 = 6;
/// The channels brume sends.
const CHANNELS: [&str; 3] = ["R", "G", "B"];
/// Most pixels in one update packet (12 bytes each: about 3 MB).
const PIXELS_PER_PACKET: usize = 1 << 18;
/// A viewer that takes less than [`STALL_BYTES`] in this long counts as gone.
const STALL_TIME: Duration = Duration::from_secs(2);
/// See [`STALL_TIME`]: a trickle (TCP window probes) is not a viewer reading.
const STALL_BYTES: usize = 64 << 10;
/// The longest one socket write blocks, so that a stall is noticed in time.
const WRITE_SLICE: Duration = Duration::from_millis(250);
/// Pixel bytes the queue of unsent frames may hold; past it the oldest are
/// dropped (the newest is always kept), so a slow viewer costs memory for
/// about one frame of a large image, not one per pass.
const QUEUE_BYTES: usize = 64 << 20;

/// A connection to a tev viewer showing one image.
///
/// Frames go to a writer thread through a bounded queue, so the render never
/// waits on the network: a viewer that stops reading only makes frames drop.
/// The writer is never joined: a stuck one cannot hold up brume's exit.
pub struct Display {
    shared: Arc<Shared>,
}

/// The queue between the render and the writer thread.
struct Shared {
    state: Mutex<State>,
    changed: Condvar,
}

#[derive(Default)]
struct State {
    /// Frames not yet taken by the writer, oldest first.
    queue: VecDeque<Image>,
    /// Pixel bytes held by `queue`.
    bytes: usize,
    /// The writer is sending a frame now.
    sending: bool,
    /// No more frames will come: the writer ends once the queue is empty.
    closing: bool,
    /// Why the connection ended, once it has.
    failure: Option<String>,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere cannot leave the queue inconsistent: keep using it.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
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
        let stream = open(address)?;
        let _ = stream.set_nodelay(true);
        let _ = stream.set_write_timeout(Some(WRITE_SLICE));
        let shared = Arc::new(Shared {
            state: Mutex::new(State::default()),
            changed: Condvar::new(),
        });
        let writer = Writer {
            stream,
            name: name.to_string(),
            created: None,
            shared: shared.clone(),
        };
        std::thread::Builder::new()
            .name("tev".into())
            .spawn(move || writer.run())
            .map_err(|e| bad_address(format!("cannot start the tev writer thread: {e}")))?;
        Ok(Display { shared })
    }

    /// Queues `image` for tev (creating it there first, the first time)
    /// without waiting for the network; an error once the viewer is gone.
    pub fn show(&mut self, image: &Image) -> std::io::Result<()> {
        // Copied before taking the lock, so the writer never waits on the copy.
        let frame = Image {
            width: image.width,
            height: image.height,
            pixels: image.pixels.clone(),
            spp: image.spp,
            partial: image.partial,
        };
        let mut state = self.shared.lock();
        if let Some(failure) = &state.failure {
            return Err(std::io::Error::other(failure.clone()));
        }
        state.bytes += frame.pixels.len() * 12;
        state.queue.push_back(frame);
        while state.bytes > QUEUE_BYTES && state.queue.len() > 1 {
            if let Some(stale) = state.queue.pop_front() {
                state.bytes -= stale.pixels.len() * 12;
            }
        }
        self.shared.changed.notify_all();
        Ok(())
    }

    /// Waits until tev has every queued frame, at most `limit` and only while
    /// `stop` is unset; says why not when it gave up. The writer is left to
    /// end (or be ended by the process exit), never joined.
    pub fn finish(self, stop: &AtomicBool, limit: Duration) -> Option<String> {
        let start = Instant::now();
        let mut state = self.shared.lock();
        state.closing = true;
        self.shared.changed.notify_all();
        loop {
            if let Some(failure) = &state.failure {
                return Some(format!("tev did not get the final image: {failure}"));
            }
            if state.queue.is_empty() && !state.sending {
                return None;
            }
            if stop.load(Ordering::Relaxed) {
                return Some("stopped before tev got the final image".into());
            }
            if start.elapsed() >= limit {
                return Some(format!(
                    "tev did not take the final image within {} s; exiting without it",
                    limit.as_secs_f64()
                ));
            }
            // Short waits, so that a stop request is seen within a few milliseconds.
            let wait = Duration::from_millis(10);
            state = match self.shared.changed.wait_timeout(state, wait) {
                Ok((s, _)) => s,
                Err(p) => p.into_inner().0,
            };
        }
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        // No more frames: the writer ends when it has sent what it holds.
        self.shared.lock().closing = true;
        self.shared.changed.notify_all();
    }
}

fn bad_address(message: String) -> Error {
    Error::Argument {
        argument: "--display".into(),
        message,
    }
}

/// A TCP connection to the first address of `address` that answers.
fn open(address: &str) -> Result<TcpStream> {
    let addrs: Vec<_> = address
        .to_socket_addrs()
        .map_err(|e| bad_address(format!("{address} is not a HOST:PORT address: {e}")))?
        .collect();
    let mut last = None;
    for addr in addrs {
        match TcpStream::connect_timeout(&addr, Duration::from_secs(5)) {
            Ok(stream) => return Ok(stream),
            Err(e) => last = Some(e),
        }
    }
    Err(bad_address(match last {
        Some(e) => format!("cannot connect to tev at {address}: {e}"),
        None => format!("{address} names no address"),
    }))
}

/// The writer thread's side: sends queued frames until closed or failed.
struct Writer {
    stream: TcpStream,
    name: String,
    /// The size tev's image was created with.
    created: Option<(usize, usize)>,
    shared: Arc<Shared>,
}

impl Writer {
    fn run(mut self) {
        while let Some(frame) = self.next_frame() {
            let result = self.send(&frame);
            let mut state = self.shared.lock();
            state.sending = false;
            if let Err(e) = result {
                state.failure = Some(describe(&e));
                state.queue.clear();
                state.bytes = 0;
                self.shared.changed.notify_all();
                return;
            }
            self.shared.changed.notify_all();
        }
        // Closed and empty: dropping the stream tells tev the image is final.
    }

    /// The oldest queued frame (marking it being sent), or `None` once closed and empty.
    fn next_frame(&self) -> Option<Image> {
        let mut state = self.shared.lock();
        loop {
            if let Some(frame) = state.queue.pop_front() {
                state.bytes -= frame.pixels.len() * 12;
                state.sending = true;
                return Some(frame);
            }
            if state.closing {
                return None;
            }
            state = match self.shared.changed.wait(state) {
                Ok(s) => s,
                Err(p) => p.into_inner(),
            };
        }
    }

    /// Sends `image` in bands of rows (creating tev's image first, when its size is new).
    fn send(&mut self, image: &Image) -> std::io::Result<()> {
        let mut progress = Progress::new();
        if self.created != Some((image.width, image.height)) {
            let packet = create_image_packet(&self.name, image.width, image.height);
            progress.write_all(&mut self.stream, &packet)?;
            self.created = Some((image.width, image.height));
        }
        let rows = (PIXELS_PER_PACKET / image.width.max(1)).max(1);
        let mut y0 = 0;
        while y0 < image.height {
            let y1 = (y0 + rows).min(image.height);
            let packet = update_image_packet(&self.name, image, y0, y1);
            progress.write_all(&mut self.stream, &packet)?;
            y0 = y1;
        }
        Ok(())
    }
}

/// When the last [`STALL_BYTES`] were sent: a socket timeout alone would let
/// a viewer that takes a few bytes per timeout (TCP window probes) hold a
/// frame forever, and a fixed window would let a stall after a burst last two windows.
struct Progress {
    since: Instant,
    bytes: usize,
}

impl Progress {
    fn new() -> Progress {
        Progress {
            since: Instant::now(),
            bytes: 0,
        }
    }

    /// Writes all of `bytes`, or fails once [`STALL_TIME`] passes without [`STALL_BYTES`] sent.
    fn write_all(&mut self, stream: &mut TcpStream, mut bytes: &[u8]) -> std::io::Result<()> {
        use std::io::ErrorKind;
        while !bytes.is_empty() {
            match stream.write(bytes) {
                Ok(0) => return Err(ErrorKind::WriteZero.into()),
                Ok(n) => {
                    bytes = &bytes[n..];
                    self.bytes += n;
                    if self.bytes >= STALL_BYTES {
                        *self = Progress::new();
                    }
                }
                // A write slice ran out or a signal came: the clock decides.
                Err(e)
                    if matches!(
                        e.kind(),
                        ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
                    ) => {}
                Err(e) => return Err(e),
            }
            if self.since.elapsed() >= STALL_TIME {
                return Err(ErrorKind::TimedOut.into());
            }
        }
        Ok(())
    }
}

/// A send error in words: a viewer that stopped reading is named as such.
fn describe(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::TimedOut => format!(
            "tev took less than {} KB in {} s",
            STALL_BYTES >> 10,
            STALL_TIME.as_secs_f64()
        ),
        _ => e.to_string(),
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
