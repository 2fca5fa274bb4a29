//! The verdict on an answer: equal to the model's equations, equal up to a change of state
//! variables, or different at a named entry or coefficient.
//!
//! Why states are matched by name: a similarity `A' = T A T⁻¹, B' = T B` leaves the
//! characteristic polynomial unchanged for *any* invertible `T`, and with one input any two
//! controllable pairs with the same characteristic polynomial are similar, so invariants
//! alone cannot tell a correct answer from one with a wrong gain in `B`. Naming the states
//! as the model does (`p_mass` or `v_mass`, `q_spring`, `x_spring` or `f_spring`) fixes `T`:
//! a reordering and, for co-energy states, a scaling by the storage (`v = p/m`, `f = q/C`),
//! checked exactly against the model's own co-energy derivation. Then every entry of `A`,
//! `B`, `E` can be compared exactly, and the first that differs named. An answer without
//! state names is compared entry by entry with the model's equations, and otherwise only its
//! characteristic polynomial can be checked, which the verdict says.

use super::answer::Answer;
use super::{Matrix, characteristic};
use crate::equations::{StateEquations, Variables};
use crate::symbolic::{RatFunc, SymbolTable};

/// What the comparison found.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// The answer's `A`, `B` (and `E`) are the model's, entry by entry, in the model's
    /// states.
    Equal,
    /// The answer is the model's equations after a change of state variables.
    Similar {
        /// What the change is, one line each (`v_mass = p_mass/m`, a reordering), or the
        /// only invariant that could be checked.
        changes: Vec<String>,
        /// Whether `T` was known (states named), so that every entry was checked; if not,
        /// only the characteristic polynomial was.
        entries_checked: bool,
    },
    /// The answer differs from the model's equations.
    Different {
        /// The first entry or coefficient that differs, with both values.
        first: String,
    },
}

/// A verdict and what was checked on the way.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The verdict.
    pub verdict: Verdict,
    /// What was checked, one sentence each.
    pub notes: Vec<String>,
}

/// One answer state matched to a model state.
struct Matched {
    /// The model state's index.
    state: usize,
    /// Whether the answer writes it in co-energy variables.
    coenergy: bool,
}

