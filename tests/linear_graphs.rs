//! Linear graphs (`*.lg.ron`) on real files: the same dynamics as the bond-graph twins, the
//! normal tree's states, Rowell & Wormley's worked examples against hand derivations, the
//! flagship in every mode, outputs, scenarios, input rates, and the program's views.

use std::collections::BTreeMap;

use bondgraph_core::equations::{Options, OutputSpec, StateEquations, Variables};
use bondgraph_core::model::Model;
use bondgraph_core::modes::{self, Mode, ModeEquations};
use bondgraph_core::symbolic::RatFunc;
use bondgraph_core::{laws, normal_tree};
use serde_json::Value;

use crate::cli::{fail, json, numbers, succeed};
use crate::support::{assert_symbolic, expected, linear_graph_files, load, root};

const EXAMPLES: &str = "models/examples";

fn options(variables: Variables) -> Options {
    Options { variables }
}

fn derive(model: &Model, mode: &Mode, variables: Variables) -> ModeEquations {
    modes::derive(model, mode, &options(variables))
        .unwrap_or_else(|e| panic!("{} {}: {e}", model.name(), mode.spec(model)))
}

/// The examples that have both a bond graph and a linear graph: `(bond graph, linear graph)`.
fn twins() -> Vec<(String, String)> {
    linear_graph_files(EXAMPLES)
        .into_iter()
        .filter_map(|lg| {
            let bg = lg.replace(".lg.ron", ".ron");
            root().join(&bg).exists().then_some((bg, lg))
        })
        .collect()
}

#[test]
fn every_bond_graph_example_has_its_linear_graph() {
    let bond_graphs = crate::support::ron_files(EXAMPLES);
    assert_eq!(bond_graphs.len(), 8);
    let twins: Vec<String> = twins().into_iter().map(|(bg, _)| bg).collect();
    assert_eq!(twins, bond_graphs);
}

// ---------------------------------------------------------------------------------------
// The same dynamics through either formalism.

/// `det(M)` by Gaussian elimination with partial pivoting.
fn determinant(mut m: Vec<Vec<f64>>) -> f64 {
    let n = m.len();
    let mut det = 1.0;
    for k in 0..n {
        let pivot = (k..n)
            .max_by(|&a, &b| m[a][k].abs().total_cmp(&m[b][k].abs()))
            .unwrap();
        if m[pivot][k] == 0.0 {
            return 0.0;
        }
        if pivot != k {
            m.swap(pivot, k);
            det = -det;
        }
        det *= m[k][k];
        let (top, rest) = m.split_at_mut(k + 1);
        let pivot_row = &top[k];
        for row in rest {
            let factor = row[k] / pivot_row[k];
            for (entry, above) in row.iter_mut().zip(pivot_row).skip(k) {
                *entry -= factor * above;
            }
        }
    }
    det
}

/// `(sI - A)⁻¹ b` by Cramer's rule on small matrices.
fn solve(s: f64, a: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
    let n = a.len();
    let shifted: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| if i == j { s - a[i][j] } else { -a[i][j] })
                .collect()
        })
        .collect();
    let det = determinant(shifted.clone());
    (0..n)
        .map(|k| {
            let mut replaced = shifted.clone();
            for i in 0..n {
                replaced[i][k] = b[i];
            }
            determinant(replaced) / det
        })
        .collect()
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale.max(a.abs()).max(b.abs()).max(1e-300)
}

fn numeric(eq: &StateEquations, m: &[Vec<RatFunc>]) -> Vec<Vec<f64>> {
    m.iter()
        .map(|row| row.iter().map(|e| eq.evaluate(e)).collect())
        .collect()
}

