//! The conventions of a model said in words: sources written backwards, step-ups, nodes.

use bondgraph_core::conventions::describe;
use bondgraph_ron::model::load_str;

#[test]
fn a_source_written_backwards_and_a_step_up_are_said_so() {
    let model = load_str(
        "cool.ron",
        r#"Model(name: "cool",
        parameters: {"n": (value: 4.0), "C": (value: 1.0), "R": (value: 2.0)},
        inputs: {"T_amb": (unit: "K")},
        elements: {"ambient": Se(effort: "T_amb"), "wall": Zero, "body": C(compliance: "C"),
                   "tf": TF(ratio: "n"), "loss": R(resistance: "R")},
        bonds: [("wall", "ambient"), ("wall", "body"), ("wall", "tf"), ("tf", "loss")])"#,
    )
    .unwrap();
    assert_eq!(
        describe(&model),
        [
            "Se 'ambient' imposes effort T_amb on a bond that points into it from 'wall': a \
             positive T_amb takes power out of the system (a load, not a supply); sources \
             usually point away",
            "TF 'tf' (n = 4): effort on the side of 'wall' = n × effort on the side of \
             'loss'; flow to 'loss' = n × flow from 'wall': the flow is amplified 4 times \
             and the effort reduced 4 times",
        ]
    );
}

#[test]
fn extreme_ratios_are_said_as_numbers() {
    // A lever of ratio 1e308 amplifies the flow 1e308 times (1e308 * 1000 overflowed in
    // the rounding and said "inf"); one of 1e-310 reduces it 1e310 times, beyond the
    // largest double (1/1e-310 is infinite in f64).
    for (ratio, words) in [
        (
            "1e308",
            "(r = 1e308): ".to_string()
                + "effort on the side of 'a' = r × effort on the side of 'b'; flow to 'b' = r × flow from 'a': the flow is amplified 1e308 times and the effort reduced 1e308 times",
        ),
        (
            "1e-310",
            "(r = 1e-310): ".to_string()
                + "effort on the side of 'a' = r × effort on the side of 'b'; flow to 'b' = r × flow from 'a': the flow is reduced 1e310 times and the effort amplified 1e310 times",
        ),
        (
            "123456789",
            "(r = 123456789): ".to_string()
                + "effort on the side of 'a' = r × effort on the side of 'b'; flow to 'b' = r × flow from 'a': the flow is amplified 1.235e8 times and the effort reduced 1.235e8 times",
        ),
    ] {
        let model = load_str(
            "lever.ron",
            &format!(
                r#"Model(name: "lever", parameters: {{"r": (value: {ratio}), "m": (value: 1.0)}},
                inputs: {{"F": ()}},
                elements: {{"a": Se(effort: "F"), "lever": TF(ratio: "r"), "b": I(inertance: "m")}},
                bonds: [("a", "lever"), ("lever", "b")])"#
            ),
        )
        .unwrap();
        let lines = describe(&model);
        assert_eq!(lines[1], format!("TF 'lever' {words}"));
    }
}

#[test]
fn a_linear_graph_speaks_of_nodes() {
    let model = load_str(
        "rc.lg.ron",
        r#"LinearGraph(name: "rc", parameters: {"R": (value: 1.0), "C": (value: 1.0)},
        inputs: {"V": (unit: "V"), "I": (unit: "A")}, ground: "g",
        branches: {"supply": AcrossSource(value: "V", from: "a", to: "g"),
                   "r": D(resistance: "R", from: "a", to: "b"),
                   "c": A(capacitance: "C", from: "b", to: "g"),
                   "inject": ThroughSource(value: "I", from: "g", to: "b")})"#,
    )
    .unwrap();
    assert_eq!(
        describe(&model),
        [
            "AcrossSource 'supply' imposes v_a - v_g = V: a positive V holds 'a' above 'g'",
            "ThroughSource 'inject' drives I from 'g' to 'b' through itself: a positive I \
             flows into node 'b'",
        ]
    );
}
