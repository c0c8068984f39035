//! One figure of a converge ladder as a PNG: its value at each level against the spacing, the
//! Richardson-extrapolated value at zero spacing, the finest value's GCI as an error bar, and the
//! exact value of a verification figure as a dashed line.

use crate::error::{Result, SphError};
use plotters::prelude::*;
use std::path::Path;

fn perr<E: std::fmt::Display>(e: E) -> SphError {
    SphError::Io(format!("plot: {e}"))
}

/// What one plot shows: `pts` (spacing in mm, value) coarse to fine, the extrapolated value
/// and the finest value's GCI (a fraction), both optional.
pub struct FigurePlot<'a> {
    pub title: &'a str,
    pub ylabel: &'a str,
    pub pts: &'a [(f64, f64)],
    pub extrapolated: Option<f64>,
    pub gci: Option<f64>,
    /// The exact value of a verification figure.
    pub exact: Option<f64>,
}

/// Draws `f` into `path` (900 × 560).
pub fn draw(path: &Path, f: &FigurePlot) -> Result<()> {
    let root = BitMapBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(perr)?;
    let finest = f.pts.last().copied().unwrap_or((0.0, 0.0));
    let bar = f.gci.filter(|g| g.is_finite()).map(|g| g * finest.1.abs());
    let mut ys: Vec<f64> = f.pts.iter().map(|p| p.1).collect();
    ys.extend(f.extrapolated.filter(|v| v.is_finite()));
    ys.extend(f.exact);
    if let Some(b) = bar {
        ys.extend([finest.1 - b, finest.1 + b]);
    }
    let lo = ys.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let pad = if hi > lo { 0.12 * (hi - lo) } else { 0.1 * hi.abs().max(1e-12) };
    let xmax = f.pts.iter().map(|p| p.0).fold(0.0, f64::max) * 1.1;
    let mut ch = ChartBuilder::on(&root)
        .caption(f.title, ("sans-serif", 19))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(80)
        .build_cartesian_2d(-0.05 * xmax..xmax, (lo - pad)..(hi + pad))
        .map_err(perr)?;
    ch.configure_mesh().x_desc("spacing (mm)").y_desc(f.ylabel).label_style(("sans-serif", 14)).draw().map_err(perr)?;
    ch.draw_series(LineSeries::new(f.pts.iter().copied(), BLUE.stroke_width(2)))
        .map_err(perr)?
        .label("blastsph, each level")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLUE.stroke_width(2)));
    ch.draw_series(f.pts.iter().map(|&p| Circle::new(p, 5, BLUE.filled()))).map_err(perr)?;
    if let Some(b) = bar {
        let (x, y) = finest;
        let cap = 0.015 * xmax;
        let strokes = [
            vec![(x, y - b), (x, y + b)],
            vec![(x - cap, y - b), (x + cap, y - b)],
            vec![(x - cap, y + b), (x + cap, y + b)],
        ];
        ch.draw_series(strokes.into_iter().map(|s| PathElement::new(s, BLACK.stroke_width(2))))
            .map_err(perr)?
            .label("finest level ± GCI")
            .legend(|(x, y)| PathElement::new(vec![(x + 8, y - 6), (x + 8, y + 6)], BLACK.stroke_width(2)));
    }
    if let Some(e) = f.extrapolated.filter(|v| v.is_finite()) {
        let red = RGBColor(200, 0, 0);
        ch.draw_series(std::iter::once(TriangleMarker::new((0.0, e), 9, red.filled())))
            .map_err(perr)?
            .label("Richardson extrapolation (zero spacing)")
            .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 6, red.filled()));
    }
    if let Some(e) = f.exact {
        let green = RGBColor(0, 140, 0);
        ch.draw_series(DashedLineSeries::new([(-0.05 * xmax, e), (xmax, e)], 8, 5, green.stroke_width(2)))
            .map_err(perr)?
            .label("exact")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], green.stroke_width(2)));
    }
    // the legend in the right-hand corner away from the coarsest level's point
    let coarse_low = f.pts.first().is_some_and(|p| p.1 < 0.5 * (lo + hi));
    ch.configure_series_labels()
        .position(if coarse_low { SeriesLabelPosition::UpperRight } else { SeriesLabelPosition::LowerRight })
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(perr)?;
    root.present().map_err(perr)?;
    Ok(())
}
