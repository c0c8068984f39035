//! PNG plots (plotters): profile panels, time series, particle snapshots.

use crate::error::{IoAt, Result, SphError};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
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
            .x_label_formatter(&axis_label)
            .y_label_formatter(&axis_label)
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
        ch.configure_mesh().x_desc(xlabel).y_desc(ylabel).x_label_formatter(&axis_label).draw().map_err(perr)?;
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
        ch.configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .x_label_formatter(&axis_label)
            .y_label_formatter(&axis_label)
            .draw()
            .map_err(perr)?;
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

// ---------------------------------------------------------------------------------------------
// Field maps, colour bars, reference overlays, scaled-distance plots and animations (report).

use plotters::style::colors::colormaps::ViridisRGB;

/// The perceptually uniform viridis colour map at t in [0, 1].
pub fn viridis(t: f64) -> RGBColor {
    ViridisRGB::get_color(t.clamp(0.0, 1.0))
}

/// How values map to colours: linear or logarithmic between `lo` and `hi` (in display units).
#[derive(Debug, Clone)]
pub struct Scale {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    /// Colour-bar label with its unit, e.g. "p (MPa)".
    pub label: String,
}

impl Scale {
    /// Position in [0, 1] of value `v` (display units); values below `lo` give 0.
    pub fn t(&self, v: f64) -> f64 {
        if !v.is_finite() {
            return 0.0;
        }
        if self.log {
            if v <= 0.0 {
                return 0.0;
            }
            ((v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())).clamp(0.0, 1.0)
        } else {
            ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0)
        }
    }

    /// A log scale over the positive values of `vals`, at most `decades` decades below the top.
    pub fn log_of(vals: impl Iterator<Item = f64>, decades: f64, label: &str) -> Scale {
        let hi = vals.filter(|v| v.is_finite() && *v > 0.0).fold(0.0, f64::max);
        let hi = if hi > 0.0 { hi } else { 1.0 };
        Scale { lo: hi / 10f64.powf(decades), hi, log: true, label: label.to_string() }
    }

    /// Tick values of the colour bar.
    fn ticks(&self) -> Vec<f64> {
        if self.log {
            let (a, b) = (self.lo.log10().ceil() as i32, self.hi.log10().floor() as i32);
            let mut v: Vec<f64> = (a..=b).map(|e| 10f64.powi(e)).collect();
            if v.len() < 2 {
                v = vec![self.lo, self.hi];
            }
            v
        } else {
            (0..=4).map(|k| self.lo + (self.hi - self.lo) * k as f64 / 4.0).collect()
        }
    }
}

/// `v` with at most `decimals` decimals, trailing zeros dropped, where its magnitude lies in
/// `plain`; in powers of ten with `exp` decimals outside it; "0" below `zero` in magnitude.
fn short_number(v: f64, zero: f64, plain: std::ops::Range<f64>, decimals: usize, exp: usize) -> String {
    let a = v.abs();
    if a <= zero {
        "0".into()
    } else if plain.contains(&a) {
        let s = format!("{v:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.exp$e}")
    }
}

/// A tick of a linear axis: its shortest decimal (200, 0.05, −0.3; plotters' own printed
/// "200.0", and "-0.0" for a key point a rounding below zero), in powers of ten outside
/// 10⁻³…10⁷.
fn axis_label(v: &f64) -> String {
    short_number(*v, 1e-12, 1e-3..1e7, 6, 2)
}

/// A tick on the data of a log axis: three significant digits (366, 51.9, 0.172; a docs-only
/// engineer read "365.868" and "159.546" on peaks.png's axis), a power of ten outside 10⁻²…10⁴.
fn tick_label(v: f64) -> String {
    short_number(v, 0.0, 1e-2..1e4, decimals_for(v, 3, 4), 0)
}

/// The decimals that print `v` to `digits` significant digits in fixed notation (at most `max`;
/// `max` for 0 or a value that is not finite).
pub(crate) fn decimals_for(v: f64, digits: i64, max: i64) -> usize {
    let a = v.abs();
    if a > 0.0 && a.is_finite() { (digits - 1 - a.log10().floor() as i64).clamp(0, max) as usize } else { max as usize }
}

/// What a particle map colours by.
pub enum Colouring<'a> {
    /// By material: the material index of each particle, a colour and a legend name per material.
    Material { index: &'a [usize], colours: &'a [RGBColor], names: &'a [String] },
    /// By a value per particle (display units) on `scale`.
    Field { values: &'a [f64], scale: &'a Scale },
}

