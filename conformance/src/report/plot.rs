//! Line plots a reader can read values off: SVG (the browser draws the
//! text, so no font files are needed), with axis titles, numbered ticks, a
//! legend, labelled reference lines and a logarithmic y axis where the
//! quantity spans decades; each plot's data is written beside it as CSV.

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// One curve: its legend label, colour and `(x, y)` points.
#[derive(Clone, Debug)]
pub struct Curve {
    /// Legend label.
    pub label: String,
    /// Line colour.
    pub colour: RGBColor,
    /// Points in data units; non-finite `y` (and `y <= 0` on a log axis) are skipped.
    pub points: Vec<(f64, f64)>,
}

/// A line plot: title, axis titles, curves and labelled horizontal lines.
#[derive(Clone, Debug)]
pub struct LinePlot<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// x-axis title, with units.
    pub x_title: &'a str,
    /// y-axis title, with units.
    pub y_title: &'a str,
    /// Logarithmic y axis (for quantities spanning decades).
    pub log_y: bool,
    /// Horizontal reference lines `(y, label)`, e.g. goals or white noise.
    pub lines: &'a [(f64, &'a str)],
    /// The curves.
    pub curves: &'a [Curve],
}

/// Pixel size of every plot (the page shows it at this size).
pub const PLOT_SIZE: (u32, u32) = (760, 440);

/// Width of the legend column at the right of the plot, in pixels.
const LEGEND_WIDTH: u32 = 170;

/// A tick label with at least two significant digits: plain decimals from
/// 0.001 to 10,000, else scientific.
pub fn tick(v: &f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if (1e-3..1e4).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).clamp(0, 4) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.1e}")
    }
}

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("plot: {e}")
}

