//! `bondgraph explain` and `bondgraph graph --format svg|text|dot` on bond graphs: the steps
//! of the causality assignment in words, and the drawing read back from its SVG (every bond
//! drawn once with its number, every causal stroke at the end that receives the effort, no
//! two text boxes overlapping), on the textbook models and every mode of the flagship.

use std::collections::HashMap;

use bondgraph_core::causality;
use bondgraph_core::equations::Options;
use bondgraph_core::{laws, modes};

use crate::cli::succeed;
use crate::support::load;

// ---------------------------------------------------------------------------------------
// A tiny reader of the SVG the program writes: each tag's name and attributes, and the text
// that follows it.

/// One SVG tag: its name, its attributes and the text after it.
pub(crate) struct Tag {
    pub(crate) name: String,
    pub(crate) attributes: HashMap<String, String>,
    pub(crate) text: String,
}

/// The tags of an SVG document, in order.
pub(crate) fn tags(svg: &str) -> Vec<Tag> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("closed tag") + start;
        let inside = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if inside.starts_with('/') {
            continue;
        }
        let name_end = inside
            .find(|c: char| c.is_whitespace() || c == '/')
            .unwrap_or(inside.len());
        let mut attributes = HashMap::new();
        let mut attrs = &inside[name_end..];
        while let Some(eq) = attrs.find("=\"") {
            let key = attrs[..eq].trim().to_string();
            let value_end = attrs[eq + 2..].find('"').expect("closed value") + eq + 2;
            attributes.insert(key, attrs[eq + 2..value_end].to_string());
            attrs = &attrs[value_end + 1..];
        }
        let text = rest[..rest.find('<').unwrap_or(rest.len())].to_string();
        out.push(Tag {
            name: inside[..name_end].to_string(),
            attributes,
            text,
        });
    }
    out
}

fn number(tag: &Tag, key: &str) -> f64 {
    tag.attributes[key].parse().expect(key)
}

/// A text's box, as its `data-box` gives it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Box4 {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) w: f64,
    pub(crate) h: f64,
}

impl Box4 {
    pub(crate) fn of(tag: &Tag) -> Self {
        let v: Vec<f64> = tag.attributes["data-box"]
            .split(' ')
            .map(|s| s.parse().unwrap())
            .collect();
        Box4 {
            x: v[0],
            y: v[1],
            w: v[2],
            h: v[3],
        }
    }
    pub(crate) fn overlaps(&self, o: &Box4) -> bool {
        self.x < o.x + o.w && o.x < self.x + self.w && self.y < o.y + o.h && o.y < self.y + self.h
    }
    fn center(&self) -> (f64, f64) {
        (self.x + self.w / 2.0, self.y + self.h / 2.0)
    }
}

/// One bond as drawn.
#[derive(Debug)]
pub(crate) struct DrawnBond {
    from: String,
    to: String,
    stroke_attr: String,
    derivative: bool,
    line: [(f64, f64); 2],
    stroke: [(f64, f64); 2],
    number_text: String,
}

/// A drawing read back: its title, its bonds by number, its element labels and every box.
pub(crate) struct Drawing {
    pub(crate) title: String,
    pub(crate) bonds: HashMap<usize, Vec<DrawnBond>>,
    elements: HashMap<String, Box4>,
    boxes: Vec<(String, Box4)>,
}

