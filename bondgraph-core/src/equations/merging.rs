//! Dependent storage, merged into the independent states it follows.
//!
//! An inertia in derivative causality has its velocity imposed by the rest of the graph:
//! `f_d = Σₖ T_dk f_k + s_d` where `f_k` are velocities of independent inertias and `s_d`
//! comes from sources. It has no state of its own. Instead of differentiating (which would
//! make the equations implicit), its inertia is merged into the inertias it follows. With
//! `M' = diag(m_k) + Tᵀ diag(m_d) T` the group's mass matrix, the generalised momentum
//! `p' = M' f + Tᵀ diag(m_d) s` obeys `dp'/dt = e_k + Σ_d T_dk e_d`, and by power
//! conservation of the junction structure the unknown efforts `e_d` cancel from that sum.
//! The dependents' own efforts then follow from the group's acceleration; where a dependent
//! is driven by an input (a block stuck to a belt moving at `v_belt`), they involve the
//! input's rate ([`Var::InputRate`]), which output equations and guards may use, and which
//! a state equation keeps as its `E du/dt` term where storage held by an input feeds a
//! state.
//! So the group keeps one state per independent inertia, its momentum now including the
//! dependent ones: two masses on one 1-junction become one mass `m1 + m2`, and a block
//! stuck to a carriage becomes the single body `M = m_block + m_carriage` of that mode.
//!
//! The group's matrix `M'` is dense as soon as one dependent follows all its states, so it
//! is kept as its diagonal plus one rank-one term per dependent ([`StorageMatrix`]), and
//! everything is first written in the states' own energy variables (`p_k = m_k f_k`), in which
//! merging keeps every form as sparse as the junction structure made it. Only then are the
//! equations written in the mode's states: the generalised momenta (energy variables, dense
//! where merging ties states together) or the velocities (co-energy variables, in which
//! each element's own momentum is simply `m_k v_k`).
//!
//! Compliances are merged the same way with efforts and flows exchanged. Storage whose
//! flow is fixed by sources alone (`T = 0`, a mass held by a stuck contact) is *held*: it
//! has no state, and its effort is zero for constant sources.
//!
//! # Errors
//! [`DiagnosticKind::DependentStorage`] when a dependent element follows a storage element
//! of the other kind (an inertia whose velocity is set by a spring through a damper).

use std::collections::BTreeMap;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::elimination::{Numbering, effort, flow};
use crate::equations::matrix::StorageMatrix;
use crate::laws::Law;
use crate::linear::{LinearForm, Var};
use crate::model::AtElement;
use crate::model::{ElementId, Model};
use crate::symbolic::RatFunc;

/// The kind of a state, which decides what it may be merged with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Domain {
    /// Momentum of an inertia.
    Kinetic,
    /// Displacement of a compliance.
    Potential,
    /// Slack length of a tension-only element gone slack (never merged).
    Slack,
}

/// A group of states whose energy variables are tied by a (possibly merged) storage matrix:
/// `x_energy[states[i]] = Σⱼ matrix[i][j] · y[states[j]] + offset[i]` where `y` are the
/// co-energy variables (velocities, efforts).
#[derive(Clone, Debug)]
pub(crate) struct Block {
    pub states: Vec<u32>,
    pub matrix: StorageMatrix,
    /// Affine in inputs and constants only.
    pub offset: Vec<LinearForm>,
}

/// The equations after merging, written in the states' own energy variables before merging
/// (`Var::State(k)` is the momentum or displacement of the `k`-th independent storage
/// element): sparse, whatever merging tied together. [`Merged::in_energy_variables`] and
/// [`coenergy::convert`](super::coenergy::convert) write them in the mode's states.
pub(crate) struct Merged {
    /// The derivative of each state's merged (generalised) energy variable, over
    /// [`Var::State`], [`Var::Input`], [`Var::Constant`].
    pub derivatives: Vec<LinearForm>,
    /// Every bond variable in the same terms, and the inputs' rates ([`Var::InputRate`])
    /// where storage driven directly by an input makes it depend on them.
    pub bond_vars: Vec<LinearForm>,
    /// Dependent elements merged into each state (by state index).
    pub merged_into: Vec<Vec<ElementId>>,
    /// Held storage: dependent elements following no state.
    pub held: Vec<ElementId>,
    /// The storage blocks, covering every state once.
    pub blocks: Vec<Block>,
    /// The energy variable of every storage element of the mode (states and dependents):
    /// for reconstructing the full physical state.
    pub storage_energy: BTreeMap<ElementId, LinearForm>,
    /// The inertance or compliance of each state's own element.
    pub storage_of_state: Vec<RatFunc>,
}

