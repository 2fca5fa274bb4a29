//! A nonlinear mode with numbers in: its `f(x, u)`, Jacobian, guards, outputs and ports
//! compiled to evaluation tapes.
//!
//! Every expression reads the same input vector `[x, u, u̇]` (states, inputs, inputs'
//! rates). The guards' tape gives, per guard, its value `g`, the size of its terms (to
//! judge `g ≈ 0` against) and its rate along the motion `dg/dt = ∇ₓg·f + ∇ᵤg·u̇`, all
//! differentiated symbolically, so that consistency checks at events are exact as in a
//! linear mode.

use std::sync::Arc;

use bondgraph_core::equations::nonlinear::NonlinearEquations;
use bondgraph_core::model::{ElementKind, Model, NonlinearLaw};
use bondgraph_core::modes::NonlinearModeEquations;
use bondgraph_core::symbolic::RatFunc;
use bondgraph_core::symbolic::expr::{Atom, Sym, Tape, TapeBuilder};
use bondgraph_core::symbolic::function::Function;

/// One value of a tape: what a [`Row`](crate::numeric::Row) of a nonlinear mode evaluates.
#[derive(Clone, Debug)]
pub struct RowProgram {
    /// The tape, reading `[x, u, u̇]`.
    pub tape: Arc<Tape>,
    /// The output holding the value.
    pub value: usize,
    /// The output holding the size of its terms.
    pub magnitude: usize,
    /// The output holding its rate along the motion.
    pub rate: usize,
    /// The tape and output holding the size of the rate's terms (a guard's, for judging a
    /// rate `≈ 0` at events; none for an output).
    pub rate_magnitude: Option<(Arc<Tape>, usize)>,
}

impl PartialEq for RowProgram {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.tape, &other.tape)
            && (self.value, self.magnitude, self.rate) == (other.value, other.magnitude, other.rate)
            && match (&self.rate_magnitude, &other.rate_magnitude) {
                (Some((a, i)), Some((b, j))) => Arc::ptr_eq(a, b) && i == j,
                (None, None) => true,
                _ => false,
            }
    }
}

impl RowProgram {
    /// The tape's outputs at `(x, u, u̇)`, allocating (for checks at events).
    pub fn outputs(&self, x: &[f64], u: &[f64], rate: &[f64]) -> Vec<f64> {
        self.tape.eval_alloc(&tape_input(x, u, rate))
    }

    /// The size of the terms of the rate at `(x, u, u̇)`: zero when none was compiled.
    pub fn rate_magnitude(&self, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
        self.rate_magnitude.as_ref().map_or(0.0, |(tape, k)| {
            tape.eval_alloc(&tape_input(x, u, rate))[*k]
        })
    }
}

/// The tapes' input `[x, u, u̇]`.
pub(crate) fn tape_input(x: &[f64], u: &[f64], rate: &[f64]) -> Vec<f64> {
    x.iter().chain(u).chain(rate).copied().collect()
}

/// The compiled expressions of a nonlinear mode.
#[derive(Debug)]
pub struct NonlinearNumeric {
    /// States.
    pub n: usize,
    /// Inputs.
    pub m: usize,
    /// `f`: `n` outputs.
    pub f: Tape,
    /// `f` then `∂f/∂x` row-major: `n + n²` outputs.
    pub f_and_jacobian: Tape,
    /// The magnitude of each rate's terms (the sum of their absolute values): what `f`'s
    /// rounding is judged against.
    pub f_magnitude: Tape,
    /// Per guard: value, magnitude, rate.
    pub guards: Arc<Tape>,
    /// Per guard, the size of its rate's terms (read at events only, so kept off the
    /// guards' tape that event location evaluates at every look).
    pub guard_rate_magnitudes: Arc<Tape>,
    /// The requested outputs, then their rates along the motion.
    pub outputs: Arc<Tape>,
    /// Per port: effort, flow into the element.
    pub ports: Arc<Tape>,
    /// Whether each port supplies energy (a source) rather than dissipating it.
    pub port_sources: Vec<bool>,
}

/// Where each variable sits in the tapes' input `[x, u, u̇]`.
fn slots(n: usize, m: usize) -> impl Fn(Atom) -> Option<usize> {
    move |a| match a {
        Atom::State(i) => Some(i as usize),
        Atom::Input(i) => Some(n + i as usize),
        Atom::InputRate(i) => Some(n + m + i as usize),
        _ => None,
    }
}

