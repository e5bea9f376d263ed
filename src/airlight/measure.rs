//! Measuring the airlight demo's image: which pixels belong to which target,
//! their mean radiance and standard error, the σt fit, and the table and CSV.

use super::{AirlightMode, AirlightOptions, AirlightReport, Layout, Measured, TargetRow};
use super::{DISTANCES, EA_BRIGHT, EA_DARK, EA_EMISSION};
use crate::film::image_io::Image;
use crate::integrator::Scene;
use crate::math::color::Rgb;
use crate::math::Vec2;
use std::fmt::Write as _;

/// Which shape fully covers pixel (x, y): all five probe rays hit it; `None` for shapes, `Some(None)` for open sky.
fn pixel_owner(scene: &Scene, x: u32, y: u32) -> Option<Option<u32>> {
    let probes = [
        (0.5, 0.5),
        (0.0, 0.0),
        (0.9999, 0.0),
        (0.0, 0.9999),
        (0.9999, 0.9999),
    ];
    let mut owner = None;
    for (i, (u, v)) in probes.into_iter().enumerate() {
        let ray = scene.camera.generate_ray(x, y, Vec2::new(u, v));
        let shape = scene
            .geometry
            .intersect(&ray, f32::INFINITY)
            .map(|h| h.shape);
        if i == 0 {
            owner = shape;
        } else if shape != owner {
            return None;
        }
    }
    Some(owner)
}

/// Running sums of luminance and colour over pixels.
#[derive(Clone, Copy, Default)]
struct Sums {
    color: [f64; 3],
    lum: f64,
    lum2: f64,
    dist: f64,
    n: usize,
}

impl Sums {
    fn add(&mut self, c: Rgb, dist: f64) {
        for (k, v) in [c.r, c.g, c.b].into_iter().enumerate() {
            self.color[k] += v as f64;
        }
        let l = c.luminance() as f64;
        self.lum += l;
        self.lum2 += l * l;
        self.dist += dist;
        self.n += 1;
    }

    fn finish(&self) -> Measured {
        let n = self.n.max(1) as f64;
        let mean = self.lum / n;
        let var = (self.lum2 / n - mean * mean).max(0.0) * n / (n - 1.0).max(1.0);
        Measured {
            mean: Rgb::new(
                (self.color[0] / n) as f32,
                (self.color[1] / n) as f32,
                (self.color[2] / n) as f32,
            ),
            std_error: (var / n).sqrt(),
            pixels: self.n,
            distance: self.dist / n,
        }
    }
}

/// Measures targets and horizon in `image`, then fits σt.
pub(super) fn measure(scene: &Scene, image: &Image, options: &AirlightOptions) -> AirlightReport {
    let layout = Layout::new(options.width);
    let mut targets = vec![Sums::default(); 2 * DISTANCES.len()];
    let mut horizon = Sums::default();
    let half = layout.target_pixels() * 0.5;
    let centre_row = layout.height as f32 * 0.5;
    for y in 0..image.height as u32 {
        for x in 0..image.width as u32 {
            let c = image.pixels[(y * image.width as u32 + x) as usize];
            match pixel_owner(scene, x, y) {
                Some(Some(shape)) => {
                    let ray = scene.camera.generate_ray(x, y, Vec2::splat(0.5));
                    let t = scene
                        .geometry
                        .intersect(&ray, f32::INFINITY)
                        .map_or(0.0, |h| h.t);
                    targets[shape as usize].add(c, t as f64);
                }
                Some(None) if (y as f32 + 0.5 - centre_row).abs() < half => horizon.add(c, 0.0),
                _ => {}
            }
        }
    }
    let rows: Vec<TargetRow> = DISTANCES
        .iter()
        .enumerate()
        .map(|(i, &distance)| TargetRow {
            distance,
            bright: targets[2 * i].finish(),
            dark: targets[2 * i + 1].finish(),
        })
        .collect();
    let (sigma_t_fit, sigma_t_fit_std_error, fit_rows) = fit_sigma_t(&rows);
    let exact = (options.mode == AirlightMode::EmissionAbsorption).then_some((
        EA_BRIGHT as f64,
        EA_DARK as f64,
        EA_EMISSION as f64,
    ));
    AirlightReport {
        rows,
        horizon: horizon.finish(),
        sigma_t_true: 50f64.ln() / options.visibility as f64,
        sigma_t_fit,
        sigma_t_fit_std_error,
        fit_rows,
        exact,
        render_seconds: 0.0,
        files: Vec::new(),
        table: String::new(),
    }
}

