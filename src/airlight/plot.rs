//! The airlight plot, drawn by plotters into a bitmap with the bundled
//! DejaVu Sans font (no system font needed).
//!
//! Upper panel: measured target luminance against distance (log axis) with
//! ±2 standard-error bars, Koschmieder's law for the true σt (solid), the
//! law with the fitted σt (dashed) and L_air measured at the horizon.
//! Lower panel: the residuals against the true-σt law with the same error
//! bars, at a scale where the bars are visible.

use super::measure::{koschmieder, l0_pair};
use super::{AirlightReport, Measured};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// Plot width in pixels.
pub const WIDTH: u32 = 900;
/// Plot height in pixels.
pub const HEIGHT: u32 = 720;
const X_MIN: f64 = 5.0;
const X_MAX: f64 = 4000.0;
/// Font family name under which the bundled font is registered.
const FONT: &str = "sans-serif";
const BRIGHT: RGBColor = RGBColor(230, 90, 5);
const DARK: RGBColor = RGBColor(5, 50, 205);
const AIR: RGBColor = RGBColor(120, 120, 120);

static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the bundled font with plotters (once per process).
fn register_font() {
    REGISTER.call_once(|| {
        // The font is compiled in and parsed by a unit test, so this cannot fail at run time.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES);
    });
}

/// The plot of `report` as 8-bit sRGB pixels, `WIDTH`×`HEIGHT`, row-major RGB.
pub(super) fn draw(report: &AirlightReport) -> Result<Vec<u8>, String> {
    register_font();
    let mut buf = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (upper, lower) = root.split_vertically(HEIGHT * 64 / 100);
        luminance_panel(&upper, report).map_err(|e| e.to_string())?;
        residual_panel(&lower, report).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(buf)
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Log-spaced distances across the x axis, for smooth curves.
fn curve_distances() -> impl Iterator<Item = f64> + Clone {
    (0..=300).map(|i| X_MIN * (X_MAX / X_MIN).powf(i as f64 / 300.0))
}

/// (distance, luminance, standard error) of each target of one kind.
fn points(report: &AirlightReport, bright: bool) -> Vec<(f64, f64, f64)> {
    report
        .rows
        .iter()
        .map(|r| {
            let m: &Measured = if bright { &r.bright } else { &r.dark };
            (m.distance, m.mean.luminance() as f64, m.std_error)
        })
        .collect()
}

fn luminance_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &AirlightReport,
) -> DrawResult<DB> {
    let l_air = report.horizon.mean.luminance() as f64;
    let (b0, d0) = l0_pair(report);
    let top = report
        .rows
        .iter()
        .map(|r| r.bright.mean.luminance() as f64)
        .fold(b0.max(d0).max(l_air), f64::max);
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "Airlight: targets in haze against Koschmieder's law (V = {:.0} m)",
                50f64.ln() / report.sigma_t_true
            ),
            (FONT, 22),
        )
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d((X_MIN..X_MAX).log_scale(), 0.0..1.15 * top)?;
    chart
        .configure_mesh()
        .x_desc("distance d (m, log scale)")
        .y_desc("luminance Y (W·m⁻²·sr⁻¹)")
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .draw()?;
    draw_laws(&mut chart, report, l_air)?;
    draw_measurements(&mut chart, report)?;
    chart
        .configure_series_labels()
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
}

/// The luminance panel's chart: distance (log) against luminance.
type LuminanceChart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, plotters::coord::types::RangedCoordf64>>;

/// Koschmieder's law with the true σt and with the fitted one, and the horizon's airlight.
fn draw_laws<DB: DrawingBackend>(
    chart: &mut LuminanceChart<'_, DB>,
    report: &AirlightReport,
    l_air: f64,
) -> DrawResult<DB> {
    let (b0, d0) = l0_pair(report);
    let s_true = report.sigma_t_true;
    for (l0, colour, name) in [(b0, BRIGHT, "bright"), (d0, DARK, "dark")] {
        chart
            .draw_series(LineSeries::new(
                curve_distances().map(|d| (d, koschmieder(l0, l_air, s_true, d))),
                colour.stroke_width(2),
            ))?
            .label(format!("Koschmieder, true σt = {s_true:.5} 1/m ({name})"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], colour.stroke_width(2)));
    }
    for (i, (curve, colour)) in fitted_curves(report, l_air).into_iter().enumerate() {
        let series = chart.draw_series(DashedLineSeries::new(
            curve,
            8,
            6,
            colour.mix(0.7).stroke_width(2),
        ))?;
        if i == 0 {
            series
                .label(format!(
                    "fitted σt = {:.5} ± {:.5} 1/m ({} columns)",
                    report.sigma_t_fit, report.sigma_t_fit_std_error, report.fit_rows
                ))
                .legend(|(x, y)| {
                    PathElement::new([(x, y), (x + 24, y)], BLACK.mix(0.7).stroke_width(2))
                });
        }
    }
    chart
        .draw_series(DashedLineSeries::new(
            [(X_MIN, l_air), (X_MAX, l_air)],
            6,
            5,
            AIR.stroke_width(2),
        ))?
        .label(format!("L_air at the horizon = {l_air:.4}"))
        .legend(|(x, y)| PathElement::new([(x, y), (x + 24, y)], AIR.stroke_width(2)));
    Ok(())
}

