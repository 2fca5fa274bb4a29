//! The validated model: names resolved, expressions turned into symbolic values, parameter
//! values bound and checked, every item remembering where in the file it came from.
//!
//! Nothing past the loader sees raw input: causality, equations and modes work on a
//! [`Model`], which cannot hold a bond to an undefined element, an unknown symbol or a
//! zero mass.

use std::collections::BTreeSet;
use std::sync::Arc;

use crate::linear::{LinearForm, Var};
use crate::source::{Location, SourceFile, Span};
use crate::symbolic::expr::Sym;
use crate::symbolic::{RatFunc, Symbol, SymbolTable};

/// Index of an element in [`Model::elements`] (and of its node in the bond graph).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ElementId(pub u32);

/// Index of a bond in [`Model::bonds`] (and of its edge in the bond graph).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BondId(pub u32);

/// Index of an input in [`Model::inputs`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InputId(pub u32);

impl ElementId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl BondId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl InputId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A checked, self-contained model: made only by the validator (from a file's reader or a
/// [`Builder`](crate::model::Builder)), so that every model a later stage sees has been
/// checked; read through its accessors.
#[derive(Clone, Debug)]
pub struct Model {
    /// The model's name.
    pub(crate) name: String,
    /// What the model describes.
    pub(crate) description: Option<String>,
    /// The file it was read from (for locating diagnostics).
    pub(crate) source: Arc<SourceFile>,
    /// The parameter symbols, in print order.
    pub(crate) symbols: SymbolTable,
    /// Parameters in file order.
    pub(crate) parameters: Vec<Parameter>,
    /// Inputs in file order.
    pub(crate) inputs: Vec<Input>,
    /// Elements in file order.
    pub(crate) elements: Vec<Element>,
    /// Bonds in file order.
    pub(crate) bonds: Vec<Bond>,
    /// Parameter values indexed by [`Symbol::index`].
    pub(crate) values: Vec<f64>,
    /// The linear graph the model was translated from, if its file is a `LinearGraph(...)`:
    /// its nodes and branches, and where each branch is in this bond graph.
    pub(crate) linear_graph: Option<Arc<crate::model::linear_graph::LinearGraph>>,
    /// The dimensions of each bond's effort and flow, where the units check could tell them
    /// (indexed by [`BondId::index`]; see [`crate::units`]).
    pub(crate) bond_dimensions: Vec<crate::units::BondDimensions>,
    /// The model's ports, for use as a sub-model of another.
    pub(crate) ports: Vec<Port>,
    /// The sub-models it was composed from.
    pub(crate) parts: Vec<crate::model::PartSpec>,
}

/// A port: a junction of the model that bonds from outside attach to when the model is used
/// as a sub-model of another.
#[derive(Clone, Debug)]
pub struct Port {
    /// The port's name (`hub`), which the using model writes after the use's name
    /// (`"front.hub"`).
    pub name: String,
    /// The junction it is.
    pub element: ElementId,
    /// What it is.
    pub description: Option<String>,
    /// Where it is declared.
    pub span: Span,
}

/// A named parameter with its value.
#[derive(Clone, Debug)]
pub struct Parameter {
    /// The name used in expressions.
    pub name: String,
    /// Its value (finite), in SI units: the file's value converted from its unit.
    pub value: f64,
    /// Its unit, as written.
    pub unit: Option<String>,
    /// What it is.
    pub description: Option<String>,
    /// The range a calibration may move it in, `(low, high)` with `low < high` and the value
    /// inside, if the file gives one; in SI units, like `value`.
    pub bounds: Option<(f64, f64)>,
    /// Its symbol in [`Model::symbols`].
    pub symbol: Symbol,
    /// The span of its name in the file.
    pub span: Span,
    /// The value as written in the file, where its unit is not an SI one (`0.2` of
    /// `value: 0.2, unit: "N/mm"`, whose `value` is 200); `value` is the SI value.
    pub as_written: Option<f64>,
    /// The SI unit `value` (and `bounds`) are in, spelt like `unit` (`N/m` for `N/mm`);
    /// `unit` itself when that is SI.
    pub si_unit: Option<String>,
}

impl Parameter {
    /// `k = 200 N/m (0.2 N/mm)`: the value in SI units, and as written where that differs.
    pub fn in_si_text(&self) -> String {
        let number = crate::units::scale::factor_text;
        let unit = |u: &Option<String>| u.as_ref().map_or(String::new(), |u| format!(" {u}"));
        let mut text = format!(
            "{} = {}{}",
            self.name,
            number(self.value),
            unit(&self.si_unit)
        );
        if let Some(written) = self.as_written {
            text.push_str(&format!(" ({}{})", number(written), unit(&self.unit)));
        }
        text
    }
}

/// A named input (a time-varying quantity that drives sources).
#[derive(Clone, Debug)]
pub struct Input {
    /// The name used in expressions.
    pub name: String,
    /// Its unit, as written.
    pub unit: Option<String>,
    /// What it is.
    pub description: Option<String>,
    /// The span of its name in the file.
    pub span: Span,
}

/// A named element with its constitutive law.
#[derive(Clone, Debug)]
pub struct Element {
    /// The element's name.
    pub name: String,
    /// What it is.
    pub kind: ElementKind,
    /// The span of its name in the file.
    pub span: Span,
    /// Its bonds, in file order.
    pub bonds: Vec<BondId>,
    /// The name its state is given in the file (`symbol:`), in place of `p_NAME`/`q_NAME`.
    pub symbol: Option<String>,
}

/// A coefficient written as a parameter expression (`1/k_ge`), with its text and place.
#[derive(Clone, Debug)]
pub struct Coefficient {
    /// Its symbolic value.
    pub value: RatFunc,
    /// The expression as written.
    pub text: String,
    /// The span of the expression text in the file.
    pub span: Span,
}

/// A source value: affine in the inputs with parameter coefficients (`A*P_s`, `F_0 + F`).
///
/// Only [`Var::Input`](crate::linear::Var::Input) and [`Var::Constant`](crate::linear::Var::Constant) appear in it, and in
/// an `Se` or `Sf` also [`Var::Storage`](crate::linear::Var::Storage): a linear feedback of
/// storage elements' energy variables (`-K_c*q_spring`).
#[derive(Clone, Debug)]
pub struct SourceValue {
    /// Its value as an affine form of the inputs.
    pub value: LinearForm,
    /// The expression as written.
    pub text: String,
    /// The span of the expression text in the file.
    pub span: Span,
}

/// The kinds of element, with their parameters.
#[derive(Clone, Debug)]
pub enum ElementKind {
    /// `Se`: imposes an effort.
    EffortSource(SourceValue),
    /// `Sf`: imposes a flow.
    FlowSource(SourceValue),
    /// `I`: stores kinetic energy, `p = inertance · f`.
    Inertia(Coefficient),
    /// `C`: stores potential energy, `q = compliance · e`.
    Compliance(Coefficient),
    /// `R`: dissipates, `e = resistance · f`.
    Resistor(Coefficient),
    /// `TF`: `e_in = ratio · e_out`, `f_out = ratio · f_in`.
    Transformer(Coefficient),
    /// `GY`: `e_in = ratio · f_out`, `e_out = ratio · f_in`.
    Gyrator(Coefficient),
    /// A Karnopp friction contact: switches between stuck and slipping.
    Friction(Box<Friction>),
    /// A compliance that carries tension only: switches between taut and slack.
    TensionOnly(TensionOnly),
    /// A limit on the flow through its bond: switches between open and limiting.
    FlowLimit(FlowLimit),
    /// An element with a nonlinear or modulated law: a source nonlinear in its inputs or
    /// driven by states, storage with a nonlinear law, a resistor with a nonlinear or
    /// modulated law, a transformer or gyrator whose ratio depends on inputs and states.
    Nonlinear(Box<NonlinearElement>),
    /// A 0-junction: common effort, flows sum to zero.
    ZeroJunction,
    /// A 1-junction: common flow, efforts sum to zero.
    OneJunction,
}

/// An element whose law is nonlinear or modulated, as written.
#[derive(Clone, Debug)]
pub struct NonlinearElement {
    /// The law.
    pub law: NonlinearLaw,
    /// The field it was written in (`effort`, `flow`, `resistance`, `ratio`, ...).
    pub field: String,
    /// The expression as written.
    pub text: String,
    /// The span of the expression text in the file.
    pub span: Span,
}

/// A nonlinear or modulated law. Its expressions name the model's inputs
/// ([`Atom::Input`](crate::symbolic::expr::Atom::Input)), the energy variables of storage
/// elements ([`Atom::Storage`](crate::symbolic::expr::Atom::Storage), by element index) and,
/// in a resistor's law, its port variable ([`Atom::Port`](crate::symbolic::expr::Atom::Port)).
#[derive(Clone, Debug, PartialEq)]
pub enum NonlinearLaw {
    /// `Se`: the effort imposed.
    EffortSource(Sym),
    /// `Sf`: the flow imposed (out of the element).
    FlowSource(Sym),
    /// `I`: the flow as a function of the element's momentum.
    Inertia(Sym),
    /// `C`: the effort as a function of the element's displacement.
    Compliance(Sym),
    /// `R`: the effort as a function of the flow into it, the flow as a function of the
    /// effort, or both where one was inverted symbolically.
    Resistor(ResistorLaw),
    /// `TF` with a modulated ratio: `e_in = ratio · e_out`, `f_out = ratio · f_in`.
    Transformer(Sym),
    /// `GY` with a modulated ratio: `e_in = ratio · f_out`, `e_out = ratio · f_in`.
    Gyrator(Sym),
}

/// A resistor's law in the causal forms known: each in terms of [`Atom::Port`](crate::symbolic::expr::Atom::Port).
#[derive(Clone, Debug, PartialEq)]
pub struct ResistorLaw {
    /// `effort = f(flow)`, for resistance causality.
    pub effort: Option<Sym>,
    /// `flow = g(effort)`, for conductance causality.
    pub flow: Option<Sym>,
}

impl NonlinearLaw {
    /// The parameters its expressions use.
    pub fn parameters(&self) -> BTreeSet<Symbol> {
        match self {
            NonlinearLaw::EffortSource(e)
            | NonlinearLaw::FlowSource(e)
            | NonlinearLaw::Inertia(e)
            | NonlinearLaw::Compliance(e)
            | NonlinearLaw::Transformer(e)
            | NonlinearLaw::Gyrator(e) => e.parameters(),
            NonlinearLaw::Resistor(law) => law
                .effort
                .iter()
                .chain(&law.flow)
                .flat_map(Sym::parameters)
                .collect(),
        }
    }

    /// The element kind it belongs to, as written in model files.
    pub fn keyword(&self) -> &'static str {
        match self {
            NonlinearLaw::EffortSource(_) => "Se",
            NonlinearLaw::FlowSource(_) => "Sf",
            NonlinearLaw::Inertia(_) => "I",
            NonlinearLaw::Compliance(_) => "C",
            NonlinearLaw::Resistor(_) => "R",
            NonlinearLaw::Transformer(_) => "TF",
            NonlinearLaw::Gyrator(_) => "GY",
        }
    }

    /// A readable description of the element.
    pub fn description(&self) -> &'static str {
        match self {
            NonlinearLaw::EffortSource(_) => "effort source",
            NonlinearLaw::FlowSource(_) => "flow source",
            NonlinearLaw::Inertia(_) => "nonlinear inertia",
            NonlinearLaw::Compliance(_) => "nonlinear compliance",
            NonlinearLaw::Resistor(_) => "nonlinear resistor",
            NonlinearLaw::Transformer(_) => "modulated transformer",
            NonlinearLaw::Gyrator(_) => "modulated gyrator",
        }
    }
}

