//! Model (and scenario) file text to a [`RawModel`] and its [`SourceMap`], or one diagnostic.
//!
//! ron reports an error as a code and a line/column span, phrased for programmers
//! ("Unexpected field named `inertia` in `I`") and sometimes positioned on the whitespace
//! before the offending token. Users need the element named and the token underlined, so
//! this module turns ron's error into a [`Diagnostic`]: it picks the [`DiagnosticKind`],
//! moves the location onto the offending token (or the end of the file), finds the entry
//! or bond the position is in with the [`SourceMap`] scanner (scanning only the text up to
//! the error when the whole text does not scan), and words the message in the model's
//! own terms: `element 'mass': unknown field 'inertia'; expected 'inertance'`.
//!
//! Scenario files are RON of the same shape (a struct of fields whose sections are maps
//! of named entries or lists), so [`parse_file`] reads them with the same machinery and
//! [`FileKind`] supplies the few words that differ (`scenario`, `Scenario(...)`).
//!
//! ron stops at the first error, so a file that does not parse gives exactly one
//! diagnostic; checks of the parsed model, which can report many, come later.

use ron::error::{Position, SpannedError};
use serde::de::DeserializeOwned;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics};
use crate::source::{SourceFile, Span};

use super::raw::RawModel;
use super::source_map::{
    EntrySpans, ItemSpans, List, Section, SourceMap, Token, TokenKind, closer, lex, open_brackets,
    skip_trivia,
};

/// Which kind of file is read: the words diagnostics use for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileKind {
    /// A model file, `Model(...)`.
    Model,
    /// A scenario file, `Scenario(...)`.
    Scenario,
    /// A model extension, `Extension(...)`.
    Extension,
    /// A linear-graph model file, `LinearGraph(...)`.
    LinearGraph,
}

impl FileKind {
    /// What messages call the file's top-level value: "model", "scenario".
    pub fn noun(self) -> &'static str {
        match self {
            FileKind::Model => "model",
            FileKind::Scenario => "scenario",
            FileKind::Extension => "extension",
            FileKind::LinearGraph => "linear graph",
        }
    }

    /// The optional struct name around the top-level value: "Model", "Scenario".
    pub fn struct_name(self) -> &'static str {
        match self {
            FileKind::Model => "Model",
            FileKind::Scenario => "Scenario",
            FileKind::Extension => "Extension",
            FileKind::LinearGraph => "LinearGraph",
        }
    }
}

/// Parses a model file into its raw model and the spans of its parts.
///
/// An empty (or blank, or comments-only) file gives an [`DiagnosticKind::EmptyModel`]
/// diagnostic; text that is not a model gives one diagnostic of kind `Syntax`,
/// `UnknownField`, `UnknownElementKind`, `MissingField` or `WrongType`, located at the
/// offending token and naming the element, parameter, input or bond it is in.
///
/// The source map normally covers every entry and bond of the raw model, one for one; if
/// the scanner cannot read a text that ron accepted, it covers what it could read.
pub fn parse_model(file: &SourceFile) -> Result<(RawModel, SourceMap), Diagnostics> {
    parse_file(file, FileKind::Model)
}

/// Parses a file of `kind` into `T` (read with [`ron_options`](super::raw::ron_options))
/// and the spans of its parts, as [`parse_model`] does for models: an empty file, or text
/// that is not a `T`, gives one located diagnostic.
pub fn parse_file<T: DeserializeOwned>(
    file: &SourceFile,
    kind: FileKind,
) -> Result<(T, SourceMap), Diagnostics> {
    let text = file.text();
    if skip_trivia(text, 0) == Ok(text.len()) {
        let diagnostic_kind = match kind {
            FileKind::Model | FileKind::LinearGraph => DiagnosticKind::EmptyModel,
            FileKind::Scenario | FileKind::Extension => DiagnosticKind::Syntax,
        };
        return Err(Diagnostic::new(
            diagnostic_kind,
            format!("the file is empty; expected a {}(...)", kind.struct_name()),
        )
        .at(file, Span::new(0, 0))
        .into());
    }
    match super::raw::ron_options().from_str::<T>(text) {
        Ok(value) => {
            let map = SourceMap::scan(text).unwrap_or_else(|| SourceMap::scan_partial(text));
            Ok((value, map))
        }
        Err(error) => Err(diagnose(file, &error, kind).into()),
    }
}

/// What was found where ron expected something else.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Found {
    /// A token, with its text as written.
    Token(Token, String),
    /// A character, at this offset, that starts no token.
    Char(char, usize),
    /// The end of the file.
    End,
}

impl Found {
    /// How messages name it: `'}'`, `"text"`, `'x'`, `end of file`.
    fn describe(&self) -> String {
        match self {
            Found::Token(token, text) => {
                let text = shorten(text);
                match token.kind {
                    TokenKind::Str | TokenKind::Char => text,
                    _ => format!("'{text}'"),
                }
            }
            Found::Char(c, _) => format!("'{}'", c.escape_debug()),
            Found::End => "end of file".to_string(),
        }
    }

    /// Whether it begins a value, so that the problem is the value's type rather than
    /// the punctuation.
    fn is_value(&self) -> bool {
        match self {
            Found::Token(token, _) => matches!(
                token.kind,
                TokenKind::Str
                    | TokenKind::Number
                    | TokenKind::Char
                    | TokenKind::Ident
                    | TokenKind::Punct(b'(' | b'[' | b'{')
            ),
            Found::Char(..) | Found::End => false,
        }
    }

