//! Units checked on whole model files: each case is a small model whose expected verdict
//! (and line, and the units named) is worked out by hand in its comment.

use bondgraph_core::diagnostics::{DiagnosticKind, Diagnostics};

fn rejected(text: &str) -> Diagnostics {
    match crate::model::load_str("units.ron", text) {
        Ok(_) => panic!("the model should be rejected"),
        Err(error) => error,
    }
}

#[test]
fn an_unknown_unit_is_named_at_its_parameter_line() {
    let error = rejected(
        r#"Model(name: "u",
    parameters: {
        "m": (value: 1.0, unit: "kg"),
        "b": (value: 1.0, unit: "N*s/furlong"),
    },
    elements: {"push": Se(effort: "1"), "j": One, "mass": I(inertance: "m"), "damper": R(resistance: "b")},
    bonds: [("push", "j"), ("j", "mass"), ("j", "damper")])"#,
    );
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnknownUnit);
    assert_eq!(first.location.as_ref().unwrap().line, 4);
    assert_eq!(first.element.as_deref(), Some("b"));
    assert_eq!(
        first.message,
        "parameter 'b' has unit \"N*s/furlong\": unknown unit 'furlong'"
    );
}

/// A mass-spring-damper pushed by a force `F` (N): `spring` and `push` are filled in.
fn msd(push: &str, spring: &str) -> String {
    format!(
        r#"Model(name: "msd",
    parameters: {{
        "m_s": (value: 2.0, unit: "kg"),
        "k": (value: 200.0, unit: "N/m"),
        "b": (value: 4.0, unit: "N*s/m"),
    }},
    inputs: {{"F": (unit: "N"), "v_r": (unit: "m/s")}},
    elements: {{
        "push": Se(effort: "{push}"),
        "v": One,
        "mass": I(inertance: "m_s"),
        "spring": C(stiffness: "{spring}"),
        "damper": R(resistance: "b"),
    }},
    bonds: [("push", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])"#
    )
}

#[test]
fn the_mass_spring_damper_with_consistent_units_passes() {
    crate::model::load_str("msd.ron", &msd("F", "k")).unwrap();
}

#[test]
fn a_mass_used_as_a_stiffness_is_named_at_its_line_with_both_units() {
    // Se F in N, so the 1-junction's flow is W/N = m/s; m_s in kg fits the inertia
    // (N*s/(m/s) = kg); a stiffness on that bond needs N/(m/s*s) = N/m.
    let error = rejected(&msd("F", "m_s"));
    assert_eq!(error.0.len(), 1, "{error}");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnitMismatch);
    assert_eq!(first.location.as_ref().unwrap().line, 12);
    assert_eq!(first.element.as_deref(), Some("spring"));
    assert_eq!(
        first.message,
        "compliance 'spring': stiffness 'm_s' is in kg but a C on a mechanical translational bond needs N/m"
    );
}

#[test]
fn a_velocity_used_as_a_force_is_named_at_the_source() {
    let error = rejected(&msd("v_r", "k"));
    assert_eq!(error.0.len(), 1, "{error}");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnitMismatch);
    assert_eq!(first.location.as_ref().unwrap().line, 9);
    assert_eq!(first.element.as_deref(), Some("push"));
    assert!(
        first
            .message
            .starts_with("effort source 'push': effort 'v_r' is in m/s, a velocity, where an Se needs an effort: force (N)"),
        "{}",
        first.message
    );
}

#[test]
fn adding_a_force_to_a_velocity_in_a_law_is_named_at_the_sum() {
    // b*v_r is N*s/m * m/s = N; adding v_r (m/s) to it is not.
    let error = rejected(&msd("b*v_r + v_r", "k"));
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnitMismatch);
    assert_eq!(first.location.as_ref().unwrap().line, 9);
    assert_eq!(
        first.message,
        "effort source 'push': 'b*v_r + v_r' adds N (b*v_r) and m/s (v_r), which are different quantities"
    );
    // The column is the sum's own (the expression starts after `Se(effort: "`).
    assert_eq!(first.location.as_ref().unwrap().column, 29);
}

