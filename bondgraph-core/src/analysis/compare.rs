//! The verdict on an answer: equal to the model's equations, equal up to a change of state
//! variables, or different at a named entry or coefficient.
//!
//! A change of state variables `z = T x` (any invertible `T`) turns the model's `(A, B, E)`
//! into `(T A T⁻¹, T B, T E)`. How `T` is had decides how much is checked:
//!
//! - **States named as the model's** (`p_mass` or `v_mass`, `q_spring`, `x_spring` or
//!   `f_spring`): `T` is a reordering and, for co-energy states, a scaling by the storage
//!   (`v = p/m`, `f = q/C`, checked exactly against the model's own co-energy derivation).
//! - **States written as combinations of the model's** (`"-q_spring"`,
//!   `"p_mass + b*q_spring"`, `"q_tyre + q_spring"`, with coefficients rational in the
//!   parameters): `T` is what the answer says.
//!
//! With `T` fixed every entry of `A`, `B`, `E` is compared exactly and the first that
//! differs named. **Unnamed states** (or names that are neither) leave `T` open: the answer
//! is similar when an invertible `T` with `T A = A' T`, `T B = B'`, `T E = E'` exists,
//! found exactly (`analysis/similarity.rs`) and reported, so that a reader sees which states
//! the answer's must be. That is a weaker check: with one input any two controllable pairs
//! with the same characteristic polynomial are similar, so a wrong gain in `B` shows only in
//! `T` (`z2 = 2*p_mass`), which the verdict asks to confirm by naming the states.
//!
//! Everything is exact: symbolic in the parameters up to [`SYMBOLIC_STATES`] states; beyond,
//! the search for `T` is done exactly at the parameter values and again at a second,
//! independent parameter point.

use super::answer::Answer;
use super::similarity::{self, Similarity, System, matrix_at_point};
use super::{Matrix, SYMBOLIC_STATES, characteristic, polynomial_text};
use crate::analysis::characteristic::product;
use crate::equations::matrix::inverse;
use crate::equations::{StateEquations, Variables};
use crate::symbolic::{Monomial, Poly, RatFunc, Symbol, SymbolTable};

/// What the comparison found.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// The answer's `A`, `B` (and `E`) are the model's, entry by entry, in the model's
    /// states.
    Equal,
    /// The answer is the model's equations after a change of state variables.
    Similar {
        /// What the change is, one line each (`v_mass = p_mass/m`, a reordering,
        /// `z2 = p_mass + b*q_spring`, `T = ...`).
        changes: Vec<String>,
        /// Whether every entry was checked: always, now that `T` is either fixed by the
        /// states' names or found (kept for the JSON field of that name).
        entries_checked: bool,
    },
    /// The answer differs from the model's equations.
    Different {
        /// The first entry or coefficient that differs, with both values.
        first: String,
    },
}

/// A change of state variables `z = T x` between the model's states `x` and the answer's
/// `z`.
#[derive(Clone, Debug, PartialEq)]
pub struct Transformation {
    /// `T`: rows the answer's states, columns the model's. Exact in the parameters when
    /// `symbolic`, else exact numbers at the model's parameter values.
    pub t: Matrix,
    /// The model's states `x`, in the variables `T` is written over.
    pub from: Vec<String>,
    /// The answer's states `z`: its names, or `z1`, `z2`, … when it names none.
    pub to: Vec<String>,
    /// Whether the answer's state names gave `T` (else it was searched for).
    pub given: bool,
    /// Whether `T` is the only one (always, when given).
    pub unique: bool,
    /// Whether `T`'s entries are symbolic in the parameters.
    pub symbolic: bool,
}

impl Transformation {
    /// Each answer state as a combination of the model's: `z2 = p_mass + b*q_spring`.
    pub fn rows_text(&self, symbols: &SymbolTable) -> Vec<String> {
        self.t
            .iter()
            .zip(&self.to)
            .map(|(row, name)| format!("{name} = {}", self.combination(row, symbols)))
            .collect()
    }

    /// `T` as one line, `T = [[0, 1], [1, b]]`.
    pub fn matrix_text(&self, symbols: &SymbolTable) -> String {
        let rows: Vec<String> = self
            .t
            .iter()
            .map(|row| {
                let cells: Vec<String> = row.iter().map(|x| self.number(x, symbols)).collect();
                format!("[{}]", cells.join(", "))
            })
            .collect();
        format!("[{}]", rows.join(", "))
    }

    /// The entries as text, one row each (for JSON).
    pub fn entries_text(&self, symbols: &SymbolTable) -> Vec<Vec<String>> {
        self.t
            .iter()
            .map(|row| row.iter().map(|x| self.number(x, symbols)).collect())
            .collect()
    }

