//! A bond graph drawn as SVG, without Graphviz: the geometry of
//! [`bondgraph_core::diagram`] written out as text.
//!
//! Each part carries a class (`element`, `bond`, `bond-line`, `half-arrow`, `causal-stroke`,
//! `bond-number`, `legend`) and each bond its number, ends and stroke end as `data-`
//! attributes, so the drawing can be styled, and checked by reading it back.

use std::fmt::Write;

use bondgraph_core::causality::{Causality, Stroke};
use bondgraph_core::diagram::{self, Diagram, FONT, Point, Rect, SMALL_FONT};
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;

use crate::lg_svg::escape;

const INK: &str = "#1b1b1b";
const DERIVATIVE: &str = "#c62828";

/// The title of a drawing of `model` in the mode `spec` (empty for the only mode).
pub fn title(model: &Model, spec: &str) -> String {
    if spec.is_empty() {
        format!("bond graph '{}'", model.name())
    } else {
        format!("bond graph '{}' in mode {spec}", model.name())
    }
}

/// The SVG document of `model` with its causal strokes in `mode`.
pub fn draw(model: &Model, mode: &Mode, causality: &Causality) -> String {
    let drawing = diagram::layout(model, mode, causality, &title(model, &mode.spec(model)));
    write(model, &drawing)
}

fn write(model: &Model, d: &Diagram) -> String {
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="sans-serif" font-size="{FONT}">"#,
        w = d.width,
        h = d.height
    );
    let _ = writeln!(
        svg,
        r#"<title>{}</title><rect width="100%" height="100%" fill="white"/>"#,
        escape(&d.title)
    );
    let t = &d.title_bounds;
    let _ = writeln!(
        svg,
        r#"<text class="title" x="{:.1}" y="{:.1}" font-size="16" font-weight="bold" {}>{}</text>"#,
        t.x,
        t.y + t.height * 0.75,
        box_data(t),
        escape(&d.title)
    );
    for b in &d.bonds {
        let colour = if b.derivative { DERIVATIVE } else { INK };
        let width = if b.derivative { 2.6 } else { 1.6 };
        let bond = model.bond(b.bond);
        let _ = writeln!(
            svg,
            r#"<g class="bond" data-bond="{}" data-from="{}" data-to="{}" data-stroke="{}" data-derivative="{}" stroke="{colour}" stroke-width="{width}" stroke-linecap="round">"#,
            b.number,
            escape(&model.element(bond.from).name),
            escape(&model.element(bond.to).name),
            match b.stroke_at {
                Stroke::AtFrom => "from",
                Stroke::AtTo => "to",
            },
            b.derivative
        );
        let _ = writeln!(
            svg,
            r#"  <line class="bond-line" {}/>"#,
            line(b.start, b.end)
        );
        let _ = writeln!(
            svg,
            r#"  <line class="half-arrow" {}/>"#,
            line(b.half_arrow[0], b.half_arrow[1])
        );
        let _ = writeln!(
            svg,
            r#"  <line class="causal-stroke" {}/>"#,
            line(b.stroke[0], b.stroke[1])
        );
        let r = &b.number_bounds;
        let _ = writeln!(
            svg,
            r#"  <text class="bond-number" x="{:.1}" y="{:.1}" text-anchor="middle" font-size="{SMALL_FONT}" fill="{colour}" stroke="none" {}>{}</text>"#,
            b.number_center.x,
            b.number_center.y + SMALL_FONT * 0.35,
            box_data(r),
            b.number
        );
        let _ = writeln!(svg, "</g>");
    }
    for n in &d.nodes {
        let r = &n.bounds;
        let name = &model.element(n.element).name;
        let label_y = match &n.mode {
            Some(_) => r.y + FONT + 1.0,
            None => n.center.y + FONT * 0.35,
        };
        let _ = write!(
            svg,
            r#"<g class="element" data-element="{}" {}><text x="{:.1}" y="{:.1}" text-anchor="middle" fill="{INK}">{}</text>"#,
            escape(name),
            box_data(r),
            n.center.x,
            label_y,
            escape(&n.label)
        );
        if let Some(mode) = &n.mode {
            let _ = write!(
                svg,
                r##"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="{SMALL_FONT}" fill="#555555">{}</text>"##,
                n.center.x,
                r.y + r.height - 4.0,
                escape(mode)
            );
        }
        let _ = writeln!(svg, "</g>");
    }
    for entry in &d.legend {
        let colour = if entry.derivative { DERIVATIVE } else { INK };
        let width = if entry.derivative { 2.6 } else { 1.6 };
        let [a, b] = entry.sample;
        let _ = writeln!(
            svg,
            r#"<g class="legend" {}><line {} stroke="{colour}" stroke-width="{width}"/><line {} stroke="{colour}" stroke-width="{width}"/><line {} stroke="{colour}" stroke-width="{width}"/><text x="{:.1}" y="{:.1}" font-size="{SMALL_FONT}" fill="{INK}">{}</text></g>"#,
            box_data(&entry.bounds),
            line(a, b),
            line(
                b,
                Point {
                    x: b.x - 10.0,
                    y: b.y - 6.0
                }
            ),
            line(
                Point {
                    x: b.x,
                    y: b.y - 8.0
                },
                Point {
                    x: b.x,
                    y: b.y + 8.0
                }
            ),
            b.x + 12.0,
            a.y + SMALL_FONT * 0.35,
            escape(&entry.text)
        );
    }
    svg.push_str("</svg>\n");
    svg
}

fn line(a: Point, b: Point) -> String {
    format!(
        r#"x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}""#,
        a.x, a.y, b.x, b.y
    )
}

/// The box a text takes, as `data-` attributes, for checking that none overlap.
fn box_data(r: &Rect) -> String {
    format!(
        r#"data-box="{:.2} {:.2} {:.2} {:.2}""#,
        r.x, r.y, r.width, r.height
    )
}
