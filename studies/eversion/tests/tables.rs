//! The paper's Table III and VI conditions predicted by both eversion models, against closed
//! forms derived by hand.
//!
//! Table IV: A = 1e-4 m², F_S_ge = 11.7 N, F_C_ge = 9.125 N, b = 1250 N·s/m. Without a catheter
//! and from rest, the tip stays put while A P_s < F_S_ge (P_s <= 115 kPa); beyond, it slides
//! pressure-driven at (A P_s - F_C_ge)/b while its inner structure is slack, and is held by the
//! taut inner structure to v_ac/2 in the flagship (eversion) or to v_ac in the paper's
//! structure.

use bondgraph_eversion::columns::{catheter, channel, pressure};

use crate::support::{dataset, predictor};

fn pressure_driven(p_kpa: f64) -> f64 {
    // mm/s
    (1e-4 * p_kpa * 1e3 - 9.125) / 1250.0 * 1e3
}

#[test]
fn table_three_by_hand() {
    let rows = dataset("table3.csv").rows;
    for (file, limit) in [
        ("models/eversion/robot.ron", 0.5),
        ("models/eversion/paper.ron", 1.0),
    ] {
        let predicted = predictor(file).predict(&rows).unwrap();
        for (row, v) in rows.iter().zip(&predicted) {
            let v = v[0];
            let expected = if pressure(row) * 1e3 * 1e-4 < 11.7 {
                0.0
            } else {
                pressure_driven(pressure(row)).min(limit * channel(row))
            };
            assert!(
                (v - expected).abs() < 1e-9,
                "{file} at {} kPa, {} mm/s: {v} vs {expected}",
                pressure(row),
                channel(row)
            );
        }
    }
}

#[test]
fn table_six_by_hand() {
    // P_s = 110 kPa, v_ac = 5.8 mm/s. Catheter held (0): nothing moves. Otherwise the
    // catheter sticks to the inner structure (flagship: at 2 v_ge) or to the tip (paper:
    // at v_ge) and its servo drives the body: K_p = 5e4 N·s/m, F_C_ge = 9.125 N,
    //   flagship: v = (A P_s - F_C_ge + 2 K_p v_ct)/(b + 4 K_p), limited to v_ac/2
    //   paper:    v = (A P_s - F_C_ge + K_p v_ct)/(b + K_p),     limited to v_ac
    let rows = dataset("table6.csv").rows;
    let (a, p, f, b, k) = (1e-4, 110e3, 9.125, 1250.0, 5e4);
    let robot = predictor("models/eversion/robot.ron")
        .predict(&rows)
        .unwrap();
    let paper = predictor("models/eversion/paper.ron")
        .predict(&rows)
        .unwrap();
    for (i, row) in rows.iter().enumerate() {
        let v_ct = catheter(row).unwrap() * 1e-3;
        let (flagship, structure) = if v_ct == 0.0 {
            (0.0, 0.0)
        } else {
            (
                ((a * p - f + 2.0 * k * v_ct) / (b + 4.0 * k)).min(2.9e-3) * 1e3,
                ((a * p - f + k * v_ct) / (b + k)).min(5.8e-3) * 1e3,
            )
        };
        assert!(
            (robot[i][0] - flagship).abs() < 1e-9,
            "robot at {v_ct}: {} vs {flagship}",
            robot[i][0]
        );
        assert!(
            (paper[i][0] - structure).abs() < 1e-9,
            "paper at {v_ct}: {} vs {structure}",
            paper[i][0]
        );
    }
}
