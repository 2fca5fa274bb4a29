//! What a recorded output is, in its domain's words and units: `flow:body` is a velocity in
//! m/s, `integral:flow:cap` a charge in C, `energy:spring` an energy in J. Plots label their
//! axes with it.

use crate::equations::OutputQuantity;
use crate::model::Model;
use crate::scenario::Record;
use crate::scenario::energy::EnergyRecord;

use super::dimension::Dim;
use super::domain::Domain;
use super::format::readable_with;

/// The quantity `record` measures and its unit (`("velocity", "m/s")`), where the model's
/// units tell them.
pub fn quantity(model: &Model, record: &Record) -> Option<(String, String)> {
    let lg = model.linear_graph.is_some();
    match record {
        Record::Output(spec) | Record::Integral(spec) => {
            let dims = model.bond_dimensions.get(spec.bond.index())?;
            let effort = spec.quantity == OutputQuantity::Effort;
            let dim = if effort { dims.effort? } else { dims.flow? };
            let domain = dims
                .effort
                .zip(dims.flow)
                .and_then(|(e, f)| Domain::of(e, f));
            // In a linear graph the bond's effort is the through variable; the domain's
            // words are the file's (`file_effort`).
            let swapped = domain.is_some_and(|d| lg && !d.effort_is_through);
            let word = domain.map(|d| match (record, effort) {
                (Record::Output(_), true) => d.file_effort(lg).1,
                (Record::Output(_), false) => d.file_flow(lg).1,
                // The integral of an effort is a momentum, of a flow a displacement (in a
                // linear graph's electrical domain, a through variable's is a charge).
                (_, true) if swapped => d.displacement,
                (_, true) => d.momentum,
                (_, false) if swapped => d.momentum,
                (_, false) => d.displacement,
            });
            let dim = if matches!(record, Record::Integral(_)) {
                dim.times(Dim::TIME)
            } else {
                dim
            };
            let unit = readable_with(dim, &unit_hints(domain));
            Some((word.unwrap_or("").to_string(), unit))
        }
        Record::Energy(_, energy) => {
            let element = match energy {
                EnergyRecord::Stored(id) => Some(*id),
                EnergyRecord::Power { element, .. } => Some(*element),
                EnergyRecord::Book(_) => None,
            };
            // Temperature times heat flow is not a power: no unit for a pseudo bond graph.
            if element
                .and_then(|id| model.element_domain(id))
                .is_some_and(Domain::is_pseudo)
            {
                return None;
            }
            Some(match energy {
                EnergyRecord::Power { .. } => ("power".to_string(), "W".to_string()),
                _ => ("energy".to_string(), "J".to_string()),
            })
        }
    }
}

/// The units a domain writes its variables and their integrals in.
fn unit_hints(domain: Option<&Domain>) -> Vec<&'static str> {
    let mut hints = Vec::new();
    if let Some(d) = domain {
        hints.extend([d.effort.0, d.flow.0]);
        hints.extend(d.hints);
    }
    hints.extend(["m", "rad", "C", "Wb", "m^3", "J", "N*s", "N*m*s"]);
    hints
}

/// An axis label for `record`: `flow:body: velocity (m/s)`, or its name alone where the
/// units do not tell.
pub fn axis_label(model: &Model, record: &Record) -> String {
    let name = record.name();
    match quantity(model, record) {
        Some((word, unit)) if word.is_empty() => format!("{name} ({unit})"),
        Some((word, unit)) => format!("{name}: {word} ({unit})"),
        None => name,
    }
}