#[test]
fn parameters_without_units_are_not_checked() {
    // No unit on any parameter: nothing is known, nothing is rejected.
    let text = msd("F", "k")
        .replace(r#", unit: "kg""#, "")
        .replace(r#", unit: "N/m""#, "");
    crate::model::load_str("msd.ron", &text).unwrap();
    // A bare number in a source is a number without a unit, not a dimensionless effort.
    crate::model::load_str("msd.ron", &msd("1", "k")).unwrap();
}

/// A torque `tau` (N*m) on a pinion of radius `r` (m) driving a rack of mass `m`:
/// `TF(ratio: "r")`, `e_in = r e_out`: the rack's force is torque/r (N), its velocity
/// r times the pinion's angular velocity (m/s).
fn rack(mass_unit: &str) -> String {
    format!(
        r#"Model(name: "rack",
    parameters: {{"r": (value: 0.05, unit: "m"), "m": (value: 2.0, unit: "{mass_unit}"),
                 "J": (value: 0.01, unit: "kg*m^2")}},
    inputs: {{"tau": (unit: "N*m")}},
    elements: {{
        "motor": Se(effort: "tau"), "shaft": One, "pinion": I(inertance: "J"),
        "gear": TF(ratio: "r"), "slide": One,
        "rack": I(inertance: "m"),
    }},
    bonds: [("motor", "shaft"), ("shaft", "pinion"), ("shaft", "gear"), ("gear", "slide"), ("slide", "rack")])"#
    )
}

#[test]
fn a_transformer_carries_dimensions_from_rotation_to_translation() {
    crate::model::load_str("rack.ron", &rack("kg")).unwrap();
    // The rack's bond is translational only through the TF: a rotational inertia there is
    // wrong.
    let error = rejected(&rack("kg*m^2"));
    assert_eq!(error.0.len(), 1, "{error}");
    assert_eq!(error.first().location.as_ref().unwrap().line, 8);
    assert_eq!(
        error.first().message,
        "inertia 'rack': inertance 'm' is in kg*m^2 but an I on a mechanical translational bond needs kg"
    );
}

/// A DC motor: a voltage `u` (V) through the armature resistance `R_a` (ohm) and a gyrator
/// of motor constant `K_m` (N*m/A): `e_out = K_m f_in`, a torque N*m/A * A = N*m on the
/// rotor of inertia `J`.
fn motor(inertia_unit: &str, friction_unit: &str) -> String {
    format!(
        r#"Model(name: "motor",
    parameters: {{"R_a": (value: 1.0, unit: "ohm"), "L_a": (value: 0.01, unit: "H"),
                 "K_m": (value: 0.05, unit: "N*m/A"), "J": (value: 0.01, unit: "{inertia_unit}"),
                 "b": (value: 0.001, unit: "{friction_unit}")}},
    inputs: {{"u": (unit: "V")}},
    elements: {{
        "supply": Se(effort: "u"), "armature": One, "resistance": R(resistance: "R_a"),
        "inductance": I(inertance: "L_a"), "motor": GY(ratio: "K_m"), "rotor": One,
        "inertia": I(inertance: "J"), "bearing": R(resistance: "b"),
    }},
    bonds: [("supply", "armature"), ("armature", "resistance"), ("armature", "inductance"),
            ("armature", "motor"), ("motor", "rotor"), ("rotor", "inertia"), ("rotor", "bearing")])"#
    )
}

#[test]
fn a_gyrator_carries_dimensions_from_the_circuit_to_the_shaft() {
    crate::model::load_str("motor.ron", &motor("kg*m^2", "N*m*s/rad")).unwrap();
    let error = rejected(&motor("kg*m^2", "N*s/m"));
    assert_eq!(error.0.len(), 1, "{error}");
    assert_eq!(error.first().location.as_ref().unwrap().line, 9);
    assert_eq!(
        error.first().message,
        "resistor 'bearing': resistance 'b' is in N*s/m but an R on a mechanical rotational bond needs N*m*s/rad"
    );
    let error = rejected(&motor("kg", "N*m*s/rad"));
    assert_eq!(
        error.first().message,
        "inertia 'inertia': inertance 'J' is in kg but an I on a mechanical rotational bond needs kg*m^2"
    );
}

#[test]
fn a_bond_whose_effort_times_flow_is_no_power_is_named() {
    // A force (N) and a current (A) on one 1-junction: N*A is no power.
    let error = rejected(
        r#"Model(name: "odd",
    parameters: {"R": (value: 1.0)},
    inputs: {"F": (unit: "N"), "i": (unit: "A")},
    elements: {"push": Se(effort: "F"), "j": One, "pump": Sf(flow: "i"), "r": R(resistance: "R")},
    bonds: [("push", "j"), ("pump", "j"), ("j", "r")])"#,
    );
    assert_eq!(error.first().kind, DiagnosticKind::UnitMismatch);
    assert_eq!(error.first().location.as_ref().unwrap().line, 5);
    assert!(
        error
            .first()
            .message
            .starts_with("bond push -> j carries an effort in N and a flow in A"),
        "{}",
        error.first().message
    );
}

