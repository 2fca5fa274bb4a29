//! Random valid bond graphs: the library's `A`, `B`, `c` against a finite-difference Jacobian
//! of the element and junction equations, assembled here independently of the library's
//! causality and elimination code.
//!
//! The pieces:
//! - [`graph_spec`](crate::random_graph::graph_spec) generates random valid bond graphs (see
//!   [`random_graph`](crate::random_graph)).
//! - [`Assembly`] writes one equation per element port law and per junction constraint over
//!   the unknowns `e_b`, `f_b` of every bond, a square linear system whose right-hand side
//!   holds the states and inputs, and solves it in `f64` by dense Gaussian elimination with
//!   partial pivoting, giving the state derivatives `F(x, u)`.
//! - [`check_case`] loads the RON text, derives the equations, differentiates `F`
//!   numerically and compares, in energy and in co-energy variables.
//! - A second property lists the bonds of each graph in a random order and expects
//!   structurally equal symbolic `A`, `B`, `c`.
//!
//! # Which graphs are checked
//! Graphs whose causality cannot be assigned (`CausalConflict`) and graphs with storage in
//! derivative causality (`Merged`/`Held` notes, or a `DependentStorage` error) are skipped:
//! the independent assembly has one state per storage element. A `SingularLoop` error is
//! accepted only when the independent equations are singular too (a junction cycle whose
//! circulating effort or flow nothing determines); otherwise it fails the test, as does
//! any other error. About 56% of the generated graphs are checked (`tally`).
//!
//! # Tolerance
//! `F` is affine, so central differences are exact in exact arithmetic, whatever the step:
//! every difference comes from rounding, and the bound is the sum of two rounding-error
//! bounds computed for each entry, times a safety factor of 2 for the second-order terms
//! they leave out.
//! - The finite difference: each solve of `M z = b` is off by at most
//!   `|M⁻¹| (γ_{3n} Pᵀ|L||U| |ẑ| + γ_2 |b|)`, component by component (the backward error of
//!   Gaussian elimination with partial pivoting, Higham Thm. 9.4, carried forward through
//!   `|M⁻¹|`); the quotient divides the two solves' errors by `2h`. The points are dyadic
//!   and `h = 1/2`, so `x ± h` is exact.
//! - The library's value: an exact rational function evaluated in `f64`, off by at most
//!   `γ_k Σ|term|` in numerator and denominator (`eval_error`).
//!
//! The bound adapts to the conditioning of each graph instead of a fixed relative
//! tolerance, which would be too loose for well-conditioned graphs and too tight for the
//! few ill-conditioned ones. Measured over 3000 generated graphs (4995 non-zero entries of
//! `A`, `B`, `c`): the largest difference used 14% of the bound; relative to its entry the
//! bound has median 4e-13, 99th percentile 5e-9 and maximum 7e-6, so a wrong entry is
//! caught unless it is wrong by less than that. The co-energy matrices are compared with
//! `D A D⁻¹`, `D B`, `D c` from the library's energy values, where only evaluation rounding
//! separates them (bound relative to the entry below 4e-13).

use crate::random_graph::{Features, Graph, GraphSpec, Kind, graph_spec};
use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::{self, Layout, Note, Options, Quantity, StateEquations, Variables};
use bondgraph_core::laws;
use bondgraph_core::symbolic::{Poly, RatFunc};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{
    Config, FileFailurePersistence, RngAlgorithm, TestCaseError, TestRng, TestRunner,
};

// ---------------------------------------------------------------------------------------
// The independent assembly
// ---------------------------------------------------------------------------------------

/// Picks one unknown of a bond: its effort or its flow.
type Unknown = fn(usize) -> usize;

/// A term of an equation's right-hand side.
#[derive(Clone, Copy, Debug)]
enum Rhs {
    /// `coefficient * x[state]`.
    State(usize, f64),
    /// `coefficient * u[input]`.
    Input(usize, f64),
    /// A constant.
    Constant(f64),
}

/// `P M = L U` by Gaussian elimination with partial pivoting.
struct Lu {
    n: usize,
    /// `L` (unit diagonal, below) and `U` (on and above the diagonal), row-major.
    factors: Vec<f64>,
    /// Row `i` of `L U` is row `perm[i]` of `M`.
    perm: Vec<usize>,
}

