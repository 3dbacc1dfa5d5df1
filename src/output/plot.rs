//! Plots (plotters), each written twice: `<name>.png` (bitmap; text through the system's
//! fontconfig fonts) and `<name>.svg` beside it.
//!
//! Every curve carries the [`Style`] its caller chose (colour, marker, dash), so that a method
//! looks the same in every figure; the legend sits beside the axes and never covers data, with
//! each entry drawn as its curve is (dash and marker). A log axis is drawn in log10 coordinates
//! and clamped to the data that matter ([`clamp_log`]): points outside are marked at the edge
//! (▲ above, ▼ below), and a diverged curve is drawn clipped without setting the range. Each axis
//! has one tick format ([`TickFormat`]).

use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Palette for several series (matplotlib's tab10, then ColorBrewer's Dark2 but its magenta
/// and grey, and black): 16 colours, so that the 13 schemes each have one of their own.
pub const PALETTE: [RGBColor; 16] = [
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
    RGBColor(27, 158, 119),
    RGBColor(0, 0, 0),
    RGBColor(117, 112, 179),
    RGBColor(230, 171, 2),
    RGBColor(102, 166, 30),
    RGBColor(166, 118, 29),
];

/// The mark drawn at every point of a curve (convergence plots and scatters).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// No mark.
    None,
    /// ●
    Circle,
    /// ■
    Square,
    /// ▲
    TriangleUp,
    /// ◆
    Diamond,
    /// ▼
    TriangleDown,
    /// ⬢
    Hexagon,
}

/// The marks in the order a registry uses them.
pub const MARKERS: [Marker; 6] = [
    Marker::Circle,
    Marker::Square,
    Marker::TriangleUp,
    Marker::Diamond,
    Marker::TriangleDown,
    Marker::Hexagon,
];

/// How a curve's line is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// ───
    Solid,
    /// ‒ ‒ ‒
    Dashed,
    /// ·····
    Dotted,
    /// ── ──
    Long,
    /// No line: the marks alone (a scatter).
    None,
}

/// The dashes in the order variants of one method use them.
pub const DASHES: [Dash; 4] = [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::Long];

impl Dash {
    /// Dash and gap lengths in pixels (None: solid).
    fn pattern(self) -> Option<(u32, u32)> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some((8, 5)),
            Dash::Dotted => Some((2, 4)),
            Dash::Long => Some((16, 6)),
            Dash::None => Some((0, 1)),
        }
    }
}

/// How a curve looks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    /// Colour of the line and marks.
    pub color: RGBColor,
    /// Mark at every point.
    pub marker: Marker,
    /// Line pattern.
    pub dash: Dash,
    /// Marks drawn as outlines.
    pub hollow: bool,
}

impl Style {
    /// A solid line of `color`, no marks.
    pub const fn line(color: RGBColor) -> Self {
        Self {
            color,
            marker: Marker::None,
            dash: Dash::Solid,
            hollow: false,
        }
    }

    /// Black, dashed, no marks: an exact or reference solution.
    pub const REFERENCE: Style = Style {
        color: RGBColor(0, 0, 0),
        marker: Marker::None,
        dash: Dash::Dashed,
        hollow: false,
    };
}

/// One curve of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
    /// How it looks.
    pub style: Style,
    /// A diverged run: drawn clipped to the range of the others, which it does not set.
    pub diverged: bool,
}

impl Series {
    /// A curve.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            label: label.into(),
            points,
            style,
            diverged: false,
        }
    }

    /// An exact or reference curve (black, dashed).
    pub fn reference(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::REFERENCE)
    }
}

pub(crate) fn plot_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Something drawn on a white canvas of a given size, on any plotters backend.
pub(crate) trait Picture {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws on `root` (already white).
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String>;
}

/// Writes `picture` to `path` (PNG) and to the same path with extension `svg`, each rendered to
/// a temporary file renamed over its name when complete ([`super::atomic`]).
pub(crate) fn save(path: &Path, picture: &impl Picture) -> Result<()> {
    let size = picture.size();
    super::atomic::write_with(path, |tmp| {
        paint(
            BitMapBackend::new(tmp, size).into_drawing_area(),
            picture,
            path,
        )
    })?;
    let svg = path.with_extension("svg");
    super::atomic::write_with(&svg, |tmp| {
        paint(
            SVGBackend::new(tmp, size).into_drawing_area(),
            picture,
            &svg,
        )
    })
}

/// A white background, then `picture`, on `root`; errors name `path`.
fn paint<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    picture: &impl Picture,
    path: &Path,
) -> Result<()> {
    root.fill(&WHITE).map_err(|e| plot_err(path, e))?;
    picture.draw(&root).map_err(|e| plot_err(path, e))?;
    root.present().map_err(|e| plot_err(path, e))
}

