//! Pictures of fields (plotters, bitmap backend): a 2D body's cells filled by a scalar value
//! (viridis colour scale with its bar), and a scatter of point values with reference curves.

use super::plot::{plot_err, Series};
use crate::error::Result;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::path::Path;

/// A polygon (vertices in cyclic order) and its value.
pub type Cell = (Vec<(f64, f64)>, f64);

/// The cells filled by value on equal x and y scales (1000 px wide), with a colour bar from 0 to
/// the largest value labelled `value_label`.
pub fn cell_map(path: &Path, title: &str, value_label: &str, cells: &[Cell]) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| plot_err(path, e);
    let bounds = cells.iter().flat_map(|c| c.0.iter()).fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |b, p| (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1)),
    );
    let (x0, x1, y0, y1) = bounds;
    if !(x1 > x0 && y1 > y0) {
        return Err(err(&"nothing to plot"));
    }
    let max = cells.iter().map(|c| c.1).fold(0.0, f64::max);
    let scale = if max > 0.0 { max } else { 1.0 };
    // Plot area 800 px wide; height for equal scales, within [300, 1000] px.
    let height = ((800.0 * (y1 - y0) / (x1 - x0)) as u32).clamp(300, 1000) + 110;
    let root = BitMapBackend::new(path, (1000, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (main, bar) = root.split_horizontally(830);
    let mut chart = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    chart
        .draw_series(cells.iter().map(|(poly, v)| {
            let colour = ViridisRGB::get_color_normalized(*v, 0.0, scale);
            Polygon::new(poly.clone(), colour.filled())
        }))
        .map_err(|e| err(&e))?;
    let mut legend = ChartBuilder::on(&bar)
        .margin_top(50)
        .margin_bottom(55)
        .margin_left(10)
        .right_y_label_area_size(90)
        .build_cartesian_2d(0.0..1.0, 0.0..scale)
        .map_err(|e| err(&e))?;
    legend
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(value_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    let steps = 100;
    legend
        .draw_series((0..steps).map(|k| {
            let (a, b) = (
                scale * k as f64 / steps as f64,
                scale * (k + 1) as f64 / steps as f64,
            );
            let colour = ViridisRGB::get_color_normalized(0.5 * (a + b), 0.0, scale);
            Rectangle::new([(0.0, a), (1.0, b)], colour.filled())
        }))
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}

/// Points (`label`, filled circles) and reference curves (solid or dashed), 1000×600 px.
pub fn scatter_plot(
    path: &Path,
    (title, x_label, y_label): (&str, &str, &str),
    (label, points): (&str, &[(f64, f64)]),
    curves: &[Series],
) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| plot_err(path, e);
    let all = || {
        points
            .iter()
            .chain(curves.iter().flat_map(|c| c.points.iter()))
    };
    let (x1, y1) = all().fold((0.0f64, 0.0f64), |m, p| (m.0.max(p.0), m.1.max(p.1)));
    if !(x1 > 0.0 && y1 > 0.0) {
        return Err(err(&"nothing to plot"));
    }
    let root = BitMapBackend::new(path, (1000, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..1.05 * x1, 0.0..1.1 * y1)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    let blue = super::plot::PALETTE[0];
    chart
        .draw_series(points.iter().map(|&p| Circle::new(p, 3, blue.filled())))
        .map_err(|e| err(&e))?
        .label(label)
        .legend(move |(x, y)| Circle::new((x + 10, y), 4, blue.filled()));
    for c in curves {
        let style = ShapeStyle::from(&c.color).stroke_width(2);
        let pts = c.points.iter().copied();
        let anno = if c.dashed {
            chart.draw_series(DashedLineSeries::new(pts, 8, 6, style))
        } else {
            chart.draw_series(LineSeries::new(pts, style))
        }
        .map_err(|e| err(&e))?;
        let colour = c.color;
        anno.label(c.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}