    /// An entry as text: symbolic, a simple fraction, or six significant digits.
    fn number(&self, x: &RatFunc, symbols: &SymbolTable) -> String {
        if self.symbolic || x.to_constant().is_some_and(|(_, d)| d < 1000.into()) {
            x.text(symbols)
        } else {
            short_number(x.eval(&[]))
        }
    }

    /// `Σⱼ row[j] xⱼ` as text: `p_mass + b*q_spring`.
    fn combination(&self, row: &[RatFunc], symbols: &SymbolTable) -> String {
        let mut out = String::new();
        for (x, name) in row.iter().zip(&self.from) {
            if x.is_zero() {
                continue;
            }
            // The sign pulled out when every numerator term is negative: `- p_mass/m`.
            let negative = x.signed_text(symbols).0;
            let magnitude = self.number(&if negative { -x.clone() } else { x.clone() }, symbols);
            let term = product_text(&magnitude, name);
            match (out.is_empty(), negative) {
                (true, false) => out.push_str(&term),
                (true, true) => out.push_str(&format!("-{term}")),
                (false, false) => out.push_str(&format!(" + {term}")),
                (false, true) => out.push_str(&format!(" - {term}")),
            }
        }
        if out.is_empty() {
            out.push('0');
        }
        out
    }
}

/// A verdict and what was checked on the way.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The verdict.
    pub verdict: Verdict,
    /// What was checked, one sentence each.
    pub notes: Vec<String>,
    /// The change of state variables that was checked or found, if any.
    pub transformation: Option<Transformation>,
    /// `det(sI - A)` of the model and of the answer, as text.
    pub polynomials: [String; 2],
}

/// One answer state matched to a model state.
struct Matched {
    /// The model state's index.
    state: usize,
    /// Whether the answer writes it in co-energy variables.
    coenergy: bool,
}

/// The comparison where the answer's states fix the change of variables: named as the
/// model's (in energy or co-energy variables), or written as combinations of them.
fn given_states(
    mut out: Comparison,
    fixed: Result<(&StateEquations, Matrix, bool), ()>,
    answer: &Answer,
    (preferred_eq, preferred): (&StateEquations, Variables),
    (poly_difference, polynomials_note): (Option<String>, String),
) -> Comparison {
    let symbols = &preferred_eq.symbols;
    let n = answer.a.len();
    let Ok((base, t, plain)) = fixed else {
        out.notes.push(
            "the co-energy variables of this mode are not each one energy variable over its storage; write all states in energy or all in co-energy variables"
                .to_string(),
        );
        return out.different(
            "the states mix energy and co-energy variables of coupled storage".to_string(),
        );
    };
    let states = answer.states.as_deref().unwrap_or_default();
    let transformation = Transformation {
        t: t.clone(),
        from: base.states.iter().map(|s| s.name.clone()).collect(),
        to: states.to_vec(),
        given: true,
        unique: true,
        symbolic: true,
    };
    let Some(t_inverse) = inverse(&t) else {
        out.transformation = Some(transformation);
        return out.different(format!(
            "the answer's states ({}) are not independent: T is singular",
            states.join(", ")
        ));
    };
    if let Some((first, in_a)) = first_difference(base, &t, &t_inverse, answer, symbols) {
        match poly_difference {
            Some(poly) => {
                out.notes.push(poly);
                out.notes.push(polynomials_note);
            }
            None => out.explain_difference(preferred_eq, answer, in_a),
        }
        return out.different(first);
    }
    let identity = t == super::characteristic::identity(n);
    let base_variables = if base.variables == Variables::CoEnergy {
        Variables::CoEnergy
    } else {
        Variables::Energy
    };
    if identity && base_variables == preferred {
        return out;
    }
    let changes = if plain {
        plain_changes(
            &t,
            base,
            preferred_eq,
            states,
            base_variables,
            preferred,
            symbols,
        )
    } else {
        // The states as the model's, where that says more than the answer's own text
        // (`v_wheel = p_wheel/m_w`), and T.
        let mut changes: Vec<String> = transformation
            .rows_text(symbols)
            .into_iter()
            .zip(states)
            .filter(|(row, state)| *row != format!("{} = {}", state, state.trim()))
            .map(|(row, _)| row)
            .collect();
        changes.push(format!(
            "T = {} (z = T x, z = ({}), x = ({}))",
            transformation.matrix_text(symbols),
            states.join(", "),
            transformation.from.join(", ")
        ));
        changes
    };
    out.transformation = Some(transformation);
    out.notes.push(
        "every entry of A and B agrees after the change of variables, so do the transfer functions from every input to every state"
            .to_string(),
    );
    out.verdict = Verdict::Similar {
        changes,
        entries_checked: true,
    };
    out
}

