//! The photon pass: light subpaths traced with bidirectional sampling's
//! walk, each scattering vertex past the first hit kept as a photon (on a
//! surface or in a medium), then gridded for the eye pass.
//!
//! Photon `i` of pass `p` draws its numbers from the stream keyed by
//! (seed, `p`, `i`), and photons are traced in fixed chunks gathered in chunk
//! order, so the map of a pass is the same for any thread count.

use super::grid::Grid;
use crate::integrator::bdpt::{trace_light_subpath, SubpathVertex, VertexKind};
use crate::integrator::Scene;
use crate::light::SceneSphere;
use crate::math::color::Rgb;
use crate::math::Vec3;
use crate::medium::PhaseFunction;
use crate::sampling::Sampler;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Photons traced by one task (a stop request is seen between chunks).
const CHUNK: usize = 2048;

/// Bytes one stored photon takes at the pass's peak: its position and data
/// in its task's buffer and again in the map, and its grid entries.
pub const PHOTON_PEAK_BYTES: u64 = (2
    * (std::mem::size_of::<Vec3>()
        + max_usize(
            std::mem::size_of::<SurfacePhoton>(),
            std::mem::size_of::<VolumePhoton>(),
        ))
    + 2 * std::mem::size_of::<u32>()) as u64;

const fn max_usize(a: usize, b: usize) -> usize {
    if a > b {
        a
    } else {
        b
    }
}

/// How a photon pass ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Built {
    /// The map is ready for the pass's eye samples.
    Ready,
    /// A stop request cut it short (the map is unusable).
    Stopped,
    /// Its photons would take more than the byte budget: at least this many
    /// were stored when tracing stopped (the map is unusable).
    OverBudget {
        /// Photons stored when the budget ran out.
        photons: u64,
    },
}

/// Salt of the photon streams: keeps them apart from every pixel stream.
const PHOTON_SALT: u64 = 0x5EED_F07C_0A11_u64;

/// A photon on a surface (its position is kept beside, for the grid).
#[derive(Clone, Copy, Debug)]
pub struct SurfacePhoton {
    /// Geometric normal of the surface it landed on, as stored.
    pub ng: Vec3,
    /// Unit direction back toward where it came from.
    pub w: Vec3,
    /// Its throughput from the light (flux per emitted path).
    pub beta: Rgb,
    /// Most scattering events an eye path may have before gathering it (depth limits).
    pub budget: u32,
}

/// A photon at a real scattering event in a medium.
#[derive(Clone, Copy, Debug)]
pub struct VolumePhoton {
    /// Unit direction back toward where it came from.
    pub w: Vec3,
    /// Its throughput from the light, σs included.
    pub beta: Rgb,
    /// The phase function where it scattered.
    pub phase: PhaseFunction,
    /// Most scattering events an eye path may have before gathering it.
    pub budget: u32,
}

/// Photons of one kind with their positions and grid.
pub struct Photons<T> {
    /// Positions, indexed like `data`.
    pub positions: Vec<Vec3>,
    /// Everything else of each photon.
    pub data: Vec<T>,
    /// The grid over `positions`.
    pub grid: Grid,
}

impl<T> Default for Photons<T> {
    fn default() -> Self {
        Photons {
            positions: Vec::new(),
            data: Vec::new(),
            grid: Grid::default(),
        }
    }
}

impl<T: Copy> Photons<T> {
    fn clear(&mut self) {
        self.positions.clear();
        self.data.clear();
    }

    fn extend(&mut self, other: &Photons<T>) {
        self.positions.extend_from_slice(&other.positions);
        self.data.extend_from_slice(&other.data);
    }

    fn push(&mut self, p: Vec3, photon: T) {
        self.positions.push(p);
        self.data.push(photon);
    }

    /// Bytes held, grid included.
    fn bytes(&self) -> usize {
        self.positions.capacity() * std::mem::size_of::<Vec3>()
            + self.data.capacity() * std::mem::size_of::<T>()
            + self.grid.bytes()
    }
}

/// What one task traces into: reused from pass to pass.
#[derive(Default)]
struct Chunk {
    path: Vec<SubpathVertex>,
    surface: Photons<SurfacePhoton>,
    volume: Photons<VolumePhoton>,
}

impl Chunk {
    /// Photons held, of both kinds.
    fn len(&self) -> usize {
        self.surface.positions.len() + self.volume.positions.len()
    }
}

/// The photon map of one pass.
#[derive(Default)]
pub struct PhotonMap {
    /// The pass it was built for.
    pub pass: Option<u32>,
    /// Gather radius of that pass.
    pub radius: f32,
    /// Light paths traced (the density estimates divide by it).
    pub emitted: u32,
    /// Photons on surfaces.
    pub surface: Photons<SurfacePhoton>,
    /// Photons in media.
    pub volume: Photons<VolumePhoton>,
    chunks: Vec<Chunk>,
}