/// The measured targets with ±2 standard error bars.
fn draw_measurements<DB: DrawingBackend>(
    chart: &mut LuminanceChart<'_, DB>,
    report: &AirlightReport,
) -> DrawResult<DB> {
    for (bright, colour, name) in [(true, BRIGHT, "bright"), (false, DARK, "dark")] {
        let pts = points(report, bright);
        chart.draw_series(pts.iter().map(|&(d, l, se)| {
            ErrorBar::new_vertical(d, l - 2.0 * se, l, l + 2.0 * se, BLACK.stroke_width(2), 10)
        }))?;
        chart
            .draw_series(
                pts.iter()
                    .map(|&(d, l, _)| Circle::new((d, l), 5, colour.filled())),
            )?
            .label(format!("measured {name} targets, ±2 SE"))
            .legend(move |(x, y)| Circle::new((x + 12, y), 5, colour.filled()));
    }
    Ok(())
}

/// Koschmieder's law with the fitted σt through the nearest column, per target kind.
fn fitted_curves(report: &AirlightReport, l_air: f64) -> Vec<(Vec<(f64, f64)>, RGBColor)> {
    let s_fit = report.sigma_t_fit;
    if !s_fit.is_finite() {
        return Vec::new();
    }
    let first = &report.rows[0];
    [(&first.bright, BRIGHT), (&first.dark, DARK)]
        .into_iter()
        .map(|(m, colour)| {
            let l0 = l_air + (m.mean.luminance() as f64 - l_air) * (s_fit * m.distance).exp();
            let curve = curve_distances()
                .map(|d| (d, koschmieder(l0, l_air, s_fit, d)))
                .collect();
            (curve, colour)
        })
        .collect()
}

fn residual_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &AirlightReport,
) -> DrawResult<DB> {
    let l_air = report.horizon.mean.luminance() as f64;
    let (b0, d0) = l0_pair(report);
    let mut rows = Vec::new();
    for (bright, l0, colour) in [(true, b0, BRIGHT), (false, d0, DARK)] {
        for (d, l, se) in points(report, bright) {
            let r = l - koschmieder(l0, l_air, report.sigma_t_true, d);
            rows.push((d, r, se, colour));
        }
    }
    let span = rows
        .iter()
        .map(|&(_, r, se, _)| r.abs() + 2.5 * se)
        .fold(1e-6, f64::max);
    let mut chart = ChartBuilder::on(area)
        .caption(
            "residuals against the true-σt law, ±2 standard errors",
            (FONT, 16),
        )
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d((X_MIN..X_MAX).log_scale(), -span..span)?;
    chart
        .configure_mesh()
        .x_desc("distance d (m, log scale)")
        .y_desc("measured − law (W·m⁻²·sr⁻¹)")
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .draw()?;
    chart.draw_series(LineSeries::new(
        [(X_MIN, 0.0), (X_MAX, 0.0)],
        BLACK.stroke_width(1),
    ))?;
    // Bright and dark residuals at one distance would overlap: nudge them apart.
    chart.draw_series(rows.iter().map(|&(d, r, se, c)| {
        let d = if c == BRIGHT { d * 0.94 } else { d / 0.94 };
        ErrorBar::new_vertical(d, r - 2.0 * se, r, r + 2.0 * se, c.stroke_width(2), 10)
    }))?;
    chart.draw_series(rows.iter().map(|&(d, r, _, c)| {
        let d = if c == BRIGHT { d * 0.94 } else { d / 0.94 };
        Circle::new((d, r), 4, c.filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::airlight::TargetRow;
    use crate::math::color::Rgb;

    #[test]
    fn the_bundled_font_parses() {
        assert!(plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    }

    fn measured(l: f32, d: f64) -> Measured {
        Measured {
            mean: Rgb::splat(l),
            std_error: 0.01,
            pixels: 100,
            distance: d,
        }
    }

    /// Dark pixels inside the box [x0, x1) × [y0, y1) of an RGB buffer.
    fn dark_pixels(buf: &[u8], (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> usize {
        let mut n = 0;
        for y in y0..y1 {
            for x in x0..x1 {
                let i = ((y * WIDTH + x) * 3) as usize;
                n += usize::from(buf[i..i + 3].iter().all(|&v| v < 128));
            }
        }
        n
    }

    #[test]
    fn the_plot_has_its_size_titles_and_points() {
        let sigma: f64 = 0.004;
        let rows: Vec<TargetRow> = crate::airlight::DISTANCES
            .iter()
            .map(|&d| {
                let t = (-sigma * d as f64).exp() as f32;
                TargetRow {
                    distance: d,
                    bright: measured(0.45 * t + 0.27 * (1.0 - t), d as f64),
                    dark: measured(0.03 * t + 0.27 * (1.0 - t), d as f64),
                }
            })
            .collect();
        let report = AirlightReport {
            rows,
            horizon: measured(0.27, 1e4),
            sigma_t_true: sigma,
            sigma_t_fit: sigma,
            sigma_t_fit_std_error: 1e-4,
            fit_rows: 6,
            exact: None,
            render_seconds: 0.0,
            files: Vec::new(),
            table: String::new(),
        };
        let buf = draw(&report).unwrap();
        assert_eq!(buf.len(), (WIDTH * HEIGHT * 3) as usize);
        // Text drawn with the bundled font: the title strip and the x-axis title
        // under the upper panel (centred) hold glyphs; a margin corner holds none.
        let upper = HEIGHT * 64 / 100;
        assert!(dark_pixels(&buf, (300, 600), (8, 34)) > 200, "no title");
        assert!(
            dark_pixels(&buf, (360, 560), (upper - 30, upper - 8)) > 100,
            "no x title"
        );
        assert_eq!(dark_pixels(&buf, (0, 8), (0, 8)), 0);
        // The orange points are drawn in the upper panel.
        let orange = buf
            .chunks(3)
            .take((WIDTH * upper) as usize)
            .filter(|p| p == &[BRIGHT.0, BRIGHT.1, BRIGHT.2])
            .count();
        assert!(orange > 300, "{orange} orange pixels");
    }
}
