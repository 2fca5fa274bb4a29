//! Where each part of a model or scenario file is: byte spans of entries, fields and items.
//!
//! A parsed value carries no position, yet later stages must still point at the file: a
//! causal conflict found long after parsing names the element's line and column, and an
//! unknown symbol in an expression is underlined inside the string it was written in. A
//! reader (`bondgraph-ron`) records the spans of the things users name next to the value it
//! reads: top-level fields and their values, the entries of the map sections (`parameters`,
//! `inputs`, `elements`, `branches`, `ports`, `initial_state`: key, kind, fields, string contents), and
//! the items of the list sections (`bonds`, `remove`, `record`). Entries and items are
//! recorded one for one with the value's lists (file order, duplicates kept), so index `i`
//! of [`SourceMap::elements`] is the span of element `i` of the [`ModelSpec`]. A model built
//! in code has an empty map. Positions are byte offsets.
//!
//! [`ModelSpec`]: super::spec::ModelSpec

use crate::source::Span;

/// The spans of a model or scenario file's parts, in file order. Sections the file does
/// not have are empty.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SourceMap {
    /// The whole top-level value, from its struct name (or `(`) to its `)`.
    pub root: Span,
    /// Each top-level field: its name, the name's span and the value's span, in file order.
    pub fields: Vec<FieldSpan>,
    /// The entries of the `parameters` map, in file order, duplicates kept.
    pub parameters: Vec<EntrySpans>,
    /// The entries of the `inputs` map, in file order, duplicates kept.
    pub inputs: Vec<EntrySpans>,
    /// The entries of the `elements` map (model files), in file order, duplicates kept.
    pub elements: Vec<EntrySpans>,
    /// The entries of the `branches` map (linear-graph files), in file order, duplicates
    /// kept.
    pub branches: Vec<EntrySpans>,
    /// The entries of the `initial_state` map (scenario files), in file order, duplicates
    /// kept.
    pub initial_state: Vec<EntrySpans>,
    /// The entries of the `ports` map (model files), in file order, duplicates kept.
    pub ports: Vec<EntrySpans>,
    /// The entries of the `terminals` map (linear-graph files), in file order, duplicates
    /// kept.
    pub terminals: Vec<EntrySpans>,
    /// The items of the `bonds` list (model files), in file order.
    pub bonds: Vec<ItemSpans>,
    /// The items of the `remove` list (scenario files), in file order.
    pub remove: Vec<ItemSpans>,
    /// The items of the `record` list (scenario files), in file order.
    pub record: Vec<ItemSpans>,
}

/// Where one `"name": value` entry of a map section is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EntrySpans {
    /// The key, with escapes decoded.
    pub key: String,
    /// The key's string literal, quotes included.
    pub key_span: Span,
    /// The whole value.
    pub value_span: Span,
    /// The value's leading identifier, if any: the element kind (`"I"`, `"Zero"`), the
    /// signal kind (`"Ramp"`), or a struct name written before a parameter's `(...)`. A raw
    /// identifier's `r#` is removed.
    pub kind: Option<String>,
    /// The value's named fields, in file order.
    pub fields: Vec<FieldSpan>,
}

/// Where one `name: value` field is (inside an entry, or at the top level).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FieldSpan {
    /// The field name.
    pub name: String,
    /// The field name's span.
    pub name_span: Span,
    /// The whole value.
    pub value_span: Span,
    /// For a string literal value (also inside `Some(...)`): the bytes between the quotes,
    /// so that a span relative to the string (an expression's) can be shifted onto the file.
    /// The shift is exact unless the string contains escapes before the spanned text.
    pub string_content: Option<Span>,
}

/// Where one item of a list section is: a bond `("pump", "j1")`, or a string such as an
/// element to remove or an output to record.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ItemSpans {
    /// The whole item, e.g. `("pump", "j1")` or `"flow:ge"`.
    pub span: Span,
    /// The item's string literals: the item itself if it is one, or each string of its
    /// tuple; each with its decoded text and the span of its content (between the quotes).
    pub strings: Vec<(String, Span)>,
}

/// Which map section an entry is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Section {
    /// `parameters: {...}`: a model's parameters, or a scenario's parameter values.
    Parameters,
    /// `inputs: {...}`: a model's inputs, or a scenario's input signals.
    Inputs,
    /// `elements: {...}`, in model files.
    Elements,
    /// `initial_state: {...}`, in scenario files.
    InitialState,
    /// `branches: {...}`, in linear-graph files.
    Branches,
    /// `ports: {...}`, in model files used as sub-models.
    Ports,
    /// `terminals: {...}`, in linear-graph files used as sub-graphs.
    Terminals,
}

/// Which list section an item is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum List {
    /// `bonds: [...]`, in model files.
    Bonds,
    /// `remove: [...]`, in scenario files.
    Remove,
    /// `record: [...]`, in scenario files.
    Record,
}