/// An answer similar to the model by the change of variables `transformation` found for it.
fn similar(
    mut out: Comparison,
    transformation: Transformation,
    symbols: &SymbolTable,
) -> Comparison {
    let (n, symbolic, unique) = (
        transformation.from.len(),
        transformation.symbolic,
        transformation.unique,
    );
    let mut changes = transformation.rows_text(symbols);
    if n <= SYMBOLIC_STATES {
        changes.push(format!(
            "T = {} (z = T x, x = ({}))",
            transformation.matrix_text(symbols),
            transformation.from.join(", ")
        ));
    }
    out.notes.push(format!(
            "T A = A' T and T B = B' hold {}, with T invertible{}",
            if symbolic {
                "exactly, for every value of the parameters"
            } else {
                "exactly at the parameter values and at a second parameter point (each value scaled by its own factor between 1.1 and 1.9); T is shown at the parameter values"
            },
            if unique {
                " and the only solution"
            } else {
                "; T is not unique (the inputs do not reach every state), this is one"
            }
        ));
    out.notes.push(
            "T is what the answer's states must be for it to be right: name them as the model does, or write them as combinations of its states (\"-q_spring\"), to have that checked"
                .to_string(),
        );
    out.transformation = Some(transformation);
    out.verdict = Verdict::Similar {
        changes,
        entries_checked: true,
    };
    out
}