/// Reads a drawing back from the SVG `bondgraph graph --format svg` writes.
pub(crate) fn read(svg: &str) -> Drawing {
    let tags = tags(svg);
    let mut drawing = Drawing {
        title: String::new(),
        bonds: HashMap::new(),
        elements: HashMap::new(),
        boxes: Vec::new(),
    };
    let mut i = 0;
    while i < tags.len() {
        let tag = &tags[i];
        let class = tag.attributes.get("class").map(String::as_str);
        if tag.name == "title" {
            drawing.title = tag.text.clone();
        }
        if let Some(b) = tag.attributes.get("data-box") {
            let label = tag
                .attributes
                .get("data-element")
                .cloned()
                .unwrap_or_else(|| format!("{} {}", class.unwrap_or(""), b));
            drawing.boxes.push((label, Box4::of(tag)));
        }
        if class == Some("element") {
            drawing
                .elements
                .insert(tag.attributes["data-element"].clone(), Box4::of(tag));
        }
        if tag.name == "g" && class == Some("bond") {
            let n: usize = tag.attributes["data-bond"].parse().unwrap();
            let part = |c: &str| {
                tags[i + 1..i + 5]
                    .iter()
                    .find(|t| t.attributes.get("class").map(String::as_str) == Some(c))
                    .unwrap_or_else(|| panic!("bond {n} has no {c}"))
            };
            let ends = |t: &Tag| {
                [
                    (number(t, "x1"), number(t, "y1")),
                    (number(t, "x2"), number(t, "y2")),
                ]
            };
            drawing.bonds.entry(n).or_default().push(DrawnBond {
                from: tag.attributes["data-from"].clone(),
                to: tag.attributes["data-to"].clone(),
                stroke_attr: tag.attributes["data-stroke"].clone(),
                derivative: tag.attributes["data-derivative"] == "true",
                line: ends(part("bond-line")),
                stroke: ends(part("causal-stroke")),
                number_text: part("bond-number").text.clone(),
            });
            // The half-arrow is there too.
            part("half-arrow");
        }
        i += 1;
    }
    drawing
}

fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    ((a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)).sqrt()
}

/// Checks a drawing against the expected strokes: for bond `n` (from 1), the name of the
/// element that receives its effort; and the expected derivative-causality bonds.
fn check_drawing(svg: &str, receivers: &[&str], derivative: &[usize], what: &str) {
    let drawing = read(svg);
    assert_eq!(drawing.bonds.len(), receivers.len(), "{what}: bonds drawn");
    for (i, receiver) in receivers.iter().enumerate() {
        let n = i + 1;
        let drawn = &drawing.bonds[&n];
        assert_eq!(
            drawn.len(),
            1,
            "{what}: bond {n} drawn {} times",
            drawn.len()
        );
        let b = &drawn[0];
        assert_eq!(b.number_text, n.to_string(), "{what}: bond {n}'s number");
        // The stroke's middle is on the line's end next to the receiving element.
        let middle = (
            (b.stroke[0].0 + b.stroke[1].0) / 2.0,
            (b.stroke[0].1 + b.stroke[1].1) / 2.0,
        );
        let at = if *receiver == b.from {
            b.line[0]
        } else {
            b.line[1]
        };
        assert!(*receiver == b.from || *receiver == b.to, "{what}: bond {n}");
        assert!(
            distance(middle, at) < 0.2,
            "{what}: bond {n}'s stroke at {middle:?}, not at {at:?} ({receiver})"
        );
        let expected_attr = if *receiver == b.from { "from" } else { "to" };
        assert_eq!(b.stroke_attr, expected_attr, "{what}: bond {n}");
        // That end is the one nearer the receiving element's label.
        let label = drawing.elements[*receiver].center();
        let other = if *receiver == b.from {
            b.line[1]
        } else {
            b.line[0]
        };
        assert!(
            distance(at, label) < distance(other, label),
            "{what}: bond {n}'s stroke end is not at '{receiver}'"
        );
        assert_eq!(
            b.derivative,
            derivative.contains(&n),
            "{what}: bond {n} derivative mark"
        );
    }
    for (i, (a, box_a)) in drawing.boxes.iter().enumerate() {
        for (b, box_b) in &drawing.boxes[i + 1..] {
            assert!(
                !box_a.overlaps(box_b),
                "{what}: '{a}' {box_a:?} overlaps '{b}' {box_b:?}"
            );
        }
    }
}

