//! A linear graph drawn as SVG, without Graphviz: the ground as a bar along the bottom, the
//! other nodes in a row above it in the order the file names them, each branch a line or a
//! curve from node to node with an arrow in its direction, tree branches thick and solid,
//! links thin and dashed.
//!
//! Branches to the ground leave their node in lanes side by side: the first straight down,
//! the others fanning out to the right and then down, each lane as wide as the label
//! beside it, so that a label never lies across another branch; the nodes are spaced to
//! make room for their lanes. Branches between two nodes arch above the row, higher for
//! nodes further apart and one above the other for parallel branches, their labels above
//! their tops. A node's name is below it, to the left of its first lane.
//!
//! Each branch is a group (`class="branch"`) that names its edge, its nodes and whether it
//! is in the tree; every text carries the box it is estimated to fill and every branch the
//! points of its line (`data-box`, `data-points`), so the drawing can be read back and
//! checked: every branch drawn once, no label on another label, a line or a node.

use std::collections::HashMap;
use std::fmt::Write;

use bondgraph_core::model::Model;
use bondgraph_core::model::linear_graph::LinearGraph;
use bondgraph_core::normal_tree::NormalTree;

/// The least distance between two nodes of the row.
const SPACING: f64 = 220.0;
const MARGIN: f64 = 90.0;
/// Height of the row of nodes above the top of the drawing's group (before the shift that
/// makes room for the arches).
const ROW: f64 = 230.0;
const GROUND_GAP: f64 = 190.0;
/// How far a fanned-out lane runs sideways before it turns down.
const FAN: f64 = 50.0;
const ARCH: f64 = 70.0;
/// Radius of a node's circle.
const NODE: f64 = 9.0;
/// Gap between a lane and its label, and between a label and the next lane.
const LABEL_GAP: f64 = 8.0;
const LANE_GAP: f64 = 18.0;
/// Font size of labels, and of the small print under a branch's name, in pixels.
const FONT: f64 = 13.0;
const SMALL_FONT: f64 = 10.0;

/// Estimated width of `text` in a font of `size` pixels: generous (0.62 of the size per
/// character), as an SVG file cannot know its fonts.
fn text_width(text: &str, size: f64) -> f64 {
    0.62 * size * text.chars().count() as f64
}

/// How one edge is drawn.
struct Drawn {
    branch: usize,
    port: usize,
    /// The line's corners (a drop to the ground) or the quadratic curve's start, control
    /// and end (an arch), from the edge's `from` node towards its `to` node.
    path: Path,
    /// Where the arrow sits and which way it points (a unit vector).
    arrow: ((f64, f64), (f64, f64)),
    /// The name's and the role's anchor (`x`, baseline) and whether they are centred there.
    name_at: (f64, f64),
    role_at: (f64, f64),
    centred: bool,
}

enum Path {
    Line(Vec<(f64, f64)>),
    Quadratic([(f64, f64); 3]),
}

impl Path {
    fn d(&self) -> String {
        match self {
            Path::Line(points) => points
                .iter()
                .enumerate()
                .map(|(i, (x, y))| format!("{} {x:.1} {y:.1}", if i == 0 { "M" } else { "L" }))
                .collect::<Vec<_>>()
                .join(" "),
            Path::Quadratic([(x0, y0), (cx, cy), (x1, y1)]) => {
                format!("M {x0:.1} {y0:.1} Q {cx:.1} {cy:.1} {x1:.1} {y1:.1}")
            }
        }
    }