/// The equations written in the mode's states.
pub(crate) struct InStates {
    pub derivatives: Vec<LinearForm>,
    pub bond_vars: Vec<LinearForm>,
    pub storage_energy: Vec<(ElementId, LinearForm)>,
}

impl Merged {
    /// Substitutes every state's own energy variable by `own(k)` (where it gives one).
    pub(crate) fn substituted(
        &self,
        derivatives: Vec<LinearForm>,
        own: impl Fn(u32) -> Option<LinearForm>,
    ) -> InStates {
        let substitute = |form: &LinearForm| {
            form.substitute(|var| match var {
                Var::State(k) => own(k),
                _ => None,
            })
        };
        InStates {
            derivatives,
            bond_vars: self.bond_vars.iter().map(&substitute).collect(),
            storage_energy: self
                .storage_energy
                .iter()
                .map(|(e, form)| (*e, substitute(form)))
                .collect(),
        }
    }

    /// The equations in energy variables: each state is its group's generalised momentum
    /// (or displacement) `x' = M y + offset`, so each element's own energy variable is
    /// `x_k = storage_k · y_k` with `y = M⁻¹ (x' - offset)`.
    pub(crate) fn in_energy_variables(&self) -> InStates {
        let mut own: Vec<Option<LinearForm>> = vec![None; self.derivatives.len()];
        for block in self.blocks.iter().filter(|b| b.matrix.has_dependents()) {
            let shifted: Vec<LinearForm> = block
                .states
                .iter()
                .zip(&block.offset)
                .map(|(&l, offset)| {
                    let mut form = LinearForm::var(Var::State(l));
                    form.add_scaled(offset, &RatFunc::integer(-1));
                    form
                })
                .collect();
            for (&k, velocity) in block.states.iter().zip(block.matrix.solve(&shifted)) {
                own[k as usize] = Some(velocity.scaled(&self.storage_of_state[k as usize]));
            }
        }
        if own.iter().all(Option::is_none) {
            // Nothing merged: every state is its element's own energy variable.
            return InStates {
                derivatives: self.derivatives.clone(),
                bond_vars: self.bond_vars.clone(),
                storage_energy: self.storage_energy.clone().into_iter().collect(),
            };
        }
        let substitute = |form: &LinearForm| {
            form.substitute(|var| match var {
                Var::State(k) => own[k as usize].clone(),
                _ => None,
            })
        };
        let derivatives = self.derivatives.iter().map(substitute).collect();
        self.substituted(derivatives, |k| own[k as usize].clone())
    }
}

/// What resolving the dependents of one merged group needs.
struct GroupSolution {
    /// The group's block.
    block: usize,
    /// For each dependent (by index), its row of `T` over the group's states.
    t_rows: Vec<(usize, Vec<RatFunc>)>,
}

struct Dependent {
    element: ElementId,
    /// The dependent's flow (inertia) or effort (compliance), before merging.
    driven: LinearForm,
    storage: RatFunc,
}