/// One particle map: positions (m), a side length per particle (m; its initial spacing or
/// √(m/ρ)), a colouring, the frame and the title. Particles whose square would cross the frame
/// are not drawn; the caption says how many lie outside.
pub struct MapSpec<'a> {
    pub title: String,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub side: &'a [f64],
    pub colouring: Colouring<'a>,
    pub bounds: ((f64, f64), (f64, f64)),
    /// Extra text under the title (reference values, notes).
    pub note: Option<String>,
    /// Axis titles: "x (m)", "y (m)" in 2D plane; r and z in RZ; x and z on a 3D section.
    pub axes: [&'a str; 2],
    /// Lines and marks drawn over the map (an outline, a point), if any.
    pub overlay: Option<&'a Overlay>,
}

/// What is drawn over a map (m): line segments in red, 2 px wide, and marks as crosses, white
/// on black so that they show on any colour.
#[derive(Debug, Clone, Default)]
pub struct Overlay {
    pub segments: Vec<[(f64, f64); 2]>,
    pub marks: Vec<(f64, f64)>,
}

/// Pixel size of a map of `bounds` at a width of `w` pixels for the map's part (without the
/// colour bar): the plotting area's height is set so that a metre along y is as long as a metre
/// along x (the chart takes 2 × 10 px of margins and 56 px of y labels from the width, 40 px of x
/// labels and 10 + 50 px of margins, or a title, from the height; see [`draw_map`]).
pub fn map_size(bounds: ((f64, f64), (f64, f64)), w: u32) -> (u32, u32) {
    let ((x0, x1), (y0, y1)) = bounds;
    let plot_w = w.saturating_sub(66) as f64;
    let plot_h = (plot_w * (y1 - y0) / (x1 - x0)).clamp(200.0, 1400.0) as u32;
    (w + 260, plot_h + 102)
}

/// Draws a particle map on `area` (which [`map_size`] sized): the map on the left, the colour
/// bar or the material legend on the right.
pub fn draw_map<DB: DrawingBackend>(area: &DrawingArea<DB, plotters::coord::Shift>, m: &MapSpec) -> Result<()>
where
    DB::ErrorType: 'static,
{
    area.fill(&WHITE).map_err(perr)?;
    let (w, _) = area.dim_in_pixel();
    let (left, right) = area.split_horizontally(w.saturating_sub(250));
    let ((x0, x1), (y0, y1)) = m.bounds;
    let inside = |i: usize| {
        let a = 0.5 * m.side[i];
        m.x[i].is_finite()
            && m.y[i].is_finite()
            && m.x[i] - a >= x0
            && m.x[i] + a <= x1
            && m.y[i] - a >= y0
            && m.y[i] + a <= y1
    };
    let outside = (0..m.x.len()).filter(|&i| !inside(i)).count();
    let mut caption = m.title.clone();
    if outside > 0 {
        caption += &format!("  ({outside} particles outside the frame)");
    }
    // with a note, the title and the note under it are written above the chart
    let mut builder = ChartBuilder::on(&left);
    builder.margin(10).x_label_area_size(40).y_label_area_size(56);
    match &m.note {
        None => builder.caption(&caption, ("sans-serif", 17)),
        Some(_) => builder.margin_top(50),
    };
    let mut ch = builder.build_cartesian_2d(x0..x1, y0..y1).map_err(perr)?;
    ch.configure_mesh()
        .x_desc(m.axes[0])
        .y_desc(m.axes[1])
        .x_label_formatter(&axis_label)
        .y_label_formatter(&axis_label)
        .disable_mesh()
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(perr)?;
    ch.draw_series((0..m.x.len()).filter(|&i| inside(i)).map(|i| {
        let a = 0.5 * m.side[i];
        let c = match &m.colouring {
            Colouring::Material { index, colours, .. } => {
                colours.get(index[i]).copied().unwrap_or(RGBColor(128, 128, 128))
            }
            Colouring::Field { values, scale } => viridis(scale.t(values[i])),
        };
        Rectangle::new([(m.x[i] - a, m.y[i] - a), (m.x[i] + a, m.y[i] + a)], c.filled())
    }))
    .map_err(perr)?;
    if let Some(ov) = m.overlay {
        let red = RGBColor(220, 20, 60);
        ch.draw_series(ov.segments.iter().map(|s| PathElement::new(s.to_vec(), red.stroke_width(2)))).map_err(perr)?;
        for (colour, size, width) in [(BLACK, 9, 4), (WHITE, 8, 2)] {
            ch.draw_series(ov.marks.iter().map(|p| Cross::new(*p, size, colour.stroke_width(width)))).map_err(perr)?;
        }
    }
    if let Some(n) = &m.note {
        left.draw(&Text::new(caption, (66, 8), ("sans-serif", 17).into_font())).map_err(perr)?;
        left.draw(&Text::new(n.clone(), (66, 31), ("sans-serif", 13).into_font())).map_err(perr)?;
    }
    match &m.colouring {
        Colouring::Material { names, colours, .. } => {
            right.draw(&Text::new("material", (10, 40), ("sans-serif", 15).into_font())).map_err(perr)?;
            for (k, name) in names.iter().enumerate() {
                let y = 66 + 26 * k as i32;
                let c = colours.get(k).copied().unwrap_or(BLACK);
                right.draw(&Rectangle::new([(10, y), (30, y + 16)], c.filled())).map_err(perr)?;
                right.draw(&Text::new(name.clone(), (38, y + 1), ("sans-serif", 14).into_font())).map_err(perr)?;
            }
        }
        Colouring::Field { scale, .. } => {
            let (_, hgt) = right.dim_in_pixel();
            let (top, bot) = (50i32, hgt as i32 - 60);
            let (bx0, bx1) = (20i32, 46i32);
            right.draw(&Text::new(scale.label.clone(), (10, 22), ("sans-serif", 15).into_font())).map_err(perr)?;
            let span = (bot - top).max(1);
            for py in top..bot {
                let t = (bot - py) as f64 / span as f64;
                right.draw(&Rectangle::new([(bx0, py), (bx1, py + 1)], viridis(t).filled())).map_err(perr)?;
            }
            right.draw(&Rectangle::new([(bx0, top), (bx1, bot)], BLACK.stroke_width(1))).map_err(perr)?;
            for v in scale.ticks() {
                let t = scale.t(v);
                let py = bot - (t * span as f64).round() as i32;
                right.draw(&PathElement::new(vec![(bx1, py), (bx1 + 6, py)], BLACK)).map_err(perr)?;
                right
                    .draw(&Text::new(tick_label(v), (bx1 + 10, py - 7), ("sans-serif", 13).into_font()))
                    .map_err(perr)?;
            }
            let under = if scale.log { format!("≤ {}: bottom colour", tick_label(scale.lo)) } else { String::new() };
            right.draw(&Text::new(under, (10, bot + 16), ("sans-serif", 12).into_font())).map_err(perr)?;
        }
    }
    Ok(())
}