impl LinePlot<'_> {
    /// `y` on the plot's vertical axis: `log10 y` on a log axis (where
    /// `y <= 0` and non-finite values have no place: `None`).
    fn axis_y(&self, y: f64) -> Option<f64> {
        let v = if self.log_y { y.log10() } else { y };
        v.is_finite().then_some(v)
    }

    /// The axis range `(x0, x1, y0, y1)` of the curves and lines, padded
    /// (`y` in axis units, see [`LinePlot::axis_y`]).
    fn ranges(&self) -> (f64, f64, f64, f64) {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in self.curves.iter().flat_map(|c| &c.points) {
            if let Some(y) = self.axis_y(y) {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
        for y in self.lines.iter().filter_map(|l| self.axis_y(l.0)) {
            (y0, y1) = (y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        if x1 <= x0 {
            x1 = x0 + 1.0;
        }
        let pad = ((y1 - y0) * 0.06).max(1e-3);
        (x0, x1, y0 - pad, y1 + pad)
    }

    /// Writes the plot as SVG to `svg` and its data as CSV to `csv` (one row
    /// per point: `curve,x,y`; reference lines as `line:<label>,,y`).
    ///
    /// A log axis is drawn as `log10 y` on a linear scale with every tick
    /// labelled by its value `y` (plotters' own log axis labels only some
    /// decades).
    ///
    /// # Errors
    /// I/O errors, or plotters' drawing errors.
    pub fn write(&self, svg: &Path, csv: &Path) -> Result<()> {
        self.write_sized(svg, csv, PLOT_SIZE)
    }

    /// [`LinePlot::write`] at `size` pixels (width, height) instead of
    /// [`PLOT_SIZE`]; the legend column narrows with the width (110 px at
    /// least).
    ///
    /// # Errors
    /// As [`LinePlot::write`].
    pub fn write_sized(&self, svg: &Path, csv: &Path, size: (u32, u32)) -> Result<()> {
        let (x0, x1, y0, y1) = self.ranges();
        {
            let legend_width = (LEGEND_WIDTH * size.0 / PLOT_SIZE.0).max(110).min(size.0 / 2);
            let root = SVGBackend::new(svg, size).into_drawing_area();
            root.fill(&WHITE).map_err(err)?;
            let (plot_area, legend_area) = root.split_horizontally(size.0 - legend_width);
            self.legend(&legend_area)?;
            let mut chart = ChartBuilder::on(&plot_area)
                .caption(self.title, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(err)?;
            let log = self.log_y;
            let y_label = move |v: &f64| tick(&if log { 10f64.powf(*v) } else { *v });
            let y_title = if log {
                format!("{} (log scale)", self.y_title)
            } else {
                self.y_title.to_string()
            };
            chart
                .configure_mesh()
                .x_desc(self.x_title)
                .y_desc(y_title)
                .y_labels(14)
                // About one numbered x tick per 80 px, so labels never overlap.
                .x_labels((size.0 / 80).max(4) as usize)
                .y_label_formatter(&y_label)
                .x_label_formatter(&tick)
                .draw()
                .map_err(err)?;
            let grey = RGBColor(90, 90, 90);
            for &(y, label) in self.lines {
                let Some(v) = self.axis_y(y) else { continue };
                chart
                    .draw_series(DashedLineSeries::new(
                        [(x0, v), (x1, v)],
                        6,
                        4,
                        grey.stroke_width(1),
                    ))
                    .map_err(err)?;
                chart
                    .draw_series([Text::new(
                        format!("{label} ({y})"),
                        (x0 + 0.01 * (x1 - x0), v),
                        ("sans-serif", 13).into_font().color(&grey),
                    )])
                    .map_err(err)?;
            }
            for c in self.curves {
                let points: Vec<(f64, f64)> = c
                    .points
                    .iter()
                    .filter_map(|&(x, y)| self.axis_y(y).map(|v| (x, v)))
                    .collect();
                chart
                    .draw_series(LineSeries::new(points, c.colour.stroke_width(2)))
                    .map_err(err)?;
            }
            root.present().map_err(err)?;
        }
        std::fs::write(csv, self.csv())?;
        Ok(())
    }

    /// The legend, one row per curve, in its own column (it never hides data).
    fn legend(&self, area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>) -> Result<()> {
        for (i, c) in self.curves.iter().enumerate() {
            let y = 48 + 20 * i as i32;
            area.draw(&PathElement::new([(4, y), (26, y)], c.colour.stroke_width(3)))
                .map_err(err)?;
            area.draw(&Text::new(c.label.clone(), (32, y - 7), ("sans-serif", 13)))
                .map_err(err)?;
        }
        Ok(())
    }

    /// The data as CSV.
    pub fn csv(&self) -> String {
        let mut s = String::from("curve,x,y\n");
        for &(y, label) in self.lines {
            let _ = writeln!(s, "line:{label},,{y}");
        }
        for c in self.curves {
            for &(x, y) in &c.points {
                let _ = writeln!(s, "{},{x},{y}", c.label);
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn svg_has_axis_titles_ticks_legend_and_lines_and_csv_has_every_point() {
        let dir = std::env::temp_dir().join(format!("bluenoise-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let curves = [
            Curve {
                label: "white".into(),
                colour: RGBColor(128, 128, 128),
                points: vec![(0.0, 1.0), (1.0, 1.0)],
            },
            Curve {
                label: "permute".into(),
                colour: RGBColor(0, 114, 178),
                points: vec![(0.0, 0.5), (1.0, 0.05)],
            },
        ];
        for log_y in [false, true] {
            let plot = LinePlot {
                title: "t",
                x_title: "frame",
                y_title: "relative power",
                log_y,
                lines: &[(0.15, "goal")],
                curves: &curves,
            };
            let (svg, csv) = (dir.join("p.svg"), dir.join("p.csv"));
            plot.write(&svg, &csv).unwrap();
            let text = std::fs::read_to_string(&svg).unwrap();
            for needle in [
                "frame",
                "relative power",
                "white",
                "permute",
                "goal (0.15)",
                "<text",
            ] {
                assert!(text.contains(needle), "log {log_y}: no {needle}");
            }
            // Numbered ticks on both axes.
            assert!(text.matches("<text").count() >= 10, "log {log_y}");
            let data = std::fs::read_to_string(&csv).unwrap();
            assert_eq!(data.lines().count(), 1 + 1 + 4);
            assert!(data.contains("permute,1,0.05"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
