//! The paper's experimental designs, for synthetic data: which conditions were (or could be)
//! set, with the tip velocity left at zero for a model to predict.

use std::sync::Arc;

use bondgraph_fit::data::Measurement;

use crate::columns::row;

/// The design of the paper's Table III: tank pressures 110 to 150 kPa in steps of 5, at
/// active-channel speeds 5.8, 8.7 and 11.6 mm/s, without a catheter.
pub fn table3_design() -> Vec<Measurement> {
    let file: Arc<str> = Arc::from("table3 design");
    let mut rows = Vec::new();
    for v_ac in [5.8, 8.7, 11.6] {
        for k in 0..9 {
            rows.push(row(
                &file,
                rows.len() + 2,
                110.0 + 5.0 * f64::from(k),
                v_ac,
                None,
                0.0,
            ));
        }
    }
    rows
}

/// A catheter sweep that shows the catheter's friction: the robot without a catheter at
/// 110 to 150 kPa (steps of 10) at Table III's active-channel speeds, then with the
/// catheter driven at 0 to 60 mm/s at 110, 130 and 150 kPa while the channel pays out at
/// 50 mm/s.
///
/// The paper's own sweep (Table VI: one pressure, catheter speeds up to 6.3 mm/s) cannot
/// show the catheter's friction: stuck to the inner structure, the catheter can pull the tip
/// with up to `2 F_S_ct` = 12.1 N, and at those speeds the tip needs at most a few newtons,
/// so every row is catheter-locked at `v_ct/2` whatever the friction. The sheath stops
/// following the catheter once `b v_ct/2 > 2 F_S_ct + A P_s - F_C_ge`, at 22 to 29 mm/s for
/// the paper's values; beyond that the tip slides at `(A P_s - F_C_ge + 2 F_C_ct)/b`, and
/// the sweep goes on well past that (to 60 mm/s) so that several rows at every pressure
/// show where the tip slides. The channel pays out fast enough (50 mm/s, more than twice
/// any tip speed here) for the inner structure to stay slack, so the catheter alone decides.
pub fn catheter_sweep_design() -> Vec<Measurement> {
    let file: Arc<str> = Arc::from("catheter sweep design");
    let mut rows = Vec::new();
    let mut push = |pressure: f64, channel: f64, catheter: Option<f64>| {
        rows.push(row(&file, rows.len() + 2, pressure, channel, catheter, 0.0));
    };
    for channel in [5.8, 8.7, 11.6] {
        for k in 0..5 {
            push(110.0 + 10.0 * f64::from(k), channel, None);
        }
    }
    for pressure in [110.0, 130.0, 150.0] {
        for catheter in [0.0, 10.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0] {
            push(pressure, 50.0, Some(catheter));
        }
    }
    rows
}

/// A grid of `pressures` tank pressures evenly from 110 to 150 kPa at `channels`
/// active-channel speeds evenly from 5.8 to 11.6 mm/s (Table III's ranges), without a
/// catheter: `pressures × channels` rows, for measuring how the cost of a fit grows with
/// the data.
pub fn grid_design(pressures: usize, channels: usize) -> Vec<Measurement> {
    let file: Arc<str> = Arc::from("grid design");
    let step = |k: usize, count: usize| k as f64 / (count.max(2) - 1) as f64;
    let mut rows = Vec::with_capacity(pressures * channels);
    for c in 0..channels {
        let v_ac = 5.8 + 5.8 * step(c, channels);
        for k in 0..pressures {
            let pressure = 110.0 + 40.0 * step(k, pressures);
            rows.push(row(&file, rows.len() + 2, pressure, v_ac, None, 0.0));
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::columns::{catheter, channel, pressure};

    #[test]
    fn the_designs_have_their_cells() {
        let design = table3_design();
        assert_eq!(design.len(), 27);
        assert_eq!((pressure(&design[26]), channel(&design[26])), (150.0, 11.6));
        let sweep = catheter_sweep_design();
        assert_eq!(sweep.len(), 15 + 27);
        assert_eq!(catheter(&sweep[14]), None);
        assert_eq!(catheter(&sweep[41]), Some(60.0));
        let grid = grid_design(20, 5);
        assert_eq!(grid.len(), 100);
        assert_eq!((pressure(&grid[0]), channel(&grid[0])), (110.0, 5.8));
        assert_eq!((pressure(&grid[99]), channel(&grid[99])), (150.0, 11.6));
        assert!((pressure(&grid[1]) - (110.0 + 40.0 / 19.0)).abs() < 1e-12);
    }
}
