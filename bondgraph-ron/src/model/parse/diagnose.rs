//! ron's error turned into one [`Diagnostic`] in the file's own terms.
//!
//! ron reports an error as a code and a line/column span, phrased for programmers
//! ("Unexpected field named `inertia` in `I`") and sometimes positioned on the whitespace
//! before the offending token. [`diagnose`] picks the [`DiagnosticKind`], moves the location
//! onto the offending token (or the end of the file), finds the entry or bond the position
//! is in with the [`SourceMap`] scanner (scanning only the text up to the error when the
//! whole text does not scan), and words the message in the model's own terms:
//! `element 'mass': unknown field 'inertia'; expected 'inertance'`. The wording is one
//! function per family of ron's errors, tried in order.

use ron::error::{Position, SpannedError};

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind};
use bondgraph_core::source::{SourceFile, Span};

use super::FileKind;
use crate::source_map::{Token, TokenKind, closer, lex, open_brackets, skip_trivia};
use bondgraph_core::model::source_map::{EntrySpans, ItemSpans, List, Section, SourceMap};

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

/// What [`diagnose`] knows of a problem before it words it: where it is and what was found.
struct Context<'m> {
    text: &'m str,
    file_kind: FileKind,
    place: Place<'m>,
    /// `element 'mass': `, or nothing outside an entry or bond.
    prefix: String,
    noun: &'static str,
    found: Found,
    found_text: String,
    /// The span of the value the problem is in.
    value_span: Span,
    field_name: Option<&'m str>,
    /// `field 'unit' must be`, for type errors.
    subject: String,
    type_kind: DiagnosticKind,
    /// The innermost bracket open at the problem, and where.
    innermost: Option<(u8, usize)>,
    /// The entry or bond a missing ',' belongs after, and where.
    comma_after: Option<(String, usize)>,
    focus: Span,
}

/// What the wording adds: the span to underline, if not the focus, and notes.
struct Said {
    span: Span,
    notes: Vec<String>,
}

/// Turns ron's error into one diagnostic.
pub(super) fn diagnose(file: &SourceFile, error: &SpannedError, file_kind: FileKind) -> Diagnostic {
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
    let full = crate::source_map::scan(text);
    let partial;
    let (map, inclusive) = match &full {
        Some(map) => (map, false),
        None => {
            let cut = focus.end.min(text.len());
            partial = crate::source_map::scan_partial(text.get(..cut).unwrap_or(text));
            (&partial, true)
        }
    };
    let (place, comma_after) = place_of(map, text, &error.code, focus, inclusive);
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
    let subject = subject_of(&place, field_name, &prefix);
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
    let cx = Context {
        text,
        file_kind,
        place,
        prefix,
        noun,
        found,
        found_text,
        value_span,
        field_name,
        subject,
        type_kind,
        innermost,
        comma_after,
        focus,
    };
    let mut said = Said { span: focus, notes };
    let (kind, message) = name_problem(&error.code, &cx, &mut said)
        .or_else(|| structure_problem(&error.code, &cx, &mut said))
        .or_else(|| type_problem(&error.code, &cx, &mut said))
        .or_else(|| punctuation_problem(&error.code, &cx, &mut said))
        .unwrap_or_else(|| lexical_problem(&error.code, &cx));
    let Said { span, mut notes } = said;
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
    if let Some(element) = cx.place.element() {
        diagnostic = diagnostic.element(element);
    }
    for note in notes {
        diagnostic = diagnostic.note(note);
    }
    diagnostic
}

/// Where the problem is: the place of `focus`; or, where ron stops past an entry or bond
/// whose '(' or ',' is missing, that entry or bond, with the offset a missing ',' belongs at.
fn place_of<'m>(
    map: &'m SourceMap,
    text: &str,
    code: &ron::Error,
    focus: Span,
    inclusive: bool,
) -> (Place<'m>, Option<(String, usize)>) {
    use ron::Error as E;
    let place = place_at(map, focus.start, inclusive);
    // `"mass": I}`: the '(' that should follow the kind is missing; `"mass": I(inertance:
    // "m") "spring": ...`: the ',' after an entry or bond is. Either way the problem is the
    // entry or bond that ends just before the token found (and the ',' belongs right after
    // it).
    let missing = matches!(
        code,
        E::ExpectedStructLike | E::ExpectedNamedStructLike(_) | E::ExpectedComma
    );
    if missing
        && matches!(place, Place::Section(_) | Place::Field(_) | Place::Model)
        && let Some(before) = token_before(text, focus.start).map(|t| t.span.end)
        && before > 0
        && let found_before @ (Place::Entry(..) | Place::Item(..)) =
            place_at(map, before - 1, inclusive)
    {
        let comma_after = matches!(code, E::ExpectedComma).then(|| (found_before.name(), before));
        return (found_before, comma_after);
    }
    (place, None)
}

