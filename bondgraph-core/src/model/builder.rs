//! Building a model in code.
//!
//! A [`Builder`] collects what a model file says (parameters, inputs, elements, bonds, as
//! [`spec`](super::spec) values) and [`Builder::build`] checks it with the very checks a
//! model file goes through, into the same [`Model`]: one constructor for files and code, so
//! a model built here derives and simulates exactly as its file would. (Fits and scenarios
//! still take a model's file, whose text they edit into variants.)

use crate::diagnostics::Result;
use crate::model::Model;
use crate::model::source_map::SourceMap;
use crate::model::spec::{BondSpec, ElementSpec, InputSpec, ModelSpec, ParameterSpec, PortSpec};
use crate::model::validate;
use crate::source::SourceFile;

/// A model under construction: what a model file says (parameters, inputs, elements,
/// bonds), collected in code and checked by [`Builder::build`] into the same [`Model`] the
/// file would give. Coefficients are expressions over the parameters and inputs, written
/// as in a file (`"1/k"`, `"b + K_p"`). A model built in code has no text, so its
/// diagnostics name their element and no line.
///
/// # Example
/// ```
/// use bondgraph_core::model::{Builder, ElementSpec};
///
/// let model = Builder::new("rc")
///     .parameter("R", 1.0e3, "ohm")
///     .parameter("C", 1.0e-6, "F")
///     .input("V", "V")
///     .element("supply", ElementSpec::effort_source("V"))
///     .element("loop", ElementSpec::One)
///     .element("resistor", ElementSpec::resistance("R"))
///     .element("capacitor", ElementSpec::compliance("C"))
///     .bonds([("supply", "loop"), ("loop", "resistor"), ("loop", "capacitor")])
///     .build()
///     .unwrap();
/// assert_eq!(model.elements().len(), 4);
///
/// let error = Builder::new("bad")
///     .element("mass", ElementSpec::inertance("m"))
///     .build()
///     .unwrap_err();
/// assert_eq!(error.first().element.as_deref(), Some("mass"));
/// assert!(error.first().location.is_none());
/// ```
#[derive(Clone, Debug, PartialEq)]
#[must_use = "a builder does nothing until `build` is called"]
pub struct Builder {
    spec: ModelSpec,
}

impl Builder {
    /// An empty model called `name`.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            spec: ModelSpec {
                name: name.into(),
                description: None,
                parameters: Vec::new(),
                inputs: Vec::new(),
                elements: Vec::new(),
                bonds: Vec::new(),
                ports: Vec::new(),
                parts: Vec::new(),
            },
        }
    }

    /// Sets the description, for people.
    pub fn description(mut self, description: impl Into<String>) -> Self {
        self.spec.description = Some(description.into());
        self
    }

    /// Adds a parameter of `value` in `unit` (`""` for none).
    pub fn parameter(self, name: impl Into<String>, value: f64, unit: &str) -> Self {
        self.parameter_spec(name, ParameterSpec::new(value, unit))
    }

    /// Adds a parameter with every field given (a description, calibration bounds).
    pub fn parameter_spec(mut self, name: impl Into<String>, parameter: ParameterSpec) -> Self {
        self.spec.parameters.push((name.into(), parameter));
        self
    }

    /// Adds an input (a signal given when the model is simulated) in `unit` (`""` for none).
    pub fn input(mut self, name: impl Into<String>, unit: &str) -> Self {
        let input = InputSpec {
            unit: (!unit.is_empty()).then(|| unit.to_owned()),
            description: None,
        };
        self.spec.inputs.push((name.into(), input));
        self
    }

    /// Adds an element.
    pub fn element(mut self, name: impl Into<String>, element: ElementSpec) -> Self {
        self.spec.elements.push((name.into(), element));
        self
    }

    /// Adds a bond: power flows from element `from` into element `to`.
    pub fn bond(mut self, from: impl Into<String>, to: impl Into<String>) -> Self {
        self.spec.bonds.push(BondSpec(from.into(), to.into()));
        self
    }

    /// Adds bonds, as [`Builder::bond`] each.
    pub fn bonds<F: Into<String>, T: Into<String>>(
        self,
        bonds: impl IntoIterator<Item = (F, T)>,
    ) -> Self {
        bonds
            .into_iter()
            .fold(self, |builder, (from, to)| builder.bond(from, to))
    }

    /// Declares a port: junction `element` is where bonds from outside attach when the
    /// model is used as a sub-model of another.
    pub fn port(mut self, name: impl Into<String>, element: impl Into<String>) -> Self {
        self.spec.ports.push((
            name.into(),
            PortSpec {
                element: element.into(),
                description: None,
            },
        ));
        self
    }

    /// What has been collected so far.
    pub fn spec(&self) -> &ModelSpec {
        &self.spec
    }

    /// Checks the model and builds it.
    ///
    /// # Errors
    /// Every problem found, as for a model file: duplicate or invalid names, unparsable
    /// expressions, unknown symbols, non-positive masses, bonds to undefined elements,
    /// wrong bond counts, graphs in pieces, units that disagree. Each names its element;
    /// none has a location.
    pub fn build(self) -> Result<Model> {
        let source = SourceFile::in_code(self.spec.name.clone());
        validate::validate(&source, self.spec, &SourceMap::default())
    }
}

