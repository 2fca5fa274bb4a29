//! Sub-models: a model built from parts derives what the same model written flat derives,
//! and every mistake of composition is a located error in the file that caused it.

use std::path::{Path, PathBuf};

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind};
use bondgraph_core::equations::{self, StateEquations};
use bondgraph_core::laws;
use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;

fn models() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../models")
}

fn load_path(path: &Path) -> Result<Model, bondgraph_core::Diagnostics> {
    let text = std::fs::read_to_string(path).unwrap();
    bondgraph_ron::model::load_source(&SourceFile::new(path.display().to_string(), text))
}

fn load(relative: &str) -> Model {
    load_path(&models().join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

fn derive(model: &Model) -> StateEquations {
    equations::derive(
        model,
        &laws::plain_laws(model),
        &equations::Options::default(),
    )
    .unwrap()
}

/// The matrices as text, each entry printed with the model's symbols.
fn printed(eq: &StateEquations) -> (Vec<String>, Vec<Vec<String>>, Vec<Vec<String>>) {
    let text = |m: Vec<Vec<bondgraph_core::symbolic::RatFunc>>| -> Vec<Vec<String>> {
        m.iter()
            .map(|row| row.iter().map(|e| e.text(&eq.symbols)).collect())
            .collect()
    };
    let states = eq.states.iter().map(|s| s.name.clone()).collect();
    (states, text(eq.a()), text(eq.b()))
}

/// The matrices evaluated at the model's values, rows and columns in the order of `states`.
fn numeric(eq: &StateEquations, states: &[&str]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let order: Vec<usize> = states
        .iter()
        .map(|s| eq.state_named(s).unwrap_or_else(|| panic!("no state {s}")))
        .collect();
    let (a, b) = (eq.a(), eq.b());
    let a = order
        .iter()
        .map(|&i| order.iter().map(|&j| eq.evaluate(&a[i][j])).collect())
        .collect();
    let b = order
        .iter()
        .map(|&i| b[i].iter().map(|e| eq.evaluate(e)).collect())
        .collect();
    (a, b)
}

fn assert_close(x: &[Vec<f64>], y: &[Vec<f64>]) {
    assert_eq!(x.len(), y.len());
    for (r, (xr, yr)) in x.iter().zip(y).enumerate() {
        for (c, (a, b)) in xr.iter().zip(yr).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * a.abs().max(b.abs()),
                "entry ({r}, {c}): {a} against {b}"
            );
        }
    }
}

#[test]
fn the_quarter_car_from_the_suspension_part_is_the_flat_quarter_car() {
    let composed = derive(&load("examples/composed/quarter_car.ron"));
    let flat = derive(&load("teaching/quarter_car.ron"));
    // Symbolically the same, entry for entry, once the use's prefix is taken off.
    let (states, a, b) = printed(&composed);
    let strip = |t: &String| t.replace("suspension.", "");
    let strip_all = |m: Vec<Vec<String>>| -> Vec<Vec<String>> {
        m.iter().map(|r| r.iter().map(strip).collect()).collect()
    };
    assert_eq!(states[2], "suspension.q_spring");
    let flat_printed = printed(&flat);
    assert_eq!(states.iter().map(strip).collect::<Vec<_>>(), flat_printed.0);
    assert_eq!(strip_all(a), flat_printed.1);
    assert_eq!(strip_all(b), flat_printed.2);
}