/// `field 'unit' must be` or `parameter 'm' must be`, for type errors.
fn subject_of(place: &Place<'_>, field_name: Option<&str>, prefix: &str) -> String {
    match (place, field_name) {
        (Place::Entry(..), Some(field)) => format!("{prefix}field '{field}' must be"),
        (Place::Field(_) | Place::Section(_), Some(field)) => format!("field '{field}' must be"),
        (Place::Entry(section, entry), None) => {
            format!("{} '{}' must be", section.noun(), entry.key)
        }
        (Place::Item(list, index, item), _) => {
            format!("{} must be", item_name(*list, *index, item))
        }
        _ => "the value must be".to_string(),
    }
}

/// The wording of a problem with a field or a variant: unknown, missing or given twice.
fn name_problem(
    code: &ron::Error,
    cx: &Context<'_>,
    said: &mut Said,
) -> Option<(DiagnosticKind, String)> {
    use DiagnosticKind as K;
    use ron::Error as E;
    let Context {
        prefix,
        noun,
        value_span,
        place,
        file_kind,
        ..
    } = cx;
    let (value_span, file_kind) = (*value_span, *file_kind);
    Some(match code {
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
            // Parts written as other tools write them (BondGraphTools' `models`).
            if !matches!(place, Place::Entry(..) | Place::Item(..))
                && file_kind == FileKind::Model
                && matches!(found.as_str(), "models" | "submodels" | "components")
            {
                said.notes.push(
                    "a model built from parts uses each part as an element, \
                     \"front\": Submodel(file: \"part.ron\"), and bonds to its ports, \
                     \"front.port\""
                        .to_string(),
                );
            }
            // A bond graph's words in a linear graph's branch.
            if matches!(place, Place::Entry(Section::Branches, _))
                && matches!(found.as_str(), "flow" | "effort")
            {
                said.notes.push(
                    "a linear graph's laws are written in its own variables: a D-type's \
                     through: \"EXPR of across\" or across: \"EXPR of through\", an A-type's \
                     across: \"EXPR of p_NAME\", a T-type's through: \"EXPR of q_NAME\""
                        .to_string(),
                );
            }
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
                said.span = value_span;
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
        _ => return None,
    })
}

/// The wording of a problem with a structure's name or kind: a struct of another name, a
/// '(' missing after a kind, an identifier where a kind or a signal belongs.
fn structure_problem(
    code: &ron::Error,
    cx: &Context<'_>,
    said: &mut Said,
) -> Option<(DiagnosticKind, String)> {
    use DiagnosticKind as K;
    use ron::Error as E;
    let Context {
        prefix,
        noun,
        found,
        found_text,
        type_kind,
        focus,
        place,
        file_kind,
        ..
    } = cx;
    let (type_kind, focus, file_kind) = (*type_kind, *focus, *file_kind);
    Some(match code {
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
                said.notes.push(format!(
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
        _ => return None,
    })
}

/// The wording of a value of the wrong type: a string, number, map or list expected.
fn type_problem(
    code: &ron::Error,
    cx: &Context<'_>,
    said: &mut Said,
) -> Option<(DiagnosticKind, String)> {
    use DiagnosticKind as K;
    use ron::Error as E;
    let Context {
        prefix,
        found,
        found_text,
        value_span,
        field_name,
        subject,
        type_kind,
        place,
        text,
        ..
    } = cx;
    let (value_span, field_name, type_kind) = (*value_span, *field_name, *type_kind);
    Some(match code {
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
                        Section::Ports => "a port",
                        Section::Terminals => "a terminal",
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
                said.notes.push(format!(
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
                    said.span = value_span;
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
        _ => return None,
    })
}

/// The wording of a punctuation problem: a missing ',', ']', '}', ')' or ':', an early end.
fn punctuation_problem(
    code: &ron::Error,
    cx: &Context<'_>,
    said: &mut Said,
) -> Option<(DiagnosticKind, String)> {
    use DiagnosticKind as K;
    use ron::Error as E;
    let Context {
        prefix,
        noun,
        found,
        found_text,
        innermost,
        comma_after,
        place,
        ..
    } = cx;
    let innermost = *innermost;
    Some(match code {
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
                        said.span = Span::new(*at, *at);
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
        _ => return None,
    })
}

/// The wording of the lexical and remaining problems (a bad string, comment, number or
/// identifier, a file too deep or unreadable), and ron's own words for the rest.
fn lexical_problem(code: &ron::Error, cx: &Context<'_>) -> (DiagnosticKind, String) {
    use DiagnosticKind as K;
    use ron::Error as E;
    let Context {
        prefix,
        noun,
        found_text,
        ..
    } = cx;
    match code {
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
    }
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
