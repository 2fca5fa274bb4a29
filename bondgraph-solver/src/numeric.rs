//! A mode with numbers in: matrices, guard rows, and the maps between the mode's own states
//! and the model's full physical state.
//!
//! Modes have different states: a stuck contact merges two bodies into one momentum, a held
//! mass has none. The simulator therefore carries the **full state**, the energy variable
//! (momentum or displacement) of every storage element of the model, and each mode maps it
//! to and from its own states. Reconstruction `x_full = R x + S u + s` comes from the
//! derivation (`StateEquations::storage_energy`). Projection is its inverse in the energy
//! metric, `x = (Rᵀ W R)⁻¹ Rᵀ W (x_full - S u - s)` with `W` the inverse inertances and
//! compliances: for bodies that stick it conserves their total momentum (a perfectly plastic
//! contact), and for an unmerged state it is the identity.
//!
//! Equations with a term in the inputs' rates, `dx/dt = A x + B u + E du/dt + c` (storage
//! driven by an input, in co-energy variables), are carried in the variable `x' = x - E u`,
//! for which `dx'/dt = A x' + (B + A E) u + c` has no rates: inputs are piecewise linear, so
//! `x'` is continuous where they step and `x = x' + E u` jumps by `E Δu` exactly as the
//! rate's impulse would make it. Every row (guards, outputs, ports) and the maps to and from
//! the full state are rewritten in `x'` once, here, so nothing downstream sees `E`.

use bondgraph_core::guards::Watched;
use bondgraph_core::linear::{LinearForm, Var};
use bondgraph_core::model::{ElementId, ElementKind, ElementMode, Model};
use bondgraph_core::modes::{Mode, ModeEquations, NonlinearModeEquations};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::sync::Arc;

mod forms;

pub use forms::ModeForms;

use crate::nonlinear::{NonlinearForms, NonlinearNumeric, RowProgram, StorageLawTape};
use crate::propagate::Propagator;

/// The storage elements of a model, whose energy variables make up the full state.
#[derive(Clone, Debug)]
pub struct Storage {
    /// The storage elements, in element order.
    pub elements: Vec<ElementId>,
    /// Their energy variables' names (`p_mass`, `q_spring`).
    pub names: Vec<String>,
    /// Their inertances or compliances (1 for nonlinear storage, which is never merged).
    pub coefficients: Vec<f64>,
    /// The laws of nonlinear storage, for the energy they store.
    pub laws: Vec<Option<Arc<StorageLawTape>>>,
}

impl Storage {
    /// The storage elements of `model`: inertias, compliances and tension-only elements.
    pub fn of(model: &Model) -> Self {
        Self::with_values(model, model.values())
    }

    /// The storage elements of `model` with the parameter values `values` (indexed like
    /// [`Model::values`]) in their coefficients.
    pub fn with_values(model: &Model, values: &[f64]) -> Self {
        let mut storage = Storage {
            elements: Vec::new(),
            names: Vec::new(),
            coefficients: Vec::new(),
            laws: Vec::new(),
        };
        for id in model.element_ids() {
            let element = model.element(id);
            let (letter, coefficient) = match &element.kind {
                ElementKind::Inertia(c) => ("p", c.value.eval(values)),
                ElementKind::Compliance(c) => ("q", c.value.eval(values)),
                ElementKind::TensionOnly(t) => ("q", t.compliance.value.eval(values)),
                ElementKind::Nonlinear(nl) => match nl.law {
                    bondgraph_core::model::NonlinearLaw::Inertia(_) => ("p", 1.0),
                    bondgraph_core::model::NonlinearLaw::Compliance(_) => ("q", 1.0),
                    _ => continue,
                },
                _ => continue,
            };
            storage.elements.push(id);
            storage.names.push(match &element.symbol {
                Some(symbol) => symbol.clone(),
                None => bondgraph_core::model::state_symbol(letter, &element.name),
            });
            storage.coefficients.push(coefficient);
            storage
                .laws
                .push(StorageLawTape::of(model, id.index(), values).map(Arc::new));
        }
        storage
    }

