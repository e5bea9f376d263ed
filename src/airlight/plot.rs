//! The airlight plot, rasterized by hand (no font or plotting dependency):
//! measured target luminance against distance (log axis) with Koschmieder's
//! curves for the true σt, and L_air as a dashed line.
//!
//! Bright targets are orange, dark ones blue; points carry ±2 standard-error
//! bars; tick labels use a built-in 3×5 digit font.

use super::measure::{koschmieder, l0_pair};
use super::AirlightReport;
use crate::color::Rgb;
use crate::image_io::Image;

const WIDTH: usize = 720;
const HEIGHT: usize = 440;
const LEFT: f64 = 64.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 16.0;
const BOTTOM: f64 = 36.0;
const X_MIN: f64 = 5.0;
const X_MAX: f64 = 4000.0;

const BRIGHT: Rgb = Rgb {
    r: 0.9,
    g: 0.35,
    b: 0.02,
};
const DARK: Rgb = Rgb {
    r: 0.02,
    g: 0.2,
    b: 0.8,
};
const GREY: Rgb = Rgb {
    r: 0.6,
    g: 0.6,
    b: 0.6,
};

/// 3×5 glyphs for `0`–`9` and `.`, one row per 3 bits, top row first.
const GLYPHS: [[u8; 5]; 11] = [
    [7, 5, 5, 5, 7],
    [2, 6, 2, 2, 7],
    [7, 1, 7, 4, 7],
    [7, 1, 7, 1, 7],
    [5, 5, 7, 1, 1],
    [7, 4, 7, 1, 7],
    [7, 4, 7, 5, 7],
    [7, 1, 1, 1, 1],
    [7, 5, 7, 5, 7],
    [7, 5, 7, 1, 7],
    [0, 0, 0, 0, 2],
];

struct Canvas {
    pixels: Vec<Rgb>,
    y_max: f64,
}

impl Canvas {
    fn set(&mut self, x: i64, y: i64, c: Rgb) {
        if (0..WIDTH as i64).contains(&x) && (0..HEIGHT as i64).contains(&y) {
            self.pixels[y as usize * WIDTH + x as usize] = c;
        }
    }

    fn px(&self, d: f64, l: f64) -> (f64, f64) {
        let fx = (d.log10() - X_MIN.log10()) / (X_MAX.log10() - X_MIN.log10());
        let fy = l / self.y_max;
        (
            LEFT + fx * (WIDTH as f64 - LEFT - RIGHT),
            HEIGHT as f64 - BOTTOM - fy * (HEIGHT as f64 - TOP - BOTTOM),
        )
    }

    fn dot(&mut self, x: f64, y: f64, r: i64, c: Rgb) {
        for dy in -r..=r {
            for dx in -r..=r {
                self.set(x.round() as i64 + dx, y.round() as i64 + dy, c);
            }
        }
    }

    /// A line of thickness 2r+1; `dash` > 0 leaves gaps every `dash` pixels.
    fn line(&mut self, a: (f64, f64), b: (f64, f64), r: i64, c: Rgb, dash: usize) {
        let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).max(1);
        for i in 0..=steps {
            if dash > 0 && (i / dash) % 2 == 1 {
                continue;
            }
            let f = i as f64 / steps as f64;
            self.dot(a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f, r, c);
        }
    }

    /// Text of digits and dots, scale 2, with its top-left corner at (x, y).
    fn text(&mut self, x: f64, y: f64, s: &str) {
        for (k, ch) in s.chars().enumerate() {
            let glyph = match ch {
                '0'..='9' => GLYPHS[ch as usize - '0' as usize],
                '.' => GLYPHS[10],
                _ => continue,
            };
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..3 {
                    if bits & (4 >> col) != 0 {
                        let gx = x as i64 + (k as i64 * 4 + col) * 2;
                        let gy = y as i64 + row as i64 * 2;
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            self.set(gx + dx, gy + dy, Rgb::BLACK);
                        }
                    }
                }
            }
        }
    }
}

/// The plot of `report` as a linear-RGB image.
pub(super) fn draw(report: &AirlightReport) -> Image {
    let l_air = report.horizon.mean.luminance() as f64;
    let (b0, d0) = l0_pair(report);
    let top = report
        .rows
        .iter()
        .map(|r| r.bright.mean.luminance() as f64)
        .fold(b0.max(d0).max(l_air), f64::max);
    let y_max = nice_ceiling(1.1 * top);
    let mut cv = Canvas {
        pixels: vec![Rgb::WHITE; WIDTH * HEIGHT],
        y_max,
    };
    let bottom = HEIGHT as f64 - BOTTOM;
    // Grid: decades in x, fifths in y, with labels.
    for d in [10.0, 100.0, 1000.0] {
        let (x, _) = cv.px(d, 0.0);
        cv.line((x, TOP), (x, bottom), 0, Rgb::splat(0.85), 0);
        let label = format!("{d}");
        cv.text(x - label.len() as f64 * 4.0, bottom + 8.0, &label);
    }
    for k in 0..=5 {
        let v = y_max * k as f64 / 5.0;
        let (_, y) = cv.px(X_MIN, v);
        cv.line((LEFT, y), (WIDTH as f64 - RIGHT, y), 0, Rgb::splat(0.85), 0);
        let label = format_tick(v);
        cv.text(LEFT - 8.0 - label.len() as f64 * 8.0, y - 5.0, &label);
    }
    cv.line((LEFT, TOP), (LEFT, bottom), 0, Rgb::BLACK, 0);
    cv.line(
        (LEFT, bottom),
        (WIDTH as f64 - RIGHT, bottom),
        0,
        Rgb::BLACK,
        0,
    );
    // L_air.
    let (_, y_air) = cv.px(X_MIN, l_air);
    cv.line((LEFT, y_air), (WIDTH as f64 - RIGHT, y_air), 0, GREY, 6);
    // Koschmieder curves for the true σt.
    for (l0, colour) in [(b0, BRIGHT), (d0, DARK)] {
        let mut prev = None;
        for i in 0..=400 {
            let d = X_MIN * (X_MAX / X_MIN).powf(i as f64 / 400.0);
            let p = cv.px(d, koschmieder(l0, l_air, report.sigma_t_true, d));
            if let Some(q) = prev {
                cv.line(q, p, 0, colour, 0);
            }
            prev = Some(p);
        }
    }
    // Measurements with ±2 standard-error bars.
    for r in &report.rows {
        for (m, colour) in [(&r.bright, BRIGHT), (&r.dark, DARK)] {
            let l = m.mean.luminance() as f64;
            let (x, y) = cv.px(m.distance, l);
            let (_, y_lo) = cv.px(m.distance, l - 2.0 * m.std_error);
            let (_, y_hi) = cv.px(m.distance, l + 2.0 * m.std_error);
            cv.line((x, y_lo), (x, y_hi), 0, Rgb::BLACK, 0);
            cv.dot(x, y, 3, Rgb::BLACK);
            cv.dot(x, y, 2, colour);
        }
    }
    Image {
        width: WIDTH,
        height: HEIGHT,
        pixels: cv.pixels,
        spp: 1,
        partial: false,
    }
}

/// The smallest of 1, 2, 5 × 10^k at or above `v`.
fn nice_ceiling(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let base = 10f64.powf(v.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * base)
        .find(|&c| c >= v)
        .unwrap_or(10.0 * base)
}

fn format_tick(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() {
        "0".into()
    } else {
        s.into()
    }
}