/// Compares `answer` with one mode's equations, derived in energy (`energy`) and co-energy
/// (`coenergy`) variables; `preferred` is the model's own choice (what "equal" means).
///
/// # Complexity
/// Two characteristic polynomials (`O(n⁴)` exact operations), `O(n³)` for a `T` the states
/// fix, and, when `T` is searched for, elimination on `n²` unknowns (`O(n⁶)`).
pub fn compare(
    energy: &StateEquations,
    coenergy: &StateEquations,
    preferred: Variables,
    answer: &Answer,
) -> Comparison {
    let symbols = &energy.symbols;
    let n = energy.state_count();
    let m = energy.inputs.len();
    let preferred_eq = match preferred {
        Variables::Energy => energy,
        Variables::CoEnergy => coenergy,
    };
    let mut out = Comparison {
        verdict: Verdict::Equal,
        notes: Vec::new(),
        transformation: None,
        polynomials: [String::new(), String::new()],
    };
    let names = |eq: &StateEquations| {
        eq.states
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if answer.a.len() != n {
        return out.different(format!(
            "the answer has {} states; the model has {n} in this mode ({})",
            answer.a.len(),
            names(energy)
        ));
    }
    if let Some(row) = answer.b.first().filter(|row| row.len() != m) {
        return out.different(format!(
            "B has {} columns; the model has {m} inputs ({})",
            row.len(),
            energy.inputs.join(", ")
        ));
    }
    // The characteristic polynomial: invariant under any change of state variables.
    let model_poly = characteristic(&energy.a()).coefficients;
    let answer_poly = characteristic(&answer.a).coefficients;
    let text =
        |p: &[RatFunc]| polynomial_text(&p.iter().rev().cloned().collect::<Vec<_>>(), symbols);
    out.polynomials = [text(&model_poly), text(&answer_poly)];
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
    let polynomials_note = format!(
        "det(sI - A) is {} in the answer, {} in the model",
        out.polynomials[1], out.polynomials[0]
    );
    if poly_difference.is_none() {
        out.notes
            .push("same characteristic polynomial det(sI - A)".to_string());
    }

    // T fixed by the answer's states: named as the model's, or combinations of them.
    let fixed = match answer.states.as_ref() {
        Some(states) => match match_states(states, energy, coenergy) {
            Some(matched) => Some(named(&matched, energy, coenergy)),
            None => combinations(states, energy, coenergy)
                .map(|given| given.map(|(base, t)| (base, t, false))),
        },
        None => None,
    };
    if let Some(fixed) = fixed {
        return given_states(
            out,
            fixed,
            answer,
            (preferred_eq, preferred),
            (poly_difference, polynomials_note),
        );
    }

    if answer.states.is_some() {
        out.notes.push(format!(
            "the answer's states are neither the model's ({}, or {}) nor combinations of them",
            names(energy),
            names(coenergy)
        ));
    }
    // Unnamed: entry by entry against the model's own variables, else a change of
    // variables searched for.
    let identity = super::characteristic::identity(n);
    if first_difference(preferred_eq, &identity, &identity, answer, symbols).is_none() {
        return out;
    }
    if let Some(poly) = poly_difference {
        out.notes.push(polynomials_note);
        return out.different(poly);
    }
    let (found, points) = search(preferred_eq, answer, true);
    let symbolic = points.is_none();
    let to: Vec<String> = match &answer.states {
        Some(states) => states.clone(),
        None => (1..=n).map(|i| format!("z{i}")).collect(),
    };
    match found {
        Similarity::Found { t, unique } => {
            let transformation = Transformation {
                t,
                from: preferred_eq.states.iter().map(|s| s.name.clone()).collect(),
                to,
                given: false,
                unique,
                symbolic,
            };
            similar(out, transformation, symbols)
        }
        Similarity::NoSolution | Similarity::Singular { .. } => {
            let why = no_t_reason(preferred_eq, answer, &found, points);
            out.different(why)
        }
    }
}

impl Comparison {
    fn different(mut self, first: String) -> Comparison {
        self.verdict = Verdict::Different { first };
        self
    }

    /// When the characteristic polynomials agree but a fixed `T` found a difference: is the
    /// answer the model's in other states, or does its input coupling differ?
    fn explain_difference(&mut self, base: &StateEquations, answer: &Answer, in_a: bool) {
        let n = base.state_count();
        if !in_a {
            self.notes.push(
                "A agrees entry by entry (so does det(sI - A)): the input coupling differs"
                    .to_string(),
            );
        }
        let (found, points) = search(base, answer, true);
        let symbolic = points.is_none();
        match found {
            Similarity::Found { t, unique } => {
                let transformation = Transformation {
                    t,
                    from: base.states.iter().map(|s| s.name.clone()).collect(),
                    to: (1..=n).map(|i| format!("z{i}")).collect(),
                    given: false,
                    unique,
                    symbolic,
                };
                let rows = transformation.rows_text(&base.symbols).join(", ");
                // A long T is no natural choice of states; JSON has it all the same.
                let states = if rows.len() <= 160 {
                    format!("z = T x with {rows}")
                } else {
                    "z = T x (T is in the JSON output)".to_string()
                };
                self.notes.push(format!(
                    "the answer's A and B are the model's {} states {states}, not in the states as written",
                    if unique { "in the" } else { "for example in the" },
                ));
                self.transformation = Some(transformation);
            }
            other => {
                if in_a {
                    self.notes.push(no_t_reason(base, answer, &other, points));
                }
            }
        }
    }
}

/// Why no `T` exists when the characteristic polynomials agree, in words; `points` as
/// [`search`] gives it. The input coupling is blamed only if `A'` alone is `A` in other
/// states (`T A = A' T` with `T` invertible); else `A` itself differs (a repeated
/// eigenvalue with fewer eigenvectors, say).
fn no_t_reason(
    base: &StateEquations,
    answer: &Answer,
    found: &Similarity,
    points: Option<usize>,
) -> String {
    let at = match points {
        None => "",
        Some(0) => " (checked exactly at the parameter values)",
        Some(_) => {
            " (checked exactly at a second parameter point, each value scaled by its own factor; at the parameter values one exists)"
        }
    };
    let (a_alone, _) = search(base, answer, false);
    if !matches!(a_alone, Similarity::Found { .. }) {
        return format!(
            "the characteristic polynomials agree, but no invertible T has T A = A' T{at}: A is not the model's in any state variables (its eigenvectors differ)"
        );
    }
    let why = match found {
        Similarity::Singular {
            ranks: Some((model, answer)),
        } => format!(
            "the inputs reach {answer} state directions in the answer and {model} in the model (the rank of [B, AB, ...]), so no invertible T with T A = A' T and T B = B' exists{at}"
        ),
        Similarity::Singular { ranks: None } => {
            format!("every T with T A = A' T and T B = B' is singular{at}")
        }
        _ => format!("no change of state variables T with T A = A' T and T B = B' exists{at}"),
    };
    format!("the characteristic polynomials agree, but {why}: the input coupling differs")
}

/// The search for `T` from `base`'s states to the answer's (`inputs`: with `B` and `E`,
/// else `A` alone): symbolic up to
/// [`SYMBOLIC_STATES`] states (`None`), else exact at the parameter values and at a second
/// point (each value scaled by its own factor), with how many points passed before the
/// result (`Some(2)` when both did; the first point's `T` is reported).
fn search(base: &StateEquations, answer: &Answer, inputs: bool) -> (Similarity, Option<usize>) {
    let n = base.state_count();
    let zero = vec![vec![RatFunc::zero(); base.inputs.len()]; n];
    let (a, mut b, mut e) = (base.a(), base.b(), base.e());
    let mut answer_b = answer.b.clone();
    let mut answer_e = answer.e.clone().unwrap_or_else(|| zero.clone());
    if !inputs {
        let none = vec![Vec::new(); n];
        (b, e, answer_b, answer_e) = (none.clone(), none.clone(), none.clone(), none);
    }
    let fresh = u32::try_from(base.symbols.len()).unwrap_or(u32::MAX / 2);
    let run = |a: &Matrix, b: &Matrix, e: &Matrix, a2: &Matrix, b2: &Matrix, e2: &Matrix| {
        similarity::similarity(
            System { a, b, e },
            System {
                a: a2,
                b: b2,
                e: e2,
            },
            fresh,
        )
    };
    if n <= SYMBOLIC_STATES {
        return (run(&a, &b, &e, &answer.a, &answer_b, &answer_e), None);
    }
    let mut first = None;
    let mut passed = 0;
    for point in parameter_points(&base.values) {
        let at = |x: &Matrix| matrix_at_point(x, &point);
        let (Some(a), Some(b), Some(e), Some(a2), Some(b2), Some(e2)) = (
            at(&a),
            at(&b),
            at(&e),
            at(&answer.a),
            at(&answer.b),
            at(&answer_e),
        ) else {
            // An entry undefined at this point (a pole): the other point decides.
            continue;
        };
        let found = run(&a, &b, &e, &a2, &b2, &e2);
        if !matches!(found, Similarity::Found { .. }) {
            return (found, Some(passed));
        }
        passed += 1;
        first.get_or_insert(found);
    }
    (first.unwrap_or(Similarity::NoSolution), Some(passed))
}

/// The model's parameter values as exact decimals, and a second point with each value
/// scaled by its own factor in [1.1, 1.9) (the fractional parts of multiples of the golden
/// ratio, so no two factors agree and none is a simple ratio of another).
fn parameter_points(values: &[f64]) -> [Vec<RatFunc>; 2] {
    let exact = |v: f64| {
        let magnitude = RatFunc::from_decimal(&format!("{:e}", v.abs())).unwrap_or_default();
        if v < 0.0 { -magnitude } else { magnitude }
    };
    let golden = 0.618_033_988_749_894_9_f64;
    let first: Vec<RatFunc> = values.iter().map(|&v| exact(v)).collect();
    let second = values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let factor = 1.1 + 0.8 * ((i + 1) as f64 * golden).fract();
            let factor = RatFunc::from_decimal(&format!("{factor:.9}")).unwrap_or_default();
            &exact(v) * &factor
        })
        .collect();
    [first, second]
}