/// A Karnopp friction contact on the relative velocity carried by its bond.
///
/// Stuck, it holds that velocity at zero with whatever force that takes, as long as the force
/// stays below `breakaway`; slipping, it resists with `viscous·v + coulomb·sgn(v)`. Slipping
/// slower than `dead_band` sticks, if the contact can then hold.
///
/// With a Stribeck velocity `v_s` the kinetic force weakens with speed: slipping slower than
/// `v_s` (`creep±`) it is `breakaway·sgn(v) + (viscous - (breakaway - coulomb)/v_s)·v`,
/// falling linearly from the breakaway force at rest to the Coulomb force at `v_s`; faster
/// (`slip±`) it is the Coulomb law above. The piecewise-linear curve keeps every mode linear,
/// so each still has its own A and B.
///
/// A Stribeck velocity of zero leaves no creeping range: the contact is then the Karnopp
/// contact with the same forces. The velocity may be a parameter that a fit sets to zero or
/// to positive values on the same checked model, so which it is gets decided where numbers
/// are bound ([`Friction::creeps_at`], [`crate::guards::Regime`]); one written as a literal
/// zero is no Stribeck velocity at all (`stribeck` is `None`).
#[derive(Clone, Debug)]
pub struct Friction {
    /// The breakaway (static) force `F_S`; affine in the inputs.
    pub breakaway: SourceValue,
    /// The Coulomb force `F_C`; affine in the inputs.
    pub coulomb: SourceValue,
    /// The viscous coefficient `b` (zero when not given).
    pub viscous: Coefficient,
    /// Karnopp's dead band `Δv` (zero when not given).
    pub dead_band: Coefficient,
    /// The Stribeck velocity `v_s`, below which the kinetic force weakens with speed.
    pub stribeck: Option<Coefficient>,
    /// The mode at the start.
    pub initial: ElementMode,
}