impl Lu {
    /// Factors the `n × n` row-major `matrix`; `None` if a pivot vanishes (to rounding: a
    /// pivot below `n ε max|M|` counts as zero).
    fn factor(matrix: &[f64], n: usize) -> Option<Lu> {
        let mut a = matrix.to_vec();
        let mut perm: Vec<usize> = (0..n).collect();
        let scale = matrix.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for k in 0..n {
            let pivot_row = (k..n)
                .max_by(|&r, &s| a[r * n + k].abs().total_cmp(&a[s * n + k].abs()))
                .expect("non-empty range");
            if a[pivot_row * n + k].abs() <= n as f64 * f64::EPSILON * scale {
                return None;
            }
            if pivot_row != k {
                for j in 0..n {
                    a.swap(k * n + j, pivot_row * n + j);
                }
                perm.swap(k, pivot_row);
            }
            let pivot = a[k * n + k];
            for r in k + 1..n {
                let factor = a[r * n + k] / pivot;
                a[r * n + k] = factor;
                if factor != 0.0 {
                    for j in k + 1..n {
                        a[r * n + j] -= factor * a[k * n + j];
                    }
                }
            }
        }
        Some(Lu {
            n,
            factors: a,
            perm,
        })
    }

    fn solve(&self, b: &[f64]) -> Vec<f64> {
        let n = self.n;
        let mut y: Vec<f64> = self.perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            for j in 0..i {
                y[i] -= self.factors[i * n + j] * y[j];
            }
        }
        for i in (0..n).rev() {
            for j in i + 1..n {
                y[i] -= self.factors[i * n + j] * y[j];
            }
            y[i] /= self.factors[i * n + i];
        }
        y
    }
}

/// The element and junction equations of a graph, `M z = b(x, u)` over
/// `z = (e_0, f_0, e_1, f_1, ...)`, factored, with what bounds the rounding of a solve.
struct Assembly {
    n: usize,
    lu: Lu,
    rhs: Vec<Vec<Rhs>>,
    /// `dx_k/dt = sign * z[unknown]` for each state `k`.
    readout: Vec<(usize, f64)>,
    /// `|M⁻¹|`, row-major.
    inverse_abs: Vec<f64>,
    /// `|M⁻¹| Pᵀ|L||U|`, row-major: see [`Assembly::solve`].
    weight: Vec<f64>,
}

/// A solution `F(x, u)` with a bound on its rounding error.
struct Solution {
    derivative: Vec<f64>,
    error: Vec<f64>,
}

/// `γ_k = k ε / (1 - k ε)`, the standard bound on the relative rounding of `k` operations.
fn gamma(k: usize) -> f64 {
    let ke = k as f64 * f64::EPSILON / 2.0;
    ke / (1.0 - ke)
}

