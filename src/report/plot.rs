//! What the reports' log-log plots share: the palette, a series drawn as a line with dots and a
//! legend entry, and the legend box.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// The series' colours, in order (matplotlib's tab10 and two more).
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(90, 90, 90),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(255, 187, 120),
];

/// A chart on a bitmap with log10 values on linear axes.
pub type LogChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws `points` as a line through dots of `radius` in the `k`-th colour, with a legend entry.
pub fn draw_series<'a, 'b: 'a>(
    chart: &mut LogChart<'a, 'b>,
    points: &[(f64, f64)],
    k: usize,
    label: &str,
    radius: i32,
) -> Result<(), String> {
    let colour = PALETTE[k % PALETTE.len()];
    chart
        .draw_series(LineSeries::new(points.to_vec(), colour.stroke_width(2)))
        .map_err(|e| e.to_string())?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
    chart
        .draw_series(
            points
                .iter()
                .map(|&p| Circle::new(p, radius, colour.filled())),
        )
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// Draws `points` dashed in the `k`-th colour, without a legend entry (a curve's estimate
/// beside its measure; [`draw_dashed_legend`] says what the dashes are once).
pub fn draw_dashed<'a, 'b: 'a>(
    chart: &mut LogChart<'a, 'b>,
    points: &[(f64, f64)],
    k: usize,
) -> Result<(), String> {
    let colour = PALETTE[k % PALETTE.len()];
    chart
        .draw_series(DashedLineSeries::new(
            points.to_vec(),
            6,
            4,
            colour.stroke_width(2),
        ))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// A legend entry for the dashed series: a grey dashed line and `label`.
pub fn draw_dashed_legend<'a, 'b: 'a>(
    chart: &mut LogChart<'a, 'b>,
    label: &str,
) -> Result<(), String> {
    let grey = PALETTE[7];
    chart
        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        .map_err(|e| e.to_string())?
        .label(label)
        .legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(0, 0), (7, 0)], grey.stroke_width(2))
                + PathElement::new(vec![(12, 0), (19, 0)], grey.stroke_width(2))
        });
    Ok(())
}

/// The legend, upper right, in a half-transparent white box.
pub fn draw_legend<'a, 'b: 'a>(chart: &mut LogChart<'a, 'b>, font_size: u32) -> Result<(), String> {
    chart
        .configure_series_labels()
        .label_font(("sans-serif", font_size))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| e.to_string())
}