    /// The number of storage elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// Whether the model stores no energy.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// The position of `element` in the full state.
    pub fn index(&self, element: ElementId) -> Option<usize> {
        self.elements.iter().position(|&e| e == element)
    }
}

/// An affine function of the mode's states, the inputs and the inputs' rates:
/// `y = c·x + d·u + r·u̇ + k`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Coefficients of the states.
    pub state: Vec<f64>,
    /// Coefficients of the inputs.
    pub input: Vec<f64>,
    /// Coefficients of the inputs' rates.
    pub rate: Vec<f64>,
    /// The constant.
    pub constant: f64,
    /// In a nonlinear mode, the compiled expression the row stands for (the affine parts
    /// above are then unused).
    pub program: Option<RowProgram>,
}

impl Row {
    /// Evaluates a symbolic form with the model's parameter values.
    pub fn from_form(form: &LinearForm, states: usize, inputs: usize, values: &[f64]) -> Self {
        let mut row = Row {
            state: vec![0.0; states],
            input: vec![0.0; inputs],
            rate: vec![0.0; inputs],
            constant: 0.0,
            program: None,
        };
        for (var, coefficient) in form.terms() {
            let value = coefficient.eval(values);
            match var {
                Var::State(i) => row.state[*i as usize] = value,
                Var::Input(i) => row.input[*i as usize] = value,
                Var::InputRate(i) => row.rate[*i as usize] = value,
                Var::Constant => row.constant = value,
                // Derivation resolves every other variable.
                Var::Dependent(_) | Var::Bond(_) | Var::Auxiliary(_) | Var::Storage(_) => {
                    row.constant = f64::NAN
                }
            }
        }
        row
    }

    /// A row standing for one value of a nonlinear mode's tape.
    pub fn program(program: RowProgram) -> Self {
        Row {
            state: Vec::new(),
            input: Vec::new(),
            rate: Vec::new(),
            constant: 0.0,
            program: Some(program),
        }
    }

    /// `y` at the state `x`, inputs `u` and rates `u̇`.
    pub fn eval(&self, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
        if let Some(program) = &self.program {
            return program.outputs(x, u, rate)[program.value];
        }
        dot(&self.state, x) + dot(&self.input, u) + dot(&self.rate, rate) + self.constant
    }

    /// The size of the terms of `y`: the scale against which `y ≈ 0` is judged.
    pub fn magnitude(&self, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
        if let Some(program) = &self.program {
            return program.outputs(x, u, rate)[program.magnitude];
        }
        let sum = |c: &[f64], v: &[f64]| c.iter().zip(v).map(|(a, b)| (a * b).abs()).sum::<f64>();
        sum(&self.state, x) + sum(&self.input, u) + sum(&self.rate, rate) + self.constant.abs()
    }

    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        self.state
            .iter()
            .chain(&self.input)
            .chain(&self.rate)
            .chain(std::iter::once(&self.constant))
            .all(|x| x.is_finite())
    }
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `Σ |aᵢ bᵢ|`.
fn dot_abs(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x * y).abs()).sum()
}

/// A guard with numbers in: fires when `row` reaches zero from below.
#[derive(Clone, Debug)]
pub struct NumericGuard {
    /// The switching element.
    pub element: ElementId,
    /// Its mode after the guard fires.
    pub leaves_to: ElementMode,
    /// Whether it switches to stuck only if static friction can then hold.
    pub requires_hold: bool,
    /// What it watches.
    pub watched: Watched,
    /// The guard function.
    pub row: Row,
}

/// A one-port's effort and inflowing flow in one mode: its power intake is their product.
#[derive(Clone, Debug)]
pub struct Port {
    /// The element.
    pub element: ElementId,
    /// Whether it supplies energy (a source) rather than dissipating it.
    pub source: bool,
    /// The effort on its bond.
    pub effort: Row,
    /// The flow into the element.
    pub flow: Row,
}