impl Assembly {
    /// Writes the equations of `graph`: one per one-port, two per two-port, `k` per junction
    /// of `k` bonds; `None` if the system is singular.
    fn new(graph: &Graph) -> Option<Assembly> {
        let n = 2 * graph.bonds.len();
        let effort = |b: usize| 2 * b;
        let flow = |b: usize| 2 * b + 1;
        let mut matrix = Vec::new();
        let mut rhs = Vec::new();
        let mut row = |terms: &[(usize, f64)], right: Vec<Rhs>| {
            let mut r = vec![0.0; n];
            for &(unknown, coefficient) in terms {
                r[unknown] += coefficient;
            }
            matrix.extend(r);
            rhs.push(right);
        };
        let storage = graph.storage();
        let state_of = |e: usize| storage.iter().position(|&s| s == e).expect("storage");
        let mut readout = vec![(0, 0.0); storage.len()];
        for (e, element) in graph.elements.iter().enumerate() {
            let bonds = graph.bonds_of(e);
            let sign = |b: usize| graph.sign_into(b, e);
            match element.kind {
                // The element's flow is sign * f_b; its effort is e_b.
                Kind::EffortSource {
                    input,
                    gain,
                    offset,
                } => row(
                    &[(effort(bonds[0]), 1.0)],
                    vec![Rhs::Input(input, gain), Rhs::Constant(offset)],
                ),
                // The value is the flow out of the source: -sign * f_b.
                Kind::FlowSource {
                    input,
                    gain,
                    offset,
                } => row(
                    &[(flow(bonds[0]), -sign(bonds[0]))],
                    vec![Rhs::Input(input, gain), Rhs::Constant(offset)],
                ),
                // m * (sign f_b) = p, dp/dt = e_b.
                Kind::Inertia { inertance } => {
                    let b = bonds[0];
                    row(
                        &[(flow(b), inertance * sign(b))],
                        vec![Rhs::State(state_of(e), 1.0)],
                    );
                    readout[state_of(e)] = (effort(b), 1.0);
                }
                // e_b = q / C (C e_b = q, or e_b = k q), dq/dt = sign f_b.
                Kind::Compliance { value, stiffness } => {
                    let b = bonds[0];
                    if stiffness {
                        row(&[(effort(b), 1.0)], vec![Rhs::State(state_of(e), value)]);
                    } else {
                        row(&[(effort(b), value)], vec![Rhs::State(state_of(e), 1.0)]);
                    }
                    readout[state_of(e)] = (flow(b), sign(b));
                }
                // e_b = R (sign f_b).
                Kind::Resistor { resistance } => {
                    let b = bonds[0];
                    row(
                        &[(effort(b), 1.0), (flow(b), -resistance * sign(b))],
                        vec![],
                    );
                }
                Kind::Transformer { ratio } | Kind::Gyrator { ratio } => {
                    let (input, output) = if graph.bonds[bonds[0]].1 == e {
                        (bonds[0], bonds[1])
                    } else {
                        (bonds[1], bonds[0])
                    };
                    if let Kind::Transformer { .. } = element.kind {
                        // e_in = n e_out, f_out = n f_in.
                        row(&[(effort(input), 1.0), (effort(output), -ratio)], vec![]);
                        row(&[(flow(output), 1.0), (flow(input), -ratio)], vec![]);
                    } else {
                        // e_in = r f_out, e_out = r f_in.
                        row(&[(effort(input), 1.0), (flow(output), -ratio)], vec![]);
                        row(&[(effort(output), 1.0), (flow(input), -ratio)], vec![]);
                    }
                }
                Kind::Zero | Kind::One => {
                    let (common, summed): (Unknown, Unknown) = if matches!(element.kind, Kind::Zero)
                    {
                        (effort, flow)
                    } else {
                        (flow, effort)
                    };
                    for &b in &bonds[1..] {
                        row(&[(common(bonds[0]), 1.0), (common(b), -1.0)], vec![]);
                    }
                    let sum: Vec<(usize, f64)> =
                        bonds.iter().map(|&b| (summed(b), sign(b))).collect();
                    row(&sum, vec![]);
                }
            }
        }
        assert_eq!(rhs.len(), n, "one equation per bond end");

        let lu = Lu::factor(&matrix, n)?;
        // |M⁻¹|, column by column.
        let mut inverse_abs = vec![0.0; n * n];
        for j in 0..n {
            let mut unit = vec![0.0; n];
            unit[j] = 1.0;
            for (i, v) in lu.solve(&unit).into_iter().enumerate() {
                inverse_abs[i * n + j] = v.abs();
            }
        }
        // Pᵀ |L| |U| in the rows of M.
        let mut lu_abs = vec![0.0; n * n];
        for i in 0..n {
            for k in 0..n {
                let mut sum = 0.0;
                for j in 0..=i.min(k) {
                    let l = if j == i {
                        1.0
                    } else {
                        lu.factors[i * n + j].abs()
                    };
                    sum += l * lu.factors[j * n + k].abs();
                }
                lu_abs[lu.perm[i] * n + k] = sum;
            }
        }
        let mut weight = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let a = inverse_abs[i * n + j];
                if a != 0.0 {
                    for k in 0..n {
                        weight[i * n + k] += a * lu_abs[j * n + k];
                    }
                }
            }
        }
        Some(Assembly {
            n,
            lu,
            rhs,
            readout,
            inverse_abs,
            weight,
        })
    }

    /// `F(x, u)`, with a first-order bound on its rounding error.
    ///
    /// The computed solution `ẑ` solves `(M + ΔM) ẑ = b + Δb` exactly with
    /// `|ΔM| ≤ γ_{3n} Pᵀ|L||U|` (Higham, *Accuracy and Stability of Numerical Algorithms*,
    /// Thm. 9.4) and `|Δb| ≤ γ_2 |b|` (each right-hand side is at most a product and a sum),
    /// so to first order `|ẑ - z| ≤ |M⁻¹| (γ_{3n} Pᵀ|L||U| |ẑ| + γ_2 |b|)`, component by
    /// component. `F` reads components of `z` exactly.
    fn solve(&self, x: &[f64], u: &[f64]) -> Solution {
        let n = self.n;
        let b: Vec<f64> = self
            .rhs
            .iter()
            .map(|terms| {
                terms
                    .iter()
                    .map(|t| match *t {
                        Rhs::State(k, c) => c * x[k],
                        Rhs::Input(k, c) => c * u[k],
                        Rhs::Constant(c) => c,
                    })
                    .sum()
            })
            .collect();
        let z = self.lu.solve(&b);
        let error: Vec<f64> = (0..n)
            .map(|i| {
                let row = i * n..(i + 1) * n;
                let from_matrix: f64 = self.weight[row.clone()]
                    .iter()
                    .zip(&z)
                    .map(|(w, z)| w * z.abs())
                    .sum();
                let from_rhs: f64 = self.inverse_abs[row]
                    .iter()
                    .zip(&b)
                    .map(|(w, b)| w * b.abs())
                    .sum();
                gamma(3 * n) * from_matrix + gamma(2) * from_rhs
            })
            .collect();
        Solution {
            derivative: self.readout.iter().map(|&(i, s)| s * z[i]).collect(),
            error: self.readout.iter().map(|&(i, _)| error[i]).collect(),
        }
    }
}

