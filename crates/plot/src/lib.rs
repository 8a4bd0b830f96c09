//! PNG figures of Brisance: the run's headline plots (`outputs.plots`) and
//! the validation report's figures (plotters' bitmap backend, text through
//! the pure-Rust `ab_glyph` renderer).
//!
//! * [`plot_panels`]: vertically stacked panels sharing an x axis, e.g.
//!   density / velocity / pressure of a shock tube, numerical points against
//!   the exact solution, each panel with its own legend.
//! * [`plot_convergence`]: log-log error-versus-resolution plot with dashed
//!   reference slopes.
//!
//! Text is drawn in DejaVu Sans, embedded in the binary (the `dejavu`
//! crate), so a figure needs no font installed on the machine;
//! [`register_font`] registers it once and both plot functions call it.

use std::path::Path;
use std::sync::OnceLock;

use anyhow::{anyhow, bail, Context, Result};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

/// Font family name under which the font is registered; plotters uses it
/// for captions, axis labels, tick labels and legends by default.
const FONT_FAMILY: &str = "sans-serif";

/// Width of a panel figure in pixels.
const PANEL_WIDTH: u32 = 900;
/// Height of one panel in pixels (the figure is `n` panels plus the title).
const PANEL_HEIGHT: u32 = 310;
/// Height reserved for the figure title in pixels.
const TITLE_HEIGHT: u32 = 50;
/// Size of a convergence figure in pixels.
const CONVERGENCE_SIZE: (u32, u32) = (850, 700);

/// Colours cycled through by the series of a panel, in order: black (for
/// the exact solution, conventionally first), then the Tableau palette.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
];

/// How a [`Series`] is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A solid polyline through the points (e.g. an exact solution).
    Line,
    /// Filled circular markers (e.g. finite-volume cell averages).
    Points,
}

/// One curve of a panel: `y[i]` against `x[i]` (same length; non-finite
/// pairs are skipped).
#[derive(Debug, Clone, Copy)]
pub struct Series<'a> {
    /// Legend text.
    pub label: &'a str,
    /// Abscissae, in the unit of the figure's x label.
    pub x: &'a [f64],
    /// Ordinates, in the unit of the panel's y label.
    pub y: &'a [f64],
    /// Line or markers.
    pub style: SeriesStyle,
}

/// One panel of a stacked figure: a y-axis label and the series drawn in it.
#[derive(Debug, Clone)]
pub struct Panel<'a> {
    /// Y-axis description, with unit (e.g. "density [kg/m³]").
    pub y_label: &'a str,
    /// Series drawn in this panel, coloured in order from the palette.
    pub series: Vec<Series<'a>>,
}

/// Registers the embedded DejaVu Sans as plotters' `"sans-serif"` font.
///
/// The `ab_glyph` text backend ships no font, so without this every text
/// element fails to draw. Later calls return the first outcome.
pub fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT_FAMILY, FontStyle::Normal, dejavu::sans::regular())
                .map_err(|_| "the embedded DejaVu Sans is not a valid TrueType font".to_string())
        })
        .clone()
        .map_err(|e| anyhow!(e))
}

/// Finite `(x, y)` pairs of a series; errors if `x` and `y` differ in length.
fn finite_points(label: &str, x: &[f64], y: &[f64]) -> Result<Vec<(f64, f64)>> {
    if x.len() != y.len() {
        bail!(
            "series \"{label}\": x has {} values but y has {}",
            x.len(),
            y.len()
        );
    }
    Ok(x.iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(&a, &b)| (a, b))
        .collect())
}

/// `[lo, hi]` of the values, widened when degenerate; `None` if empty.
fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo > hi {
        return None;
    }
    if hi - lo <= 1e-12 * hi.abs().max(lo.abs()) {
        let pad = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
        return Some((lo - pad, hi + pad));
    }
    Some((lo, hi))
}

/// The legend corner that covers the fewest data points: each corner box
/// spans 40 % of the width and 35 % of the height of the plotting range.
fn legend_corner(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (position, right, upper) in corners {
        let count = points
            .iter()
            .filter(|&&(px, py)| {
                let u = (px - x.0) / (x.1 - x.0);
                let v = (py - y.0) / (y.1 - y.0);
                let in_x = if right { u > 0.6 } else { u < 0.4 };
                let in_y = if upper { v > 0.65 } else { v < 0.35 };
                in_x && in_y
            })
            .count();
        if count < best.1 {
            best = (position, count);
        }
    }
    best.0
}