impl Friction {
    /// The viscous coefficient while creeping (slower than the Stribeck velocity):
    /// `viscous - (breakaway - coulomb)/v_s`, negative where friction weakens faster than
    /// viscosity grows. `None` without a Stribeck velocity, or where breakaway and Coulomb
    /// forces differ by an amount that depends on inputs (the validator rejects that).
    pub fn creep_resistance(&self) -> Option<RatFunc> {
        let stribeck = self.stribeck.as_ref()?;
        let mut drop = self.breakaway.value.clone();
        drop.add_scaled(&self.coulomb.value, &RatFunc::integer(-1));
        if drop.mentions(|v| v != Var::Constant) {
            return None;
        }
        let slope = drop
            .coefficient(Var::Constant)
            .checked_div(&stribeck.value)?;
        Some(self.viscous.value.sub_ref(&slope))
    }

    /// Whether the contact has a creeping range with the parameter `values` (indexed like
    /// [`Model::values`]): a Stribeck velocity that is not zero there. Without one it breaks
    /// away into `slip±` and slides to a stop as a Karnopp contact.
    pub fn creeps_at(&self, values: &[f64]) -> bool {
        self.stribeck
            .as_ref()
            .is_some_and(|stribeck| stribeck.value.eval(values) != 0.0)
    }

