//! A simulated trajectory as an SVG figure: stacked panels over one time axis, modes shaded.
//!
//! Panels are stacked top to bottom and share the time axis (seconds). Behind the curves,
//! the time spent in each mode is shaded in a pale colour of its own (the same in every
//! panel), and each event (mode change) is a thin grey vertical line across every panel. A
//! legend under the panels gives the colour of each mode with its specification.

use std::error::Error;
use std::ops::Range;

use bondgraph_solver::Trajectory;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The figure's width, in pixels.
const WIDTH: u32 = 900;
/// The height of one panel, in pixels.
const PANEL_HEIGHT: u32 = 220;
/// The height of the title strip, in pixels.
const TITLE_HEIGHT: u32 = 40;
/// Extra height under the bottom panel for the time axis' name, in pixels.
const TIME_AXIS_HEIGHT: u32 = 20;
/// Left and right margin of the legend, in pixels.
const LEGEND_MARGIN: u32 = 20;
/// Font size of the legend, as plotters counts it (its SVG text is 1.24 times smaller).
const LEGEND_FONT: u32 = 16;
/// Height of one line of legend text, in pixels.
const LEGEND_LINE: u32 = 18;
/// Side of a legend swatch, in pixels.
const SWATCH: i32 = 14;
/// Samples larger than this in magnitude are skipped like infinities: a range over them has
/// no finite width to place tick marks in.
const LARGEST_PLOTTED: f64 = 1e300;

/// The colour of the mode with this index: the Okabe-Ito palette (distinguishable with
/// colour blindness), then colours spread round the hue circle.
pub fn mode_colour(index: usize) -> RGBColor {
    const PALETTE: [RGBColor; 8] = [
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 158, 115),
        RGBColor(240, 228, 66),
        RGBColor(204, 121, 167),
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(153, 153, 153),
    ];
    match PALETTE.get(index) {
        Some(&colour) => colour,
        None => {
            // The golden ratio spreads successive hues evenly.
            let hue = (index as f64 * 0.618_033_988_749_895).fract();
            let (r, g, b) = HSLColor(hue, 0.6, 0.5).rgb();
            RGBColor(r, g, b)
        }
    }
}

/// The pale shade of a mode's colour used for its background bands: the colour mixed with
/// white, opaque so that the grid and the curves drawn over it stay crisp.
fn band_colour(index: usize) -> RGBColor {
    let RGBColor(r, g, b) = mode_colour(index);
    let pale = |c: u8| (255.0 - (255.0 - f64::from(c)) * 0.25).round() as u8;
    RGBColor(pale(r), pale(g), pale(b))
}

/// Consecutive plottable points `(t, value)` of one output: a curve without a gap.
type Stretch = Vec<(f64, f64)>;

/// The colour of event lines.
const EVENT_COLOUR: RGBColor = RGBColor(80, 80, 80);

/// The colours of the curves within one panel, in the order of its outputs.
const CURVE_COLOURS: [RGBColor; 5] = [
    RGBColor(20, 50, 140),
    RGBColor(190, 30, 45),
    RGBColor(20, 120, 60),
    RGBColor(110, 40, 140),
    RGBColor(60, 60, 60),
];