/// Any plotters drawing error as text.
pub(crate) fn text<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// One axis: label, range of the values drawn, log or linear.
#[derive(Debug, Clone)]
pub struct Axis {
    /// Label (with the unit or symbol).
    pub label: String,
    /// Smallest value shown.
    pub lo: f64,
    /// Largest value shown.
    pub hi: f64,
    /// Logarithmic.
    pub log: bool,
}

impl Axis {
    /// The plot coordinate of a value (log10 on a log axis).
    fn at(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// The plot-coordinate range.
    fn range(&self) -> (f64, f64) {
        (self.at(self.lo), self.at(self.hi))
    }

    /// Tick positions (plot coordinates) and their one format.
    fn ticks(&self) -> (Vec<f64>, TickFormat) {
        if self.log {
            let keys = log_key_points(self.lo, self.hi);
            let format = TickFormat::for_log(&keys);
            (keys.iter().map(|k| k.log10()).collect(), format)
        } else {
            let step = nice_step((self.hi - self.lo) / 7.0);
            let first = (self.lo / step).ceil() as i64;
            let last = (self.hi / step).floor() as i64;
            let keys = (first..=last).map(|k| k as f64 * step).collect();
            (
                keys,
                TickFormat::for_step(step, self.lo.abs().max(self.hi.abs())),
            )
        }
    }
}

/// 1, 2 or 5 times a power of ten, the nearest above `x`.
fn nice_step(x: f64) -> f64 {
    let p = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= x)
        .unwrap_or(10.0 * p)
}

/// Key points of a log axis over `[lo, hi]`: 1, 2 and 5 times the powers of ten (the powers
/// alone when the axis spans more than three decades, every k-th of them beyond eight; 1 to 9
/// times them when fewer than two would be inside), so that the tick labels are few and never
/// run into each other.
fn log_key_points(lo: f64, hi: f64) -> Vec<f64> {
    let decades = lo.log10().floor() as i32..=hi.log10().ceil() as i32;
    let points = |mantissas: &[f64]| -> Vec<f64> {
        decades
            .clone()
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let span = (hi / lo).log10();
    let wide = span > 3.0;
    let nice = points(if wide { &[1.0] } else { &[1.0, 2.0, 5.0] });
    // More than eight decades: every k-th power only, at most about eight labels.
    let every = (span / 8.0).ceil().max(1.0) as i32;
    let nice: Vec<f64> = nice
        .into_iter()
        .filter(|v| v.log10().round() as i32 % every == 0)
        .collect();
    if nice.len() >= 2 {
        nice
    } else {
        points(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

/// The one format of an axis' tick labels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TickFormat {
    /// Fixed point with this many decimals (`0.25`, `-1.50`).
    Fixed(usize),
    /// Scientific with this many mantissa decimals (`2e-3`, `1.5e6`).
    Scientific(usize),
    /// Shortest decimal of each value (`0.002`, `0.01`, `20`: a log axis within 1e-3 … 1e4).
    Shortest,
}

impl TickFormat {
    /// The format of linear ticks `step` apart on values up to `magnitude`.
    fn for_step(step: f64, magnitude: f64) -> Self {
        let step_exp = step.log10().floor() as i32;
        if step < 1e-4 || magnitude >= 1e6 {
            let mag_exp = magnitude.log10().floor() as i32;
            TickFormat::Scientific((mag_exp - step_exp).max(0) as usize)
        } else {
            TickFormat::Fixed((-step_exp).max(0) as usize)
        }
    }

    /// The format of log key points (one significant digit each).
    fn for_log(keys: &[f64]) -> Self {
        if keys.iter().all(|k| (1e-3..1e4).contains(k)) {
            TickFormat::Shortest
        } else {
            TickFormat::Scientific(0)
        }
    }

    /// The label of `v` (a negative zero is written as zero).
    pub fn label(self, v: f64) -> String {
        match self {
            TickFormat::Fixed(d) => {
                let s = format!("{v:.d$}");
                let zero = s
                    .trim_start_matches('-')
                    .chars()
                    .all(|c| c == '0' || c == '.');
                if zero {
                    s.trim_start_matches('-').to_string()
                } else {
                    s
                }
            }
            TickFormat::Scientific(d) => format!("{v:.d$e}"),
            TickFormat::Shortest => {
                let s = format!("{v:.6}");
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            }
        }
    }
}

/// The range of a log axis over `values` (positive, finite), clamped to the data that matter:
/// at most 5 decades below and 3 above the median (in log), so that a round-off error or a
/// blown-up run does not squeeze the others into a line.
pub fn clamp_log(values: &[f64]) -> Option<(f64, f64)> {
    let mut logs: Vec<f64> = values
        .iter()
        .filter(|v| v.is_finite() && **v > 0.0)
        .map(|v| v.log10())
        .collect();
    if logs.is_empty() {
        return None;
    }
    logs.sort_by(f64::total_cmp);
    let median = logs[logs.len() / 2];
    let lo = logs[0].max(median - 5.0);
    let hi = logs[logs.len() - 1].min(median + 3.0);
    Some((10f64.powf(lo), 10f64.powf(hi)))
}

/// The linear range of the series that did not diverge, with a margin; a curve constant to
/// 1e-3 of its size is drawn flat, not magnified.
fn linear_range(series: &[Series]) -> Option<(f64, f64, f64, f64)> {
    let pts = || {
        series
            .iter()
            .filter(|s| !s.diverged)
            .flat_map(|s| s.points.iter().copied())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    let (x0, x1, y0, y1) = pts().fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |b, p| (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1)),
    );
    if !(x0.is_finite() && y0.is_finite()) {
        return None;
    }
    let pad = ((y1 - y0) * 0.06)
        .max(1e-3 * y0.abs().max(y1.abs()))
        .max(1e-12);
    Some((x0, x1.max(x0 + 1e-12), y0 - pad, y1 + pad))
}

/// At most four points per pixel column (first, lowest, highest, last) of a long curve: the same
/// picture, smaller files.
fn decimate(points: &[(f64, f64)], x: (f64, f64), columns: usize) -> Vec<(f64, f64)> {
    if points.len() <= 4 * columns {
        return points.to_vec();
    }
    let width = (x.1 - x.0) / columns as f64;
    let column = |p: &(f64, f64)| ((p.0 - x.0) / width).floor() as i64;
    let mut out = Vec::with_capacity(4 * columns);
    let mut start = 0;
    while start < points.len() {
        let c = column(&points[start]);
        let end = start
            + points[start..]
                .iter()
                .take_while(|p| column(p) == c)
                .count();
        let run = &points[start..end];
        let lowest = run
            .iter()
            .enumerate()
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let highest = run
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let mut keep = vec![0, run.len() - 1];
        keep.extend(lowest.map(|l| l.0));
        keep.extend(highest.map(|h| h.0));
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|k| run[k]));
        start = end;
    }
    out
}