    fn is_punct(&self, c: u8) -> bool {
        matches!(self, Found::Token(token, _) if token.kind == TokenKind::Punct(c))
    }
}

/// Long literals are cut in messages.
fn shorten(text: &str) -> String {
    const MAX: usize = 40;
    let first_line = text.lines().next().unwrap_or("");
    if first_line.chars().count() > MAX || first_line.len() < text.len() {
        let cut: String = first_line.chars().take(MAX).collect();
        format!("{cut}...")
    } else {
        text.to_string()
    }
}

/// Where in the file an error position is.
enum Place<'m> {
    /// Inside an entry of a map section.
    Entry(Section, &'m EntrySpans),
    /// Inside the item of a list section with this index (a bond).
    Item(List, usize, &'m ItemSpans),
    /// Inside a map section, between entries.
    Section(Section),
    /// In the value of another top-level field.
    Field(&'m str),
    /// Anywhere else.
    Model,
}

impl Place<'_> {
    /// The message prefix naming the entry or bond: `element 'mass': `.
    fn prefix(&self) -> String {
        match self {
            Place::Entry(..) | Place::Item(..) => format!("{}: ", self.name()),
            Place::Section(_) | Place::Field(_) | Place::Model => String::new(),
        }
    }

    /// The entry or bond as messages name it: `element 'mass'`, `bond 2 ('j' -> 'mass')`;
    /// empty elsewhere.
    fn name(&self) -> String {
        match self {
            Place::Entry(section, entry) => format!("{} '{}'", section.noun(), entry.key),
            Place::Item(list, index, item) => item_name(*list, *index, item),
            Place::Section(_) | Place::Field(_) | Place::Model => String::new(),
        }
    }

    /// The entry's name, for [`Diagnostic::element`].
    fn element(&self) -> Option<&str> {
        match self {
            Place::Entry(_, entry) => Some(&entry.key),
            _ => None,
        }
    }
}

/// `bond 2 ('j' -> 'mass')`, or `bond 2` when its ends are not two names; `record item 2`
/// for the items of other lists.
fn item_name(list: List, index: usize, item: &ItemSpans) -> String {
    match (list, &item.strings[..]) {
        (List::Bonds, [(from, _), (to, _)]) => {
            format!("bond {} ('{from}' -> '{to}')", index + 1)
        }
        (List::Bonds, _) => format!("bond {}", index + 1),
        (list, _) => format!("{} item {}", list.field_name(), index + 1),
    }
}

/// Finds the place of `offset`; with `inclusive`, an entry or bond ending exactly at
/// `offset` counts (for the end of a partial scan).
fn place_at(map: &SourceMap, offset: usize, inclusive: bool) -> Place<'_> {
    let inside = |span: Span| {
        span.contains(offset) || (inclusive && span.end == offset && span.start <= offset)
    };
    for section in Section::ALL {
        if let Some(entry) = map.entries(section).iter().find(|e| inside(e.span())) {
            return Place::Entry(section, entry);
        }
    }
    for list in List::ALL {
        let items = map.items(list).iter().enumerate();
        if let Some((index, item)) = items.clone().find(|(_, b)| inside(b.span)) {
            return Place::Item(list, index, item);
        }
    }
    match map.field_before(offset) {
        Some(field) if field.name_span.end <= offset => {
            match Section::from_field_name(&field.name) {
                Some(section) => Place::Section(section),
                None => Place::Field(&field.name),
            }
        }
        _ => Place::Model,
    }
}

/// The byte offset of a ron position.
fn offset_of(file: &SourceFile, position: Position) -> usize {
    file.offset(position.line, position.col)
}

/// The first token that ends after `offset` (the token containing it, or the next one).
fn token_from(text: &str, offset: usize) -> Found {
    let mut pos = 0;
    loop {
        match lex(text, pos) {
            Ok(Some(token)) if token.span.end <= offset => pos = token.span.end,
            Ok(Some(token)) => {
                let written = text[token.span.start..token.span.end].to_string();
                return Found::Token(token, written);
            }
            Ok(None) => return Found::End,
            Err(error) => {
                // Text that does not tokenise: report the character where it starts, or
                // the one at `offset` if that is later.
                let at = if error.at >= offset {
                    error.at
                } else {
                    skip_trivia(text, offset).unwrap_or(offset)
                };
                return match text.get(at..).and_then(|rest| rest.chars().next()) {
                    Some(c) => Found::Char(c, at),
                    None => Found::End,
                };
            }
        }
    }
}

/// The span a [`Found`] covers (empty at the end of the file).
fn found_span(text: &str, found: &Found) -> Span {
    match found {
        Found::Token(token, _) => token.span,
        Found::Char(c, at) => Span::new(*at, at + c.len_utf8()),
        Found::End => Span::new(text.len(), text.len()),
    }
}

/// Quotes each name: `'a'`, `'a' or 'b'`, `one of 'a', 'b', 'c'`.
fn one_of(names: &[&str]) -> String {
    match names {
        [] => "nothing".to_string(),
        [one] => format!("'{one}'"),
        [a, b] => format!("'{a}' or '{b}'"),
        _ => {
            let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
            format!("one of {}", quoted.join(", "))
        }
    }
}

/// 1-based line and column of `offset`, as `line L, column C`.
fn line_column(file: &SourceFile, offset: usize) -> String {
    let (line, column) = file.line_col(offset);
    format!("line {line}, column {column}")
}