/// `T` from states named as the model's: answer state `i` = `scale_i` · base state `k_i`.
/// `Err` when they mix energy and co-energy variables of coupled storage.
fn named<'a>(
    matched: &[Matched],
    energy: &'a StateEquations,
    coenergy: &'a StateEquations,
) -> Result<(&'a StateEquations, Matrix, bool), ()> {
    let n = matched.len();
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
        return Err(());
    };
    let mut t = vec![vec![RatFunc::zero(); n]; n];
    for (i, (k, scale)) in map.into_iter().enumerate() {
        t[i][k] = scale;
    }
    Ok((base, t, true))
}

/// The changes a `T` of named states makes, as the verdict lists them: `v_mass =
/// p_mass/m`, a co-energy state, a reordering.
fn plain_changes(
    t: &Matrix,
    base: &StateEquations,
    preferred_eq: &StateEquations,
    states: &[String],
    base_variables: Variables,
    preferred: Variables,
    symbols: &SymbolTable,
) -> Vec<String> {
    let map: Vec<(usize, &RatFunc)> = t
        .iter()
        .map(|row| {
            row.iter()
                .enumerate()
                .find(|(_, x)| !x.is_zero())
                .unwrap_or((0, &row[0]))
        })
        .collect();
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
    if map.iter().enumerate().any(|(i, (k, _))| i != *k) {
        let names: Vec<&str> = preferred_eq
            .states
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        changes.push(format!(
            "states in the order {} (the model's: {})",
            states.join(", "),
            names.join(", ")
        ));
    }
    changes
}