/// Merges dependent storage into the states it follows; see the module documentation.
pub(crate) fn merge(
    model: &Model,
    laws: &[Law],
    numbering: &Numbering,
    state_elements: &[ElementId],
    bond_vars: &[LinearForm],
) -> Result<Merged> {
    let state_count = state_elements.len();
    let storage_of_state: Vec<RatFunc> = state_elements
        .iter()
        .map(|e| storage_coefficient(&laws[e.index()]))
        .collect();

    // Own derivatives: dp/dt = e for an inertia, dq/dt = f (into the element) otherwise.
    let mut derivatives: Vec<LinearForm> = state_elements
        .iter()
        .map(|&e| {
            let bond = model.element(e).bonds[0];
            match domain(&laws[e.index()]) {
                Domain::Kinetic => bond_vars[effort(bond).bond_index()].clone(),
                _ => bond_vars[flow(bond).bond_index()]
                    .scaled(&RatFunc::integer(model.bond(bond).sign_into(e))),
            }
        })
        .collect();

    let dependents = dependents(model, laws, numbering, state_elements, bond_vars)?;
    let Groups {
        members,
        group_dependents,
        held,
    } = groups(state_count, &dependents);
    let Blocks {
        blocks,
        merged_into,
        group_solutions,
    } = blocks(
        model,
        (state_elements, &storage_of_state),
        &dependents,
        &members,
        &group_dependents,
    )?;

    // Merged derivatives: dx'_k/dt = dx_k/dt + Σ_d T_dk e_d, where the e_d cancel.
    for GroupSolution { block, t_rows } in &group_solutions {
        for (a, &k) in blocks[*block].states.iter().enumerate() {
            for (j, row) in t_rows {
                derivatives[k as usize]
                    .add_scaled(&LinearForm::var(Var::Dependent(*j as u32)), &row[a]);
            }
            for (j, _) in t_rows {
                if derivatives[k as usize]
                    .get(Var::Dependent(*j as u32))
                    .is_some()
                {
                    let element = dependents[*j].element;
                    let feedback = feedback_sources(model, laws);
                    if !feedback.is_empty() {
                        return Err(through_feedback(model, element, &feedback));
                    }
                    return Err(internal(
                        model,
                        element,
                        "the effort of a merged element did not cancel (junction structure not power-conserving)",
                    ));
                }
            }
        }
    }

    // Each dependent's own effort (inertia) or flow (compliance): storage · d/dt(driven),
    // where the time derivative of an input is its rate, `Var::InputRate`.
    let source_rate = |j: usize| input_rate(&dependents[j].driven);
    let mut dependent_value: Vec<LinearForm> = vec![LinearForm::zero(); dependents.len()];
    for &j in &held {
        dependent_value[j] = source_rate(j).scaled(&dependents[j].storage);
    }
    let held_values = dependent_value.clone();
    let substitute_held = |form: &LinearForm| {
        form.substitute(|var| match var {
            Var::Dependent(j) if held.contains(&(j as usize)) => {
                Some(held_values[j as usize].clone())
            }
            _ => None,
        })
    };
    for GroupSolution { block, t_rows } in &group_solutions {
        let block = &blocks[*block];
        // M' df/dt = dp'/dt - Σ_d T_dᵀ m_d ds_d/dt: the momentum fed in by the sources moves
        // with them, not with the group.
        let mut forcing: Vec<LinearForm> = block
            .states
            .iter()
            .map(|&k| substitute_held(&derivatives[k as usize]))
            .collect();
        for (j, row) in t_rows {
            let fed = source_rate(*j);
            for (a, entry) in row.iter().enumerate() {
                if !entry.is_zero() {
                    forcing[a].add_scaled(&fed, &-(entry * &dependents[*j].storage));
                }
            }
        }
        let accelerations = block.matrix.solve(&forcing);
        for (j, row) in t_rows {
            let mut value = source_rate(*j);
            for (a, acceleration) in accelerations.iter().enumerate() {
                value.add_scaled(acceleration, &row[a]);
            }
            dependent_value[*j] = value.scaled(&dependents[*j].storage);
        }
    }

    let resolve = |form: &LinearForm| -> LinearForm {
        if dependents.is_empty() {
            return form.clone();
        }
        form.substitute(|var| match var {
            Var::Dependent(j) => Some(dependent_value[j as usize].clone()),
            _ => None,
        })
    };

    for derivative in &mut derivatives {
        *derivative = resolve(derivative);
    }

    let mut storage_energy = BTreeMap::new();
    for (k, &element) in state_elements.iter().enumerate() {
        storage_energy.insert(element, LinearForm::var(Var::State(k as u32)));
    }
    for dependent in &dependents {
        // x_d = storage_d · driven_d.
        storage_energy.insert(
            dependent.element,
            dependent.driven.scaled(&dependent.storage),
        );
    }

    Ok(Merged {
        derivatives,
        bond_vars: bond_vars.iter().map(resolve).collect(),
        merged_into,
        held: held.iter().map(|&j| dependents[j].element).collect(),
        blocks,
        storage_energy,
        storage_of_state,
    })
}

