//! PNG plots (plotters): profile panels, time series, particle snapshots.

use crate::error::{Result, SphError};
use plotters::prelude::*;
use std::path::Path;

fn perr<E: std::fmt::Display>(e: E) -> SphError {
    SphError::Io(format!("plot: {e}"))
}

/// One panel: scattered SPH values and, optionally, a reference curve.
pub struct Panel {
    pub title: String,
    pub xlabel: String,
    pub ylabel: String,
    pub points: Vec<(f64, f64)>,
    pub curve: Vec<(f64, f64)>,
    pub curve_label: String,
    pub points_label: String,
}

fn range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// Panels on a grid of `cols` columns.
pub fn panels(path: &Path, panels: &[Panel], cols: usize, size: (u32, u32)) -> Result<()> {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let rows = panels.len().div_ceil(cols);
    let areas = root.split_evenly((rows, cols));
    for (pn, area) in panels.iter().zip(areas.iter()) {
        let (x0, x1) = range(pn.points.iter().map(|p| p.0).chain(pn.curve.iter().map(|p| p.0)));
        let (y0, y1) = range(pn.points.iter().map(|p| p.1).chain(pn.curve.iter().map(|p| p.1)));
        let mut ch = ChartBuilder::on(area)
            .caption(&pn.title, ("sans-serif", 18))
            .margin(8)
            .x_label_area_size(32)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        ch.configure_mesh()
            .x_desc(&pn.xlabel)
            .y_desc(&pn.ylabel)
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(perr)?;
        if !pn.curve.is_empty() {
            ch.draw_series(LineSeries::new(pn.curve.iter().copied(), BLACK.stroke_width(2)))
                .map_err(perr)?
                .label(&pn.curve_label)
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK.stroke_width(2)));
        }
        ch.draw_series(pn.points.iter().map(|&(x, y)| Circle::new((x, y), 2, BLUE.filled())))
            .map_err(perr)?
            .label(&pn.points_label)
            .legend(|(x, y)| Circle::new((x + 8, y), 3, BLUE.filled()));
        ch.configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(perr)?;
    }
    root.present().map_err(perr)?;
    Ok(())
}

/// Several named curves on one chart.
pub fn lines(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[(String, Vec<(f64, f64)>)],
    log_y: bool,
) -> Result<()> {
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let (x0, x1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.0)));
    let (mut y0, y1) = range(series.iter().flat_map(|s| s.1.iter().map(|p| p.1)));
    let colours = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK, RGBColor(255, 140, 0), RGBColor(128, 0, 128)];
    if log_y {
        let pos =
            series.iter().flat_map(|s| s.1.iter().map(|p| p.1)).filter(|v| *v > 0.0).fold(f64::INFINITY, f64::min);
        y0 = if pos.is_finite() { pos * 0.8 } else { 1e-12 };
        let mut ch = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, (y0..y1.max(y0 * 10.0)).log_scale())
            .map_err(perr)?;
        ch.configure_mesh().x_desc(xlabel).y_desc(ylabel).draw().map_err(perr)?;
        for (k, (name, pts)) in series.iter().enumerate() {
            let c = colours[k % colours.len()];
            ch.draw_series(LineSeries::new(pts.iter().copied().filter(|p| p.1 > 0.0), c.stroke_width(2)))
                .map_err(perr)?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
            ch.draw_series(pts.iter().filter(|p| p.1 > 0.0).map(|&p| Circle::new(p, 3, c.filled()))).map_err(perr)?;
        }
        ch.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(perr)?;
    } else {
        let mut ch = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(perr)?;
        ch.configure_mesh().x_desc(xlabel).y_desc(ylabel).draw().map_err(perr)?;
        for (k, (name, pts)) in series.iter().enumerate() {
            let c = colours[k % colours.len()];
            ch.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
                .map_err(perr)?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
        }
        ch.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw().map_err(perr)?;
    }
    root.present().map_err(perr)?;
    Ok(())
}

/// A colour for value t in [0, 1] (blue → red).
pub fn heat(t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0);
    let r = (255.0 * (1.5 * t).min(1.0)) as u8;
    let g = (255.0 * (1.0 - (2.0 * t - 1.0).abs())) as u8;
    let b = (255.0 * (1.5 * (1.0 - t)).min(1.0)) as u8;
    RGBColor(r, g, b)
}

