//! PNG plots of time series (plotters, bitmap backend), shared by every
//! command that draws: joint angles, residuals, estimates.
//!
//! Text uses the bundled DejaVu Sans (`assets/DejaVuSans.ttf`), so plots
//! render the same on a machine without system fonts.

use plotters::coord::types::RangedCoordf64;
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
    /// A filled band (an interval): the points trace its outline, the
    /// lower edge forward and the upper edge back ([`band`] builds them);
    /// one legend entry.
    Band,
}

/// The outline of the band between `lower` and `upper` over `x`, for a
/// [`Mark::Band`] series: `x` forward with `lower`, then back with `upper`.
pub fn band(x: &[f64], lower: &[f64], upper: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let xs = x.iter().chain(x.iter().rev()).copied().collect();
    let ys = lower.iter().chain(upper.iter().rev()).copied().collect();
    (xs, ys)
}

/// One curve of a panel.
#[derive(Clone, Debug)]
pub struct Series<'a> {
    /// Legend text.
    pub label: String,
    /// Abscissae (usually time \[s\]).
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
    /// Line or dots.
    pub mark: Mark,
    /// Index into the palette.
    pub color: usize,
}

impl<'a> Series<'a> {
    /// A curve of `y` over `x` drawn as `mark` in palette colour `color`.
    pub fn new(
        label: impl Into<String>,
        x: &'a [f64],
        y: &'a [f64],
        mark: Mark,
        color: usize,
    ) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            mark,
            color,
        }
    }
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

/// How a panel's y axis is laid out beyond what its data spans.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct YAxis {
    /// Fixed limits `(lower, upper)` in the unit of the data; values beyond
    /// them are drawn at the frame. `None`: the data's range.
    pub limits: Option<(f64, f64)>,
    /// Horizontal reference lines `(y, label)`, e.g. the 0 % line of a margin.
    pub lines: Vec<(f64, String)>,
}

/// Draws `panels` stacked vertically into a PNG at `path`, each y axis
/// fitted to its data.
pub fn draw(path: &Path, title: &str, x_label: &str, panels: &[Panel]) -> Result<(), PlotError> {
    let with_axes: Vec<(Panel, YAxis)> = panels
        .iter()
        .map(|p| (p.clone(), YAxis::default()))
        .collect();
    draw_with_axes(path, title, x_label, &with_axes)
}

/// Draws `panels` stacked vertically into a PNG at `path`, each with its
/// [`YAxis`], all over the x axis `x_label`.
pub fn draw_with_axes(
    path: &Path,
    title: &str,
    x_label: &str,
    panels: &[(Panel, YAxis)],
) -> Result<(), PlotError> {
    let labelled: Vec<(Panel, YAxis, &str)> = panels
        .iter()
        .map(|(p, a)| (p.clone(), a.clone(), x_label))
        .collect();
    draw_panels(path, title, &labelled)
}

/// The legend of a panel, in the order drawn: the series, then the
/// reference lines of its axis; what has an empty label has no entry.
pub fn legend_entries<'p>(panel: &'p Panel, axis: &'p YAxis) -> Vec<&'p str> {
    let lines = panel.series.iter().filter(|s| s.mark != Mark::Dots);
    let dots = panel.series.iter().filter(|s| s.mark == Mark::Dots);
    lines
        .chain(dots)
        .map(|s| s.label.as_str())
        .chain(axis.lines.iter().map(|(_, l)| l.as_str()))
        .filter(|l| !l.is_empty())
        .collect()
}

/// Draws `panels` stacked vertically into a PNG at `path`, each with its
/// [`YAxis`] and its own x axis label (`(panel, axis, x label)`). Bands and
/// lines first, measured dots on top (visible even under a good fit), then
/// the vertical markers with their labels staggered so that close ones do
/// not overlap, then the reference lines and the legend
/// ([`legend_entries`]).
pub fn draw_panels(
    path: &Path,
    title: &str,
    panels: &[(Panel, YAxis, &str)],
) -> Result<(), PlotError> {
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
    for ((panel, axis, x_label), area) in panels.iter().zip(areas.iter()) {
        draw_panel(area, x_label, panel, axis).map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// The error type of drawing on the bitmap backend.
type DrawError = DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>;

/// The chart of one panel, on the coordinates it is drawn in.
type Chart<'a> = ChartContext<'a, BitMapBackend<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// One panel: frame and mesh, series, markers, reference lines, legend.
fn draw_panel(
    area: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    x_label: &str,
    panel: &Panel,
    axis: &YAxis,
) -> Result<(), DrawError> {
    let (x0, x1) = range(panel.series.iter().flat_map(|s| s.x.iter().copied()));
    let (y0, y1) = axis
        .limits
        .unwrap_or_else(|| range(panel.series.iter().flat_map(|s| s.y.iter().copied())));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(&panel.y_label)
        .label_style(("sans-serif", 13))
        .draw()?;
    // Bands and lines first, then the measured dots on top of them.
    let lines = panel.series.iter().filter(|s| s.mark != Mark::Dots);
    let dots = panel.series.iter().filter(|s| s.mark == Mark::Dots);
    for s in lines.chain(dots) {
        draw_series(&mut chart, s, (y0, y1))?;
    }
    draw_markers(&mut chart, &panel.markers, (x0, x1), (y0, y1))?;
    for (y, label) in &axis.lines {
        let style = BLACK.stroke_width(1);
        let drawn = chart.draw_series(LineSeries::new([(x0, *y), (x1, *y)], style))?;
        if !label.is_empty() {
            drawn
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 14, y)], style));
        }
    }
    if !legend_entries(panel, axis).is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    Ok(())
}