/// `T` from states written as combinations of the model's (`"-q_spring"`, `"p_mass +
/// b*q_spring"`, `"q_tyre + q_spring"`): `None` unless every state is one, each a non-zero
/// linear form in the model's states (energy names, their `x_` aliases, or co-energy
/// names) with coefficients rational in the parameters; `Err` when energy and co-energy
/// variables of coupled storage are mixed.
fn combinations<'a>(
    states: &[String],
    energy: &'a StateEquations,
    coenergy: &'a StateEquations,
) -> Option<Result<(&'a StateEquations, Matrix), ()>> {
    let symbols = &energy.symbols;
    let n = energy.state_count();
    let base = u32::try_from(symbols.len()).ok()?;
    // Energy state k is the symbol base + k, co-energy state k is base + n + k.
    let index = |k: usize| base + u32::try_from(k).unwrap_or(0);
    let resolve = |name: &str| -> Option<RatFunc> {
        let alias = name.strip_prefix("x_").map(|rest| format!("q_{rest}"));
        if let Some(k) = energy
            .state_named(name)
            .or_else(|| alias.and_then(|a| energy.state_named(&a)))
        {
            return Some(RatFunc::symbol(Symbol(index(k))));
        }
        if let Some(k) = coenergy.state_named(name) {
            return Some(RatFunc::symbol(Symbol(index(n + k))));
        }
        symbols.get(name).map(RatFunc::symbol)
    };
    let mut rows = Vec::new();
    for text in states {
        let value = super::answer::rational_with(text, &resolve).ok()?;
        let row = linear_coefficients(&value, base, 2 * n)?;
        if row.iter().all(RatFunc::is_zero) {
            return None;
        }
        rows.push(row);
    }
    let uses = |range: std::ops::Range<usize>| {
        rows.iter()
            .any(|row| row[range.clone()].iter().any(|x| !x.is_zero()))
    };
    let (uses_energy, uses_coenergy) = (uses(0..n), uses(n..2 * n));
    Some(if !uses_coenergy {
        Ok((
            energy,
            rows.into_iter().map(|row| row[..n].to_vec()).collect(),
        ))
    } else if !uses_energy {
        Ok((
            coenergy,
            rows.into_iter().map(|row| row[n..].to_vec()).collect(),
        ))
    } else if scaling_is_diagonal(energy, coenergy) {
        // A co-energy state is its energy state over its storage.
        let t = rows
            .into_iter()
            .map(|row| {
                (0..n)
                    .map(|k| {
                        let over = row[n + k]
                            .checked_div(&energy.states[k].storage)
                            .unwrap_or_default();
                        &row[k] + &over
                    })
                    .collect()
            })
            .collect();
        Ok((energy, t))
    } else {
        Err(())
    })
}

/// The coefficients of `value` in the symbols `base..base + count`, if it is linear and
/// homogeneous in them (coefficients free of them).
fn linear_coefficients(value: &RatFunc, base: u32, count: usize) -> Option<Vec<RatFunc>> {
    let is_state = |s: Symbol| s.0 >= base;
    if value.denominator().symbols().into_iter().any(is_state) {
        return None;
    }
    let mut terms: Vec<Vec<(Monomial, num_bigint::BigInt)>> = vec![Vec::new(); count];
    for (monomial, c) in value.numerator().terms() {
        let mut state = None;
        for (s, e) in monomial.iter() {
            if is_state(s) {
                if e != 1 || state.is_some() {
                    return None;
                }
                state = Some(s);
            }
        }
        let s = state?;
        let rest = Monomial::new(monomial.iter().filter(|(x, _)| *x != s));
        terms[(s.0 - base) as usize].push((rest, c.clone()));
    }
    terms
        .into_iter()
        .map(|t| RatFunc::from_polys(Poly::from_terms(t), value.denominator().clone()))
        .collect()
}

/// `coefficient * name` as a textbook writes it: `p_mass/m` rather than `1/m*p_mass`,
/// parentheses around a bare sum.
fn product_text(magnitude: &str, name: &str) -> String {
    let sum = magnitude
        .char_indices()
        .scan(0i32, |depth, (i, c)| {
            match c {
                '(' => *depth += 1,
                ')' => *depth -= 1,
                _ => {}
            }
            Some(i > 0 && *depth == 0 && (c == '+' || c == '-'))
        })
        .any(|x| x);
    if magnitude == "1" {
        name.to_string()
    } else if let Some(denominator) = magnitude.strip_prefix("1/") {
        format!("{name}/{denominator}")
    } else if sum {
        format!("({magnitude})*{name}")
    } else {
        format!("{magnitude}*{name}")
    }
}

