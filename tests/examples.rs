//! Every textbook model in `models/examples/` against its matrices derived by hand.
//!
//! Each test states the physics, derives the equations on paper (in the comment), and
//! checks both the symbolic entries and their values with the file's parameters.

use bondgraph_core::equations::{Layout, Matrix, Note, OutputSpec, Quantity, Variables};

use crate::support::{assert_numeric, assert_symbolic, derive, expected, load, value};

/// Numeric matrices of a derivation.
fn values(eq: &bondgraph_core::equations::StateEquations) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let json = eq.to_json_as("", &[], Layout::Dense);
    let rows = |m: &Matrix<f64>| m.rows().expect("dense").to_vec();
    (rows(&json.A_value), rows(&json.B_value))
}

fn state_names(eq: &bondgraph_core::equations::StateEquations) -> Vec<&str> {
    eq.states.iter().map(|s| s.name.as_str()).collect()
}

#[test]
fn mass_spring_damper() {
    // One velocity v = p/m shared by mass, spring and damper (a 1-junction):
    //   dp/dt = F - k q - b v = -(b/m) p - k q + F
    //   dq/dt = v             =  (1/m) p
    let model = load("models/examples/mass_spring_damper.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_mass", "q_spring"]);
    assert_symbolic(&model, "A", &eq.a(), &[&["-b/m", "-k"], &["1/m", "0"]]);
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"]]);
    assert_symbolic(&model, "c", &[eq.c()], &[&["0", "0"]]);
    let (m, k, b) = (value(&model, "m"), value(&model, "k"), value(&model, "b"));
    let (a, bb) = values(&eq);
    assert_numeric("A", &a, &[&[-b / m, -k], &[1.0 / m, 0.0]]);
    assert_numeric("B", &bb, &[&[1.0], &[0.0]]);

    // In velocity and spring force: m dv/dt = F - f - b v, df/dt = k v.
    let co = derive(&model, Variables::CoEnergy);
    assert_eq!(state_names(&co), ["v_mass", "f_spring"]);
    assert_eq!(co.states[0].quantity, Quantity::Velocity);
    assert_eq!(co.states[1].quantity, Quantity::Force);
    assert_symbolic(&model, "A", &co.a(), &[&["-b/m", "-1/m"], &["k", "0"]]);
    assert_symbolic(&model, "B", &co.b(), &[&["1/m"], &["0"]]);

    // The damper force is b v = (b/m) p.
    let spec = OutputSpec::parse(&model, "effort:damper").unwrap();
    let out = eq.output(&spec);
    assert_eq!(
        out.row.coefficient(bondgraph_core::linear::Var::State(0)),
        expected(&model, "b/m")
    );
    assert_eq!(eq.form_text(&out.row), "b/m*p_mass");
}

#[test]
fn two_masses() {
    // v1 = p1/m1, v2 = p2/m2; the spring (0-junction between the two 1-junctions) stretches
    // at v1 - v2 and pushes both with f = k q:
    //   dp1/dt = F - k q
    //   dq/dt  = p1/m1 - p2/m2
    //   dp2/dt = k q - b p2/m2
    let model = load("models/examples/two_masses.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_mass1", "q_spring", "p_mass2"]);
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[
            &["0", "-k", "0"],
            &["1/m1", "0", "-1/m2"],
            &["0", "k", "-b/m2"],
        ],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"], &["0"]]);
    let (m1, m2, k, b) = (
        value(&model, "m1"),
        value(&model, "m2"),
        value(&model, "k"),
        value(&model, "b"),
    );
    let (a, _) = values(&eq);
    assert_numeric(
        "A",
        &a,
        &[
            &[0.0, -k, 0.0],
            &[1.0 / m1, 0.0, -1.0 / m2],
            &[0.0, k, -b / m2],
        ],
    );
}

