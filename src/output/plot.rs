//! PNG plots (plotters, bitmap backend; text through the system's fontconfig fonts).

use crate::error::{Error, Result};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;

/// One curve of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (t, value).
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Dashed (used for exact solutions).
    pub dashed: bool,
}

impl Series {
    /// A solid curve.
    pub fn solid(label: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self {
            label: label.into(),
            points,
            color,
            dashed: false,
        }
    }

    /// A dashed curve (exact solution).
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Self {
            dashed: true,
            ..Self::solid(label, points, color)
        }
    }
}

/// Palette for several series (matplotlib's tab10).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

pub(crate) fn plot_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Line plot of several series against time, 1000×600 px.
pub fn time_plot(path: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<()> {
    let (x0, x1, y0, y1) = time_range(series).ok_or_else(|| plot_err(path, "nothing to plot"))?;
    let frame = Frame::time(title, y_label, SeriesLabelPosition::UpperRight);
    render(path, &frame, x0..x1, y0..y1, series)
}

/// Layout of a plot: 1000 px wide, `height` px high, sans-serif text.
struct Frame<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    height: u32,
    /// Stroke width of solid curves (dashed ones are 2).
    width: u32,
    /// Draw a marker at every point of solid curves.
    markers: bool,
    legend: SeriesLabelPosition,
    /// Log axes (tick labels on both axes with [`tick`]).
    log: bool,
}

impl<'a> Frame<'a> {
    /// A plot against time: 600 px high, thin curves, no markers.
    fn time(title: &'a str, y_label: &'a str, legend: SeriesLabelPosition) -> Self {
        Self {
            title,
            x_label: "t",
            y_label,
            height: 600,
            width: 1,
            markers: false,
            legend,
            log: false,
        }
    }
}

/// Key points of a log axis over `[lo, hi]`: 1, 2 and 5 times the powers of ten (the powers
/// alone when the axis spans more than three decades; 1 to 9 times them when fewer than two
/// would be inside), so that the tick labels are few and never run into each other.
fn log_key_points(lo: f64, hi: f64) -> Vec<f64> {
    let decades = lo.log10().floor() as i32..=hi.log10().ceil() as i32;
    let points = |mantissas: &[f64]| -> Vec<f64> {
        decades
            .clone()
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let wide = (hi / lo).log10() > 3.0;
    let nice = points(if wide { &[1.0] } else { &[1.0, 2.0, 5.0] });
    if nice.len() >= 2 {
        nice
    } else {
        points(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

/// Draws `series` on axes `x` × `y` (linear or log ranges) and writes the PNG.
fn render<X, Y>(path: &Path, frame: &Frame<'_>, x: X, y: Y, series: &[Series]) -> Result<()>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let err = |e: &dyn std::fmt::Display| plot_err(path, e);
    let root = BitMapBackend::new(path, (1000, frame.height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    draw_panel(&root, frame, x, y, series).map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// One chart (caption, axes, curves, legend) on a drawing area.
fn draw_panel<X, Y>(area: &Area<'_>, frame: &Frame<'_>, x: X, y: Y, series: &[Series]) -> DrawResult
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut chart = ChartBuilder::on(area)
        .caption(frame.title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)?;
    // Log key points are 1, 2, 5 (or 1 to 9) times a power of ten: one significant digit.
    let fmt = |v: &f64| match frame.log && !(1e-2..1e4).contains(v) {
        true => format!("{v:.0e}"),
        false => tick(*v),
    };
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(frame.x_label)
        .y_desc(frame.y_label)
        .y_label_formatter(&fmt)
        .label_style(("sans-serif", 16));
    if frame.log {
        mesh.x_label_formatter(&fmt);
    }
    mesh.draw()?;
    draw_curves(&mut chart, series, frame)
}

/// A tick label with four significant digits.
fn tick(v: f64) -> String {
    if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0');
        s.trim_end_matches('.').to_string()
    } else {
        format!("{v:.3e}")
    }
}

/// Data range of the series: `(x0, x1, y0, y1)` with a margin on y, or None if empty.
fn time_range(series: &[Series]) -> Option<(f64, f64, f64, f64)> {
    let pts = || series.iter().flat_map(|s| s.points.iter().copied());
    let (x0, x1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (x, _)| {
        (a.min(x), b.max(x))
    });
    let (y0, y1) = pts()
        .filter(|p| p.1.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, y)| {
            (a.min(y), b.max(y))
        });
    if !(x0.is_finite() && y0.is_finite()) {
        return None;
    }
    // A curve constant to 1e-3 of its size is drawn flat, not magnified.
    let pad = ((y1 - y0) * 0.08)
        .max(1e-3 * y0.abs().max(y1.abs()))
        .max(1e-12);
    Some((x0, x1, y0 - pad, y1 + pad))
}

/// Panels side by side (one chart per `(title, series)`, each with its own y range), all
/// against time, 1500 px wide.
pub fn time_panels(path: &Path, y_label: &str, panels: &[(String, Vec<Series>)]) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| plot_err(path, e);
    let root = BitMapBackend::new(path, (500 * panels.len() as u32, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let areas = root.split_evenly((1, panels.len()));
    for ((title, series), area) in panels.iter().zip(&areas) {
        let Some((x0, x1, y0, y1)) = time_range(series) else {
            return Err(err(&format!("panel {title}: nothing to plot")));
        };
        let frame = Frame::time(title, y_label, SeriesLabelPosition::LowerRight);
        draw_panel(area, &frame, x0..x1, y0..y1, series).map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))
}

type Chart<'a, X, Y> = ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>;
type DrawResult = std::result::Result<
    (),
    DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>,
>;

/// Draws the curves and the legend with the widths, markers and legend position of `frame`.
fn draw_curves<'a, X, Y>(
    chart: &mut Chart<'a, X, Y>,
    series: &[Series],
    frame: &Frame<'_>,
) -> DrawResult
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for s in series {
        let style = ShapeStyle::from(&s.color).stroke_width(if s.dashed { 2 } else { frame.width });
        let points = s.points.iter().copied();
        let anno = if s.dashed {
            chart.draw_series(DashedLineSeries::new(points, 8, 6, style))?
        } else {
            chart.draw_series(LineSeries::new(points, style))?
        };
        let c = s.color;
        let anno = anno.label(s.label.clone());
        if s.dashed {
            // Drawn as the curve is: two dashes.
            anno.legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (8, 0)], c.stroke_width(2))
                    + PathElement::new(vec![(12, 0), (20, 0)], c.stroke_width(2))
            });
        } else {
            anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        }
        if frame.markers && !s.dashed {
            chart.draw_series(
                s.points
                    .iter()
                    .map(|&p| Circle::new(p, 4, s.color.filled())),
            )?;
        }
    }
    chart
        .configure_series_labels()
        .position(frame.legend.clone())
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()
}