/// The dependent storage of this mode, in numbering order: what drives each (its flow for
/// an inertia, its effort for a compliance) and its storage coefficient. A dependent driven
/// through a nonlinear law, or by storage of another domain, is an error.
fn dependents(
    model: &Model,
    laws: &[Law],
    numbering: &Numbering,
    state_elements: &[ElementId],
    bond_vars: &[LinearForm],
) -> Result<Vec<Dependent>> {
    let domain_of_state: Vec<Domain> = state_elements
        .iter()
        .map(|e| domain(&laws[e.index()]))
        .collect();
    let mut dependents: Vec<Dependent> = Vec::new();
    for element in model.element_ids() {
        let Some(index) = numbering.dependent[element.index()] else {
            continue;
        };
        debug_assert_eq!(index as usize, dependents.len());
        let law = &laws[element.index()];
        let bond = model.element(element).bonds[0];
        let driven = match domain(law) {
            Domain::Kinetic => bond_vars[flow(bond).bond_index()]
                .scaled(&RatFunc::integer(model.bond(bond).sign_into(element))),
            _ => bond_vars[effort(bond).bond_index()].clone(),
        };
        if driven.mentions(|v| matches!(v, Var::Auxiliary(_))) {
            return Err(crate::equations::nonlinear::dependent_through_law(
                model, laws, element,
            ));
        }
        let own = domain(law);
        for (var, _) in driven.terms() {
            let offending = match var {
                Var::State(k) if domain_of_state[*k as usize] != own => {
                    Some(state_elements[*k as usize])
                }
                Var::Dependent(j) => {
                    Some(dependents.get(*j as usize).map_or(element, |d| d.element))
                }
                _ => None,
            };
            if let Some(other) = offending {
                return Err(cross_domain(model, element, other));
            }
        }
        dependents.push(Dependent {
            element,
            driven,
            storage: storage_coefficient(law),
        });
    }

    Ok(dependents)
}

/// States connected through dependents, and which dependents each group has.
struct Groups {
    /// Each group's states, by the group's root state.
    members: BTreeMap<usize, Vec<u32>>,
    /// Each group's dependents (by index), by the group's root state.
    group_dependents: BTreeMap<usize, Vec<usize>>,
    /// The dependents that follow no state (held by sources alone).
    held: Vec<usize>,
}

