//! Guards: the conditions that end a mode, and the mode each leads to.
//!
//! Every guard watches one quantity of one switching element, written in the mode's own
//! states and inputs, against a threshold:
//!
//! | element mode | watches | leaves when | for |
//! |---|---|---|---|
//! | friction `stuck` | the force it must hold (the effort on its bond) | `≥ F_S` / `≤ -F_S` | `slip+` / `slip-` |
//! | friction `slip+` | its relative velocity | `≤ Δv` (if static friction can then hold) / `≤ 0` | `stuck` / `slip-` |
//! | friction `slip-` | its relative velocity | `≥ -Δv` (if static friction can then hold) / `≥ 0` | `stuck` / `slip+` |
//!
//! A contact with a Stribeck velocity `v_s` breaks away into `creep±` instead, and:
//!
//! | element mode | watches | leaves when | for |
//! |---|---|---|---|
//! | friction `creep+` | its relative velocity | `≤ Δv` (if static friction can then hold) / `≤ 0` / `≥ v_s + Δv` | `stuck` / `creep-` / `slip+` |
//! | friction `creep-` | its relative velocity | `≥ -Δv` (if static friction can then hold) / `≥ 0` / `≤ -(v_s + Δv)` | `stuck` / `creep+` / `slip-` |
//! | friction `slip+` | its relative velocity | `≤ v_s - Δv` | `creep+` |
//! | friction `slip-` | its relative velocity | `≥ -(v_s - Δv)` | `creep-` |
//!
//! (The dead band `Δv` doubles as a hysteresis around `v_s`, where the two laws meet.)
//!
//! | tension-only `taut` | its tension | `≤ 0` | `slack` |
//! | tension-only `slack` | its slack length (a state) | `≥ 0` | `taut` |
//! | flow limit `open` | the flow into it | `≥ max_flow` (if the limit then holds back a positive effort) | `limiting` |
//! | flow limit `limiting` | the effort it holds back (power it absorbs per unit flow) | `≤ 0` | `open` |
//!
//! A Stribeck velocity of zero leaves no creeping range: the contact is then exactly the
//! Karnopp contact with the same breakaway and Coulomb forces, and the guards of the first
//! table apply. The Stribeck velocity is a parameter like any other, and a fit moves it
//! between zero and positive values by substituting numbers into modes derived once (it
//! never re-checks or re-derives the model per trial). So a Stribeck contact's modes carry
//! both sets of guards where they differ, each marked with the [`Regime`] it belongs to, and
//! the one that applies is chosen where numbers are bound ([`Guard::applies`]); a listing
//! shows those that apply at the model's own values.
//!
//! The holding force of a stuck contact is an output equation of the stuck mode: for a
//! block stuck to a moving carriage it is the force that makes the block accelerate with the
//! carriage, which is how papers derive their stick conditions by hand. A guard marked
//! [`Guard::requires_hold`] leads to `stuck` only if the target mode's holding force is then
//! within `±F_S`; otherwise the contact slips through zero velocity and the next guard
//! (velocity through zero, to the opposite slip) applies. A flow limit's guard into
//! `limiting` is marked the same way: it limits only if it then holds back a positive effort.

use crate::equations::nonlinear::NonlinearEquations;
use crate::equations::{StateEquations, StateVariable};
use crate::linear::{LinearForm, Var};
use crate::mode::Mode;
use crate::model::{BondId, ElementId, ElementKind, ElementMode, Friction, Model};
use crate::symbolic::RatFunc;
use crate::symbolic::expr::{Atom, Sym};

/// What a guard watches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Watched {
    /// The force a stuck contact must transmit.
    HoldingForce,
    /// The relative velocity of a slipping contact, against zero or the dead band.
    RelativeVelocity,
    /// The relative velocity of a slipping contact, against its Stribeck velocity.
    StribeckVelocity,
    /// The tension of a taut tension-only element.
    Tension,
    /// The slack length (negative extension) of a slack tension-only element.
    SlackLength,
    /// The flow into an open flow limit.
    LimitedFlow,
    /// The effort a limiting flow limit holds back.
    RestrainingEffort,
}

impl Watched {
    /// A readable name.
    pub fn description(self) -> &'static str {
        match self {
            Watched::HoldingForce => "holding force",
            Watched::RelativeVelocity | Watched::StribeckVelocity => "relative velocity",
            Watched::Tension => "tension",
            Watched::SlackLength => "extension",
            Watched::LimitedFlow => "flow",
            Watched::RestrainingEffort => "restraining effort",
        }
    }
}

