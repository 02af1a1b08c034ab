//! PNG plots of time series (plotters, bitmap backend), shared by every
//! command that draws: joint angles, residuals, estimates.
//!
//! Text uses the bundled DejaVu Sans (`assets/DejaVuSans.ttf`), so plots
//! render the same on a machine without system fonts.

use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../../assets/DejaVuSans.ttf");
        // A font that fails to parse only loses the text, never the plot.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A line.
    Line,
    /// Small dots (measured samples).
    Dots,
}

/// One curve of a panel.
#[derive(Clone, Debug)]
pub struct Series<'a> {
    /// Legend text.
    pub label: String,
    /// Abscissae (usually time [s]).
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
    /// Line or dots.
    pub mark: Mark,
    /// Index into the palette.
    pub color: usize,
}

/// One stacked panel of a figure.
#[derive(Clone, Debug, Default)]
pub struct Panel<'a> {
    /// Panel caption.
    pub title: String,
    /// Y axis label.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series<'a>>,
    /// Vertical markers `(x, label)`, e.g. latch instants.
    pub markers: Vec<(f64, String)>,
}

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {message}")]
pub struct PlotError {
    /// The PNG being written.
    pub path: String,
    /// What failed.
    pub message: String,
}

/// The palette (colour-blind friendly, Okabe–Ito).
pub fn color(i: usize) -> RGBColor {
    const P: [RGBColor; 8] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 0, 0),
        RGBColor(240, 228, 66),
    ];
    P[i % P.len()]
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-12 {
        return (lo - 1.0, hi + 1.0);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Draws `panels` stacked vertically into a PNG at `path`.
pub fn draw(path: &Path, title: &str, x_label: &str, panels: &[Panel]) -> Result<(), PlotError> {
    register_font();
    let err = |e: &dyn std::fmt::Display| PlotError {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let height = 40 + 300 * panels.len().max(1) as u32;
    let root = BitMapBackend::new(path, (1100, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root
        .titled(title, ("sans-serif", 22))
        .map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels.len().max(1), 1));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        let (x0, x1) = range(panel.series.iter().flat_map(|s| s.x.iter().copied()));
        let (y0, y1) = range(panel.series.iter().flat_map(|s| s.y.iter().copied()));
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(&panel.y_label)
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
        for s in &panel.series {
            let c = color(s.color);
            let pts =
                s.x.iter()
                    .zip(s.y.iter())
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|(x, y)| (*x, *y));
            let drawn = match s.mark {
                Mark::Line => chart
                    .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                    .map_err(|e| err(&e))?,
                Mark::Dots => chart
                    .draw_series(pts.map(|p| Circle::new(p, 1, c.filled())))
                    .map_err(|e| err(&e))?,
            };
            drawn
                .label(s.label.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 4), (x + 14, y + 4)], c.filled()));
        }
        for (x, label) in &panel.markers {
            if *x >= x0 && *x <= x1 {
                chart
                    .draw_series(LineSeries::new([(*x, y0), (*x, y1)], BLACK.mix(0.35)))
                    .map_err(|e| err(&e))?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        label.clone(),
                        (*x, y1),
                        ("sans-serif", 12),
                    )))
                    .map_err(|e| err(&e))?;
            }
        }
        if !panel.series.is_empty() {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .label_font(("sans-serif", 13))
                .draw()
                .map_err(|e| err(&e))?;
        }
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