#[test]
fn a_thermal_pseudo_bond_graph_passes_though_temperature_times_heat_flow_is_no_power() {
    crate::model::load_str(
        "thermal.ron",
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/fixtures/units/thermal.ron"
        ))
        .unwrap(),
    )
    .unwrap();
}

/// A linear-graph mass-spring-damper; `spring` is the T-type's stiffness parameter.
fn lg_msd(spring: &str) -> String {
    format!(
        r#"LinearGraph(name: "msd",
    parameters: {{"m": (value: 2.0, unit: "kg"), "k": (value: 200.0, unit: "N/m"), "b": (value: 4.0, unit: "N*s/m")}},
    inputs: {{"F": (unit: "N")}},
    ground: "g",
    branches: {{
        "force": ThroughSource(value: "F", from: "g", to: "v1"),
        "mass": A(capacitance: "m", from: "v1", to: "g"),
        "spring": T(stiffness: "{spring}", from: "v1", to: "g"),
        "damper": D(conductance: "b", from: "v1", to: "g"),
    }})"#
    )
}

#[test]
fn a_linear_graph_is_checked_through_its_bond_graph() {
    crate::model::load_str("msd.lg.ron", &lg_msd("k")).unwrap();
    let error = rejected(&lg_msd("m"));
    assert_eq!(error.0.len(), 1, "{error}");
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::UnitMismatch);
    assert_eq!(first.location.as_ref().unwrap().line, 8);
    assert!(
        first.message.contains("stiffness 'm' is in kg but")
            && first.message.ends_with("needs N/m"),
        "{}",
        first.message
    );
}

/// An electrical linear graph: the through variable (current) is the bond graph's effort,
/// so a current source is plausible and a voltage source's value must be a voltage.
#[test]
fn a_linear_graph_circuit_takes_currents_as_through_variables() {
    let circuit = |source_unit: &str| {
        format!(
            r#"LinearGraph(name: "rc",
    parameters: {{"R": (value: 1000.0, unit: "ohm"), "C": (value: 1e-6, unit: "F")}},
    inputs: {{"u": (unit: "{source_unit}")}},
    ground: "g",
    branches: {{
        "supply": AcrossSource(value: "u", from: "a", to: "g"),
        "resistor": D(resistance: "R", from: "a", to: "b"),
        "capacitor": A(capacitance: "C", from: "b", to: "g"),
    }})"#
        )
    };
    crate::model::load_str("rc.lg.ron", &circuit("V")).unwrap();
    let error = rejected(&circuit("A"));
    let first = error.first();
    assert_eq!(first.location.as_ref().unwrap().line, 6, "{error}");
    assert!(
        first.message.contains("'u' is in A, a current"),
        "{}",
        first.message
    );
}

// ---------------------------------------------------------------------------------------
// Scaled units: a value written beside a unit is in that unit, and is read into SI.
// ---------------------------------------------------------------------------------------

/// The value of parameter `x` written as `value` in `unit`, as the model holds it (SI).
fn si_value(value: &str, unit: &str) -> f64 {
    let text = format!(
        r#"Model(name: "scaled",
    parameters: {{"m": (value: 2.0, unit: "kg"), "x": (value: {value}, unit: "{unit}")}},
    inputs: {{"F": (unit: "N")}},
    elements: {{"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m")}},
    bonds: [("force", "v"), ("v", "mass")])"#
    );
    let model =
        crate::model::load_str("scaled.ron", &text).unwrap_or_else(|e| panic!("{unit}: {e}"));
    model.parameters()[1].value
}