/// Draws one linear-axes panel into `area`.
fn draw_panel(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    x_label: &str,
    panel: &Panel<'_>,
) -> Result<()> {
    let mut data = Vec::with_capacity(panel.series.len());
    for series in &panel.series {
        data.push(finite_points(series.label, series.x, series.y)?);
    }
    let all: Vec<(f64, f64)> = data.iter().flatten().copied().collect();
    let x_range = range(all.iter().map(|p| p.0))
        .ok_or_else(|| anyhow!("panel \"{}\" has no finite data", panel.y_label))?;
    let (y_lo, y_hi) = range(all.iter().map(|p| p.1)).unwrap_or((0.0, 1.0));
    let pad = 0.06 * (y_hi - y_lo);
    let y_range = (y_lo - pad, y_hi + pad);

    let mut chart = ChartBuilder::on(area)
        .margin_top(8)
        .margin_bottom(4)
        .margin_left(8)
        .margin_right(24)
        .x_label_area_size(48)
        .y_label_area_size(84)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(|e| anyhow!("building the \"{}\" panel: {e}", panel.y_label))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(panel.y_label)
        .axis_desc_style((FONT_FAMILY, 18))
        .label_style((FONT_FAMILY, 14))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(|e| anyhow!("drawing the \"{}\" axes: {e}", panel.y_label))?;

    for (index, (series, points)) in panel.series.iter().zip(data).enumerate() {
        let color = PALETTE[index % PALETTE.len()];
        let failed = |e| anyhow!("drawing series \"{}\": {e}", series.label);
        match series.style {
            SeriesStyle::Line => {
                chart
                    .draw_series(LineSeries::new(points, color.stroke_width(2)))
                    .map_err(failed)?
                    .label(series.label)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x - 2, y), (x + 18, y)], color.stroke_width(2))
                    });
            }
            SeriesStyle::Points => {
                chart
                    .draw_series(
                        points
                            .into_iter()
                            .map(|p| Circle::new(p, 3, color.filled())),
                    )
                    .map_err(failed)?
                    .label(series.label)
                    .legend(move |(x, y)| Circle::new((x + 8, y), 4, color.filled()));
            }
        }
    }

    chart
        .configure_series_labels()
        .position(legend_corner(&all, x_range, y_range))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(120, 120, 120))
        .label_font((FONT_FAMILY, 15))
        .margin(10)
        .draw()
        .map_err(|e| anyhow!("drawing the \"{}\" legend: {e}", panel.y_label))?;
    Ok(())
}

/// Draws `panels` stacked vertically (sharing the x-axis description
/// `x_label`) under `title` into a PNG at `path`, `900 × (50 + 310·n)`
/// pixels. Every panel gets its own axes, y label and legend (placed in the
/// corner with the least data). Series are coloured in order: black first
/// (put the exact solution first), then blue, red, green, ….
///
/// Errors if the font cannot be registered, a series has
/// `x` and `y` of different lengths, a panel has no finite data, or the
/// file cannot be written.
pub fn plot_panels(path: &Path, title: &str, x_label: &str, panels: &[Panel]) -> Result<()> {
    let partial = partial_path(path);
    let drawn = draw_panels(&partial, title, x_label, panels);
    settle(drawn, &partial, path)
}

/// Draws [`plot_panels`]' figure into `partial`.
fn draw_panels(partial: &Path, title: &str, x_label: &str, panels: &[Panel]) -> Result<()> {
    let path = partial;
    register_font()?;
    if panels.is_empty() {
        bail!("plot_panels: no panels to draw for {}", path.display());
    }
    let height = TITLE_HEIGHT + PANEL_HEIGHT * panels.len() as u32;
    let root = BitMapBackend::new(partial, (PANEL_WIDTH, height)).into_drawing_area();
    root.fill(&WHITE)
        .map_err(|e| anyhow!("clearing {}: {e}", path.display()))?;
    let (title_area, body) = root.split_vertically(TITLE_HEIGHT);
    title_area
        .draw(&Text::new(
            title.to_string(),
            (PANEL_WIDTH as i32 / 2, TITLE_HEIGHT as i32 / 2),
            (FONT_FAMILY, 24)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(|e| anyhow!("drawing the title: {e}"))?;
    let areas = body.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, x_label, panel)?;
    }
    root.present()
        .map_err(|e| anyhow!("writing {}: {e}", partial.display()))
        .with_context(|| format!("plot \"{title}\""))
}

