//! The scanner that finds where each part of a model or scenario file is ([`SourceMap`]).
//!
//! serde tells us where an error is, but a successfully parsed value carries no position,
//! and later stages must still point at the file: a causal conflict found long after
//! parsing names the element's line and column, and an unknown symbol in an expression is
//! underlined inside the string it was written in. So, next to serde, a small independent
//! RON scanner walks the same text and records the spans of the things users name:
//! top-level fields and their values, the entries of the map sections (`parameters`,
//! `inputs`, `elements`, `branches`, `initial_state`: key, kind, fields, string contents), and the items
//! of the list sections (`bonds`, `remove`, `record`).
//!
//! Model files and scenario files share this scanner: both are a struct of named fields
//! whose sections are maps of named entries or lists of items, and a section's name says
//! which it is in either kind of file. The scanner does not check which fields a file may
//! have (serde does), and [`edit`](crate::model::edit) uses the same spans to rewrite a model's
//! text in place.
//!
//! The scanner only knows the shape of these files and skips any other value as a
//! balanced group of tokens, so it accepts some texts ron rejects; it is not a validator.
//! Entries and items are recorded one for one with serde's lists (file order, duplicates
//! kept), so index `i` of [`SourceMap::elements`] is the span of element `i` of the raw
//! model. Positions are byte offsets, so multi-byte characters anywhere do not shift them.

use bondgraph_core::model::source_map::{
    EntrySpans, FieldSpan, ItemSpans, List, Section, SourceMap,
};
use bondgraph_core::source::Span;

mod lex;
use lex::string_value;
pub(crate) use lex::{Token, TokenKind, closer, lex, open_brackets, skip_trivia};

/// Scans a whole model or scenario file; `None` if the text is not scannable (a token
/// RON does not have, an unbalanced bracket, an unterminated string or comment, text
/// after the top-level value, or an empty file).
pub fn scan(text: &str) -> Option<SourceMap> {
    let mut walker = Walker::new(text);
    match walker.document() {
        Ok(()) => Some(walker.map),
        Err(Stop) => None,
    }
}

/// Scans as much of `text` as it can: everything recorded before the first problem is
/// kept, and whatever was still open there (the top-level value, an entry, a field, an
/// item) extends to the end of `text`. Meant for the text up to a syntax error, to find
/// the entry the error is in.
pub fn scan_partial(text: &str) -> SourceMap {
    let mut walker = Walker::new(text);
    let _ = walker.document();
    walker.close_open(text.len());
    walker.map
}

/// The top-level items of the list that starts at the first `[` in `span` of `text`: the
/// span of each item, in order (`[(0, 1), (2, 3)]` gives the spans of `(0, 1)` and
/// `(2, 3)`). `None` if there is no such list or it does not scan; meant for pointing at one
/// item of a list value that serde has already read, such as a point of a table.
pub fn list_items(text: &str, span: Span) -> Option<Vec<Span>> {
    let mut pos = span.start;
    let open = loop {
        let token = lex(text, pos).ok()??;
        if token.span.end > span.end {
            return None;
        }
        if token.is_punct(b'[') {
            break token;
        }
        pos = token.span.end;
    };
    let mut walker = Walker::new(text);
    walker.pos = open.span.end;
    let mut items = Vec::new();
    loop {
        if walker.peek_is(b']').ok()? {
            return Some(items);
        }
        let start = walker.peek().ok()??.span.start;
        walker.value().ok()?;
        items.push(Span::new(start, walker.last_end));
        walker.comma_or(b']').ok()?;
    }
}

// ---------------------------------------------------------------------------------------
// The walk

/// The end of a span whose construct is still open.
const OPEN: usize = usize::MAX;

/// The scan met something it cannot read.
struct Stop;

type Step<T = ()> = Result<T, Stop>;

struct Walker<'a> {
    text: &'a str,
    /// Where the next token is looked for.
    pos: usize,
    /// End of the last token taken.
    last_end: usize,
    map: SourceMap,
}