#[test]
fn mass_spring_damper_svg_strokes_by_hand() {
    // force -> v_mass|, v_mass -> mass| (the integral inertia receives the effort),
    // |v_mass -> spring (the spring gives its effort), |v_mass -> damper (resistance
    // causality).
    let svg = succeed(&[
        "graph",
        "models/examples/mass_spring_damper.ron",
        "--format",
        "svg",
    ]);
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.trim_end().ends_with("</svg>"));
    check_drawing(
        &svg,
        &["v_mass", "mass", "v_mass", "v_mass"],
        &[],
        "mass_spring_damper",
    );
    let drawing = read(&svg);
    assert_eq!(drawing.title, "bond graph 'mass_spring_damper'");
    for label in ["Se:force", "1:v_mass", "I:mass", "C:spring", "R:damper"] {
        assert!(svg.contains(&format!(">{label}</text>")), "{label}");
    }
}

#[test]
fn rigid_masses_svg_marks_the_derivative_bond() {
    let svg = succeed(&[
        "graph",
        "models/examples/rigid_masses.ron",
        "--format",
        "svg",
    ]);
    // Bond 3 (v -> mass2) is stroked at v: mass2 gives the effort, in derivative causality.
    check_drawing(&svg, &["v", "mass1", "v", "v", "v"], &[3], "rigid_masses");
    assert!(svg.contains("bond of storage in derivative causality"));
}

#[test]
fn every_flagship_mode_is_drawn_readably() {
    let model = load("models/eversion/robot.ron");
    let reachable = modes::reachable(&model, &Options::default()).expect("flagship modes");
    assert_eq!(reachable.modes.len(), 18);
    for derived in &reachable.modes {
        let spec = derived.mode.spec(&model);
        let laws = laws::for_mode(&model, &derived.mode);
        let causal = causality::assign(&model, &laws).expect("causal");
        let receivers: Vec<String> = model
            .bond_ids()
            .map(|b| {
                model
                    .element(causal.effort_receiver(&model, b))
                    .name
                    .clone()
            })
            .collect();
        let receivers: Vec<&str> = receivers.iter().map(String::as_str).collect();
        let derivative: Vec<usize> = causal
            .dependent
            .iter()
            .map(|&e| model.element(e).bonds[0].index() + 1)
            .collect();
        let svg = succeed(&[
            "graph",
            "models/eversion/robot.ron",
            "--mode",
            &spec,
            "--format",
            "svg",
        ]);
        check_drawing(&svg, &receivers, &derivative, &spec);
        assert_eq!(
            read(&svg).title,
            format!("bond graph 'eversion_robot' in mode {spec}")
        );
    }
    // By hand, all contacts stuck: the stuck nozzle contact receives the effort on bond 3
    // (tip -> fr_ge|) and holds both inertias: bonds 2 and 13 in derivative causality.
    let svg = succeed(&["graph", "models/eversion/robot.ron", "--format", "svg"]);
    let drawing = read(&svg);
    assert_eq!(drawing.bonds[&3][0].stroke_attr, "to");
    let marked: Vec<usize> = (1..=16)
        .filter(|n| drawing.bonds[n][0].derivative)
        .collect();
    assert_eq!(marked, [2, 13]);
    assert!(svg.contains(">Friction:fr_ge</text>"));
    assert!(svg.contains(">stuck</text>"));
}

#[test]
fn text_and_dot_number_the_bonds_and_mark_derivative_causality() {
    let text = succeed(&["graph", "models/examples/rigid_masses.ron"]);
    assert!(text.contains("  3  v -> mass2\n"), "{text}");
    assert!(
        text.contains(
            "  3  |v -> mass2   effort set by mass2, flow by v  (derivative causality)\n"
        ),
        "{text}"
    );
    let dot = succeed(&[
        "graph",
        "models/examples/rigid_masses.ron",
        "--format",
        "dot",
    ]);
    assert!(
        dot.contains(
            "\"v\" -> \"mass2\" [dir=both, arrowhead=lvee, arrowtail=tee, label=\"3\", color=red, fontcolor=red, penwidth=2];"
        ),
        "{dot}"
    );
    assert_eq!(dot.matches(", color=red").count(), 1);
    assert!(
        dot.contains("label=\"bond graph 'rigid_masses'\\n"),
        "{dot}"
    );
}