/// One mode ready to simulate.
#[derive(Clone, Debug)]
pub struct NumericMode {
    /// The mode.
    pub mode: Mode,
    /// Its specification (`fr_1=stuck,...`).
    pub spec: String,
    /// Its states' names. With an `E du/dt` term the numbers carried are `x - E u`
    /// ([`NumericMode::states`] gives `x`).
    pub state_names: Vec<String>,
    /// `E`, the coefficients of the inputs' rates (zero for most models).
    pub e: DMatrix<f64>,
    /// `A`.
    pub a: DMatrix<f64>,
    /// `B`.
    pub b: DMatrix<f64>,
    /// `c`.
    pub c: DVector<f64>,
    /// Its guards, in the derivation's order.
    pub guards: Vec<NumericGuard>,
    /// Each guard's state row in eigen-coordinates, `G V`, one guard after another (empty
    /// when propagation is not modal): event location evaluates guards from there.
    pub(crate) modal_guards: Vec<Complex64>,
    /// The requested outputs in this mode.
    pub outputs: Vec<Row>,
    /// Every one-port that exchanges energy without storing it (sources, resistors, friction
    /// contacts): its effort and its flow into the element, for energy accounting.
    pub ports: Vec<Port>,
    /// Exact propagation (of a linear mode; a nonlinear mode's is of zero matrices and
    /// unused).
    pub propagator: Propagator,
    /// A nonlinear mode's compiled `f(x, u)` and its other expressions; `a`, `b`, `c` are
    /// then zero and unused.
    pub nonlinear: Option<Arc<NonlinearNumeric>>,
    /// `R`: full state from the mode's states.
    reconstruct_state: DMatrix<f64>,
    /// `S`: full state from the inputs.
    reconstruct_input: DMatrix<f64>,
    /// `s`: the constant part of the full state.
    reconstruct_constant: DVector<f64>,
    /// `(Rᵀ W R)⁻¹ Rᵀ W`.
    projection: DMatrix<f64>,
}

impl NumericMode {
    /// Puts numbers into a derived mode: the parameter `values` (indexed like
    /// [`Model::values`]); `outputs` are the rows of requested outputs.
    pub fn new(
        model: &Model,
        values: &[f64],
        storage: &Storage,
        derived: &ModeEquations,
        outputs: &[LinearForm],
    ) -> Self {
        Self::from_forms(&ModeForms::new(model, derived, outputs), values, storage)
    }

    /// Puts the parameter `values` (indexed like [`Model::values`]) into a mode's forms,
    /// gathered once ([`ModeForms`]): what a calibration does at every trial.
    pub fn from_forms(forms: &ModeForms, values: &[f64], storage: &Storage) -> Self {
        Self::from_forms_beside(forms, values, storage, None)
    }

    /// [`NumericMode::from_forms`], reusing the eigendecomposition of `previous` (the same
    /// mode at other values) where `A` came out the same ([`Propagator::new_beside`]).
    pub fn from_forms_beside(
        forms: &ModeForms,
        values: &[f64],
        storage: &Storage,
        previous: Option<&NumericMode>,
    ) -> Self {
        let (n, m) = (forms.state_names.len(), forms.inputs);
        let evaluate = |entries: &[forms::Entry], columns: usize| {
            let mut matrix = DMatrix::zeros(n, columns);
            for (i, j, value) in entries {
                matrix[(*i, *j)] = value.eval(values);
            }
            matrix
        };
        let a = evaluate(&forms.a, n);
        let mut b = evaluate(&forms.b, m);
        let c = DVector::from_column_slice(evaluate(&forms.c, 1).as_slice());
        let e = evaluate(&forms.e, m);
        let with_rates = e.iter().any(|x| *x != 0.0);
        if with_rates {
            b += &a * &e;
        }

        let (reconstruct_state, mut reconstruct_input, reconstruct_constant, projection) =
            reconstruction(storage, &forms.storage_energy, n, m, values);
        if with_rates {
            reconstruct_input += &reconstruct_state * &e;
        }
        // A row in x becomes a row in x' = x - E u: its input part gains (state part)·E.
        let row = |form: &LinearForm| {
            let mut row = Row::from_form(form, n, m, values);
            if with_rates {
                for j in 0..m {
                    row.input[j] += (0..n).map(|i| row.state[i] * e[(i, j)]).sum::<f64>();
                }
            }
            row
        };

        let guards: Vec<NumericGuard> = forms
            .guards
            .iter()
            .filter(|g| g.applies(values))
            .map(|g| NumericGuard {
                element: g.element,
                leaves_to: g.leaves_to,
                requires_hold: g.requires_hold,
                watched: g.watched,
                row: row(&g.function),
            })
            .collect();
        let outputs = forms.outputs.iter().map(row).collect();
        let ports = forms
            .ports
            .iter()
            .map(|p| Port {
                element: p.element,
                source: p.source,
                effort: row(&p.effort),
                flow: row(&p.flow),
            })
            .collect();
        let propagator = match previous {
            Some(previous) => Propagator::new_beside(&a, &b, &c, &previous.a, &previous.propagator),
            None => Propagator::new(&a, &b, &c),
        };
        let modal_guards = modal_guard_rows(&propagator, &guards);
        NumericMode {
            spec: forms.spec.clone(),
            mode: forms.mode.clone(),
            state_names: forms.state_names.clone(),
            propagator,
            a,
            b,
            c,
            e,
            guards,
            modal_guards,
            outputs,
            ports,
            reconstruct_state,
            reconstruct_input,
            reconstruct_constant,
            projection,
            nonlinear: None,
        }
    }