#[test]
fn twins_derive_the_same_dynamics() {
    for (bg_path, lg_path) in twins() {
        let (bg, lg) = (load(&bg_path), load(&lg_path));
        let reachable = modes::reachable(&bg, &options(Variables::CoEnergy)).unwrap();
        for mode in &reachable.modes {
            let spec = mode.mode.spec(&bg);
            let lg_mode = Mode::parse(&lg, &spec).unwrap();
            let (x, y) = (
                derive(&bg, &mode.mode, Variables::CoEnergy).equations,
                derive(&lg, &lg_mode, Variables::CoEnergy).equations,
            );
            let what = format!("{lg_path} in mode '{spec}'");
            assert_eq!(x.state_count(), y.state_count(), "{what}: states");
            let (ax, ay) = (numeric(&x, &x.a()), numeric(&y, &y.a()));
            let (bx, by) = (numeric(&x, &x.b()), numeric(&y, &y.b()));
            let scale = ax.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
            // Characteristic polynomials agree at n + 1 points, so they are equal.
            let n = x.state_count();
            for k in 0..=n {
                let s = 0.37 + 1.9 * k as f64;
                let char_poly = |a: &[Vec<f64>]| {
                    determinant(
                        (0..n)
                            .map(|i| {
                                (0..n)
                                    .map(|j| if i == j { s - a[i][j] } else { -a[i][j] })
                                    .collect()
                            })
                            .collect(),
                    )
                };
                let (px, py) = (char_poly(&ax), char_poly(&ay));
                assert!(
                    close(px, py, scale.powi(n as i32)),
                    "{what}: det(sI - A) at s = {s}: {px} against {py}"
                );
            }
            // States correspond by element: the same physical variable (the inductor's
            // current is a bond graph's flow of an inertia and a linear graph's through
            // variable of a T-type).
            let corresponding: Vec<usize> = x
                .states
                .iter()
                .map(|state| {
                    y.states
                        .iter()
                        .position(|other| other.element == state.element)
                        .unwrap_or_else(|| panic!("{what}: no state of '{}'", state.element))
                })
                .collect();
            for (i, &k) in corresponding.iter().enumerate() {
                for (j, &l) in corresponding.iter().enumerate() {
                    assert!(
                        close(ax[i][j], ay[k][l], scale),
                        "{what}: A[{i}][{j}] {} against {}",
                        ax[i][j],
                        ay[k][l]
                    );
                }
                for u in 0..x.inputs.len() {
                    assert!(close(bx[i][u], by[k][u], scale), "{what}: B[{i}][{u}]");
                }
            }
            // Transfer functions from every input to every state, at points off the poles.
            for u in 0..x.inputs.len() {
                let column = |b: &[Vec<f64>]| b.iter().map(|row| row[u]).collect::<Vec<_>>();
                for s in [0.21, 3.3, 47.0] {
                    let (hx, hy) = (solve(s, &ax, &column(&bx)), solve(s, &ay, &column(&by)));
                    for (i, &k) in corresponding.iter().enumerate() {
                        assert!(
                            close(hx[i], hy[k], hx[i].abs()),
                            "{what}: H(s = {s}) from {} to {}",
                            x.inputs[u],
                            x.states[i].name
                        );
                    }
                }
            }
        }
    }
}

/// The acceptance test of the linear-graph format: the mass-spring-damper's `A_value` from
/// the linear graph (co-energy states by default) is the bond graph's in co-energy states,
/// and the two agree in energy states too, up to the order of the states.
#[test]
fn mass_spring_damper_json_matches_the_bond_graph() {
    let lg = "models/examples/mass_spring_damper.lg.ron";
    let bg = "models/examples/mass_spring_damper.ron";
    let by_state = |json: &Value| -> BTreeMap<(String, String), f64> {
        let names: Vec<String> = json["states"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["name"].as_str().unwrap().to_string())
            .collect();
        let a = numbers(&json["A_value"]);
        let mut entries = BTreeMap::new();
        for (i, row) in a.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                entries.insert((names[i].clone(), names[j].clone()), *value);
            }
        }
        entries
    };
    let linear = json(&[lg]);
    assert_eq!(linear["variables"], "coenergy");
    let bond = json(&[bg, "--states", "coenergy"]);
    assert_eq!(by_state(&linear), by_state(&bond));
    // m = 2, k = 200, b = 4: m dv/dt = F - f - b v, df/dt = k v.
    assert_eq!(numbers(&linear["A_value"]), [[-2.0, -0.5], [200.0, 0.0]]);
    assert_eq!(
        by_state(&json(&[lg, "--states", "energy"])),
        by_state(&json(&[bg, "--states", "energy"]))
    );
    assert!(linear.get("E").is_none(), "no input rates, no E");
}

// ---------------------------------------------------------------------------------------
// The normal tree.

/// Every linear graph shipped, and the fixtures that load.
fn every_linear_graph() -> Vec<String> {
    let mut files = linear_graph_files(EXAMPLES);
    files.extend(linear_graph_files("models/eversion"));
    files.extend(linear_graph_files("tests/fixtures/linear_graph"));
    files
}

#[test]
fn the_states_are_the_normal_trees_in_every_mode() {
    for path in every_linear_graph() {
        let model = load(&path);
        let graph = model.linear_graph().unwrap();
        let reachable = modes::reachable(&model, &options(Variables::CoEnergy)).unwrap();
        for mode in &reachable.modes {
            let laws = laws::for_mode(&model, &mode.mode);
            let tree = normal_tree::of_mode(&model, &laws).unwrap();
            // A slack string keeps its slack length as a state; the tree sees a source.
            let derived: Vec<String> = mode
                .equations
                .states
                .iter()
                .filter(|s| {
                    !matches!(
                        laws[model.element_named(&s.element).unwrap().index()],
                        laws::Law::SlackStorage
                    )
                })
                .map(|s| s.name.clone())
                .collect();
            assert_eq!(
                derived,
                tree.states(graph),
                "{path} in mode '{}'",
                mode.mode.spec(&model)
            );
            // Every dependent storage element is merged into a state or held.
            for b in tree.dependent_storage() {
                let name = &graph.branches[b].name;
                let merged = mode
                    .equations
                    .states
                    .iter()
                    .any(|s| s.merged.contains(name));
                let held = mode.equations.notes.iter().any(|n| {
                    matches!(n, bondgraph_core::equations::Note::Held { element } if element == name)
                });
                assert!(
                    merged || held,
                    "{path}: '{name}' is neither merged nor held"
                );
            }
        }
    }
}