impl PhotonMap {
    /// Traces `emitted` light paths for `pass` and grids their photons with
    /// `radius`, holding at most `budget` bytes of photons
    /// ([`PHOTON_PEAK_BYTES`] each). Whether the budget runs out does not
    /// depend on the thread count: the stored count only grows, so it passes
    /// the budget during the pass exactly when the whole pass's count would.
    pub fn build(
        &mut self,
        scene: &Scene,
        sphere: &SceneSphere,
        (pass, emitted, radius): (u32, u32, f32),
        (budget, cancel): (u64, &AtomicBool),
    ) -> Built {
        self.pass = None;
        let most = budget / PHOTON_PEAK_BYTES;
        let stored = AtomicU64::new(0);
        let over = AtomicBool::new(false);
        let n = emitted as usize;
        self.chunks.resize_with(n.div_ceil(CHUNK), Chunk::default);
        self.chunks
            .par_iter_mut()
            .enumerate()
            .for_each(|(c, chunk)| {
                chunk.surface.clear();
                chunk.volume.clear();
                for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    if cancel.load(Ordering::Relaxed) || over.load(Ordering::Relaxed) {
                        return;
                    }
                    let before = chunk.len();
                    trace_photon(scene, sphere, pass, i as u32, chunk);
                    let added = (chunk.len() - before) as u64;
                    if stored.fetch_add(added, Ordering::Relaxed) + added > most {
                        over.store(true, Ordering::Relaxed);
                    }
                }
            });
        if over.load(Ordering::Relaxed) {
            self.release();
            return Built::OverBudget {
                photons: stored.load(Ordering::Relaxed),
            };
        }
        if cancel.load(Ordering::Relaxed) {
            return Built::Stopped;
        }
        self.gather_chunks(radius);
        self.pass = Some(pass);
        self.radius = radius;
        self.emitted = emitted;
        Built::Ready
    }

    /// Moves the chunks' photons into the map, in chunk order, and grids them.
    fn gather_chunks(&mut self, radius: f32) {
        self.surface.clear();
        self.volume.clear();
        for chunk in &self.chunks {
            self.surface.extend(&chunk.surface);
            self.volume.extend(&chunk.volume);
        }
        self.surface.grid.build(&self.surface.positions, radius);
        self.volume.grid.build(&self.volume.positions, radius);
    }

    /// Frees every photon buffer (after a pass over its budget).
    fn release(&mut self) {
        *self = PhotonMap::default();
    }

    /// Bytes the map holds now (photons, grids and the tasks' buffers).
    pub fn bytes(&self) -> usize {
        let chunks: usize = self
            .chunks
            .iter()
            .map(|c| {
                c.surface.bytes()
                    + c.volume.bytes()
                    + c.path.capacity() * std::mem::size_of::<SubpathVertex>()
            })
            .sum();
        self.surface.bytes() + self.volume.bytes() + chunks
    }
}

/// Traces photon `index` of `pass` and keeps its photons in `chunk`.
fn trace_photon(scene: &Scene, sphere: &SceneSphere, pass: u32, index: u32, chunk: &mut Chunk) {
    let settings = &scene.settings;
    let mut sampler = Sampler::new(settings.seed ^ PHOTON_SALT, pass, u32::MAX, index as u64);
    let time = match settings.shutter {
        Some(_) => settings.sample_time(sampler.time_1d()),
        None => 0.0,
    };
    trace_light_subpath(scene, sphere, time, &mut sampler, &mut chunk.path);
    let path = &chunk.path;
    // path[1] is lit straight from the light: next-event estimation's part.
    for (j, v) in path.iter().enumerate().skip(2) {
        let Some(budget) = settings.max_depth.checked_sub(j as u32) else {
            break;
        };
        if !v.scatters() || !v.connectable() || !within_media_limit(settings, path, v) {
            continue;
        }
        match v.kind {
            VertexKind::Surface { .. } => chunk.surface.push(
                v.p,
                SurfacePhoton {
                    ng: v.ng,
                    w: v.w_prev,
                    beta: v.beta,
                    budget,
                },
            ),
            VertexKind::Medium { phase } => chunk.volume.push(
                v.p,
                VolumePhoton {
                    w: v.w_prev,
                    beta: v.beta,
                    phase,
                    budget,
                },
            ),
            _ => {}
        }
    }
}

/// True when the path a photon at `v` closes is in the path tracer's set:
/// at most `max_scatter_depth` medium events, and with that many the one
/// nearest the light is a medium event (the path tracer scatters no more
/// after its last allowed one). Eye paths reach a photon through Dirac
/// surfaces only, so the photon's own count is the path's.
fn within_media_limit(
    settings: &crate::integrator::Settings,
    path: &[SubpathVertex],
    v: &SubpathVertex,
) -> bool {
    let limit = settings.max_scatter_depth;
    match v.media.cmp(&limit) {
        std::cmp::Ordering::Less => true,
        std::cmp::Ordering::Equal => matches!(path[1].kind, VertexKind::Medium { .. }),
        std::cmp::Ordering::Greater => false,
    }
}
