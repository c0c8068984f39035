//! Curves with reference markers (thesis values), and points on log–log axes with their ticks on
//! the data and reference curves (scaled-distance plots).

use super::{axis_label, draw_line, legend_line, perr, range, series_style, tick_label};
use crate::error::Result;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

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
        // a point that is not finite breaks the line (a gauge's void): one segment each side
        let segments: Vec<&[(f64, f64)]> =
            pts.split(|p| !(p.0.is_finite() && p.1.is_finite())).filter(|s| !s.is_empty()).collect();
        for (j, seg) in segments.iter().enumerate() {
            let drawn = draw_line(&mut ch, seg, k)?;
            if j == 0 {
                drawn.label(name).legend(legend_line(k));
            }
        }
    }
    for (k, r) in refs.iter().enumerate() {
        let c = series_style(k).0;
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