/// A bound on the rounding error of `RatFunc::eval`: each polynomial is a sum of terms,
/// each a coefficient times powers, so its value is off by at most
/// `γ_{terms + 2·degree + 2} Σ|term|`; the quotient adds one rounding.
fn eval_error(value: &RatFunc, parameters: &[f64]) -> f64 {
    fn poly_error(p: &Poly, parameters: &[f64]) -> (f64, f64) {
        let absolute: f64 = p
            .terms()
            .map(|(m, c)| {
                let c: f64 = c.to_string().parse().expect("integer coefficient");
                m.iter().fold(c.abs(), |acc, (s, e)| {
                    acc * parameters[s.index()].abs().powi(e as i32)
                })
            })
            .sum();
        let operations = p.term_count() + 2 * p.degree() as usize + 2;
        (p.eval(parameters), gamma(operations) * absolute)
    }
    if value.is_zero() {
        return 0.0;
    }
    let (num, num_error) = poly_error(value.numerator(), parameters);
    let (den, den_error) = poly_error(value.denominator(), parameters);
    let quotient = (num / den).abs();
    quotient * (num_error / num.abs() + den_error / den.abs() + gamma(1))
}

// ---------------------------------------------------------------------------------------
// The check
// ---------------------------------------------------------------------------------------

/// Why a case was not checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Skip {
    /// Causality cannot be assigned.
    CausalConflict,
    /// Storage in derivative causality (merged, held, or not mergeable): the independent
    /// assembly has one state per storage element, so it does not model it.
    DerivativeCausality,
    /// The library reports a singular algebraic loop and the independent assembly confirms
    /// that the element and junction equations are singular: a cycle of the junction
    /// structure whose effort or flow nothing determines (a valid file, an ill-posed model).
    Singular,
}

/// What an accepted case exercised.
#[derive(Clone, Copy, Debug, Default)]
struct Exercised {
    graph: Features,
    states: usize,
    algebraic_loops: usize,
    nonzero_c: bool,
}

/// The outcome of one case.
#[derive(Clone, Copy, Debug)]
enum Outcome {
    Skipped(Skip),
    Checked(Exercised),
}

/// The step of the central differences, a power of two so that `x ± h` is exact for the
/// dyadic points used. `F` is affine, so central differences have no truncation error and
/// `h` only needs to be large against rounding.
const STEP: f64 = 0.5;

/// A point with dyadic coordinates `k/1024` in `[-1, 1]`, from `seed` (splitmix64).
fn point(seed: &mut u64, len: usize) -> Vec<f64> {
    (0..len)
        .map(|_| {
            *seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = *seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            ((z % 2049) as f64 - 1024.0) / 1024.0
        })
        .collect()
}