/// Which Stribeck velocities a guard applies at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Regime {
    /// At any: the guards of every element other than a Stribeck contact, and those of a
    /// Stribeck contact that do not depend on its creeping range.
    Always,
    /// Only where the contact's Stribeck velocity is not zero: breaking away into `creep±`,
    /// sliding down into `creep±`.
    Weakening,
    /// Only where the contact's Stribeck velocity is zero, which makes it a Karnopp
    /// contact: breaking away into `slip±`, sliding to a stop or through zero.
    Karnopp,
}

impl Regime {
    /// Whether a guard of this regime applies to a contact that has a creeping range
    /// (`creeps`) or not.
    pub fn applies(self, creeps: bool) -> bool {
        match self {
            Regime::Always => true,
            Regime::Weakening => creeps,
            Regime::Karnopp => !creeps,
        }
    }
}

/// Which way the watched quantity crosses its threshold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Crossing {
    /// The guard fires when the quantity reaches the threshold from below.
    Rises,
    /// The guard fires when the quantity reaches the threshold from above.
    Falls,
}

/// One condition that ends a mode; its quantities are affine forms ([`LinearForm`]) in a
/// linear mode, expressions ([`Sym`]) in a nonlinear one.
#[derive(Clone, Debug, PartialEq)]
pub struct Guard<Q = LinearForm> {
    /// The switching element whose mode changes.
    pub element: ElementId,
    /// What is watched.
    pub watched: Watched,
    /// The watched quantity, in the mode's states and the inputs.
    pub quantity: Q,
    /// Which way it must cross.
    pub crossing: Crossing,
    /// The threshold, in the inputs.
    pub threshold: Q,
    /// The element's mode after the guard fires.
    pub leaves_to: ElementMode,
    /// Whether the switch happens only if the element can then hold: a contact going
    /// `stuck` within its breakaway force, a flow limit going `limiting` with a positive
    /// restraining effort.
    pub requires_hold: bool,
    /// The Stribeck velocities it applies at.
    pub regime: Regime,
}

impl<Q> Guard<Q> {
    /// Whether the guard applies with the parameter `values` (indexed like
    /// [`Model::values`]): a guard of one [`Regime`] of a Stribeck contact applies only where
    /// the contact's Stribeck velocity is, or is not, zero.
    pub fn applies(&self, model: &Model, values: &[f64]) -> bool {
        match &model.element(self.element).kind {
            ElementKind::Friction(friction) => self.regime.applies(friction.creeps_at(values)),
            _ => true,
        }
    }
}

impl Guard<Sym> {
    /// The guard function `g(x, u)`: the guard fires when `g` reaches zero from below.
    pub fn function(&self) -> Sym {
        let g = Sym::sub(&self.quantity, &self.threshold);
        match self.crossing {
            Crossing::Rises => g,
            Crossing::Falls => Sym::neg(&g),
        }
    }

    /// The condition as text: `holding force <expr> >= F_S`.
    pub fn condition_text(&self, equations: &NonlinearEquations) -> String {
        condition(
            self,
            &equations.sym_text(&self.quantity),
            &equations.sym_text(&self.threshold),
        )
    }
}

/// A guard's condition as text, from its quantity's and threshold's text.
fn condition<Q>(guard: &Guard<Q>, quantity: &str, threshold: &str) -> String {
    let comparison = match guard.crossing {
        Crossing::Rises => ">=",
        Crossing::Falls => "<=",
    };
    let mut text = format!(
        "{} {quantity} {comparison} {threshold}",
        guard.watched.description()
    );
    if guard.requires_hold {
        text.push_str(match guard.watched {
            Watched::LimitedFlow => ", if the limit then holds back a positive effort",
            _ => ", if static friction can then hold",
        });
    }
    text
}

impl Guard {
    /// The guard function `g(x, u)`: the guard fires when `g` reaches zero from below.
    pub fn function(&self) -> LinearForm {
        let mut g = self.quantity.clone();
        g.add_scaled(&self.threshold, &RatFunc::integer(-1));
        match self.crossing {
            Crossing::Rises => g,
            Crossing::Falls => g.scaled(&RatFunc::integer(-1)),
        }
    }

    /// The condition as text: `holding force <expr> >= F_S`.
    pub fn condition_text(&self, equations: &StateEquations) -> String {
        condition(
            self,
            &equations.form_text(&self.quantity),
            &equations.form_text(&self.threshold),
        )
    }
}

/// What the guards of a mode are written in: the bond variables and states of its
/// equations, linear or nonlinear.
trait GuardForms {
    /// An affine form or an expression.
    type Form: Clone;
    /// The effort of `bond`.
    fn effort(&self, bond: BondId) -> Self::Form;
    /// The flow of `bond` times `sign`.
    fn flow(&self, bond: BondId, sign: i64) -> Self::Form;
    /// An affine form of the inputs (a threshold).
    fn lift(&self, form: &LinearForm) -> Self::Form;
    /// State `k`.
    fn state(&self, k: usize) -> Self::Form;
    /// The states.
    fn states(&self) -> &[StateVariable];
}