/// The parts of a polyline inside `[x0, x1] × [y0, y1]` (Liang–Barsky on every segment; a NaN
/// point breaks the line).
fn clip(points: &[(f64, f64)], (x0, x1, y0, y1): (f64, f64, f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut parts: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let inside = |p: (f64, f64)| (x0..=x1).contains(&p.0) && (y0..=y1).contains(&p.1);
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let segment = if a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite() {
            clip_segment(a, b, (x0, x1, y0, y1))
        } else {
            None
        };
        match segment {
            Some((p, q)) => {
                if current.last() != Some(&p) {
                    if !current.is_empty() {
                        parts.push(std::mem::take(&mut current));
                    }
                    current.push(p);
                }
                current.push(q);
                if !inside(b) {
                    parts.push(std::mem::take(&mut current));
                }
            }
            None => {
                if !current.is_empty() {
                    parts.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        parts.push(current);
    }
    if points.len() == 1 && inside(points[0]) {
        parts.push(points.to_vec());
    }
    parts
}

/// The part of segment `a b` inside the box, if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

/// The outline of `marker` of radius `r` around the origin, in pixels.
fn marker_outline(marker: Marker, r: i32) -> Vec<(i32, i32)> {
    let polygon = |n: usize, phase: f64, radius: f64| -> Vec<(i32, i32)> {
        (0..n)
            .map(|k| {
                let a = phase + std::f64::consts::TAU * k as f64 / n as f64;
                (
                    (radius * a.cos()).round() as i32,
                    (radius * a.sin()).round() as i32,
                )
            })
            .collect()
    };
    let rf = r as f64;
    match marker {
        Marker::None => Vec::new(),
        Marker::Circle => polygon(16, 0.0, rf),
        Marker::Square => vec![
            (-r + 1, -r + 1),
            (r - 1, -r + 1),
            (r - 1, r - 1),
            (-r + 1, r - 1),
        ],
        Marker::TriangleUp => polygon(3, -std::f64::consts::FRAC_PI_2, rf * 1.2),
        Marker::TriangleDown => polygon(3, std::f64::consts::FRAC_PI_2, rf * 1.2),
        Marker::Diamond => polygon(4, 0.0, rf * 1.25),
        Marker::Hexagon => polygon(6, 0.0, rf * 1.1),
    }
}

/// Draws `marker` centred at pixel `(x, y)` of `area`.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    style: &Style,
    r: i32,
) -> std::result::Result<(), String> {
    let outline: Vec<(i32, i32)> = marker_outline(style.marker, r)
        .into_iter()
        .map(|(dx, dy)| (x + dx, y + dy))
        .collect();
    if outline.is_empty() {
        return Ok(());
    }
    let fill = if style.hollow { WHITE } else { style.color };
    area.draw(&Polygon::new(outline.clone(), fill.filled()))
        .map_err(text)?;
    let mut closed = outline;
    closed.push(closed[0]);
    area.draw(&PathElement::new(closed, style.color.stroke_width(2)))
        .map_err(text)
}

/// Draws a polyline of pixels with `style`'s dash.
pub(crate) fn draw_line<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    pixels: Vec<(i32, i32)>,
    style: &Style,
    width: u32,
) -> std::result::Result<(), String> {
    if pixels.len() < 2 || style.dash == Dash::None {
        return Ok(());
    }
    let stroke = style.color.stroke_width(width);
    match style.dash.pattern() {
        None => area.draw(&PathElement::new(pixels, stroke)).map_err(text),
        Some((on, off)) => {
            // Dashes along the polyline's arc length, continuing across its vertices.
            let mut drawn = 0.0f64;
            let period = (on + off) as f64;
            let mut piece: Vec<(i32, i32)> = Vec::new();
            for w in pixels.windows(2) {
                let (a, b) = (w[0], w[1]);
                let len = (((b.0 - a.0).pow(2) + (b.1 - a.1).pow(2)) as f64).sqrt();
                let mut s = 0.0;
                while s < len {
                    let phase = (drawn + s) % period;
                    let on_dash = phase < on as f64;
                    let left = if on_dash {
                        on as f64 - phase
                    } else {
                        period - phase
                    };
                    let t1 = (s + left).min(len);
                    let at = |t: f64| {
                        let f = if len > 0.0 { t / len } else { 0.0 };
                        (
                            a.0 + (f * (b.0 - a.0) as f64).round() as i32,
                            a.1 + (f * (b.1 - a.1) as f64).round() as i32,
                        )
                    };
                    if on_dash {
                        if piece.is_empty() {
                            piece.push(at(s));
                        }
                        piece.push(at(t1));
                    } else if piece.len() >= 2 {
                        area.draw(&PathElement::new(std::mem::take(&mut piece), stroke))
                            .map_err(text)?;
                    } else {
                        piece.clear();
                    }
                    s = t1;
                }
                drawn += len;
            }
            if piece.len() >= 2 {
                area.draw(&PathElement::new(piece, stroke)).map_err(text)?;
            }
            Ok(())
        }
    }
}

/// What a chart draws besides its curves.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Extras {
    /// Stroke width of the curves.
    pub width: u32,
    /// Radius of the marks.
    pub marker: i32,
    /// Marks at this many evenly spaced abscissae per curve (shifted from curve to curve),
    /// instead of at every point (0): for curves of thousands of samples.
    pub spread: usize,
}