impl<'a> Walker<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text,
            pos: 0,
            last_end: 0,
            map: SourceMap {
                root: Span::new(0, OPEN),
                ..SourceMap::default()
            },
        }
    }

    fn peek(&self) -> Step<Option<Token>> {
        lex(self.text, self.pos).map_err(|_| Stop)
    }

    /// The token after the next one (for `name:` lookahead).
    fn peek_second(&self) -> Option<Token> {
        let first = lex(self.text, self.pos).ok()??;
        lex(self.text, first.span.end).ok()?
    }

    fn next(&mut self) -> Step<Token> {
        let token = self.peek()?.ok_or(Stop)?;
        self.pos = token.span.end;
        self.last_end = token.span.end;
        Ok(token)
    }

    fn peek_is(&self, c: u8) -> Step<bool> {
        Ok(self.peek()?.is_some_and(|t| t.is_punct(c)))
    }

    fn expect(&mut self, c: u8) -> Step<Token> {
        let token = self.next()?;
        if token.is_punct(c) {
            Ok(token)
        } else {
            Err(Stop)
        }
    }

    /// After an item of a list closed by `close`: a comma, or the closer (left in place).
    fn comma_or(&mut self, close: u8) -> Step {
        match self.peek()? {
            Some(t) if t.is_punct(b',') => {
                self.next()?;
                Ok(())
            }
            Some(t) if t.is_punct(close) => Ok(()),
            _ => Err(Stop),
        }
    }

    fn ident_name(&self, token: &Token) -> String {
        let name = &self.text[token.span.start..token.span.end];
        name.strip_prefix("r#").unwrap_or(name).to_string()
    }

    /// The whole file: attributes, then the top-level struct of named fields.
    fn document(&mut self) -> Step {
        while self.peek()?.is_some_and(|t| t.kind == TokenKind::Attribute) {
            self.next()?;
        }
        let first = self.peek()?.ok_or(Stop)?;
        self.map.root.start = first.span.start;
        if first.kind == TokenKind::Ident {
            self.next()?;
        }
        self.expect(b'(')?;
        loop {
            if self.peek_is(b')')? {
                self.map.root.end = self.next()?.span.end;
                break;
            }
            let name = self.next()?;
            if name.kind != TokenKind::Ident {
                return Err(Stop);
            }
            let field = self.ident_name(&name);
            self.expect(b':')?;
            let value_start = skip_trivia(self.text, self.pos).unwrap_or(self.pos);
            self.map.fields.push(FieldSpan {
                name: field.clone(),
                name_span: name.span,
                value_span: Span::new(value_start, OPEN),
                string_content: None,
            });
            let mut content = None;
            match (
                Section::from_field_name(&field),
                List::from_field_name(&field),
            ) {
                (Some(section), _) if self.peek_is(b'{')? => self.section(section)?,
                (_, Some(list)) if self.peek_is(b'[')? => self.list(list)?,
                _ => content = self.field_value()?,
            }
            let end = self.last_end;
            if let Some(field) = self.map.fields.last_mut() {
                field.value_span.end = end;
                field.string_content = content;
            }
            self.comma_or(b')')?;
        }
        match self.peek()? {
            None => Ok(()),
            Some(_) => Err(Stop),
        }
    }

    fn entries_mut(&mut self, section: Section) -> &mut Vec<EntrySpans> {
        match section {
            Section::Parameters => &mut self.map.parameters,
            Section::Inputs => &mut self.map.inputs,
            Section::Elements => &mut self.map.elements,
            Section::InitialState => &mut self.map.initial_state,
            Section::Branches => &mut self.map.branches,
            Section::Ports => &mut self.map.ports,
            Section::Terminals => &mut self.map.terminals,
        }
    }

    fn items_mut(&mut self, list: List) -> &mut Vec<ItemSpans> {
        match list {
            List::Bonds => &mut self.map.bonds,
            List::Remove => &mut self.map.remove,
            List::Record => &mut self.map.record,
        }
    }

    fn section(&mut self, section: Section) -> Step {
        self.expect(b'{')?;
        loop {
            if self.peek_is(b'}')? {
                self.next()?;
                return Ok(());
            }
            let key = self.next()?;
            if key.kind != TokenKind::Str {
                return Err(Stop);
            }
            let entry = EntrySpans {
                key: string_value(self.text, &key),
                key_span: key.span,
                value_span: Span::new(key.span.end, OPEN),
                kind: None,
                fields: Vec::new(),
            };
            self.entries_mut(section).push(entry);
            self.expect(b':')?;
            let start = skip_trivia(self.text, self.pos).unwrap_or(self.pos);
            self.current_entry(section).value_span.start = start;
            self.entry_value(section)?;
            let end = self.last_end;
            self.current_entry(section).value_span.end = end;
            self.comma_or(b'}')?;
        }
    }

    fn current_entry(&mut self, section: Section) -> &mut EntrySpans {
        let entries = self.entries_mut(section);
        let last = entries.len() - 1;
        &mut entries[last]
    }

    /// `Kind`, `Kind(field: value, ...)`, `(field: value, ...)` or any other value.
    fn entry_value(&mut self, section: Section) -> Step {
        let mut named = false;
        if let Some(token) = self.peek()?
            && token.kind == TokenKind::Ident
        {
            self.next()?;
            let kind = self.ident_name(&token);
            self.current_entry(section).kind = Some(kind);
            named = true;
        }
        if !self.peek_is(b'(')? {
            return if named { Ok(()) } else { self.value() };
        }
        self.next()?;
        loop {
            if self.peek_is(b')')? {
                self.next()?;
                return Ok(());
            }
            let first = self.peek()?.ok_or(Stop)?;
            let is_named_field = first.kind == TokenKind::Ident
                && self.peek_second().is_some_and(|t| t.is_punct(b':'));
            if is_named_field {
                self.next()?;
                self.next()?;
                // Recorded before the value is read, so that a partial scan stopped by a
                // bad value still knows which field it is in.
                let value_start = skip_trivia(self.text, self.pos).unwrap_or(self.pos);
                let field = FieldSpan {
                    name: self.ident_name(&first),
                    name_span: first.span,
                    value_span: Span::new(value_start, OPEN),
                    string_content: None,
                };
                self.current_entry(section).fields.push(field);
                let content = self.field_value()?;
                let end = self.last_end;
                let entry = self.current_entry(section);
                if let Some(field) = entry.fields.last_mut() {
                    field.value_span.end = end;
                    field.string_content = content;
                }
            } else {
                self.value()?;
            }
            self.comma_or(b')')?;
        }
    }

    /// A field's value; for a string literal, alone or in `Some(...)`, its content span.
    fn field_value(&mut self) -> Step<Option<Span>> {
        let Some(first) = self.peek()? else {
            return Err(Stop);
        };
        if first.kind == TokenKind::Str {
            self.next()?;
            return Ok(Some(first.content));
        }
        if first.kind == TokenKind::Ident && &self.text[first.span.start..first.span.end] == "Some"
        {
            let mut tokens = Vec::with_capacity(4);
            let mut pos = first.span.end;
            for _ in 0..3 {
                match lex(self.text, pos) {
                    Ok(Some(token)) => {
                        pos = token.span.end;
                        tokens.push(token);
                    }
                    _ => break,
                }
            }
            if let [open, string, close] = tokens[..]
                && open.is_punct(b'(')
                && string.kind == TokenKind::Str
                && close.is_punct(b')')
            {
                self.pos = close.span.end;
                self.last_end = close.span.end;
                return Ok(Some(string.content));
            }
        }
        self.value()?;
        Ok(None)
    }

    /// A list section: each item is a string, or a tuple (optionally named, as in
    /// `Bond("a", "b")`) whose strings are recorded, or any other value.
    fn list(&mut self, list: List) -> Step {
        self.expect(b'[')?;
        loop {
            if self.peek_is(b']')? {
                self.next()?;
                return Ok(());
            }
            let first = self.peek()?.ok_or(Stop)?;
            self.items_mut(list).push(ItemSpans {
                span: Span::new(first.span.start, OPEN),
                strings: Vec::new(),
            });
            if first.kind == TokenKind::Str {
                self.next()?;
                self.record_string(list, &first);
            } else {
                if first.kind == TokenKind::Ident {
                    self.next()?;
                }
                if self.peek_is(b'(')? {
                    self.next()?;
                    loop {
                        if self.peek_is(b')')? {
                            self.next()?;
                            break;
                        }
                        match self.peek()? {
                            Some(token) if token.kind == TokenKind::Str => {
                                self.next()?;
                                self.record_string(list, &token);
                            }
                            _ => self.value()?,
                        }
                        self.comma_or(b')')?;
                    }
                } else if first.kind != TokenKind::Ident {
                    self.value()?;
                }
            }
            let end = self.last_end;
            if let Some(item) = self.items_mut(list).last_mut() {
                item.span.end = end;
            }
            self.comma_or(b']')?;
        }
    }

    /// Records string `token` in the current item of `list`.
    fn record_string(&mut self, list: List, token: &Token) {
        let name = string_value(self.text, token);
        if let Some(item) = self.items_mut(list).last_mut() {
            item.strings.push((name, token.content));
        }
    }

    /// Any value: a literal, an identifier with an optional `(...)`, or a bracketed group
    /// skipped as balanced tokens.
    fn value(&mut self) -> Step {
        let token = self.next()?;
        match token.kind {
            TokenKind::Str | TokenKind::Number | TokenKind::Char => Ok(()),
            TokenKind::Ident => {
                if self.peek_is(b'(')? {
                    let open = self.next()?;
                    self.skip_group(open)
                } else {
                    Ok(())
                }
            }
            TokenKind::Punct(b'(' | b'[' | b'{') => self.skip_group(token),
            TokenKind::Punct(_) | TokenKind::Attribute => Err(Stop),
        }
    }

    /// Skips to the bracket that closes `open` (already taken).
    fn skip_group(&mut self, open: Token) -> Step {
        let TokenKind::Punct(c) = open.kind else {
            return Err(Stop);
        };
        let mut stack = vec![closer(c)];
        while let Some(&expected) = stack.last() {
            let token = self.next()?;
            match token.kind {
                TokenKind::Punct(c @ (b'(' | b'[' | b'{')) => stack.push(closer(c)),
                TokenKind::Punct(c @ (b')' | b']' | b'}')) => {
                    if c != expected {
                        return Err(Stop);
                    }
                    stack.pop();
                }
                TokenKind::Attribute => return Err(Stop),
                _ => {}
            }
        }
        Ok(())
    }

    /// Ends every span still open at `end`.
    fn close_open(&mut self, end: usize) {
        let close = |span: &mut Span| {
            if span.end == OPEN {
                span.end = end;
            }
            span.start = span.start.min(end);
        };
        let map = &mut self.map;
        close(&mut map.root);
        for field in &mut map.fields {
            close(&mut field.value_span);
        }
        for entry in map
            .parameters
            .iter_mut()
            .chain(&mut map.inputs)
            .chain(&mut map.elements)
            .chain(&mut map.initial_state)
        {
            close(&mut entry.value_span);
            for field in &mut entry.fields {
                close(&mut field.value_span);
            }
        }
        for item in map
            .bonds
            .iter_mut()
            .chain(&mut map.remove)
            .chain(&mut map.record)
        {
            close(&mut item.span);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A realistic model: attributes, line and nested block comments, raw strings,
    /// escapes, odd spacing, multi-byte characters, `Some(...)`, a raw identifier and a
    /// duplicate name.
    const MODEL: &str = r###"#![enable(implicit_some)]
// Hydraulic cylinder — a test model “with” multi-byte text: µ, π, ✓.
Model (
    name:"cylinder",
    description: r#"A "quoted" description, ½ raw"#,
    parameters : {
        "A"  :(value: 2e-3, unit: "m²", description: "piston área"),
        "m":  Parameter( value : -1.5e+2 , unit: Some("kg") ),
        /* a block /* nested */ comment */ "k\"x": (value: 1_000),
    },
    inputs: { "P_s": (unit: "Pa") },
    elements: {
        "pump"  : Se( effort : "A*P_s" ),
        "j"     :One,
        "mass":I(inertance:r"m + m"),
        "spring": r#C(stiffness: "1/k", compliance: None),
        "j": Zero, // duplicate, kept
    },
    bonds: [ ("pump","j") , Bond( "j", "mass" ),("j" , "spring"),
    ],
)
"###;

    fn at(span: Span) -> &'static str {
        &MODEL[span.start..span.end]
    }

    #[test]
    fn records_the_model_and_its_top_level_fields() {
        let map = crate::source_map::scan(MODEL).expect("scannable");
        assert!(at(map.root).starts_with("Model (\n    name:"));
        assert!(at(map.root).ends_with("],\n)"));
        let fields: Vec<(&str, &str)> = map
            .fields
            .iter()
            .map(|f| (f.name.as_str(), at(f.name_span)))
            .collect();
        assert_eq!(
            fields,
            [
                ("name", "name"),
                ("description", "description"),
                ("parameters", "parameters"),
                ("inputs", "inputs"),
                ("elements", "elements"),
                ("bonds", "bonds"),
            ]
        );
    }

    #[test]
    fn records_parameter_keys_fields_and_string_contents() {
        let map = crate::source_map::scan(MODEL).expect("scannable");
        let keys: Vec<(&str, &str)> = map
            .parameters
            .iter()
            .map(|e| (e.key.as_str(), at(e.key_span)))
            .collect();
        assert_eq!(
            keys,
            [("A", "\"A\""), ("m", "\"m\""), ("k\"x", "\"k\\\"x\"")]
        );

        let area = &map.parameters[0];
        assert_eq!(area.kind, None);
        assert_eq!(
            at(area.value_span),
            "(value: 2e-3, unit: \"m²\", description: \"piston área\")"
        );
        let fields: Vec<(&str, &str, &str)> = area
            .fields
            .iter()
            .map(|f| (f.name.as_str(), at(f.name_span), at(f.value_span)))
            .collect();
        assert_eq!(
            fields,
            [
                ("value", "value", "2e-3"),
                ("unit", "unit", "\"m²\""),
                ("description", "description", "\"piston área\""),
            ]
        );
        assert_eq!(area.fields[0].string_content, None);
        assert_eq!(at(area.fields[2].string_content.unwrap()), "piston área");

        let mass = &map.parameters[1];
        assert_eq!(mass.kind.as_deref(), Some("Parameter"));
        assert_eq!(at(mass.field("value").unwrap().value_span), "-1.5e+2");
        let unit = mass.field("unit").unwrap();
        assert_eq!(at(unit.value_span), "Some(\"kg\")");
        assert_eq!(at(unit.string_content.unwrap()), "kg");
        assert_eq!(at(map.parameters[2].value_span), "(value: 1_000)");
        assert_eq!(at(map.inputs[0].key_span), "\"P_s\"");
        assert_eq!(at(map.inputs[0].fields[0].string_content.unwrap()), "Pa");
    }

    #[test]
    fn records_element_kinds_and_expression_strings_with_duplicates() {
        let map = crate::source_map::scan(MODEL).expect("scannable");
        let summary: Vec<(&str, Option<&str>, &str)> = map
            .elements
            .iter()
            .map(|e| (e.key.as_str(), e.kind.as_deref(), at(e.value_span)))
            .collect();
        assert_eq!(
            summary,
            [
                ("pump", Some("Se"), "Se( effort : \"A*P_s\" )"),
                ("j", Some("One"), "One"),
                ("mass", Some("I"), "I(inertance:r\"m + m\")"),
                (
                    "spring",
                    Some("C"),
                    "r#C(stiffness: \"1/k\", compliance: None)"
                ),
                ("j", Some("Zero"), "Zero"),
            ]
        );
        let effort = &map.elements[0].fields[0];
        assert_eq!(at(effort.name_span), "effort");
        let content = effort.string_content.unwrap();
        assert_eq!(at(content), "A*P_s");
        // An expression's span shifted onto the file lands on the symbol.
        let expr = bondgraph_core::expr::parse(at(content)).unwrap();
        let (symbol, span) = expr.symbols()[1];
        assert_eq!((symbol, at(span.shifted(content.start))), ("P_s", "P_s"));
        assert_eq!(
            at(map.elements[2].fields[0].string_content.unwrap()),
            "m + m"
        );
        let spring = &map.elements[3];
        assert_eq!(at(spring.field("compliance").unwrap().value_span), "None");
        assert_eq!(spring.field("compliance").unwrap().string_content, None);
        assert!(map.elements[1].fields.is_empty());
    }

    #[test]
    fn records_bonds_and_their_ends() {
        let map = crate::source_map::scan(MODEL).expect("scannable");
        let bonds: Vec<(&str, Vec<(&str, &str)>)> = map
            .bonds
            .iter()
            .map(|b| {
                (
                    at(b.span),
                    b.strings
                        .iter()
                        .map(|(n, s)| (n.as_str(), at(*s)))
                        .collect(),
                )
            })
            .collect();
        assert_eq!(
            bonds,
            [
                ("(\"pump\",\"j\")", vec![("pump", "pump"), ("j", "j")]),
                (
                    "Bond( \"j\", \"mass\" )",
                    vec![("j", "j"), ("mass", "mass")]
                ),
                (
                    "(\"j\" , \"spring\")",
                    vec![("j", "j"), ("spring", "spring")]
                ),
            ]
        );
    }

    #[test]
    fn lookups_by_offset() {
        let map = crate::source_map::scan(MODEL).expect("scannable");
        let offset = |needle: &str| MODEL.find(needle).unwrap();
        assert_eq!(
            map.element_at(offset("inertance")).map(|e| e.key.as_str()),
            Some("mass")
        );
        assert_eq!(map.element_at(offset("2e-3")), None);
        let (section, entry) = map.entry_containing(offset("2e-3")).unwrap();
        assert_eq!((section, entry.key.as_str()), (Section::Parameters, "A"));
        let (section, entry) = map.entry_containing(offset("\"Pa\"")).unwrap();
        assert_eq!((section, entry.key.as_str()), (Section::Inputs, "P_s"));
        // The key belongs to the entry too.
        let (section, entry) = map.entry_containing(offset("\"pump\"  :")).unwrap();
        assert_eq!((section, entry.key.as_str()), (Section::Elements, "pump"));
        assert_eq!(map.entry_containing(offset("cylinder")), None);
        let (index, bond) = map.bond_at(offset("\"mass\" )")).unwrap();
        assert_eq!((index, bond.strings[1].0.as_str()), (1, "mass"));
        assert_eq!(map.bond_at(offset("\"pump\",")), Some((0, &map.bonds[0])));
        assert_eq!(map.bond_at(offset(" ,")), None);
        assert_eq!(
            map.entries(Section::Elements)[0].field_at(offset("A*P_s")),
            Some(&map.elements[0].fields[0])
        );
        assert_eq!(
            map.field_before(offset("\"P_s\"")).map(|f| f.name.as_str()),
            Some("inputs")
        );
    }

    #[test]
    fn multi_byte_text_does_not_shift_spans() {
        let ascii = "(name: \"x\", description: \"plain\", elements: {\"a\": Zero})";
        let utf8 = "(name: \"x\", description: \"ŝŧřåñĝé\", elements: {\"a\": Zero})";
        let a = crate::source_map::scan(ascii).unwrap();
        let b = crate::source_map::scan(utf8).unwrap();
        let extra = utf8.len() - ascii.len();
        assert_eq!(
            b.elements[0].key_span,
            a.elements[0].key_span.shifted(extra)
        );
        assert_eq!(
            &utf8[b.elements[0].value_span.start..b.elements[0].value_span.end],
            "Zero"
        );
    }

    #[test]
    fn unscannable_texts() {
        for text in [
            "",
            "   // only a comment\n",
            "(name: \"x\"",
            "(name: \"x\") trailing",
            "(name: \"x\", elements: {\"a\": I(inertance: \"m\"}})",
            "(name: \"unterminated)",
            "(name: \"x\") /* unclosed",
            "(name: $)",
            "(name: \"x\", elements: {3: Zero})",
            "[1, 2]",
        ] {
            assert_eq!(crate::source_map::scan(text), None, "{text:?}");
        }
        let deep = format!("(name: {}{})", "[".repeat(100_000), "]".repeat(100_000));
        assert!(crate::source_map::scan(&deep).is_some());
    }

    #[test]
    fn partial_scans_keep_what_was_read_and_leave_open_entries_open() {
        let text = "(name: \"x\", elements: {\"a\": Zero, \"mass\": I(inertance: \"m\"";
        let map = crate::source_map::scan_partial(text);
        assert_eq!(map.elements.len(), 2);
        let zero = text.find("Zero").unwrap();
        assert_eq!(map.elements[0].value_span, Span::new(zero, zero + 4));
        let mass = &map.elements[1];
        assert_eq!(mass.kind.as_deref(), Some("I"));
        assert_eq!(mass.value_span.end, text.len());
        assert_eq!(
            &text[mass.fields[0].string_content.unwrap().start..][..1],
            "m"
        );
        assert_eq!(map.root, Span::new(0, text.len()));
        assert_eq!(
            map.element_at(text.len() - 1).map(|e| e.key.as_str()),
            Some("mass")
        );

        let bonds =
            crate::source_map::scan_partial("(name: \"x\", bonds: [(\"a\", \"b\"), (\"c\",");
        assert_eq!(bonds.bonds.len(), 2);
        assert_eq!(
            bonds.bonds[1].strings,
            vec![("c".to_string(), Span::new(34, 35))]
        );
        assert_eq!(bonds.bonds[1].span, Span::new(32, 37));

        assert_eq!(crate::source_map::scan_partial(""), SourceMap::default());
    }

    /// A scenario file: the same scanner records its map sections, its lists of strings
    /// and every top-level field's value.
    const SCENARIO: &str = r#"Scenario(
    name: "push",
    remove: ["rubber", r"fr_b",],
    parameters: { "dv": 1e-6 },
    inputs: {
        "F": Ramp(slope: 1.0e6, ceiling: 2.0e5),
        "v_w": Constant(5.8e-3),
        "x": Table([(0.0, 0.0), (1.0, /* two */ 2.0) , (2.0, 2.0)]),
    },
    initial_mode: Some("fr_a=stuck"),
    initial_state: { "k": -1.0e-4 },
    duration: 0.2,
    record: ["flow:cart", "integral:flow:cart"],
)"#;

    #[test]
    fn records_the_sections_and_fields_of_a_scenario() {
        let map = crate::source_map::scan(SCENARIO).expect("scannable");
        let at = |span: Span| &SCENARIO[span.start..span.end];
        let fields: Vec<(&str, &str)> = map
            .fields
            .iter()
            .map(|f| (f.name.as_str(), at(f.value_span)))
            .collect();
        assert_eq!(fields[0], ("name", "\"push\""));
        assert_eq!(fields[1], ("remove", "[\"rubber\", r\"fr_b\",]"));
        assert_eq!(fields[5], ("initial_state", "{ \"k\": -1.0e-4 }"));
        assert_eq!(fields[6], ("duration", "0.2"));
        assert_eq!(map.field("name").unwrap().text_span(), Span::new(21, 25));
        let mode = map.field("initial_mode").unwrap();
        assert_eq!(at(mode.value_span), "Some(\"fr_a=stuck\")");
        assert_eq!(at(mode.text_span()), "fr_a=stuck");

        let strings = |list: List| -> Vec<(String, &str)> {
            map.items(list)
                .iter()
                .map(|item| (item.strings[0].0.clone(), at(item.text_span())))
                .collect()
        };
        assert_eq!(
            strings(List::Remove),
            [("rubber".into(), "rubber"), ("fr_b".into(), "fr_b")]
        );
        assert_eq!(at(map.remove[1].span), "r\"fr_b\"");
        assert_eq!(
            strings(List::Record),
            [
                ("flow:cart".into(), "flow:cart"),
                ("integral:flow:cart".into(), "integral:flow:cart")
            ]
        );

        assert_eq!(at(map.parameters[0].value_span), "1e-6");
        let inputs: Vec<(&str, Option<&str>, &str)> = map
            .inputs
            .iter()
            .map(|e| (e.key.as_str(), e.kind.as_deref(), at(e.value_span)))
            .collect();
        assert_eq!(inputs[1], ("v_w", Some("Constant"), "Constant(5.8e-3)"));
        let ramp = &map.inputs[0];
        assert_eq!(at(ramp.field("ceiling").unwrap().value_span), "2.0e5");
        assert_eq!(map.initial_state[0].key, "k");
        assert_eq!(at(map.initial_state[0].value_span), "-1.0e-4");
        let (section, entry) = map
            .entry_containing(SCENARIO.find("-1.0e-4").unwrap())
            .unwrap();
        assert_eq!((section, entry.key.as_str()), (Section::InitialState, "k"));

        let table = map.inputs[2].value_span;
        let points: Vec<&str> = list_items(SCENARIO, table)
            .unwrap()
            .into_iter()
            .map(at)
            .collect();
        assert_eq!(points, ["(0.0, 0.0)", "(1.0, /* two */ 2.0)", "(2.0, 2.0)"]);
        assert_eq!(list_items(SCENARIO, ramp.value_span), None);
        assert_eq!(list_items("[1, (2", Span::new(0, 6)), None);
        assert_eq!(list_items("[]", Span::new(0, 2)), Some(vec![]));
    }
}
