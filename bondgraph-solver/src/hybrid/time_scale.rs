//! The fastest time scale of a mode at an instant, for the message of a run whose steps ran
//! out.
//!
//! A run that spends its budget of steps has met a time scale far shorter than its
//! duration: an integrator held to steps of 1e-260 s by a velocity damped at 1e307 /s (a
//! damper seen through a transformer of ratio 1e-154), or a long duration sampled on a
//! mode's oscillations. Which scale, and in which state, is what lets a user act on it.

use std::fmt;

use num_complex::Complex64;

/// A time scale of a mode, and the states it lives in where known.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeScale {
    /// In seconds.
    pub seconds: f64,
    /// The states it belongs to: one (a decay), two (an oscillation between them), or none
    /// where only the mode's eigenvalues are known.
    pub states: Vec<String>,
}

impl TimeScale {
    /// `1/max|λ|` over a linear mode's eigenvalues; `None` if none is a finite nonzero rate.
    pub(super) fn of_eigenvalues(values: &[Complex64]) -> Option<Self> {
        let fastest = values
            .iter()
            .map(|v| v.norm())
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        (fastest > 0.0).then(|| TimeScale {
            seconds: 1.0 / fastest,
            states: Vec::new(),
        })
    }

    /// The fastest rate a Jacobian shows (`n` rows of `stride` entries, the states named by
    /// `names`): each state's own rate `|J_ii|` and each pair's oscillation `√|J_ij J_ji|`, both
    /// in 1/s whatever the states' units; `None` if every one is zero.
    pub(super) fn of_jacobian(
        jacobian: &[f64],
        n: usize,
        stride: usize,
        names: &[String],
    ) -> Option<Self> {
        let entry = |i: usize, j: usize| jacobian[i * stride + j];
        let mut fastest = (0.0, Vec::new());
        for i in 0..n {
            let own = entry(i, i).abs();
            if own.is_finite() && own > fastest.0 {
                fastest = (own, vec![i]);
            }
            for j in i + 1..n {
                let swing = (entry(i, j) * entry(j, i)).abs().sqrt();
                if swing.is_finite() && swing > fastest.0 {
                    fastest = (swing, vec![i, j]);
                }
            }
        }
        let (rate, states) = fastest;
        (rate > 0.0).then(|| TimeScale {
            seconds: 1.0 / rate,
            states: states.into_iter().map(|i| names[i].clone()).collect(),
        })
    }
}

impl fmt::Display for TimeScale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Six significant digits are all a message needs (1/1e307 is 1.0000000000000001e-307).
        let seconds: f64 = format!("{:.5e}", self.seconds)
            .parse()
            .unwrap_or(self.seconds);
        write!(f, "{seconds:e} s")?;
        let quoted: Vec<String> = self.states.iter().map(|s| format!("'{s}'")).collect();
        if !quoted.is_empty() {
            write!(f, ", in {}", quoted.join(" and "))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_decay_and_an_oscillation_are_read_off_a_jacobian() {
        let names = ["p_mass".to_string(), "q_spring".to_string()];
        // dp/dt = -1e307 p/m - q k, dq/dt = p/m (m = 1, k = 1): the damping dominates.
        let damped = [-1e307, -1.0, 1.0, 0.0];
        let scale = TimeScale::of_jacobian(&damped, 2, 2, &names).unwrap();
        assert!((scale.seconds / 1e-307 - 1.0).abs() < 1e-15);
        assert_eq!(scale.to_string(), "1e-307 s, in 'p_mass'");
        // Undamped, m = 1e-4 and k = 1: ω = 100 rad/s between the two states.
        let swinging = [0.0, -1.0, 1e4, 0.0];
        let scale = TimeScale::of_jacobian(&swinging, 2, 2, &names).unwrap();
        assert_eq!(scale.seconds, 1e-2);
        assert_eq!(scale.to_string(), "1e-2 s, in 'p_mass' and 'q_spring'");
        assert_eq!(TimeScale::of_jacobian(&[0.0; 4], 2, 2, &names), None);
        let modal = [Complex64::new(-3.0, 4.0), Complex64::new(0.0, 0.0)];
        assert_eq!(
            TimeScale::of_eigenvalues(&modal).map(|s| s.to_string()),
            Some("2e-1 s".to_string())
        );
    }
}