/// Turns ron's error into one diagnostic.
fn diagnose(file: &SourceFile, error: &SpannedError, file_kind: FileKind) -> Diagnostic {
    use DiagnosticKind as K;
    use ron::Error as E;

    let text = file.text();
    let start = offset_of(file, error.span.start);
    let end = offset_of(file, error.span.end).max(start);
    let ron_span = Span::new(start, end);

    // Errors whose span ron gives exactly (a name, or a literal's bad part).
    let exact = matches!(
        error.code,
        E::NoSuchStructField { .. }
            | E::NoSuchEnumVariant { .. }
            | E::DuplicateStructField { .. }
            | E::ExpectedDifferentStructName { .. }
            | E::NoSuchExtension(_)
            | E::InvalidEscape(_)
            | E::ExpectedStringEnd
            | E::UnclosedBlockComment
            | E::Utf8Error(_)
    );
    let at_end = skip_trivia(text, end).is_ok_and(|p| p >= text.len())
        && (start < end || start >= text.len());
    let found = if at_end && !exact {
        Found::End
    } else {
        token_from(text, start)
    };
    let focus = match error.code {
        // ron points inside the comment; the scanner knows where it opens.
        E::UnclosedBlockComment => {
            first_lex_error(text).map_or(ron_span, |at| Span::new(at, (at + 2).min(text.len())))
        }
        _ if exact && !ron_span.is_empty() => ron_span,
        _ => found_span(text, &found),
    };

    // Where it is: scan the whole text, or failing that the text up to the focus.
    let full = SourceMap::scan(text);
    let partial;
    let (map, inclusive) = match &full {
        Some(map) => (map, false),
        None => {
            let cut = focus.end.min(text.len());
            partial = SourceMap::scan_partial(text.get(..cut).unwrap_or(text));
            (&partial, true)
        }
    };
    let mut place = place_at(map, focus.start, inclusive);
    // `"mass": I}`: the '(' that should follow the kind is missing; the problem is the
    // entry that ends just before the token found.
    if matches!(
        error.code,
        E::ExpectedStructLike | E::ExpectedNamedStructLike(_)
    ) && matches!(place, Place::Section(_) | Place::Field(_) | Place::Model)
        && let Some(before) = token_before(text, focus.start).map(|t| t.span.end)
        && before > 0
        && let found_before @ (Place::Entry(..) | Place::Item(..)) =
            place_at(map, before - 1, inclusive)
    {
        place = found_before;
    }
    // `"mass": I(inertance: "m") "spring": ...`: the ',' after an entry or bond is missing;
    // the problem is the entry or bond that ends just before the token found, and the ','
    // belongs right after it.
    let mut comma_after = None;
    if matches!(error.code, E::ExpectedComma)
        && matches!(place, Place::Section(_) | Place::Field(_) | Place::Model)
        && let Some(before) = token_before(text, focus.start).map(|t| t.span.end)
        && before > 0
        && let found_before @ (Place::Entry(..) | Place::Item(..)) =
            place_at(map, before - 1, inclusive)
    {
        comma_after = Some((found_before.name(), before));
        place = found_before;
    }
    let prefix = place.prefix();
    let noun = file_kind.noun();
    let found_text = found.describe();

    // The span of the value the position is in, for problems with a whole value.
    let value_span = match &place {
        Place::Entry(_, entry) => entry.value_span,
        Place::Item(_, _, item) => item.span,
        _ => map.root,
    };
    let field_name = match &place {
        Place::Entry(_, entry) => entry.field_at(focus.start).map(|f| f.name.as_str()),
        Place::Field(name) => Some(*name),
        Place::Section(section) => Some(section.field_name()),
        _ => None,
    };
    // `field 'unit' must be` or `parameter 'm' must be`, for type errors.
    let subject = match (&place, field_name) {
        (Place::Entry(..), Some(field)) => format!("{prefix}field '{field}' must be"),
        (Place::Field(_) | Place::Section(_), Some(field)) => format!("field '{field}' must be"),
        (Place::Entry(section, entry), None) => {
            format!("{} '{}' must be", section.noun(), entry.key)
        }
        (Place::Item(list, index, item), _) => {
            format!("{} must be", item_name(*list, *index, item))
        }
        _ => "the value must be".to_string(),
    };
    let type_kind = if found.is_value() {
        K::WrongType
    } else {
        K::Syntax
    };
    // What closes the innermost open bracket at the focus.
    let innermost = open_brackets(text, focus.start).last().copied();
    let mut notes = Vec::new();
    if let (Some((open, at)), Found::End) = (innermost, &found) {
        notes.push(format!(
            "the '{}' at {} is never closed",
            char::from(open),
            line_column(file, at)
        ));
    }
    let mut span = focus;

    let (kind, message) = match &error.code {
        E::NoSuchStructField {
            expected, found, ..
        } => {
            let expected = one_of(expected);
            let message = match &place {
                Place::Entry(..) | Place::Item(..) => {
                    format!("{prefix}unknown field '{found}'; expected {expected}")
                }
                _ => format!("unknown field '{found}' in the {noun}; expected {expected}"),
            };
            (K::UnknownField, message)
        }
        E::NoSuchEnumVariant {
            expected, found, ..
        } => match &place {
            Place::Entry(Section::Inputs, _) if file_kind == FileKind::Scenario => (
                K::UnknownSignalKind,
                format!(
                    "{prefix}unknown signal kind '{found}'; expected one of {}",
                    expected.join(", ")
                ),
            ),
            Place::Entry(Section::Elements, _) => (
                K::UnknownElementKind,
                format!(
                    "{prefix}unknown element kind '{found}'; expected one of {}",
                    expected.join(", ")
                ),
            ),
            Place::Entry(Section::Branches, _) => (
                K::UnknownElementKind,
                format!(
                    "{prefix}unknown branch kind '{found}'; expected one of {}",
                    expected.join(", ")
                ),
            ),
            _ => (
                K::UnknownElementKind,
                format!(
                    "{prefix}unknown variant '{found}'; expected one of {}",
                    expected.join(", ")
                ),
            ),
        },
        E::MissingStructField { field, .. } => {
            if !value_span.is_empty() {
                span = value_span;
            }
            let message = match &place {
                Place::Entry(..) | Place::Item(..) => format!("{prefix}missing field '{field}'"),
                _ => format!("missing field '{field}' in the {noun}"),
            };
            (K::MissingField, message)
        }
        E::DuplicateStructField { field, .. } => {
            let message = match &place {
                Place::Entry(..) | Place::Item(..) => {
                    format!("{prefix}field '{field}' is given twice")
                }
                _ => format!("field '{field}' is given twice in the {noun}"),
            };
            (K::Syntax, message)
        }
        E::ExpectedDifferentStructName { expected, found } => {
            let message = match *expected {
                "Model" | "Scenario" | "LinearGraph" => {
                    format!(
                        "expected {expected}(...) or just (...) around the {noun}, found '{found}'"
                    )
                }
                "Bond" => format!(
                    "{prefix}expected a bond (\"from\", \"to\") or Bond(\"from\", \"to\"), found '{found}'"
                ),
                name => format!("{prefix}expected {name}(...) or just (...), found '{found}'"),
            };
            (K::WrongType, message)
        }
        E::ExpectedNamedStructLike(name) if !name.is_empty() => {
            let what = match *name {
                "Model" | "Scenario" | "LinearGraph" => format!("a {name}(...)"),
                "Parameter" => "a parameter (value: ..., unit: \"...\")".to_string(),
                "Input" => "an input (unit: \"...\", description: \"...\")".to_string(),
                "Bond" => "a bond (\"from\", \"to\")".to_string(),
                other => format!("{other}(...)"),
            };
            (
                type_kind,
                format!("{prefix}expected {what}, found {found_text}"),
            )
        }
        E::ExpectedStructLike | E::ExpectedNamedStructLike(_) => {
            let message = match &place {
                Place::Entry(
                    Section::Elements,
                    EntrySpans {
                        kind: Some(kind), ..
                    },
                ) => {
                    format!("{prefix}expected '(' after {kind}, found {found_text}")
                }
                _ => format!("{prefix}expected '(', found {found_text}"),
            };
            (type_kind, message)
        }
        E::ExpectedIdentifier | E::InvalidIdentifier(_) | E::SuggestRawIdentifier(_)
            if file_kind == FileKind::Scenario
                && matches!(&place, Place::Entry(Section::Inputs, entry)
                    if focus.start == entry.value_span.start) =>
        {
            if let Found::Token(token, written) = &found
                && token.kind == TokenKind::Number
            {
                notes.push(format!(
                    "a constant input is written Constant({})",
                    shorten(written)
                ));
            }
            (
                type_kind,
                format!(
                    "{prefix}expected a signal (Constant, Step, Ramp or Table), found {found_text}"
                ),
            )
        }
        E::ExpectedIdentifier => match &place {
            Place::Entry(Section::Elements, entry) if focus.start == entry.value_span.start => (
                type_kind,
                format!(
                    "{prefix}expected an element kind (Se, Sf, I, C, R, TF, GY, Friction, TensionOnly, FlowLimit, Zero or One), found {found_text}"
                ),
            ),
            Place::Entry(Section::Branches, entry) if focus.start == entry.value_span.start => (
                type_kind,
                format!(
                    "{prefix}expected a branch kind (A, T, D, AcrossSource, ThroughSource, Transformer, Gyrator, Friction or TensionOnly), found {found_text}"
                ),
            ),
            _ => (
                K::Syntax,
                format!("{prefix}expected a field name, found {found_text}"),
            ),
        },
        E::ExpectedString => {
            let message = match &place {
                Place::Section(section) => format!(
                    "{}: expected {} name in double quotes, found {found_text}",
                    section.field_name(),
                    match section {
                        Section::Inputs => "an input",
                        Section::Parameters => "a parameter",
                        Section::Elements | Section::InitialState => "an element",
                        Section::Branches => "a branch",
                    }
                ),
                Place::Item(List::Bonds, ..) => {
                    format!("{prefix}expected an element name in double quotes, found {found_text}")
                }
                _ => format!("{subject} a string in double quotes, found {found_text}"),
            };
            // A bare word where a string belongs (not `Some(...)`, `None`, `true`).
            if let Found::Token(token, written) = &found
                && token.kind == TokenKind::Ident
                && !matches!(written.as_str(), "Some" | "None" | "true" | "false")
                && !lex(text, token.span.end).is_ok_and(|t| {
                    t.is_some_and(|t| {
                        t.span.start == token.span.end && t.kind == TokenKind::Punct(b'(')
                    })
                })
            {
                notes.push(format!(
                    "strings are written in double quotes, as in \"{}\"",
                    shorten(written)
                ));
            }
            (type_kind, message)
        }
        E::ExpectedFloat | E::ExpectedInteger => {
            (type_kind, format!("{subject} a number, found {found_text}"))
        }
        E::ExpectedBoolean => (
            type_kind,
            format!("{subject} true or false, found {found_text}"),
        ),
        E::ExpectedChar | E::ExpectedByteLiteral => (
            type_kind,
            format!("{subject} a character, found {found_text}"),
        ),
        E::ExpectedByteString => (
            type_kind,
            format!("{subject} a byte string, found {found_text}"),
        ),
        E::ExpectedOption => (type_kind, format!("{subject} optional, found {found_text}")),
        E::ExpectedUnit => (type_kind, format!("{subject} (), found {found_text}")),
        E::ExpectedMap => {
            let message = match field_name {
                Some(name) if Section::from_field_name(name).is_some() => format!(
                    "field '{name}' must be a map {{\"name\": ..., ...}}, found {found_text}"
                ),
                _ => format!("{prefix}expected a map {{...}}, found {found_text}"),
            };
            (type_kind, message)
        }
        E::ExpectedArray => {
            let message = match field_name {
                Some(name) => format!("field '{name}' must be a list [...], found {found_text}"),
                None => format!("{prefix}expected a list [...], found {found_text}"),
            };
            (type_kind, message)
        }
        E::ExpectedDifferentLength { expected, found } => match &place {
            Place::Item(List::Bonds, ..) => {
                if !value_span.is_empty() {
                    span = value_span;
                }
                let count = match found {
                    0 => "none".to_string(),
                    1 => "one".to_string(),
                    n => n.to_string(),
                };
                (
                    K::WrongType,
                    format!("{prefix}expected two element names (\"from\", \"to\"), found {count}"),
                )
            }
            _ => (
                K::WrongType,
                format!("{prefix}expected {expected}, found {found} items"),
            ),
        },
        E::InvalidValueForType { expected, found } => (
            K::WrongType,
            format!("{prefix}expected {expected}, found {found}"),
        ),
        E::ExpectedComma => {
            let zero_or_one = match &place {
                Place::Entry(Section::Elements, entry) if found.is_punct(b'(') => entry
                    .kind
                    .as_deref()
                    .filter(|kind| matches!(*kind, "Zero" | "One")),
                _ => None,
            };
            if let Some(kind) = zero_or_one {
                (
                    K::Syntax,
                    format!("{prefix}a {kind} junction has no fields; write just {kind}"),
                )
            } else {
                let expected = match innermost {
                    Some((open, _)) => format!("',' or '{}'", char::from(closer(open))),
                    None => "','".to_string(),
                };
                match &comma_after {
                    Some((name, at)) => {
                        span = Span::new(*at, *at);
                        (
                            K::Syntax,
                            format!("expected {expected} after {name}, found {found_text}"),
                        )
                    }
                    None => (
                        K::Syntax,
                        format!("{prefix}expected {expected}, found {found_text}"),
                    ),
                }
            }
        }
        E::ExpectedArrayEnd => (
            K::Syntax,
            format!("{prefix}expected ']', found {found_text}"),
        ),
        E::ExpectedMapEnd => (
            K::Syntax,
            format!("{prefix}expected '}}', found {found_text}"),
        ),
        E::ExpectedOptionEnd | E::ExpectedStructLikeEnd => {
            let kind = if found.is_value() {
                K::WrongType
            } else {
                K::Syntax
            };
            let message = match &place {
                Place::Item(List::Bonds, ..) if found.is_value() => format!(
                    "{prefix}a bond names exactly two elements (\"from\", \"to\"), found another item {found_text}"
                ),
                _ => format!("{prefix}expected ')', found {found_text}"),
            };
            (kind, message)
        }
        E::ExpectedMapColon => (
            K::Syntax,
            format!("{prefix}expected ':', found {found_text}"),
        ),
        E::Eof => {
            let message = match innermost {
                Some((open, _)) => format!(
                    "{prefix}unexpected end of file; expected '{}'",
                    char::from(closer(open))
                ),
                None => format!("{prefix}unexpected end of file"),
            };
            (K::Syntax, message)
        }
        E::TrailingCharacters => (
            K::Syntax,
            format!("unexpected {found_text} after the end of the {noun}"),
        ),
        E::UnexpectedChar(c) => (
            K::Syntax,
            format!("{prefix}unexpected character '{}'", c.escape_debug()),
        ),
        E::ExpectedStringEnd => (
            K::Syntax,
            format!("{prefix}unterminated string: no closing '\"'"),
        ),
        E::InvalidEscape(why) => (
            K::Syntax,
            format!("{prefix}invalid escape in string: {}", lowercase_first(why)),
        ),
        E::UnclosedBlockComment => (
            K::Syntax,
            "unclosed block comment: no closing '*/'".to_string(),
        ),
        E::UnclosedLineComment => (K::Syntax, "unclosed line comment".to_string()),
        E::NoSuchExtension(name) => (
            K::Syntax,
            format!(
                "unknown RON extension '{name}'; {noun} files may enable implicit_some, unwrap_newtypes or unwrap_variant_newtypes"
            ),
        ),
        E::ExpectedAttribute | E::ExpectedAttributeEnd => (
            K::Syntax,
            "malformed attribute; expected #![enable(...)]".to_string(),
        ),
        E::FloatUnderscore | E::UnderscoreAtBeginning => (
            K::Syntax,
            format!("{prefix}misplaced '_' in the number {found_text}"),
        ),
        E::InvalidIntegerDigit { digit, base } => (
            K::Syntax,
            format!(
                "{prefix}invalid digit '{}' in a base-{base} number",
                digit.escape_debug()
            ),
        ),
        E::IntegerOutOfBounds => (
            K::WrongType,
            format!("{prefix}the number {found_text} is out of range"),
        ),
        E::InvalidIdentifier(name) | E::SuggestRawIdentifier(name) => {
            (K::Syntax, format!("{prefix}invalid identifier '{name}'"))
        }
        E::ExceededRecursionLimit => (
            K::Syntax,
            "the file is nested too deeply to read".to_string(),
        ),
        E::Utf8Error(_) => (K::Syntax, "the file is not valid UTF-8".to_string()),
        E::Io(message) => (K::Io, format!("could not read the {noun}: {message}")),
        other => (
            K::Syntax,
            format!("{prefix}{}", lowercase_first(&other.to_string())),
        ),
    };
    // `"m),` swallows text up to the next quote, and the error comes a line later.
    if !matches!(error.code, E::ExpectedStringEnd)
        && let Some(string) = token_before(text, focus.start)
        && string.kind == TokenKind::Str
        && text[string.span.start..string.span.end].contains('\n')
    {
        let (line, column) = file.line_col(string.span.start);
        let (end_line, _) = file.line_col(string.span.end);
        notes.push(format!(
            "the string at line {line}, column {column} runs on to line {end_line}; \
             is a closing '\"' missing?"
        ));
    }
    let mut diagnostic = Diagnostic::new(kind, message).at(file, span);
    if let Some(element) = place.element() {
        diagnostic = diagnostic.element(element);
    }
    for note in notes {
        diagnostic = diagnostic.note(note);
    }
    diagnostic
}