/// Draws a trajectory as an SVG document, one panel per group of outputs, stacked top to
/// bottom over a shared time axis.
///
/// # Arguments
///
/// - `trajectory`: the run to draw.
/// - `title`: the figure's title, drawn above the panels.
/// - `panels`: for each panel, top to bottom, the indices (into
///   `trajectory.output_names`) of the outputs it shows. An empty slice gives one panel per
///   output. A panel with one output takes the output's name as its y label; a panel with
///   several lists them all and adds a key.
///
/// # Returns
///
/// The SVG document's text, about 900 px wide and 220 px high per panel, plus the title and
/// a legend that gives each mode's colour and specification. The time spent in each mode is
/// shaded as a pale band of the mode's colour in every panel; each event is a thin grey
/// vertical line across every panel. Y ranges are padded; a constant signal gets a range
/// around its value; samples that are NaN, infinite or beyond ±1e300 are left out (the curve
/// has a gap there).
///
/// # Errors
///
/// A message, if the trajectory has no outputs or no sample at a finite time, if a panel
/// lists no output or an output the trajectory does not have, or if drawing fails.
pub fn plot_svg(
    trajectory: &Trajectory,
    title: &str,
    panels: &[Vec<usize>],
) -> Result<String, String> {
    let count = trajectory.output_names.len();
    if count == 0 {
        return Err("nothing to plot: the trajectory has no outputs".into());
    }
    let panels: Vec<Vec<usize>> = if panels.is_empty() {
        (0..count).map(|i| vec![i]).collect()
    } else {
        panels.to_vec()
    };
    for (k, panel) in panels.iter().enumerate() {
        if panel.is_empty() {
            return Err(format!("panel {} lists no output", k + 1));
        }
        if let Some(&bad) = panel.iter().find(|&&i| i >= count) {
            return Err(format!(
                "panel {} asks for output {bad}, but the trajectory has {count} output{} \
                 (numbered from 0)",
                k + 1,
                if count == 1 { "" } else { "s" }
            ));
        }
    }
    let time = time_range(trajectory)
        .ok_or("nothing to plot: the trajectory has no samples (at finite times)")?;
    // A run that never switches has nothing to tell apart: no shading, no legend.
    let switching = trajectory.modes.len() > 1 || !trajectory.events.is_empty();
    let legend = if switching {
        Legend::new(&trajectory.modes)
    } else {
        Legend::none()
    };
    let height =
        TITLE_HEIGHT + PANEL_HEIGHT * panels.len() as u32 + TIME_AXIS_HEIGHT + legend.height;

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        draw(&root, trajectory, title, &panels, time, &legend, switching)
            .and_then(|()| root.present().map_err(Into::into))
            .map_err(|e| format!("could not draw the plot: {e}"))?;
    }
    Ok(svg)
}

/// Draws the whole figure on `root`.
fn draw(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    trajectory: &Trajectory,
    title: &str,
    panels: &[Vec<usize>],
    time: Range<f64>,
    legend: &Legend,
    switching: bool,
) -> Result<(), Box<dyn Error>> {
    root.fill(&WHITE)?;
    let (title_area, rest) = root.split_vertically(TITLE_HEIGHT);
    let title_style = ("sans-serif", 24)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    title_area.draw_text(
        title,
        &title_style,
        (WIDTH as i32 / 2, TITLE_HEIGHT as i32 / 2),
    )?;

    let breakpoints: Vec<u32> = (1..panels.len() as u32).map(|k| k * PANEL_HEIGHT).collect();
    let (panel_rows, legend_area) =
        rest.split_vertically(PANEL_HEIGHT * panels.len() as u32 + TIME_AXIS_HEIGHT);
    let areas = panel_rows.split_by_breakpoints::<u32, u32, _, _>([], breakpoints);
    for (k, (area, outputs)) in areas.iter().zip(panels).enumerate() {
        let bottom = k + 1 == panels.len();
        draw_panel(area, trajectory, outputs, time.clone(), bottom, switching)?;
    }
    if switching {
        legend.draw(&legend_area)?;
    }
    Ok(())
}