#[test]
fn dc_motor() {
    // Armature current i = λ/L_a (λ the flux linkage), load speed w = p/J. The gyrator gives
    // motor torque K i and back-EMF K w_m; the gear TF(1/N) gives w = w_m/N and load torque
    // N·(K i). So w_m = N w and:
    //   dλ/dt = V - R_a i - K w_m = -(R_a/L_a) λ - (K N/J) p + V
    //   dp/dt = N K i - b w       =  (K N/L_a) λ - (b/J) p
    let model = load("models/examples/dc_motor.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_winding_inductance", "p_load_inertia"]);
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[&["-R_a/L_a", "-K*N/J"], &["K*N/L_a", "-b/J"]],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"]]);
    let v = |n| value(&model, n);
    let (a, _) = values(&eq);
    assert_numeric(
        "A",
        &a,
        &[
            &[-v("R_a") / v("L_a"), -v("K") * v("N") / v("J")],
            &[v("K") * v("N") / v("L_a"), -v("b") / v("J")],
        ],
    );
}

#[test]
fn rlc() {
    // Series loop, current i = λ/L, capacitor voltage q/C:
    //   dλ/dt = V - R i - q/C = -(R/L) λ - q/C + V
    //   dq/dt = i             =  λ/L
    let model = load("models/examples/rlc.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_inductor", "q_capacitor"]);
    assert_symbolic(&model, "A", &eq.a(), &[&["-R/L", "-1/C"], &["1/L", "0"]]);
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"]]);
    let (r, l, c) = (value(&model, "R"), value(&model, "L"), value(&model, "C"));
    let (a, _) = values(&eq);
    assert_numeric("A", &a, &[&[-r / l, -1.0 / c], &[1.0 / l, 0.0]]);
}

#[test]
fn tank_pipe() {
    // Tank volume V with pressure P = V/C_t, C_t = A_t/(rho g); pipe flow Q = Γ/I_p with
    // pressure momentum Γ and inertance I_p = rho L/A_p; the outlet is at zero pressure:
    //   dV/dt = Q_in - Q        = -(A_p/(rho L)) Γ + Q_in
    //   dΓ/dt = P - R_p Q       =  (rho g/A_t) V - (R_p A_p/(rho L)) Γ
    let model = load("models/examples/tank_pipe.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["q_tank", "p_pipe_inertia"]);
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[&["0", "-A_p/(rho*L)"], &["rho*g/A_t", "-R_p*A_p/(rho*L)"]],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"]]);
    let v = |n| value(&model, n);
    let inertance = v("rho") * v("L") / v("A_p");
    let capacitance = v("A_t") / (v("rho") * v("g"));
    let (a, _) = values(&eq);
    assert_numeric(
        "A",
        &a,
        &[
            &[0.0, -1.0 / inertance],
            &[1.0 / capacitance, -v("R_p") / inertance],
        ],
    );
}

#[test]
fn rigid_masses_merge_into_one_body() {
    // Both masses move at v; only one can be independent. With M = m1 + m2 the total
    // momentum p = M v obeys dp/dt = F - k q - b v:
    //   dp/dt = -(b/M) p - k q + F
    //   dq/dt =  (1/M) p
    let model = load("models/examples/rigid_masses.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_mass1", "q_spring"]);
    assert_eq!(eq.states[0].merged, ["mass2"]);
    assert_eq!(eq.states[0].storage, expected(&model, "m1 + m2"));
    assert!(
        eq.notes
            .iter()
            .any(|n| matches!(n, Note::Merged { merged, .. } if merged == &["mass2"]))
    );
    assert_symbolic(
        &model,
        "A",
        &eq.a(),
        &[&["-b/(m1 + m2)", "-k"], &["1/(m1 + m2)", "0"]],
    );
    assert_symbolic(&model, "B", &eq.b(), &[&["1"], &["0"]]);
    let (m1, m2, k, b) = (
        value(&model, "m1"),
        value(&model, "m2"),
        value(&model, "k"),
        value(&model, "b"),
    );
    let (a, _) = values(&eq);
    assert_numeric("A", &a, &[&[-b / (m1 + m2), -k], &[1.0 / (m1 + m2), 0.0]]);

    // In co-energy form the merged body's velocity: M dv/dt = F - f - b v.
    let co = derive(&model, Variables::CoEnergy);
    assert_eq!(state_names(&co), ["v_mass1", "f_spring"]);
    assert_symbolic(
        &model,
        "A",
        &co.a(),
        &[&["-b/(m1 + m2)", "-1/(m1 + m2)"], &["k", "0"]],
    );
    assert_symbolic(&model, "B", &co.b(), &[&["1/(m1 + m2)"], &["0"]]);

    // The force the spring-side of the junction puts into the second mass is its share of
    // the acceleration: e2 = m2 dv/dt = m2 (F - k q - b v)/M.
    let spec = OutputSpec::parse(&model, "effort:mass2").unwrap();
    let out = eq.output(&spec);
    use bondgraph_core::linear::Var;
    assert_eq!(
        out.row.coefficient(Var::Input(0)),
        expected(&model, "m2/(m1 + m2)")
    );
    assert_eq!(
        out.row.coefficient(Var::State(1)),
        expected(&model, "-k*m2/(m1 + m2)")
    );
    assert_eq!(
        out.row.coefficient(Var::State(0)),
        expected(&model, "-b*m2/(m1 + m2)^2")
    );
}