/// Compares `actual` with `expected` within `SAFETY × (expected_error + actual_error)`.
///
/// `SAFETY = 2` covers the second-order terms the first-order error bounds leave out.
fn assert_close(
    what: &str,
    actual: f64,
    expected: f64,
    bound: f64,
    text: &str,
) -> Result<(), TestCaseError> {
    const SAFETY: f64 = 2.0;
    prop_assert!(
        actual.is_finite() && (actual - expected).abs() <= SAFETY * bound,
        "{what}: library {actual:e}, independent {expected:e}, difference {:e} > bound {:e}\n{text}",
        (actual - expected).abs(),
        SAFETY * bound
    );
    Ok(())
}

/// Derives `text`'s equations in `variables`, or says why the case is skipped.
fn derive(text: &str, variables: Variables) -> Result<Result<StateEquations, Skip>, TestCaseError> {
    let model = match bondgraph_ron::model::load_str("random.ron", text) {
        Ok(model) => model,
        Err(e) => return Err(TestCaseError::fail(format!("load failed: {e}\n{text}"))),
    };
    match equations::derive(&model, &laws::plain_laws(&model), &Options { variables }) {
        Ok(eq) => {
            let derivative = eq
                .notes
                .iter()
                .any(|n| matches!(n, Note::Merged { .. } | Note::Held { .. }));
            prop_assert_eq!(
                derivative,
                !eq.causality.dependent.is_empty(),
                "notes and causality disagree on dependent storage\n{}",
                text
            );
            Ok(if derivative {
                Err(Skip::DerivativeCausality)
            } else {
                Ok(eq)
            })
        }
        Err(e) if e.has(DiagnosticKind::CausalConflict) => Ok(Err(Skip::CausalConflict)),
        Err(e) if e.has(DiagnosticKind::DependentStorage) => Ok(Err(Skip::DerivativeCausality)),
        // Whether the equations really are singular is for the caller to confirm.
        Err(e) if e.has(DiagnosticKind::SingularLoop) => Ok(Err(Skip::Singular)),
        Err(e) => Err(TestCaseError::fail(format!("derive failed: {e}\n{text}"))),
    }
}

