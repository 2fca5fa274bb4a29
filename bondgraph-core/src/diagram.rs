//! The geometry of a bond-graph drawing: where each element's label goes, and each bond's
//! line, half-arrow, causal stroke and number, as data that can be tested and then written
//! out (the program writes it as SVG, without Graphviz).
//!
//! # Conventions
//! - Each element is drawn as its label, `type:name` (`I:mass`, `1:v`, `Friction:fr`),
//!   with a switching element's mode in small print below it.
//! - A bond is a line between two labels with a half-arrow at its head (`to`): power flows
//!   the way it points.
//! - The causal stroke is a bar across the bond at the end that **receives the effort**
//!   ([`Stroke`]): at an inertia in integral causality, at the junction next to an effort
//!   source or a compliance in integral causality.
//! - Bonds carry their numbers in file order, from 1, as `bondgraph explain` and
//!   `bondgraph graph` name them.
//! - The bond of a storage element in derivative causality is marked (`derivative`), and
//!   drawn highlighted, with a legend.
//!
//! # Layout
//! Deterministic and without iteration: a breadth-first tree from the first source (in file
//! order), each element in the column of its distance from the root; rows are given to the
//! tree's leaves in depth-first order and every other element sits midway between its first
//! and last child, so that two labels never share a place. Columns are as wide as their
//! widest label plus a gap that leaves room for bond numbers. A graph with loops draws its
//! remaining bonds straight across. Text widths are estimated from character counts, on the
//! generous side.
//!
//! # Example
//! ```
//! use bondgraph_core::{causality, diagram, laws, model, modes};
//! let model = bondgraph_ron::model::load_str("m.ron", r#"Model(name: "m",
//!     parameters: {"m": (value: 1.0)}, inputs: {"F": ()},
//!     elements: {"push": Se(effort: "F"), "j": One, "mass": I(inertance: "m")},
//!     bonds: [("push", "j"), ("j", "mass")])"#).unwrap();
//! let mode = modes::Mode::initial(&model);
//! let laws = laws::for_mode(&model, &mode);
//! let causal = causality::assign(&model, &laws).unwrap();
//! let drawing = diagram::layout(&model, &mode, &causal, "m");
//! assert_eq!(drawing.bonds.len(), 2);
//! // The effort source's stroke is at the junction's end: the line's head.
//! let bond = &drawing.bonds[0];
//! assert_eq!(bond.stroke_point(), bond.end);
//! ```

use crate::causality::{Causality, Stroke};
use crate::mode::Mode;
use crate::model::{BondId, ElementId, ElementKind, Model, NonlinearLaw};

/// Font size of labels, in pixels.
pub const FONT: f64 = 14.0;
/// Font size of small print (modes, bond numbers, legend).
pub const SMALL_FONT: f64 = 11.0;
/// Estimated width of one character at [`FONT`] (generous for a sans-serif font).
const CHAR: f64 = 0.62 * FONT;
const SMALL_CHAR: f64 = 0.62 * SMALL_FONT;
const MARGIN: f64 = 30.0;
const TOP: f64 = 80.0;
const ROW: f64 = 66.0;
const GAP: f64 = 96.0;
const PAD: f64 = 4.0;
/// Length of the half-arrow's barb and half the causal stroke's length.
const BARB: f64 = 12.0;
const STROKE_HALF: f64 = 8.0;

/// A point in the drawing (y grows downwards, as in SVG).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Horizontal position.
    pub x: f64,
    /// Vertical position, downwards.
    pub y: f64,
}

/// An axis-aligned box: top-left corner and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left edge.
    pub x: f64,
    /// Top edge.
    pub y: f64,
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
}

impl Rect {
    /// The box of the given size centred on `center`.
    pub fn centered(center: Point, width: f64, height: f64) -> Self {
        Rect {
            x: center.x - width / 2.0,
            y: center.y - height / 2.0,
            width,
            height,
        }
    }

    /// Its centre.
    pub fn center(&self) -> Point {
        Point {
            x: self.x + self.width / 2.0,
            y: self.y + self.height / 2.0,
        }
    }

    /// Whether the two boxes share any area (touching edges do not count).
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x < other.x + other.width
            && other.x < self.x + self.width
            && self.y < other.y + other.height
            && other.y < self.y + self.height
    }
}