/// Every SI prefix, on the metre, the gram and the pascal, against its power of ten as
/// the SI brochure (9th edition, table 7) defines it; the gram's base is 1e-3 kg.
#[test]
fn every_prefix_scales_a_value_by_its_power_of_ten() {
    let prefixes = [
        ("Y", 1e24),
        ("Z", 1e21),
        ("E", 1e18),
        ("P", 1e15),
        ("T", 1e12),
        ("G", 1e9),
        ("M", 1e6),
        ("k", 1e3),
        ("h", 1e2),
        ("da", 1e1),
        ("d", 1e-1),
        ("c", 1e-2),
        ("m", 1e-3),
        ("u", 1e-6),
        ("µ", 1e-6),
        ("μ", 1e-6),
        ("n", 1e-9),
        ("p", 1e-12),
        ("f", 1e-15),
        ("a", 1e-18),
        ("z", 1e-21),
        ("y", 1e-24),
    ];
    for (prefix, power) in prefixes {
        assert_eq!(si_value("1.0", &format!("{prefix}m")), power, "{prefix}m");
        assert_eq!(si_value("1.0", &format!("{prefix}Pa")), power, "{prefix}Pa");
        // The gram: 1e-3 kg, so a prefixed gram is power/1000 kg (the literal is the
        // correctly rounded value of the exact product).
        let gram = si_value("1.0", &format!("{prefix}g"));
        let expected: f64 = format!("1e{}", power.log10().round() as i32 - 3)
            .parse()
            .unwrap();
        assert_eq!(gram, expected, "{prefix}g");
    }
}

/// Every scaled symbol the unit names accept, against its SI definition by hand.
#[test]
fn every_scaled_symbol_converts_by_its_hand_factor() {
    use std::f64::consts::PI;
    let cases = [
        ("g", 1e-3),       // gram, kg
        ("t", 1000.0),     // tonne, kg
        ("min", 60.0),     // s
        ("h", 3600.0),     // s
        ("L", 1e-3),       // litre, m^3
        ("l", 1e-3),       // litre, m^3
        ("bar", 1e5),      // Pa
        ("atm", 101325.0), // Pa
        ("Wh", 3600.0),    // J
        ("rpm", 2.0 * PI / 60.0),
        ("rev", 2.0 * PI),
        ("deg", PI / 180.0),
        ("°", PI / 180.0),
        ("%", 0.01),
        // Coherent SI units: factor 1.
        ("kg", 1.0),
        ("N", 1.0),
        ("rad", 1.0),
        ("Hz", 1.0),
        ("ohm", 1.0),
        ("Ω", 1.0),
        ("K", 1.0),
        // Prefixed scaled units.
        ("mL", 1e-6),
        ("kWh", 3.6e6),
        ("mbar", 100.0),
        ("hPa", 100.0),
        ("ms", 1e-3),
        ("kΩ", 1e3),
        ("mrad", 1e-3),
    ];
    for (unit, factor) in cases {
        assert_eq!(si_value("1.0", unit), factor, "{unit}");
    }
}

/// Factors compose through products, quotients, powers and parentheses.
#[test]
fn composed_units_convert_by_the_product_of_their_factors() {
    // 1 L/min = 1e-3 m^3 / 60 s; 1 g*cm^2 = 1e-3 kg * (1e-2 m)^2.
    assert_eq!(si_value("1.0", "L/min"), 1.0 / 60000.0);
    assert_eq!(si_value("0.2", "N/mm"), 200.0);
    assert_eq!(si_value("1.0", "N/mm"), 1000.0);
    assert_eq!(si_value("101.325", "kPa"), 101325.0);
    assert_eq!(si_value("1.0", "g*cm^2"), 1e-7);
    assert_eq!(si_value("1.0", "kN*s/m"), 1000.0);
    assert_eq!(si_value("1.0", "1/min"), 1.0 / 60.0);
    assert_eq!(si_value("1.0", "kg/(m*min)"), 1.0 / 60.0);
    assert_eq!(si_value("1.0", "mm^2"), 1e-6);
    assert_eq!(si_value("1.0", "cm³"), 1e-6);
    assert_eq!(si_value("1.0", "s⁻¹"), 1.0);
    assert_eq!(si_value("1.0", "mm^-1"), 1000.0);
    assert_eq!(si_value("1.0", "N*m/rpm"), 30.0 / std::f64::consts::PI);
    // Fractional powers: (1e-3 m)^(1/2) and (1e3 Pa)^(1/2); the root is the one inexact
    // step, so within two units in the last place.
    let close = |a: f64, b: f64| (a - b).abs() <= 2.0 * f64::EPSILON * b.abs();
    assert!(close(si_value("1.0", "mm^(1/2)"), 1e-3_f64.sqrt()));
    assert!(close(si_value("1.0", "kPa^0.5"), 1e3_f64.sqrt()));
    assert!(close(si_value("1.0", "m^3/s/kPa^0.5"), 1e-3_f64.sqrt()));
    // The value is converted exactly as written, then rounded once: 1.001 kN is the double
    // nearest 1001, as is 1001 N (the double nearest 1.001, times 1000 exactly, would
    // round to 1000.9999999999999).
    assert_eq!(si_value("1.001", "kN"), 1001.0);
    assert_eq!(si_value("-2.5", "mm"), -0.0025);
}