/// A 2D particle snapshot coloured by `colour(i)`, with a title.
pub fn snapshot(
    path: &Path,
    title: &str,
    x: &[f64],
    y: &[f64],
    colour: &dyn Fn(usize) -> RGBColor,
    bounds: ((f64, f64), (f64, f64)),
) -> Result<()> {
    let ((x0, x1), (y0, y1)) = bounds;
    let w = 800u32;
    let hgt = ((w as f64) * (y1 - y0) / (x1 - x0)).clamp(300.0, 1600.0) as u32 + 60;
    let root = BitMapBackend::new(path, (w + 80, hgt)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(50)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(perr)?;
    ch.configure_mesh().x_desc("x (m)").y_desc("y (m)").disable_mesh().draw().map_err(perr)?;
    ch.draw_series((0..x.len()).map(|i| Circle::new((x[i], y[i]), 2, colour(i).filled()))).map_err(perr)?;
    root.present().map_err(perr)?;
    Ok(())
}

/// A named series of points (x, y, label) for [`loglog_panels`].
pub type LogSeries = (String, Vec<(f64, f64, String)>);

/// One log–log panel: named series of points (x, y, label); the label is written beside its
/// point. Points with x ≤ 0 or y ≤ 0 (or not finite) cannot be shown on log axes and are left out.
pub struct LogPanel {
    pub title: String,
    pub xlabel: String,
    pub ylabel: String,
    pub series: Vec<LogSeries>,
}

/// A logarithmic axis range that holds `vals` (positive and finite only), padded by a factor.
fn log_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return None;
    }
    // at least a decade, so that the axis has a labelled power of ten or two
    if hi / lo < 10.0 {
        let mid = (lo * hi).sqrt();
        lo = lo.min(mid / 10f64.sqrt());
        hi = hi.max(mid * 10f64.sqrt());
    }
    Some((lo / 1.3, hi * 1.3))
}

/// Log–log panels on a grid of `cols` columns, one line and marker colour per series.
pub fn loglog_panels(path: &Path, panels: &[LogPanel], cols: usize, size: (u32, u32)) -> Result<()> {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let areas = root.split_evenly((rows, cols));
    let colours = [
        BLUE,
        RED,
        RGBColor(0, 150, 0),
        MAGENTA,
        RGBColor(0, 150, 170),
        BLACK,
        RGBColor(255, 140, 0),
        RGBColor(140, 90, 40),
        RGBColor(128, 128, 128),
    ];
    let ok = |p: &(f64, f64, String)| p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0;
    for (pn, area) in panels.iter().zip(areas.iter()) {
        let xr = log_range(pn.series.iter().flat_map(|s| s.1.iter().filter(|p| ok(p)).map(|p| p.0)));
        let yr = log_range(pn.series.iter().flat_map(|s| s.1.iter().filter(|p| ok(p)).map(|p| p.1)));
        let (Some((x0, x1)), Some((y0, y1))) = (xr, yr) else {
            let sub = area.titled(&pn.title, ("sans-serif", 16)).map_err(perr)?;
            sub.draw(&Text::new("no positive values to plot", (40, 40), ("sans-serif", 14).into_font()))
                .map_err(perr)?;
            continue;
        };
        let mut ch = ChartBuilder::on(area)
            .caption(&pn.title, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(36)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(perr)?;
        ch.configure_mesh()
            .x_desc(&pn.xlabel)
            .y_desc(&pn.ylabel)
            .x_labels(8)
            .y_labels(12)
            .x_label_formatter(&|v| format!("{v:.1e}"))
            .y_label_formatter(&|v| format!("{v:.1e}"))
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(perr)?;
        for (k, (name, pts)) in pn.series.iter().enumerate() {
            let c = colours[k % colours.len()];
            let good: Vec<&(f64, f64, String)> = pts.iter().filter(|p| ok(p)).collect();
            ch.draw_series(LineSeries::new(good.iter().map(|p| (p.0, p.1)), c.stroke_width(2)))
                .map_err(perr)?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
            ch.draw_series(good.iter().map(|p| {
                EmptyElement::at((p.0, p.1))
                    + Circle::new((0, 0), 4, c.filled())
                    + Text::new(p.2.clone(), (6, -14 + 12 * (k as i32 % 3)), ("sans-serif", 11).into_font())
            }))
            .map_err(perr)?;
        }
        ch.configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(perr)?;
    }
    root.present().map_err(perr)?;
    Ok(())
}
