//! Particle maps: a field or the materials on a colour scale, with a colour bar or a legend and
//! an overlay; their animations.

use super::{axis_label, perr, tick_label};
use crate::error::{IoAt, Result};
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;
use std::path::Path;

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