/// Draws one panel: mode bands, grid, event lines, then the curves.
fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    trajectory: &Trajectory,
    outputs: &[usize],
    time: Range<f64>,
    bottom: bool,
    switching: bool,
) -> Result<(), Box<dyn Error>> {
    let curves: Vec<(String, Vec<Stretch>)> = outputs
        .iter()
        .map(|&i| {
            let name = trajectory.output_names.get(i).cloned().unwrap_or_default();
            (name, runs(trajectory, i))
        })
        .collect();
    let values = range(
        curves
            .iter()
            .flat_map(|(_, runs)| runs.iter().flatten().map(|&(_, y)| y)),
    );
    let names: Vec<&str> = curves.iter().map(|(name, _)| name.as_str()).collect();
    let (label, keys) = panel_label(&names);

    let mut chart = ChartBuilder::on(area)
        .margin_top(10)
        .margin_left(10)
        .margin_right(28)
        .x_label_area_size(if bottom { 28 + TIME_AXIS_HEIGHT } else { 28 })
        .y_label_area_size(90)
        .build_cartesian_2d(time.clone(), values.clone())?;

    // The time spent in each mode, behind everything else.
    chart.draw_series(
        trajectory
            .intervals
            .iter()
            .filter(|_| switching)
            .filter_map(|&(start, end, mode)| {
                if !(start.is_finite() && end.is_finite() && start <= end) {
                    return None;
                }
                if end < time.start || start > time.end {
                    return None;
                }
                let (start, end) = (start.max(time.start), end.min(time.end));
                Some(Rectangle::new(
                    [(start, values.start), (end, values.end)],
                    band_colour(mode).filled(),
                ))
            }),
    )?;

    let mut mesh = chart.configure_mesh();
    mesh.light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .x_labels(10)
        .y_labels(6)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 17))
        .y_desc(label);
    if bottom {
        mesh.x_desc("t (s)");
    }
    mesh.draw()?;

    // The mode changes.
    chart.draw_series(
        trajectory
            .events
            .iter()
            .filter(|event| time.contains(&event.t) || event.t == time.end)
            .map(|event| {
                PathElement::new(
                    [(event.t, values.start), (event.t, values.end)],
                    EVENT_COLOUR.mix(0.85).stroke_width(1),
                )
            }),
    )?;

    for (k, ((_, runs), key)) in curves.iter().zip(&keys).enumerate() {
        let colour = CURVE_COLOURS[k % CURVE_COLOURS.len()];
        for (r, run) in runs.iter().enumerate() {
            let series =
                chart.draw_series(LineSeries::new(run.iter().copied(), colour.stroke_width(2)))?;
            if r == 0 && curves.len() > 1 {
                series.label(key.as_str()).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            }
        }
    }
    if curves.len() > 1 {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .label_font(("sans-serif", 15))
            .draw()?;
    }
    Ok(())
}

/// A panel's y label and the names in its key. One output: its label (`flow:body:
/// velocity (m/s)`) and no key. Several whose labels end in the same quantity and unit
/// (`energy:stored: energy (J)`): that quantity (`energy (J)`), the outputs' names in the
/// key. Several of different quantities: those quantities, the whole labels in the key.
/// Without units: the labels joined. A panel's label fits its height only when short.
fn panel_label(labels: &[&str]) -> (String, Vec<String>) {
    let whole = || labels.iter().map(|l| l.to_string()).collect::<Vec<_>>();
    if labels.len() == 1 {
        return (labels[0].to_string(), whole());
    }
    // `name: quantity (unit)` or `name (unit)`.
    let parts: Option<Vec<(&str, &str)>> = labels
        .iter()
        .map(|label| {
            label.split_once(": ").or_else(|| {
                label
                    .find(" (")
                    .map(|i| (&label[..i], label[i + 1..].trim()))
            })
        })
        .collect();
    let Some(parts) = parts else {
        return (labels.join(", "), whole());
    };
    let mut quantities: Vec<&str> = Vec::new();
    for (_, quantity) in &parts {
        if !quantities.contains(quantity) {
            quantities.push(quantity);
        }
    }
    if quantities.len() == 1 {
        let names = parts.iter().map(|(name, _)| name.to_string()).collect();
        (quantities[0].to_string(), names)
    } else {
        (quantities.join(", "), whole())
    }
}