impl GuardForms for StateEquations {
    type Form = LinearForm;
    fn effort(&self, bond: BondId) -> LinearForm {
        self.bond_effort(bond).clone()
    }
    fn flow(&self, bond: BondId, sign: i64) -> LinearForm {
        self.bond_flow(bond).scaled(&RatFunc::integer(sign))
    }
    fn lift(&self, form: &LinearForm) -> LinearForm {
        form.clone()
    }
    fn state(&self, k: usize) -> LinearForm {
        LinearForm::var(Var::State(k as u32))
    }
    fn states(&self) -> &[StateVariable] {
        &self.states
    }
}

impl GuardForms for NonlinearEquations {
    type Form = Sym;
    fn effort(&self, bond: BondId) -> Sym {
        self.bond_effort(bond).clone()
    }
    fn flow(&self, bond: BondId, sign: i64) -> Sym {
        self.bond_flow(bond).scaled(&RatFunc::integer(sign))
    }
    fn lift(&self, form: &LinearForm) -> Sym {
        crate::equations::nonlinear::form_to_sym(form)
    }
    fn state(&self, k: usize) -> Sym {
        Sym::atom(Atom::State(k as u32))
    }
    fn states(&self) -> &[StateVariable] {
        &self.states
    }
}

/// The guards of `mode`, written in the states of its `equations`.
pub fn derive(model: &Model, mode: &Mode, equations: &StateEquations) -> Vec<Guard> {
    derive_in(model, mode, equations)
}

/// The guards of a nonlinear `mode`: expressions of its states.
pub fn derive_nonlinear(
    model: &Model,
    mode: &Mode,
    equations: &NonlinearEquations,
) -> Vec<Guard<Sym>> {
    derive_in(model, mode, equations)
}

fn derive_in<E: GuardForms>(model: &Model, mode: &Mode, equations: &E) -> Vec<Guard<E::Form>> {
    let mut guards = Vec::new();
    for &(element, element_mode) in mode.assignments() {
        let bond = model.element(element).bonds[0];
        let sign = model.bond(bond).sign_into(element);
        let effort = || equations.effort(bond);
        let flow = || equations.flow(bond, sign);
        let lift = |form: &LinearForm| equations.lift(form);
        let guard =
            |watched, quantity: E::Form, crossing, threshold, leaves_to, requires_hold| Guard {
                element,
                watched,
                quantity,
                crossing,
                threshold,
                leaves_to,
                requires_hold,
                regime: Regime::Always,
            };
        match (&model.element(element).kind, element_mode) {
            (ElementKind::Friction(friction), _) => {
                let forms = (effort(), flow());
                guards.extend(friction_guards(
                    friction,
                    element,
                    element_mode,
                    forms,
                    &lift,
                ));
            }
            (ElementKind::TensionOnly(_), ElementMode::Taut) => {
                guards.push(guard(
                    Watched::Tension,
                    effort(),
                    Crossing::Falls,
                    lift(&LinearForm::zero()),
                    ElementMode::Slack,
                    false,
                ));
            }
            (ElementKind::TensionOnly(_), _) => {
                let name = &model.element(element).name;
                let state = equations
                    .states()
                    .iter()
                    .position(|s| &s.element == name)
                    .expect("a slack element keeps its extension as a state");
                guards.push(guard(
                    Watched::SlackLength,
                    equations.state(state),
                    Crossing::Rises,
                    lift(&LinearForm::zero()),
                    ElementMode::Taut,
                    false,
                ));
            }
            (ElementKind::FlowLimit(_), ElementMode::Limiting) => {
                // Power into the element is effort times the flow into it, so holding a
                // positive flow back takes a positive effort.
                guards.push(guard(
                    Watched::RestrainingEffort,
                    effort(),
                    Crossing::Falls,
                    lift(&LinearForm::zero()),
                    ElementMode::Open,
                    false,
                ));
            }
            (ElementKind::FlowLimit(limit), _) => {
                // Where the flow only touches the limit (the effort that would be held back
                // is zero and falling), rounding decides the flow's rate: limiting only if
                // the limit then holds back a positive effort keeps the two guards from
                // sending each other round.
                guards.push(guard(
                    Watched::LimitedFlow,
                    flow(),
                    Crossing::Rises,
                    lift(&limit.max_flow.value),
                    ElementMode::Limiting,
                    true,
                ));
            }
            _ => {}
        }
    }
    guards
}