/// Moves a drawn figure from `partial` to `path`, or removes what a failed
/// drawing left in `partial`.
fn settle(drawn: Result<()>, partial: &Path, path: &Path) -> Result<()> {
    match drawn {
        Ok(()) => std::fs::rename(partial, path)
            .with_context(|| format!("renaming {} to {}", partial.display(), path.display())),
        Err(e) => {
            let _ = std::fs::remove_file(partial);
            Err(e)
        }
    }
}

/// The file a figure is drawn into before it is renamed to `path`, so a
/// reader never sees a half-written PNG: `<stem>.partial.png` beside it
/// (the encoder picks the format from the extension).
fn partial_path(path: &Path) -> std::path::PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy())
        .unwrap_or_default();
    path.with_file_name(format!("{stem}.partial.png"))
}

/// A readable unit for a time axis whose values reach `t_max` seconds:
/// the factor to multiply seconds by and the unit's symbol (µs below 1 ms,
/// ms below 1 s, s otherwise).
pub fn time_unit(t_max: f64) -> (f64, &'static str) {
    if t_max.abs() < 1e-3 {
        (1e6, "µs")
    } else if t_max.abs() < 1.0 {
        (1e3, "ms")
    } else {
        (1.0, "s")
    }
}

/// Least-squares slope of `ln y` against `ln x` over the pairs with both
/// values positive and finite: the observed order of convergence when `x`
/// is the cell size (its negative when `x` is the number of cells). `None`
/// with fewer than two usable points.
pub fn fitted_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite() && **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Draws a log-log convergence plot into a PNG at `path` (850 × 700 px).
///
/// `series` holds `(label, x, y)` triples, e.g. cell count or cell size
/// against an error norm; each is drawn as a line with markers, coloured
/// blue, red, green, …. Pairs that are not positive and finite are skipped.
/// When all series together have at most 12 distinct x values, those values
/// are the x ticks (e.g. 32, 64, 128, …); otherwise ticks follow 1–2–5 per
/// decade.
///
/// `reference_slopes` are literal log-log slopes `s`: for each, a dashed grey
/// line `y = C x^s` labelled "slope s" is drawn alongside the series whose
/// fitted slope ([`fitted_slope`]) is closest to `s`, over that series' x
/// range and a factor 2 below its largest `y` (its coarsest resolution).
/// With `x` the cell size, order `p` means slope `p`; with `x` the number of
/// cells it means slope `−p` (pass e.g. `&[-1.0, -2.0]`).
///
/// Errors if the font cannot be registered, a series has `x` and `y` of different
/// lengths, there are no positive data, or the file cannot be written.
pub fn plot_convergence(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<f64>, Vec<f64>)],
    reference_slopes: &[f64],
) -> Result<()> {
    let partial = partial_path(path);
    let drawn = draw_convergence(&partial, title, x_label, y_label, series, reference_slopes);
    settle(drawn, &partial, path)
}

