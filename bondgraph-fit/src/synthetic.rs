//! Synthetic measurements: a model (possibly extended with a hidden effect) simulated on an
//! experimental design, with measurement noise.
//!
//! This is how `calibrate` and `discover` are tested: data made from a model with known
//! parameter values (or with one extension hidden in it), handed over as CSV, must lead back
//! to those values (or that extension); data with nothing hidden must give nothing. The
//! noise is Gaussian (SplitMix64 seeds, Box–Muller), deterministic for a seed.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;

use crate::data::Measurement;
use crate::experiment::{Experiment, ExperimentError};
use crate::predict::Predictor;

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

/// What `model` (with `values` set, by parameter name) predicts on `design` for every
/// observed column, plus Gaussian noise of standard deviation `noise_sd` (in each column's
/// units), optionally clipped from below at `floor` (a velocity filmed standing still cannot
/// be negative).
///
/// # Errors
/// When a parameter is unknown or a row does not settle.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    model: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    values: &[(String, f64)],
    design: &[Measurement],
    noise_sd: f64,
    floor: Option<f64>,
    noise: &mut Noise,
) -> Result<Vec<Measurement>, ExperimentError> {
    let mut predictor = Predictor::new(model.clone(), source, experiment)?;
    predictor.set_parameters(values)?;
    let truth = predictor.predict(design)?;
    Ok(design
        .iter()
        .zip(truth)
        .map(|(row, observed)| Measurement {
            observed: observed
                .iter()
                .map(|v| {
                    let noisy = v + noise_sd * noise.normal();
                    floor.map_or(noisy, |f| noisy.max(f))
                })
                .collect(),
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
}