/// The time axis: from the first to the last finite sample time (or the final time, if
/// later), widened if it is a single instant. `None` if no sample time is finite.
fn time_range(trajectory: &Trajectory) -> Option<Range<f64>> {
    let finite = |t: &f64| t.is_finite() && t.abs() <= LARGEST_PLOTTED;
    let mut times = trajectory.times.iter().copied().filter(finite);
    let first = times.next()?;
    let (mut start, mut end) = times.fold((first, first), |(lo, hi), t| (lo.min(t), hi.max(t)));
    if finite(&trajectory.final_time) && trajectory.final_time > end {
        end = trajectory.final_time;
    }
    if end - start <= start.abs().max(end.abs()) * 1e-12 {
        let pad = if start == 0.0 { 1.0 } else { start.abs() * 0.1 };
        (start, end) = (start - pad, end + pad);
    }
    Some(start..end)
}

/// The plottable points of output `i`, cut into runs at samples that cannot be plotted.
fn runs(trajectory: &Trajectory, i: usize) -> Vec<Stretch> {
    let plottable = |x: f64| x.is_finite() && x.abs() <= LARGEST_PLOTTED;
    let mut runs = vec![Vec::new()];
    for (k, &t) in trajectory.times.iter().enumerate() {
        let value = trajectory.value(k, i);
        match value {
            Some(y) if plottable(t) && plottable(y) => {
                if let Some(run) = runs.last_mut() {
                    run.push((t, y));
                }
            }
            _ => {
                if runs.last().is_some_and(|run| !run.is_empty()) {
                    runs.push(Vec::new());
                }
            }
        }
    }
    runs.retain(|run| !run.is_empty());
    runs
}

/// A y range over these values with a margin; a constant signal gets a range around its
/// value, and no values at all get `-1..1`.
fn range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let Some((lo, hi)) = values.fold(None, |acc, y| match acc {
        None => Some((y, y)),
        Some((lo, hi)) => Some((f64::min(lo, y), f64::max(hi, y))),
    }) else {
        return -1.0..1.0;
    };
    let scale = lo.abs().max(hi.abs());
    let span = hi - lo;
    if span <= scale * 1e-9 {
        let middle = lo / 2.0 + hi / 2.0;
        let pad = if scale == 0.0 { 1.0 } else { scale * 0.1 };
        return middle - pad..middle + pad;
    }
    let pad = span * 0.08;
    lo - pad..hi + pad
}

/// The key under the panels: what the shading and the vertical lines mean, and each mode's
/// colour with its specification.
struct Legend {
    /// Per mode: its colour index and its specification cut into lines.
    entries: Vec<(usize, Vec<String>)>,
    /// Entries per row.
    columns: usize,
    /// Total height, in pixels.
    height: u32,
}

impl Legend {
    /// The text above the entries.
    const HEADING: &str = "Background shading: the mode in force; \
         grey vertical lines: events (mode changes).";

    /// No legend, for a run in one mode throughout.
    fn none() -> Self {
        Self {
            entries: Vec::new(),
            columns: 1,
            height: 0,
        }
    }

    /// Lays out the legend for these modes.
    fn new(modes: &[String]) -> Self {
        let width = (WIDTH - 2 * LEGEND_MARGIN) as f64;
        let entry_extra = f64::from(SWATCH) + 8.0 + 24.0;
        let text = |spec: &String| {
            if spec.is_empty() {
                "(the only mode)".to_string()
            } else {
                spec.clone()
            }
        };
        let widest = modes
            .iter()
            .map(|m| text_width(&text(m)))
            .fold(0.0, f64::max);
        let columns = ((width / (widest + entry_extra)) as usize).clamp(1, 4);
        let wrap = width / columns as f64 - entry_extra;
        let entries: Vec<(usize, Vec<String>)> = modes
            .iter()
            .enumerate()
            .map(|(i, m)| (i, wrap_at_commas(&text(m), wrap)))
            .collect();
        let rows: u32 = entries
            .chunks(columns)
            .map(|row| {
                row.iter()
                    .map(|(_, lines)| lines.len() as u32)
                    .max()
                    .unwrap_or(1)
            })
            .map(|lines| lines * LEGEND_LINE + 6)
            .sum();
        Self {
            entries,
            columns,
            height: 12 + LEGEND_LINE + 8 + rows + 10,
        }
    }

