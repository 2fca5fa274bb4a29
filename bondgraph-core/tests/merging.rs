//! Merging dependent storage into many states at once.
//!
//! Rowell & Wormley's dependent spring with `n` springs in parallel: a force source `F`
//! pushes a massless node held to the ground by spring `K2`, and `n` springs of stiffness
//! `K1` join the node to a mass `m` (damped by `B`). `K2` is in the normal tree, so it is
//! dependent storage following all `n` spring forces: one group of `n` states with one
//! dependent. By hand (continuity at the node, `f_K2 = F - Σ f_i`, so
//! `v_node = (dF/dt - Σ df_i/dt)/K2`, and `df_i/dt = K1 (v_node - v_mass)`): summing,
//! `Σ df_i/dt = n K1 (dF/dt/K2 - v_mass)/(1 + n K1/K2)`, and each spring
//! `df_i/dt = -K1 K2/(K2 + n K1) v_mass + K1/(K2 + n K1) dF/dt`; the mass
//! `m dv_mass/dt = Σ f_i - B v_mass`. With `n = 1` this is the book's Example 5.9.

use bondgraph_core::equations::{self, Options, Variables};
use bondgraph_core::laws;
use bondgraph_core::model::Model;
use bondgraph_core::symbolic::RatFunc;

fn parallel_springs(n: usize) -> Model {
    let mut branches = vec![
        r#""F": ThroughSource(value: "F", from: "g", to: "node")"#.to_string(),
        r#""mass": A(capacitance: "m", from: "m", to: "g")"#.to_string(),
        r#""B": D(conductance: "B", from: "m", to: "g")"#.to_string(),
        r#""K2": T(stiffness: "K2", from: "node", to: "g")"#.to_string(),
    ];
    branches
        .extend((1..=n).map(|i| format!(r#""S{i}": T(stiffness: "K1", from: "node", to: "m")"#)));
    let text = format!(
        r#"LinearGraph(name: "parallel_springs",
            parameters: {{"m": (value: 2.0), "B": (value: 8.0), "K1": (value: 300.0), "K2": (value: 100.0)}},
            inputs: {{"F": ()}},
            ground: "g",
            branches: {{ {} }})"#,
        branches.join(",\n")
    );
    bondgraph_ron::model::load_str("parallel_springs.lg.ron", &text)
        .unwrap_or_else(|e| panic!("{e}"))
}

fn symbol(model: &Model, name: &str) -> RatFunc {
    RatFunc::symbol(model.symbols().get(name).expect("parameter"))
}

/// Eighty springs, in co-energy variables (a linear graph's): every entry by hand. Merging
/// inverted the group's dense 80×80 storage matrix and the co-energy change multiplied
/// dense matrices (`O(n³)` symbolic operations: 34 s in a release build); the storage
/// matrix is now kept as diagonal plus one rank-one term per dependent.
#[test]
fn eighty_parallel_springs_after_a_dependent_one_merge_exactly() {
    let n = 80;
    let model = parallel_springs(n);
    let options = Options {
        variables: Variables::CoEnergy,
    };
    let eq = equations::derive(&model, &laws::plain_laws(&model), &options)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(eq.state_count(), n + 1);
    assert_eq!(eq.states[0].name, "v_mass");
    assert_eq!(eq.states[1].merged, ["K2"]);
    let (m, b, k1, k2) = (
        symbol(&model, "m"),
        symbol(&model, "B"),
        symbol(&model, "K1"),
        symbol(&model, "K2"),
    );
    let denominator = &k2 + &(&RatFunc::integer(n as i64) * &k1);
    let spring_on_mass = -(&k1 * &k2).checked_div(&denominator).unwrap();
    let spring_on_rate = k1.checked_div(&denominator).unwrap();
    let (a, e) = (eq.a(), eq.e());
    assert_eq!(a[0][0], -b.checked_div(&m).unwrap());
    for i in 1..=n {
        assert_eq!(a[0][i], m.inv().unwrap(), "A[v_mass][f_S{i}]");
        assert_eq!(a[i][0], spring_on_mass, "A[f_S{i}][v_mass]");
        for (j, entry) in a[i].iter().enumerate().skip(1) {
            assert!(entry.is_zero(), "A[f_S{i}][f_S{j}] = {entry:?}");
        }
        assert_eq!(e[i][0], spring_on_rate, "E[f_S{i}]");
    }
    assert!(e[0][0].is_zero());
    assert!(eq.b().iter().all(|row| row[0].is_zero()));
}