/// The whole check of one random graph: load, derive, and compare `A`, `B`, `c` in energy
/// and co-energy variables with the independent finite-difference Jacobian.
fn check_case(spec: &GraphSpec) -> Result<Outcome, TestCaseError> {
    let graph = spec.build();
    let text = graph.ron_text();
    let eq = match derive(&text, Variables::Energy)? {
        Ok(eq) => eq,
        Err(Skip::Singular) => {
            prop_assert!(
                Assembly::new(&graph).is_none(),
                "the library reports a singular loop, but the element and junction equations \
                 are regular\n{}",
                text
            );
            return Ok(Outcome::Skipped(Skip::Singular));
        }
        Err(skip) => return Ok(Outcome::Skipped(skip)),
    };

    // States: the storage elements in element order, in energy variables.
    let storage = graph.storage();
    let names: Vec<&str> = eq.states.iter().map(|s| s.element.as_str()).collect();
    let expected: Vec<&str> = storage
        .iter()
        .map(|&e| graph.elements[e].name.as_str())
        .collect();
    prop_assert_eq!(&names, &expected, "state order\n{}", text);
    for (state, &e) in eq.states.iter().zip(&storage) {
        let quantity = match graph.elements[e].kind {
            Kind::Inertia { .. } => Quantity::Momentum,
            _ => Quantity::Displacement,
        };
        prop_assert_eq!(state.quantity, quantity);
    }
    prop_assert_eq!(eq.inputs.len(), graph.inputs);

    let Some(assembly) = Assembly::new(&graph) else {
        return Err(TestCaseError::fail(format!(
            "the library derived equations, but the element and junction equations are \
             singular\n{text}"
        )));
    };
    let (n_x, n_u) = (storage.len(), graph.inputs);
    let mut seed = spec.point_seed;
    let x = point(&mut seed, n_x);
    let u = point(&mut seed, n_u);

    let json = eq.to_json_as("", &[], Layout::Dense);
    let (json_a, json_b) = (
        json.A_value.rows().expect("dense"),
        json.B_value.rows().expect("dense"),
    );
    let (a, b, c) = (eq.a(), eq.b(), eq.c());
    let values = &eq.values;

    // Column j of A (then of B): (F(x + h e_j, u) - F(x - h e_j, u)) / 2h. The error of
    // each difference quotient is at most (δ⁺ + δ⁻)/2h from the two solves (see
    // `Assembly::solve`), plus two roundings of the quotient itself; the library's value is
    // an exact rational function evaluated in f64, off by at most `eval_error`.
    let column = |name: &str,
                  j: usize,
                  library: &dyn Fn(usize) -> (f64, f64),
                  plus: Solution,
                  minus: Solution|
     -> Result<(), TestCaseError> {
        for i in 0..n_x {
            let fd = (plus.derivative[i] - minus.derivative[i]) / (2.0 * STEP);
            let fd_error = (plus.error[i] + minus.error[i]) / (2.0 * STEP) + gamma(2) * fd.abs();
            let (value, value_error) = library(i);
            assert_close(
                &format!("{name}[{i}][{j}]"),
                value,
                fd,
                fd_error + value_error,
                &text,
            )?;
        }
        Ok(())
    };
    for j in 0..n_x {
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[j] += STEP;
        xm[j] -= STEP;
        let library = |i: usize| (json_a[i][j], eval_error(&a[i][j], values));
        column(
            "A",
            j,
            &library,
            assembly.solve(&xp, &u),
            assembly.solve(&xm, &u),
        )?;
    }
    for j in 0..n_u {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[j] += STEP;
        um[j] -= STEP;
        let library = |i: usize| (json_b[i][j], eval_error(&b[i][j], values));
        column(
            "B",
            j,
            &library,
            assembly.solve(&x, &up),
            assembly.solve(&x, &um),
        )?;
    }
    // c = F(0, 0).
    let zero = assembly.solve(&vec![0.0; n_x], &vec![0.0; n_u]);
    for (i, entry) in c.iter().enumerate() {
        assert_close(
            &format!("c[{i}]"),
            json.c_value[i],
            zero.derivative[i],
            zero.error[i] + eval_error(entry, values),
            &text,
        )?;
    }

    // Co-energy: y = D x with D = diag(1/m or 1/C), so A_co = D A D⁻¹, B_co = D B,
    // c_co = D c. Both sides evaluate exact rational functions: the bound is the two
    // evaluation errors (the energy one scaled like its entry) and the three roundings of
    // `d_i * A_ij / d_j`.
    let co = match derive(&text, Variables::CoEnergy)? {
        Ok(co) => co,
        Err(skip) => {
            return Err(TestCaseError::fail(format!(
                "energy derivation succeeded, co-energy skipped as {skip:?}\n{text}"
            )));
        }
    };
    let co_json = co.to_json_as("", &[], Layout::Dense);
    let (co_a, co_b) = (
        co_json.A_value.rows().expect("dense"),
        co_json.B_value.rows().expect("dense"),
    );
    let (a_co, b_co, c_co) = (co.a(), co.b(), co.c());
    let d: Vec<f64> = storage.iter().map(|&e| graph.coenergy_factor(e)).collect();
    for (state, &e) in co.states.iter().zip(&storage) {
        let quantity = match graph.elements[e].kind {
            Kind::Inertia { .. } => Quantity::Velocity,
            _ => Quantity::Force,
        };
        prop_assert_eq!(state.quantity, quantity);
    }
    for i in 0..n_x {
        for j in 0..n_x {
            let scale = d[i] / d[j];
            let expected = d[i] * json_a[i][j] / d[j];
            let bound = eval_error(&a_co[i][j], values)
                + scale * eval_error(&a[i][j], values)
                + gamma(3) * expected.abs();
            assert_close(
                &format!("A_co[{i}][{j}]"),
                co_a[i][j],
                expected,
                bound,
                &text,
            )?;
        }
        for j in 0..n_u {
            let expected = d[i] * json_b[i][j];
            let bound = eval_error(&b_co[i][j], values)
                + d[i] * eval_error(&b[i][j], values)
                + gamma(2) * expected.abs();
            assert_close(
                &format!("B_co[{i}][{j}]"),
                co_b[i][j],
                expected,
                bound,
                &text,
            )?;
        }
        let expected = d[i] * json.c_value[i];
        let bound = eval_error(&c_co[i], values)
            + d[i] * eval_error(&c[i], values)
            + gamma(2) * expected.abs();
        assert_close(
            &format!("c_co[{i}]"),
            co_json.c_value[i],
            expected,
            bound,
            &text,
        )?;
    }

    Ok(Outcome::Checked(Exercised {
        graph: graph.features,
        states: n_x,
        algebraic_loops: eq
            .notes
            .iter()
            .filter(|n| matches!(n, Note::AlgebraicLoop { .. }))
            .count(),
        nonzero_c: c.iter().any(|v| !v.is_zero()),
    }))
}