/// A Celsius temperature alone is offset by 273.15 K; in a compound unit `degC` is a
/// temperature difference, of the kelvin's size.
#[test]
fn a_celsius_temperature_alone_is_offset_and_in_a_compound_unit_is_a_difference() {
    assert_eq!(si_value("20.0", "degC"), 293.15);
    assert_eq!(si_value("-273.15", "°C"), 0.0);
    assert_eq!(si_value("4186.0", "J/(kg*degC)"), 4186.0);
    assert_eq!(si_value("2.5", "W/°C"), 2.5);
    assert_eq!(si_value("1.0", "kJ/(kg*degC)"), 1000.0);
}

#[test]
fn a_parameters_bounds_are_converted_with_its_value() {
    let model = crate::model::load_str(
        "bounds.ron",
        r#"Model(name: "b",
    parameters: {"m": (value: 2.0, unit: "kg"), "k": (value: 0.2, unit: "N/mm", bounds: (0.05, 1.5))},
    inputs: {"F": (unit: "N")},
    elements: {"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"), "spring": C(stiffness: "k")},
    bonds: [("force", "v"), ("v", "mass"), ("v", "spring")])"#,
    )
    .unwrap();
    let k = &model.parameters()[1];
    assert_eq!(k.value, 200.0);
    assert_eq!(k.bounds, Some((50.0, 1500.0)));
    assert_eq!(model.values()[k.symbol.index()], 200.0);
}

#[test]
fn a_value_too_large_once_in_si_units_is_named() {
    // 1e300 Ym^2 = 1e348 m^2: beyond the largest double (about 1.8e308).
    let error = rejected(
        r#"Model(name: "big",
    parameters: {"m": (value: 2.0, unit: "kg"), "A": (value: 1e300, unit: "Ym^2")},
    inputs: {"F": (unit: "N")},
    elements: {"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m")},
    bonds: [("force", "v"), ("v", "mass")])"#,
    );
    let first = error.first();
    assert_eq!(first.kind, DiagnosticKind::InvalidValue);
    assert_eq!(first.location.as_ref().unwrap().line, 2);
    assert_eq!(first.element.as_deref(), Some("A"));
    assert_eq!(
        first.message,
        "parameter 'A' has value 1e300 Ym^2, which is too large in SI units (m^2) for a 64-bit floating-point number"
    );
}