#[test]
fn nested_parts_with_values_per_use_derive_the_half_car_by_hand() {
    let model = load("examples/composed/half_car.ron");
    let value = |name: &str| {
        model
            .parameters()
            .iter()
            .find(|p| p.name == name)
            .unwrap_or_else(|| panic!("no parameter {name}"))
            .value
    };
    // The part's default where the use gives none, the use's value where it does.
    assert_eq!(value("front.m_w"), 35.0);
    assert_eq!(value("rear.m_w"), 40.0);
    assert_eq!(value("front.suspension.k_s"), 20000.0);
    assert_eq!(value("rear.suspension.k_s"), 22000.0);
    let parts: Vec<&str> = model.parts().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        parts,
        ["front", "front.suspension", "rear", "rear.suspension"]
    );
    let eq = derive(&model);
    let (states, a, _) = printed(&eq);
    let at = |row: &str, column: &str| {
        let i = states.iter().position(|s| s == row).unwrap();
        let j = states.iter().position(|s| s == column).unwrap();
        a[i][j].clone()
    };
    // By hand: the front strut's stroke rate is the wheel's velocity less the body's at the
    // front axle, v + l_f w; the pitch torque is l_f F_f - l_r F_r with F = k_s q + b_s q'.
    let stroke = "front.suspension.q_spring";
    assert_eq!(at(stroke, "front.p_wheel"), "1/front.m_w");
    assert_eq!(at(stroke, "p_body"), "-1/m_b");
    assert_eq!(at(stroke, "p_body_pitch"), "-l_f/J_b");
    assert_eq!(at("rear.suspension.q_spring", "p_body_pitch"), "l_r/J_b");
    assert_eq!(at("p_body_pitch", stroke), "front.suspension.k_s*l_f");
    assert_eq!(
        at("p_body_pitch", "rear.suspension.q_spring"),
        "-l_r*rear.suspension.k_s"
    );
}

/// The same drive written flat, every element by hand.
const FLAT_DRIVE: &str = r#"Model(
    name: "flat_drive",
    parameters: {
        "R_a": (value: 1.2, unit: "ohm"), "L_a": (value: 0.005, unit: "H"),
        "K": (value: 0.05, unit: "N*m/A"), "J_m": (value: 0.00002, unit: "kg*m^2"),
        "b_m": (value: 0.0001, unit: "N*m*s/rad"), "N": (value: 12.0, unit: "1"),
        "b_g": (value: 0.0, unit: "N*m*s/rad"), "J": (value: 0.002, unit: "kg*m^2"),
        "b": (value: 0.001, unit: "N*m*s/rad"),
    },
    inputs: {"V": (unit: "V")},
    elements: {
        "supply": Se(effort: "V"), "armature": One, "r_a": R(resistance: "R_a"),
        "l_a": I(inertance: "L_a"), "magnet": GY(ratio: "K"), "rotor": One,
        "j_m": I(inertance: "J_m"), "b_rotor": R(resistance: "b_m"), "mesh": TF(ratio: "1/N"),
        "out": One, "loss": R(resistance: "b_g"), "load": I(inertance: "J"),
        "friction": R(resistance: "b"),
    },
    bonds: [("supply", "armature"), ("armature", "r_a"), ("armature", "l_a"),
        ("armature", "magnet"), ("magnet", "rotor"), ("rotor", "j_m"), ("rotor", "b_rotor"),
        ("rotor", "mesh"), ("mesh", "out"), ("out", "loss"), ("out", "load"),
        ("out", "friction")],
)"#;

#[test]
fn the_geared_drive_from_two_parts_is_the_drive_written_flat() {
    let composed = derive(&load("examples/composed/geared_drive.ron"));
    let flat_model = bondgraph_ron::model::load_str("flat.ron", FLAT_DRIVE).unwrap();
    let flat = derive(&flat_model);
    let (a, b) = numeric(
        &composed,
        &["motor.p_winding_inductance", "motor.p_rotor_inertia"],
    );
    let (a_flat, b_flat) = numeric(&flat, &["p_l_a", "p_j_m"]);
    assert_close(&a, &a_flat);
    assert_close(&b, &b_flat);
    // And by hand: the rotor's momentum carries J + N^2 J_m, seen from the rotor as
    // (J + N^2 J_m)/N^2, so dp/dt's own coefficient is -(b + N^2 b_m)/(N^2 J_m + J).
    let expected = -(0.001 + 144.0 * 0.0001) / (144.0 * 0.00002 + 0.002);
    assert!((a[1][1] - expected).abs() < 1e-12 * expected.abs());
}