/// Axes with title and curves on `area`: the curves clipped to the axes, their marks, points off
/// a log axis marked at its edge. Returns the pixel mapping for further drawing.
fn draw_chart<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    (x, y): (&Axis, &Axis),
    series: &[Series],
    extras: Extras,
) -> std::result::Result<Mapping, String> {
    let (xr, yr) = (x.range(), y.range());
    let (xk, xf) = x.ticks();
    let (yk, yf) = y.ticks();
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 21))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(84)
        .build_cartesian_2d(Ticked::new(xr, xk), Ticked::new(yr, yk))
        .map_err(text)?;
    let value = |axis: &Axis, p: f64| if axis.log { 10f64.powf(p) } else { p };
    let xl = |p: &f64| xf.label(value(x, *p));
    let yl = |p: &f64| yf.label(value(y, *p));
    chart
        .configure_mesh()
        .x_desc(x.label.as_str())
        .y_desc(y.label.as_str())
        .x_label_formatter(&xl)
        .y_label_formatter(&yl)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 16))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(text)?;
    let (px, py) = chart.plotting_area().get_pixel_range();
    let base = area.get_base_pixel();
    let mapping = Mapping {
        x: (xr.0, xr.1),
        y: (yr.0, yr.1),
        px: (px.start - base.0, px.end - base.0),
        py: (py.start - base.1, py.end - base.1),
    };
    let root = area.strip_coord_spec();
    let columns = (px.end - px.start).max(1) as usize;
    for (k, s) in series.iter().enumerate() {
        let pts: Vec<(f64, f64)> = s.points.iter().map(|p| (x.at(p.0), y.at(p.1))).collect();
        let pts = decimate(&pts, xr, columns);
        for part in clip(&pts, (xr.0, xr.1, yr.0, yr.1)) {
            let pixels = part.iter().map(|&p| mapping.pixel(p)).collect();
            draw_line(&root, pixels, &s.style, extras.width)?;
        }
        let marked: Vec<(f64, f64)> = if extras.spread > 0 {
            let shift = (k + 1) as f64 / (series.len() + 1) as f64;
            (0..extras.spread)
                .filter_map(|j| {
                    let at = xr.0 + (j as f64 + shift) * (xr.1 - xr.0) / extras.spread as f64;
                    let i = pts.partition_point(|p| p.0 < at);
                    pts.get(i).copied()
                })
                .collect()
        } else {
            pts.clone()
        };
        for &p in &marked {
            if !p.0.is_finite() || !(xr.0..=xr.1).contains(&p.0) {
                continue;
            }
            if (yr.0..=yr.1).contains(&p.1) {
                draw_marker(&root, mapping.pixel(p), &s.style, extras.marker)?;
            } else if y.log && !p.1.is_nan() {
                let (edge, marker) = if p.1 > yr.1 {
                    (yr.1, Marker::TriangleUp)
                } else {
                    (yr.0, Marker::TriangleDown)
                };
                let (cx, cy) = mapping.pixel((p.0, edge));
                let style = Style {
                    marker,
                    hollow: true,
                    ..s.style
                };
                let dy = if marker == Marker::TriangleUp { 7 } else { -7 };
                draw_marker(&root, (cx, cy + dy), &style, 6)?;
            }
        }
    }
    Ok(mapping)
}

