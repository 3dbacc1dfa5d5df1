//! Pictures of fields (plotters, PNG and SVG): a 2D body's cells filled by a scalar value on
//! equal x and y scales (viridis colour scale with its bar, reference curves drawn over it), and
//! a scatter of point values with reference curves.

use super::plot::{draw_line, plot_err, save, text, Axis, Chart, Extras, Picture, Series, Ticked};
use crate::error::Result;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::path::Path;

/// A polygon (vertices in cyclic order) and its value.
pub type Cell = (Vec<(f64, f64)>, f64);

/// Title and axis labels of a picture.
#[derive(Debug, Clone, Copy)]
pub struct Labels<'a> {
    /// Title.
    pub title: &'a str,
    /// x axis.
    pub x: &'a str,
    /// y axis.
    pub y: &'a str,
    /// The value (colour bar or y of a scatter).
    pub value: &'a str,
}

/// Width of the map's plot area in pixels.
const MAP_WIDTH: u32 = 760;

/// The cells on equal scales.
struct CellMap<'a> {
    labels: Labels<'a>,
    cells: &'a [Cell],
    /// Curves drawn over the cells (dashed, black: a reference contour).
    overlay: &'a [Series],
    /// `(x0, x1, y0, y1)` of the data, widened to equal scales.
    bounds: (f64, f64, f64, f64),
    /// Largest value (top of the colour bar).
    scale: f64,
}

/// Margins of the map: title, x labels, y labels, right margin (pixels).
const MAP_TITLE: u32 = 44;
const MAP_X_AREA: u32 = 50;
const MAP_Y_AREA: u32 = 80;
const MAP_MARGIN: u32 = 14;

impl Picture for CellMap<'_> {
    fn size(&self) -> (u32, u32) {
        let (x0, x1, y0, y1) = self.bounds;
        let height = (MAP_WIDTH as f64 * (y1 - y0) / (x1 - x0)).round() as u32;
        (
            MAP_Y_AREA + MAP_WIDTH + 2 * MAP_MARGIN + 190,
            MAP_TITLE + height + MAP_X_AREA + 2 * MAP_MARGIN,
        )
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> std::result::Result<(), String> {
        let (x0, x1, y0, y1) = self.bounds;
        let (w, _) = self.size();
        let title = TextStyle::from(("sans-serif", 21).into_font()).pos(
            plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Top,
            ),
        );
        root.draw_text(self.labels.title, &title, (w as i32 / 2, 10))
            .map_err(text)?;
        let body = root.margin(MAP_TITLE, 0, 0, 0);
        let (main, bar) = body.split_horizontally(MAP_Y_AREA + MAP_WIDTH + 2 * MAP_MARGIN);
        let (xs, xf) = Ticked::linear(x0, x1);
        let (ys, yf) = Ticked::linear(y0, y1);
        let mut chart = ChartBuilder::on(&main)
            .margin(MAP_MARGIN)
            .x_label_area_size(MAP_X_AREA)
            .y_label_area_size(MAP_Y_AREA)
            .build_cartesian_2d(xs, ys)
            .map_err(text)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(self.labels.x)
            .y_desc(self.labels.y)
            .x_label_formatter(&|v| xf.label(*v))
            .y_label_formatter(&|v| yf.label(*v))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(text)?;
        chart
            .draw_series(self.cells.iter().map(|(poly, v)| {
                let colour = ViridisRGB::get_color_normalized(*v, 0.0, self.scale);
                Polygon::new(poly.clone(), colour.filled())
            }))
            .map_err(text)?;
        for s in self.overlay {
            let pixels: Vec<(i32, i32)> = s.points.iter().map(|p| chart.backend_coord(p)).collect();
            draw_line(&root.strip_coord_spec(), pixels, &s.style, 2)?;
        }
        let (vs, vf) = Ticked::linear(0.0, self.scale);
        let mut legend = ChartBuilder::on(&bar)
            .margin_top(MAP_MARGIN)
            .margin_bottom(MAP_MARGIN + MAP_X_AREA)
            .margin_left(10)
            .right_y_label_area_size(110)
            .build_cartesian_2d(Ticked::linear(0.0, 1.0).0, vs)
            .map_err(text)?;
        legend
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(self.labels.value)
            .y_label_formatter(&|v| vf.label(*v))
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(text)?;
        let steps = 100;
        legend
            .draw_series((0..steps).map(|k| {
                let (a, b) = (
                    self.scale * k as f64 / steps as f64,
                    self.scale * (k + 1) as f64 / steps as f64,
                );
                let colour = ViridisRGB::get_color_normalized(0.5 * (a + b), 0.0, self.scale);
                Rectangle::new([(0.0, a), (1.0, b)], colour.filled())
            }))
            .map_err(text)?;
        Ok(())
    }
}

/// The cells filled by value on equal x and y scales (the plot 760 px wide, its height in
/// proportion), with a colour bar from 0 to the largest value and `overlay` curves (e.g. a
/// reference contour) drawn over them.
pub fn cell_map(path: &Path, labels: Labels<'_>, cells: &[Cell], overlay: &[Series]) -> Result<()> {
    let points = cells
        .iter()
        .flat_map(|c| c.0.iter())
        .chain(overlay.iter().flat_map(|s| s.points.iter()));
    let (x0, x1, y0, y1) = points.fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |b, p| (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1)),
    );
    if !(x1 > x0 && y1 > y0) {
        return Err(plot_err(path, "nothing to plot"));
    }
    // Between 1:3 and 4:3 (height over width): a flatter or taller region gets room around it.
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (mut hw, mut hh) = (0.5 * (x1 - x0), 0.5 * (y1 - y0));
    hh = hh.max(hw / 3.0);
    hw = hw.max(hh * 0.75);
    let max = cells.iter().map(|c| c.1).fold(0.0, f64::max);
    save(
        path,
        &CellMap {
            labels,
            cells,
            overlay,
            bounds: (cx - hw, cx + hw, cy - hh, cy + hh),
            scale: if max > 0.0 { max } else { 1.0 },
        },
    )
}

/// Point values (a series with marks and no line) and reference curves, on axes from 0, legend
/// beside them.
pub fn scatter_plot(path: &Path, labels: Labels<'_>, series: &[Series]) -> Result<()> {
    let (x1, y1) = series
        .iter()
        .flat_map(|s| s.points.iter())
        .fold((0.0f64, 0.0f64), |m, p| (m.0.max(p.0), m.1.max(p.1)));
    if !(x1 > 0.0 && y1 > 0.0) {
        return Err(plot_err(path, "nothing to plot"));
    }
    let axis = |label: &str, hi: f64| Axis {
        label: label.into(),
        lo: 0.0,
        hi,
        log: false,
    };
    save(
        path,
        &Chart {
            title: labels.title,
            series,
            x: axis(labels.x, 1.05 * x1),
            y: axis(labels.value, 1.1 * y1),
            extras: Extras {
                width: 2,
                marker: 3,
                spread: 0,
            },
            height: 560,
            triangle: None,
            note: None,
        },
    )
}
