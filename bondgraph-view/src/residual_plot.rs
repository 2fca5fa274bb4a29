//! Residuals of a fit along a condition, one series per setting of the other conditions,
//! before and after an extension: where a model goes wrong, and whether the extension fixes
//! it.

use std::collections::BTreeMap;
use std::error::Error;

use bondgraph_fit::discover::RowResult;
use plotters::prelude::*;

/// An SVG of `model - measured` against the condition column with the most levels (for each
/// row, among the columns it has a value in), one series per setting of the other columns:
/// the baseline's residuals when `after` is false, the selected model's otherwise, of the
/// observed column `column` (its index, and `observed` its name). A time series' residuals
/// are drawn along time.
///
/// # Errors
/// A message when there is nothing to draw or drawing fails.
pub fn residual_svg(
    rows: &[RowResult],
    (column, observed): (usize, &str),
    title: &str,
    after: bool,
) -> Result<String, String> {
    // A time series: the residuals along time, the run's samples one series.
    if !rows.is_empty() && rows.iter().all(|r| r.time.is_some()) {
        let points: Vec<(String, f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let model = if after {
                    r.selected.as_ref()?[column]
                } else {
                    r.baseline[column]
                };
                Some(("samples".to_string(), r.time?, model - r.measured[column]))
            })
            .collect();
        if points.is_empty() {
            return Err("no residuals to plot".into());
        }
        let mut svg = String::new();
        draw(&mut svg, &points, title, "time", observed).map_err(|e| e.to_string())?;
        return Ok(svg);
    }
    let mut levels: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    for row in rows {
        for (column, value) in &row.conditions {
            if let Some(v) = value {
                let entry = levels.entry(column.as_str()).or_default();
                if !entry.contains(v) {
                    entry.push(*v);
                }
            }
        }
    }
    let mut axes: Vec<&str> = Vec::new();
    let points: Vec<(String, f64, f64)> = rows
        .iter()
        .filter_map(|r| {
            let model = if after {
                r.selected.as_ref()?[column]
            } else {
                r.baseline[column]
            };
            let (x_column, x) = r
                .conditions
                .iter()
                .filter_map(|(c, v)| v.map(|v| (c.as_str(), v)))
                .max_by_key(|(c, _)| levels.get(c).map_or(0, Vec::len))?;
            if !axes.contains(&x_column) {
                axes.push(x_column);
            }
            let series: Vec<String> = r
                .conditions
                .iter()
                .filter(|(c, _)| c.as_str() != x_column && levels.contains_key(c.as_str()))
                .map(|(c, v)| match v {
                    Some(v) => format!("{c} = {v}"),
                    None => format!("{c} empty"),
                })
                .collect();
            Some((series.join(", "), x, model - r.measured[column]))
        })
        .collect();
    if points.is_empty() {
        return Err("no residuals to plot".into());
    }
    let mut svg = String::new();
    draw(&mut svg, &points, title, &axes.join(" / "), observed).map_err(|e| e.to_string())?;
    Ok(svg)
}

fn draw(
    svg: &mut String,
    points: &[(String, f64, f64)],
    title: &str,
    x_label: &str,
    observed: &str,
) -> Result<(), Box<dyn Error>> {
    let root = SVGBackend::with_string(svg, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let (x_lo, x_hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let y_max = points.iter().map(|p| p.2.abs()).fold(1e-12, f64::max) * 1.15;
    let pad = ((x_hi - x_lo) * 0.05).max(1e-3 * x_hi.abs().max(1.0));
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x_lo - pad)..(x_hi + pad), -y_max..y_max)?;
    chart
        .configure_mesh()
        .light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .x_desc(x_label)
        .y_desc(format!("model - measured ({observed})"))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()?;
    chart.draw_series(std::iter::once(PathElement::new(
        [(x_lo - pad, 0.0), (x_hi + pad, 0.0)],
        BLACK.mix(0.5).stroke_width(1),
    )))?;
    let mut names: Vec<&str> = Vec::new();
    for (name, _, _) in points {
        if !names.contains(&name.as_str()) {
            names.push(name);
        }
    }
    for (k, name) in names.iter().enumerate() {
        // The palette of the trajectory plots (Okabe-Ito, safe with colour blindness).
        let colour = crate::plot::mode_colour(k);
        let mut series: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == *name)
            .map(|p| (p.1, p.2))
            .collect();
        series.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(series.clone(), colour.stroke_width(2)))?;
        chart
            .draw_series(series.iter().map(|&p| Circle::new(p, 4, colour.filled())))?
            .label(*name)
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, colour.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font(("sans-serif", 14))
        .draw()?;
    root.present()?;
    Ok(())
}
