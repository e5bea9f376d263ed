//! Primary sample space (Kelemen et al. 2002) for Metropolis light transport:
//! the state of a chain is the vector of uniform numbers a path was made
//! from, and a mutation changes the numbers, not the path.
//!
//! Multiplexed MLT (Hachisuka, Pantaleoni and Jensen 2014) keeps three
//! streams, the camera subpath's, the light subpath's and the connection's,
//! interleaved in one vector (dimension `i` of stream `s` at `3i + s`), so a
//! longer camera subpath does not shift the light subpath's numbers. Free
//! flights, Russian roulette and null-collision decisions draw from the same
//! streams: a small step moves a tracking decision a little too.
//!
//! Mutations are lazy (as in pbrt-v3's `MLTSampler`): a number is mutated
//! only when the path asks for it, by as many small steps as iterations
//! passed since it last changed (one Gaussian of `σ·√n`), or made afresh if
//! a large step was accepted meanwhile. A large step draws every number
//! anew (an independence proposal); a small step adds a Gaussian of standard
//! deviation `small_step_size` and wraps around [0, 1), which is symmetric,
//! so the acceptance ratio is the ratio of the targets alone.

use rand::RngCore;
use rand_pcg::Pcg32;

/// One of the three interleaved streams of a multiplexed state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    /// The camera subpath: time, pixel, lens and its walk.
    Camera = 0,
    /// The light subpath: light pick, emission and its walk.
    Light = 1,
    /// The strategy choice and the connection's numbers (shadow rays, next-event picks).
    Connection = 2,
}

/// Streams interleaved in the vector.
const STREAMS: usize = 3;

/// One coordinate of the state and what a rejection restores.
#[derive(Clone, Copy, Debug, Default)]
struct Coordinate {
    value: f32,
    modified: u64,
    backup_value: f32,
    backup_modified: u64,
}

/// A chain's primary-sample vector, its mutation settings and its own random numbers.
#[derive(Clone, Debug)]
pub struct PrimarySamples {
    coords: Vec<Coordinate>,
    rng: Pcg32,
    sigma: f32,
    large_step_probability: f32,
    iteration: u64,
    large_step: bool,
    last_large_step: u64,
    stream: usize,
    next_dimension: [usize; STREAMS],
}

impl PrimarySamples {
    /// A state whose numbers are drawn by a PCG stream keyed by `key`; its
    /// first iteration is a large step (every number fresh), so the same key
    /// gives the same path again (bootstrap, then the chain it starts).
    pub fn new(key: u64, sigma: f32, large_step_probability: f32) -> PrimarySamples {
        let state = super::mix64(key);
        let stream = super::mix64(key.rotate_left(23) ^ 0x6D4C_5453);
        PrimarySamples {
            coords: Vec::new(),
            rng: Pcg32::new(state, stream),
            sigma,
            large_step_probability,
            // Iteration 1 is the state's first evaluation: a large step, never rejected.
            iteration: 1,
            large_step: true,
            last_large_step: 0,
            stream: 0,
            next_dimension: [0; STREAMS],
        }
    }

    /// [`PrimarySamples::new`] for another key, keeping the vector's memory
    /// (one state per thread for the bootstrap, no allocation per sample).
    pub fn reseed(&mut self, key: u64) {
        let mut coords = std::mem::take(&mut self.coords);
        coords.clear();
        *self = PrimarySamples {
            coords,
            ..PrimarySamples::new(key, self.sigma, self.large_step_probability)
        };
    }

    /// Starts a proposal: a large step with the large-step probability, else a small one.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.uniform() < self.large_step_probability;
        self.next_dimension = [0; STREAMS];
        self.stream = 0;
    }

    /// True when the current proposal is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Starts evaluating the same state again from its first number of every stream.
    pub fn rewind(&mut self) {
        self.next_dimension = [0; STREAMS];
        self.stream = 0;
    }

    /// Numbers drawn from now on come from `stream`, from its number `dimension` on
    /// (every strategy of a bootstrap sample reads the same connection numbers).
    pub fn seek(&mut self, stream: Stream, dimension: usize) {
        self.stream = stream as usize;
        self.next_dimension[self.stream] = dimension;
    }

    /// Sets number `dimension` of `stream` in the current state, drawing the
    /// numbers before it first if no evaluation asked for them yet.
    pub fn set(&mut self, stream: Stream, dimension: usize, value: f32) {
        let saved = (self.stream, self.next_dimension);
        self.seek(stream, dimension);
        self.next_1d();
        let c = &mut self.coords[dimension * STREAMS + stream as usize];
        c.value = value;
        c.backup_value = value;
        (self.stream, self.next_dimension) = saved;
    }

    /// Numbers drawn from now on come from `stream`.
    #[inline]
    pub fn set_stream(&mut self, stream: Stream) {
        self.stream = stream as usize;
    }

    /// The proposal becomes the state.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// The proposal is dropped: every number it changed gets its old value back.
    pub fn reject(&mut self) {
        let it = self.iteration;
        for c in self.coords.iter_mut().filter(|c| c.modified == it) {
            c.value = c.backup_value;
            c.modified = c.backup_modified;
        }
        self.iteration -= 1;
    }

    /// The next number of the current stream, mutated up to this iteration.
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let d = self.next_dimension[self.stream];
        self.next_dimension[self.stream] = d + 1;
        let index = d * STREAMS + self.stream;
        while index >= self.coords.len() {
            // A number no path asked for yet: a uniform one in the current
            // state, as every unused number of the infinite vector is.
            // Grows to the longest path met, then never again.
            let value = self.uniform();
            self.coords.push(Coordinate {
                value,
                modified: self.iteration - 1,
                backup_value: value,
                backup_modified: self.iteration - 1,
            });
        }
        self.ensure_ready(index);
        self.coords[index].value
    }

    /// Brings coordinate `index` up to the current iteration.
    fn ensure_ready(&mut self, index: usize) {
        let mut c = self.coords[index];
        if c.modified == self.iteration {
            return;
        }
        // A large step accepted since it last changed: it was drawn afresh then.
        if c.modified < self.last_large_step {
            c.value = self.uniform();
            c.modified = self.last_large_step;
        }
        c.backup_value = c.value;
        c.backup_modified = c.modified;
        if self.large_step {
            c.value = self.uniform();
        } else {
            let steps = (self.iteration - c.modified) as f64;
            let step = self.gaussian() * self.sigma as f64 * steps.sqrt();
            c.value = wrap(c.value as f64 + step);
        }
        c.modified = self.iteration;
        self.coords[index] = c;
    }

    /// A uniform number in [0, 1) from the chain's own generator.
    fn uniform(&mut self) -> f32 {
        (self.rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// A standard normal number (Box–Muller).
    fn gaussian(&mut self) -> f64 {
        let u1 = 1.0 - self.rng.next_u32() as f64 / 4_294_967_296.0;
        let u2 = self.rng.next_u32() as f64 / 4_294_967_296.0;
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// `v` wrapped into [0, 1): the small step lives on a torus, so it is symmetric.
fn wrap(v: f64) -> f32 {
    let w = (v - v.floor()) as f32;
    // f32 rounding of a value just below 1 (or of −tiny + 1) must not reach 1.
    if w >= 1.0 {
        0.0
    } else {
        w
    }
}

#[cfg(test)]
mod tests;