/// Groups the states connected through dependents (union-find).
fn groups(state_count: usize, dependents: &[Dependent]) -> Groups {
    let mut parent: Vec<usize> = (0..state_count).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for dependent in dependents {
        let followed: Vec<usize> = followed_states(&dependent.driven);
        for pair in followed.windows(2) {
            let (a, b) = (root(&mut parent, pair[0]), root(&mut parent, pair[1]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut members: BTreeMap<usize, Vec<u32>> = BTreeMap::new();
    for state in 0..state_count {
        let r = root(&mut parent, state);
        members.entry(r).or_default().push(state as u32);
    }
    let mut group_dependents: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    let mut held: Vec<usize> = Vec::new();
    for (j, dependent) in dependents.iter().enumerate() {
        match followed_states(&dependent.driven).first() {
            Some(&k) => group_dependents
                .entry(root(&mut parent, k))
                .or_default()
                .push(j),
            None => held.push(j),
        }
    }

    Groups {
        members,
        group_dependents,
        held,
    }
}

/// Each group's block, where its dependents are reported, and the groups with dependents.
struct Blocks {
    blocks: Vec<Block>,
    merged_into: Vec<Vec<ElementId>>,
    group_solutions: Vec<GroupSolution>,
}

/// Each group's storage matrix and the momentum its dependents' sources feed in.
fn blocks(
    model: &Model,
    (state_elements, storage_of_state): (&[ElementId], &[RatFunc]),
    dependents: &[Dependent],
    members: &BTreeMap<usize, Vec<u32>>,
    group_dependents: &BTreeMap<usize, Vec<usize>>,
) -> Result<Blocks> {
    let state_count = state_elements.len();
    let mut blocks = Vec::new();
    let mut merged_into: Vec<Vec<ElementId>> = vec![Vec::new(); state_count];
    let mut group_solutions: Vec<GroupSolution> = Vec::new();
    for (group_root, states) in members {
        let deps = group_dependents
            .get(group_root)
            .cloned()
            .unwrap_or_default();
        let n = states.len();
        // T_dk = τ_dk · storage_k, where the dependent follows f_k = x_k / storage_k.
        let t_rows: Vec<(usize, Vec<RatFunc>)> = deps
            .iter()
            .map(|&j| {
                let row = states
                    .iter()
                    .map(|&k| {
                        &dependents[j].driven.coefficient(Var::State(k))
                            * &storage_of_state[k as usize]
                    })
                    .collect();
                (j, row)
            })
            .collect();
        let mut offset = vec![LinearForm::zero(); n];
        for (j, row) in &t_rows {
            let dependent = &dependents[*j];
            let sources = dependent
                .driven
                .filtered(|v| matches!(v, Var::Input(_) | Var::Constant));
            for a in 0..n {
                if !row[a].is_zero() {
                    offset[a].add_scaled(&sources, &(&row[a] * &dependent.storage));
                }
            }
            // The dependent is reported under the first state it follows.
            let first_followed = row.iter().position(|c| !c.is_zero()).unwrap_or(0);
            merged_into[states[first_followed] as usize].push(dependent.element);
        }
        let matrix = StorageMatrix::new(
            states
                .iter()
                .map(|&k| storage_of_state[k as usize].clone())
                .collect(),
            t_rows.iter().map(|(_, row)| row.clone()).collect(),
            t_rows
                .iter()
                .map(|(j, _)| dependents[*j].storage.clone())
                .collect(),
        );
        let Some(matrix) = matrix else {
            let element = deps
                .first()
                .map_or(state_elements[states[0] as usize], |&j| {
                    dependents[j].element
                });
            return Err(singular_merge(model, element));
        };
        if !t_rows.is_empty() {
            group_solutions.push(GroupSolution {
                block: blocks.len(),
                t_rows,
            });
        }
        blocks.push(Block {
            states: states.clone(),
            matrix,
            offset,
        });
    }

    Ok(Blocks {
        blocks,
        merged_into,
        group_solutions,
    })
}

/// The time derivative of the input part of `form`: each input replaced by its rate, the
/// constant and everything else dropped.
pub(crate) fn input_rate(form: &LinearForm) -> LinearForm {
    let mut rate = LinearForm::zero();
    for (var, coefficient) in form.terms() {
        if let Var::Input(i) = var {
            rate.add_scaled(&LinearForm::var(Var::InputRate(*i)), coefficient);
        }
    }
    rate
}

/// The states a dependent's driven variable follows.
fn followed_states(driven: &LinearForm) -> Vec<usize> {
    driven
        .terms()
        .iter()
        .filter_map(|(v, _)| match v {
            Var::State(k) => Some(*k as usize),
            _ => None,
        })
        .collect()
}

pub(crate) fn domain(law: &Law) -> Domain {
    match law {
        Law::Inertia(_) => Domain::Kinetic,
        Law::Compliance(_) => Domain::Potential,
        Law::Nonlinear(nonlinear) => match **nonlinear {
            crate::model::NonlinearLaw::Inertia(_) => Domain::Kinetic,
            crate::model::NonlinearLaw::Compliance(_) => Domain::Potential,
            _ => Domain::Slack,
        },
        _ => Domain::Slack,
    }
}

/// The inertance or compliance of a storage law; 1 for slack storage (its state is its own
/// co-energy variable) and for nonlinear storage (never merged, and never converted to
/// co-energy variables).
pub(crate) fn storage_coefficient(law: &Law) -> RatFunc {
    match law {
        Law::Inertia(m) | Law::Compliance(m) => m.clone(),
        _ => RatFunc::one(),
    }
}

fn cross_domain(model: &Model, dependent: ElementId, other: ElementId) -> Diagnostics {
    let d = model.element(dependent);
    let o = model.element(other);
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!(
            "{} '{}' is in derivative causality and follows {} '{}' of another kind; it cannot be merged into one state",
            d.kind.description(),
            d.name,
            o.kind.description(),
            o.name
        ),
    )
    .at_element(model, dependent)
    .element(d.name.clone())
    .note("add a compliance or resistor next to it so that it can keep its own state")
    .into()
}

/// The sources of the mode whose value feeds back a state.
fn feedback_sources(model: &Model, laws: &[Law]) -> Vec<String> {
    model
        .element_ids()
        .filter(|e| match &laws[e.index()] {
            Law::EffortSource(value) | Law::FlowSource(value) => {
                value.mentions(|v| matches!(v, Var::Storage(_)))
            }
            _ => false,
        })
        .map(|e| format!("'{}'", model.element(e).name))
        .collect()
}

/// A dependent element that follows a state through a source's feedback: the source
/// imposes its motion like a controller, not like a rigid link, so the junction structure
/// does not cancel its effort and merging does not apply.
fn through_feedback(model: &Model, dependent: ElementId, sources: &[String]) -> Diagnostics {
    let name = &model.element(dependent).name;
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!(
            "'{name}' is in derivative causality and follows a state through the feedback of {}; it cannot be merged into one state",
            sources.join(", ")
        ),
    )
    .at_element(model, dependent)
    .element(name.clone())
    .note("add a compliance or resistor next to it so that it keeps its own state")
    .into()
}

fn singular_merge(model: &Model, element: ElementId) -> Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!("merging '{name}' into the states it follows gives a singular storage matrix"),
    )
    .at_element(model, element)
    .element(name.clone())
    .into()
}