/// Compares `answer` with one mode's equations, derived in energy (`energy`) and co-energy
/// (`coenergy`) variables; `preferred` is the model's own choice (what "equal" means).
///
/// # Complexity
/// Two characteristic polynomials (`O(n⁴)` exact operations) and `O(n²)` comparisons.
pub fn compare(
    energy: &StateEquations,
    coenergy: &StateEquations,
    preferred: Variables,
    answer: &Answer,
) -> Comparison {
    let symbols = &energy.symbols;
    let mut notes = Vec::new();
    let n = energy.state_count();
    let m = energy.inputs.len();
    let names = |eq: &StateEquations| {
        eq.states
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if answer.a.len() != n {
        return different(
            notes,
            format!(
                "the answer has {} states; the model has {n} in this mode ({})",
                answer.a.len(),
                names(energy)
            ),
        );
    }
    if let Some(row) = answer.b.first().filter(|row| row.len() != m) {
        return different(
            notes,
            format!(
                "B has {} columns; the model has {m} inputs ({})",
                row.len(),
                energy.inputs.join(", ")
            ),
        );
    }
    // The characteristic polynomial: invariant under any change of state variables.
    let model_poly = characteristic(&energy.a()).coefficients;
    let answer_poly = characteristic(&answer.a).coefficients;
    let poly_difference = (0..=n).rev().find_map(|power| {
        (model_poly[power] != answer_poly[power]).then(|| {
            format!(
                "det(sI - A): the coefficient of {} is {} in the answer, {} in the model",
                power_name(power),
                answer_poly[power].text(symbols),
                model_poly[power].text(symbols)
            )
        })
    });
    if poly_difference.is_none() {
        notes.push("same characteristic polynomial det(sI - A)".to_string());
    }

    let preferred_eq = match preferred {
        Variables::Energy => energy,
        Variables::CoEnergy => coenergy,
    };
    let matched = answer
        .states
        .as_ref()
        .and_then(|states| match_states(states, energy, coenergy));
    let Some(matched) = matched else {
        if answer.states.is_some() {
            notes.push(format!(
                "the answer's states are not named as the model's ({}, or {})",
                names(energy),
                names(coenergy)
            ));
        }
        // Unnamed: entry by entry against the model's own variables, else the invariant.
        let identity: Vec<(usize, RatFunc)> = (0..n).map(|k| (k, RatFunc::one())).collect();
        let first = first_difference(preferred_eq, &identity, answer, symbols);
        return match (first, poly_difference) {
            (None, _) => Comparison {
                verdict: Verdict::Equal,
                notes,
            },
            (Some(_), Some(poly)) => different(notes, poly),
            (Some(_), None) => {
                notes.push(
                    "name the states as the model does to check every entry, not only the characteristic polynomial"
                        .to_string(),
                );
                Comparison {
                    verdict: Verdict::Similar {
                        changes: vec![format!(
                            "the same characteristic polynomial as the model's {} equations, with other entries: an unknown change of state variables",
                            variables_name(preferred)
                        )],
                        entries_checked: false,
                    },
                    notes,
                }
            }
        };
    };

    // T: answer state i = scale_i · base state k_i.
    let all_coenergy = matched.iter().all(|s| s.coenergy);
    let all_energy = matched.iter().all(|s| !s.coenergy);
    let (base, map): (&StateEquations, Vec<(usize, RatFunc)>) = if all_coenergy {
        (
            coenergy,
            matched.iter().map(|s| (s.state, RatFunc::one())).collect(),
        )
    } else if all_energy {
        (
            energy,
            matched.iter().map(|s| (s.state, RatFunc::one())).collect(),
        )
    } else if scaling_is_diagonal(energy, coenergy) {
        let map = matched
            .iter()
            .map(|s| {
                let scale = if s.coenergy {
                    energy.states[s.state].storage.inv().unwrap_or_default()
                } else {
                    RatFunc::one()
                };
                (s.state, scale)
            })
            .collect();
        (energy, map)
    } else {
        notes.push(
            "the co-energy variables of this mode are not each one energy variable over its storage; write all states in energy or all in co-energy variables"
                .to_string(),
        );
        return different(
            notes,
            "the states mix energy and co-energy variables of coupled storage".to_string(),
        );
    };
    if let Some(first) = first_difference(base, &map, answer, symbols) {
        if let Some(poly) = poly_difference {
            notes.push(poly);
        }
        return different(notes, first);
    }
    let states = answer.states.as_deref().unwrap_or_default();
    let reordered = map.iter().enumerate().any(|(i, (k, _))| i != *k);
    let base_variables = if base.variables == Variables::CoEnergy {
        Variables::CoEnergy
    } else {
        Variables::Energy
    };
    let scaled = map.iter().any(|(_, s)| !s.is_one());
    if !reordered && !scaled && base_variables == preferred {
        return Comparison {
            verdict: Verdict::Equal,
            notes,
        };
    }
    let mut changes = Vec::new();
    for (i, (k, scale)) in map.iter().enumerate() {
        let state = &base.states[*k];
        if !scale.is_one() {
            changes.push(format!(
                "{} = {}/{}",
                states[i],
                state.name,
                state.storage.text(symbols)
            ));
        } else if base_variables != preferred {
            let own = &preferred_eq.states[*k];
            changes.push(format!(
                "{}: {} variable (the model's own state is {})",
                states[i],
                variables_name(base_variables),
                own.name
            ));
        }
    }
    if reordered {
        changes.push(format!(
            "states in the order {} (the model's: {})",
            states.join(", "),
            names(preferred_eq)
        ));
    }
    notes.push(
        "every entry of A and B agrees after the change of variables, so do the transfer functions from every input to every state"
            .to_string(),
    );
    Comparison {
        verdict: Verdict::Similar {
            changes,
            entries_checked: true,
        },
        notes,
    }
}

fn different(notes: Vec<String>, first: String) -> Comparison {
    Comparison {
        verdict: Verdict::Different { first },
        notes,
    }
}

fn variables_name(v: Variables) -> &'static str {
    match v {
        Variables::Energy => "energy",
        Variables::CoEnergy => "co-energy",
    }
}

fn power_name(power: usize) -> String {
    match power {
        0 => "s^0 (the constant)".to_string(),
        1 => "s".to_string(),
        p => format!("s^{p}"),
    }
}

