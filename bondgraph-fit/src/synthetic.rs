//! Synthetic measurements: a model (possibly extended with a hidden effect) simulated on an
//! experimental design, with measurement noise.
//!
//! This is how `discover` is tested: data made from the flagship with one extension hidden
//! in it, handed over as CSV, must lead back to that extension; data with nothing hidden
//! must give nothing. The noise is Gaussian (SplitMix64 seeds, Box–Muller), and a velocity
//! cannot be measured below zero (a tip held by the nozzle is filmed standing still), so
//! noisy values are clipped at zero as the data format requires.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;

use crate::data::Measurement;
use crate::experiment::{Experiment, ExperimentError, Predictor};

/// The design of the paper's Table III: tank pressures 110 to 150 kPa in steps of 5, at
/// active-channel speeds 5.8, 8.7 and 11.6 mm/s, without a catheter.
pub fn table3_design() -> Vec<Measurement> {
    let mut rows = Vec::new();
    for v_ac in [5.8, 8.7, 11.6] {
        for k in 0..9 {
            rows.push(Measurement {
                pressure_kpa: 110.0 + 5.0 * f64::from(k),
                channel_velocity_mm_s: v_ac,
                catheter_velocity_mm_s: None,
                tip_velocity_mm_s: 0.0,
                row: rows.len() + 2,
            });
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
    let mut rows = Vec::new();
    let mut push = |pressure: f64, channel: f64, catheter: Option<f64>| {
        rows.push(Measurement {
            pressure_kpa: pressure,
            channel_velocity_mm_s: channel,
            catheter_velocity_mm_s: catheter,
            tip_velocity_mm_s: 0.0,
            row: rows.len() + 2,
        });
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

/// A deterministic source of normal deviates.
#[derive(Clone, Debug)]
pub struct Noise {
    state: u64,
    spare: Option<f64>,
}

impl Noise {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed,
            spare: None,
        }
    }

    /// A uniform deviate in (0, 1) (SplitMix64).
    pub fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal deviate (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        if let Some(spare) = self.spare.take() {
            return spare;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let radius = (-2.0 * u.ln()).sqrt();
        let angle = 2.0 * std::f64::consts::PI * v;
        self.spare = Some(radius * angle.sin());
        radius * angle.cos()
    }
}

/// The steady tip velocities `model` (with `values` set, by parameter name) predicts on
/// `design`, plus Gaussian noise of standard deviation `noise_mm_s`, clipped at zero.
///
/// # Errors
/// When a parameter is unknown or a row does not settle.
pub fn measure(
    model: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    values: &[(String, f64)],
    design: &[Measurement],
    noise_mm_s: f64,
    noise: &mut Noise,
) -> Result<Vec<Measurement>, ExperimentError> {
    let mut predictor = Predictor::new(model.clone(), source, experiment)?;
    predictor.set_parameters(values)?;
    let truth = predictor.predict(design)?;
    Ok(design
        .iter()
        .zip(truth)
        .map(|(row, v)| Measurement {
            tip_velocity_mm_s: (v + noise_mm_s * noise.normal()).max(0.0),
            ..row.clone()
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_has_the_moments_of_a_standard_normal() {
        let mut noise = Noise::new(7);
        let n = 200_000;
        let samples: Vec<f64> = (0..n).map(|_| noise.normal()).collect();
        let mean = samples.iter().sum::<f64>() / n as f64;
        let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        let beyond_2 = samples.iter().filter(|x| x.abs() > 2.0).count() as f64 / n as f64;
        // Standard errors: 1/sqrt(n) = 0.0022 for the mean, sqrt(2/n) = 0.0032 for the
        // variance; P(|Z| > 2) = 0.0455.
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((variance - 1.0).abs() < 0.015, "{variance}");
        assert!((beyond_2 - 0.0455).abs() < 0.003, "{beyond_2}");
    }

    #[test]
    fn the_table3_design_has_27_cells() {
        let design = table3_design();
        assert_eq!(design.len(), 27);
        assert_eq!(design[26].pressure_kpa, 150.0);
        assert_eq!(design[26].channel_velocity_mm_s, 11.6);
    }
}
