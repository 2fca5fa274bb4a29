//! Modes' forms shared among the simulators of one model.

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;

use super::{ModeMap, Output};
use crate::numeric::ModeForms;

/// Linear modes' forms ([`ModeForms`]: matrices, guards and outputs as expressions of the
/// parameters), derived once and shared by the simulators of one model with one set of
/// outputs ([`Simulator::with_shared_forms`](crate::Simulator::with_shared_forms)). A fit
/// runs a simulator on each thread, fold and face, and each derived every mode it met
/// symbolically: on a steady sweep of a model with many modes, a twentieth of the fit.
///
/// The first simulator handed it binds it to its model (that very value, by address: keep
/// the forms no longer than the model, as a fit's predictor keeps both) and its outputs;
/// another model's simulator, or one with other outputs, derives its own forms instead.
#[derive(Default)]
pub struct SharedForms(Mutex<Shared>);

/// What the first simulator bound the forms to, and the forms.
#[derive(Default)]
struct Shared {
    /// The address of the model and the outputs (with whether each is integrated).
    owner: Option<(usize, Vec<(OutputSpec, bool)>)>,
    forms: ModeMap<Arc<ModeForms>>,
}

impl std::fmt::Debug for SharedForms {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SharedForms({} modes)", self.lock().forms.len())
    }
}

impl SharedForms {
    /// Whether these forms serve a simulator of `model` recording `outputs`: binds them to
    /// that pair on first use.
    pub(super) fn serves(&self, model: &Model, outputs: &[Output]) -> bool {
        let key = (
            std::ptr::from_ref(model) as usize,
            outputs
                .iter()
                .map(|o| (o.spec.clone(), o.integral))
                .collect::<Vec<_>>(),
        );
        let mut shared = self.lock();
        match &shared.owner {
            Some(owner) => *owner == key,
            None => {
                shared.owner = Some(key);
                true
            }
        }
    }

    pub(super) fn get(&self, mode: &Mode) -> Option<Arc<ModeForms>> {
        self.lock().forms.get(mode).cloned()
    }

    pub(super) fn insert(&self, mode: &Mode, forms: &Arc<ModeForms>) {
        self.lock().forms.insert(mode.clone(), Arc::clone(forms));
    }

    fn lock(&self) -> MutexGuard<'_, Shared> {
        // A thread that panicked while holding it left a map of whole entries.
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

#[cfg(test)]
mod tests {
    use bondgraph_core::equations::OutputSpec;

    use bondgraph_core::modes::Mode;

    use super::*;
    use crate::{Output, Simulator};

    /// A block on a belt, held by a spring: a second simulator sharing the first's forms
    /// derives no mode of its own, and puts the same numbers into each (at other values
    /// too: the forms are expressions of the parameters).
    #[test]
    fn a_simulator_sharing_forms_derives_none_and_agrees() {
        let belt = bondgraph_ron::model::load_str(
            "belt.ron",
            r#"Model(
                name: "belt",
                parameters: {
                    "m": (value: 1.0, unit: "kg"), "k": (value: 100.0, unit: "N/m"),
                    "b": (value: 25.0, unit: "N*s/m"),
                    "F_S": (value: 10.0, unit: "N"), "F_C": (value: 6.0, unit: "N"),
                },
                inputs: { "v_belt": (unit: "m/s") },
                elements: {
                    "belt": Sf(flow: "v_belt"), "contact": Zero,
                    "friction": Friction(breakaway: "F_S", coulomb: "F_C", initial: "stuck"),
                    "v_block": One, "block": I(inertance: "m"),
                    "spring": C(compliance: "1/k"), "damper": R(resistance: "b"),
                },
                bonds: [("belt", "contact"), ("contact", "friction"), ("contact", "v_block"),
                        ("v_block", "block"), ("v_block", "spring"), ("v_block", "damper")],
            )"#,
        )
        .unwrap();
        let shared = Arc::new(SharedForms::default());
        let outputs = || {
            vec![Output {
                name: "spring".into(),
                spec: OutputSpec::parse(&belt, "effort:spring").unwrap(),
                integral: false,
            }]
        };
        let stuck = Mode::initial(&belt);
        let slipping = Mode::parse(&belt, "friction=slip+").unwrap();
        let mut first = Simulator::new(&belt, outputs()).with_shared_forms(Arc::clone(&shared));
        let mut second = Simulator::new(&belt, outputs()).with_shared_forms(Arc::clone(&shared));
        let mut values = belt.values().to_vec();
        for mode in [&stuck, &slipping] {
            let a = first.mode(mode).unwrap();
            let b = second.mode(mode).unwrap();
            assert_eq!((&a.a, &a.b, &a.c), (&b.a, &b.b, &b.c));
            assert_eq!(a.outputs, b.outputs);
        }
        assert_eq!(first.symbolic.len(), 2);
        assert_eq!(second.symbolic.len(), 0);
        // At b = 40 N s/m the slipping block is m p̈ + b ṗ + k p = 0:
        // s = -20 ± √300 (s² + 40 s + 100 = 0).
        let b_index = belt.parameters().iter().find(|p| p.name == "b").unwrap();
        values[b_index.symbol.index()] = 40.0;
        second.set_parameter_values(&values).unwrap();
        let slipping = second.mode(&slipping).unwrap();
        let mut roots: Vec<f64> = slipping
            .propagator
            .eigenvalues()
            .iter()
            .map(|v| v.re)
            .collect();
        roots.sort_by(f64::total_cmp);
        let expected = [-20.0 - 300f64.sqrt(), -20.0 + 300f64.sqrt()];
        for (got, want) in roots.iter().zip(expected) {
            assert!((got - want).abs() < 1e-12 * want.abs(), "{roots:?}");
        }
        assert_eq!(second.symbolic.len(), 0);

        // Another model's simulator, or one recording other outputs, derives its own.
        let mut other_outputs =
            Simulator::new(&belt, vec![]).with_shared_forms(Arc::clone(&shared));
        let copy = belt.clone();
        let mut other_model = Simulator::new(&copy, outputs()).with_shared_forms(shared);
        other_outputs.mode(&stuck).unwrap();
        other_model.mode(&stuck).unwrap();
        assert_eq!(other_outputs.symbolic.len(), 1);
        assert_eq!(other_model.symbolic.len(), 1);
    }
}
