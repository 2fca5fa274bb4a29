//! A friction contact whose Stribeck velocity is zero, through the `bondgraph` program: it
//! is listed, derived and simulated as the Karnopp contact with the same forces.

use crate::cli::{fail, succeed};

const ZERO: &str = "tests/fixtures/stribeck/zero.ron";

#[test]
fn its_modes_are_karnopp_modes() {
    // Written to start creeping, it starts slipping: there is no creeping range.
    let text = succeed(&["modes", ZERO]);
    assert!(
        text.starts_with(
            "model 'stribeck_zero': 1 switching element, 3 modes reachable from contact=slip+\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("contact: holding force F >= F_S -> contact=slip+\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "contact: relative velocity p_block/m <= 0, if static friction can then hold -> contact=stuck\n"
        ),
        "{text}"
    );
    assert!(!text.contains("creep"), "{text}");
}

#[test]
fn a_creeping_mode_is_refused_with_the_reason() {
    let error = fail(&["equations", ZERO, "--mode", "contact=creep+"]);
    assert!(
        error.contains(
            "contact 'contact' cannot be creep+: its Stribeck velocity \"v_s\" is 0, which leaves no creeping range"
        ),
        "{error}"
    );
}

#[test]
fn its_initial_creeping_mode_is_derived_as_slipping() {
    // Slipping forward, the block obeys dp/dt = F - F_C.
    let text = succeed(&["equations", ZERO]);
    assert!(text.starts_with("mode contact=slip+\n"), "{text}");
    assert!(text.contains("dp_block/dt = F - F_C\n"), "{text}");
}
