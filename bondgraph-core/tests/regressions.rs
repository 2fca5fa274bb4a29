//! Minimal cases of library defects found by the property tests in [`crate::jacobian`],
//! kept as regression tests once fixed.
//!
//! # Causality assignment of degenerate junction structures
//!
//! A cycle of junctions (and transformers or gyrators) whose loop gain is not one fixes an
//! effort or a flow by itself: two bonds from a 1-junction into the same 0-junction force
//! that 0-junction's effort `E` to satisfy `E + E = 0`; a bond and a transformer of ratio
//! `n ≠ 1` in parallel between two 0-junctions force `E = n E`. Such a cycle acts as a
//! hidden zero source. The equations are regular, a valid causality exists, and
//! elimination solves the cycle as an algebraic loop. `causality::assign` used to commit
//! its arbitrary choices greedily and report a false `CausalConflict` (and whether it did
//! depended on the order of the bonds); it now searches its choices depth-first and undoes
//! the ones that lead to a conflict.

use bondgraph_core::causality::{Causality, Stroke};
use bondgraph_core::equations::{self, Note, Options};
use bondgraph_core::laws;
use bondgraph_core::linear::Var;
use bondgraph_core::model::{BondId, Model};
use bondgraph_core::symbolic::RatFunc;

/// A mass and a damper on a 0-junction whose effort is shorted by a 1-junction bonded to it
/// twice, both bonds pointing the same way: the 1-junction's efforts sum to `E + E = 0`.
const SHORTED_JUNCTION: &str = r#"Model(
    name: "shorted_junction",
    parameters: { "m": (value: 2.0), "b": (value: 3.0) },
    elements: {
        "node": Zero,
        "short": One,
        "mass": I(inertance: "m"),
        "damper": R(resistance: "b"),
    },
    bonds: [("node", "short"), ("node", "short"), ("node", "mass"), ("node", "damper")],
)"#;

fn load(text: &str) -> Model {
    bondgraph_ron::model::load_str("regression.ron", text).unwrap_or_else(|e| panic!("{e}"))
}

fn symbol(model: &Model, name: &str) -> RatFunc {
    RatFunc::symbol(model.symbols().get(name).expect("parameter"))
}

/// By hand: the node's effort is `E = 0`, so `dp/dt = E = 0`; the mass's flow `p/m` leaves
/// the node with the short's common flow `F` on both short bonds, `-2F - p/m - E/b = 0`,
/// so `F = -p/(2m)`.
#[test]
fn scap_finds_the_causality_of_a_shorted_junction() {
    let model = load(SHORTED_JUNCTION);
    let eq = equations::derive(&model, &laws::plain_laws(&model), &Options::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(eq.a(), vec![vec![RatFunc::zero()]]);
    assert_eq!(eq.c(), vec![RatFunc::zero()]);
}

/// The causality `assign` must find exists, and elimination derives the right equations
/// from it by hand-assigned strokes too.
///
/// The mass takes its effort (integral causality), the damper too (conductance causality);
/// the node takes its effort from the short on the second bond and gives it to the short
/// on the first; the short gives its effort on exactly one bond, the second. The node's
/// effort then depends on itself through the short: an algebraic loop, `E = -E`.
#[test]
fn a_hand_assigned_causality_of_the_shorted_junction_derives() {
    let model = load(SHORTED_JUNCTION);
    let causality = Causality {
        strokes: vec![Stroke::AtTo, Stroke::AtFrom, Stroke::AtTo, Stroke::AtTo],
        dependent: vec![],
        arbitrary: vec![],
    };
    let eq = equations::derive_with(
        &model,
        &laws::plain_laws(&model),
        causality,
        &Options::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(eq.a(), vec![vec![RatFunc::zero()]]);
    assert_eq!(eq.c(), vec![RatFunc::zero()]);
    assert!(
        eq.notes
            .iter()
            .any(|n| matches!(n, Note::AlgebraicLoop { .. })),
        "{:?}",
        eq.notes
    );
    let m = symbol(&model, "m");
    let flow = eq.bond_flow(BondId(0));
    let expected = RatFunc::integer(-1)
        .checked_div(&(&RatFunc::integer(2) * &m))
        .expect("non-zero");
    assert_eq!(flow.coefficient(Var::State(0)), expected);
}

/// Two 1-junctions joined three ways (a bond, a gyrator, a transformer) and driven by an
/// effort source. By hand: the bond and the transformer force the common flows to
/// `F_j = F_k = n F_j`, so both are zero (`n ≠ 1`), and the efforts follow uniquely, e.g.
/// the transformer's output effort `-(u + E0)/(1 - n)`. The equations are regular (and
/// there is no state); a greedy choice for the first free bond used to make listing the
/// gyrator's output bond last a causal conflict.
fn order_dependent(gyrator_output_first: bool) -> String {
    let gyrator_output = r#"("gy", "k"),"#;
    let rest = r#"("j", "gy"), ("j", "tf"), ("tf", "k"), ("j", "k"), ("source", "k"),"#;
    let bonds = if gyrator_output_first {
        format!("{gyrator_output} {rest}")
    } else {
        format!("{rest} {gyrator_output}")
    };
    format!(
        r#"Model(
    name: "order_dependent",
    parameters: {{ "r": (value: -0.25), "n": (value: -0.5), "E0": (value: 2.5) }},
    inputs: {{ "u": () }},
    elements: {{
        "j": One,
        "k": One,
        "gy": GY(ratio: "r"),
        "tf": TF(ratio: "n"),
        "source": Se(effort: "u + E0"),
    }},
    bonds: [{bonds}],
)"#
    )
}

/// Both bond orders describe one model and must give the same equations.
#[test]
fn bond_order_does_not_decide_whether_causality_is_found() {
    let derive = |text: &str| {
        let model = load(text);
        equations::derive(&model, &laws::plain_laws(&model), &Options::default())
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let first = derive(&order_dependent(true));
    let last = derive(&order_dependent(false));
    assert_eq!(first.a(), last.a());
    assert_eq!(first.b(), last.b());
    assert_eq!(first.c(), last.c());
}
