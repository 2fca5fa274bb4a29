//! Typed errors that point at the model file.
//!
//! The library never prints and never panics on bad input: every problem becomes a
//! [`Diagnostic`] that carries what went wrong ([`DiagnosticKind`]), a one-sentence message
//! naming the element or bond concerned, and the [`Location`] (file, line, column) it came
//! from. The command-line program renders them with a source snippet and picks the exit code.
//! Loading collects every independent problem it finds, so a user fixes a file in one pass.

mod suggest;
pub use suggest::suggest;

use std::fmt;

use crate::source::{Location, SourceFile, Span};

/// What kind of problem a [`Diagnostic`] reports; stable for tests and tools to match on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum DiagnosticKind {
    /// The file could not be read.
    Io,
    /// The text is not valid RON.
    Syntax,
    /// A field that the element, parameter or model does not have.
    UnknownField,
    /// An element kind that does not exist (`Q(...)` instead of `I(...)`).
    UnknownElementKind,
    /// A scenario's input signal kind that does not exist (`Rmp(...)` instead of
    /// `Ramp(...)`).
    UnknownSignalKind,
    /// A required field is missing.
    MissingField,
    /// Two fields that exclude each other are both given (a compliance and a stiffness).
    ConflictingFields,
    /// A field has the wrong type (a number where a string is expected, ...).
    WrongType,
    /// A bond names an element that is not defined.
    UndefinedElement,
    /// Two parameters, inputs or elements share a name.
    DuplicateName,
    /// A name that is not a valid identifier (for use in expressions).
    InvalidName,
    /// An element has the wrong number of bonds, or a two-port's bonds point the wrong way.
    BondCount,
    /// A bond from an element to itself.
    SelfBond,
    /// An expression names a symbol that is neither a parameter nor an input.
    UnknownSymbol,
    /// An expression that cannot be parsed.
    BadExpression,
    /// An expression that is not allowed where it is used (an input in a mass, a product
    /// of two inputs, a division by an input).
    NotLinear,
    /// A parameter value, or an element's coefficient evaluated with the parameter
    /// values, that is zero, negative or not finite where that is not allowed; in a
    /// scenario, a number that is not finite, a duration or sample interval that is not
    /// positive, a ramp that never reaches its ceiling, or table times that do not
    /// increase.
    InvalidValue,
    /// The model has no elements.
    EmptyModel,
    /// The model's graph is in more than one piece.
    Disconnected,
    /// Causality cannot be assigned: two sources (or constraints) fight over one variable.
    CausalConflict,
    /// Storage in derivative causality that cannot be merged into the independent states.
    DependentStorage,
    /// An algebraic loop whose linear system is singular.
    SingularLoop,
    /// A mode specification that names an unknown element or mode.
    BadMode,
    /// A requested output that names no bond of the model.
    BadOutput,
    /// A simulation that could not go on (no consistent mode, chattering, non-finite states).
    Simulation,
    /// A scenario or model edit names an element, parameter or input that the model does
    /// not have.
    UnknownName,
    /// A scenario gives no signal for an input the model uses.
    MissingInput,
    /// A scenario gives an initial state to an element that stores no energy.
    NotStorage,
    /// A linear-graph branch names a node that is neither the ground nor the end of
    /// another branch (a typo), or a two-port names the same node twice in one pair.
    UndefinedNode,
    /// A linear-graph node that only one branch touches: the branch carries no through
    /// variable, and is almost always a typo in a node name.
    DanglingNode,
    /// Across sources (velocity, voltage, pressure) that form a loop: their across variables
    /// must sum to zero, so they contradict each other.
    AcrossSourceLoop,
    /// Through sources (force, current, flow) that form a cut-set: their through variables
    /// must sum to zero at the cut, so they contradict each other.
    ThroughSourceCutSet,
    /// An input beyond one of the documented limits of [`crate::limits`]: an expression
    /// that expands too far, a simulation that would record too many samples.
    TooLarge,
    /// A parameter's or input's `unit` string that names something that is not a unit
    /// (`"N*s/furlong"`), or does not parse; or an input's unit with a factor or offset to
    /// SI (`"kPa"`), as inputs take SI values.
    UnknownUnit,
    /// Units that disagree: an expression that adds a force to a velocity, or an element
    /// whose parameter does not have the unit its law needs on its bond (a mass used as a
    /// stiffness), or a bond whose effort times flow is not a power.
    UnitMismatch,
    /// A sub-model's use that cannot be composed: a file that uses itself, a port the
    /// sub-model does not have or one left unconnected, a value for a parameter or input it
    /// does not have, a file with no ports.
    Submodel,
}

/// One problem found in a model, with where it is and what it concerns.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// What kind of problem this is.
    pub kind: DiagnosticKind,
    /// One sentence, naming the element, bond or parameter concerned.
    pub message: String,
    /// Where in which file, when the problem has a place.
    pub location: Option<Location>,
    /// The element (or parameter, or input) concerned, when there is one.
    pub element: Option<String>,
    /// Further explanation or a suggested fix, one sentence each.
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// A diagnostic of `kind` with `message` and no location yet.
    pub fn new(kind: DiagnosticKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
            location: None,
            element: None,
            notes: Vec::new(),
        }
    }

    /// Points the diagnostic at `span` in `file` (nowhere if the file was built in code,
    /// whose diagnostics name their element instead).
    pub fn at(self, file: &SourceFile, span: Span) -> Self {
        self.at_location(file.locate(span))
    }

    /// Points the diagnostic at an already computed location (nowhere if it is in a
    /// source built in code).
    pub fn at_location(mut self, location: Location) -> Self {
        self.location = (!location.is_in_code()).then_some(location);
        self
    }

    /// Names the element (or parameter, or input) concerned.
    pub fn element(mut self, name: impl Into<String>) -> Self {
        self.element = Some(name.into());
        self
    }

    /// Adds a note.
    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(location) = &self.location {
            write!(f, "{location}: ")?;
        }
        write!(f, "error: {}", self.message)?;
        for note in &self.notes {
            write!(f, "\n  note: {note}")?;
        }
        Ok(())
    }
}

/// One or more [`Diagnostic`]s: the error type of every fallible operation on models.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl Diagnostics {
    /// The diagnostics, in the order found.
    pub fn iter(&self) -> std::slice::Iter<'_, Diagnostic> {
        self.0.iter()
    }

    /// The first diagnostic (there is always at least one).
    pub fn first(&self) -> &Diagnostic {
        &self.0[0]
    }

    /// Whether any diagnostic is of `kind`.
    pub fn has(&self, kind: DiagnosticKind) -> bool {
        self.0.iter().any(|d| d.kind == kind)
    }
}

impl From<Diagnostic> for Diagnostics {
    fn from(diagnostic: Diagnostic) -> Self {
        Self(vec![diagnostic])
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, diagnostic) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{diagnostic}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// The result type of fallible model operations.
pub type Result<T, E = Diagnostics> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_file_line_column_and_notes() {
        let file = SourceFile::new("models/x.ron", "a\n  \"mass\": I(inertance: \"m\"),\n");
        let d = Diagnostic::new(
            DiagnosticKind::InvalidValue,
            "element 'mass': inertance m = 0 must be positive",
        )
        .at(&file, Span::new(4, 10))
        .element("mass")
        .note("a mass of zero has no dynamics; remove the element instead");
        assert_eq!(
            d.to_string(),
            "models/x.ron:2:3: error: element 'mass': inertance m = 0 must be positive\n  \
             note: a mass of zero has no dynamics; remove the element instead"
        );
    }
}