    /// The mode the contact is in with the parameter `values` when its mode is said to be
    /// `mode`: without a creeping range there, `creep±` is `slip±` (the two laws meet at
    /// the Stribeck velocity, which is zero).
    pub fn mode_at(&self, mode: ElementMode, values: &[f64]) -> ElementMode {
        match mode {
            ElementMode::CreepPositive if !self.creeps_at(values) => ElementMode::SlipPositive,
            ElementMode::CreepNegative if !self.creeps_at(values) => ElementMode::SlipNegative,
            _ => mode,
        }
    }
}

/// The modes of a friction contact without a creeping range.
const KARNOPP_MODES: &[ElementMode] = &[
    ElementMode::Stuck,
    ElementMode::SlipPositive,
    ElementMode::SlipNegative,
];

/// A compliance that carries tension only, like a string.
///
/// Taut, it is a linear compliance; slack, it carries no force but its (negative) extension
/// is still integrated, so it becomes taut again exactly when the slack is taken up.
#[derive(Clone, Debug)]
pub struct TensionOnly {
    /// The compliance when taut.
    pub compliance: Coefficient,
    /// The mode at the start.
    pub initial: ElementMode,
}

/// A one-sided limit on the flow through its bond, like a supply that cannot deliver more
/// than a maximum flow or a stop that a velocity cannot pass.
///
/// Open, it carries no effort and the flow is whatever the rest of the graph makes it; when
/// the flow into it reaches `max_flow` it limits, holding the flow at `max_flow` with
/// whatever effort that takes (absorbing the power a source would have pushed past the
/// limit), until that effort falls to zero and it opens again. The ideal limit needs no
/// stiff parameter: in each mode the element is a source (of zero effort, or of the flow
/// `max_flow`).
#[derive(Clone, Debug)]
pub struct FlowLimit {
    /// The largest flow into the element; affine in the inputs.
    pub max_flow: SourceValue,
    /// The mode at the start.
    pub initial: ElementMode,
}