/// A linear axis in plot coordinates with its own tick positions (plotters' `with_key_points`
/// on `f64` ranges has no label formatter).
#[derive(Debug, Clone)]
pub(crate) struct Ticked {
    lo: f64,
    hi: f64,
    keys: Vec<f64>,
}

impl Ticked {
    fn new((lo, hi): (f64, f64), keys: Vec<f64>) -> Self {
        Self { lo, hi, keys }
    }

    /// A linear axis over `[lo, hi]` and the format of its tick labels.
    pub(crate) fn linear(lo: f64, hi: f64) -> (Self, TickFormat) {
        let axis = Axis {
            label: String::new(),
            lo,
            hi,
            log: false,
        };
        let (keys, format) = axis.ticks();
        (Self::new((lo, hi), keys), format)
    }
}

impl plotters::coord::ranged1d::Ranged for Ticked {
    type FormatOption = plotters::coord::ranged1d::DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let f = (value - self.lo) / (self.hi - self.lo);
        limit.0 + (f * (limit.1 - limit.0) as f64).round() as i32
    }

    fn key_points<Hint: plotters::coord::ranged1d::KeyPointHint>(&self, _hint: Hint) -> Vec<f64> {
        self.keys.clone()
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

/// Plot coordinates to pixels of one chart.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mapping {
    x: (f64, f64),
    y: (f64, f64),
    /// Pixel ranges relative to the chart's drawing area.
    px: (i32, i32),
    py: (i32, i32),
}

impl Mapping {
    /// The pixel (relative to the chart's drawing area) of plot coordinates `(x, y)`.
    pub(crate) fn pixel(&self, (x, y): (f64, f64)) -> (i32, i32) {
        let fx = (x - self.x.0) / (self.x.1 - self.x.0);
        let fy = (y - self.y.0) / (self.y.1 - self.y.0);
        (
            self.px.0 + (fx * (self.px.1 - self.px.0) as f64).round() as i32,
            self.py.1 - (fy * (self.py.1 - self.py.0) as f64).round() as i32,
        )
    }
}

/// Width of the legend column beside the axes.
const LEGEND: u32 = 270;

/// The legend of `series` in its own area: each entry drawn as its curve is (line with its dash
/// and a mark), its label wrapped to the column; a note when marks were drawn at an edge.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    series: &[&Series],
    note: Option<&str>,
    width: u32,
) -> std::result::Result<(), String> {
    let font = ("sans-serif", 15).into_font();
    let style = TextStyle::from(font.clone()).color(&BLACK);
    let (w, _) = area.dim_in_pixel();
    let text_width = w.saturating_sub(56);
    let mut y = 58;
    for s in series.iter().filter(|s| !s.label.is_empty()) {
        let sample = Style {
            hollow: s.style.hollow,
            ..s.style
        };
        draw_line(area, vec![(6, y), (40, y)], &sample, width)?;
        draw_marker(area, (23, y), &sample, 5)?;
        let lines = wrap(area, &s.label, &font, text_width);
        for (k, line) in lines.iter().enumerate() {
            area.draw_text(line, &style, (48, y - 8 + 18 * k as i32))
                .map_err(text)?;
        }
        y += 18 * (lines.len() as i32 - 1) + 26;
    }
    if let Some(note) = note {
        let grey = BLACK.mix(0.75);
        let small = TextStyle::from(("sans-serif", 13).into_font()).color(&grey);
        for line in wrap(
            area,
            note,
            &("sans-serif", 13).into_font(),
            w.saturating_sub(12),
        ) {
            area.draw_text(&line, &small, (6, y)).map_err(text)?;
            y += 16;
        }
    }
    Ok(())
}

