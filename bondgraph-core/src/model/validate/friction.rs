//! A friction contact's fields checked: breakaway and Coulomb levels, viscous and dead-band
//! coefficients, the Stribeck velocity (zero or positive; a literal zero is none), the
//! initial mode among those the contact has.

use crate::diagnostics::{Diagnostic, DiagnosticKind};
use crate::model::checked::{ElementKind, ElementMode, Friction};

use super::{Scope, Sign, Validator};

impl Validator<'_> {
    /// The contact `name` (element `index`) from its fields as written: `(breakaway,
    /// coulomb)` and the optional `[viscous, dead_band, stribeck, initial]`.
    pub(super) fn friction(
        &mut self,
        name: &str,
        index: usize,
        (breakaway, coulomb): (&String, &String),
        [viscous, dead_band, stribeck, initial]: [&Option<String>; 4],
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let breakaway = self.source_value(name, index, "breakaway", breakaway, scope, false);
        let coulomb = self.source_value(name, index, "coulomb", coulomb, scope, false);
        let viscous = self.optional_coefficient(name, index, "viscous", viscous, scope);
        let dead_band = self.optional_coefficient(name, index, "dead_band", dead_band, scope);
        // Zero is no creeping range, the Karnopp contact (a fit may set it there, see
        // `Friction`); written as a literal zero it is no Stribeck velocity at all.
        let stribeck = stribeck
            .as_ref()
            .map(|text| self.coefficient(name, index, "stribeck", text, scope, Sign::NonNegative))
            .filter(|coefficient| coefficient.as_ref().is_none_or(|c| !c.value.is_zero()));
        let mut allowed = vec![
            ElementMode::Stuck,
            ElementMode::SlipPositive,
            ElementMode::SlipNegative,
        ];
        if stribeck.is_some() {
            allowed.extend([ElementMode::CreepPositive, ElementMode::CreepNegative]);
        }
        let initial = self.initial_mode(name, index, initial.as_deref(), &allowed);
        let (breakaway, coulomb) = (breakaway?, coulomb?);
        self.check_friction_levels(name, &breakaway, &coulomb, scope)?;
        let friction = Friction {
            breakaway,
            coulomb,
            viscous: viscous?,
            dead_band: dead_band?,
            stribeck: match stribeck {
                Some(coefficient) => Some(coefficient?),
                None => None,
            },
            initial: initial?,
        };
        if friction.stribeck.is_some() && friction.creep_resistance().is_none() {
            let span = friction.breakaway.span;
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "friction contact '{name}': with a Stribeck velocity, breakaway \"{}\" and Coulomb \"{}\" must differ by an amount that does not depend on inputs",
                        friction.breakaway.text, friction.coulomb.text
                    ),
                )
                .at(&self.file, span)
                .element(name)
                .note("the weakening slope (breakaway - coulomb)/stribeck is a coefficient of the creeping modes' equations"),
            );
            return None;
        }
        Some(ElementKind::Friction(Box::new(friction)))
    }
}