/// The mode of one switching element.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ElementMode {
    /// A friction contact holding its relative velocity at zero.
    Stuck,
    /// A friction contact slipping with positive relative velocity.
    SlipPositive,
    /// A friction contact slipping with negative relative velocity.
    SlipNegative,
    /// A friction contact slipping forward slower than its Stribeck velocity.
    CreepPositive,
    /// A friction contact slipping backward slower than its Stribeck velocity.
    CreepNegative,
    /// A tension-only element carrying tension.
    Taut,
    /// A tension-only element gone slack.
    Slack,
    /// A flow limit below its limit, carrying no effort.
    Open,
    /// A flow limit holding the flow at its limit.
    Limiting,
}

impl ElementMode {
    /// The name used in mode specifications (`stuck`, `slip+`, `slip-`, `creep+`, `creep-`,
    /// `taut`, `slack`, `open`, `limiting`).
    pub fn name(self) -> &'static str {
        match self {
            ElementMode::Stuck => "stuck",
            ElementMode::SlipPositive => "slip+",
            ElementMode::SlipNegative => "slip-",
            ElementMode::CreepPositive => "creep+",
            ElementMode::CreepNegative => "creep-",
            ElementMode::Taut => "taut",
            ElementMode::Slack => "slack",
            ElementMode::Open => "open",
            ElementMode::Limiting => "limiting",
        }
    }

    /// The mode called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [
            ElementMode::Stuck,
            ElementMode::SlipPositive,
            ElementMode::SlipNegative,
            ElementMode::CreepPositive,
            ElementMode::CreepNegative,
            ElementMode::Taut,
            ElementMode::Slack,
            ElementMode::Open,
            ElementMode::Limiting,
        ]
        .into_iter()
        .find(|m| m.name() == name)
    }
}

impl ElementKind {
    /// The kind as written in model files (`Se`, `I`, `Zero`, ...).
    pub fn keyword(&self) -> &'static str {
        match self {
            ElementKind::EffortSource(_) => "Se",
            ElementKind::FlowSource(_) => "Sf",
            ElementKind::Inertia(_) => "I",
            ElementKind::Compliance(_) => "C",
            ElementKind::Resistor(_) => "R",
            ElementKind::Transformer(_) => "TF",
            ElementKind::Gyrator(_) => "GY",
            ElementKind::Friction(_) => "Friction",
            ElementKind::TensionOnly(_) => "TensionOnly",
            ElementKind::FlowLimit(_) => "FlowLimit",
            ElementKind::Nonlinear(n) => n.law.keyword(),
            ElementKind::ZeroJunction => "Zero",
            ElementKind::OneJunction => "One",
        }
    }

    /// A readable description of the kind ("inertia", "0-junction", ...).
    pub fn description(&self) -> &'static str {
        match self {
            ElementKind::EffortSource(_) => "effort source",
            ElementKind::FlowSource(_) => "flow source",
            ElementKind::Inertia(_) => "inertia",
            ElementKind::Compliance(_) => "compliance",
            ElementKind::Resistor(_) => "resistor",
            ElementKind::Transformer(_) => "transformer",
            ElementKind::Gyrator(_) => "gyrator",
            ElementKind::Friction(_) => "friction contact",
            ElementKind::TensionOnly(_) => "tension-only element",
            ElementKind::FlowLimit(_) => "flow limit",
            ElementKind::Nonlinear(n) => n.law.description(),
            ElementKind::ZeroJunction => "0-junction",
            ElementKind::OneJunction => "1-junction",
        }
    }

    /// The modes a switching element can be in (empty for plain elements).
    pub fn modes(&self) -> &'static [ElementMode] {
        match self {
            ElementKind::Friction(f) if f.stribeck.is_some() => &[
                ElementMode::Stuck,
                ElementMode::SlipPositive,
                ElementMode::SlipNegative,
                ElementMode::CreepPositive,
                ElementMode::CreepNegative,
            ],
            ElementKind::Friction(_) => KARNOPP_MODES,
            ElementKind::TensionOnly(_) => &[ElementMode::Taut, ElementMode::Slack],
            ElementKind::FlowLimit(_) => &[ElementMode::Open, ElementMode::Limiting],
            _ => &[],
        }
    }

    /// The modes a switching element can be in with the parameter `values` (indexed like
    /// [`Model::values`]): a friction contact's Stribeck velocity of zero there leaves it
    /// no `creep±`.
    pub fn modes_at(&self, values: &[f64]) -> &'static [ElementMode] {
        match self {
            ElementKind::Friction(f) if !f.creeps_at(values) => KARNOPP_MODES,
            _ => self.modes(),
        }
    }

    /// The mode a switching element starts in.
    pub fn initial_mode(&self) -> Option<ElementMode> {
        match self {
            ElementKind::Friction(f) => Some(f.initial),
            ElementKind::TensionOnly(t) => Some(t.initial),
            ElementKind::FlowLimit(l) => Some(l.initial),
            _ => None,
        }
    }

    /// How many bonds the element takes: `Some(n)` for a fixed number, `None` for a
    /// junction (two or more).
    pub fn port_count(&self) -> Option<usize> {
        match self {
            ElementKind::Transformer(_) | ElementKind::Gyrator(_) => Some(2),
            ElementKind::Nonlinear(n)
                if matches!(
                    n.law,
                    NonlinearLaw::Transformer(_) | NonlinearLaw::Gyrator(_)
                ) =>
            {
                Some(2)
            }
            ElementKind::ZeroJunction | ElementKind::OneJunction => None,
            _ => Some(1),
        }
    }
}