/// `label` in lines of at most `width` pixels, broken after `;`, `,`, a space or `_` (a
/// method's name longer than the column, `contact_stabilised_newmark`).
fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    label: &str,
    font: &FontDesc<'_>,
    width: u32,
) -> Vec<String> {
    let fits = |s: &str| {
        area.estimate_text_size(s, &TextStyle::from(font.clone()))
            .map_or(s.chars().count() as u32 * 8 <= width, |(w, _)| w <= width)
    };
    let mut words: Vec<String> = Vec::new();
    let mut word = String::new();
    for c in label.chars() {
        word.push(c);
        if matches!(c, ';' | ',' | ' ' | '_') {
            words.push(std::mem::take(&mut word));
        }
    }
    words.push(word);
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for w in words {
        let candidate = format!("{line}{w}");
        if line.is_empty() || fits(candidate.trim_end()) {
            line = candidate;
        } else {
            lines.push(line.trim_end().to_string());
            line = w;
        }
    }
    lines.push(line.trim_end().to_string());
    lines
}

/// Axes with their curves and, beside them, the legend (and a note under it); a slope
/// triangle on a log–log chart.
pub(crate) struct Chart<'a> {
    /// Title.
    pub title: &'a str,
    /// Curves.
    pub series: &'a [Series],
    /// Axes.
    pub x: Axis,
    /// Axes.
    pub y: Axis,
    /// Widths and marks.
    pub extras: Extras,
    /// Height in pixels (the chart is 1000 wide, the legend [`LEGEND`]).
    pub height: u32,
    /// Slope triangle: slope and corners (values; log–log charts only).
    pub triangle: Option<(f64, [(f64, f64); 3])>,
    /// A note under the legend.
    pub note: Option<&'a str>,
}

impl Picture for Chart<'_> {
    fn size(&self) -> (u32, u32) {
        (1000 + LEGEND, self.height)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
        let (plot, legend) = root.split_horizontally(1000);
        let m = draw_chart(
            &plot,
            self.title,
            (&self.x, &self.y),
            self.series,
            self.extras,
        )?;
        if let Some((slope, corners)) = self.triangle {
            draw_triangle(&plot, &m, slope, corners)?;
        }
        let all: Vec<&Series> = self.series.iter().collect();
        draw_legend(&legend, &all, self.note, self.extras.width)
    }
}

/// The slope triangle `a b c` (log–log values) with its slope written beside the vertical leg
/// and 1 under the horizontal one.
fn draw_triangle<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    m: &Mapping,
    slope: f64,
    [a, b, c]: [(f64, f64); 3],
) -> std::result::Result<(), String> {
    let at = |p: (f64, f64)| m.pixel((p.0.log10(), p.1.log10()));
    let area = area.strip_coord_spec();
    draw_line(
        &area,
        vec![at(a), at(b), at(c), at(a)],
        &Style::line(BLACK),
        1,
    )?;
    let font = TextStyle::from(("sans-serif", 15).into_font()).color(&BLACK);
    let ((ax, _), (bx, by), (_, cy)) = (at(a), at(b), at(c));
    area.draw_text(&slope.to_string(), &font, (bx + 6, (by + cy) / 2 - 8))
        .map_err(text)?;
    area.draw_text("1", &font, ((ax + bx) / 2 - 4, by + 4))
        .map_err(text)
}

/// The axes of a plot against time over the series that did not diverge.
fn time_axes(series: &[Series], y_label: &str) -> Option<(Axis, Axis)> {
    linear_axes(series, ("time t", y_label))
}

/// Linear axes `(x_label, y_label)` over the series that did not diverge.
fn linear_axes(series: &[Series], (x_label, y_label): (&str, &str)) -> Option<(Axis, Axis)> {
    let (x0, x1, y0, y1) = linear_range(series)?;
    Some((
        Axis {
            label: x_label.into(),
            lo: x0,
            hi: x1,
            log: false,
        },
        Axis {
            label: y_label.into(),
            lo: y0,
            hi: y1,
            log: false,
        },
    ))
}