/// Weighted least squares of ln(L_bright - L_dark) = a - σt·d (delta-method weights).
///
/// Returns (σt, its standard error, rows used); rows whose difference is below
/// 3 standard errors carry no usable logarithm and are left out.
pub fn fit_sigma_t(rows: &[TargetRow]) -> (f64, f64, usize) {
    let mut points = Vec::new();
    for r in rows {
        let delta = r.bright.mean.luminance() as f64 - r.dark.mean.luminance() as f64;
        let se = (r.bright.std_error.powi(2) + r.dark.std_error.powi(2)).sqrt();
        if delta > 3.0 * se && delta > 0.0 {
            // Var(ln Δ) ≈ (se/Δ)²; an exactly known Δ gets a large finite weight.
            let w = (delta / se.max(1e-9 * delta)).powi(2);
            let d = 0.5 * (r.bright.distance + r.dark.distance);
            points.push((d, delta.ln(), w));
        }
    }
    if points.len() < 2 {
        return (f64::NAN, f64::NAN, points.len());
    }
    let sw: f64 = points.iter().map(|p| p.2).sum();
    let xm = points.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let ym = points.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = points.iter().map(|p| p.2 * (p.0 - xm).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| p.2 * (p.0 - xm) * (p.1 - ym)).sum();
    let slope = sxy / sxx;
    (-slope, (1.0 / sxx).sqrt(), points.len())
}

/// Koschmieder's radiance at distance `d`.
pub fn koschmieder(l0: f64, l_air: f64, sigma_t: f64, d: f64) -> f64 {
    let t = (-sigma_t * d).exp();
    l0 * t + l_air * (1.0 - t)
}

/// L0 that puts Koschmieder's curve (true σt, measured L_air) through the nearest measurement.
fn extrapolated_l0(m: &Measured, l_air: f64, sigma_t: f64) -> f64 {
    l_air + (m.mean.luminance() as f64 - l_air) * (sigma_t * m.distance).exp()
}

pub(super) fn csv(report: &AirlightReport) -> String {
    let l_air = report.horizon.mean.luminance() as f64;
    let mut s = String::from(
        "distance_m,bright_luminance,bright_std_error,dark_luminance,dark_std_error,\
         bright_contrast,dark_contrast,koschmieder_bright,koschmieder_dark,horizon_luminance\n",
    );
    let (b0, d0) = l0_pair(report);
    for r in &report.rows {
        let (lb, ld) = (
            r.bright.mean.luminance() as f64,
            r.dark.mean.luminance() as f64,
        );
        let d = r.distance as f64;
        let _ = writeln!(
            s,
            "{d},{lb:.6},{:.6},{ld:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{l_air:.6}",
            r.bright.std_error,
            r.dark.std_error,
            (lb - l_air) / l_air,
            (ld - l_air) / l_air,
            koschmieder(b0, l_air, report.sigma_t_true, r.bright.distance),
            koschmieder(d0, l_air, report.sigma_t_true, r.dark.distance),
        );
    }
    s
}

/// (bright L0, dark L0): exact in `EmissionAbsorption` mode, else extrapolated from the nearest column.
pub(super) fn l0_pair(report: &AirlightReport) -> (f64, f64) {
    if let Some((b, d, _)) = report.exact {
        return (b, d);
    }
    let l_air = report.horizon.mean.luminance() as f64;
    let first = &report.rows[0];
    (
        extrapolated_l0(&first.bright, l_air, report.sigma_t_true),
        extrapolated_l0(&first.dark, l_air, report.sigma_t_true),
    )
}

pub(super) fn table(report: &AirlightReport) -> String {
    let l_air = report.horizon.mean.luminance() as f64;
    let (b0, d0) = l0_pair(report);
    let mut s = format!(
        "L_air (horizon) = {l_air:.4} ± {:.4}\n{:>8} {:>16} {:>10} {:>16} {:>10} {:>9} {:>9}\n",
        report.horizon.std_error,
        "d (m)",
        "bright",
        "Kosch.",
        "dark",
        "Kosch.",
        "C bright",
        "C dark"
    );
    for r in &report.rows {
        let (lb, ld) = (
            r.bright.mean.luminance() as f64,
            r.dark.mean.luminance() as f64,
        );
        let _ = writeln!(
            s,
            "{:>8} {:>8.4} ± {:<5.4} {:>10.4} {:>8.4} ± {:<5.4} {:>10.4} {:>9.4} {:>9.4}",
            r.distance,
            lb,
            r.bright.std_error,
            koschmieder(b0, l_air, report.sigma_t_true, r.bright.distance),
            ld,
            r.dark.std_error,
            koschmieder(d0, l_air, report.sigma_t_true, r.dark.distance),
            (lb - l_air) / l_air,
            (ld - l_air) / l_air,
        );
    }
    let _ = writeln!(
        s,
        "sigma_t fitted = {:.6} ± {:.6} 1/m ({} columns), true = {:.6} 1/m; visibility fitted {:.0} m, true {:.0} m",
        report.sigma_t_fit,
        report.sigma_t_fit_std_error,
        report.fit_rows,
        report.sigma_t_true,
        50f64.ln() / report.sigma_t_fit,
        50f64.ln() / report.sigma_t_true,
    );
    s
}