#[test]
fn series_dampers_loop_is_solved() {
    // Both dampers carry the same force f; their velocities add to the mass's v = p/m:
    //   f/b1 + f/b2 = v  =>  f = b1 b2/(b1 + b2) v
    //   dp/dt = F - f = -(b1 b2/(m (b1 + b2))) p + F
    let model = load("models/examples/series_dampers.ron");
    let eq = derive(&model, Variables::Energy);
    assert_eq!(state_names(&eq), ["p_mass"]);
    assert!(eq.notes.iter().any(|n| matches!(
        n,
        Note::AlgebraicLoop { elements, .. } if elements.contains(&"damper1".to_string())
            && elements.contains(&"damper2".to_string())
    )));
    assert_symbolic(&model, "A", &eq.a(), &[&["-b1*b2/(m*(b1 + b2))"]]);
    assert_symbolic(&model, "B", &eq.b(), &[&["1"]]);
    let (m, b1, b2) = (value(&model, "m"), value(&model, "b1"), value(&model, "b2"));
    let (a, _) = values(&eq);
    assert_numeric("A", &a, &[&[-b1 * b2 / (m * (b1 + b2))]]);

    // The first damper moves at f/b1 = b2/(b1 + b2) v.
    let spec = OutputSpec::parse(&model, "flow:damper1").unwrap();
    let out = eq.output(&spec);
    assert_eq!(
        out.row.coefficient(bondgraph_core::linear::Var::State(0)),
        expected(&model, "b2/(m*(b1 + b2))")
    );
}