    /// Points along the line, for reading the drawing back: the corners of a line, twenty
    /// samples of a curve.
    fn points(&self) -> Vec<(f64, f64)> {
        match self {
            Path::Line(points) => points.clone(),
            Path::Quadratic([a, c, b]) => (0..=20)
                .map(|i| {
                    let t = f64::from(i) / 20.0;
                    let (u, v, w) = ((1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t);
                    (u * a.0 + v * c.0 + w * b.0, u * a.1 + v * c.1 + w * b.1)
                })
                .collect(),
        }
    }
}

/// Where everything goes: the nodes in a row above the ground, each edge to the ground in a
/// lane of its own, the other edges as arches over the row.
struct Layout {
    /// Each node's position along the row (the ground's unused).
    x: Vec<f64>,
    /// The non-ground nodes, left to right.
    row: Vec<usize>,
    ground_y: f64,
    width: f64,
    height: f64,
    /// How far everything moves down to make room for the highest arch.
    shift: f64,
    /// Every edge's path, arrow and label places, in file order.
    drawn: Vec<Drawn>,
}

fn layout(graph: &LinearGraph, tree: &NormalTree) -> Layout {
    let ground = graph.ground.index();
    let label_width = |b: usize, p: usize| {
        text_width(&graph.edge_name(b, p), FONT)
            .max(text_width(tree.roles[b][p].description(), SMALL_FONT))
    };
    // The non-ground nodes in a row, and the edges that drop from each to the ground.
    let row: Vec<usize> = (0..graph.nodes.len()).filter(|&n| n != ground).collect();
    let mut drops: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
    for (b, p, e) in graph.edges() {
        let (from, to) = (e.from.index(), e.to.index());
        if from == ground || to == ground {
            let node = if from == ground { to } else { from };
            drops.entry(node).or_default().push((b, p));
        }
    }
    // Positions: each node right of the previous one's lanes and of its own name.
    let ground_y = ROW + GROUND_GAP;
    let mut x = vec![0.0; graph.nodes.len()];
    let mut lanes: HashMap<(usize, usize), f64> = HashMap::new();
    let mut right = MARGIN / 2.0;
    for (i, &n) in row.iter().enumerate() {
        let name = text_width(&graph.nodes[n].name, FONT);
        let least = if i == 0 {
            MARGIN
        } else {
            x[row[i - 1]] + SPACING
        };
        x[n] = least.max(right + LANE_GAP + name + NODE + 4.0);
        let mut lane = x[n];
        right = x[n] + NODE;
        for &(b, p) in drops.get(&n).map_or(&[][..], Vec::as_slice) {
            lanes.insert((b, p), lane);
            right = lane + LABEL_GAP + label_width(b, p);
            lane = right + LANE_GAP;
        }
    }
    let width = right + MARGIN;

    let lane_mid = (ROW + FAN + ground_y) / 2.0;
    let mut drawn = Vec::new();
    let mut arches = Vec::new();
    for (b, p, e) in graph.edges() {
        let (from, to) = (e.from.index(), e.to.index());
        let Some(&lane) = lanes.get(&(b, p)) else {
            arches.push((b, p, from, to));
            continue;
        };
        let node = if from == ground { to } else { from };
        let mut points = vec![(x[node], ROW + NODE)];
        if lane != x[node] {
            points.push((lane, ROW + FAN));
        }
        points.push((lane, ground_y));
        if from == ground {
            points.reverse();
        }
        let down = if from == ground { -1.0 } else { 1.0 };
        drawn.push(Drawn {
            branch: b,
            port: p,
            path: Path::Line(points),
            arrow: ((lane, lane_mid + 16.0 * down), (0.0, down)),
            name_at: (lane + LABEL_GAP, lane_mid - 4.0),
            role_at: (lane + LABEL_GAP, lane_mid + 8.0),
            centred: false,
        });
    }
    // Arches, the narrowest first: each as low as it can be without its line crossing a
    // label placed before it, or its label meeting a line or a label placed before it, so
    // that a wide arch passes over the narrow ones and their labels.
    arches.sort_by(|a, b| {
        let span = |&(_, _, from, to): &(usize, usize, usize, usize)| (x[from] - x[to]).abs();
        span(a).total_cmp(&span(b))
    });
    let mut labels: Vec<Rect> = Vec::new();
    let mut curves: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut top = ROW;
    for (b, p, from, to) in arches {
        let (x0, x1) = (x[from], x[to]);
        let mid = (x0 + x1) / 2.0;
        let direction = if x1 >= x0 { 1.0 } else { -1.0 };
        let (name, role) = (graph.edge_name(b, p), tree.roles[b][p].description());
        let mut lift = ARCH * 0.6 * ((x1 - x0).abs() / SPACING).max(1.0);
        let arch = loop {
            let peak = ROW - lift;
            let path = Path::Quadratic([(x0, ROW), (mid, ROW - 2.0 * lift), (x1, ROW)]);
            let own = [
                Rect::of_text(mid, peak - 20.0, FONT, &name, true),
                Rect::of_text(mid, peak - 8.0, SMALL_FONT, role, true),
            ];
            let points = path.points();
            let clear = !own.iter().any(|r| {
                labels.iter().any(|l| l.overlaps(r)) || curves.iter().any(|c| r.crossed_by(c))
            }) && !labels.iter().any(|l| l.crossed_by(&points));
            if clear || lift > 40.0 * ARCH {
                labels.extend(own);
                curves.push(points);
                top = top.min(peak - 20.0 - FONT - 10.0);
                break Drawn {
                    branch: b,
                    port: p,
                    path,
                    arrow: ((mid, peak), (direction, 0.0)),
                    name_at: (mid, peak - 20.0),
                    role_at: (mid, peak - 8.0),
                    centred: true,
                };
            }
            lift += 12.0;
        };
        drawn.push(arch);
    }
    // In file order, as the edges are listed.
    drawn.sort_by_key(|d| (d.branch, d.port));
    let shift = (60.0 - top).max(0.0);
    let height = ground_y + 70.0 + shift;
    Layout {
        x,
        row,
        ground_y,
        width,
        height,
        shift,
        drawn,
    }
}

/// The SVG document of `graph` with its normal `tree`.
pub fn draw(model: &Model, graph: &LinearGraph, tree: &NormalTree, spec: &str) -> String {
    let Layout {
        x,
        row,
        ground_y,
        width,
        height,
        shift,
        drawn,
    } = layout(graph, tree);

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="{FONT}">"#
    );
    let title = if spec.is_empty() {
        format!(
            "linear graph '{}': normal tree bold, links dashed",
            model.name()
        )
    } else {
        format!(
            "linear graph '{}' in mode {spec}: normal tree bold, links dashed",
            model.name()
        )
    };
    let _ = writeln!(
        svg,
        r#"<title>{}</title><rect width="100%" height="100%" fill="white"/>"#,
        escape(&title)
    );
    let _ = writeln!(
        svg,
        r#"<text class="title" x="{:.0}" y="24" font-size="15" font-weight="bold" {}>{}</text>"#,
        MARGIN / 3.0,
        text_box(MARGIN / 3.0, 24.0, 15.0, &title, false, 0.0),
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
    let ground_label = format!("{} (ground)", graph.node(graph.ground).name);
    let ground_x = width - MARGIN / 2.0 - text_width(&ground_label, FONT);
    let _ = writeln!(
        svg,
        r#"<text class="ground" x="{ground_x:.0}" y="{:.0}" {}>{}</text>"#,
        ground_y + 32.0,
        text_box(ground_x, ground_y + 32.0, FONT, &ground_label, false, shift),
        escape(&ground_label)
    );
    for d in &drawn {
        let (b, p) = (d.branch, d.port);
        let in_tree = tree.in_tree[b][p];
        let (stroke, dash, colour) = if in_tree {
            (3.2, "", "#1f4e9c")
        } else {
            (1.4, r#" stroke-dasharray="7 5""#, "#555555")
        };
        let e = &graph.branches[b].edges[p];
        let points: Vec<String> = d
            .path
            .points()
            .iter()
            .map(|(px, py)| format!("{px:.1},{:.1}", py + shift))
            .collect();
        let _ = writeln!(
            svg,
            r#"<g class="branch" data-edge="{}" data-from="{}" data-to="{}" data-tree="{in_tree}" data-points="{}">"#,
            escape(&graph.edge_name(b, p)),
            escape(&graph.node(e.from).name),
            escape(&graph.node(e.to).name),
            points.join(" ")
        );
        let _ = writeln!(
            svg,
            r#"<path d="{}" fill="none" stroke="{colour}" stroke-width="{stroke}"{dash}/>"#,
            d.path.d()
        );
        let ((mx, my), (ux, uy)) = d.arrow;
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
        let (name, role) = (graph.edge_name(b, p), tree.roles[b][p].description());
        let anchor = if d.centred {
            r#" text-anchor="middle""#
        } else {
            ""
        };
        let _ = writeln!(
            svg,
            r#"<text class="branch-name" x="{:.1}" y="{:.1}" fill="{colour}"{anchor} {}>{}</text><text class="branch-role" x="{:.1}" y="{:.1}" fill="{colour}" font-size="{SMALL_FONT}"{anchor} {}>{}</text>"#,
            d.name_at.0,
            d.name_at.1,
            text_box(d.name_at.0, d.name_at.1, FONT, &name, d.centred, shift),
            escape(&name),
            d.role_at.0,
            d.role_at.1,
            text_box(d.role_at.0, d.role_at.1, SMALL_FONT, role, d.centred, shift),
            escape(role)
        );
        let _ = writeln!(svg, "</g>");
    }
    for &n in &row {
        let name = &graph.nodes[n].name;
        let (lx, ly) = (x[n] - NODE - 4.0, ROW + NODE + FONT + 2.0);
        let _ = writeln!(
            svg,
            r#"<circle class="node" cx="{:.1}" cy="{ROW:.1}" r="{NODE}" fill="white" stroke="black" stroke-width="2" data-box="{:.2} {:.2} {:.2} {:.2}"/><text class="node-name" x="{lx:.1}" y="{ly:.1}" font-weight="bold" text-anchor="end" {}>{}</text>"#,
            x[n],
            x[n] - NODE,
            ROW - NODE + shift,
            2.0 * NODE,
            2.0 * NODE,
            text_box(lx - text_width(name, FONT), ly, FONT, name, false, shift),
            escape(name)
        );
    }
    let _ = writeln!(svg, "</g>\n</svg>");
    svg
}

/// A text's box, estimated (see [`text_width`]).
#[derive(Clone, Copy, Debug)]
struct Rect {
    x: f64,
    y: f64,
    width: f64,
    height: f64,
}

impl Rect {
    /// The box of `text` at `(x, baseline)` in a font of `size` pixels, `x` its centre when
    /// `centred`, else its left end: from the ascent to the descent in height.
    fn of_text(x: f64, baseline: f64, size: f64, text: &str, centred: bool) -> Self {
        let width = text_width(text, size);
        Rect {
            x: if centred { x - width / 2.0 } else { x },
            y: baseline - 0.8 * size,
            width,
            height: size,
        }
    }

    fn overlaps(&self, o: &Rect) -> bool {
        self.x < o.x + o.width
            && o.x < self.x + self.width
            && self.y < o.y + o.height
            && o.y < self.y + self.height
    }

    /// Whether the line through `points` enters the box (checked every pixel or so).
    fn crossed_by(&self, points: &[(f64, f64)]) -> bool {
        points.windows(2).any(|pair| {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            let steps = (x1 - x0).hypot(y1 - y0).ceil().max(1.0) as usize;
            (0..=steps).any(|k| {
                let t = k as f64 / steps as f64;
                let (x, y) = (x0 + t * (x1 - x0), y0 + t * (y1 - y0));
                x > self.x && x < self.x + self.width && y > self.y && y < self.y + self.height
            })
        })
    }
}

/// The `data-box` of a text at `(x, baseline)` in a font of `size` pixels (`x` its centre
/// when `centred`, else its left end), in the drawing's coordinates (`shift` down from
/// where the text is written): from the ascent to the descent in height, and as wide as
/// [`text_width`] estimates.
fn text_box(x: f64, baseline: f64, size: f64, text: &str, centred: bool, shift: f64) -> String {
    let r = Rect::of_text(x, baseline, size, text, centred);
    format!(
        r#"data-box="{:.2} {:.2} {:.2} {:.2}""#,
        r.x,
        r.y + shift,
        r.width,
        r.height
    )
}

/// `text` with the characters XML reserves escaped.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