#[test]
fn a_gear_between_two_inertias_needs_the_two_port_alternatives() {
    let model = load("models/examples/rowell_wormley_dc_motor.lg.ron");
    let graph = model.linear_graph().unwrap();
    let tree = normal_tree::of_mode(&model, &laws::plain_laws(&model)).unwrap();
    // Two transformers, four placements (the motor's port varying first): both primaries
    // (J_L in the tree); the motor's secondary with the gear's primary, infeasible (both on
    // node w_m); the gear's secondary (J_m in the tree); both secondaries (neither inertia in
    // the tree, and the inductance in it to reach node c).
    let summary: Vec<(bool, usize, usize)> = tree
        .alternatives
        .iter()
        .map(|a| (a.feasible, a.a_in_tree, a.t_in_tree))
        .collect();
    assert_eq!(summary[0], (true, 1, 0));
    assert!(!summary[1].0);
    assert_eq!(summary[2..], [(true, 1, 0), (true, 0, 1)]);
    assert_eq!(tree.chosen, 0);
    assert_eq!(tree.states(graph), ["f_L", "v_J_L"]);
    let dependent: Vec<&str> = tree
        .dependent_storage()
        .into_iter()
        .map(|b| graph.branches[b].name.as_str())
        .collect();
    assert_eq!(dependent, ["J_m"]);
}

#[test]
fn cut_set_and_loop_equations_of_the_normal_tree() {
    let model = load("models/examples/two_masses.lg.ron");
    let graph = model.linear_graph().unwrap();
    let tree = normal_tree::of_mode(&model, &laws::plain_laws(&model)).unwrap();
    let named = |terms: normal_tree::Terms| -> Vec<(String, i64)> {
        terms
            .into_iter()
            .map(|(b, _, sign)| (graph.branches[b].name.clone(), sign))
            .collect()
    };
    let index = |name: &str| graph.branch_named(name).unwrap();
    // The tree: mass1 (v1 - g) and mass2 (v2 - g). Cut-set of mass1 (node v1): the force
    // flows in, the spring out: f_mass1 = f_force - f_spring.
    assert_eq!(
        named(tree.cut_set_equation(graph, index("mass1"), 0)),
        [("force".to_string(), 1), ("spring".to_string(), -1)]
    );
    // Cut-set of mass2 (node v2): the spring flows in, the damper out.
    assert_eq!(
        named(tree.cut_set_equation(graph, index("mass2"), 0)),
        [("spring".to_string(), 1), ("damper".to_string(), -1)]
    );
    // Loop of the spring (v1 -> v2): v_spring = v_mass1 - v_mass2.
    assert_eq!(
        named(tree.loop_equation(graph, index("spring"), 0)),
        [("mass1".to_string(), 1), ("mass2".to_string(), -1)]
    );
    // Loop of the force (g -> v1): v_force = -v_mass1.
    assert_eq!(
        named(tree.loop_equation(graph, index("force"), 0)),
        [("mass1".to_string(), -1)]
    );
}

// ---------------------------------------------------------------------------------------
// Rowell & Wormley's worked examples, against hand derivations (in each file's comments).

fn plain(path: &str) -> (Model, StateEquations) {
    let model = load(path);
    let eq = derive(&model, &Mode::initial(&model), Variables::CoEnergy).equations;
    (model, eq)
}

fn names(eq: &StateEquations) -> Vec<&str> {
    eq.states.iter().map(|s| s.name.as_str()).collect()
}

#[test]
fn rowell_wormley_rlc() {
    // C dv_C/dt = (V_s - v_C)/R - f_L,  L df_L/dt = v_C.
    let (model, eq) = plain("models/examples/rowell_wormley_rlc.lg.ron");
    assert_eq!(names(&eq), ["v_C", "f_L"]);
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[&["-1/(R*C)", "-1/C"], &["1/L", "0"]],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1/(R*C)"], &["0"]]);
    assert!(!eq.has_input_rates());
}

#[test]
fn rowell_wormley_dependent_spring() {
    // m dv/dt = f_K1 - B v,  df_K1/dt = -K1 K2/(K1 + K2) v + K1/(K1 + K2) dF/dt.
    let (model, eq) = plain("models/examples/rowell_wormley_dependent_spring.lg.ron");
    assert_eq!(names(&eq), ["v_mass", "f_K1"]);
    assert_eq!(eq.states[1].merged, ["K2"]);
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[&["-B/m", "1/m"], &["-K1*K2/(K1 + K2)", "0"]],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["0"], &["0"]]);
    assert_symbolic(&model, "E", &eq.e(), &[&["0"], &["K1/(K1 + K2)"]]);
    // In energy variables the merged displacement absorbs the source: no rates.
    let energy = derive(&model, &Mode::initial(&model), Variables::Energy).equations;
    assert!(!energy.has_input_rates());
}

#[test]
fn rowell_wormley_dc_motor() {
    // (J_L + N^2 J_m) dw_L/dt = N K_m i - (B_L + N^2 B_m) w_L,  L di/dt = V_s - R i - K_m N w_L.
    let (model, eq) = plain("models/examples/rowell_wormley_dc_motor.lg.ron");
    assert_eq!(names(&eq), ["f_L", "v_J_L"]);
    assert_eq!(eq.states[1].merged, ["J_m"]);
    assert_eq!(eq.states[1].storage, expected(&model, "J_L + N^2*J_m"));
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[
            &["-R/L", "-K_m*N/L"],
            &["N*K_m/(J_L + N^2*J_m)", "-(B_L + N^2*B_m)/(J_L + N^2*J_m)"],
        ],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1/L"], &["0"]]);
}