/// Line plot of several series against time (`<path>` PNG and SVG), legend beside it.
pub fn time_plot(path: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<()> {
    linear_plot(path, title, ("time t", y_label), series, TIME_EXTRAS)
}

/// Plot of a few points per series on linear axes `(x_label, y_label)`, every point marked
/// (`<path>` PNG and SVG), legend beside it.
pub fn xy_plot(path: &Path, title: &str, labels: (&str, &str), series: &[Series]) -> Result<()> {
    linear_plot(
        path,
        title,
        labels,
        series,
        Extras {
            width: 1,
            marker: 5,
            spread: 0,
        },
    )
}

fn linear_plot(
    path: &Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    extras: Extras,
) -> Result<()> {
    let (x, y) = linear_axes(series, labels).ok_or_else(|| plot_err(path, "nothing to plot"))?;
    save(
        path,
        &Chart {
            title,
            series,
            x,
            y,
            extras,
            height: 560,
            triangle: None,
            note: None,
        },
    )
}

/// Curves against time: thin, ten marks each.
const TIME_EXTRAS: Extras = Extras {
    width: 1,
    marker: 5,
    spread: 10,
};

/// Panels side by side, one chart per `(title, series)` with its own y range, all against
/// time; one legend (the curves of the first panel) on the right.
struct Panels<'a> {
    panels: Vec<(&'a str, &'a [Series], Axis, Axis)>,
    extras: Extras,
    /// Panels per row (rows of 540 px).
    columns: usize,
}

impl Panels<'_> {
    /// `(columns, rows)` of the grid.
    fn grid(&self) -> (u32, u32) {
        let columns = self.columns.clamp(1, self.panels.len().max(1));
        (
            columns as u32,
            self.panels.len().div_ceil(columns).max(1) as u32,
        )
    }
}

impl Picture for Panels<'_> {
    fn size(&self) -> (u32, u32) {
        let (columns, rows) = self.grid();
        (480 * columns + LEGEND - 60, 540 * rows)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
        let (columns, rows) = self.grid();
        let (charts, legend) = root.split_horizontally(480 * columns);
        let areas = charts.split_evenly((rows as usize, columns as usize));
        for ((title, series, x, y), area) in self.panels.iter().zip(&areas) {
            draw_chart(area, title, (x, y), series, self.extras)?;
        }
        let first: Vec<&Series> = self
            .panels
            .first()
            .map_or_else(Vec::new, |p| p.1.iter().collect());
        draw_legend(&legend, &first, None, self.extras.width)
    }
}

/// Panels side by side (one chart per `(title, series)`, each with its own y range), all
/// against time; the curves of every panel have the same labels and styles (one legend).
pub fn time_panels(path: &Path, y_label: &str, panels: &[(String, Vec<Series>)]) -> Result<()> {
    let mut drawn = Vec::new();
    for (title, series) in panels {
        let (x, y) = time_axes(series, y_label)
            .ok_or_else(|| plot_err(path, format!("panel {title}: nothing to plot")))?;
        drawn.push((title.as_str(), series.as_slice(), x, y));
    }
    save(
        path,
        &Panels {
            columns: drawn.len(),
            panels: drawn,
            extras: TIME_EXTRAS,
        },
    )
}

/// Log–log scatter panels side by side on common axes, one `(title, series)` each (a series a
/// point or a few, marks only), one legend (the first panel's series): `(x_label, y_label)`.
/// Values must be positive (the caller floors zeros and says so).
pub fn loglog_panels(
    path: &Path,
    (x_label, y_label): (&str, &str),
    panels: &[(String, Vec<Series>)],
) -> Result<()> {
    let pts: Vec<(f64, f64)> = panels
        .iter()
        .flat_map(|(_, s)| s.iter().flat_map(|s| s.points.iter().copied()))
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .collect();
    if pts.is_empty() {
        return Err(plot_err(path, "nothing to plot"));
    }
    let range = |v: Vec<f64>| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(*x), b.max(*x)));
        (lo / 3.0, hi * 3.0)
    };
    let axis = |label: &str, (lo, hi): (f64, f64)| Axis {
        label: label.into(),
        lo,
        hi,
        log: true,
    };
    let x = axis(x_label, range(pts.iter().map(|p| p.0).collect()));
    let y = axis(y_label, range(pts.iter().map(|p| p.1).collect()));
    let drawn = panels
        .iter()
        .map(|(title, series)| (title.as_str(), series.as_slice(), x.clone(), y.clone()))
        .collect();
    save(
        path,
        &Panels {
            panels: drawn,
            extras: Extras {
                width: 1,
                marker: 6,
                spread: 0,
            },
            columns: 3,
        },
    )
}