#[test]
fn a_pipe_of_four_segment_uses_is_the_pipe_written_segment_by_segment() {
    let composed = derive(&load("examples/composed/pipeline.ron"));
    let mut elements = String::from(
        r#""inflow": Sf(flow: "Q_in"), "tank_pressure": Zero, "tank": C(compliance: "C_t"), "atmosphere": Se(effort: "0"),"#,
    );
    let mut bonds = String::from(r#"("inflow", "tank_pressure"), ("tank_pressure", "tank"),"#);
    let mut upstream = "tank_pressure".to_string();
    let mut states = Vec::new();
    for i in 1..=4 {
        elements.push_str(&format!(
            r#""in{i}": Zero, "c{i}": C(compliance: "C_s"), "f{i}": One, "l{i}": I(inertance: "L_s"), "r{i}": R(resistance: "R_s"),"#
        ));
        bonds.push_str(&format!(
            r#"("{upstream}", "in{i}"), ("in{i}", "c{i}"), ("in{i}", "f{i}"), ("f{i}", "l{i}"), ("f{i}", "r{i}"),"#
        ));
        upstream = format!("f{i}");
        // The first segment's compliance shares the tank's pressure: merged into the
        // tank's state in both.
        if i > 1 {
            states.push((format!("s{i}.q_compliance"), format!("q_c{i}")));
        }
        states.push((format!("s{i}.p_inertance"), format!("p_l{i}")));
    }
    bonds.push_str(r#"("f4", "atmosphere")"#);
    let flat_text = format!(
        r#"Model(name: "flat_pipe",
    parameters: {{"C_t": (value: 5.0e-5, unit: "m^3/Pa"), "C_s": (value: 2.0e-10, unit: "m^3/Pa"),
        "L_s": (value: 2.5e6, unit: "Pa*s^2/m^3"), "R_s": (value: 5.0e5, unit: "Pa*s/m^3")}},
    inputs: {{"Q_in": (unit: "m^3/s")}},
    elements: {{{elements}}},
    bonds: [{bonds}])"#
    );
    let flat = derive(&bondgraph_ron::model::load_str("flat.ron", &flat_text).unwrap());
    let mut composed_order = vec!["q_tank"];
    let mut flat_order = vec!["q_tank"];
    for (c, f) in &states {
        composed_order.push(c);
        flat_order.push(f);
    }
    let (a, b) = numeric(&composed, &composed_order);
    let (a_flat, b_flat) = numeric(&flat, &flat_order);
    assert_close(&a, &a_flat);
    assert_close(&b, &b_flat);
}

/// A folder of model files for one test, removed when dropped.
struct Folder(PathBuf);

impl Folder {
    fn new(test: &str, files: &[(&str, &str)]) -> Self {
        let path =
            std::env::temp_dir().join(format!("bondgraph-compose-{}-{test}", std::process::id()));
        std::fs::create_dir_all(&path).unwrap();
        for (name, text) in files {
            std::fs::write(path.join(name), text).unwrap();
        }
        Self(path)
    }

    /// The diagnostics of loading `name`, which must fail.
    fn errors(&self, name: &str) -> Vec<Diagnostic> {
        match load_path(&self.0.join(name)) {
            Ok(_) => panic!("{name} loaded"),
            Err(diagnostics) => diagnostics.0,
        }
    }

    fn load(&self, name: &str) -> Model {
        load_path(&self.0.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const MASS: &str = r#"Model(
    name: "mass",
    parameters: {"m": (value: 2.0, unit: "kg")},
    ports: {"hub": (element: "v")},
    elements: {"v": One, "mass": I(inertance: "m")},
    bonds: [("v", "mass")],
)"#;

/// A model pushing a use of `mass.ron` with the use's fields `fields` and bonds `bonds`.
fn user(fields: &str, bonds: &str) -> String {
    format!(
        r#"Model(
    name: "user",
    inputs: {{"F": (unit: "N")}},
    elements: {{
        "push": Se(effort: "F"),
        "cart": Submodel(file: "mass.ron"{fields}),
    }},
    bonds: [{bonds}],
)"#
    )
}

/// File, line and column of a diagnostic, the file's name only.
fn place(d: &Diagnostic) -> (String, usize, usize) {
    let l = d.location.as_ref().expect("located");
    let file = Path::new(&l.file)
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    (file, l.line, l.column)
}

#[test]
fn values_and_expressions_given_per_use() {
    let user_text = r#"Model(
    name: "user",
    parameters: {"m_total": (value: 9.0, unit: "kg")},
    inputs: {"F": (unit: "N")},
    elements: {
        "push": Se(effort: "F"),
        "junction": One,
        "a": Submodel(file: "mass.ron", parameters: {"m": 3000}),
        "b": Submodel(file: "mass.ron", parameters: {"m": "m_total/3"}),
    },
    bonds: [("push", "junction"), ("junction", "a.hub"), ("junction", "b.hub")],
)"#;
    let folder = Folder::new("values", &[("mass.ron", MASS), ("user.ron", user_text)]);
    let model = folder.load("user.ron");
    let names: Vec<&str> = model.parameters().iter().map(|p| p.name.as_str()).collect();
    // A value keeps the parameter (3000 in the part's own unit, kg); an expression replaces it.
    assert_eq!(names, ["m_total", "a.m"]);
    assert_eq!(model.parameters()[1].value, 3000.0);
    let (states, a, b) = printed(&derive(&model));
    // The two masses move together: one state, the second merged into the first, and the
    // force accelerates both, m_a + m_total/3 = 3003 kg.
    assert_eq!(states, ["a.p_mass"]);
    assert_eq!(a, [["0"]]);
    assert_eq!(b, [["1"]]);
    let eq = derive(&model);
    assert!(
        (eq.evaluate(&eq.states[0].storage) - 3003.0).abs() < 1e-9,
        "{}",
        eq.evaluate(&eq.states[0].storage)
    );
}

#[test]
fn mistakes_of_composition_are_located_in_the_composing_file() {
    let folder = Folder::new(
        "mistakes",
        &[
            ("mass.ron", MASS),
            ("typo.ron", &user("", r#"("push", "cart.hb")"#)),
            ("bare.ron", &user("", r#"("push", "cart")"#)),
            ("open.ron", &user("", r#"("push", "push2")"#)),
            (
                "unknown.ron",
                &user(r#", parameters: {"mass": 1.0}"#, r#"("push", "cart.hub")"#),
            ),
            (
                "missing.ron",
                &user("", r#"("push", "cart.hub")"#).replace("mass.ron", "nowhere.ron"),
            ),
        ],
    );
    let d = folder.errors("typo.ron");
    assert_eq!(d[0].kind, DiagnosticKind::Submodel);
    assert_eq!(
        d[0].message,
        format!(
            "bond 1: 'hb' is not a port of sub-model 'cart' ('{}')",
            folder.0.join("mass.ron").display()
        )
    );
    assert_eq!(d[0].notes, ["did you mean 'cart.hub'?"]);
    assert_eq!(place(&d[0]), ("typo.ron".into(), 8, 23));

    let d = folder.errors("bare.ron");
    assert_eq!(
        d[0].message,
        "bond 1: a bond joins a port of sub-model 'cart', not the sub-model itself"
    );
    assert_eq!(d[0].notes, ["its ports: 'cart.hub'"]);

    let d = folder.errors("open.ron");
    assert!(
        d.iter().any(
            |d| d.message == "sub-model 'cart': port 'hub' is not connected"
                && place(d) == ("open.ron".into(), 6, 9)
        ),
        "{d:?}"
    );

    let d = folder.errors("unknown.ron");
    assert_eq!(
        d[0].message,
        format!(
            "sub-model 'cart': 'mass' is not a parameter of '{}'",
            folder.0.join("mass.ron").display()
        )
    );
    assert_eq!(d[0].notes, ["its parameters: 'm'"]);
    // Underlined: the name given, inside the use's parameters.
    assert_eq!(place(&d[0]), ("unknown.ron".into(), 6, 57));

    let d = folder.errors("missing.ron");
    assert_eq!(d[0].kind, DiagnosticKind::Io);
    assert!(
        d[0].message
            .starts_with("sub-model 'cart': cannot read sub-model file '")
    );
    assert_eq!(place(&d[0]), ("missing.ron".into(), 6, 33));
}

#[test]
fn a_mistake_inside_a_part_is_located_in_the_part() {
    let broken = MASS.replace(r#"I(inertance: "m")"#, r#"I(inertance: "mm")"#);
    let folder = Folder::new(
        "inside",
        &[
            ("mass.ron", &broken),
            ("user.ron", &user("", r#"("push", "cart.hub")"#)),
        ],
    );
    let d = folder.errors("user.ron");
    assert_eq!(d[0].kind, DiagnosticKind::UnknownSymbol);
    assert_eq!(place(&d[0]), ("mass.ron".into(), 5, 48));
    assert_eq!(d[0].element.as_deref(), Some("mass"));
}

#[test]
fn a_problem_across_parts_points_at_the_use_and_names_the_part_line() {
    let user_text = r#"Model(
    name: "user",
    inputs: {"v1": (unit: "m/s"), "v2": (unit: "m/s")},
    elements: {
        "drive": Sf(flow: "v1"),
        "cart": Submodel(file: "mass.ron"),
        "other": Sf(flow: "v2"),
    },
    bonds: [("drive", "cart.hub"), ("other", "cart.hub")],
)"#;
    let folder = Folder::new("across", &[("mass.ron", MASS), ("user.ron", user_text)]);
    let model = folder.load("user.ron");
    let error =
        equations::derive(&model, &laws::plain_laws(&model), &Default::default()).unwrap_err();
    let d = error.first();
    assert_eq!(d.kind, DiagnosticKind::CausalConflict);
    assert_eq!(place(d), ("user.ron".into(), 6, 9));
    let origin = d
        .notes
        .iter()
        .find(|n| n.starts_with("'cart.v' is element 'v' of "));
    assert!(
        origin.is_some_and(|n| n.ends_with("mass.ron:5:16")),
        "{:?}",
        d.notes
    );
}

#[test]
fn a_cycle_of_files_is_an_error_in_the_file_that_closes_it() {
    let part = |name: &str, other: &str| {
        format!(
            r#"Model(name: "{name}", ports: {{"p": (element: "j")}},
    elements: {{"j": One, "m": I(inertance: "1"), "inner": Submodel(file: "{other}")}},
    bonds: [("j", "m"), ("j", "inner.p")])"#
        )
    };
    let folder = Folder::new(
        "cycle",
        &[
            ("a.ron", &part("a", "b.ron")),
            ("b.ron", &part("b", "a.ron")),
            (
                "user.ron",
                &user("", r#"("push", "cart.p")"#).replace("mass.ron", "a.ron"),
            ),
        ],
    );
    let d = folder.errors("user.ron");
    assert_eq!(d[0].kind, DiagnosticKind::Submodel);
    assert_eq!(
        d[0].message,
        "sub-model 'inner': 'a.ron' uses itself (a.ron -> b.ron -> a.ron); a model cannot contain itself"
    );
    assert_eq!(place(&d[0]), ("b.ron".into(), 2, 75));
}

#[test]
fn names_with_dots_and_parts_without_ports_are_refused() {
    let no_ports = MASS.replace(r#"ports: {"hub": (element: "v")},"#, "");
    let dotted = user("", r#"("push", "cart.hub")"#).replace(r#""push""#, r#""p.ush""#);
    let folder = Folder::new(
        "refused",
        &[
            ("mass.ron", MASS),
            ("noports.ron", &no_ports),
            ("dotted.ron", &dotted),
            (
                "user.ron",
                &user("", r#"("push", "cart.hub")"#).replace("mass.ron", "noports.ron"),
            ),
        ],
    );
    let d = folder.errors("dotted.ron");
    assert_eq!(d[0].kind, DiagnosticKind::InvalidName);
    assert!(
        d[0].message
            .starts_with("element name 'p.ush' is not a valid name")
    );
    let d = folder.errors("user.ron");
    assert!(
        d[0].message.contains("'noports.ron' declares no ports"),
        "{}",
        d[0].message
    );
}

#[test]
fn a_part_alone_is_checked_but_has_no_equations_of_its_own() {
    let model = load("parts/suspension.ron");
    let ports: Vec<&str> = model.ports().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(ports, ["wheel", "body"]);
    let error =
        equations::derive(&model, &laws::plain_laws(&model), &Default::default()).unwrap_err();
    assert_eq!(error.first().kind, DiagnosticKind::Submodel);
    assert!(
        error
            .first()
            .message
            .starts_with("model 'suspension' is a part with open ports ('wheel', 'body')")
    );
}

#[test]
fn a_sub_models_parameter_is_set_in_its_use() {
    use bondgraph_ron::model::edit::{self, Edit};
    let path = models().join("examples/composed/half_car.ron");
    let source = SourceFile::new(
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    );
    let edit = Edit {
        remove: Vec::new(),
        parameters: vec![
            // Given in the use already: replaced; not given: added to the use's map.
            ("front.suspension.k_s".into(), 25000.0),
            ("front.k_t".into(), 150000.0),
            ("m_b".into(), 650.0),
        ],
    };
    let edited = edit::apply(&source, &edit).unwrap();
    assert!(
        edited.text().contains(
            r#"Submodel(file: "../../parts/corner.ron", parameters: {"k_t": 150000.0, "suspension.k_s": 25000.0, "suspension.b_s": 1500.0})"#
        ),
        "{}",
        edited.text()
    );
    let model = bondgraph_ron::model::load_source(&edited).unwrap();
    let value = |name: &str| {
        model
            .parameters()
            .iter()
            .find(|p| p.name == name)
            .unwrap()
            .value
    };
    assert_eq!(value("front.suspension.k_s"), 25000.0);
    assert_eq!(value("front.k_t"), 150000.0);
    assert_eq!(value("m_b"), 650.0);
    // The rear corner keeps its own.
    assert_eq!(value("rear.suspension.k_s"), 22000.0);

    // A use without parameters gets them.
    let path = models().join("examples/composed/quarter_car.ron");
    let source = SourceFile::new(
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    );
    let edit = Edit {
        remove: Vec::new(),
        parameters: vec![("suspension.b_s".into(), 1200.0)],
    };
    let edited = edit::apply(&source, &edit).unwrap();
    assert!(edited.text().contains(
        r#""suspension": Submodel(file: "../../parts/suspension.ron", parameters: {"b_s": 1200.0}),"#
    ));
    let error = edit::apply(
        &source,
        &Edit {
            remove: Vec::new(),
            parameters: vec![("suspension.b".into(), 1.0)],
        },
    )
    .unwrap_err();
    assert_eq!(
        error.first().message,
        "cannot set parameter 'suspension.b': model 'quarter_car' has no parameter 'suspension.b'"
    );
    // A part is used whole: its elements are not removed one by one.
    let error = edit::apply(
        &source,
        &Edit {
            remove: vec!["suspension.damper".into()],
            parameters: Vec::new(),
        },
    )
    .unwrap_err();
    assert_eq!(
        error.first().notes,
        [
            "'suspension.damper' is inside sub-model 'suspension' ('../../parts/suspension.ron'), \
          which is used whole: remove 'suspension', or use a part without it"
        ]
    );
}

#[test]
fn the_wall_as_a_linear_graph_of_sub_graphs_is_the_wall_of_sub_models() {
    let graph = load("examples/composed/wall.lg.ron");
    let bond_graph = load("examples/composed/wall.ron");
    let parts: Vec<&str> = graph.parts().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(parts, ["brick", "insulation", "plaster"]);
    let energy = |model: &Model| {
        equations::derive(
            model,
            &laws::plain_laws(model),
            &equations::Options {
                variables: equations::Variables::Energy,
            },
        )
        .unwrap()
    };
    // Each layer's heat: an A-type's integral of its through variable in the linear graph,
    // a C's displacement in the bond graph.
    let (a, b) = numeric(
        &energy(&graph),
        &[
            "p_air_capacity",
            "plaster.p_capacity",
            "brick.p_capacity",
            "insulation.p_capacity",
        ],
    );
    let (a_bg, b_bg) = numeric(
        &energy(&bond_graph),
        &[
            "q_air_capacity",
            "plaster.q_capacity",
            "brick.q_capacity",
            "insulation.q_capacity",
        ],
    );
    assert_close(&a, &a_bg);
    assert_close(&b, &b_bg);
    // By hand, the insulation's heat leaks to the outside through half its resistance and
    // to the brick through the two halves between the cores: -(2/R_i + 2/(R_b + R_i))/C_i.
    let (r_b, r_i, c_i) = (0.02, 0.1, 2.0e5);
    let expected = -(2.0 / r_i + 2.0 / (r_b + r_i)) / c_i;
    assert!((a[3][3] - expected).abs() < 1e-12 * expected.abs());
}

#[test]
fn a_sub_graphs_terminals_are_joined_or_named_and_checked() {
    let layer = std::fs::read_to_string(models().join("parts/wall_layer.lg.ron")).unwrap();
    let user = |use_fields: &str, outside: &str| {
        format!(
            r#"LinearGraph(
    name: "room",
    inputs: {{"P": (unit: "W"), "T_out": (unit: "K")}},
    ground: "g",
    branches: {{
        "heater": ThroughSource(value: "P", from: "g", to: "air"),
        "wall": Subgraph(file: "layer.lg.ron"{use_fields}),
        "outside": AcrossSource(value: "T_out", from: "{outside}", to: "g"),
    }},
)"#
        )
    };
    let folder = Folder::new(
        "terminals",
        &[
            ("layer.lg.ron", &layer),
            (
                "good.lg.ron",
                &user(r#", terminals: {"inside": "air"}"#, "wall.outside"),
            ),
            (
                "typo.lg.ron",
                &user(r#", terminals: {"inside": "air"}"#, "wall.outsde"),
            ),
            ("open.lg.ron", &user("", "wall.outside")),
            (
                "wrong.lg.ron",
                &user(r#", terminals: {"inner": "air"}"#, "wall.outside"),
            ),
        ],
    );
    let model = folder.load("good.lg.ron");
    let states: Vec<String> = derive(&model)
        .states
        .iter()
        .map(|s| s.name.clone())
        .collect();
    assert_eq!(states, ["wall.p_capacity"]);

    let d = folder.errors("typo.lg.ron");
    assert_eq!(d[0].kind, DiagnosticKind::Submodel);
    assert!(
        d[0].message
            .starts_with("branch 'outside': 'outsde' is not a terminal of sub-graph 'wall'")
    );
    assert_eq!(d[0].notes, ["did you mean 'wall.outside'?"]);
    assert_eq!(place(&d[0]), ("typo.lg.ron".into(), 8, 55));

    let d = folder.errors("open.lg.ron");
    assert_eq!(
        d[0].message,
        "sub-graph 'wall': terminal 'inside' is not connected"
    );
    assert_eq!(place(&d[0]), ("open.lg.ron".into(), 7, 9));

    let d = folder.errors("wrong.lg.ron");
    assert!(
        d[0].message
            .starts_with("sub-graph 'wall': 'inner' is not a terminal of '")
    );
    assert_eq!(d[0].notes, ["its terminals: 'inside', 'outside'"]);
}

#[test]
fn drawings_group_each_sub_model_or_collapse_it_to_a_box() {
    let model = load("examples/composed/half_car.ron");
    let expanded = bondgraph_core::graph::to_dot_titled(&model, None, None);
    // Nested clusters: the corner's box holds its own elements and its suspension's box.
    let front = expanded.find("subgraph \"cluster_front\"").unwrap();
    let nested = expanded
        .find("subgraph \"cluster_front.suspension\"")
        .unwrap();
    let wheel = expanded.find("\"front.wheel\" [").unwrap();
    let spring = expanded.find("\"front.suspension.spring\" [").unwrap();
    assert!(
        front < wheel && wheel < nested && nested < spring,
        "{expanded}"
    );
    // Every element is declared once, every bond drawn.
    assert_eq!(expanded.matches(" [label=").count(), model.elements().len());
    assert_eq!(expanded.matches(" -> ").count(), model.bonds().len());

    let collapsed = bondgraph_core::graph::to_dot_collapsed(&model, None, None);
    assert!(collapsed.contains("\"front\" [shape=box, style=rounded, label=\"front\\ncorner\"];"));
    // The bonds into and out of a corner end at its box, at the port they join; the bonds
    // inside it are hidden: 12 bonds of the half car's own file remain.
    assert!(collapsed.contains(
        "\"front_road\" -> \"front\" [dir=both, arrowhead=lvee, arrowtail=none, label=\"1\", headlabel=\"road\"];"
    ));
    assert!(collapsed.contains("\"rear\" -> \"rear_point\" [dir=both, arrowhead=lvee, arrowtail=none, label=\"7\", taillabel=\"body\"];"));
    assert_eq!(collapsed.matches(" -> ").count(), 12);
    assert!(!collapsed.contains("front.suspension.spring"));
}

#[test]
fn composition_is_bounded_in_depth_and_in_size() {
    // Seventeen files, each using the next: one more than the nesting limit.
    let mut files: Vec<(String, String)> = Vec::new();
    for level in 0..=bondgraph_ron::model::compose::MAX_DEPTH {
        let inner = if level == bondgraph_ron::model::compose::MAX_DEPTH {
            String::new()
        } else {
            format!(r#", "inner": Submodel(file: "level{}.ron")"#, level + 1)
        };
        let bond = if inner.is_empty() {
            String::new()
        } else {
            r#", ("j", "inner.p")"#.to_string()
        };
        files.push((
            format!("level{level}.ron"),
            format!(
                r#"Model(name: "level{level}", ports: {{"p": (element: "j")}},
    elements: {{"j": One, "m": I(inertance: "1"){inner}}}, bonds: [("j", "m"){bond}])"#
            ),
        ));
    }
    files.push((
        "user.ron".into(),
        user("", r#"("push", "cart.p")"#).replace("mass.ron", "level0.ron"),
    ));
    let borrowed: Vec<(&str, &str)> = files
        .iter()
        .map(|(n, t)| (n.as_str(), t.as_str()))
        .collect();
    let folder = Folder::new("deep", &borrowed);
    let d = folder.errors("user.ron");
    assert_eq!(d[0].kind, DiagnosticKind::TooLarge);
    assert_eq!(
        d[0].message,
        "sub-model 'inner': sub-models are nested deeper than the limit of 16"
    );

    // A part of 101 elements used 200 times: the 199th use takes the model's two elements
    // and the uses' to 2 + 199 * 101 = 20 101, over the limit of 20 000, and stops there.
    let chain: String = (0..100)
        .map(|i| format!(r#", "m{i}": I(inertance: "1")"#))
        .collect();
    let chain_bonds: String = (0..100).map(|i| format!(r#", ("j", "m{i}")"#)).collect();
    let big = format!(
        r#"Model(name: "big", ports: {{"p": (element: "j")}}, elements: {{"j": One{chain}}},
    bonds: [{}])"#,
        &chain_bonds[2..]
    );
    let uses: String = (0..200)
        .map(|i| format!(r#""u{i}": Submodel(file: "big.ron"), "#))
        .collect();
    let use_bonds: String = (0..200).map(|i| format!(r#", ("j", "u{i}.p")"#)).collect();
    let many = format!(
        r#"Model(name: "many", inputs: {{"F": (unit: "N")}},
    elements: {{"push": Se(effort: "F"), "j": One, {uses}}},
    bonds: [("push", "j"){use_bonds}])"#
    );
    let folder = Folder::new("size", &[("big.ron", &big), ("many.ron", &many)]);
    let d = folder.errors("many.ron");
    assert_eq!(d[0].kind, DiagnosticKind::TooLarge);
    assert!(
        d[0].message.starts_with(
            "sub-model 'u198': the composed model has 20101 elements, over the limit of 20000"
        ),
        "{}",
        d[0].message
    );
}

#[test]
fn a_value_outside_the_parts_bounds_is_refused_at_the_use() {
    let bounded = MASS.replace(
        r#""m": (value: 2.0, unit: "kg")"#,
        r#""m": (value: 2.0, unit: "kg", bounds: (1.0, 10.0))"#,
    );
    let folder = Folder::new(
        "bounds",
        &[
            ("mass.ron", &bounded),
            (
                "user.ron",
                &user(r#", parameters: {"m": 30.0}"#, r#"("push", "cart.hub")"#),
            ),
        ],
    );
    let d = folder.errors("user.ron");
    assert_eq!(d[0].kind, DiagnosticKind::InvalidValue);
    assert_eq!(
        d[0].message,
        "parameter 'cart.m' has value 30, outside its bounds (1, 10)"
    );
    assert_eq!(place(&d[0]), ("user.ron".into(), 6, 9));
}