/// Where the first text that does not tokenise starts (an unterminated comment or string).
fn first_lex_error(text: &str) -> Option<usize> {
    let mut pos = 0;
    loop {
        match lex(text, pos) {
            Ok(Some(token)) => pos = token.span.end,
            Ok(None) => return None,
            Err(error) => return Some(error.at),
        }
    }
}

/// The last token that ends at or before `offset`.
fn token_before(text: &str, offset: usize) -> Option<Token> {
    let mut pos = 0;
    let mut last = None;
    while let Ok(Some(token)) = lex(text, pos) {
        if token.span.end > offset {
            break;
        }
        last = Some(token);
        pos = token.span.end;
    }
    last
}

/// `"Unknown escape"` -> `"unknown escape"`.
fn lowercase_first(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A valid model; tests replace one line of it to make one mistake.
    const MODEL: &str = r#"// A mass on a spring, pushed.
Model(
    name: "oscillator",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "k": (value: 50.0, unit: "N/m"),
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "push": Se(effort: "F"),
        "j": One,
        "mass": I(inertance: "m"),
        "spring": C(stiffness: "k"),
    },
    bonds: [
        ("push", "j"),
        ("j", "mass"),
        ("j", "spring"),
    ],
)
"#;

    /// The model with `from` replaced by `to` (which must occur exactly once).
    fn with(from: &str, to: &str) -> String {
        assert_eq!(MODEL.matches(from).count(), 1, "{from:?}");
        MODEL.replace(from, to)
    }

    /// Parses `text` expecting one diagnostic; returns it with its line and column.
    fn diagnose(text: &str) -> (Diagnostic, usize, usize) {
        let file = SourceFile::new("models/test.ron", text);
        let diagnostics = match parse_model(&file) {
            Ok(_) => panic!("parsed:\n{text}"),
            Err(diagnostics) => diagnostics,
        };
        assert_eq!(diagnostics.0.len(), 1);
        let diagnostic = diagnostics.first().clone();
        let location = diagnostic.location.clone().expect("located");
        assert_eq!(location.file, "models/test.ron");
        (diagnostic, location.line, location.column)
    }

    /// The text a diagnostic's span covers.
    fn underlined(text: &str, diagnostic: &Diagnostic) -> String {
        let span = diagnostic
            .location
            .as_ref()
            .map(|l| l.span)
            .unwrap_or_default();
        text[span.start..span.end].to_string()
    }

    #[test]
    fn a_valid_model_parses_with_a_matching_source_map() {
        let file = SourceFile::new("m.ron", MODEL);
        let (model, map) = parse_model(&file).unwrap();
        assert_eq!(model.name, "oscillator");
        let keys: Vec<&str> = map.elements.iter().map(|e| e.key.as_str()).collect();
        let names: Vec<&str> = model.elements.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(keys, names);
        assert_eq!(map.bonds.len(), model.bonds.len());
        assert_eq!(map.parameters.len(), 2);
        let (line, column) = file.line_col(map.elements[2].key_span.start);
        assert_eq!((line, column), (12, 9));
    }

    #[test]
    fn unusual_but_valid_ron_still_gets_a_complete_source_map() {
        let text = r##"#![enable(implicit_some)]
            /* leading /* nested */ comment */ (
            name: r#"odd "name""#, description: Some("\u{e9}t\u{e9}"),
            parameters: {"a": (value: 1_000), "b": (value: -inf), "c": (value: +0.5e-3,),
                r"d": Parameter(value: 2, unit: None)},
            elements: {"x": r#Zero, "y": Se(effort: r#"a"#,), "y": C(stiffness: "b",
                compliance: Some("c"))},
            bonds: [Bond("x", "y",), ("y", r"x")],
        )"##;
        let file = SourceFile::new("m.ron", text);
        let (model, map) = parse_model(&file).unwrap();
        assert_eq!(map.parameters.len(), model.parameters.len());
        assert_eq!(map.elements.len(), model.elements.len());
        assert_eq!(map.bonds.len(), model.bonds.len());
        let keys: Vec<&str> = map.parameters.iter().map(|e| e.key.as_str()).collect();
        assert_eq!(keys, ["a", "b", "c", "d"]);
        let ends: Vec<&str> = map.bonds[1]
            .strings
            .iter()
            .map(|(n, _)| n.as_str())
            .collect();
        assert_eq!(ends, ["y", "x"]);
        assert_eq!(map.elements[0].kind.as_deref(), Some("Zero"));
    }

    #[test]
    fn empty_files() {
        for text in ["", "  \n\t\n", "// nothing here\n/* nor here */\n"] {
            let (d, line, column) = diagnose(text);
            assert_eq!(d.kind, DiagnosticKind::EmptyModel);
            assert_eq!(d.message, "the file is empty; expected a Model(...)");
            assert_eq!((line, column, d.element.as_deref()), (1, 1, None));
        }
    }

    #[test]
    fn unknown_field_in_an_element() {
        let text = with("I(inertance: \"m\")", "I(inertia: \"m\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "element 'mass': unknown field 'inertia'; expected 'inertance' or 'flow'"
        );
        assert_eq!((line, column), (12, 19));
        assert_eq!(d.element.as_deref(), Some("mass"));
        assert_eq!(underlined(&text, &d), "inertia");
    }

    #[test]
    fn unknown_field_in_a_parameter_and_in_the_model() {
        let text = with("unit: \"kg\"", "units: \"kg\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "parameter 'm': unknown field 'units'; expected one of 'value', 'unit', 'description', 'bounds'"
        );
        assert_eq!((line, column), (5, 27));
        assert_eq!(d.element.as_deref(), Some("m"));

        let text = with(
            "    name: \"oscillator\",",
            "    name: \"oscillator\",\n    author: \"me\",",
        );
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(
            d.message,
            "unknown field 'author' in the model; expected one of 'name', 'description', \
             'parameters', 'inputs', 'elements', 'bonds'"
        );
        assert_eq!((line, column, d.element.as_deref()), (4, 5, None));
    }

    #[test]
    fn unknown_element_kind() {
        let text = with("Se(effort: \"F\")", "Q(effort: \"F\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownElementKind);
        assert_eq!(
            d.message,
            "element 'push': unknown element kind 'Q'; expected one of Se, Sf, I, C, R, TF, GY, Friction, TensionOnly, FlowLimit, Zero, One"
        );
        assert_eq!((line, column), (10, 17));
        assert_eq!(d.element.as_deref(), Some("push"));
        assert_eq!(underlined(&text, &d), "Q");
    }

    #[test]
    fn missing_fields() {
        let text = with("(value: 50.0, unit: \"N/m\")", "(unit: \"N/m\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "parameter 'k': missing field 'value'");
        assert_eq!((line, column), (6, 14));
        assert_eq!(d.element.as_deref(), Some("k"));
        assert_eq!(underlined(&text, &d), "(unit: \"N/m\")");

        // An inertia may be given by its inertance or a nonlinear law, so which is missing
        // is the validator's to say, at the same place.
        let text = with("I(inertance: \"m\")", "I()");
        let error = crate::model::load_str("models/test.ron", &text).unwrap_err();
        let d = error.first();
        let location = d.location.clone().expect("located");
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "element 'mass': missing field 'inertance'");
        assert_eq!(
            (location.line, location.column, d.element.as_deref()),
            (12, 17, Some("mass"))
        );

        let text = with("    name: \"oscillator\",\n", "");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::MissingField);
        assert_eq!(d.message, "missing field 'name' in the model");
        assert_eq!((line, column, d.element.as_deref()), (2, 1, None));
    }

    #[test]
    fn wrong_types() {
        let text = with("value: 2.0", "value: \"2.0\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "parameter 'm': field 'value' must be a number, found \"2.0\""
        );
        assert_eq!((line, column, d.element.as_deref()), (5, 22, Some("m")));

        let text = with("C(stiffness: \"k\")", "C(stiffness: k)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "element 'spring': field 'stiffness' must be a string in double quotes, found 'k'"
        );
        assert_eq!(
            d.notes,
            ["strings are written in double quotes, as in \"k\""]
        );
        assert_eq!(
            (line, column, d.element.as_deref()),
            (13, 32, Some("spring"))
        );

        let text = with("inputs: { \"F\": (unit: \"N\") }", "inputs: [\"F\"]");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "field 'inputs' must be a map {\"name\": ..., ...}, found '['"
        );
        assert_eq!((line, column, d.element.as_deref()), (8, 13, None));

        let text = with("(\"j\", \"mass\")", "(\"j\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "bond 2: expected two element names (\"from\", \"to\"), found one"
        );
        assert_eq!((line, column, d.element.as_deref()), (17, 9, None));
        assert_eq!(underlined(&text, &d), "(\"j\")");

        let text = with("Model(", "Modle(");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "expected Model(...) or just (...) around the model, found 'Modle'"
        );
        assert_eq!((line, column), (2, 1));
    }

    #[test]
    fn syntax_errors_inside_an_element() {
        let text = with("I(inertance: \"m\")", "I(inertance: \"m\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected a field name, found \"spring\""
        );
        // The next entry's key, on the line after.
        assert_eq!((line, column, d.element.as_deref()), (13, 9, Some("mass")));

        let text = with("I(inertance: \"m\"),", "I(inertance: \"m\"");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected ',' or ')', found \"spring\""
        );
        assert_eq!((line, column, d.element.as_deref()), (13, 9, Some("mass")));

        // The string runs on to the next line's quote.
        let text = with("I(inertance: \"m\")", "I(inertance: \"m)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'mass': expected ',' or ')', found 'spring'"
        );
        assert_eq!(
            d.notes,
            ["the string at line 12, column 30 runs on to line 13; is a closing '\"' missing?"]
        );
        assert_eq!((line, column, d.element.as_deref()), (13, 10, Some("mass")));

        let text = with("\"j\": One", "\"j\": One()");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "element 'j': a One junction has no fields; write just One"
        );
        assert_eq!((line, column, d.element.as_deref()), (11, 17, Some("j")));

        let text = with("I(inertance: \"m\")", "I");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "element 'mass': expected '(' after I, found ','");
        assert_eq!((line, column, d.element.as_deref()), (12, 18, Some("mass")));
    }

    #[test]
    fn syntax_errors_outside_elements() {
        let text = format!("{MODEL}extra\n");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unexpected 'extra' after the end of the model");
        assert_eq!((line, column, d.element.as_deref()), (21, 1, None));

        let text = MODEL.trim_end().trim_end_matches(')');
        let (d, line, column) = diagnose(text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unexpected end of file; expected ')'");
        assert_eq!(d.notes, ["the '(' at line 2, column 6 is never closed"]);
        assert_eq!((line, column, d.element.as_deref()), (20, 1, None));

        let text = with(
            "\"m\": (value: 2.0, unit: \"kg\"),\n",
            "\"m\": (value: 2.0, unit: \"kg\")\n",
        );
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "expected ',' or '}' after parameter 'm', found \"k\""
        );
        // Where the ',' belongs: right after the entry.
        assert_eq!((line, column, d.element.as_deref()), (5, 38, Some("m")));
        assert!(underlined(&text, &d).is_empty());

        let text = with("(\"push\", \"j\"),", "(\"push\", \"j\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(
            d.message,
            "expected ',' or ']' after bond 1 ('push' -> 'j'), found '('"
        );
        assert_eq!((line, column, d.element.as_deref()), (16, 22, None));

        let text = with("// A mass", "/* A mass");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "unclosed block comment: no closing '*/'");
        assert_eq!((line, column), (1, 1));
    }

    #[test]
    fn syntax_errors_in_bonds() {
        let text = with("(\"j\", \"spring\")", "(\"j\", \"spring)");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::Syntax);
        assert_eq!(d.message, "bond 3: unterminated string: no closing '\"'");
        assert_eq!((line, column, d.element.as_deref()), (18, 15, None));

        let text = with("(\"j\", \"spring\")", "(\"j\", \"spring\", \"mass\")");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::WrongType);
        assert_eq!(
            d.message,
            "bond 3: a bond names exactly two elements (\"from\", \"to\"), \
             found another item \"mass\""
        );
        assert_eq!((line, column, d.element.as_deref()), (18, 25, None));
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let text = with("\"mass\": I(inertance", "\"mäßé\": I(inertia");
        let (d, line, column) = diagnose(&text);
        assert_eq!(d.kind, DiagnosticKind::UnknownField);
        assert_eq!(d.element.as_deref(), Some("mäßé"));
        assert_eq!((line, column), (12, 19));
        assert_eq!(underlined(&text, &d), "inertia");
    }

    /// Checks the contract for any text: no panic, and an error is one located diagnostic
    /// whose span lies on character boundaries inside the text.
    fn check_any(text: &str) {
        let file = SourceFile::new("fuzz.ron", text);
        if let Err(diagnostics) = parse_model(&file) {
            assert_eq!(diagnostics.0.len(), 1);
            let location = diagnostics.first().location.clone().expect("located");
            let span = location.span;
            assert!(span.start <= span.end && span.end <= text.len(), "{span:?}");
            assert!(text.is_char_boundary(span.start) && text.is_char_boundary(span.end));
            assert!(!diagnostics.first().message.is_empty());
        }
    }

    proptest::proptest! {
        #[test]
        fn any_ron_like_text_gives_a_located_diagnostic_or_a_model(
            text in "[ (){}\\[\\]:,\"'#!/*\\\\a-zA-Z0-9_.+\\-\né€]{0,120}"
        ) {
            check_any(&text);
        }

        #[test]
        fn any_damaged_model_gives_a_located_diagnostic_or_a_model(
            cut in 0..MODEL.len(),
            len in 0_usize..12,
            insert in "[ (){}\\[\\]:,\"'#/*a-z0-9é]{0,3}",
        ) {
            let mut text = MODEL.to_string();
            let start = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap_or(0);
            let end = (start + len..=text.len())
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(text.len());
            text.replace_range(start..end, &insert);
            check_any(&text);
            check_any(&text[..start]);
        }
    }

    #[test]
    fn hostile_nesting_is_an_error_not_a_crash() {
        let deep = format!(
            "(name: \"x\", description: {}1{})",
            "[".repeat(50_000),
            "]".repeat(50_000)
        );
        check_any(&deep);
        let open = format!("(name: \"x\", elements: {{\"a\": {}", "(".repeat(50_000));
        check_any(&open);
        let comments = format!("{}(name: \"x\")", "/*".repeat(10_000));
        check_any(&comments);
    }
}