/// One element's label.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The element.
    pub element: ElementId,
    /// `type:name`.
    pub label: String,
    /// The switching element's mode, in small print below the label.
    pub mode: Option<String>,
    /// Where the label is centred.
    pub center: Point,
    /// The box the label (and its mode) takes.
    pub bounds: Rect,
}

/// One bond's drawing.
#[derive(Clone, Debug, PartialEq)]
pub struct BondShape {
    /// The bond.
    pub bond: BondId,
    /// Its number, from 1, in file order.
    pub number: usize,
    /// The line's start, at the edge of the tail element's label (`from`).
    pub start: Point,
    /// The line's end, at the edge of the head element's label (`to`).
    pub end: Point,
    /// The half-arrow's barb, from [`Self::end`] back and to one side.
    pub half_arrow: [Point; 2],
    /// Where the stroke is: the end that receives the effort.
    pub stroke_at: Stroke,
    /// The causal stroke, a bar across the line at that end.
    pub stroke: [Point; 2],
    /// Whether this is the bond of storage in derivative causality.
    pub derivative: bool,
    /// Where the bond number is centred.
    pub number_center: Point,
    /// The box the number takes.
    pub number_bounds: Rect,
}

impl BondShape {
    /// The end of the line at which the causal stroke is drawn.
    pub fn stroke_point(&self) -> Point {
        match self.stroke_at {
            Stroke::AtFrom => self.start,
            Stroke::AtTo => self.end,
        }
    }
}

/// One line of the legend, with a sample bond drawn before it.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// What it says.
    pub text: String,
    /// Whether its sample is drawn as a derivative-causality bond.
    pub derivative: bool,
    /// The sample line.
    pub sample: [Point; 2],
    /// The box the sample and the text take.
    pub bounds: Rect,
}

/// A complete drawing.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagram {
    /// The title (the model, and the mode).
    pub title: String,
    /// The title's box; its text's baseline is at its bottom less a quarter of its height.
    pub title_bounds: Rect,
    /// Every element, in element order.
    pub nodes: Vec<Node>,
    /// Every bond, in bond order.
    pub bonds: Vec<BondShape>,
    /// The legend, below the graph.
    pub legend: Vec<LegendEntry>,
    /// The drawing's width.
    pub width: f64,
    /// The drawing's height.
    pub height: f64,
}

impl Diagram {
    /// Every text box of the drawing: title, labels, bond numbers and legend lines.
    pub fn text_boxes(&self) -> Vec<Rect> {
        let mut boxes = vec![self.title_bounds];
        boxes.extend(self.nodes.iter().map(|n| n.bounds));
        boxes.extend(self.bonds.iter().map(|b| b.number_bounds));
        boxes.extend(self.legend.iter().map(|l| l.bounds));
        boxes
    }
}

/// The label of an element: `type:name`.
pub fn label(model: &Model, element: ElementId) -> String {
    let e = model.element(element);
    let kind = match &e.kind {
        ElementKind::ZeroJunction => "0",
        ElementKind::OneJunction => "1",
        other => other.keyword(),
    };
    format!("{kind}:{}", e.name)
}

/// A breadth-first spanning forest of the bond graph, sources first as roots: each
/// element's depth, its children, and the roots in order.
fn spanning_forest(model: &Model) -> (Vec<usize>, Vec<Vec<usize>>, Vec<usize>) {
    let count = model.elements.len();
    let mut depth = vec![usize::MAX; count];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); count];
    let mut roots = Vec::new();
    let candidates: Vec<usize> = (0..count)
        .filter(|&i| is_source(&model.elements[i].kind))
        .chain(0..count)
        .collect();
    for root in candidates {
        if depth[root] != usize::MAX {
            continue;
        }
        roots.push(root);
        depth[root] = 0;
        let mut queue = std::collections::VecDeque::from([root]);
        while let Some(current) = queue.pop_front() {
            for &bond in &model.elements[current].bonds {
                let other = model.bond(bond).other(ElementId(current as u32)).index();
                if depth[other] == usize::MAX {
                    depth[other] = depth[current] + 1;
                    children[current].push(other);
                    queue.push_back(other);
                }
            }
        }
    }
    (depth, children, roots)
}