/// An input's values come in SI units (scenarios, experiments, `--at`): a scaled unit on an
/// input is refused at its line, naming the factor and the SI unit to declare.
#[test]
fn an_input_with_a_scaled_unit_is_refused_naming_the_factor_and_the_si_unit() {
    let with_input = |unit: &str| {
        format!(
            r#"Model(name: "tank",
    parameters: {{"A": (value: 1e-3, unit: "m^2"), "m": (value: 1.0, unit: "kg")}},
    inputs: {{
        "P_s": (unit: "{unit}"),
    }},
    elements: {{"supply": Se(effort: "A*P_s"), "v": One, "mass": I(inertance: "m")}},
    bonds: [("supply", "v"), ("v", "mass")])"#
        )
    };
    let cases = [
        ("kPa", "\"kPa\" = 1000 Pa", "Pa"),
        ("bar", "\"bar\" = 100000 Pa", "Pa"),
        ("MPa", "\"MPa\" = 1000000 Pa", "Pa"),
    ];
    for (unit, said, si) in cases {
        let error = rejected(&with_input(unit));
        assert_eq!(error.0.len(), 1, "{error}");
        let first = error.first();
        assert_eq!(first.kind, DiagnosticKind::UnknownUnit, "{unit}");
        assert_eq!(first.location.as_ref().unwrap().line, 4, "{unit}");
        assert_eq!(first.element.as_deref(), Some("P_s"));
        assert_eq!(
            first.message,
            format!(
                "input 'P_s' has unit {said}: inputs take SI values in scenarios, experiments and --at; declare it in \"{si}\""
            )
        );
    }
    // Dimensionless units with a factor, and the Celsius offset, likewise.
    let dimensionless = |unit: &str| {
        format!(
            r#"Model(name: "gain",
    parameters: {{"m": (value: 1.0, unit: "kg"), "F_0": (value: 1.0, unit: "N")}},
    inputs: {{
        "u": (unit: "{unit}"),
    }},
    elements: {{"push": Se(effort: "F_0*u"), "v": One, "mass": I(inertance: "m")}},
    bonds: [("push", "v"), ("v", "mass")])"#
        )
    };
    assert_eq!(
        rejected(&dimensionless("%")).first().message,
        "input 'u' has unit \"%\" = 0.01 (dimensionless): inputs take SI values in scenarios, experiments and --at; declare it in \"1\""
    );
    assert_eq!(
        rejected(&dimensionless("deg")).first().message,
        "input 'u' has unit \"deg\" = 0.017453292519943295 rad: inputs take SI values in scenarios, experiments and --at; declare it in \"rad\""
    );
    let thermal = r#"Model(name: "room",
    parameters: {"C_th": (value: 500.0, unit: "J/K"), "R_th": (value: 0.1, unit: "K/W")},
    inputs: {
        "T_amb": (unit: "degC"),
    },
    elements: {"ambient": Se(effort: "T_amb"), "wall_drop": One, "wall": R(resistance: "R_th"),
               "body_temperature": Zero, "body": C(compliance: "C_th")},
    bonds: [("ambient", "wall_drop"), ("wall_drop", "wall"), ("wall_drop", "body_temperature"),
            ("body_temperature", "body")])"#;
    assert_eq!(
        rejected(thermal).first().message,
        "input 'T_amb' has unit \"degC\" = K - 273.15: inputs take SI values in scenarios, experiments and --at; declare it in \"K\""
    );
    // An input in a coherent SI unit passes.
    crate::model::load_str("tank.ron", &with_input("Pa")).unwrap();
    crate::model::load_str("tank.ron", &with_input("N/m^2")).unwrap();
}

// ---------------------------------------------------------------------------------------
// Which law is blamed, a linear graph's words, decimal powers.
// ---------------------------------------------------------------------------------------

/// A half car: heave and pitch of one body, the front and rear suspension points at lever
/// arms `a` (front) and `b` (rear) from the centre of mass: `TF(ratio: "a")` from the pitch
/// (N*m, rad/s) to the front point (N, m/s), so `a` must be a length. `front_arm_unit` is
/// the front arm's unit.
fn half_car(front_arm_unit: &str) -> String {
    format!(
        r#"Model(name: "half_car",
    parameters: {{
        "m": (value: 500.0, unit: "kg"),
        "J": (value: 800.0, unit: "kg*m^2"),
        "a": (value: 1.2, unit: "{front_arm_unit}"),
        "b": (value: 1.5, unit: "m"),
        "k_f": (value: 2e4, unit: "N/m"),
        "k_r": (value: 2e4, unit: "N/m"),
    }},
    inputs: {{"v_f": (unit: "m/s"), "v_r": (unit: "m/s")}},
    elements: {{
        "heave": One,
        "body": I(inertance: "m"),
        "pitch": One,
        "inertia": I(inertance: "J"),
        "front_arm": TF(ratio: "a"),
        "rear_arm": TF(ratio: "b"),
        "front": Zero,
        "rear": Zero,
        "front_spring": C(stiffness: "k_f"),
        "rear_spring": C(stiffness: "k_r"),
        "road_f": Sf(flow: "v_f"),
        "road_r": Sf(flow: "v_r"),
    }},
    bonds: [("heave", "body"), ("pitch", "inertia"),
            ("pitch", "front_arm"), ("front_arm", "front"),
            ("pitch", "rear_arm"), ("rear_arm", "rear"),
            ("heave", "front"), ("heave", "rear"),
            ("front", "front_spring"), ("rear", "rear_spring"),
            ("road_f", "front"), ("road_r", "rear")])"#
    )
}

