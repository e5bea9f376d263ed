//! Light-traced contributions: splats land on any pixel of the display
//! window, whichever pixel's sample traced them, so the film keeps their sums
//! over the whole display window (a crop piece's splats fall outside its crop
//! too) and divides them by the samples per pixel of the render.

use crate::math::color::Rgb;

/// One light-tracing contribution landing on display pixel (`x`, `y`): radiance
/// summed into the film's splat layer, divided like the beauty by the samples
/// per pixel of the pass (not by the pixel's own count). Integrators that trace
/// from the lights (bidirectional, photon, Metropolis) hand these to the film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splat {
    /// Display column.
    pub x: u32,
    /// Display row (0 at the top).
    pub y: u32,
    /// Radiance, already weighted (MIS, pdfs, importance).
    pub radiance: Rgb,
}

/// f64 sums of the splats over the display window.
#[derive(Clone, Debug, PartialEq)]
pub struct Splats {
    /// Display window width.
    pub width: u32,
    /// Three sums per display pixel, row-major.
    pub sums: Vec<f64>,
    /// Splats left out: NaN or infinite radiance, or a pixel outside the display window.
    pub dropped: u64,
}

impl Splats {
    /// Zero sums over a `width`×`height` display window.
    pub fn new(width: u32, height: u32) -> Splats {
        Splats {
            width,
            sums: vec![0.0; 3 * width as usize * height as usize],
            dropped: 0,
        }
    }

    /// Adds `splats` in their order (the order is part of the result: f64
    /// addition is not associative, so callers add them in a fixed order).
    pub fn add(&mut self, splats: &[Splat]) {
        let height = (self.sums.len() / 3) / (self.width.max(1) as usize);
        for s in splats {
            if !s.radiance.is_finite() || s.x >= self.width || s.y as usize >= height {
                self.dropped += 1;
                continue;
            }
            let i = 3 * (s.y as usize * self.width as usize + s.x as usize);
            self.sums[i] += s.radiance.r as f64;
            self.sums[i + 1] += s.radiance.g as f64;
            self.sums[i + 2] += s.radiance.b as f64;
        }
    }

    /// Adds another film's (or pass's) sums of the same display window.
    pub fn add_sums(&mut self, other: &Splats) {
        for (a, b) in self.sums.iter_mut().zip(&other.sums) {
            *a += b;
        }
        self.dropped += other.dropped;
    }

    /// Sets every sum to zero, keeping the memory.
    pub fn clear(&mut self) {
        self.sums.fill(0.0);
        self.dropped = 0;
    }

    /// The sums at display pixel (`x`, `y`).
    pub fn at(&self, x: u32, y: u32) -> [f64; 3] {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.sums[i], self.sums[i + 1], self.sums[i + 2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splats_sum_per_display_pixel_and_bad_ones_are_dropped() {
        let mut s = Splats::new(4, 3);
        let at = |x, y, v| Splat {
            x,
            y,
            radiance: Rgb::new(v, 2.0 * v, 0.0),
        };
        s.add(&[
            at(3, 2, 1.0),
            at(3, 2, 0.5),
            at(0, 0, 4.0),
            at(4, 0, 1.0),
            at(0, 3, 1.0),
            at(1, 1, f32::NAN),
        ]);
        assert_eq!(s.at(3, 2), [1.5, 3.0, 0.0]);
        assert_eq!(s.at(0, 0), [4.0, 8.0, 0.0]);
        assert_eq!(s.at(1, 1), [0.0; 3]);
        assert_eq!(s.dropped, 3);
        let mut total = Splats::new(4, 3);
        total.add_sums(&s);
        total.add_sums(&s);
        assert_eq!(total.at(3, 2), [3.0, 6.0, 0.0]);
        assert_eq!(total.dropped, 6);
    }
}