/// Each element's row: leaves in depth-first order, parents midway between their first and
/// last child.
fn rows(roots: &[usize], children: &[Vec<usize>]) -> Vec<f64> {
    let mut row = vec![0.0; children.len()];
    let mut next_row = 0.0;
    for &root in roots {
        let mut stack = vec![(root, false)];
        while let Some((node, expanded)) = stack.pop() {
            if children[node].is_empty() {
                row[node] = next_row;
                next_row += 1.0;
            } else if expanded {
                let first = row[children[node][0]];
                let last = row[*children[node].last().expect("not empty")];
                row[node] = (first + last) / 2.0;
            } else {
                stack.push((node, true));
                for &child in children[node].iter().rev() {
                    stack.push((child, false));
                }
            }
        }
    }
    row
}

/// Lays out `model` with the strokes of `causality` (derived in `mode`) under `title`.
///
/// # Complexity
/// Linear in the number of elements and bonds.
pub fn layout(model: &Model, mode: &Mode, causality: &Causality, title: &str) -> Diagram {
    let count = model.elements.len();
    let labels: Vec<String> = model.element_ids().map(|e| label(model, e)).collect();
    let modes: Vec<Option<String>> = model
        .element_ids()
        .map(|e| {
            mode.of(e)
                .or_else(|| model.element(e).kind.initial_mode())
                .map(|m| m.name().to_string())
        })
        .collect();
    let sizes: Vec<(f64, f64)> = (0..count)
        .map(|i| {
            let text = labels[i].chars().count() as f64 * CHAR;
            let small = modes[i]
                .as_ref()
                .map_or(0.0, |m| m.chars().count() as f64 * SMALL_CHAR);
            let height = FONT
                + 2.0 * PAD
                + if modes[i].is_some() {
                    SMALL_FONT + 2.0
                } else {
                    0.0
                };
            (text.max(small) + 2.0 * PAD, height)
        })
        .collect();

    let (depth, children, roots) = spanning_forest(model);
    let row = rows(&roots, &children);

    // Columns as wide as their widest label.
    let columns = depth.iter().copied().max().map_or(0, |d| d + 1);
    let mut column_width = vec![0.0_f64; columns];
    for i in 0..count {
        column_width[depth[i]] = column_width[depth[i]].max(sizes[i].0);
    }
    let mut column_x = Vec::with_capacity(columns);
    let mut x = MARGIN;
    for width in &column_width {
        column_x.push(x + width / 2.0);
        x += width + GAP;
    }
    let nodes: Vec<Node> = (0..count)
        .map(|i| {
            let center = Point {
                x: column_x[depth[i]],
                y: TOP + row[i] * ROW,
            };
            Node {
                element: ElementId(i as u32),
                label: labels[i].clone(),
                mode: modes[i].clone(),
                center,
                bounds: Rect::centered(center, sizes[i].0, sizes[i].1),
            }
        })
        .collect();

    let bonds: Vec<BondShape> = model
        .bond_ids()
        .map(|bond| {
            let b = model.bond(bond);
            let (tail, head) = (&nodes[b.from.index()], &nodes[b.to.index()]);
            let start = clip(tail.center, head.center, &tail.bounds);
            let end = clip(head.center, tail.center, &head.bounds);
            bond_shape(model, causality, bond, start, end)
        })
        .collect();

    let graph_bottom = nodes
        .iter()
        .map(|n| n.bounds.y + n.bounds.height)
        .fold(TOP, f64::max);
    let title_bounds = Rect {
        x: MARGIN,
        y: 14.0,
        width: title.chars().count() as f64 * 0.62 * 16.0,
        height: 22.0,
    };
    let legend_texts = [
        (
            "power flows the way the half-arrow points; the stroke | is at the end that receives the effort; numbers are bond numbers",
            false,
        ),
        (
            "bond of storage in derivative causality (no state of its own)",
            true,
        ),
    ];
    let legend: Vec<LegendEntry> = legend_texts
        .iter()
        .enumerate()
        .map(|(i, (text, derivative))| {
            let y = graph_bottom + 36.0 + i as f64 * 22.0;
            let sample = [
                Point { x: MARGIN, y },
                Point {
                    x: MARGIN + 40.0,
                    y,
                },
            ];
            LegendEntry {
                text: (*text).to_string(),
                derivative: *derivative,
                sample,
                bounds: Rect {
                    x: MARGIN,
                    y: y - 9.0,
                    width: 52.0 + text.chars().count() as f64 * SMALL_CHAR,
                    height: 18.0,
                },
            }
        })
        .collect();
    let right = nodes
        .iter()
        .map(|n| n.bounds.x + n.bounds.width)
        .chain(legend.iter().map(|l| l.bounds.x + l.bounds.width))
        .chain([title_bounds.x + title_bounds.width])
        .fold(0.0, f64::max);
    let bottom = legend
        .iter()
        .map(|l| l.bounds.y + l.bounds.height)
        .fold(graph_bottom, f64::max);
    Diagram {
        title: title.to_string(),
        title_bounds,
        nodes,
        bonds,
        legend,
        width: (right + MARGIN).ceil(),
        height: (bottom + MARGIN / 2.0).ceil(),
    }
}