fn compile(n: usize, m: usize, values: &[f64], exprs: &[Sym]) -> Tape {
    let slot = slots(n, m);
    let mut builder = TapeBuilder::new(n + 2 * m, &slot, values);
    for e in exprs {
        // Derivation resolves every other variable; one that is left is a NaN.
        if builder.push(e).is_err() {
            builder
                .push(&Sym::coefficient(RatFunc::zero()))
                .expect("a constant compiles");
        }
    }
    builder.finish()
}

/// The rate of `g` along the motion: `∇ₓg·f + ∇ᵤg·u̇`.
pub(crate) fn rate_along(g: &Sym, equations: &NonlinearEquations) -> Sym {
    let mut parts = Vec::new();
    for (i, f) in equations.derivatives.iter().enumerate() {
        let d = g.diff(Atom::State(i as u32));
        if !d.is_zero() {
            parts.push((Sym::mul(&d, f), RatFunc::one()));
        }
    }
    for j in 0..equations.inputs.len() {
        let d = g.diff(Atom::Input(j as u32));
        if !d.is_zero() {
            parts.push((
                Sym::mul(&d, &Sym::atom(Atom::InputRate(j as u32))),
                RatFunc::one(),
            ));
        }
    }
    Sym::sum(parts)
}

/// The size of the terms of `g`'s rate along the motion, before they cancel:
/// `Σᵢ |∂g/∂xᵢ| Σ|terms of fᵢ| + Σⱼ |∂g/∂uⱼ u̇ⱼ|`, as a linear mode measures
/// `Σ|gᵢ| (Σ|Aᵢⱼ xⱼ| + ...)`. A contact slipping at the instant its drive meets its Coulomb
/// force has a rate of rounding size (`1e-17 m/s²` where its forces are 10 N), which must
/// not decide by its sign.
pub(crate) fn rate_magnitude_along(g: &Sym, equations: &NonlinearEquations) -> Sym {
    let abs = |e: Sym| Sym::call(Function::Abs, vec![e]);
    let mut parts = Vec::new();
    for (i, f) in equations.derivatives.iter().enumerate() {
        let d = g.diff(Atom::State(i as u32));
        if !d.is_zero() {
            parts.push((Sym::mul(&abs(d), &f.magnitude()), RatFunc::one()));
        }
    }
    for j in 0..equations.inputs.len() {
        let d = g.diff(Atom::Input(j as u32));
        if !d.is_zero() {
            let term = Sym::mul(&d, &Sym::atom(Atom::InputRate(j as u32)));
            parts.push((abs(term), RatFunc::one()));
        }
    }
    Sym::sum(parts)
}

/// A nonlinear mode's expressions before any value is put in: its rates and their Jacobian,
/// its guards with their sizes and rates, its outputs with their rates, its ports. They do
/// not depend on the parameter values, so a simulator derives them once per mode and keeps
/// them when a fit changes the values, compiling only the tapes again (differentiating at
/// every trial was a tenth of a fit's time on a motor with a nonlinear resistor).
#[derive(Debug)]
pub struct NonlinearForms {
    f: Vec<Sym>,
    f_and_jacobian: Vec<Sym>,
    magnitudes: Vec<Sym>,
    /// Per guard of the mode, all of them (which apply depends on the values): its value,
    /// magnitude and rate, then the size of its rate's terms.
    guards: Vec<([Sym; 3], Sym)>,
    /// The requested outputs, then their rates along the motion.
    outputs: Vec<Sym>,
    ports: Vec<Sym>,
    port_sources: Vec<bool>,
}