/// Axes of a log–log convergence plot.
#[derive(Debug, Clone, Copy)]
pub struct LogLog<'a> {
    /// Title.
    pub title: &'a str,
    /// Label of the x axis (`h` or `dt`).
    pub x_label: &'a str,
    /// Label of the y axis.
    pub y_label: &'a str,
    /// Slope of the reference triangle.
    pub slope: f64,
}

/// Log–log plot of errors against the mesh size or time step, one series per label, with a
/// reference slope triangle (legs over one factor 2 of x) below the data.
pub fn loglog_plot(path: &Path, axes: LogLog<'_>, series: &[Series]) -> Result<()> {
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.1.is_finite())
        .collect();
    if pts.is_empty() {
        return Err(plot_err(path, "nothing to plot"));
    }
    let (x0, x1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let (y0, y1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    let (xa, ya) = (x0, y0 * 0.6);
    let (xb, yb) = (2.0 * x0, ya * 2f64.powf(axes.slope));
    let triangle = vec![(xa, ya), (xb, ya), (xb, yb), (xa, ya)];
    let mut all: Vec<Series> = vec![Series::dashed(
        format!("slope {}", axes.slope),
        triangle,
        BLACK,
    )];
    all.extend(series.iter().cloned());
    // x: the data with a margin; y: the data and the triangle, with room above for the legend
    // (its height, 22 px a line over the 520 px of the axis, as a fraction of the log range).
    let (left, right) = (x0 / 1.25, x1 * 1.25);
    let (bottom, high) = (ya / 1.4, y1.max(yb) * 1.4);
    let legend = ((22 * all.len() + 16) as f64 / 520.0).min(0.6);
    let top = high * (high / bottom).powf(legend / (1.0 - legend));
    let frame = Frame {
        title: axes.title,
        x_label: axes.x_label,
        y_label: axes.y_label,
        height: 650,
        width: 2,
        markers: true,
        legend: SeriesLabelPosition::UpperLeft,
        log: true,
    };
    render(
        path,
        &frame,
        (left..right)
            .log_scale()
            .with_key_points(log_key_points(left, right)),
        (bottom..top)
            .log_scale()
            .with_key_points(log_key_points(bottom, top)),
        &all,
    )
}