/// Draws [`plot_convergence`]' figure into `partial`.
fn draw_convergence(
    partial: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[(&str, Vec<f64>, Vec<f64>)],
    reference_slopes: &[f64],
) -> Result<()> {
    let path = partial;
    register_font()?;
    let mut data = Vec::with_capacity(series.len());
    for (label, x, y) in series {
        let points: Vec<(f64, f64)> = finite_points(label, x, y)?
            .into_iter()
            .filter(|&(a, b)| a > 0.0 && b > 0.0)
            .collect();
        data.push(points);
    }

    let references = reference_lines(&data, reference_slopes);
    let all: Vec<(f64, f64)> = data
        .iter()
        .flatten()
        .copied()
        .chain(references.iter().flat_map(|r| r.1))
        .filter(|p| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite())
        .collect();
    if all.is_empty() {
        bail!(
            "plot_convergence: no positive finite data for {}",
            path.display()
        );
    }
    let x_range = log_range(all.iter().map(|p| p.0), 0.06);
    let y_range = log_range(all.iter().map(|p| p.1), 0.08);

    let mut x_data: Vec<f64> = data.iter().flatten().map(|p| p.0).collect();
    x_data.sort_by(f64::total_cmp);
    x_data.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    let x_ticks = if !x_data.is_empty() && x_data.len() <= 12 {
        x_data
    } else {
        log_ticks(x_range)
    };
    let y_ticks = log_ticks(y_range);
    let x_plain = x_ticks.iter().all(|&v| plain_tick(v));
    let y_plain = y_ticks.iter().all(|&v| plain_tick(v));

    let root = BitMapBackend::new(partial, CONVERGENCE_SIZE).into_drawing_area();
    root.fill(&WHITE)
        .map_err(|e| anyhow!("clearing {}: {e}", path.display()))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT_FAMILY, 24))
        .margin(16)
        .margin_right(30)
        .x_label_area_size(55)
        .y_label_area_size(90)
        .build_cartesian_2d(
            (x_range.0..x_range.1)
                .log_scale()
                .with_key_points(x_ticks)
                .with_light_points(minor_log_ticks(x_range)),
            (y_range.0..y_range.1)
                .log_scale()
                .with_key_points(y_ticks)
                .with_light_points(minor_log_ticks(y_range)),
        )
        .map_err(|e| anyhow!("building the convergence axes: {e}"))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT_FAMILY, 18))
        .label_style((FONT_FAMILY, 14))
        .x_label_formatter(&|v| format_log_tick(*v, x_plain))
        .y_label_formatter(&|v| format_log_tick(*v, y_plain))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()
        .map_err(|e| anyhow!("drawing the convergence axes: {e}"))?;

    let grey = RGBColor(110, 110, 110);
    for (slope, ends) in &references {
        chart
            .draw_series(DashedLineSeries::new(
                ends.iter().copied(),
                10,
                6,
                grey.stroke_width(2),
            ))
            .map_err(|e| anyhow!("drawing the slope-{slope} reference: {e}"))?
            .label(format!("slope {}", format_slope(*slope)))
            .legend(move |(x, y)| {
                DashedPathElement::new(vec![(x - 2, y), (x + 18, y)], 5, 3, grey.stroke_width(2))
            });
    }

    for (index, ((label, _, _), points)) in series.iter().zip(data).enumerate() {
        let color = PALETTE[1 + index % (PALETTE.len() - 1)];
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(2),
            ))
            .map_err(|e| anyhow!("drawing series \"{label}\": {e}"))?;
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| anyhow!("drawing series \"{label}\": {e}"))?
            .label(*label)
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(-2, 0), (18, 0)], color.stroke_width(2))
                    + Circle::new((8, 0), 4, color.filled())
            });
    }

    let logs: Vec<(f64, f64)> = all.iter().map(|p| (p.0.log10(), p.1.log10())).collect();
    chart
        .configure_series_labels()
        .position(legend_corner(
            &logs,
            (x_range.0.log10(), x_range.1.log10()),
            (y_range.0.log10(), y_range.1.log10()),
        ))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(120, 120, 120))
        .label_font((FONT_FAMILY, 15))
        .margin(10)
        .draw()
        .map_err(|e| anyhow!("drawing the convergence legend: {e}"))?;
    root.present()
        .map_err(|e| anyhow!("writing {}: {e}", partial.display()))
        .with_context(|| format!("plot \"{title}\""))
}

/// Reference lines `(slope, [start, end])`: each runs along the series whose
/// fitted slope is closest, over its x range, a factor 2 below its point of
/// largest `y`.
fn reference_lines(data: &[Vec<(f64, f64)>], slopes: &[f64]) -> Vec<(f64, [(f64, f64); 2])> {
    let fitted: Vec<Option<f64>> = data
        .iter()
        .map(|d| {
            let (x, y): (Vec<f64>, Vec<f64>) = d.iter().copied().unzip();
            fitted_slope(&x, &y)
        })
        .collect();
    let mut lines = Vec::new();
    for &slope in slopes.iter().filter(|s| s.is_finite()) {
        let closest = fitted
            .iter()
            .enumerate()
            .filter_map(|(i, f)| f.map(|f| (i, (f - slope).abs())))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((index, _)) = closest else { continue };
        let points = &data[index];
        let anchor = points
            .iter()
            .copied()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("a fitted series has points");
        let Some((x_lo, x_hi)) = range(points.iter().map(|p| p.0)) else {
            continue;
        };
        let line = |x: f64| 0.5 * anchor.1 * (x / anchor.0).powf(slope);
        lines.push((slope, [(x_lo, line(x_lo)), (x_hi, line(x_hi))]));
    }
    lines
}

/// `[lo, hi]` of positive values widened to at least 0.6 decades and padded
/// by `pad` times the span (in decades) on each side.
fn log_range(values: impl Iterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v.log10()), hi.max(v.log10()))
    });
    let (lo, hi) = if hi - lo < 0.6 {
        let mid = 0.5 * (lo + hi);
        (mid - 0.3, mid + 0.3)
    } else {
        (lo, hi)
    };
    let span = hi - lo;
    (10f64.powf(lo - pad * span), 10f64.powf(hi + pad * span))
}