impl NonlinearForms {
    /// The expressions of a derived nonlinear mode; `outputs` are the requested outputs'.
    pub fn new(model: &Model, derived: &NonlinearModeEquations, outputs: &[Sym]) -> Self {
        let eq = &derived.equations;
        let mut f_and_jacobian = eq.derivatives.clone();
        for row in eq.jacobian_states() {
            f_and_jacobian.extend(row);
        }
        let guards = derived
            .guards
            .iter()
            .map(|guard| {
                let g = guard.function();
                let (magnitude, rate) = (g.magnitude(), rate_along(&g, eq));
                let rate_magnitude = rate_magnitude_along(&g, eq);
                ([g, magnitude, rate], rate_magnitude)
            })
            .collect();
        let mut output_exprs = outputs.to_vec();
        output_exprs.extend(outputs.iter().map(|y| rate_along(y, eq)));
        let mut ports = Vec::new();
        let mut port_sources = Vec::new();
        for id in model.element_ids() {
            let source = match &model.element(id).kind {
                ElementKind::EffortSource(_) | ElementKind::FlowSource(_) => true,
                ElementKind::Resistor(_) | ElementKind::Friction(_) | ElementKind::FlowLimit(_) => {
                    false
                }
                ElementKind::Nonlinear(nl) => match nl.law {
                    NonlinearLaw::EffortSource(_) | NonlinearLaw::FlowSource(_) => true,
                    NonlinearLaw::Resistor(_) => false,
                    _ => continue,
                },
                _ => continue,
            };
            let bond = model.element(id).bonds[0];
            let sign = RatFunc::integer(model.bond(bond).sign_into(id));
            ports.push(eq.bond_effort(bond).clone());
            ports.push(eq.bond_flow(bond).scaled(&sign));
            port_sources.push(source);
        }
        Self {
            f: eq.derivatives.clone(),
            f_and_jacobian,
            magnitudes: eq.derivatives.iter().map(Sym::magnitude).collect(),
            guards,
            outputs: output_exprs,
            ports,
            port_sources,
        }
    }

    /// The requested outputs' count.
    pub fn output_count(&self) -> usize {
        self.outputs.len() / 2
    }
}

impl NonlinearNumeric {
    /// Compiles a derived nonlinear mode's `forms` with the parameter `values`.
    pub fn new(
        model: &Model,
        values: &[f64],
        derived: &NonlinearModeEquations,
        forms: &NonlinearForms,
    ) -> Self {
        let eq = &derived.equations;
        let (n, m) = (eq.states.len(), eq.inputs.len());
        let mut guard_exprs = Vec::new();
        let mut rate_magnitudes = Vec::new();
        // Only the guards that apply at these values, in order, as the mode lists them.
        for (guard, (value_size_rate, rate_magnitude)) in derived.guards.iter().zip(&forms.guards) {
            if guard.applies(model, values) {
                guard_exprs.extend(value_size_rate.iter().cloned());
                rate_magnitudes.push(rate_magnitude.clone());
            }
        }
        Self {
            n,
            m,
            f: compile(n, m, values, &forms.f),
            f_and_jacobian: compile(n, m, values, &forms.f_and_jacobian),
            f_magnitude: compile(n, m, values, &forms.magnitudes),
            guards: Arc::new(compile(n, m, values, &guard_exprs)),
            guard_rate_magnitudes: Arc::new(compile(n, m, values, &rate_magnitudes)),
            outputs: Arc::new(compile(n, m, values, &forms.outputs)),
            ports: Arc::new(compile(n, m, values, &forms.ports)),
            port_sources: forms.port_sources.clone(),
        }
    }
}

/// A nonlinear storage element's law as a tape of its own energy variable, for the energy
/// it stores: `∫₀^x law(s) ds`.
#[derive(Debug)]
pub struct StorageLawTape {
    tape: Tape,
}

impl StorageLawTape {
    /// The law of nonlinear storage element `index` of `model`, if it is one.
    pub fn of(model: &Model, index: usize, values: &[f64]) -> Option<Self> {
        let element = &model.elements()[index];
        let ElementKind::Nonlinear(nl) = &element.kind else {
            return None;
        };
        let (NonlinearLaw::Inertia(law) | NonlinearLaw::Compliance(law)) = &nl.law else {
            return None;
        };
        let own = index as u32;
        let slot = move |a: Atom| (a == Atom::Storage(own)).then_some(0);
        let mut builder = TapeBuilder::new(1, &slot, values);
        builder.push(law).ok()?;
        Some(Self {
            tape: builder.finish(),
        })
    }

    /// The energy stored at `x`: the law integrated from 0 by Gauss–Legendre quadrature on
    /// 32 panels (exact to rounding for smooth laws; a kink at zero is a panel edge).
    pub fn energy(&self, x: f64) -> f64 {
        const PANELS: usize = 32;
        let mut scratch = self.tape.scratch();
        let mut out = [0.0];
        let mut total = 0.0;
        let width = x / PANELS as f64;
        for p in 0..PANELS {
            let a = p as f64 * width;
            let (mid, half) = (a + width / 2.0, width / 2.0);
            for (node, weight) in crate::gauss::NODES.iter().zip(crate::gauss::WEIGHTS) {
                self.tape.eval(&[mid + half * node], &mut scratch, &mut out);
                total += weight * half * out[0];
            }
        }
        total
    }
}