/// A bond: power flows from `from` to `to` (the half-arrow points at `to`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bond {
    /// The element at the tail.
    pub from: ElementId,
    /// The element at the head (the half-arrow).
    pub to: ElementId,
    /// The span of the bond in the file.
    pub span: Span,
}

impl Bond {
    /// The end of the bond that is not `element`.
    pub fn other(&self, element: ElementId) -> ElementId {
        if self.from == element {
            self.to
        } else {
            self.from
        }
    }

    /// `+1` if the bond points into `element`, `-1` if it points out of it.
    pub fn sign_into(&self, element: ElementId) -> i64 {
        if self.to == element { 1 } else { -1 }
    }
}

impl Model {
    /// The model's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What the model describes.
    pub fn description(&self) -> Option<&str> {
        self.description.as_deref()
    }

    /// The file it was read from (for locating diagnostics), or a source with no text for a
    /// model built in code.
    pub fn source(&self) -> &Arc<SourceFile> {
        &self.source
    }

    /// The parameter symbols, in print order.
    pub fn symbols(&self) -> &SymbolTable {
        &self.symbols
    }

    /// Parameters in file order.
    pub fn parameters(&self) -> &[Parameter] {
        &self.parameters
    }

    /// The model's ports, in file order: the junctions bonds attach to when it is used as a
    /// sub-model of another.
    pub fn ports(&self) -> &[Port] {
        &self.ports
    }

    /// The sub-models the model was composed from, in the order they are used (a nested
    /// use after its parent's, named `front.rear`): empty for a flat model.
    pub fn parts(&self) -> &[crate::model::PartSpec] {
        &self.parts
    }

    /// Inputs in file order.
    pub fn inputs(&self) -> &[Input] {
        &self.inputs
    }

    /// Elements in file order.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Bonds in file order.
    pub fn bonds(&self) -> &[Bond] {
        &self.bonds
    }

    /// Parameter values indexed by [`Symbol::index`] (in SI units).
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Sets the value of parameter `symbol` (in SI units), as a fit's trial: in
    /// [`Model::values`] and in its [`Parameter`]. The model's laws are symbolic, so nothing
    /// else depends on it.
    ///
    /// # Panics
    /// If `symbol` is not one of this model's parameters.
    pub fn set_value(&mut self, symbol: Symbol, value: f64) {
        self.values[symbol.index()] = value;
        if let Some(parameter) = self.parameters.iter_mut().find(|p| p.symbol == symbol) {
            parameter.value = value;
        }
    }

    /// The linear graph the model was translated from, if its file is a `LinearGraph(...)`:
    /// its nodes and branches, and where each branch is in this bond graph.
    pub fn linear_graph(&self) -> Option<&Arc<crate::model::linear_graph::LinearGraph>> {
        self.linear_graph.as_ref()
    }

    /// The dimensions of each bond's effort and flow, where the units check could tell them
    /// (indexed by [`BondId::index`]; see [`crate::units`]).
    pub fn bond_dimensions(&self) -> &[crate::units::BondDimensions] {
        &self.bond_dimensions
    }

