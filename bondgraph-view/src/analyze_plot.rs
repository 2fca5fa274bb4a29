//! SVG plots of `bondgraph analyze`: the Bode diagram (magnitude and phase against a
//! logarithmic frequency axis) and the exact step response with its final value and ±2 %
//! band.

use std::error::Error;

use bondgraph_solver::analysis::BodePoint;
use plotters::prelude::*;

const WIDTH: u32 = 800;

/// The Bode diagram of `points`, titled `title`, its magnitude axis labelled
/// `magnitude_label` (`magnitude (dB of V/V)`).
///
/// # Errors
/// A message when drawing fails.
pub fn bode_svg(
    points: &[BodePoint],
    title: &str,
    magnitude_label: &str,
) -> Result<String, String> {
    let mut svg = String::new();
    draw_bode(&mut svg, points, title, magnitude_label).map_err(|e| e.to_string())?;
    Ok(svg)
}

/// How many ticks the frequency axis (logarithms from `lo` to `hi`) may have so that they
/// fall on decades: as many as the whole decades in the range, so no finer step than one
/// decade fits (a tick between two decades would print the same rounded label twice).
fn decade_ticks(lo: f64, hi: f64) -> usize {
    ((hi - lo).floor() as usize + 1).max(2)
}

/// `10^k` as a tick label: `0.01`, `1`, `1000` near 1, `1e-5`, `1e6` beyond.
fn decade_label(k: f64) -> String {
    match k.round() as i32 {
        -3 => "0.001".to_string(),
        -2 => "0.01".to_string(),
        -1 => "0.1".to_string(),
        k @ 0..=4 => format!("1{}", "0".repeat(k as usize)),
        k => format!("1e{k}"),
    }
}

fn range(values: impl Iterator<Item = f64>, floor: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.08).max(floor);
    (lo - pad, hi + pad)
}

fn draw_bode(
    svg: &mut String,
    points: &[BodePoint],
    title: &str,
    magnitude_label: &str,
) -> Result<(), Box<dyn Error>> {
    let root = SVGBackend::with_string(svg, (WIDTH, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, ("sans-serif", 20))?;
    let (top, bottom) = root.split_vertically(300);
    let x: Vec<f64> = points.iter().map(|p| p.omega.log10()).collect();
    let (x_lo, x_hi) = (x[0], x[x.len() - 1]);
    let panels: [(&DrawingArea<_, _>, &str, Vec<f64>); 2] = [
        (
            &top,
            magnitude_label,
            points.iter().map(|p| p.magnitude_db).collect(),
        ),
        (
            &bottom,
            "phase (deg)",
            points.iter().map(|p| p.phase_deg).collect(),
        ),
    ];
    for (area, label, values) in panels {
        let (y_lo, y_hi) = range(values.iter().copied(), 1.0);
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)?;
        chart
            .configure_mesh()
            .light_line_style(TRANSPARENT)
            .bold_line_style(BLACK.mix(0.12))
            .x_desc("angular frequency (rad/s)")
            .x_labels(decade_ticks(x_lo, x_hi))
            .x_label_formatter(&|v| decade_label(*v))
            .y_desc(label)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()?;
        let series = x
            .iter()
            .zip(&values)
            .filter(|(_, v)| v.is_finite())
            .map(|(a, b)| (*a, *b));
        chart.draw_series(LineSeries::new(
            series,
            crate::plot::mode_colour(0).stroke_width(2),
        ))?;
    }
    root.present()?;
    Ok(())
}

/// The step response `(t, y)` with its final value, titled `title`.
///
/// # Errors
/// A message when drawing fails.
pub fn step_svg(
    points: &[(f64, f64)],
    final_value: Option<f64>,
    title: &str,
    y_label: &str,
) -> Result<String, String> {
    let mut svg = String::new();
    draw_step(&mut svg, points, final_value, title, y_label).map_err(|e| e.to_string())?;
    Ok(svg)
}

fn draw_step(
    svg: &mut String,
    points: &[(f64, f64)],
    final_value: Option<f64>,
    title: &str,
    y_label: &str,
) -> Result<(), Box<dyn Error>> {
    let root = SVGBackend::with_string(svg, (WIDTH, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let t_hi = points.last().map_or(1.0, |p| p.0).max(f64::MIN_POSITIVE);
    let (y_lo, y_hi) = range(
        points.iter().map(|p| p.1).chain(final_value).chain([0.0]),
        1e-12,
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..t_hi, y_lo..y_hi)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .x_desc("time (s)")
        .y_desc(y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    if let Some(y) = final_value {
        for (level, style) in [
            (y, BLACK.mix(0.6).stroke_width(1)),
            (y * 1.02, BLACK.mix(0.25).stroke_width(1)),
            (y * 0.98, BLACK.mix(0.25).stroke_width(1)),
        ] {
            chart.draw_series(std::iter::once(PathElement::new(
                [(0.0, level), (t_hi, level)],
                style,
            )))?;
        }
    }
    chart.draw_series(LineSeries::new(
        points.iter().copied(),
        crate::plot::mode_colour(0).stroke_width(2),
    ))?;
    root.present()?;
    Ok(())
}