/// A particle map written to a PNG.
pub fn map_png(path: &Path, m: &MapSpec) -> Result<()> {
    let size = map_size(m.bounds, 820);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    draw_map(&root, m)?;
    root.present().map_err(perr)?;
    Ok(())
}

/// A reference series: points drawn as open markers with a label (thesis values).
pub struct Reference {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// Curves with references overlaid (markers) on linear axes.
pub fn lines_with_refs(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[(String, Vec<(f64, f64)>)],
    refs: &[Reference],
) -> Result<()> {
    let root = BitMapBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let (x0, x1) = range(
        series
            .iter()
            .flat_map(|s| s.1.iter().map(|p| p.0))
            .chain(refs.iter().flat_map(|r| r.points.iter().map(|p| p.0))),
    );
    let (y0, y1) = range(
        series
            .iter()
            .flat_map(|s| s.1.iter().map(|p| p.1))
            .chain(refs.iter().flat_map(|r| r.points.iter().map(|p| p.1))),
    );
    let colours = [
        BLUE,
        RED,
        RGBColor(0, 150, 0),
        MAGENTA,
        RGBColor(0, 150, 170),
        BLACK,
        RGBColor(255, 140, 0),
        RGBColor(128, 0, 128),
    ];
    let mut ch = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(76)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(perr)?;
    ch.configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .x_label_formatter(&axis_label)
        .y_label_formatter(&axis_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(perr)?;
    for (k, (name, pts)) in series.iter().enumerate() {
        let c = colours[k % colours.len()];
        // a point that is not finite breaks the line (a gauge's void): one segment each side
        let segments: Vec<&[(f64, f64)]> =
            pts.split(|p| !(p.0.is_finite() && p.1.is_finite())).filter(|s| !s.is_empty()).collect();
        for (j, seg) in segments.iter().enumerate() {
            let drawn = ch.draw_series(LineSeries::new(seg.iter().copied(), c.stroke_width(2))).map_err(perr)?;
            if j == 0 {
                drawn.label(name).legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)));
            }
        }
    }
    for (k, r) in refs.iter().enumerate() {
        let c = colours[k % colours.len()];
        let pts: Vec<(f64, f64)> = r.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        ch.draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 9, c.stroke_width(2))))
            .map_err(perr)?
            .label(&r.label)
            .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, c.stroke_width(2)));
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(perr)?;
    root.present().map_err(perr)?;
    Ok(())
}