    /// The model as a directed graph: node `i` is element `i`, edge `j` is bond `j`, pointing
    /// the way power flows.
    pub fn bond_graph(&self) -> petgraph::graph::DiGraph<ElementId, BondId> {
        use petgraph::graph::{DiGraph, NodeIndex};
        let mut graph = DiGraph::with_capacity(self.elements.len(), self.bonds.len());
        for element in self.element_ids() {
            graph.add_node(element);
        }
        for bond in self.bond_ids() {
            let b = self.bond(bond);
            graph.add_edge(
                NodeIndex::new(b.from.index()),
                NodeIndex::new(b.to.index()),
                bond,
            );
        }
        graph
    }

    /// The element with id `id`.
    pub fn element(&self, id: ElementId) -> &Element {
        &self.elements[id.index()]
    }

    /// The bond with id `id`.
    pub fn bond(&self, id: BondId) -> &Bond {
        &self.bonds[id.index()]
    }

    /// The element called `name`.
    pub fn element_named(&self, name: &str) -> Option<ElementId> {
        self.elements
            .iter()
            .position(|e| e.name == name)
            .map(|i| ElementId(i as u32))
    }

    /// The input called `name`.
    pub fn input_named(&self, name: &str) -> Option<InputId> {
        self.inputs
            .iter()
            .position(|e| e.name == name)
            .map(|i| InputId(i as u32))
    }

    /// Where element `id` is defined: in the model's file (for a sub-model's element, where
    /// the sub-model is used; see [`Model::element_origin`]).
    pub fn locate_element(&self, id: ElementId) -> Location {
        self.source.locate(self.element(id).span)
    }

    /// Where a sub-model's element `id` is written in the sub-model's own file; `None` for
    /// an element of the model's own file.
    pub fn element_origin(&self, id: ElementId) -> Option<&Location> {
        let name = &self.element(id).name;
        self.parts
            .iter()
            .flat_map(|part| &part.origins)
            .find(|(element, _)| element == name)
            .map(|(_, location)| location)
    }

    /// Where bond `id` is defined.
    pub fn locate_bond(&self, id: BondId) -> Location {
        self.source.locate(self.bond(id).span)
    }

    /// A readable name for bond `id`: `from -> to`.
    pub fn bond_label(&self, id: BondId) -> String {
        let bond = self.bond(id);
        format!(
            "{} -> {}",
            self.element(bond.from).name,
            self.element(bond.to).name
        )
    }

    /// Whether any element has a nonlinear or modulated law: then every mode is derived as
    /// `dx/dt = f(x, u)` ([`crate::equations::nonlinear`]).
    pub fn is_nonlinear(&self) -> bool {
        self.elements
            .iter()
            .any(|e| matches!(e.kind, ElementKind::Nonlinear(_)))
    }

    /// The name of the state of storage element `id` in energy variables (`p_mass`,
    /// `q_spring`), if it is storage.
    pub fn storage_name(&self, id: ElementId) -> Option<String> {
        let element = self.element(id);
        let letter = match &element.kind {
            ElementKind::Inertia(_) => "p",
            ElementKind::Compliance(_) | ElementKind::TensionOnly(_) => "q",
            ElementKind::Nonlinear(n) => match n.law {
                NonlinearLaw::Inertia(_) => "p",
                NonlinearLaw::Compliance(_) => "q",
                _ => return None,
            },
            _ => return None,
        };
        Some(match &element.symbol {
            Some(symbol) => symbol.clone(),
            None => super::state_symbol(letter, &element.name),
        })
    }