#[test]
fn the_input_rate_term_in_json_text_and_latex() {
    let path = "models/examples/rowell_wormley_dependent_spring.lg.ron";
    let doc = json(&[path]);
    // K1 = 300, K2 = 100: E = [0, 0.75].
    assert_eq!(doc["E"], serde_json::json!([["0"], ["K1/(K1 + K2)"]]));
    assert_eq!(numbers(&doc["E_value"]), [[0.0], [0.75]]);
    let text = succeed(&["equations", path]);
    assert!(
        text.contains("df_K1/dt   = -K1*K2/(K1 + K2)*v_mass + K1/(K1 + K2)*der(F)\n"),
        "{text}"
    );
    assert!(
        text.contains("E = [            0 ]\n    [ K1/(K1 + K2) ]\n"),
        "{text}"
    );
    let latex = succeed(&["equations", path, "--format", "latex"]);
    assert!(
        latex.contains("\\frac{K_{1}}{K_{1} + K_{2}} \\end{bmatrix} \\frac{dF}{dt}"),
        "{latex}"
    );
}

// ---------------------------------------------------------------------------------------
// The flagship.

/// Every mode of `bg` and `lg` derives the same equations and guards, in both variables.
fn same_in_every_mode(bg_path: &str, lg_path: &str) -> usize {
    let (bg, lg) = (load(bg_path), load(lg_path));
    let reachable = modes::reachable(&bg, &options(Variables::Energy)).unwrap();
    for mode in &reachable.modes {
        let spec = mode.mode.spec(&bg);
        let lg_mode = Mode::parse(&lg, &spec).unwrap();
        assert_eq!(lg_mode.spec(&lg), spec);
        for variables in [Variables::Energy, Variables::CoEnergy] {
            let (x, y) = (
                derive(&bg, &mode.mode, variables),
                derive(&lg, &lg_mode, variables),
            );
            let (ex, ey) = (&x.equations, &y.equations);
            let what = format!("{lg_path} in mode {spec} ({variables:?})");
            assert_eq!(names(ex), names(ey), "{what}");
            let text = |eq: &StateEquations, m: Vec<Vec<RatFunc>>| -> Vec<Vec<String>> {
                m.iter()
                    .map(|row| row.iter().map(|e| e.text(&eq.symbols)).collect())
                    .collect()
            };
            assert_eq!(text(ex, ex.a()), text(ey, ey.a()), "{what}: A");
            assert_eq!(text(ex, ex.b()), text(ey, ey.b()), "{what}: B");
            assert_eq!(text(ex, ex.e()), text(ey, ey.e()), "{what}: E");
            let c = |eq: &StateEquations| -> Vec<String> {
                eq.c().iter().map(|e| e.text(&eq.symbols)).collect()
            };
            assert_eq!(c(ex), c(ey), "{what}: c");
            let guards = |m: &ModeEquations, model: &Model| -> Vec<String> {
                m.guards
                    .iter()
                    .map(|g| {
                        format!(
                            "{}: {} -> {}",
                            model.element(g.element).name,
                            g.condition_text(&m.equations),
                            g.leaves_to.name()
                        )
                    })
                    .collect()
            };
            assert_eq!(guards(&x, &bg), guards(&y, &lg), "{what}: guards");
        }
    }
    reachable.modes.len()
}

#[test]
fn the_flagship_as_a_linear_graph_is_the_robot_in_every_mode() {
    assert_eq!(
        same_in_every_mode("models/eversion/robot.ron", "models/eversion/robot.lg.ron"),
        18
    );
    let text = succeed(&["modes", "models/eversion/robot.lg.ron"]);
    assert!(
        text.starts_with(
            "model 'eversion_robot': 3 switching elements, 18 modes reachable from fr_ge=stuck,k=taut,fr_ct=stuck\n"
        ),
        "{text}"
    );
    assert_eq!(text.matches("\nmode ").count(), 18);
    // In the linear graph's own variables, the states are v_ge, f_k, v_ct.
    assert!(
        text.contains("mode fr_ge=slip+,k=taut,fr_ct=slip+: 3 states (v_ge, f_k, v_ct)\n"),
        "{text}"
    );
}

#[test]
fn the_papers_structure_as_a_linear_graph_is_paper_ron_in_every_mode() {
    assert_eq!(
        same_in_every_mode("models/eversion/paper.ron", "models/eversion/paper.lg.ron"),
        18
    );
}

#[test]
fn the_flagships_scenario_runs_on_the_linear_graph() {
    // fig6.ron names bond-graph outputs; the linear graph has the same elements and bonds
    // where those outputs are, so it simulates the same trajectory.
    let args = |model: &str| {
        vec![
            "simulate".to_string(),
            model.to_string(),
            "--scenario".to_string(),
            "models/eversion/fig6.ron".to_string(),
            "--format".to_string(),
            "json".to_string(),
        ]
    };
    let run = |model: &str| -> Value {
        let a = args(model);
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        serde_json::from_str(&succeed(&refs)).unwrap()
    };
    let (bg, lg) = (
        run("models/eversion/robot.ron"),
        run("models/eversion/robot.lg.ron"),
    );
    assert_eq!(bg["events"], lg["events"]);
    assert_eq!(bg["final"], lg["final"]);
}