    /// Draws the legend on its own strip.
    fn draw(&self, area: &DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), Box<dyn Error>> {
        let font = ("sans-serif", LEGEND_FONT).into_font().color(&BLACK);
        let margin = LEGEND_MARGIN as i32;
        let mut y = 12;
        area.draw_text(Self::HEADING, &font, (margin, y))?;
        y += (LEGEND_LINE + 8) as i32;
        let column_width = (WIDTH - 2 * LEGEND_MARGIN) as i32 / self.columns as i32;
        for row in self.entries.chunks(self.columns) {
            let mut lines_in_row = 1;
            for (c, (mode, lines)) in row.iter().enumerate() {
                let x = margin + c as i32 * column_width;
                area.draw(&Rectangle::new(
                    [(x, y), (x + SWATCH, y + SWATCH)],
                    band_colour(*mode).filled(),
                ))?;
                area.draw(&Rectangle::new(
                    [(x, y), (x + SWATCH, y + SWATCH)],
                    mode_colour(*mode).stroke_width(1),
                ))?;
                for (l, line) in lines.iter().enumerate() {
                    let line_y = y + l as i32 * LEGEND_LINE as i32;
                    area.draw_text(line, &font, (x + SWATCH + 8, line_y))?;
                }
                lines_in_row = lines_in_row.max(lines.len());
            }
            y += (lines_in_row as u32 * LEGEND_LINE + 6) as i32;
        }
        Ok(())
    }
}

/// The panels `--panel` asks for, as indices of the trajectory's outputs: each text is one
/// panel, its outputs separated by commas (`flow:mass,flow:wall`). None given: one panel
/// per output.
///
/// # Errors
/// A message naming an output the trajectory does not record, or an empty panel.
pub fn panels(trajectory: &Trajectory, texts: &[String]) -> Result<Vec<Vec<usize>>, String> {
    texts
        .iter()
        .enumerate()
        .map(|(k, text)| {
            let names: Vec<&str> = text.split(',').map(str::trim).filter(|n| !n.is_empty()).collect();
            if names.is_empty() {
                return Err(format!("--panel {}: names no output", k + 1));
            }
            names
                .iter()
                .map(|name| {
                    trajectory
                        .output_names
                        .iter()
                        .position(|n| n == name)
                        .ok_or_else(|| {
                            format!(
                                "--panel {}: '{name}' is not recorded by the scenario (it records {})",
                                k + 1,
                                trajectory
                                    .output_names
                                    .iter()
                                    .map(|n| format!("'{n}'"))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            )
                        })
                })
                .collect()
        })
        .collect()
}

/// A generous estimate of the width of legend text, in pixels (an SVG file cannot know the
/// font the viewer will use).
fn text_width(text: &str) -> f64 {
    text.chars().count() as f64 * f64::from(LEGEND_FONT) * 0.5
}

