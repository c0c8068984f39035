//! PNG plots (plotters): profile panels, time series, particle snapshots. Particle maps and
//! animations are in [`map`], curves with reference markers and scaled-distance plots in [`refs`].

use crate::error::{Result, SphError};
use plotters::chart::SeriesAnno;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

mod map;
mod refs;

pub use map::{Colouring, MapSpec, Overlay, Scale, animate, map_png};
pub use refs::{Reference, lines_with_refs, loglog_on_data};

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

/// The eight colours of a chart's series.
const PALETTE: [RGBColor; 8] = [
    BLUE,
    RED,
    RGBColor(0, 150, 0),
    MAGENTA,
    RGBColor(0, 150, 170),
    BLACK,
    RGBColor(255, 140, 0),
    RGBColor(128, 0, 128),
];

/// The colour of series `k` and whether it is dashed: the eight colours solid, then the same
/// eight dashed, so that 16 series (four directions at four distances) stay apart.
fn series_style(k: usize) -> (RGBColor, bool) {
    (PALETTE[k % PALETTE.len()], (k / PALETTE.len()) % 2 == 1)
}

/// Draws one line of series `k` (its colour and dash from [`series_style`]); returns its
/// annotation, on which the caller sets the legend entry with [`legend_line`].
fn draw_line<'a, 'b, DB, CT>(
    ch: &'b mut ChartContext<'a, DB, CT>,
    pts: &[(f64, f64)],
    k: usize,
) -> Result<&'b mut SeriesAnno<'a, DB>>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate<From = (f64, f64)>,
{
    let (c, dashed) = series_style(k);
    let drawn = if dashed {
        ch.draw_series(DashedLineSeries::new(pts.iter().copied(), 8, 5, c.stroke_width(2)))
    } else {
        ch.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
    };
    drawn.map_err(perr)
}

/// The legend entry of series `k`: a short line in its colour and dash.
fn legend_line<DB: DrawingBackend>(k: usize) -> impl Fn((i32, i32)) -> DynElement<'static, DB, (i32, i32)> {
    let (c, dashed) = series_style(k);
    move |(x, y)| {
        if dashed {
            DashedPathElement::new(vec![(x, y), (x + 16, y)], 5, 3, c.stroke_width(2)).into_dyn()
        } else {
            PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(2)).into_dyn()
        }
    }
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
            let c = series_style(k).0;
            let shown: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.1 > 0.0).collect();
            draw_line(&mut ch, &shown, k)?.label(name).legend(legend_line(k));
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
            draw_line(&mut ch, pts, k)?.label(name).legend(legend_line(k));
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

#[cfg(test)]
mod tests {
    use super::refs::{LabelBox, spread_labels};

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
