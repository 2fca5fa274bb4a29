//! From energy variables (`p`, `q`) to co-energy variables (`v`, `f`).
//!
//! Energy variables are what the junction structure integrates, so derivation happens in
//! them; textbooks and papers usually write velocities and forces. Per storage block
//! `x = M y + r` (a mass or compliance matrix, with the constant momentum of merged storage
//! driven by constant sources as `r`), so `dy/dt = M⁻¹ dx/dt`: a change of variables, exact,
//! with the same eigenvalues.

use crate::diagnostics::{Diagnostic, DiagnosticKind, Result};
use crate::equations::matrix;
use crate::equations::merging::Block;
use crate::linear::{LinearForm, Var};
use crate::model::{ElementId, Model};

pub(crate) struct Converted {
    pub derivatives: Vec<LinearForm>,
    pub bond_vars: Vec<LinearForm>,
    pub storage_energy: Vec<(ElementId, LinearForm)>,
}

pub(crate) fn convert(
    model: &Model,
    blocks: &[Block],
    state_elements: &[ElementId],
    derivatives: &[LinearForm],
    bond_vars: &[LinearForm],
    storage_energy: &[(ElementId, LinearForm)],
) -> Result<Converted> {
    // x_k as a form of the co-energy states y.
    let mut energy_in_coenergy: Vec<LinearForm> = vec![LinearForm::zero(); derivatives.len()];
    for block in blocks {
        for (a, &k) in block.states.iter().enumerate() {
            if block.offset[a].mentions(|v| matches!(v, Var::Input(_))) {
                let element = state_elements[k as usize];
                let name = &model.element(element).name;
                return Err(Diagnostic::new(
                    DiagnosticKind::DependentStorage,
                    format!(
                        "co-energy states are not available for this mode: the merged state of '{name}' includes storage driven directly by an input"
                    ),
                )
                .at_location(model.locate_element(element))
                .element(name.clone())
                .note("derive in energy variables (the default) instead")
                .into());
            }
            let mut form = block.offset[a].clone();
            for (b, &l) in block.states.iter().enumerate() {
                form.add_scaled(&LinearForm::var(Var::State(l)), &block.matrix[a][b]);
            }
            energy_in_coenergy[k as usize] = form;
        }
    }
    let substitute = |form: &LinearForm| {
        form.substitute(|var| match var {
            Var::State(k) => Some(energy_in_coenergy[k as usize].clone()),
            _ => None,
        })
    };

    let mut converted = vec![LinearForm::zero(); derivatives.len()];
    for block in blocks {
        let rates: Vec<LinearForm> = block
            .states
            .iter()
            .map(|&k| substitute(&derivatives[k as usize]))
            .collect();
        for (a, row) in matrix::apply(&block.inverse, &rates)
            .into_iter()
            .enumerate()
        {
            converted[block.states[a] as usize] = row;
        }
    }

    Ok(Converted {
        derivatives: converted,
        bond_vars: bond_vars.iter().map(&substitute).collect(),
        storage_energy: storage_energy
            .iter()
            .map(|(e, v)| (*e, substitute(v)))
            .collect(),
    })
}