// ---------------------------------------------------------------------------------------
// Outputs and scenarios by branch.

#[test]
fn across_and_through_outputs_read_the_branches() {
    let model = load("models/examples/rlc.lg.ron");
    let eq = derive(&model, &Mode::initial(&model), Variables::CoEnergy).equations;
    // Each row as the equations print it: states, then inputs, then the constant.
    let row = |spec: &str| eq.form_text(&eq.output(&OutputSpec::parse(&model, spec).unwrap()).row);
    // The source's across variable is V; its through variable, from a to g through the
    // source, is minus the loop current (continuity at node a: f_source + f_resistor = 0).
    assert_eq!(row("across:source"), "V");
    assert_eq!(row("through:source"), "-f_inductor");
    assert_eq!(row("through:resistor"), "f_inductor");
    // The resistor's across variable is R times its current; the inductor's, the loop's.
    assert_eq!(row("across:resistor"), "R*f_inductor");
    assert_eq!(row("across:inductor"), "-R*f_inductor - v_capacitor + V");
    assert_eq!(row("across:capacitor"), "v_capacitor");
    let problem = |spec: &str| {
        OutputSpec::parse(&model, spec)
            .unwrap_err()
            .first()
            .message
            .clone()
    };
    assert_eq!(
        problem("across:resistr"),
        "output 'across:resistr': the linear graph has no branch 'resistr'"
    );
    let motor = load("models/examples/dc_motor.lg.ron");
    assert!(OutputSpec::parse(&motor, "through:motor").is_err());
    let bond = load("models/examples/rlc.ron");
    assert!(
        OutputSpec::parse(&bond, "across:resistor")
            .unwrap_err()
            .first()
            .message
            .contains("is a bond graph")
    );
}

/// The samples of a CSV trajectory: `(t, columns)`.
fn samples(csv: &str) -> (Vec<String>, Vec<(f64, Vec<f64>)>) {
    let mut lines = csv.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|line| {
            // The mode is quoted and holds commas: take the numbers around it.
            let (t, rest) = line.split_once(',').unwrap();
            let after_mode = rest.rsplit_once('"').map_or(rest, |(_, r)| r);
            let values = after_mode
                .split(',')
                .filter(|s| !s.is_empty())
                .map(|v| v.parse().unwrap())
                .collect();
            (t.parse().unwrap(), values)
        })
        .collect();
    (header, rows)
}

#[test]
fn a_scenario_removes_and_starts_branches_by_name() {
    let csv = succeed(&[
        "simulate",
        "models/examples/mass_spring_damper.lg.ron",
        "--scenario",
        "tests/fixtures/linear_graph/free_oscillation.ron",
    ]);
    let (header, rows) = samples(&csv);
    assert_eq!(
        header,
        [
            "t",
            "mode",
            "through:spring",
            "across:mass",
            "integral:across:mass"
        ]
    );
    // Undamped, from x = 0.01 m at rest: x = 0.01 cos(w t), w = sqrt(k/m) = 10 rad/s;
    // the spring's force k x, the mass's velocity -0.01 w sin(w t), its displacement
    // x - 0.01.
    let (k, w, x0) = (200.0, 10.0f64, 0.01);
    assert_eq!(rows.len(), 21);
    for (t, values) in rows {
        let exact = [
            k * x0 * (w * t).cos(),
            -x0 * w * (w * t).sin(),
            x0 * (w * t).cos() - x0,
        ];
        for (value, exact) in values.iter().zip(exact) {
            assert!(
                (value - exact).abs() < 1e-9,
                "t = {t}: {value} against {exact}"
            );
        }
    }
}

#[test]
fn a_step_on_a_dependent_spring_jumps_by_its_input_rate_coefficient() {
    // The solver integrates energy variables, where the dependent spring's displacement is
    // merged and nothing jumps; K1's force f = (q + F/K2)/(1/K1 + 1/K2) jumps with F. By hand
    // (see the fixture): after a step F0 at t0, f = K1/(K1 + K2) F0 e^{-a (t - t0)},
    // a = K1 K2/(B (K1 + K2)); the damper moves at f/B.
    let csv = succeed(&[
        "simulate",
        "tests/fixtures/linear_graph/dependent_spring_damper.lg.ron",
        "--scenario",
        "tests/fixtures/linear_graph/force_step.ron",
    ]);
    let (_, rows) = samples(&csv);
    let (k1, k2, b, f0, t0) = (300.0, 100.0, 15.0, 12.0, 0.055);
    let a = k1 * k2 / (b * (k1 + k2));
    for (t, values) in rows {
        let f = if t < t0 {
            0.0
        } else {
            k1 / (k1 + k2) * f0 * (-a * (t - t0)).exp()
        };
        assert!(
            (values[0] - f).abs() < 1e-9,
            "t = {t}: f {} against {f}",
            values[0]
        );
        assert!(
            (values[1] - f / b).abs() < 1e-9,
            "t = {t}: v {} against {}",
            values[1],
            f / b
        );
    }
}

