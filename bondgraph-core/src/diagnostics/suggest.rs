//! Suggestions for a misspelt name: the closest of the names a reader knows, if it is
//! close enough to be a typo ("did you mean 'mass'?").

/// The candidate closest to `name` by edit distance, if it is close enough to be a typo:
/// a candidate differing only in case comes first, and one that keeps nothing of the name
/// (`F` for `c`) is no suggestion.
pub fn suggest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .map(|c| {
            let longer = name.chars().count().max(c.chars().count());
            let distance = if c.eq_ignore_ascii_case(name) {
                0
            } else {
                edit_distance(name, c)
            };
            (distance, longer, c)
        })
        .filter(|(d, longer, _)| *d <= (longer / 3).max(1) && *d < *longer)
        .min_by_key(|(d, _, c)| (*d, *c))
        .map(|(_, _, c)| c)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = previous + usize::from(ca != *cb);
            previous = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(previous + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_catch_typos_only() {
        let names = ["mass", "spring", "damper"];
        assert_eq!(suggest("mas", names.into_iter()), Some("mass"));
        assert_eq!(suggest("dampr", names.into_iter()), Some("damper"));
        assert_eq!(suggest("valve", names.into_iter()), None);
        // One-letter names: a case slip is a typo, another letter is not.
        let symbols = ["F", "b", "k", "m"];
        assert_eq!(suggest("f", symbols.into_iter()), Some("F"));
        assert_eq!(suggest("c", symbols.into_iter()), None);
        assert_eq!(suggest("k1", ["k", "m"].into_iter()), Some("k"));
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
