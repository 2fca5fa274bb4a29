//! From energy variables (`p`, `q`) to co-energy variables (`v`, `f`).
//!
//! Energy variables are what the junction structure integrates, so derivation happens in
//! them; textbooks and papers usually write velocities and forces. Per storage block
//! `x = M y + r(u)` (a mass or compliance matrix, with the momentum of merged storage driven
//! by sources as `r`), so `dy/dt = M⁻¹ (dx/dt - dr/dt)`: a change of variables, exact, with
//! the same eigenvalues. Where merged storage is driven by an input (a spring between a
//! force source and a spring, in series: Rowell & Wormley's dependent spring), `r` depends
//! on the input and `dr/dt` brings the input's rate into the co-energy equations:
//! `dy/dt = A y + B u + E du/dt + c`.

use crate::diagnostics::Result;
use crate::equations::matrix;
use crate::equations::merging::{Block, input_rate};
use crate::linear::{LinearForm, Var};
use crate::model::ElementId;
use crate::symbolic::RatFunc;

pub(crate) struct Converted {
    pub derivatives: Vec<LinearForm>,
    pub bond_vars: Vec<LinearForm>,
    pub storage_energy: Vec<(ElementId, LinearForm)>,
}

pub(crate) fn convert(
    blocks: &[Block],
    derivatives: &[LinearForm],
    bond_vars: &[LinearForm],
    storage_energy: &[(ElementId, LinearForm)],
) -> Result<Converted> {
    // x_k as a form of the co-energy states y.
    let mut energy_in_coenergy: Vec<LinearForm> = vec![LinearForm::zero(); derivatives.len()];
    for block in blocks {
        for (a, &k) in block.states.iter().enumerate() {
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
        // dx/dt - dr/dt, with dr/dt the offset's inputs replaced by their rates.
        let rates: Vec<LinearForm> = block
            .states
            .iter()
            .enumerate()
            .map(|(a, &k)| {
                let mut rate = substitute(&derivatives[k as usize]);
                rate.add_scaled(&input_rate(&block.offset[a]), &RatFunc::integer(-1));
                rate
            })
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