/// Major ticks of a log axis over `[lo, hi]`: powers of ten, plus 2× and 5×
/// (or only 3×) multiples when the range spans few decades.
fn log_ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    let decades = hi.log10() - lo.log10();
    let mantissas: &[f64] = if decades <= 2.5 {
        &[1.0, 2.0, 5.0]
    } else if decades <= 4.5 {
        &[1.0, 3.0]
    } else {
        &[1.0]
    };
    let step = if decades > 12.0 { 2 } else { 1 };
    let mut ticks = Vec::new();
    let mut k = lo.log10().floor() as i32;
    while f64::from(k) <= hi.log10().ceil() {
        for m in mantissas {
            let v = m * 10f64.powi(k);
            if v >= lo && v <= hi {
                ticks.push(v);
            }
        }
        k += step;
    }
    ticks
}

/// Minor grid of a log axis: 1…9 × 10^k inside `[lo, hi]`.
fn minor_log_ticks((lo, hi): (f64, f64)) -> Vec<f64> {
    if hi.log10() - lo.log10() > 8.0 {
        return Vec::new();
    }
    let mut ticks = Vec::new();
    let mut k = lo.log10().floor() as i32;
    while f64::from(k) <= hi.log10().ceil() {
        for m in 1..10 {
            let v = f64::from(m) * 10f64.powi(k);
            if v >= lo && v <= hi {
                ticks.push(v);
            }
        }
        k += 1;
    }
    ticks
}

/// Whether a tick value reads well as a plain decimal number.
fn plain_tick(v: f64) -> bool {
    let a = v.abs();
    (1e-2..1e5).contains(&a) && ((a * 100.0).round() - a * 100.0).abs() < 1e-6 * a * 100.0
}

/// Tick label for a log axis: a plain number (`32`, `0.05`) when the whole
/// axis reads well that way, otherwise scientific notation (`2e-5`).
fn format_log_tick(v: f64, plain: bool) -> String {
    if plain {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let s = format!("{v:.1e}");
        s.replace(".0e", "e")
    }
}

/// Slope for a legend, with a proper minus sign.
fn format_slope(s: f64) -> String {
    let text = if s.fract() == 0.0 {
        format!("{}", s.abs() as i64)
    } else {
        format!("{}", s.abs())
    };
    if s < 0.0 {
        format!("\u{2212}{text}")
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitted_slope_of_a_power_law_is_its_exponent() {
        let x = [1.0, 2.0, 4.0, 8.0];
        let y: Vec<f64> = x.iter().map(|v: &f64| 3.0 * v.powf(-2.0)).collect();
        let p = fitted_slope(&x, &y).unwrap();
        assert!((p + 2.0).abs() < 1e-12, "{p}");
        assert_eq!(fitted_slope(&[1.0], &[1.0]), None);
        assert_eq!(fitted_slope(&[1.0, -2.0], &[1.0, 2.0]), None);
    }

    #[test]
    fn time_units_follow_the_span() {
        assert_eq!(time_unit(8.0e-5), (1e6, "µs"));
        assert_eq!(time_unit(2.0e-3), (1e3, "ms"));
        assert_eq!(time_unit(3.0), (1.0, "s"));
    }

    #[test]
    fn a_figure_is_a_whole_png_and_leaves_no_partial_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("wall.png");
        let t = [0.0, 1.0, 2.0, 3.0];
        let v = [0.0, 400.0, 700.0, 750.0];
        let panel = Panel {
            y_label: "velocity [m/s]",
            series: vec![Series {
                label: "wall",
                x: &t,
                y: &v,
                style: SeriesStyle::Line,
            }],
        };
        plot_panels(&path, "a test", "time [µs]", &[panel]).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        // Width and height from the IHDR chunk: one panel and the title.
        let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        assert_eq!((w, h), (PANEL_WIDTH, TITLE_HEIGHT + PANEL_HEIGHT));
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("wall.png")]);
    }

    #[test]
    fn series_of_unequal_lengths_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let panel = Panel {
            y_label: "y",
            series: vec![Series {
                label: "bad",
                x: &[0.0, 1.0],
                y: &[0.0],
                style: SeriesStyle::Points,
            }],
        };
        let e = plot_panels(&dir.path().join("bad.png"), "t", "x", &[panel]).unwrap_err();
        assert!(
            format!("{e:#}").contains("x has 2 values but y has 1"),
            "{e:#}"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