    /// Puts numbers into a derived nonlinear mode, whose expressions (with the requested
    /// outputs') are `forms`.
    pub fn from_nonlinear(
        model: &Model,
        values: &[f64],
        storage: &Storage,
        derived: &NonlinearModeEquations,
        forms: &NonlinearForms,
    ) -> Self {
        let eq = &derived.equations;
        let (n, m) = (eq.states.len(), eq.inputs.len());
        let compiled = Arc::new(NonlinearNumeric::new(model, values, derived, forms));
        let (reconstruct_state, reconstruct_input, reconstruct_constant, projection) =
            reconstruction(storage, eq.storage_energy(), n, m, values);
        let program = |tape: &Arc<bondgraph_core::symbolic::expr::Tape>,
                       value,
                       magnitude,
                       rate,
                       rate_magnitude| {
            Row::program(RowProgram {
                tape: tape.clone(),
                value,
                magnitude,
                rate,
                rate_magnitude,
            })
        };
        let guards = derived
            .guards
            .iter()
            .filter(|g| g.applies(model, values))
            .enumerate()
            .map(|(k, g)| NumericGuard {
                element: g.element,
                leaves_to: g.leaves_to,
                requires_hold: g.requires_hold,
                watched: g.watched,
                row: program(
                    &compiled.guards,
                    3 * k,
                    3 * k + 1,
                    3 * k + 2,
                    Some((compiled.guard_rate_magnitudes.clone(), k)),
                ),
            })
            .collect();
        let count = forms.output_count();
        let outputs = (0..count)
            .map(|k| program(&compiled.outputs, k, k, count + k, None))
            .collect();
        let a = DMatrix::zeros(n, n);
        let b = DMatrix::zeros(n, m);
        let c = DVector::zeros(n);
        NumericMode {
            spec: derived.mode.spec(model),
            mode: derived.mode.clone(),
            state_names: eq.states.iter().map(|s| s.name.clone()).collect(),
            propagator: Propagator::new(&a, &b, &c),
            e: DMatrix::zeros(n, m),
            a,
            b,
            c,
            guards,
            modal_guards: Vec::new(),
            outputs,
            ports: Vec::new(),
            reconstruct_state,
            reconstruct_input,
            reconstruct_constant,
            projection,
            nonlinear: Some(compiled),
        }
    }

    /// The number of states.
    pub fn state_count(&self) -> usize {
        self.a.nrows()
    }

    /// The mode's named states `x = x' + E u` from the numbers carried, `x'`.
    pub fn states(&self, carried: &[f64], u: &[f64]) -> Vec<f64> {
        let x = DVector::from_column_slice(carried) + &self.e * DVector::from_column_slice(u);
        x.iter().copied().collect()
    }