/// One series: a line, or measured samples as dots with every k-th one
/// ringed (at most [`MAX_RINGS`] rings), so that the measurement stays
/// visible on top of a curve that fits it. Values beyond the y limits are
/// drawn at the frame.
fn draw_series<'a>(
    chart: &mut Chart<'a>,
    s: &Series,
    (y0, y1): (f64, f64),
) -> Result<(), DrawError> {
    let c = color(s.color);
    let pts: Vec<(f64, f64)> =
        s.x.iter()
            .zip(s.y.iter())
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| (*x, y.clamp(y0, y1)))
            .collect();
    let drawn = match s.mark {
        Mark::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?,
        Mark::Band => {
            let fill = c.mix(0.25).filled();
            let drawn = chart.draw_series(std::iter::once(Polygon::new(pts, fill)))?;
            if !s.label.is_empty() {
                drawn
                    .label(s.label.clone())
                    .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], fill));
            }
            return Ok(());
        }
        Mark::Dots => {
            let every = pts.len().div_ceil(MAX_RINGS).max(1);
            let rings = pts
                .iter()
                .step_by(every)
                .map(|p| Circle::new(*p, 4, c.stroke_width(1)));
            chart.draw_series(rings)?;
            chart.draw_series(pts.iter().map(|p| Circle::new(*p, 1, c.filled())))?
        }
    };
    if s.label.is_empty() {
        return Ok(());
    }
    // The legend: a line, or a ring (the other drawn invisible).
    let (line, ring) = match s.mark {
        Mark::Dots => (TRANSPARENT.stroke_width(0), c.stroke_width(1)),
        _ => (c.stroke_width(2), TRANSPARENT.stroke_width(0)),
    };
    drawn.label(s.label.clone()).legend(move |(x, y)| {
        EmptyElement::at((x, y))
            + PathElement::new([(0, 0), (14, 0)], line)
            + Circle::new((7, 0), 4, ring)
    });
    Ok(())
}

/// Vertical markers (latch instants) with labels staggered over rows: a
/// label closer than [`MARKER_LABEL_GAP`] of the x range to the previous
/// one in a row goes to the next row.
fn draw_markers<'a>(
    chart: &mut Chart<'a>,
    markers: &[(f64, String)],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Result<(), DrawError> {
    let mut visible: Vec<&(f64, String)> = markers
        .iter()
        .filter(|(x, _)| *x >= x0 && *x <= x1)
        .collect();
    visible.sort_by(|a, b| a.0.total_cmp(&b.0));
    let gap = MARKER_LABEL_GAP * (x1 - x0);
    let row_height = 0.07 * (y1 - y0);
    let mut row_end: Vec<f64> = Vec::new();
    for (x, label) in visible {
        chart.draw_series(LineSeries::new([(*x, y0), (*x, y1)], BLACK.mix(0.35)))?;
        let row = row_end
            .iter()
            .position(|end| *x >= *end)
            .unwrap_or(row_end.len());
        if row == row_end.len() {
            row_end.push(f64::NEG_INFINITY);
        }
        row_end[row] = x + gap;
        let at = (x + 0.004 * (x1 - x0), y1 - row as f64 * row_height);
        chart.draw_series(std::iter::once(Text::new(
            label.clone(),
            at,
            ("sans-serif", 12),
        )))?;
    }
    Ok(())
}

/// The most rings a measured series gets (every k-th sample ringed).
pub const MAX_RINGS: usize = 120;

/// The least distance between two marker labels in one row, as a fraction
/// of the x range \[1\]: the width of "latch 1" at 12 px on a 1000 px axis,
/// with a little air.
pub const MARKER_LABEL_GAP: f64 = 0.06;