    /// The energy domain of element `id`'s (first) bond, if its units tell it: a capacitor's
    /// bond is electrical, a spring's mechanical translational.
    pub fn element_domain(&self, id: ElementId) -> Option<&'static crate::units::Domain> {
        let bond = self.element(id).bonds.first()?;
        let dims = self.bond_dimensions.get(bond.index())?;
        crate::units::Domain::of(dims.effort?, dims.flow?)
    }

    /// The parameters some element's law uses: a parameter outside it (one only a removed
    /// element used) changes nothing the model computes.
    pub fn parameters_in_use(&self) -> BTreeSet<Symbol> {
        let mut used = BTreeSet::new();
        let mut form = |form: &LinearForm| {
            for (_, coefficient) in form.terms() {
                used.extend(coefficient.symbols());
            }
        };
        let mut law_symbols = Vec::new();
        for element in &self.elements {
            match &element.kind {
                ElementKind::EffortSource(v) | ElementKind::FlowSource(v) => form(&v.value),
                ElementKind::Inertia(c)
                | ElementKind::Compliance(c)
                | ElementKind::Resistor(c)
                | ElementKind::Transformer(c)
                | ElementKind::Gyrator(c) => law_symbols.push(c.value.symbols()),
                ElementKind::Friction(f) => {
                    form(&f.breakaway.value);
                    form(&f.coulomb.value);
                    law_symbols.push(f.viscous.value.symbols());
                    law_symbols.push(f.dead_band.value.symbols());
                    if let Some(s) = &f.stribeck {
                        law_symbols.push(s.value.symbols());
                    }
                }
                ElementKind::TensionOnly(t) => law_symbols.push(t.compliance.value.symbols()),
                ElementKind::FlowLimit(l) => form(&l.max_flow.value),
                ElementKind::Nonlinear(n) => law_symbols.push(n.law.parameters()),
                ElementKind::ZeroJunction | ElementKind::OneJunction => {}
            }
        }
        used.extend(law_symbols.into_iter().flatten());
        used
    }

    /// Evaluates a symbolic coefficient with the model's parameter values.
    pub fn evaluate(&self, value: &RatFunc) -> f64 {
        value.eval(&self.values)
    }

    /// The ids of all elements.
    pub fn element_ids(&self) -> impl Iterator<Item = ElementId> + '_ {
        (0..self.elements.len() as u32).map(ElementId)
    }

    /// The ids of all bonds.
    pub fn bond_ids(&self) -> impl Iterator<Item = BondId> + '_ {
        (0..self.bonds.len() as u32).map(BondId)
    }
}

/// Placing a diagnostic at an element of a model: its location, and for a sub-model's
/// element a note naming where the element is written in its own file.
pub trait AtElement {
    /// The diagnostic at element `id` of `model`.
    #[must_use]
    fn at_element(self, model: &Model, id: ElementId) -> Self;
}

impl AtElement for crate::diagnostics::Diagnostic {
    fn at_element(self, model: &Model, id: ElementId) -> Self {
        let placed = self.at_location(model.locate_element(id));
        match model.element_origin(id) {
            Some(origin) if !origin.is_in_code() => {
                let name = &model.element(id).name;
                let leaf = name.rsplit('.').next().unwrap_or(name);
                placed.note(format!("'{name}' is element '{leaf}' of {origin}"))
            }
            _ => placed,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(model: &Model, symbols: &BTreeSet<Symbol>) -> Vec<String> {
        let mut names: Vec<String> = model
            .parameters
            .iter()
            .filter(|p| symbols.contains(&p.symbol))
            .map(|p| p.name.clone())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn parameters_in_use_are_those_some_law_names() {
        // `unused` is in no law; `mu` only in an input's coefficient of the contact's forces;
        // `g` and `l` only inside a nonlinear law's coefficient; `c` in a flow limit.
        let model = crate::testing::model(
            r#"Model(
                name: "uses",
                parameters: {
                    "m": (value: 1.0), "g": (value: 9.81), "l": (value: 2.0),
                    "F_S": (value: 2.0), "F_C": (value: 1.0), "mu": (value: 0.1),
                    "dv": (value: 1.0e-6), "c": (value: 3.0), "unused": (value: 5.0),
                },
                inputs: { "P": () },
                elements: {
                    "push": Se(effort: "P"), "v": One, "body": I(inertance: "m"),
                    "pendulum": C(effort: "m*g*l*sin(q_pendulum)"),
                    "contact": Friction(breakaway: "F_S + mu*P", coulomb: "F_C + mu*P", dead_band: "dv"),
                    "stop": FlowLimit(max_flow: "c"),
                },
                bonds: [("push", "v"), ("v", "body"), ("v", "pendulum"), ("v", "contact"), ("v", "stop")],
            )"#,
        );
        assert_eq!(
            names(&model, &model.parameters_in_use()),
            ["F_C", "F_S", "c", "dv", "g", "l", "m", "mu"]
        );
    }
}