impl From<ModelSpec> for Builder {
    /// A builder holding `spec`, to add to or build.
    fn from(spec: ModelSpec) -> Self {
        Self { spec }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostics::DiagnosticKind;

    fn built() -> Builder {
        Builder::new("msd")
            .parameter("m", 2000.0, "g")
            .input("F", "N")
            .element("force", ElementSpec::effort_source("F"))
            .element("v", ElementSpec::One)
            .element("mass", ElementSpec::inertance("m"))
            .bonds([("force", "v"), ("v", "mass")])
    }

    #[test]
    fn a_built_model_is_checked_like_a_file_and_its_errors_name_elements_not_lines() {
        let error = built()
            .element("mass", ElementSpec::One)
            .element("gear", ElementSpec::transformer("n"))
            .bond("v", "nowhere")
            .build()
            .unwrap_err();
        let found: Vec<(DiagnosticKind, Option<&str>)> = error
            .0
            .iter()
            .map(|d| (d.kind, d.element.as_deref()))
            .collect();
        assert!(
            found.contains(&(DiagnosticKind::DuplicateName, Some("mass"))),
            "{found:?}"
        );
        assert!(
            found.contains(&(DiagnosticKind::UnknownSymbol, Some("gear"))),
            "{found:?}"
        );
        assert!(
            found.contains(&(DiagnosticKind::UndefinedElement, Some("nowhere"))),
            "{found:?}"
        );
        assert!(error.0.iter().all(|d| d.location.is_none()));
        assert!(
            error.first().to_string().starts_with("error: "),
            "{}",
            error.first()
        );
    }

    #[test]
    fn a_built_models_misplaced_bonds_are_named_by_their_ends_not_lines() {
        let error = Builder::new("gear")
            .parameter("n", 2.0, "")
            .element("j", ElementSpec::One)
            .element("k", ElementSpec::One)
            .element("t", ElementSpec::transformer("n"))
            .bonds([("j", "t"), ("k", "j")])
            .build()
            .unwrap_err();
        let messages: Vec<String> = error.0.iter().map(|d| d.message.clone()).collect();
        assert!(
            messages.contains(
                &"transformer 't' has 1 bonds (j -> t); it takes exactly two, one in and one out"
                    .to_string()
            ),
            "{messages:?}"
        );
    }

    #[test]
    fn a_spec_becomes_a_builder_again() {
        let builder = built();
        let again = Builder::from(builder.spec().clone());
        assert_eq!(again, builder);
        // 2000 g is 2 kg.
        assert_eq!(again.build().unwrap().parameters[0].value, 2.0);
    }
}