#[test]
fn output_terms_in_input_rates_are_in_json_and_latex_outputs() {
    // A velocity source driving a mass: the mass's force is m dv/dt, a term of F.
    let path = "tests/fixtures/linear_graph/flow_source_mass.ron";
    let doc = json(&[path, "--output", "effort:mass"]);
    let output = &doc["outputs"][0];
    assert_eq!(output["D"], serde_json::json!(["0"]));
    assert_eq!(output["F"], serde_json::json!(["m"]));
    assert_eq!(output["F_value"], serde_json::json!([2.0]));
    // An output with no rate terms has no F.
    let plain = json(&[
        "models/examples/mass_spring_damper.ron",
        "--output",
        "effort:damper",
    ]);
    assert!(plain["outputs"][0].get("F").is_none());
    // LaTeX shows the output equations after the state equations.
    let latex = succeed(&[
        "equations",
        "models/examples/mass_spring_damper.ron",
        "--output",
        "effort:damper",
        "--format",
        "latex",
    ]);
    assert!(
        latex.contains("\\mathrm{effort}(\\mathrm{damper}) = \\frac{b}{m} p_{\\mathrm{mass}}\n"),
        "{latex}"
    );
    let latex = succeed(&[
        "equations",
        path,
        "--output",
        "effort:mass",
        "--format",
        "latex",
    ]);
    assert!(latex.contains("= m \\frac{dv}{dt}\n"), "{latex}");
}

// ---------------------------------------------------------------------------------------
// The program's views, and what it refuses.

#[test]
fn graph_shows_nodes_branches_and_the_normal_tree() {
    let path = "models/examples/two_masses.lg.ron";
    let text = succeed(&["graph", path]);
    assert!(
        text.starts_with("linear graph 'two_masses': 3 nodes (ground 'g'), 5 branches\n"),
        "{text}"
    );
    assert!(
        text.contains("  spring  T-type              v1 -> v2  stiffness k\n"),
        "{text}"
    );
    assert!(text.contains("normal tree:\n  tree:   mass1, mass2\n  links:  force, spring, damper\n  states: v_mass1, f_spring, v_mass2\n"), "{text}");
    let dot = succeed(&["graph", path, "--format", "dot"]);
    assert!(dot.starts_with("digraph \"two_masses\" {"), "{dot}");
    assert_eq!(dot.matches("style=bold").count(), 2);
    assert_eq!(dot.matches("style=dashed").count(), 3);
    let svg = succeed(&["graph", path, "--format", "svg"]);
    assert!(
        svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""),
        "{svg}"
    );
    assert!(svg.trim_end().ends_with("</svg>"));
    // One curve and one arrow per branch, tree branches solid, links dashed.
    assert_eq!(svg.matches("<path ").count(), 5);
    assert_eq!(svg.matches("<polygon ").count(), 5);
    assert_eq!(svg.matches("stroke-dasharray").count(), 3);
    // A mode's tree: the belt's stuck contact is an across source in the tree.
    let stuck = succeed(&["graph", "models/examples/belt_friction.lg.ron"]);
    assert!(stuck.contains("(here: across source)"), "{stuck}");
    assert!(stuck.contains("  tree:   belt, friction\n"), "{stuck}");
    assert!(stuck.contains("  dependent storage: block\n"), "{stuck}");
    let slipping = succeed(&[
        "graph",
        "models/examples/belt_friction.lg.ron",
        "--mode",
        "friction=slip+",
    ]);
    assert!(slipping.contains("  tree:   belt, block\n"), "{slipping}");
}

#[test]
fn explain_walks_through_the_tree_and_its_equations() {
    let text = succeed(&["explain", "models/examples/mass_spring_damper.lg.ron"]);
    for line in [
        "  1. 'mass' (A-type, v1 -> g) joins the tree: it reaches a node the tree did not reach; its across variable v_mass is a state.\n",
        "  3. 'spring' (T-type, v1 -> g) becomes a link: it would close a loop with 'mass'; its through variable f_spring is a state.\n",
        "  4. 'force' (through source, g -> v1) is a link: through sources are links.\n",
        "Primary variables: the across variables of the tree, v_mass; the through variables of the links, f_force, f_spring, f_damper.\n",
        "  f_mass = f_force - f_spring - f_damper\n",
        "  v_spring = v_mass\n",
        "  v_force = -v_mass\n",
        "  mass: f_mass = m*dv_mass/dt\n",
        "dv_mass/dt   = -b/m*v_mass - f_spring/m + F/m\n",
    ] {
        assert!(text.contains(line), "missing {line:?} in\n{text}");
    }
    let motor = succeed(&["explain", "models/examples/rowell_wormley_dc_motor.lg.ron"]);
    assert!(motor.contains("  1. 'motor.primary', 'gear.primary' in the tree: 1 A-type and 0 T-types in the tree  <- chosen\n"), "{motor}");
    assert!(
        motor.contains("  motor: v_motor_1 = K_m*v_motor_2, f_motor_1 = -f_motor_2/K_m\n"),
        "{motor}"
    );
}

