//! The main job on the bundled models and data.

use bondgraph_fit::reproduce::reproduce;

use crate::support::Files;

#[test]
fn removing_the_parasitic_tip_mass_changes_no_table_cell() {
    // The tip's mass against the nozzle damper: m_ge/b = 5e-15/1250 = 4e-18 s, against the
    // next time scale, the catheter servo's m_ct/K_p = 5e-4/5e4 = 1e-8 s.
    let files = Files::read();
    let r = reproduce(&files.bundle()).unwrap();
    assert_eq!(r.reduction.removed.len(), 1);
    assert_eq!(r.reduction.removed[0].element, "ge");
    assert!((r.reduction.removed[0].time_constant - 4e-18).abs() < 1e-30);
    assert!((r.reduction.removed[0].next_time_constant - 1e-8).abs() < 1e-20);
    assert_eq!(r.reduction.cells, 33);
    assert!(
        r.reduction.largest_difference_mm_s < 1e-9,
        "{}",
        r.reduction.largest_difference_mm_s
    );
}

#[test]
fn the_paper_simulated_column_implies_other_friction_than_table_four() {
    // By hand: the paper's simulated cells of Table III between static and the channel's
    // limit are 0.3, 1.1, 1.85, 2.6 (all columns), 3.4 and 4.15 (8.7 and 11.6 mm/s) at
    // 115...140 kPa: 0.75 mm/s per 5 kPa, i.e. about 0.15 mm/s per kPa, where Table IV's
    // v = (A P_s - F_C)/b rises 1e-4 * 1e3 / 1250 = 0.08 mm/s per kPa from 91.25 kPa.
    let files = Files::read();
    let r = reproduce(&files.bundle()).unwrap();
    assert_eq!(r.findings.table4_line, (0.08, 91.25));
    let line = r.findings.paper_sim_line.unwrap();
    assert_eq!(line.cells.len(), 16);
    assert!((line.slope - 0.15).abs() < 0.01, "{}", line.slope);
    assert!(line.largest_residual < 0.05);
    // Implied: b = A/slope ≈ 1e-4 Pa·m² ... ≈ 650 N·s/m and F_C = A P_onset ≈ 11.3 N.
    assert!((line.implied_b - 650.0).abs() < 20.0, "{}", line.implied_b);
    assert!(
        (line.implied_coulomb - 11.3).abs() < 0.1,
        "{}",
        line.implied_coulomb
    );
}