/// Axes of a log–log convergence plot.
#[derive(Debug, Clone, Copy)]
pub struct LogLog<'a> {
    /// Title.
    pub title: &'a str,
    /// Label of the x axis (`mesh size h` or `time step dt`).
    pub x_label: &'a str,
    /// Label of the y axis.
    pub y_label: &'a str,
    /// Slope of the reference triangle.
    pub slope: f64,
}

/// Log–log plot of errors against the mesh size or time step, one series per label (marks at
/// every level), with a slope triangle (legs over one factor 2 of x, its slope written beside
/// it) below the data. The y range is clamped by [`clamp_log`]; points outside are marked at
/// its edges.
pub fn loglog_plot(path: &Path, axes: LogLog<'_>, series: &[Series]) -> Result<()> {
    let pts: Vec<(f64, f64)> = series
        .iter()
        .filter(|s| !s.diverged)
        .flat_map(|s| s.points.iter().copied())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.1.is_finite())
        .collect();
    let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let Some((y0, y1)) = clamp_log(&ys) else {
        return Err(plot_err(path, "nothing to plot"));
    };
    let (x0, x1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    // Off the scale: a finite error outside the clamped range, or a diverged level (+∞).
    let off_scale = series
        .iter()
        .flat_map(|s| s.points.iter())
        .any(|p| p.1 > 0.0 && (p.1 < y0 || p.1 > y1));
    // The triangle below the data, at the smallest x.
    let (xa, ya) = (x0, y0 * 0.55);
    let (xb, yb) = (2.0 * x0, ya * 2f64.powf(axes.slope));
    let (left, right) = (x0 / 1.3, x1 * 1.3);
    let (bottom, top) = (ya / 2.5, y1.max(yb) * 1.6);
    save(
        path,
        &Chart {
            title: axes.title,
            series,
            x: Axis {
                label: axes.x_label.into(),
                lo: left,
                hi: right,
                log: true,
            },
            y: Axis {
                label: axes.y_label.into(),
                lo: bottom,
                hi: top,
                log: true,
            },
            extras: Extras {
                width: 2,
                marker: 5,
                spread: 0,
            },
            height: 620,
            triangle: Some((axes.slope, [(xa, ya), (xb, ya), (xb, yb)])),
            note: off_scale.then_some(
                "▲ ▼ hollow, at an edge: a level whose error is off the scale (above or below \
                 it); ▲ also a level that diverged.",
            ),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_have_one_format_per_axis_and_no_negative_zero() {
        let axis = Axis {
            label: String::new(),
            lo: -0.013,
            hi: 0.011,
            log: false,
        };
        let (keys, f) = axis.ticks();
        let labels: Vec<String> = keys.iter().map(|k| f.label(*k)).collect();
        assert_eq!(labels, ["-0.010", "-0.005", "0.000", "0.005", "0.010"]);
        let log = Axis {
            label: String::new(),
            lo: 3e-4,
            hi: 0.2,
            log: true,
        };
        let (keys, f) = log.ticks();
        let labels: Vec<String> = keys.iter().map(|k| f.label(10f64.powf(*k))).collect();
        assert_eq!(
            labels,
            ["5e-4", "1e-3", "2e-3", "5e-3", "1e-2", "2e-2", "5e-2", "1e-1", "2e-1"]
        );
        assert_eq!(TickFormat::Shortest.label(0.002), "0.002");
        assert_eq!(TickFormat::for_step(2e-6, 5e-3), TickFormat::Scientific(3));
    }

    #[test]
    fn log_ranges_are_clamped_to_the_data_that_matter() {
        let (lo, hi) = clamp_log(&[1e-14, 1e-3, 2e-3, 5e-3, 1e-2, 1e11]).unwrap();
        assert!(
            (lo / 5e-8 - 1.0).abs() < 1e-9 && (hi / 5.0 - 1.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        let (lo, hi) = clamp_log(&[0.1, 0.2]).unwrap();
        assert!((lo / 0.1 - 1.0).abs() < 1e-12 && (hi / 0.2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn lines_are_clipped_to_the_box() {
        let parts = clip(&[(0.0, 0.0), (2.0, 2.0), (3.0, 0.0)], (0.0, 3.0, 0.0, 1.0));
        assert_eq!(
            parts,
            vec![vec![(0.0, 0.0), (1.0, 1.0)], vec![(2.5, 1.0), (3.0, 0.0)]]
        );
        let long: Vec<(f64, f64)> = (0..10_000).map(|k| (k as f64, (k % 7) as f64)).collect();
        let d = decimate(&long, (0.0, 9999.0), 100);
        assert!(d.len() <= 400 && d.first() == long.first() && d.last() == long.last());
    }
}
