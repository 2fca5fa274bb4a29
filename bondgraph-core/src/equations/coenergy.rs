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

use crate::equations::merging::{InStates, Merged, input_rate};
use crate::linear::{LinearForm, Var};
use crate::symbolic::RatFunc;

/// The equations of `merged` in co-energy states `y`. Each element's own energy variable is
/// `x_k = storage_k · y_k`, so bond variables and stored energies stay as sparse as merging
/// left them; the derivatives solve one storage system per block.
pub(crate) fn convert(merged: &Merged) -> InStates {
    let own = |k: u32| {
        Some(LinearForm::term(
            Var::State(k),
            merged.storage_of_state[k as usize].clone(),
        ))
    };
    let substitute = |form: &LinearForm| {
        form.substitute(|var| match var {
            Var::State(k) => own(k),
            _ => None,
        })
    };
    let mut derivatives = vec![LinearForm::zero(); merged.derivatives.len()];
    for block in &merged.blocks {
        // dx/dt - dr/dt, with dr/dt the offset's inputs replaced by their rates.
        let rates: Vec<LinearForm> = block
            .states
            .iter()
            .zip(&block.offset)
            .map(|(&k, offset)| {
                let mut rate = substitute(&merged.derivatives[k as usize]);
                rate.add_scaled(&input_rate(offset), &RatFunc::integer(-1));
                rate
            })
            .collect();
        for (&k, row) in block.states.iter().zip(block.matrix.solve(&rates)) {
            derivatives[k as usize] = row;
        }
    }
    merged.substituted(derivatives, own)
}