#[test]
fn a_wrong_front_lever_arm_is_blamed_on_the_front_arm() {
    crate::model::load_str("half_car.ron", &half_car("m")).unwrap();
    for wrong in ["1", "m^2", "kg"] {
        let error = rejected(&half_car(wrong));
        assert_eq!(error.0.len(), 1, "{wrong}: {error}");
        let first = error.first();
        assert_eq!(first.kind, DiagnosticKind::UnitMismatch);
        assert_eq!(
            first.element.as_deref(),
            Some("front_arm"),
            "{wrong}: {error}"
        );
        assert_eq!(first.location.as_ref().unwrap().line, 16, "{wrong}");
        assert_eq!(
            first.message,
            format!(
                "transformer 'front_arm': ratio 'a' is in {wrong} but a TF between these bonds needs m"
            )
        );
    }
}

/// A tank filled by a pump and drained through a valve, as a linear graph: `tank` is an
/// A-type whose capacitance is in `capacitance_unit` (m^3/Pa is right).
fn lg_tank(capacitance_unit: &str, pump: &str) -> String {
    format!(
        r#"LinearGraph(name: "tank",
    parameters: {{"C_h": (value: 1e-6, unit: "{capacitance_unit}"), "R_h": (value: 1e8, unit: "Pa*s/m^3")}},
    inputs: {{"Q": (unit: "m^3/s"), "P": (unit: "Pa")}},
    ground: "g",
    branches: {{
        "pump": ThroughSource(value: "{pump}", from: "g", to: "p"),
        "tank": A(capacitance: "C_h", from: "p", to: "g"),
        "valve": D(resistance: "R_h", from: "p", to: "g"),
    }})"#
    )
}

#[test]
fn a_linear_graphs_unit_errors_speak_its_own_words() {
    crate::model::load_str("tank.lg.ron", &lg_tank("m^3/Pa", "Q")).unwrap();
    let error = rejected(&lg_tank("kg", "Q"));
    assert_eq!(error.0.len(), 1, "{error}");
    assert_eq!(error.first().location.as_ref().unwrap().line, 7);
    assert_eq!(
        error.first().message,
        "A-type 'tank': capacitance 'C_h' is in kg but an A-type on a hydraulic branch needs m^3/Pa"
    );
    // A pressure given as the through source's value: a through source needs a flow.
    let error = rejected(&lg_tank("m^3/Pa", "P"));
    assert_eq!(error.first().location.as_ref().unwrap().line, 6, "{error}");
    let message = &error.first().message;
    assert!(
        message.starts_with(
            "through source 'pump': value 'P' is in Pa, a pressure, where a through source needs a through variable: force (N)"
        ),
        "{message}"
    );
    // The mass-spring-damper as a linear graph: a mass used as a stiffness.
    let error = rejected(&lg_msd("m"));
    assert_eq!(
        error.first().message,
        "T-type 'spring': stiffness 'm' is in kg but a T-type on a mechanical translational branch needs N/m"
    );
    for message in error.0.iter().map(|d| d.message.as_str()) {
        for word in ["inertance", "an I ", "a C ", "bond", "effort", "flow"] {
            assert!(!message.contains(word), "{word}: {message}");
        }
    }
}

#[test]
fn decimal_powers_parse_as_exact_rationals() {
    // An orifice: Q = K sqrt(P), K in m^3/(s*Pa^0.5).
    let orifice = |unit: &str| {
        format!(
            r#"Model(name: "orifice",
    parameters: {{"K": (value: 1e-6, unit: "{unit}"), "A": (value: 1e-3, unit: "m^2"), "m": (value: 1.0, unit: "kg")}},
    inputs: {{"F": (unit: "N")}},
    elements: {{"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m")}},
    bonds: [("force", "v"), ("v", "mass")])"#
        )
    };
    for unit in [
        "m^3/(s*Pa^0.5)",
        "m^3/(s*(Pa^0.5))",
        "m^3/s/Pa^(0.5)",
        "m^3*s^-1*Pa^-0.5",
        "m^1.5",
        "s^-0.5",
        "m^(1/2)",
        "m^(3/2)",
        "Pa^0.25",
    ] {
        crate::model::load_str("orifice.ron", &orifice(unit))
            .unwrap_or_else(|e| panic!("{unit}: {e}"));
    }
    let problem = |unit: &str| rejected(&orifice(unit)).first().message.clone();
    assert_eq!(
        problem("Pa^0.5.2"),
        "parameter 'K' has unit \"Pa^0.5.2\": unexpected '.2'"
    );
    assert_eq!(
        problem("Pa^1."),
        "parameter 'K' has unit \"Pa^1.\": a decimal point needs digits after it in '^1.'"
    );
    assert_eq!(
        problem("Pa^.5"),
        "parameter 'K' has unit \"Pa^.5\": a power needs a number in '^.5'"
    );
    assert_eq!(
        problem("m^0.1"),
        "parameter 'K' has unit \"m^0.1\": a power finer than twelfths cannot be kept exactly in '^0.1'"
    );
}