impl Section {
    /// Every section, in the order lookups try them.
    pub const ALL: [Section; 7] = [
        Section::Parameters,
        Section::Inputs,
        Section::Elements,
        Section::InitialState,
        Section::Branches,
        Section::Ports,
        Section::Terminals,
    ];

    /// What one entry of the section is called in messages: "parameter", "input",
    /// "element", "initial state".
    pub fn noun(self) -> &'static str {
        match self {
            Section::Parameters => "parameter",
            Section::Inputs => "input",
            Section::Elements => "element",
            Section::InitialState => "initial state",
            Section::Branches => "branch",
            Section::Ports => "port",
            Section::Terminals => "terminal",
        }
    }

    /// The section's field name in the file.
    pub fn field_name(self) -> &'static str {
        match self {
            Section::Parameters => "parameters",
            Section::Inputs => "inputs",
            Section::Elements => "elements",
            Section::InitialState => "initial_state",
            Section::Branches => "branches",
            Section::Ports => "ports",
            Section::Terminals => "terminals",
        }
    }

    /// The section named by top-level field `name`, if it is one.
    pub fn from_field_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.field_name() == name)
    }
}

impl List {
    /// Every list section.
    pub const ALL: [List; 3] = [List::Bonds, List::Remove, List::Record];

    /// The list's field name in the file.
    pub fn field_name(self) -> &'static str {
        match self {
            List::Bonds => "bonds",
            List::Remove => "remove",
            List::Record => "record",
        }
    }

    /// The list named by top-level field `name`, if it is one.
    pub fn from_field_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|l| l.field_name() == name)
    }
}

impl EntrySpans {
    /// From the start of the key to the end of the value.
    pub fn span(&self) -> Span {
        Span::new(
            self.key_span.start,
            self.value_span.end.max(self.key_span.end),
        )
    }

    /// The field called `name`, if the entry has one (the first, if written twice).
    pub fn field(&self, name: &str) -> Option<&FieldSpan> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// The field whose name or value contains `offset`.
    pub fn field_at(&self, offset: usize) -> Option<&FieldSpan> {
        self.fields.iter().find(|f| f.span().contains(offset))
    }
}

impl FieldSpan {
    /// From the start of the name to the end of the value.
    pub fn span(&self) -> Span {
        Span::new(
            self.name_span.start,
            self.value_span.end.max(self.name_span.end),
        )
    }

    /// The string's content if the value is a string literal, else the whole value: where
    /// a problem with the value's text is pointed at.
    pub fn text_span(&self) -> Span {
        self.string_content.unwrap_or(self.value_span)
    }
}

impl ItemSpans {
    /// The content of the item's only string (between the quotes) if it is one string,
    /// else the whole item.
    pub fn text_span(&self) -> Span {
        match self.strings[..] {
            [(_, content)] => content,
            _ => self.span,
        }
    }
}

impl SourceMap {
    /// The entries of `section`.
    pub fn entries(&self, section: Section) -> &[EntrySpans] {
        match section {
            Section::Parameters => &self.parameters,
            Section::Inputs => &self.inputs,
            Section::Elements => &self.elements,
            Section::InitialState => &self.initial_state,
            Section::Branches => &self.branches,
            Section::Ports => &self.ports,
            Section::Terminals => &self.terminals,
        }
    }

    /// The items of `list`.
    pub fn items(&self, list: List) -> &[ItemSpans] {
        match list {
            List::Bonds => &self.bonds,
            List::Remove => &self.remove,
            List::Record => &self.record,
        }
    }

    /// The top-level field called `name`, if the file has it (the first, if written twice).
    pub fn field(&self, name: &str) -> Option<&FieldSpan> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// The element whose entry (key to end of value) contains byte `offset`.
    pub fn element_at(&self, offset: usize) -> Option<&EntrySpans> {
        self.elements.iter().find(|e| e.span().contains(offset))
    }

    /// The entry of any map section that contains byte `offset`, and its section.
    pub fn entry_containing(&self, offset: usize) -> Option<(Section, &EntrySpans)> {
        Section::ALL.into_iter().find_map(|section| {
            self.entries(section)
                .iter()
                .find(|e| e.span().contains(offset))
                .map(|e| (section, e))
        })
    }

    /// The bond that contains byte `offset`, with its index in the `bonds` list.
    pub fn bond_at(&self, offset: usize) -> Option<(usize, &ItemSpans)> {
        self.bonds
            .iter()
            .enumerate()
            .find(|(_, b)| b.span.contains(offset))
    }

    /// The top-level field that `offset` is in: the last field whose name starts before
    /// `offset` (a field's value runs until the next field's name).
    pub fn field_before(&self, offset: usize) -> Option<&FieldSpan> {
        self.fields
            .iter()
            .take_while(|f| f.name_span.start <= offset)
            .last()
    }
}
