//! How many modes a search over several elements' modes would derive, bounded.
//!
//! When switching one element at a time cycles, the simulator searches every combination of
//! the modes of the elements involved ([`super::Simulator`]'s consistent-mode search). That
//! is `3^N` for `N` friction contacts, each a symbolic derivation: the product once wrapped
//! past `usize::MAX` at 41 contacts (a panic in a debug build, a wrong count in a release
//! one), and long before that it is more work than any run should do. The count is checked,
//! and bounded by [`MAX_MODES`](bondgraph_core::limits::MAX_MODES).

use bondgraph_core::limits::MAX_MODES;

/// The number of combinations of elements with `sizes` modes each, or `None` when it is
/// over [`MAX_MODES`] (a product that would overflow is over it).
pub(super) fn count(sizes: impl IntoIterator<Item = usize>) -> Option<usize> {
    sizes.into_iter().try_fold(1usize, |product, size| {
        product.checked_mul(size).filter(|&c| c <= MAX_MODES)
    })
}

/// The number of combinations in words, however large (`3^41` is `3.647299637717079e19`).
pub(super) fn in_words(sizes: impl IntoIterator<Item = usize>) -> String {
    let product: f64 = sizes.into_iter().map(|s| s as f64).product();
    bondgraph_core::limits::count_in_words(product)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forty_one_contacts_are_over_the_limit_not_a_wrapped_product() {
        // 3^41 = 36 472 996 377 170 786 403 > usize::MAX = 18 446 744 073 709 551 615.
        assert_eq!(count([3; 41]), None);
        let words = in_words([3; 41]);
        assert!(words.contains('e'), "{words}");
        assert_eq!(words.parse::<f64>(), Ok(36_472_996_377_170_786_403.0));
    }

    #[test]
    fn combinations_up_to_the_limit_are_counted() {
        // Six contacts and a string: 3^6 * 2 = 1458 > 1000; six contacts: 729.
        assert_eq!(count([3; 6]), Some(729));
        assert_eq!(count([3, 3, 3, 3, 3, 3, 2]), None);
        assert_eq!(count([]), Some(1));
    }
}