    /// The mode's states from the full state, conserving momentum where bodies merge.
    pub fn project(&self, full: &[f64], u: &[f64]) -> Vec<f64> {
        // (Rᵀ W R)⁻¹ Rᵀ W (full - S u - s), without temporaries: it runs at every event.
        let (n, size) = self.projection.shape();
        debug_assert_eq!(
            full.len(),
            size,
            "a full state has every storage element's value"
        );
        let mut x = vec![0.0; n];
        for (k, full_k) in full.iter().enumerate().take(size) {
            let mut free = *full_k;
            for (j, uj) in u.iter().enumerate() {
                free -= self.reconstruct_input[(k, j)] * uj;
            }
            free -= self.reconstruct_constant[k];
            for (i, xi) in x.iter_mut().enumerate() {
                *xi += self.projection[(i, k)] * free;
            }
        }
        x
    }

    /// The full state from the mode's states.
    pub fn reconstruct(&self, x: &[f64], u: &[f64]) -> Vec<f64> {
        (0..self.reconstruct_state.nrows())
            .map(|k| {
                let state: f64 = x
                    .iter()
                    .enumerate()
                    .map(|(j, xj)| self.reconstruct_state[(k, j)] * xj)
                    .sum();
                let input: f64 = u
                    .iter()
                    .enumerate()
                    .map(|(j, uj)| self.reconstruct_input[(k, j)] * uj)
                    .sum();
                state + input + self.reconstruct_constant[k]
            })
            .collect()
    }

    /// `dx/dt = A x + B u + c`, or `f(x, u)` in a nonlinear mode.
    pub fn derivative(&self, x: &[f64], u: &[f64]) -> Vec<f64> {
        if let Some(nl) = &self.nonlinear {
            let input: Vec<f64> = x
                .iter()
                .chain(u)
                .copied()
                .chain(std::iter::repeat_n(0.0, u.len()))
                .collect();
            return nl.f.eval_alloc(&input);
        }
        let x = DVector::from_column_slice(x);
        let u = DVector::from_column_slice(u);
        (&self.a * x + &self.b * u + &self.c)
            .iter()
            .copied()
            .collect()
    }

    /// The energy stored in the full state: `p²/2m` for inertias, `q²/2C` for compliances,
    /// and for tension-only elements `q²/2C` when stretched, nothing when slack.
    pub fn stored_energy(storage: &Storage, model: &Model, full: &[f64]) -> f64 {
        (0..storage.len())
            .zip(full)
            .map(|(i, x)| Self::element_energy(storage, model, i, *x))
            .sum()
    }

    /// The energy held by storage element `index` (in [`Storage`]'s order) when its energy
    /// variable is `x`: `x²/2c` for a linear law (nothing for a slack tension-only element),
    /// `∫₀ˣ law` for a nonlinear one.
    pub fn element_energy(storage: &Storage, model: &Model, index: usize, x: f64) -> f64 {
        if let Some(law) = &storage.laws[index] {
            return law.energy(x);
        }
        let id = storage.elements[index];
        let tension_only = matches!(model.element(id).kind, ElementKind::TensionOnly(_));
        if tension_only && x < 0.0 {
            0.0
        } else {
            x * x / (2.0 * storage.coefficients[index])
        }
    }

    /// A row's rate of change along the trajectory at `x`, with inputs `u` changing at `u̇`
    /// (inputs are piecewise linear, so `ü = 0`).
    pub fn row_rate(&self, row: &Row, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
        if let Some(program) = &row.program {
            return program.outputs(x, u, rate)[program.rate];
        }
        if self.nonlinear.is_some() {
            return dot(&row.state, &self.derivative(x, u)) + dot(&row.input, rate);
        }
        // `g·(A x + B u + c)` row by row, skipping the states the row does not read: event
        // location asks for every guard's rate at every sample, so this must not allocate.
        let mut sum = dot(&row.input, rate);
        for (i, &g) in row.state.iter().enumerate() {
            if g == 0.0 {
                continue;
            }
            let mut derivative = self.c[i];
            for (j, xj) in x.iter().enumerate() {
                derivative += self.a[(i, j)] * xj;
            }
            for (k, uk) in u.iter().enumerate() {
                derivative += self.b[(i, k)] * uk;
            }
            sum += g * derivative;
        }
        sum
    }