/// `cases` cases, with room for the skipped ones (about half), failures saved next to this
/// file (`jacobian.proptest-regressions`; there is no `lib.rs` beside an integration test
/// for proptest's default place).
fn config(cases: u32) -> Config {
    Config {
        cases,
        max_global_rejects: 4 * cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// `A`, `B`, `c` (and their co-energy forms) match the finite-difference Jacobian of the
    /// independently assembled element and junction equations.
    #[test]
    fn state_matrices_match_a_finite_difference_jacobian(spec in graph_spec()) {
        let outcome = check_case(&spec)?;
        prop_assume!(matches!(outcome, Outcome::Checked(_)), "skipped: {:?}", outcome);
    }
}

// ---------------------------------------------------------------------------------------
// Bond-order invariance
// ---------------------------------------------------------------------------------------

/// A random graph with a random order of its bonds list.
fn spec_with_bond_order() -> impl Strategy<Value = (GraphSpec, Vec<usize>)> {
    graph_spec().prop_flat_map(|spec| {
        let count = spec.build().bonds.len();
        (
            Just(spec),
            Just((0..count).collect::<Vec<_>>()).prop_shuffle(),
        )
    })
}

proptest! {
    #![proptest_config(config(256))]

    /// Listing the bonds in another order gives structurally equal symbolic `A`, `B`, `c`.
    ///
    /// Cases where either order meets a causal conflict are skipped: whether causality
    /// assignment succeeds on degenerate junction structures can depend on bond order, a
    /// known defect pinned down in `regressions`.
    #[test]
    fn bond_order_does_not_change_the_equations((spec, order) in spec_with_bond_order()) {
        let graph = spec.build();
        let text = graph.ron_text();
        let shuffled_text = graph.ron(&order);
        let eq = derive(&text, Variables::Energy)?;
        let shuffled = derive(&shuffled_text, Variables::Energy)?;
        let conflict = |r: &Result<StateEquations, Skip>| {
            matches!(r, Err(Skip::CausalConflict))
        };
        prop_assume!(!conflict(&eq) && !conflict(&shuffled), "causal conflict");
        let (eq, shuffled) = match (eq, shuffled) {
            (Ok(eq), Ok(shuffled)) => (eq, shuffled),
            (Err(a), Err(b)) if a == b => return Err(TestCaseError::reject(format!("{a:?}"))),
            (a, b) => {
                return Err(TestCaseError::fail(format!(
                    "file order: {:?}, bond order {order:?}: {:?}\n{text}",
                    a.err(),
                    b.err()
                )));
            }
        };
        let names = |eq: &StateEquations| -> Vec<String> {
            eq.states.iter().map(|s| s.name.clone()).collect()
        };
        prop_assert_eq!(names(&eq), names(&shuffled));
        prop_assert!(eq.a() == shuffled.a(), "A differs in bond order {:?}\n{}", order, text);
        prop_assert!(eq.b() == shuffled.b(), "B differs in bond order {:?}\n{}", order, text);
        prop_assert!(eq.c() == shuffled.c(), "c differs in bond order {:?}\n{}", order, text);
    }
}

// ---------------------------------------------------------------------------------------
// Coverage of the generator
// ---------------------------------------------------------------------------------------

/// Counts over a run of the generator.
#[derive(Debug, Default)]
struct Tally {
    generated: usize,
    conflicts: usize,
    /// Causal conflicts whose element and junction equations are nevertheless regular:
    /// see `regressions::scap_misses_the_causality_of_a_shorted_junction`.
    conflicts_with_regular_equations: usize,
    derivative: usize,
    singular: usize,
    /// Cases where listing the bonds in reverse order changes the kind of outcome (success,
    /// conflict, ...): the known defect of `regressions`.
    order_dependent: usize,
    accepted: usize,
    with_loops: usize,
    with_transformer: usize,
    with_gyrator: usize,
    with_negative_ratio: usize,
    with_extra_links: usize,
    with_reversed: usize,
    with_reversed_source: usize,
    with_reversed_storage: usize,
    with_effort_source: usize,
    with_flow_source: usize,
    with_stiffness: usize,
    with_two_or_more_states: usize,
    with_three_or_more_states: usize,
    with_nonzero_c: usize,
}

/// Runs the full check on `count` graphs from a fixed seed, tallying what they exercise.
fn tally(count: usize) -> Tally {
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let strategy = graph_spec();
    let mut tally = Tally::default();
    for _ in 0..count {
        let spec = strategy
            .new_tree(&mut runner)
            .expect("the generator never rejects")
            .current();
        tally.generated += 1;
        let graph = spec.build();
        let reversed: Vec<usize> = (0..graph.bonds.len()).rev().collect();
        let kind = |text: &str| {
            derive(text, Variables::Energy)
                .expect("loads and fails only by a skip")
                .err()
        };
        if kind(&graph.ron_text()) != kind(&graph.ron(&reversed)) {
            tally.order_dependent += 1;
        }
        match check_case(&spec) {
            Err(e) => panic!("{e}"),
            Ok(Outcome::Skipped(Skip::CausalConflict)) => {
                tally.conflicts += 1;
                if Assembly::new(&spec.build()).is_some() {
                    tally.conflicts_with_regular_equations += 1;
                }
            }
            Ok(Outcome::Skipped(Skip::DerivativeCausality)) => tally.derivative += 1,
            Ok(Outcome::Skipped(Skip::Singular)) => tally.singular += 1,
            Ok(Outcome::Checked(x)) => {
                tally.accepted += 1;
                let count = |yes: bool| usize::from(yes);
                tally.with_loops += count(x.algebraic_loops > 0);
                tally.with_transformer += count(x.graph.transformers > 0);
                tally.with_gyrator += count(x.graph.gyrators > 0);
                tally.with_negative_ratio += count(x.graph.negative_ratios > 0);
                tally.with_extra_links += count(x.graph.extra_links > 0);
                tally.with_reversed += count(x.graph.reversed > 0);
                tally.with_reversed_source += count(x.graph.reversed_sources > 0);
                tally.with_reversed_storage += count(x.graph.reversed_storage > 0);
                tally.with_effort_source += count(x.graph.effort_sources > 0);
                tally.with_flow_source += count(x.graph.flow_sources > 0);
                tally.with_stiffness += count(x.graph.stiffnesses > 0);
                tally.with_two_or_more_states += count(x.states >= 2);
                tally.with_three_or_more_states += count(x.states >= 3);
                tally.with_nonzero_c += count(x.nonzero_c);
            }
        }
    }
    tally
}

/// The generator exercises every feature the Jacobian property is meant to cover.
///
/// Measured on these 500 graphs (fixed seed): 281 accepted (56%); skipped 143 causal
/// conflicts (29%; 27 of them with regular equations, the known defect of `regressions`),
/// 66 with storage in derivative causality (13%) and 10 singular (2%). Of the accepted:
/// 88 with algebraic loops, 78 with a transformer, 77 with a gyrator, 88 with a negative
/// ratio, 63 with extra junction links, 150 with reversed bonds (58 into a source, 59 out
/// of storage), 120 with an effort source, 112 with a flow source, 75 with a compliance
/// written as a stiffness, 102 with two or more states (44 with three or more), 67 with a
/// non-zero `c`. Reversing the bond order changed the outcome of 1 graph. The floors below
/// are about half of these, so that a change of the generator that starves a feature fails
/// here.
#[test]
fn generator_exercises_every_feature() {
    let t = tally(500);
    eprintln!("{t:#?}");
    assert_eq!(t.generated, 500);
    let at_least = |what: &str, count: usize, floor: usize| {
        assert!(count >= floor, "{what}: {count} < {floor}\n{t:#?}");
    };
    at_least("accepted", t.accepted, 225);
    at_least("algebraic loops", t.with_loops, 40);
    at_least("transformers", t.with_transformer, 35);
    at_least("gyrators", t.with_gyrator, 35);
    at_least("negative ratios", t.with_negative_ratio, 40);
    at_least("extra junction links", t.with_extra_links, 30);
    at_least("reversed sources", t.with_reversed_source, 25);
    at_least("reversed storage", t.with_reversed_storage, 25);
    at_least("effort sources", t.with_effort_source, 50);
    at_least("flow sources", t.with_flow_source, 50);
    at_least("stiffnesses", t.with_stiffness, 30);
    at_least("two or more states", t.with_two_or_more_states, 50);
    at_least("three or more states", t.with_three_or_more_states, 20);
    at_least("non-zero c", t.with_nonzero_c, 30);
}