#[test]
fn explain_in_markdown_has_headings_numbered_steps_and_equation_blocks() {
    let md = succeed(&[
        "explain",
        "models/examples/mass_spring_damper.lg.ron",
        "--format",
        "markdown",
    ]);
    for part in [
        "# linear graph `mass_spring_damper`: the normal tree (Rowell & Wormley)\n\n",
        "\n## Construction\n\n1. `mass` (A-type, v1 -> g) joins the tree: it reaches a node the tree did not reach; its across variable `v_mass` is a state.\n",
        "\n3. `spring` (T-type, v1 -> g) becomes a link: it would close a loop with `mass`; its through variable `f_spring` is a state.\n",
        "\n- States: `v_mass`, `f_spring`.\n",
        "\n## Continuity (cut-set) equations, one per tree branch\n\n```text\nf_mass = f_force - f_spring - f_damper\n```\n",
        "\n## Elemental equations in this mode\n\n```text\n",
        "\n## State equations (co-energy variables), from the elemental, continuity and compatibility equations\n\n```text\n",
    ] {
        assert!(md.contains(part), "missing {part:?} in\n{md}");
    }
    // The numbered steps are Markdown's, outside any code block.
    let before_first_block = &md[..md.find("```").expect("a code block")];
    assert!(before_first_block.contains("\n4. `force` (through source, g -> v1) is a link"));
    let motor = succeed(&[
        "explain",
        "models/examples/rowell_wormley_dc_motor.lg.ron",
        "--format",
        "markdown",
    ]);
    assert!(
        motor.contains("## Two-ports\n\nA transformer puts one of its ports in the tree, a gyrator both or neither.")
            && motor.contains("\n1. `motor.primary`, `gear.primary` in the tree: 1 A-type and 0 T-types in the tree (**chosen**)\n"),
        "{motor}"
    );
}

#[test]
fn a_bond_graph_fragment_is_refused_on_a_linear_graph_at_its_line() {
    let err = fail(&[
        "extend",
        "models/eversion/robot.lg.ron",
        "models/eversion/extensions/ac-sheath-drag.ron",
    ]);
    assert!(
        err.starts_with("error: extension 'ac-sheath-drag' is a bond-graph fragment (elements), and model 'eversion_robot' is a linear graph\n  --> models/eversion/extensions/ac-sheath-drag.ron:18:15\n"),
        "{err}"
    );
}

#[test]
fn a_linear_graph_takes_its_fragments() {
    let merged = succeed(&[
        "extend",
        "models/examples/thermal/thermal.lg.ron",
        "models/examples/thermal/extensions/contact-resistance.ron",
    ]);
    assert!(
        merged.contains("name: \"thermal+contact-resistance\"")
            && merged.contains("\"bar\": D(resistance: \"R_12\", from: \"T1\", to: \"contact\")")
            && merged.contains("\"joint\": D(resistance: \"R_c\", from: \"contact\", to: \"T2\")"),
        "{merged}"
    );
}

