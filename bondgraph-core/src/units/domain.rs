//! Energy domains: which effort and flow make a bond mechanical, electrical, hydraulic or
//! thermal, and what a domain calls its variables and its elements' parameters.
//!
//! A bond's domain is read off the dimensions of its effort and flow. A linear graph is
//! translated with its through variable as the bond graph's effort and its across variable
//! as the flow ([`crate::model::linear_graph`]), so an electrical branch carries an "effort"
//! in A and a "flow" in V: [`Domain::of`] accepts either order.

use super::dimension::Dim;
use super::parse::parse_unit;

/// An energy domain with its variables' names and units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Domain {
    /// The domain, as an adjective: `mechanical translational`, `electrical`.
    pub name: &'static str,
    /// The effort's unit and name.
    pub effort: (&'static str, &'static str),
    /// The flow's unit and name.
    pub flow: (&'static str, &'static str),
    /// What the integral of the flow is called (a C's state): displacement, charge.
    pub displacement: &'static str,
    /// What the integral of the effort is called (an I's state): momentum, flux linkage.
    pub momentum: &'static str,
    /// The units its textbooks write parameters in, for the readable needed unit.
    pub hints: &'static [&'static str],
    /// Whether the effort is a linear graph's through variable (a force, a torque) rather
    /// than its across variable (a voltage, a pressure, a temperature).
    pub effort_is_through: bool,
}

/// The domains the checks know.
pub const DOMAINS: &[Domain] = &[
    Domain {
        name: "mechanical translational",
        effort: ("N", "force"),
        flow: ("m/s", "velocity"),
        displacement: "displacement",
        momentum: "momentum",
        hints: &["kg", "N/m", "m/N", "N*s/m", "m*s/N", "m", "N*s"],
        effort_is_through: true,
    },
    Domain {
        name: "mechanical rotational",
        effort: ("N*m", "torque"),
        flow: ("rad/s", "angular velocity"),
        displacement: "angle",
        momentum: "angular momentum",
        hints: &[
            "kg*m^2",
            "N*m/rad",
            "rad/(N*m)",
            "N*m*s/rad",
            "rad",
            "N*m*s",
        ],
        effort_is_through: true,
    },
    Domain {
        name: "electrical",
        effort: ("V", "voltage"),
        flow: ("A", "current"),
        displacement: "charge",
        momentum: "flux linkage",
        hints: &["H", "1/F", "F", "ohm", "1/ohm", "C", "Wb"],
        effort_is_through: false,
    },
    Domain {
        name: "hydraulic",
        effort: ("Pa", "pressure"),
        flow: ("m^3/s", "volume flow"),
        displacement: "volume",
        momentum: "pressure momentum",
        hints: &["Pa*s^2/m^3", "Pa/m^3", "m^3/Pa", "Pa*s/m^3", "m^3", "Pa*s"],
        effort_is_through: false,
    },
    Domain {
        name: "thermal",
        effort: ("K", "temperature"),
        flow: ("W", "heat flow"),
        displacement: "heat",
        momentum: "temperature momentum",
        hints: &["J/K", "K/J", "K/W", "W/K", "J"],
        effort_is_through: false,
    },
    Domain {
        name: "thermal (entropy)",
        effort: ("K", "temperature"),
        flow: ("W/K", "entropy flow"),
        displacement: "entropy",
        momentum: "temperature momentum",
        hints: &["J/K^2", "K^2/J", "K^2/W", "J/K"],
        effort_is_through: false,
    },
];

fn dim(unit: &str) -> Dim {
    parse_unit(unit).unwrap_or(Dim::NONE)
}

impl Domain {
    /// The effort's dimension.
    pub fn effort_dim(&self) -> Dim {
        dim(self.effort.0)
    }

    /// The flow's dimension.
    pub fn flow_dim(&self) -> Dim {
        dim(self.flow.0)
    }

    /// The domain of a bond with effort `effort` and flow `flow`, in either order (see the
    /// module documentation).
    pub fn of(effort: Dim, flow: Dim) -> Option<&'static Domain> {
        DOMAINS.iter().find(|d| {
            (d.effort_dim() == effort && d.flow_dim() == flow)
                || (d.effort_dim() == flow && d.flow_dim() == effort)
        })
    }

    /// The domain whose effort is `effort`, if only one domain's is (a temperature is the
    /// effort of both thermal domains: the first, heat flow, is taken).
    pub fn of_effort(effort: Dim) -> Option<&'static Domain> {
        DOMAINS.iter().find(|d| d.effort_dim() == effort)
    }

    /// The domain whose flow is `flow`.
    pub fn of_flow(flow: Dim) -> Option<&'static Domain> {
        DOMAINS.iter().find(|d| d.flow_dim() == flow)
    }

    /// Whether this is a pseudo bond graph domain, where effort times flow is not a power
    /// (temperature times heat flow).
    pub fn is_pseudo(&self) -> bool {
        self.effort_dim().times(self.flow_dim()) != power()
    }
}

/// The dimension of power, W.
pub fn power() -> Dim {
    dim("W")
}

impl Domain {
    /// The unit and name of what a file calls the effort: a bond graph's effort, or (in a
    /// linear graph, `through_is_effort`) the through variable.
    pub fn file_effort(&self, through_is_effort: bool) -> (&'static str, &'static str) {
        if !through_is_effort || self.effort_is_through {
            self.effort
        } else {
            self.flow
        }
    }

    /// The unit and name of what a file calls the flow (see [`Domain::file_effort`]).
    pub fn file_flow(&self, through_is_effort: bool) -> (&'static str, &'static str) {
        if !through_is_effort || self.effort_is_through {
            self.flow
        } else {
            self.effort
        }
    }
}

/// The efforts of every domain, as a list for messages: `force (N), torque (N*m), ...`.
pub fn effort_list(through_is_effort: bool) -> String {
    list(|d| d.file_effort(through_is_effort))
}

/// The flows of every domain, as a list for messages.
pub fn flow_list(through_is_effort: bool) -> String {
    list(|d| d.file_flow(through_is_effort))
}

fn list(pick: impl Fn(&Domain) -> (&'static str, &'static str)) -> String {
    let mut items: Vec<String> = Vec::new();
    for d in DOMAINS {
        let (unit, name) = pick(d);
        let item = format!("{name} ({unit})");
        if !items.contains(&item) {
            items.push(item);
        }
    }
    items.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bond_is_classified_by_its_effort_and_flow_in_either_order() {
        let (n, v) = (dim("N"), dim("m/s"));
        assert_eq!(Domain::of(n, v).unwrap().name, "mechanical translational");
        assert_eq!(Domain::of(v, n).unwrap().name, "mechanical translational");
        // rad/s and 1/s agree.
        assert_eq!(
            Domain::of(dim("N*m"), dim("1/s")).unwrap().name,
            "mechanical rotational"
        );
        assert_eq!(Domain::of(dim("A"), dim("V")).unwrap().name, "electrical");
        assert_eq!(
            Domain::of(dim("Pa"), dim("m^3/s")).unwrap().name,
            "hydraulic"
        );
        let thermal = Domain::of(dim("K"), dim("W")).unwrap();
        assert!(thermal.is_pseudo());
        assert!(!Domain::of(dim("K"), dim("W/K")).unwrap().is_pseudo());
        assert!(!Domain::of(n, v).unwrap().is_pseudo());
        assert_eq!(Domain::of(n, dim("A")), None);
    }
}