#[test]
fn explain_rigid_masses_step_by_step() {
    let text = succeed(&["explain", "models/examples/rigid_masses.ron"]);
    for line in [
        "  1. effort source 'force': a source of effort, its causality is fixed. It sets the effort on bond 1 (force -> v), so the stroke is at the end of 'v': force -> v|.\n",
        "  2. inertia 'mass1' takes its preferred integral causality: it receives the effort (force) on bond 2 (v -> mass1) and integrates it into its momentum p_mass1, a state; it gives its flow (velocity) back: v -> mass1|.\n",
        "       - 1-junction 'v' has its flow brought in by bond 2 (from 'mass1'), so it gives that flow to bond 3 |v -> mass2, bond 4 |v -> spring and bond 5 |v -> damper, each giving an effort back.\n",
        "  3. inertia 'mass2' would take integral causality, receiving the effort (force) on bond 3 (v -> mass2), but step 2 (inertia 'mass1', through 1-junction 'v') stroked that bond the other way, |v -> mass2: 'v' imposes its flow (velocity). It is in derivative causality: its momentum follows from the rest of the graph, and is no state of its own.\n",
        "       - The derivation merges it into 'mass1': the state p_mass1 now has the inertance m1 + m2.\n",
        "  5. resistor 'damper': step 2 (inertia 'mass1', through 1-junction 'v') decided its causality. It receives the flow on bond 5 (v -> damper) and gives the effort (resistance causality: the effort from the flow): |v -> damper.\n",
        "  3  |v -> mass2   derivative causality\n",
        "States: p_mass1 ('mass2' merged in), q_spring.\n",
        "Algebraic loops: none; every resistor's causality followed from the sources and the storage.\n",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
}

#[test]
fn explain_names_what_storage_integrates_in_its_domain() {
    // A capacitor integrates current into charge, an inductor voltage into flux linkage, a
    // rotating inertia torque into angular momentum (the gear ratio N has a unit, so the
    // load side's domain is known).
    let rc = succeed(&["explain", "models/teaching/rc.ron"]);
    assert!(
        rc.contains("compliance 'capacitor' takes its preferred integral causality: it receives the flow (current) on bond 3 (loop_current -> capacitor) and integrates it into its charge q_capacitor, a state; it gives its effort (voltage) back"),
        "{rc}"
    );
    let motor = succeed(&[
        "explain",
        "models/teaching/dc_motor.ron",
        "--format",
        "markdown",
    ]);
    for words in [
        "it receives the effort (voltage) on bond 3 (`armature -> winding_inductance`) and integrates it into its flux linkage `p_winding_inductance`, a state; it gives its flow (current) back",
        "it receives the effort (torque) on bond 7 (`load -> load_inertia`) and integrates it into its angular momentum `p_load_inertia`, a state; it gives its flow (angular velocity) back",
    ] {
        assert!(motor.contains(words), "missing {words:?} in\n{motor}");
    }
    // Without units there is no domain: the bond-graph words alone.
    let text = r#"Model(name: "rc", parameters: {"R": (value: 1.0), "C": (value: 1.0)},
        inputs: {"V": ()},
        elements: {"s": Se(effort: "V"), "j": One, "r": R(resistance: "R"), "c": C(compliance: "C")},
        bonds: [("s", "j"), ("j", "r"), ("j", "c")])"#;
    let source = bondgraph_core::source::SourceFile::new("rc.ron".to_string(), text.to_string());
    let model = bondgraph_ron::model::load_source(&source).expect("a model");
    let mode = modes::Mode::initial(&model);
    let plain = bondgraph_view::explain_bg::document(
        &model,
        &mode,
        &source,
        bondgraph_view::explain_bg::ExplainFormat::Text,
    )
    .unwrap_or_else(|_| panic!("explained"))
    .text;
    assert!(
        plain.contains("it receives the flow on bond 3 (j -> c) and integrates it into its displacement q_c, a state; it gives its effort back"),
        "{plain}"
    );
}