    /// The size of the terms of [`NumericMode::row_rate`] before they cancel, the scale
    /// against which a rate `≈ 0` is judged: `Σ|gᵢ| (Σ|Aᵢⱼ xⱼ| + Σ|Bᵢₖ uₖ| + |cᵢ|) + Σ|hₖ u̇ₖ|`.
    /// In a nonlinear mode, the same sum with `Σ|terms of fᵢ|` for a row's `Σ|Aᵢⱼ xⱼ| + ...`
    /// (a guard's compiled with it; zero for a requested output).
    pub fn row_rate_magnitude(&self, row: &Row, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
        if let Some(program) = &row.program {
            return program.rate_magnitude(x, u, rate);
        }
        if let Some(nl) = &self.nonlinear {
            let terms = nl
                .f_magnitude
                .eval_alloc(&crate::nonlinear::tape_input(x, u, rate));
            return dot_abs(&row.state, &terms) + dot_abs(&row.input, rate);
        }
        let mut sum = 0.0;
        for (i, g) in row.state.iter().enumerate() {
            if *g == 0.0 {
                continue;
            }
            let terms = (0..x.len())
                .map(|j| (self.a[(i, j)] * x[j]).abs())
                .chain((0..u.len()).map(|k| (self.b[(i, k)] * u[k]).abs()))
                .sum::<f64>()
                + self.c[i].abs();
            sum += g.abs() * terms;
        }
        sum + row
            .input
            .iter()
            .zip(rate)
            .map(|(h, r)| (h * r).abs())
            .sum::<f64>()
    }
}

/// `G V`: each guard's state row times the eigenvectors of a modal propagator, guard after
/// guard (empty for one that is not modal).
fn modal_guard_rows(propagator: &Propagator, guards: &[NumericGuard]) -> Vec<Complex64> {
    let Propagator::Modal(modal) = propagator else {
        return Vec::new();
    };
    let v = &modal.eigen().vectors;
    let n = v.nrows();
    let mut rows = Vec::with_capacity(n * guards.len());
    for g in guards {
        rows.extend((0..n).map(|j| {
            (0..n)
                .map(|i| v[(i, j)] * g.row.state[i])
                .sum::<Complex64>()
        }));
    }
    rows
}

/// `R`, `S`, `s` and the projection `(Rᵀ W R)⁻¹ Rᵀ W` of a mode's storage energy forms.
fn reconstruction(
    storage: &Storage,
    storage_energy: &[(bondgraph_core::model::ElementId, LinearForm)],
    n: usize,
    m: usize,
    values: &[f64],
) -> (DMatrix<f64>, DMatrix<f64>, DVector<f64>, DMatrix<f64>) {
    let full = storage.len();
    let mut reconstruct_state = DMatrix::zeros(full, n);
    let mut reconstruct_input = DMatrix::zeros(full, m);
    let mut reconstruct_constant = DVector::zeros(full);
    for (element, form) in storage_energy {
        let Some(i) = storage.index(*element) else {
            continue;
        };
        let row = Row::from_form(form, n, m, values);
        for j in 0..n {
            reconstruct_state[(i, j)] = row.state[j];
        }
        for j in 0..m {
            reconstruct_input[(i, j)] = row.input[j];
        }
        reconstruct_constant[i] = row.constant;
    }
    let weight = DMatrix::from_diagonal(&DVector::from_iterator(
        full,
        storage.coefficients.iter().map(|c| 1.0 / c),
    ));
    let weighted = reconstruct_state.transpose() * &weight;
    let gram = &weighted * &reconstruct_state;
    let projection = gram
        .try_inverse()
        .map(|inverse| inverse * weighted)
        .unwrap_or_else(|| DMatrix::from_element(n, full, f64::NAN));

    (
        reconstruct_state,
        reconstruct_input,
        reconstruct_constant,
        projection,
    )
}