fn internal(model: &Model, element: ElementId, what: &str) -> Diagnostics {
    let name = &model.element(element).name;
    Diagnostic::new(
        DiagnosticKind::DependentStorage,
        format!("internal error while merging '{name}': {what}"),
    )
    .at_element(model, element)
    .element(name.clone())
    .note("please report this model as a bug")
    .into()
}

trait BondIndex {
    fn bond_index(self) -> usize;
}

impl BondIndex for Var {
    fn bond_index(self) -> usize {
        match self {
            Var::Bond(i) => i as usize,
            _ => unreachable!("only bond variables index bond_vars"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equations::{elimination, number_storage};
    use crate::{causality, laws};

    /// A force source on a massless node held by spring `K2` (dependent storage), joined to
    /// a mass by `n` parallel springs (each a 0-junction between the node's and the mass's
    /// velocities).
    fn parallel_springs(n: usize) -> Model {
        let mut elements = vec![
            r#""F": Se(effort: "F"), "node": One, "v_m": One, "mass": I(inertance: "m")"#
                .to_string(),
            r#""K2": C(stiffness: "K2")"#.to_string(),
        ];
        let mut bonds = vec![r#"("F", "node"), ("node", "K2"), ("v_m", "mass")"#.to_string()];
        for i in 1..=n {
            elements.push(format!(r#""s{i}": Zero, "S{i}": C(stiffness: "K1")"#));
            bonds.push(format!(
                r#"("node", "s{i}"), ("s{i}", "S{i}"), ("s{i}", "v_m")"#
            ));
        }
        crate::testing::model(&format!(
            r#"Model(name: "parallel_springs",
                parameters: {{"m": (value: 2.0), "K1": (value: 300.0), "K2": (value: 100.0)}},
                inputs: {{"F": ()}}, elements: {{ {} }}, bonds: [{}])"#,
            elements.join(",\n"),
            bonds.join(",\n")
        ))
    }

    /// The size of the linear system each block solves to merge its dependents.
    fn system_sizes(model: &Model) -> Vec<(usize, usize)> {
        let laws = laws::plain_laws(model);
        let causal = causality::assign(model, &laws).unwrap();
        let (numbering, state_elements) =
            number_storage(model, &laws, &causal, vec![None; model.elements.len()]);
        let solved = elimination::solve(model, &laws, &causal, &numbering).unwrap();
        let merged = merge(model, &laws, &numbering, &state_elements, &solved.bond_vars).unwrap();
        merged
            .blocks
            .iter()
            .map(|b| (b.states.len(), b.matrix.system_size()))
            .collect()
    }

    /// Forty springs follow one dependent: their block solves a 1 × 1 system (Woodbury's
    /// capacitance matrix), not the 40 × 40 storage matrix it once inverted densely.
    #[test]
    fn one_dependent_following_forty_states_solves_a_one_by_one_system() {
        let model = parallel_springs(40);
        assert_eq!(system_sizes(&model), [(1, 0), (40, 1)]);
    }
}
