//! A linear graph drawn as SVG, without Graphviz: the ground as a bar along the bottom, the
//! other nodes in a row above it in the order the file names them, each branch a curve from
//! node to node with an arrow in its direction, tree branches thick and solid, links thin
//! and dashed.
//!
//! Branches to the ground drop from their node to the bar, spread side by side; branches
//! between two nodes arch above the row, higher for nodes further apart, and parallel
//! branches between one pair arch one above the other, so that no two curves coincide.

use std::collections::HashMap;
use std::fmt::Write;

use bondgraph_core::model::Model;
use bondgraph_core::model::linear_graph::LinearGraph;
use bondgraph_core::normal_tree::NormalTree;

const SPACING: f64 = 220.0;
const MARGIN: f64 = 90.0;
const ROW: f64 = 230.0;
const GROUND_GAP: f64 = 170.0;
const ARCH: f64 = 70.0;

/// The SVG document of `graph` with its normal `tree`.
pub fn draw(model: &Model, graph: &LinearGraph, tree: &NormalTree, spec: &str) -> String {
    let ground = graph.ground.index();
    // Positions: the non-ground nodes in a row, the ground below.
    let row: Vec<usize> = (0..graph.nodes.len()).filter(|&n| n != ground).collect();
    let mut x = vec![0.0; graph.nodes.len()];
    for (i, &n) in row.iter().enumerate() {
        x[n] = MARGIN + SPACING * i as f64 + SPACING / 2.0;
    }
    let width = MARGIN * 2.0 + SPACING * row.len().max(1) as f64;
    let ground_y = ROW + GROUND_GAP;

    // How many edges each node pair has, to spread parallel edges.
    let mut pair_count: HashMap<(usize, usize), usize> = HashMap::new();
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    for (_, _, e) in graph.edges() {
        *pair_count
            .entry(key(e.from.index(), e.to.index()))
            .or_default() += 1;
    }
    // The highest arch decides the top margin.
    let mut top = ROW;
    let mut seen: HashMap<(usize, usize), usize> = HashMap::new();
    let mut curves = Vec::new();
    for (b, p, e) in graph.edges() {
        let (from, to) = (e.from.index(), e.to.index());
        let k = key(from, to);
        let index = *seen.entry(k).and_modify(|i| *i += 1).or_insert(0);
        let count = pair_count[&k];
        let point = |n: usize, offset: f64| {
            if n == ground {
                (offset, ground_y)
            } else {
                (x[n], ROW)
            }
        };
        let curve = if from == ground || to == ground {
            let node = if from == ground { to } else { from };
            let spread = (index as f64 - (count as f64 - 1.0) / 2.0) * 46.0;
            let bottom = x[node] + spread;
            let (start, end) = if from == ground {
                (point(from, bottom), point(to, 0.0))
            } else {
                (point(from, 0.0), point(to, bottom))
            };
            // Bow the curve sideways by its spread, so parallel drops stay apart.
            let control = (
                (start.0 + end.0) / 2.0 + spread * 0.8,
                (ROW + ground_y) / 2.0,
            );
            (start, control, end)
        } else {
            let (start, end) = (point(from, 0.0), point(to, 0.0));
            let distance = (row.iter().position(|&n| n == from).unwrap_or(0) as f64
                - row.iter().position(|&n| n == to).unwrap_or(0) as f64)
                .abs();
            let lift = ARCH * (distance.max(1.0) * 0.6 + index as f64 * 0.9);
            let control = ((start.0 + end.0) / 2.0, ROW - 2.0 * lift);
            top = top.min(ROW - lift - 30.0);
            (start, control, end)
        };
        // Labels of parallel drops to the ground are stacked, so they do not overlap.
        let label_shift = if from == ground || to == ground {
            26.0 * (index as f64 - (count as f64 - 1.0) / 2.0)
        } else {
            0.0
        };
        curves.push((b, p, curve, label_shift));
    }
    let shift = (60.0 - top).max(0.0);
    let height = ground_y + 70.0 + shift;

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="13">"#
    );
    let title = if spec.is_empty() {
        format!(
            "linear graph '{}': normal tree bold, links dashed",
            model.name
        )
    } else {
        format!(
            "linear graph '{}' in mode {spec}: normal tree bold, links dashed",
            model.name
        )
    };
    let _ = writeln!(
        svg,
        r#"<title>{}</title><rect width="100%" height="100%" fill="white"/>"#,
        escape(&title)
    );
    let _ = writeln!(
        svg,
        r#"<text x="{:.0}" y="24" font-size="15" font-weight="bold">{}</text>"#,
        MARGIN / 3.0,
        escape(&title)
    );
    let _ = writeln!(svg, r#"<g transform="translate(0 {shift:.1})">"#);
    // The ground bar.
    let _ = writeln!(
        svg,
        r#"<line x1="{:.0}" y1="{ground_y:.0}" x2="{:.0}" y2="{ground_y:.0}" stroke="black" stroke-width="3"/>"#,
        MARGIN / 2.0,
        width - MARGIN / 2.0
    );
    for i in 0..((width - MARGIN) / 24.0) as usize {
        let x0 = MARGIN / 2.0 + 24.0 * i as f64;
        let _ = writeln!(
            svg,
            r#"<line x1="{x0:.0}" y1="{:.0}" x2="{:.0}" y2="{:.0}" stroke="black" stroke-width="1"/>"#,
            ground_y,
            x0 - 10.0,
            ground_y + 12.0
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="{:.0}" y="{:.0}">{} (ground)</text>"#,
        width - MARGIN / 2.0 - 110.0,
        ground_y + 32.0,
        escape(&graph.node(graph.ground).name)
    );
    for (b, p, ((x0, y0), (cx, cy), (x1, y1)), label_shift) in &curves {
        let in_tree = tree.in_tree[*b][*p];
        let (stroke, dash, colour) = if in_tree {
            (3.2, "", "#1f4e9c")
        } else {
            (1.4, r#" stroke-dasharray="7 5""#, "#555555")
        };
        let _ = writeln!(
            svg,
            r#"<path d="M {x0:.1} {y0:.1} Q {cx:.1} {cy:.1} {x1:.1} {y1:.1}" fill="none" stroke="{colour}" stroke-width="{stroke}"{dash}/>"#
        );
        // The curve's midpoint and direction there, for the arrow and the label.
        let (mx, my) = (
            0.25 * x0 + 0.5 * cx + 0.25 * x1,
            0.25 * y0 + 0.5 * cy + 0.25 * y1,
        );
        let (dx, dy) = (x1 - x0, y1 - y0);
        let length = (dx * dx + dy * dy).sqrt().max(1e-9);
        let (ux, uy) = (dx / length, dy / length);
        let (nx, ny) = (-uy, ux);
        let tip = (mx + 7.0 * ux, my + 7.0 * uy);
        let left = (mx - 6.0 * ux + 5.0 * nx, my - 6.0 * uy + 5.0 * ny);
        let right = (mx - 6.0 * ux - 5.0 * nx, my - 6.0 * uy - 5.0 * ny);
        let _ = writeln!(
            svg,
            r#"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}" fill="{colour}"/>"#,
            tip.0, tip.1, left.0, left.1, right.0, right.1
        );
        // The branch's name, and its role in the mode in small print below it.
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" fill="{colour}">{}</text><text x="{:.1}" y="{:.1}" fill="{colour}" font-size="10">{}</text>"#,
            mx + 10.0,
            my - 6.0 + label_shift,
            escape(&graph.edge_name(*b, *p)),
            mx + 10.0,
            my + 5.0 + label_shift,
            escape(tree.roles[*b][*p].description())
        );
    }
    for &n in &row {
        let _ = writeln!(
            svg,
            r#"<circle cx="{:.1}" cy="{ROW:.1}" r="9" fill="white" stroke="black" stroke-width="2"/><text x="{:.1}" y="{:.1}" font-weight="bold">{}</text>"#,
            x[n],
            x[n] + 12.0,
            ROW - 12.0,
            escape(&graph.nodes[n].name)
        );
    }
    let _ = writeln!(svg, "</g>\n</svg>");
    svg
}

/// `text` with the characters XML reserves escaped.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