/// A parameter value set by an edit (a scenario's `parameters`, a fit written back) is SI;
/// it is written into the file in the parameter's own unit, so that reading it gives the
/// same SI value.
#[test]
fn an_edit_writes_an_si_value_in_the_parameters_own_unit() {
    use crate::model::edit::{self, Edit};
    let text = r#"Model(name: "msd",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "k": (value: 0.2, unit: "N/mm"),
        "Q": (value: 1.0, unit: "L/min"),
        "T": (value: 20.0, unit: "degC"),
        "w": (value: 1.0, unit: "rpm"),
    },
    inputs: {"F": (unit: "N")},
    elements: {"force": Se(effort: "F"), "v": One, "mass": I(inertance: "m"), "spring": C(stiffness: "k")},
    bonds: [("force", "v"), ("v", "mass"), ("v", "spring")])"#;
    let source = bondgraph_core::source::SourceFile::new("msd.ron", text);
    let set = [
        ("k", 250.0),
        ("Q", 1e-4),
        ("T", 300.0),
        ("w", 10.0),
        ("m", 0.1 + 0.2),
    ];
    let edit = Edit {
        remove: Vec::new(),
        parameters: set.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
    };
    let edited = edit::apply(&source, &edit).unwrap();
    // 250 N/m is 0.25 N/mm; 1e-4 m^3/s is 6 L/min; 300 K is 26.85 degC.
    assert!(
        edited
            .text()
            .contains(r#""k": (value: 0.25, unit: "N/mm")"#),
        "{}",
        edited.text()
    );
    assert!(
        edited
            .text()
            .contains(r#""Q": (value: 6.0, unit: "L/min")"#),
        "{}",
        edited.text()
    );
    assert!(
        edited
            .text()
            .contains(r#""T": (value: 26.85, unit: "degC")"#),
        "{}",
        edited.text()
    );
    let model = crate::model::load_source(&edited).unwrap();
    for (name, value) in set {
        let p = model.parameters().iter().find(|p| p.name == name).unwrap();
        assert_eq!(
            p.value.to_bits(),
            value.to_bits(),
            "{name}: {} vs {value}",
            p.value
        );
    }
}

/// Every model file of the repository (examples, teaching models, the studies' models, the test
/// fixtures) checked both ways: the closure that `check` runs first must find exactly the
/// dimensions, or the diagnostics, of the ordered schedule that was the whole check before.
#[test]
fn the_linear_closure_agrees_with_the_ordered_check_on_every_model_file() {
    use std::path::{Path, PathBuf};
    fn ron_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                ron_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "ron") {
                out.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in ["models", "tests/fixtures", "studies"] {
        ron_files(&root.join(dir), &mut files);
    }
    let load = |path: &Path, text: &str, ordered: bool| {
        bondgraph_core::model::validate::ordered_reference(ordered);
        let result = crate::model::load_str(&path.display().to_string(), text);
        bondgraph_core::model::validate::ordered_reference(false);
        result
    };
    let (mut models, mut rejected) = (0, 0);
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap();
        match (load(path, &text, false), load(path, &text, true)) {
            (Ok(closed), Ok(ordered)) => {
                assert_eq!(
                    closed.bond_dimensions(),
                    ordered.bond_dimensions(),
                    "{}",
                    path.display()
                );
                models += usize::from(closed.bond_dimensions().iter().any(|d| d.effort.is_some()));
            }
            (Err(closed), Err(ordered)) => {
                let messages = |d: &Diagnostics| -> Vec<String> {
                    d.0.iter().map(|d| d.message.clone()).collect()
                };
                assert_eq!(messages(&closed), messages(&ordered), "{}", path.display());
                rejected += usize::from(closed.first().kind == DiagnosticKind::UnitMismatch);
            }
            (closed, ordered) => panic!(
                "{}: the closure says {:?}, the ordered check {:?}",
                path.display(),
                closed.err(),
                ordered.err()
            ),
        }
    }
    // Scenario, experiment and extension files are rejected as models, alike both ways.
    assert!(
        models >= 40 && rejected >= 1,
        "{models} models with units, {rejected} rejected for their units"
    );
}