/// A number with six significant digits, without trailing zeros.
fn short_number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if (-3.0..6.0).contains(&magnitude) {
        let decimals = usize::try_from((5.0 - magnitude) as i64).unwrap_or(0);
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{x:.5e}")
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
/// in the states `z = T x` (`T A T⁻¹`, `T B`, `T E`), and whether it is in `A`.
fn first_difference(
    base: &StateEquations,
    t: &Matrix,
    t_inverse: &Matrix,
    answer: &Answer,
    symbols: &SymbolTable,
) -> Option<(String, bool)> {
    let n = t.len();
    let a = product(&product(t, &base.a()), t_inverse);
    let (b, e) = (product(t, &base.b()), product(t, &base.e()));
    let name = |i: usize| -> String {
        let name = answer
            .states
            .as_ref()
            .map_or_else(|| base.states[i].name.clone(), |s| s[i].trim().to_string());
        if name.chars().all(|c| c.is_alphanumeric() || c == '_') {
            name
        } else {
            format!("({name})")
        }
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
    for (i, (got_row, want_row)) in answer.a.iter().zip(&a).enumerate() {
        for (j, (got, want)) in got_row.iter().zip(want_row).enumerate() {
            if got != want {
                let what = format!("coefficient of {}", name(j));
                return Some((report("A", i, j, what, got, want), true));
            }
        }
    }
    let zero = vec![vec![RatFunc::zero(); base.inputs.len()]; n];
    for (label, model, given) in [
        ("B", &b, &answer.b),
        ("E", &e, answer.e.as_ref().unwrap_or(&zero)),
    ] {
        for i in 0..n {
            for (j, input) in base.inputs.iter().enumerate() {
                let want = &model[i][j];
                let got = given[i].get(j).cloned().unwrap_or_default();
                if got != *want {
                    let what = if label == "B" {
                        format!("coefficient of {input}")
                    } else {
                        format!("coefficient of d{input}/dt")
                    };
                    return Some((report(label, i, j, what, &got, want), false));
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{equations, laws};

    /// Three masses in a chain (five states, past `SYMBOLIC_STATES`): F pushes the first,
    /// G the third, the third is damped; m1 = 1 so that `1/m1^2` and `1/m1` agree at the
    /// parameter values.
    fn chain() -> (StateEquations, StateEquations) {
        let model = crate::testing::model(
            r#"Model(
    name: "chain",
    parameters: {
        "m1": (value: 1.0, unit: "kg"), "m2": (value: 2.0, unit: "kg"),
        "m3": (value: 4.0, unit: "kg"), "k1": (value: 10.0, unit: "N/m"),
        "k2": (value: 20.0, unit: "N/m"), "b": (value: 3.0, unit: "N*s/m"),
    },
    inputs: { "F": (unit: "N"), "G": (unit: "N") },
    elements: {
        "force": Se(effort: "F"), "v1": One, "mass1": I(inertance: "m1"),
        "c1": Zero, "spring1": C(stiffness: "k1"),
        "v2": One, "mass2": I(inertance: "m2"),
        "c2": Zero, "spring2": C(stiffness: "k2"),
        "v3": One, "mass3": I(inertance: "m3"), "damper": R(resistance: "b"),
        "push": Se(effort: "G"),
    },
    bonds: [
        ("force", "v1"), ("v1", "mass1"), ("v1", "c1"), ("c1", "spring1"), ("c1", "v2"),
        ("v2", "mass2"), ("v2", "c2"), ("c2", "spring2"), ("c2", "v3"),
        ("v3", "mass3"), ("v3", "damper"), ("push", "v3"),
    ],
)"#,
        );
        let derive = |variables| {
            equations::derive(
                &model,
                &laws::plain_laws(&model),
                &equations::Options { variables },
            )
            .unwrap()
        };
        (derive(Variables::Energy), derive(Variables::CoEnergy))
    }

    /// The answer in `z = T x` for a signed permutation `T` (so `T⁻¹ = Tᵀ`): `z_i = sign_i
    /// x_{order_i}`.
    fn permuted(eq: &StateEquations, order: &[usize], sign: &[i64]) -> (Matrix, Answer) {
        let n = order.len();
        let mut t = vec![vec![RatFunc::zero(); n]; n];
        for i in 0..n {
            t[i][order[i]] = RatFunc::integer(sign[i]);
        }
        let transpose: Matrix = (0..n)
            .map(|i| (0..n).map(|j| t[j][i].clone()).collect())
            .collect();
        let answer = Answer {
            states: None,
            a: product(&product(&t, &eq.a()), &transpose),
            b: product(&t, &eq.b()),
            e: None,
        };
        (t, answer)
    }

    #[test]
    fn five_states_are_compared_at_two_parameter_points() {
        let (energy, coenergy) = chain();
        assert_eq!(energy.state_count(), 5);
        let names: Vec<&str> = energy.states.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(
            names,
            ["p_mass1", "q_spring1", "p_mass2", "q_spring2", "p_mass3"]
        );
        // z = (q_spring1, -p_mass1, q_spring2, p_mass3, -p_mass2).
        let (t, answer) = permuted(&energy, &[1, 0, 3, 4, 2], &[1, -1, 1, 1, -1]);
        let found = compare(&energy, &coenergy, Variables::Energy, &answer);
        assert!(
            matches!(found.verdict, Verdict::Similar { .. }),
            "{found:?}"
        );
        let transformation = found.transformation.unwrap();
        assert!(!transformation.symbolic && transformation.unique);
        assert_eq!(transformation.t, t);
        assert_eq!(
            transformation.rows_text(&energy.symbols)[1],
            "z2 = -p_mass1"
        );

        // F's column scaled by 1/m1: the same at the values (m1 = 1), not at the second
        // point, where no T maps both columns.
        let (_, mut wrong) = permuted(&energy, &[1, 0, 3, 4, 2], &[1, -1, 1, 1, -1]);
        let m1 = RatFunc::symbol(energy.symbols.get("m1").unwrap());
        for row in &mut wrong.b {
            row[0] = row[0].checked_div(&m1).unwrap();
        }
        let found = compare(&energy, &coenergy, Variables::Energy, &wrong);
        let Verdict::Different { first } = &found.verdict else {
            panic!("{found:?}");
        };
        assert!(
            first.contains("the characteristic polynomials agree")
                && first.contains("at a second parameter point")
                && first.contains("at the parameter values one exists"),
            "{first}"
        );
    }

    #[test]
    fn states_written_as_combinations_fix_t() {
        let (energy, coenergy) = chain();
        // The model's own equations, the states written as -(-p_mass1) and so on: T = I.
        let answer = Answer {
            states: Some(
                [
                    "-(-p_mass1)",
                    "x_spring1",
                    "m2*v_mass2",
                    "q_spring2",
                    "p_mass3",
                ]
                .map(String::from)
                .to_vec(),
            ),
            a: energy.a(),
            b: energy.b(),
            e: None,
        };
        let found = compare(&energy, &coenergy, Variables::Energy, &answer);
        assert_eq!(found.verdict, Verdict::Equal, "{found:?}");
        // A state that is not linear in the model's states is no combination: searched.
        let mut squared = answer.clone();
        squared.states.as_mut().unwrap()[0] = "p_mass1^2".to_string();
        let found = compare(&energy, &coenergy, Variables::Energy, &squared);
        assert!(
            found.notes.iter().any(|n| n.contains("nor combinations")),
            "{found:?}"
        );
        // Dependent states: T is singular.
        let mut dependent = answer;
        dependent.states.as_mut().unwrap()[1] = "2*p_mass1".to_string();
        let found = compare(&energy, &coenergy, Variables::Energy, &dependent);
        assert!(
            matches!(&found.verdict, Verdict::Different { first } if first.contains("not independent")),
            "{found:?}"
        );
    }

    #[test]
    fn same_polynomial_other_eigenvectors_is_not_blamed_on_b() {
        // Two free masses pushed by one force through a 0-junction: A = 0, det(sI - A) =
        // s^2. An answer with A' = [[0, 1], [0, 0]] has the same polynomial but one
        // eigenvector, so no T with T A = A' T is invertible, whatever B is.
        let model = crate::testing::model(
            r#"Model(
    name: "free",
    parameters: { "m1": (value: 1.0, unit: "kg"), "m2": (value: 2.0, unit: "kg") },
    inputs: { "F": (unit: "N") },
    elements: {
        "f": Se(effort: "F"), "split": Zero,
        "v1": One, "mass1": I(inertance: "m1"), "v2": One, "mass2": I(inertance: "m2"),
    },
    bonds: [("f", "split"), ("split", "v1"), ("v1", "mass1"), ("split", "v2"), ("v2", "mass2")],
)"#,
        );
        let derive = |variables| {
            equations::derive(
                &model,
                &laws::plain_laws(&model),
                &equations::Options { variables },
            )
            .unwrap()
        };
        let (energy, coenergy) = (derive(Variables::Energy), derive(Variables::CoEnergy));
        let (zero, one) = (RatFunc::zero(), RatFunc::one());
        let answer = Answer {
            states: None,
            a: vec![
                vec![zero.clone(), one.clone()],
                vec![zero.clone(), zero.clone()],
            ],
            b: vec![vec![zero], vec![one]],
            e: None,
        };
        let found = compare(&energy, &coenergy, Variables::Energy, &answer);
        let Verdict::Different { first } = &found.verdict else {
            panic!("{found:?}");
        };
        assert!(
            first.contains("no invertible T has T A = A' T") && !first.contains("input coupling"),
            "{first}"
        );
    }
}