#[test]
fn explain_series_dampers_names_the_loop_and_its_solution() {
    let text = succeed(&["explain", "models/examples/series_dampers.ron"]);
    for line in [
        "  3. Nothing has forced the causality of resistor 'damper1', so it is chosen (resistance causality first). It receives the flow on bond 4 (damper_force -> damper1) and gives the effort (resistance causality: the effort from the flow): |damper_force -> damper1. A free choice like this is where an algebraic loop can start.\n",
        "       - 0-junction 'damper_force' has its effort brought in by bond 4 (from 'damper1'), so it gives that effort to bond 5 damper_force -> damper2|.\n",
        "Resistors: 'damper1' resistance causality (decided in step 3), 'damper2' conductance causality (decided in step 3).\n",
        // The pair acts as one damper b1*b2/(b1 + b2) at the mass's velocity p/m.
        "Algebraic loop through 'damper1' and 'damper2' (at 'damper_force'):",
        "'damper1': effort b1*b2/(m*(b1 + b2))*p_mass, flow b2/(m*(b1 + b2))*p_mass",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
}

#[test]
fn explain_in_markdown_and_on_every_flagship_mode() {
    let md = succeed(&[
        "explain",
        "models/eversion/robot.ron",
        "--format",
        "markdown",
    ]);
    assert!(md.starts_with("# bond graph `eversion_robot` in mode fr_ge=stuck,k=taut,fr_ct=stuck: causality assigned step by step (SCAP)\n"), "{md}");
    for line in [
        "## Sources\n",
        "2. stuck friction contact `fr_ge` (it holds its relative velocity at zero): a source of flow, its causality is fixed. It sets the flow on bond 3 (`tip -> fr_ge`), so the stroke is at the end of `fr_ge`: `tip -> fr_ge|`.\n",
        "   - transformer `eversion` passes the causality of bond 4 through to bond 5 `|eversion -> inner`: what comes in on one port goes out on the other.\n",
        "6. inertia `ge` would take integral causality",
        "   - It follows sources alone: it is held by them and has no state in this mode.\n",
    ] {
        assert!(md.contains(line), "missing {line:?} in\n{md}");
    }
    // Every mode explains, with one numbered step per storage element at least.
    let model = load("models/eversion/robot.ron");
    let reachable = modes::reachable(&model, &Options::default()).expect("flagship modes");
    for derived in &reachable.modes {
        let spec = derived.mode.spec(&model);
        let text = succeed(&["explain", "models/eversion/robot.ron", "--mode", &spec]);
        assert!(text.contains(&format!("in mode {spec}:")), "{spec}");
        // The states named in the result are the mode's.
        let expected: Vec<&str> = derived
            .equations
            .states
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        let line = text
            .lines()
            .find(|l| l.starts_with("States: "))
            .unwrap_or_else(|| panic!("{spec}: no states line"));
        let named: Vec<&str> = line
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .filter(|w| w.starts_with("p_") || w.starts_with("q_"))
            .collect();
        assert_eq!(named, expected, "{spec}: {line}");
        // Each of its storage elements has its numbered step.
        for state in &derived.equations.states {
            assert!(
                text.contains(&format!(" '{}' ", state.element)),
                "{spec}: {}",
                state.element
            );
        }
    }
    // A linear graph still gets its normal tree.
    let lg = succeed(&["explain", "models/examples/mass_spring_damper.lg.ron"]);
    assert!(lg.contains("the normal tree (Rowell & Wormley)"), "{lg}");
}