/// Points (x, y, label) on log–log axes whose ticks sit on the data: every x and every y of the
/// points is a tick, labelled with its value; each of `curves` (a reference, with its legend
/// label) is drawn as a dashed line. Labels that would overlap are moved apart ([`spread_labels`])
/// and joined to their point by a leader line.
pub fn loglog_on_data(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    points: &[(f64, f64, String)],
    curves: &[(String, Vec<(f64, f64)>)],
) -> Result<()> {
    let root = BitMapBackend::new(path, (1000, 680)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    // in order of distance (the ticks)
    let mut good: Vec<&(f64, f64, String)> =
        points.iter().filter(|p| p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0).collect();
    good.sort_by(|a, b| a.0.total_cmp(&b.0));
    if good.is_empty() {
        root.draw(&Text::new(format!("{title}: no positive values to plot"), (40, 40), ("sans-serif", 18).into_font()))
            .map_err(perr)?;
        root.present().map_err(perr)?;
        return Ok(());
    }
    let (mut xl, mut xh) = good.iter().fold((f64::INFINITY, 0.0f64), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let (mut yl, mut yh) = good.iter().fold((f64::INFINITY, 0.0f64), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    for (_, c) in curves {
        for p in c.iter().filter(|p| p.0 >= xl && p.0 <= xh && p.1 > 0.0) {
            yl = yl.min(p.1);
            yh = yh.max(p.1);
        }
    }
    xl /= 1.25;
    xh *= 1.25;
    yl /= 1.5;
    yh *= 1.5;
    let mut xt: Vec<f64> = good.iter().map(|p| p.0).collect();
    let mut yt: Vec<f64> = good.iter().map(|p| p.1).collect();
    xt.sort_by(|a, b| a.total_cmp(b));
    yt.sort_by(|a, b| a.total_cmp(b));
    // ticks closer than 4 % on a log axis would print on top of each other
    xt.dedup_by(|a, b| (*a / *b) < 1.04);
    yt.dedup_by(|a, b| (*a / *b) < 1.04);
    let mut ch = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(52)
        .y_label_area_size(80)
        .build_cartesian_2d((xl..xh).log_scale().with_key_points(xt), (yl..yh).log_scale().with_key_points(yt))
        .map_err(perr)?;
    ch.configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .x_label_formatter(&|v| format!("{v:.3}"))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(perr)?;
    for (k, (name, c)) in curves.iter().enumerate() {
        let colour = [RGBColor(120, 120, 120), RGBColor(200, 110, 0)][k % 2];
        let pts: Vec<(f64, f64)> =
            c.iter().copied().filter(|p| p.0 >= xl && p.0 <= xh && p.1 >= yl && p.1 <= yh).collect();
        ch.draw_series(DashedLineSeries::new(pts, 8, 5, colour.stroke_width(2)))
            .map_err(perr)?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
    }
    // markers only: gauges in different directions from the charge (under it, beside it, in the
    // air) are no one attenuation curve, and a line through them would read as one
    ch.draw_series(good.iter().map(|p| EmptyElement::at((p.0, p.1)) + Circle::new((0, 0), 5, BLUE.filled())))
        .map_err(perr)?
        .label("SPH gauges")
        .legend(|(x, y)| Circle::new((x + 8, y), 5, BLUE.filled()));
    // a label in the right third of the axis is written to the left of its point (it ran off the
    // frame); labels that would overlap are moved apart, with a leader line back to the point
    let split = xl * (xh / xl).powf(2.0 / 3.0);
    let at: Vec<(i32, i32)> = good.iter().map(|p| ch.backend_coord(&(p.0, p.1))).collect();
    let left: Vec<bool> = good.iter().map(|p| p.0 > split).collect();
    let boxes: Vec<LabelBox> = good
        .iter()
        .zip(&at)
        .zip(&left)
        .map(|((p, &(x, y)), &l)| {
            let w = 7 * p.2.chars().count() as i32;
            LabelBox { x0: if l { x - 8 - w } else { x + 8 }, x1: if l { x - 8 } else { x + 8 + w }, y: y - 6 }
        })
        .collect();
    let placed = spread_labels(&boxes, 16);
    for (k, p) in good.iter().enumerate() {
        let (anchor, x) = if left[k] { (HPos::Right, boxes[k].x1) } else { (HPos::Left, boxes[k].x0) };
        let font = TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(anchor, VPos::Bottom));
        if placed[k] != boxes[k].y {
            let end = (if left[k] { boxes[k].x1 } else { boxes[k].x0 }, placed[k] - 6);
            root.draw(&PathElement::new(vec![at[k], end], RGBColor(90, 90, 90).stroke_width(1))).map_err(perr)?;
        }
        root.draw(&Text::new(p.2.clone(), (x, placed[k]), font)).map_err(perr)?;
    }
    ch.configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(perr)?;
    root.present().map_err(perr)?;
    Ok(())
}

/// A label's box in pixels: from x0 to x1, its text's baseline at y (the text above it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LabelBox {
    pub x0: i32,
    pub x1: i32,
    pub y: i32,
}

/// The baselines of `labels` after moving apart those whose boxes (`height` px tall) overlap:
/// taken from the top down, a label that overlaps one already placed moves down below it.
pub fn spread_labels(labels: &[LabelBox], height: i32) -> Vec<i32> {
    let mut order: Vec<usize> = (0..labels.len()).collect();
    order.sort_by_key(|&k| (labels[k].y, labels[k].x0));
    let mut placed: Vec<(usize, i32)> = Vec::new();
    let mut out = vec![0; labels.len()];
    for k in order {
        let b = labels[k];
        let mut y = b.y;
        // each move can bring the label onto another placed one: repeat until none overlaps
        while let Some(&(_, py)) =
            placed.iter().find(|&&(j, py)| labels[j].x0 < b.x1 && b.x0 < labels[j].x1 && (py - y).abs() < height)
        {
            y = py + height;
        }
        placed.push((k, y));
        out[k] = y;
    }
    out
}

/// An animated GIF of particle maps, `delay_ms` between frames.
pub fn animate(path: &Path, maps: &[MapSpec], delay_ms: u32) -> Result<()> {
    let Some(first) = maps.first() else { return Ok(()) };
    let size = map_size(first.bounds, 640);
    // written under a temporary name and renamed when whole: an interrupted report leaves no
    // truncated animation under the final name (`rundir::remove_report` clears the `.tmp`)
    let tmp = path.with_extension("gif.tmp");
    {
        let root = BitMapBackend::gif(&tmp, size, delay_ms).map_err(perr)?.into_drawing_area();
        for m in maps {
            draw_map(&root, m)?;
            root.present().map_err(perr)?;
        }
    }
    std::fs::rename(&tmp, path).io_at(path.display())?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{LabelBox, spread_labels};

    /// Labels whose boxes overlap are moved apart; one apart in x stays where it is.
    #[test]
    fn labels_that_would_overlap_are_moved_apart() {
        // two labels on one line and a third beside them, apart in x: the second moves below the
        // first, the third stays
        let b = [
            LabelBox { x0: 0, x1: 100, y: 50 },
            LabelBox { x0: 50, x1: 150, y: 55 },
            LabelBox { x0: 300, x1: 400, y: 52 },
        ];
        assert_eq!(spread_labels(&b, 16), vec![50, 66, 52]);
        // a third on the first's line moves below the second, not onto it
        let c = [b[0], b[1], LabelBox { x0: 20, x1: 80, y: 50 }];
        let y = spread_labels(&c, 16);
        assert_eq!(y[0], 50);
        assert!(y[1] != y[2] && (y[1] - y[2]).abs() >= 16 && y[1] >= 66 && y[2] >= 66, "{y:?}");
    }

    /// Linear ticks print their shortest decimal, and a key point a rounding below zero prints 0.
    #[test]
    fn axis_labels_are_short_and_never_minus_zero() {
        let l = |v: f64| super::axis_label(&v);
        assert_eq!(
            [l(-1.1e-17), l(200.0), l(0.30000000000000004), l(-0.3), l(0.05)],
            ["0", "200", "0.3", "-0.3", "0.05"]
        );
        assert_eq!(l(2.5e-5), "2.50e-5");
        let t = super::tick_label;
        assert_eq!(
            [t(365.868), t(51.912), t(0.172), t(0.0123), t(1000.0), t(0.01), t(2.0)],
            ["366", "51.9", "0.172", "0.0123", "1000", "0.01", "2"]
        );
        assert_eq!(t(4.2e5), "4e5");
    }
}