/// Cuts a mode specification into lines no wider than `width` pixels, after commas; a
/// single element's mode longer than that stays whole.
fn wrap_at_commas(spec: &str, width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for piece in spec.split_inclusive(',') {
        if !line.is_empty() && text_width(&line) + text_width(piece) > width {
            lines.push(std::mem::take(&mut line));
        }
        line.push_str(piece);
    }
    lines.push(line);
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use bondgraph_solver::{Event, Stats};

    /// A run through four modes of two friction contacts and a string: the first contact
    /// held, then slipping while the second slips past it, then the second stuck to it,
    /// then the string taut.
    fn four_mode_run() -> Trajectory {
        let modes: Vec<String> = [
            "fr_a=stuck,k=slack,fr_b=slip-",
            "fr_a=slip+,k=slack,fr_b=slip-",
            "fr_a=slip+,k=slack,fr_b=stuck",
            "fr_a=slip+,k=taut,fr_b=stuck",
        ]
        .map(String::from)
        .to_vec();
        let switches = [0.007, 0.02, 0.05];
        let mode_at = |t: f64| switches.iter().filter(|&&s| t >= s).count();
        let times: Vec<f64> = (0..=200).map(|k| f64::from(k) * 1e-3).collect();
        let values = times
            .iter()
            .flat_map(|&t| {
                let v_a = match mode_at(t) {
                    0 => 0.0,
                    1 => 3.0945e-3 * (t - 0.007) / 0.013,
                    2 => 3.0945e-3,
                    _ => 2.9e-3 + 0.19e-3 * (-(t - 0.05) / 0.01).exp(),
                };
                let x_a = if t < 0.007 { 0.0 } else { 2.9e-3 * (t - 0.007) };
                let f_k = if t < 0.05 {
                    0.0
                } else {
                    8.0 * (1.0 - (-(t - 0.05) / 0.01).exp())
                };
                let f_fr_b = if (0.02..0.05).contains(&t) {
                    -5.5 + 0.4 * (t - 0.02) / 0.03
                } else {
                    -5.5
                };
                [f_k, v_a, x_a, f_fr_b]
            })
            .collect();
        let sample_modes = times.iter().map(|&t| mode_at(t)).collect();
        let events = switches
            .iter()
            .enumerate()
            .map(|(i, &t)| Event {
                t,
                from: modes[i].clone(),
                to: modes[i + 1].clone(),
                element: ["fr_a", "fr_b", "k"][i].into(),
                reason: "test".into(),
            })
            .collect();
        Trajectory {
            output_names: ["f_k", "v_a", "x_a", "f_fr_b"].map(String::from).to_vec(),
            times,
            values,
            sample_modes,
            modes,
            intervals: vec![
                (0.0, 0.007, 0),
                (0.007, 0.02, 1),
                (0.02, 0.05, 2),
                (0.05, 0.2, 3),
            ],
            events,
            final_time: 0.2,
            final_state: Vec::new(),
            final_mode: "fr_a=slip+,k=taut,fr_b=stuck".into(),
            stats: Stats {
                segments: 4,
                events: 3,
                modes: 4,
            },
            energy: None,
        }
    }

    fn hex(RGBColor(r, g, b): RGBColor) -> String {
        format!("#{r:02X}{g:02X}{b:02X}")
    }

    /// Whether the SVG has a text element that says exactly this.
    fn has_text(svg: &str, text: &str) -> bool {
        svg.contains(&format!(">\n{text}\n</text>"))
    }

    /// Rectangles filled with this colour.
    fn filled_with(svg: &str, colour: RGBColor) -> usize {
        svg.matches(&format!("fill=\"{}\" stroke=\"none\"", hex(colour)))
            .count()
    }

    /// Lines and polylines stroked in this colour.
    fn stroked_with(svg: &str, colour: RGBColor) -> usize {
        svg.matches(&format!("stroke=\"{}\"", hex(colour))).count()
    }

    #[test]
    fn a_four_mode_run_has_its_title_names_bands_and_event_lines() {
        let trajectory = four_mode_run();
        let title = "Two contacts: v_a = 5.8 mm/s, F ramped, v_b = 6.3 mm/s";
        let svg = plot_svg(&trajectory, title, &[]).unwrap();
        if let Some(path) = std::env::var_os("BONDGRAPH_PLOT_EXAMPLE") {
            std::fs::write(path, &svg).unwrap();
        }
        assert!(svg.starts_with("<svg"), "{}", &svg[..100]);
        assert!(has_text(&svg, title));
        for name in &trajectory.output_names {
            assert!(has_text(&svg, name), "no label {name}");
        }
        let panels = trajectory.output_names.len();
        // Each mode here holds for one interval: a band in each panel, and a legend swatch.
        for (mode, spec) in trajectory.modes.iter().enumerate() {
            assert_eq!(filled_with(&svg, band_colour(mode)), panels + 1, "{spec}");
            assert!(has_text(&svg, spec), "no legend entry for {spec}");
        }
        assert_eq!(
            stroked_with(&svg, EVENT_COLOUR),
            trajectory.events.len() * panels
        );
        assert!(has_text(&svg, "t (s)"));
        assert!(svg.contains("width=\"900\""));
    }

    #[test]
    fn a_mode_visited_twice_gets_a_band_per_visit_and_panels_can_group_outputs() {
        let mut trajectory = four_mode_run();
        trajectory.intervals = vec![(0.0, 0.05, 0), (0.05, 0.1, 1), (0.1, 0.2, 0)];
        trajectory.modes.truncate(2);
        trajectory.sample_modes = trajectory
            .times
            .iter()
            .map(|&t| usize::from((0.05..0.1).contains(&t)))
            .collect();
        trajectory.events.truncate(2);
        let svg = plot_svg(&trajectory, "grouped", &[vec![1, 2], vec![0, 3]]).unwrap();
        assert_eq!(filled_with(&svg, band_colour(0)), 2 * 2 + 1);
        assert_eq!(filled_with(&svg, band_colour(1)), 2 + 1);
        assert_eq!(stroked_with(&svg, EVENT_COLOUR), 2 * 2);
        assert!(has_text(&svg, "v_a, x_a"));
        assert!(has_text(&svg, "f_k, f_fr_b"));
        // A key names each curve of a shared panel.
        assert!(has_text(&svg, "x_a"));
    }

    #[test]
    fn a_shared_panel_is_labelled_with_its_common_quantity_and_unit() {
        let label = |labels: &[&str]| panel_label(labels);
        // One output keeps its whole label.
        assert_eq!(
            label(&["flow:body: velocity (m/s)"]).0,
            "flow:body: velocity (m/s)"
        );
        // One quantity: on the axis once, the names in the key.
        assert_eq!(
            label(&["energy:supplied: energy (J)", "energy:stored: energy (J)"]),
            (
                "energy (J)".to_string(),
                vec!["energy:supplied".to_string(), "energy:stored".to_string()]
            )
        );
        assert_eq!(label(&["a (m)", "b (m)"]).0, "(m)");
        // Different quantities: each once on the axis, the whole labels in the key.
        let (axis, key) = label(&["effort:c: voltage (V)", "flow:c: current (A)"]);
        assert_eq!(axis, "voltage (V), current (A)");
        assert_eq!(key[1], "flow:c: current (A)");
        // No units: the names, joined.
        assert_eq!(label(&["v_a", "x_a"]).0, "v_a, x_a");
    }

    #[test]
    fn a_run_in_one_mode_has_no_shading_and_no_legend() {
        let mut trajectory = four_mode_run();
        trajectory.modes = vec![String::new()];
        trajectory.events.clear();
        trajectory.intervals = vec![(0.0, trajectory.final_time, 0)];
        trajectory.sample_modes.iter_mut().for_each(|m| *m = 0);
        let svg = plot_svg(&trajectory, "one mode", &[vec![0, 1]]).unwrap();
        assert_eq!(filled_with(&svg, band_colour(0)), 0);
        assert!(!has_text(&svg, "(the only mode)"));
        assert!(!has_text(&svg, "Background shading"));
        // Both curves in the one panel, with a key.
        assert_eq!(stroked_with(&svg, CURVE_COLOURS[0]), 1 + 1);
        assert_eq!(stroked_with(&svg, CURVE_COLOURS[1]), 1 + 1);
        let names = &trajectory.output_names;
        let asked = vec![format!("{}, {}", names[0], names[2]), names[1].clone()];
        assert_eq!(
            panels(&trajectory, &asked).unwrap(),
            vec![vec![0, 2], vec![1]]
        );
        assert_eq!(
            panels(&trajectory, &["v_a,nothing".to_string()]).unwrap_err(),
            "--panel 1: 'nothing' is not recorded by the scenario (it records 'f_k', 'v_a', \
             'x_a', 'f_fr_b')"
        );
    }

    #[test]
    fn a_constant_signal_plots_around_its_value() {
        let mut trajectory = four_mode_run();
        for row in trajectory.values.chunks_mut(4) {
            row[0] = 5.0;
            row[1] = 0.0;
        }
        let svg = plot_svg(&trajectory, "constant", &[vec![0], vec![1]]).unwrap();
        assert_eq!(stroked_with(&svg, CURVE_COLOURS[0]), 2);
        assert_eq!(range([5.0, 5.0].into_iter()), 4.5..5.5);
        assert_eq!(range([0.0].into_iter()), -1.0..1.0);
        assert_eq!(range(std::iter::empty()), -1.0..1.0);
    }

    #[test]
    fn unplottable_samples_leave_gaps() {
        let mut trajectory = four_mode_run();
        trajectory.values[50 * 4 + 1] = f64::NAN;
        trajectory.values[100 * 4 + 1] = f64::INFINITY;
        trajectory.values[101 * 4 + 1] = -f64::INFINITY;
        for row in trajectory.values.chunks_mut(4) {
            row[3] = f64::NAN;
        }
        trajectory.values[150 * 4 + 1] = f64::NAN;
        trajectory.times[180] = f64::NAN;
        let svg = plot_svg(&trajectory, "gaps", &[vec![1], vec![3]]).unwrap();
        // The velocity in five pieces, the all-NaN force not at all.
        assert_eq!(stroked_with(&svg, CURVE_COLOURS[0]), 5);
        let runs = runs(&trajectory, 1);
        assert_eq!(runs.iter().map(Vec::len).sum::<usize>(), 201 - 5);
    }

    #[test]
    fn degenerate_trajectories_are_errors_or_plots_but_never_panics() {
        let mut empty = four_mode_run();
        empty.times.clear();
        empty.values.clear();
        empty.sample_modes.clear();
        let error = plot_svg(&empty, "empty", &[]).unwrap_err();
        assert!(error.contains("no samples"), "{error}");

        let mut no_outputs = four_mode_run();
        no_outputs.output_names.clear();
        let error = plot_svg(&no_outputs, "none", &[]).unwrap_err();
        assert!(error.contains("no outputs"), "{error}");

        let error = plot_svg(&four_mode_run(), "bad", &[vec![0], vec![4]]).unwrap_err();
        assert_eq!(
            error,
            "panel 2 asks for output 4, but the trajectory has 4 outputs (numbered from 0)"
        );
        let error = plot_svg(&four_mode_run(), "bad", &[vec![]]).unwrap_err();
        assert_eq!(error, "panel 1 lists no output");

        // One sample, huge values, inconsistent intervals and events, unknown modes.
        let mut odd = four_mode_run();
        odd.times.truncate(1);
        odd.values = vec![1e308, -1e299, 1e-300, 7.0];
        odd.intervals = vec![(f64::NAN, 1.0, 0), (0.5, 0.1, 1), (-5.0, 5.0, 99)];
        odd.events[0].t = f64::INFINITY;
        odd.modes = vec![String::new(), "x".repeat(300)];
        let svg = plot_svg(&odd, "odd", &[]).unwrap();
        assert!(has_text(&svg, "(the only mode)"));
    }

    #[test]
    fn long_specifications_wrap_after_commas() {
        let spec = "fr_a=slip+,k=taut,fr_b=slip-";
        assert_eq!(wrap_at_commas(spec, 1000.0), vec![spec]);
        assert_eq!(
            wrap_at_commas(spec, text_width("fr_a=slip+,k=taut,")),
            vec!["fr_a=slip+,k=taut,", "fr_b=slip-"]
        );
        assert_eq!(
            wrap_at_commas("a_long_name=stuck", 10.0),
            vec!["a_long_name=stuck"]
        );
        let many: Vec<String> = (0..20).map(|i| format!("element_{i}=slip+")).collect();
        let legend = Legend::new(&[many.join(",")]);
        assert_eq!(legend.columns, 1);
        assert!(legend.entries[0].1.len() > 1);
    }
}