/// Whether the element is a source by kind (the layout does not change with the mode).
fn is_source(kind: &ElementKind) -> bool {
    match kind {
        ElementKind::EffortSource(_) | ElementKind::FlowSource(_) => true,
        ElementKind::Nonlinear(n) => matches!(
            n.law,
            NonlinearLaw::EffortSource(_) | NonlinearLaw::FlowSource(_)
        ),
        _ => false,
    }
}

/// The point where the segment from `center` towards `toward` leaves `bounds`.
fn clip(center: Point, toward: Point, bounds: &Rect) -> Point {
    let (dx, dy) = (toward.x - center.x, toward.y - center.y);
    let half_w = bounds.width / 2.0 + 2.0;
    let half_h = bounds.height / 2.0 + 2.0;
    let tx = if dx.abs() > 1e-9 {
        half_w / dx.abs()
    } else {
        f64::INFINITY
    };
    let ty = if dy.abs() > 1e-9 {
        half_h / dy.abs()
    } else {
        f64::INFINITY
    };
    let t = tx.min(ty).min(1.0);
    Point {
        x: center.x + dx * t,
        y: center.y + dy * t,
    }
}

fn bond_shape(
    model: &Model,
    causality: &Causality,
    bond: BondId,
    start: Point,
    end: Point,
) -> BondShape {
    let (dx, dy) = (end.x - start.x, end.y - start.y);
    let length = (dx * dx + dy * dy).sqrt().max(1e-9);
    let (ux, uy) = (dx / length, dy / length);
    // The normal on the upper side (or the left, for a vertical bond).
    let (mut nx, mut ny) = (-uy, ux);
    if ny > 1e-9 || (ny.abs() <= 1e-9 && nx > 0.0) {
        (nx, ny) = (-nx, -ny);
    }
    let half_arrow = [
        end,
        Point {
            x: end.x - BARB * ux + 0.6 * BARB * nx,
            y: end.y - BARB * uy + 0.6 * BARB * ny,
        },
    ];
    let stroke_at = causality.strokes[bond.index()];
    let at = match stroke_at {
        Stroke::AtFrom => start,
        Stroke::AtTo => end,
    };
    let stroke = [
        Point {
            x: at.x + STROKE_HALF * nx,
            y: at.y + STROKE_HALF * ny,
        },
        Point {
            x: at.x - STROKE_HALF * nx,
            y: at.y - STROKE_HALF * ny,
        },
    ];
    let number = bond.index() + 1;
    let digits = number.to_string().len() as f64;
    let (width, height) = (digits * SMALL_CHAR + 4.0, SMALL_FONT + 3.0);
    // Beside the middle of the line, on its upper side, clear of it.
    let clearance = 3.0 + (width / 2.0 * nx.abs()).max(height / 2.0 * ny.abs());
    let number_center = Point {
        x: (start.x + end.x) / 2.0 + clearance * nx,
        y: (start.y + end.y) / 2.0 + clearance * ny,
    };
    BondShape {
        bond,
        number,
        start,
        end,
        half_arrow,
        stroke_at,
        stroke,
        derivative: crate::graph::is_derivative_bond(model, causality, bond),
        number_center,
        number_bounds: Rect::centered(number_center, width, height),
    }
}