#[test]
fn every_example_is_tested_here() {
    // A new example must come with its hand derivation above.
    let tested = [
        "belt_friction",
        "dc_motor",
        "mass_spring_damper",
        "rigid_masses",
        "rlc",
        "series_dampers",
        "tank_pipe",
        "two_masses",
    ];
    let files = crate::support::ron_files("models/examples");
    let names: Vec<String> = files
        .iter()
        .map(|f| {
            std::path::Path::new(f)
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    for name in &names {
        assert!(
            tested.contains(&name.as_str()),
            "models/examples/{name}.ron has no hand-derived test"
        );
    }
}

#[test]
fn belt_friction_modes_and_guards() {
    use bondgraph_core::equations::Options;
    use bondgraph_core::guards::{Crossing, Watched};
    use bondgraph_core::linear::{LinearForm, Var};
    use bondgraph_core::model::ElementMode;
    use bondgraph_core::modes::{self, Mode};

    // The contact carries v_rel = v_belt - v_block; its force e drags the block:
    //   m dv/dt = e - k q,   dq/dt = v.
    let model = load("models/examples/belt_friction.ron");
    let derive = |spec: &str| {
        let mode = Mode::parse(&model, spec).unwrap();
        modes::derive(&model, &mode, &Options::default()).unwrap()
    };
    let friction = model.element_named("friction").unwrap();
    let e = |text: &str| expected(&model, text);

    // Stuck: the block rides with the belt (v = v_belt, no momentum state), the spring
    // stretches at v_belt, and the contact holds e = m dv_belt/dt + k q.
    let stuck = derive("friction=stuck");
    assert_eq!(state_names(&stuck.equations), ["q_spring"]);
    assert_symbolic(&model, "A", &stuck.equations.a(), &[&["0"]]);
    assert_symbolic(&model, "B", &stuck.equations.b(), &[&["1"]]);
    let hold = &stuck.guards[0].quantity;
    assert_eq!(hold.coefficient(Var::State(0)), e("k"));
    assert_eq!(hold.coefficient(Var::InputRate(0)), e("m"));
    assert_eq!(hold.terms().len(), 2);
    assert_eq!(stuck.guards.len(), 2);
    for (guard, crossing, threshold, to) in [
        (
            &stuck.guards[0],
            Crossing::Rises,
            "F_S",
            ElementMode::SlipPositive,
        ),
        (
            &stuck.guards[1],
            Crossing::Falls,
            "-F_S",
            ElementMode::SlipNegative,
        ),
    ] {
        assert_eq!(guard.element, friction);
        assert_eq!(guard.watched, Watched::HoldingForce);
        assert_eq!(&guard.quantity, hold);
        assert_eq!(guard.crossing, crossing);
        assert_eq!(guard.threshold, LinearForm::constant(e(threshold)));
        assert_eq!(guard.leaves_to, to);
        assert!(!guard.requires_hold);
    }

    // Slipping (no viscous part): e = ±F_C, so dp/dt = ±F_C - k q and dq/dt = p/m.
    for (spec, coulomb, crossing, reverse) in [
        (
            "friction=slip+",
            "F_C",
            Crossing::Falls,
            ElementMode::SlipNegative,
        ),
        (
            "friction=slip-",
            "-F_C",
            Crossing::Rises,
            ElementMode::SlipPositive,
        ),
    ] {
        let slip = derive(spec);
        assert_eq!(
            state_names(&slip.equations),
            ["p_block", "q_spring"],
            "{spec}"
        );
        assert_symbolic(
            &model,
            "A",
            &slip.equations.a(),
            &[&["0", "-k"], &["1/m", "0"]],
        );
        assert_symbolic(&model, "B", &slip.equations.b(), &[&["0"], &["0"]]);
        assert_symbolic(&model, "c", &[slip.equations.c()], &[&[coulomb, "0"]]);
        // Its relative velocity v_belt - p/m reaching zero (the dead band is zero) ends it:
        // stuck if static friction can then hold, else slipping the other way.
        let velocity = &slip.guards[0].quantity;
        assert_eq!(velocity.coefficient(Var::State(0)), e("-1/m"));
        assert_eq!(velocity.coefficient(Var::Input(0)), e("1"));
        assert_eq!(velocity.terms().len(), 2);
        assert_eq!(slip.guards.len(), 2);
        assert_eq!(slip.guards[0].leaves_to, ElementMode::Stuck);
        assert!(slip.guards[0].requires_hold);
        assert_eq!(slip.guards[1].leaves_to, reverse);
        assert!(!slip.guards[1].requires_hold);
        for guard in &slip.guards {
            assert_eq!(guard.watched, Watched::RelativeVelocity);
            assert_eq!(guard.crossing, crossing);
            assert!(guard.threshold.is_zero());
        }
    }

    // Every mode is reachable from the initial (stuck) one.
    let reachable = modes::reachable(&model, &Options::default()).unwrap();
    let specs: Vec<String> = reachable
        .modes
        .iter()
        .map(|m| m.mode.spec(&model))
        .collect();
    assert_eq!(
        specs,
        ["friction=stuck", "friction=slip+", "friction=slip-"]
    );
    assert!(reachable.impossible.is_empty());
}