/// Each answer state matched to a model state, if every name is one and none repeats.
fn match_states(
    states: &[String],
    energy: &StateEquations,
    coenergy: &StateEquations,
) -> Option<Vec<Matched>> {
    let mut seen = vec![false; energy.state_count()];
    let mut out = Vec::new();
    for name in states {
        let name = name.trim();
        let alias = name.strip_prefix("x_").map(|rest| format!("q_{rest}"));
        let found = energy
            .state_named(name)
            .map(|k| (k, false))
            .or_else(|| coenergy.state_named(name).map(|k| (k, true)))
            .or_else(|| {
                alias
                    .and_then(|a| energy.state_named(&a))
                    .map(|k| (k, false))
            })?;
        if std::mem::replace(&mut seen[found.0], true) {
            return None;
        }
        out.push(Matched {
            state: found.0,
            coenergy: found.1,
        });
    }
    Some(out)
}

/// Whether each co-energy state is its energy state over its storage, exactly: then
/// `A_c = S⁻¹ A_e S`, `B_c = S⁻¹ B_e`, `E_c = S⁻¹ E_e` with `S = diag(storage)`.
fn scaling_is_diagonal(energy: &StateEquations, coenergy: &StateEquations) -> bool {
    let storage: Vec<RatFunc> = energy.states.iter().map(|s| s.storage.clone()).collect();
    let Some(inverse) = storage.iter().map(RatFunc::inv).collect::<Option<Vec<_>>>() else {
        return false;
    };
    let (ae, ac) = (energy.a(), coenergy.a());
    let n = storage.len();
    let a_ok = (0..n).all(|i| (0..n).all(|j| ac[i][j] == &(&inverse[i] * &ae[i][j]) * &storage[j]));
    let columns_ok = |e: Matrix, c: Matrix| {
        e.iter()
            .zip(&c)
            .enumerate()
            .all(|(i, (re, rc))| re.iter().zip(rc).all(|(x, y)| *y == &inverse[i] * x))
    };
    a_ok && columns_ok(energy.b(), coenergy.b()) && columns_ok(energy.e(), coenergy.e())
}

/// The first entry (row-major, `A` then `B` then `E`) where the answer differs from `base`
/// transformed by `map` (answer state `i` = `scale_i` · base state `k_i`).
fn first_difference(
    base: &StateEquations,
    map: &[(usize, RatFunc)],
    answer: &Answer,
    symbols: &SymbolTable,
) -> Option<String> {
    let n = map.len();
    let (a, b, e) = (base.a(), base.b(), base.e());
    let name = |i: usize| -> String {
        answer
            .states
            .as_ref()
            .map_or_else(|| base.states[map[i].0].name.clone(), |s| s[i].clone())
    };
    let report = |matrix: &str, i: usize, j: usize, what: String, got: &RatFunc, want: &RatFunc| {
        format!(
            "{matrix}[{}][{}] (d{}/dt, {what}) is {} in the answer, {} in the model",
            i + 1,
            j + 1,
            name(i),
            got.text(symbols),
            want.text(symbols)
        )
    };
    for (i, (ki, si)) in map.iter().enumerate() {
        for (j, (kj, sj)) in map.iter().enumerate() {
            let want = (si * &a[*ki][*kj]).checked_div(sj).unwrap_or_default();
            if answer.a[i][j] != want {
                return Some(report(
                    "A",
                    i,
                    j,
                    format!("coefficient of {}", name(j)),
                    &answer.a[i][j],
                    &want,
                ));
            }
        }
    }
    let zero = vec![vec![RatFunc::zero(); base.inputs.len()]; n];
    for (label, model, given) in [
        ("B", &b, &answer.b),
        ("E", &e, answer.e.as_ref().unwrap_or(&zero)),
    ] {
        for (i, (ki, si)) in map.iter().enumerate() {
            for (j, input) in base.inputs.iter().enumerate() {
                let want = si * &model[*ki][j];
                let got = given[i].get(j).cloned().unwrap_or_default();
                if got != want {
                    let what = if label == "B" {
                        format!("coefficient of {input}")
                    } else {
                        format!("coefficient of d{input}/dt")
                    };
                    return Some(report(label, i, j, what, &got, &want));
                }
            }
        }
    }
    None
}
