//! Symbols (parameter and input names) and the table that numbers them.
//!
//! Symbol ids are assigned in *print order*, so that ordering terms by symbol id is the same
//! as ordering them alphabetically the way a textbook would (`b + K_p`, `m_ct + m_ge`). The
//! table is therefore built once, from all names of a model, and never grown.

use std::collections::HashMap;

/// A symbol: the id of a name in a [`SymbolTable`]. A smaller id prints first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Symbol(pub u32);

impl Symbol {
    /// The symbol's position in its table; also its index in the value slice passed to
    /// `eval`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// The names of all symbols of a model, numbered in print order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SymbolTable {
    names: Vec<String>,
    ids: HashMap<String, Symbol>,
}

/// The sort key of print order: case-insensitive name order, ties broken by byte order
/// (`b` < `K_p` < `M` < `m` < `m_ct` < `m_ge`).
fn print_key(name: &str) -> (String, String) {
    (
        name.chars().flat_map(char::to_lowercase).collect(),
        name.to_string(),
    )
}

impl SymbolTable {
    /// Builds a table from names, dropping duplicates. Ids are assigned in print order:
    /// case-insensitive name order, ties broken by byte order.
    pub fn new<I: IntoIterator<Item = S>, S: Into<String>>(names: I) -> Self {
        let mut names: Vec<String> = names.into_iter().map(Into::into).collect();
        names.sort_by_cached_key(|name| print_key(name));
        names.dedup();
        let ids = names
            .iter()
            .enumerate()
            .map(|(i, name)| (name.clone(), Symbol(u32::try_from(i).unwrap_or(u32::MAX))))
            .collect();
        SymbolTable { names, ids }
    }

    /// The symbol with this exact name, if the table has it.
    pub fn get(&self, name: &str) -> Option<Symbol> {
        self.ids.get(name).copied()
    }

    /// The name of a symbol; `"?"` for a symbol that does not belong to this table.
    pub fn name(&self, s: Symbol) -> &str {
        self.names.get(s.index()).map_or("?", String::as_str)
    }

    /// Number of symbols.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether the table has no symbols.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// All symbols and their names, in id (print) order.
    pub fn iter(&self) -> impl Iterator<Item = (Symbol, &str)> {
        self.names
            .iter()
            .enumerate()
            .map(|(i, name)| (Symbol(u32::try_from(i).unwrap_or(u32::MAX)), name.as_str()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_follow_case_insensitive_order_with_byte_order_ties() {
        let table = SymbolTable::new(["m_ge", "M", "K_p", "m_ct", "b", "m"]);
        let names: Vec<&str> = table.iter().map(|(_, n)| n).collect();
        assert_eq!(names, ["b", "K_p", "M", "m", "m_ct", "m_ge"]);
        assert_eq!(table.get("b"), Some(Symbol(0)));
        assert_eq!(table.get("K_p"), Some(Symbol(1)));
        assert_eq!(table.get("M"), Some(Symbol(2)));
        assert_eq!(table.get("m"), Some(Symbol(3)));
        assert_eq!(table.get("m_ge").map(Symbol::index), Some(5));
        assert_eq!(table.name(Symbol(4)), "m_ct");
    }

    #[test]
    fn underscore_sorts_before_letters() {
        // Case-folded, '_' (0x5F) sorts before 'a' (0x61): m_x before ma.
        let table = SymbolTable::new(["ma", "m_x", "MB"]);
        let names: Vec<&str> = table.iter().map(|(_, n)| n).collect();
        assert_eq!(names, ["m_x", "ma", "MB"]);
    }

    #[test]
    fn duplicates_are_dropped_and_unknowns_are_safe() {
        let table = SymbolTable::new(vec!["a".to_string(), "b".into(), "a".into()]);
        assert_eq!(table.len(), 2);
        assert!(!table.is_empty());
        assert_eq!(table.get("c"), None);
        assert_eq!(table.name(Symbol(7)), "?");
        assert!(SymbolTable::default().is_empty());
        assert_eq!(
            SymbolTable::new(Vec::<String>::new()),
            SymbolTable::default()
        );
    }
}