/// The guards of a friction contact in `element_mode`: from stuck, breaking away; from a slide
/// or a creep, stopping, reversing, or crossing the Stribeck velocity. `effort` and
/// `velocity` are the contact's (the flow signed into it); `lift` makes a threshold a form.
/// Where a Stribeck velocity is given each guard carries the [`Regime`] of values it applies
/// at (`v_s` zero or not), since a fit moves `v_s` on one derived model.
fn friction_guards<F: Clone>(
    friction: &Friction,
    element: ElementId,
    element_mode: ElementMode,
    (effort, velocity): (F, F),
    lift: &dyn Fn(&LinearForm) -> F,
) -> Vec<Guard<F>> {
    let guard =
        |regime, watched, quantity: F, crossing, threshold, leaves_to, requires_hold| Guard {
            element,
            watched,
            quantity,
            crossing,
            threshold,
            leaves_to,
            requires_hold,
            regime,
        };
    let mut guards = Vec::new();
    if element_mode == ElementMode::Stuck {
        let breakaway = lift(&friction.breakaway.value);
        let negative_breakaway = lift(&friction.breakaway.value.scaled(&RatFunc::integer(-1)));
        let slip = (ElementMode::SlipPositive, ElementMode::SlipNegative);
        let creep = (ElementMode::CreepPositive, ElementMode::CreepNegative);
        let targets = if friction.stribeck.is_some() {
            vec![(Regime::Weakening, creep), (Regime::Karnopp, slip)]
        } else {
            vec![(Regime::Always, slip)]
        };
        for (regime, (forward, backward)) in targets {
            let hold = Watched::HoldingForce;
            guards.push(guard(
                regime,
                hold,
                effort.clone(),
                Crossing::Rises,
                breakaway.clone(),
                forward,
                false,
            ));
            guards.push(guard(
                regime,
                hold,
                effort.clone(),
                Crossing::Falls,
                negative_breakaway.clone(),
                backward,
                false,
            ));
        }
        return guards;
    }
    let forward = matches!(
        element_mode,
        ElementMode::SlipPositive | ElementMode::CreepPositive
    );
    let creeping = matches!(
        element_mode,
        ElementMode::CreepPositive | ElementMode::CreepNegative
    );
    if let Some(stribeck) = &friction.stribeck {
        // The two laws agree at v_s, so where the motion settles right at v_s (a taut string
        // holding the contact there) switching on either side of one threshold would chatter
        // on rounding. A hysteresis of the dead band prevents it, at a force error of at most
        // (F_S - F_C) Δv/v_s.
        let band = &friction.dead_band.value;
        let above = LinearForm::constant(stribeck.value.add_ref(band));
        let below = LinearForm::constant(stribeck.value.sub_ref(band));
        let minus = |form: &LinearForm| lift(&form.scaled(&RatFunc::integer(-1)));
        let (crossing, threshold, to) = match (forward, creeping) {
            (true, true) => (Crossing::Rises, lift(&above), ElementMode::SlipPositive),
            (false, true) => (Crossing::Falls, minus(&above), ElementMode::SlipNegative),
            (true, false) => (Crossing::Falls, lift(&below), ElementMode::CreepPositive),
            (false, false) => (Crossing::Rises, minus(&below), ElementMode::CreepNegative),
        };
        let watched = Watched::StribeckVelocity;
        guards.push(guard(
            Regime::Weakening,
            watched,
            velocity.clone(),
            crossing,
            threshold,
            to,
            false,
        ));
    }
    // Sliding faster than a positive v_s, it must creep before it can stop; with v_s zero it
    // stops or reverses as a Karnopp contact does.
    let regime = if friction.stribeck.is_some() && !creeping {
        Regime::Karnopp
    } else {
        Regime::Always
    };
    let dead_band = friction.dead_band.value.clone();
    let (crossing, band, reverse) = match (forward, creeping) {
        (true, false) => (Crossing::Falls, dead_band, ElementMode::SlipNegative),
        (false, false) => (Crossing::Rises, -dead_band, ElementMode::SlipPositive),
        (true, true) => (Crossing::Falls, dead_band, ElementMode::CreepNegative),
        (false, true) => (Crossing::Rises, -dead_band, ElementMode::CreepPositive),
    };
    let relative = Watched::RelativeVelocity;
    let stop = lift(&LinearForm::constant(band));
    guards.push(guard(
        regime,
        relative,
        velocity.clone(),
        crossing,
        stop,
        ElementMode::Stuck,
        true,
    ));
    let zero = lift(&LinearForm::zero());
    guards.push(guard(
        regime, relative, velocity, crossing, zero, reverse, false,
    ));
    guards
}
