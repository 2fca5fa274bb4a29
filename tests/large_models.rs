//! Large models through the command line: a chain of masses joined by springs and dampers,
//! big enough that its JSON writes the matrices as their non-zero entries, checked entry by
//! entry against the chain's equations derived by hand.

use serde_json::Value;

use crate::cli::{json, scratch};

/// An `n`-mass chain: `force` pushes mass 1; spring `k_i` and damper `b_i` join masses `i`
/// and `i + 1`. Masses `m_i = 1 + i/100` kg, `k_i = 100 + i` N/m, `b_i = 0.5 + i/1000` N s/m.
fn chain(n: usize) -> String {
    let mut parameters = Vec::new();
    let mut elements = vec![r#""force": Se(effort: "F")"#.to_string()];
    let mut bonds = vec![r#"("force", "v1")"#.to_string()];
    for i in 1..=n {
        parameters.push(format!(r#""m{i}": (value: {}, unit: "kg")"#, mass(i)));
        elements.push(format!(r#""v{i}": One, "mass{i}": I(inertance: "m{i}")"#));
        bonds.push(format!(r#"("v{i}", "mass{i}")"#));
        if i < n {
            parameters.push(format!(r#""k{i}": (value: {}, unit: "N/m")"#, stiffness(i)));
            parameters.push(format!(r#""b{i}": (value: {}, unit: "N*s/m")"#, damping(i)));
            elements.push(format!(
                r#""joint{i}": Zero, "stretch{i}": One, "spring{i}": C(stiffness: "k{i}"), "damper{i}": R(resistance: "b{i}")"#
            ));
            bonds.push(format!(
                r#"("v{i}", "joint{i}"), ("joint{i}", "v{}"), ("joint{i}", "stretch{i}"), ("stretch{i}", "spring{i}"), ("stretch{i}", "damper{i}")"#,
                i + 1
            ));
        }
    }
    format!(
        "Model(name: \"chain\", parameters: {{ {} }}, inputs: {{ \"F\": (unit: \"N\") }}, elements: {{ {} }}, bonds: [ {} ])",
        parameters.join(", "),
        elements.join(", "),
        bonds.join(", ")
    )
}

fn mass(i: usize) -> f64 {
    1.0 + i as f64 / 100.0
}

fn stiffness(i: usize) -> f64 {
    100.0 + i as f64
}

fn damping(i: usize) -> f64 {
    0.5 + i as f64 / 1000.0
}

/// `A` by hand, in the order of `states`. The stretch `q_i` of spring `i` grows with
/// `v_i - v_{i+1}`, so `dq_i/dt = p_i/m_i - p_{i+1}/m_{i+1}`, and mass `i` feels
/// `k_{i-1} q_{i-1} - k_i q_i + b_{i-1} (v_{i-1} - v_i) - b_i (v_i - v_{i+1})`.
fn a_by_hand(n: usize, states: &[String]) -> Vec<Vec<f64>> {
    let at = |name: String| states.iter().position(|s| *s == name).unwrap();
    let (p, q) = (|i| at(format!("p_mass{i}")), |i| at(format!("q_spring{i}")));
    let mut a = vec![vec![0.0; states.len()]; states.len()];
    for i in 1..=n {
        if i > 1 {
            a[p(i)][q(i - 1)] += stiffness(i - 1);
            a[p(i)][p(i - 1)] += damping(i - 1) / mass(i - 1);
            a[p(i)][p(i)] -= damping(i - 1) / mass(i);
        }
        if i < n {
            a[p(i)][q(i)] -= stiffness(i);
            a[p(i)][p(i)] -= damping(i) / mass(i);
            a[p(i)][p(i + 1)] += damping(i) / mass(i + 1);
            a[q(i)][p(i)] += 1.0 / mass(i);
            a[q(i)][p(i + 1)] -= 1.0 / mass(i + 1);
        }
    }
    a
}

/// The dense rows of a sparse matrix of the document (`{shape, row, col, data}`), zeros
/// filled with `zero`.
fn expand(sparse: &Value, zero: Value) -> Vec<Vec<Value>> {
    let shape: Vec<usize> = serde_json::from_value(sparse["shape"].clone()).unwrap();
    let mut rows = vec![vec![zero; shape[1]]; shape[0]];
    let (row, col, data) = (
        sparse["row"].as_array().unwrap(),
        sparse["col"].as_array().unwrap(),
        sparse["data"].as_array().unwrap(),
    );
    assert!(row.len() == col.len() && col.len() == data.len());
    for k in 0..data.len() {
        let (i, j) = (row[k].as_u64().unwrap(), col[k].as_u64().unwrap());
        rows[i as usize][j as usize] = data[k].clone();
    }
    rows
}

fn states(document: &Value) -> Vec<String> {
    document["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_chain_of_501_states_writes_its_matrices_as_non_zeros_matching_the_hand_derivation() {
    let n = 251;
    let dir = scratch("chain-501");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("chain.ron");
    std::fs::write(&path, chain(n)).unwrap();
    let path = path.to_str().unwrap();

    let sparse = json(&[path]);
    assert_eq!(sparse["matrices"], "sparse");
    let names = states(&sparse);
    assert_eq!(names.len(), 2 * n - 1);
    // Rows of p: 3 momenta and 2 stretches inside the chain, 2 and 1 at its ends; rows of
    // q: 2 momenta. 5n - 4 + 2(n - 1) = 7n - 6 non-zeros.
    assert_eq!(sparse["A"]["data"].as_array().unwrap().len(), 7 * n - 6);
    assert_eq!(
        sparse["A"]["shape"],
        serde_json::json!([2 * n - 1, 2 * n - 1])
    );
    let expected = a_by_hand(n, &names);
    let values = expand(&sparse["A_value"], Value::from(0.0));
    for (i, (row, expected)) in values.iter().zip(&expected).enumerate() {
        for (j, (value, expected)) in row.iter().zip(expected).enumerate() {
            let value = value.as_f64().unwrap();
            assert!(
                (value - expected).abs() <= 1e-12 * expected.abs(),
                "A[{}][{}] = {value}, by hand {expected}",
                names[i],
                names[j]
            );
        }
    }
    // The first row in symbols: mass 1 feels its damper and its spring.
    let texts = expand(&sparse["A"], Value::from("0"));
    let p1 = names.iter().position(|s| s == "p_mass1").unwrap();
    let q1 = names.iter().position(|s| s == "q_spring1").unwrap();
    assert_eq!(texts[p1][p1], "-b1/m1");
    assert_eq!(texts[p1][q1], "-k1");
    // B: the force on mass 1 alone.
    assert_eq!(sparse["B"]["data"], serde_json::json!(["1"]));
    assert_eq!(sparse["B"]["row"], serde_json::json!([p1]));

    // The same document on request in rows: every entry as the triplets say.
    let dense = json(&[path, "--matrices", "dense"]);
    assert_eq!(dense["matrices"], "dense");
    assert_eq!(dense["A"], serde_json::json!(texts));
    assert_eq!(dense["A_value"], serde_json::json!(values));
    assert_eq!(
        dense["B"],
        serde_json::json!(expand(&sparse["B"], Value::from("0")))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_chain_of_499_states_keeps_its_rows_and_can_be_asked_for_non_zeros() {
    let dir = scratch("chain-499");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("chain.ron");
    std::fs::write(&path, chain(250)).unwrap();
    let path = path.to_str().unwrap();
    let dense = json(&[path]);
    assert_eq!(dense["matrices"], "dense");
    assert_eq!(dense["A"].as_array().unwrap().len(), 499);
    let sparse = json(&[path, "--matrices", "sparse"]);
    assert_eq!(
        dense["A_value"],
        serde_json::json!(expand(&sparse["A_value"], Value::from(0.0)))
    );
    let _ = std::fs::remove_dir_all(&dir);
}