/// Every linear-graph example with one line deleted: located diagnostics or equations,
/// never a panic.
#[test]
fn damaged_linear_graphs_never_panic() {
    for path in every_linear_graph() {
        let text = std::fs::read_to_string(root().join(&path)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for i in 0..lines.len() {
            let mut without = lines.clone();
            without.remove(i);
            let name = format!("{path} without line {}", i + 1);
            match bondgraph_ron::model::load_str(&name, &without.join("\n")) {
                Ok(model) => {
                    let _ = modes::reachable(&model, &options(Variables::CoEnergy));
                }
                Err(diagnostics) => {
                    for d in diagnostics.iter() {
                        assert!(d.location.is_some(), "{name}: {d} has no location");
                    }
                }
            }
        }
    }
}

#[test]
fn check_summarises_a_linear_graph_in_its_terms() {
    assert_eq!(
        succeed(&["check", "models/examples/mass_spring_damper.lg.ron"]),
        "models/examples/mass_spring_damper.lg.ron: ok: linear graph 'mass_spring_damper' with \
         2 nodes, 4 branches, 3 parameters, 1 input and 2 states\n"
    );
    for path in every_linear_graph() {
        let line = succeed(&["check", &path]);
        assert!(line.contains(": ok: linear graph '"), "{line}");
    }
}

#[test]
fn a_gyrator_relates_across_to_through() {
    // By hand (see the fixture): dv/dt = -(B + R/G^2)/M v - P_s/(G M); the gyrator's ports
    // stay out of the tree, which keeps the mass in it.
    let (model, eq) = plain("tests/fixtures/linear_graph/piston.lg.ron");
    assert_eq!(names(&eq), ["v_mass"]);
    assert_symbolic(&model, "A", &eq.a(), &[&["-(B + R/G^2)/M"]]);
    assert_symbolic(&model, "B", &eq.b(), &[&["-1/(G*M)"]]);
    let tree = normal_tree::of_mode(&model, &laws::plain_laws(&model)).unwrap();
    let summary: Vec<(bool, usize)> = tree
        .alternatives
        .iter()
        .map(|a| (a.feasible, a.a_in_tree))
        .collect();
    // Both ports in the tree (the mass a dependent link), or neither (the mass in the tree).
    assert_eq!(summary, [(true, 0), (true, 1)]);
    assert_eq!(tree.chosen, 1);
}

/// Checks a linear graph's drawing, read back from its SVG: every edge of every branch drawn
/// once, as a tree branch or a link as the normal tree says; no two labels (or a label and
/// a node) overlapping, and no branch's line across a label.
fn check_lg_drawing(model: &Model, mode: &Mode, what: &str) {
    use crate::bond_graph_views::{Box4, tags};
    let graph = model.linear_graph().expect("a linear graph");
    let laws = laws::for_mode(model, mode);
    let tree = normal_tree::of_mode(model, &laws).expect("a normal tree");
    let svg = bondgraph_view::lg_svg::draw(model, graph, &tree, &mode.spec(model));
    let tags = tags(&svg);
    let mut drawn: std::collections::HashMap<String, Vec<bool>> = Default::default();
    let mut lines: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let mut boxes: Vec<(String, Box4)> = Vec::new();
    for tag in &tags {
        if tag.name == "g" && tag.attributes.get("class").map(String::as_str) == Some("branch") {
            let edge = tag.attributes["data-edge"].clone();
            drawn
                .entry(edge.clone())
                .or_default()
                .push(tag.attributes["data-tree"] == "true");
            let points = tag.attributes["data-points"]
                .split(' ')
                .map(|xy| {
                    let (x, y) = xy.split_once(',').expect("x,y");
                    (x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect();
            lines.push((edge, points));
        }
        if tag.attributes.contains_key("data-box") {
            let label = if tag.name == "circle" {
                "a node".to_string()
            } else {
                tag.text.clone()
            };
            boxes.push((label, Box4::of(tag)));
        }
    }
    let edges: Vec<(usize, usize)> = graph.edges().map(|(b, p, _)| (b, p)).collect();
    assert_eq!(drawn.len(), edges.len(), "{what}: edges drawn");
    for (b, p) in edges {
        let name = graph.edge_name(b, p);
        let marks = drawn
            .get(&name)
            .unwrap_or_else(|| panic!("{what}: {name} not drawn"));
        assert_eq!(
            marks,
            &[tree.in_tree[b][p]],
            "{what}: {name} drawn once, in the tree or not"
        );
    }
    // The title, the ground's name, each node and its name, each branch's name and role.
    let nodes = graph.nodes.len() - 1;
    assert_eq!(
        boxes.len(),
        2 + 2 * nodes + 2 * drawn.len(),
        "{what}: labels"
    );
    for (i, (a, box_a)) in boxes.iter().enumerate() {
        for (b, box_b) in &boxes[i + 1..] {
            assert!(
                !box_a.overlaps(box_b),
                "{what}: '{a}' {box_a:?} overlaps '{b}' {box_b:?}"
            );
        }
    }
    // No line runs through a text: each segment, sampled every pixel, stays out of every
    // label's box.
    for (edge, points) in &lines {
        for pair in points.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            let steps = ((x1 - x0).hypot(y1 - y0)).ceil().max(1.0) as usize;
            for k in 0..=steps {
                let t = k as f64 / steps as f64;
                let (x, y) = (x0 + t * (x1 - x0), y0 + t * (y1 - y0));
                for (label, b) in boxes.iter().filter(|(l, _)| l != "a node") {
                    let inside = x > b.x && x < b.x + b.w && y > b.y && y < b.y + b.h;
                    assert!(
                        !inside,
                        "{what}: the line of {edge} crosses '{label}' at ({x:.1}, {y:.1})"
                    );
                }
            }
        }
    }
}

#[test]
fn every_linear_graph_is_drawn_readably_in_every_mode() {
    let mut files = linear_graph_files("models/examples");
    files.push("models/eversion/robot.lg.ron".to_string());
    for path in &files {
        let model = load(path);
        let reachable =
            modes::reachable(&model, &Options::default()).unwrap_or_else(|e| panic!("{path}: {e}"));
        for derived in &reachable.modes {
            let what = format!("{path} {}", derived.mode.spec(&model));
            check_lg_drawing(&model, &derived.mode, &what);
        }
    }
}

/// A linear graph made nonlinear by an extension (two heated blocks, block 1 radiating to the
/// room) keeps the linear graph's words for its states: an A-type's across variable is a
/// temperature. The nonlinear printer once used the bond graph's words, where the state is
/// the flow, and called it a heat flow.
#[test]
fn a_nonlinear_linear_graph_describes_its_states_in_its_own_words() {
    let dir = std::env::temp_dir().join(format!("bondgraph-lg-words-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let extended = dir.join("radiating.lg.ron");
    let out = extended.to_string_lossy().to_string();
    crate::cli::succeed(&[
        "extend",
        "models/examples/thermal/thermal.lg.ron",
        "models/examples/thermal/extensions/radiation.ron",
        "--out",
        &out,
    ]);
    let text = crate::cli::succeed(&["equations", &out]);
    assert!(text.contains("nonlinear"), "{text}");
    assert!(
        text.contains("  v_block_1  temperature of 'block_1'\n"),
        "{text}"
    );
    assert!(
        text.contains("  v_block_2  temperature of 'block_2'\n"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
