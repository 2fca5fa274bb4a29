//! Event location: the first time a guard function reaches zero from below.
//!
//! Within a segment every guard is a closed-form function of local time (a sum of complex
//! exponentials times polynomials, through [`Segment`]), so an event is found by bracketing
//! and then refined to machine precision; no step size limits the accuracy. The bracketing
//! samples follow the mode's own time scales: geometrically from a fraction of the fastest
//! time constant (a stiff tip settles in 1e-17 s), and finely enough to resolve every
//! oscillation while it lasts.
//!
//! A guard is *armed* once its function has been seen negative: a guard that is already
//! satisfied when a mode is entered (a velocity guard of a contact that just started to slip
//! from zero) only fires after it has been left and is reached again.
//!
//! # Complexity
//! `O(s · (n² + g))` for `s` samples (typically a hundred), `n` states and `g` guards, plus a
//! few dozen evaluations per refinement.

use num_complex::Complex64;

use crate::numeric::NumericMode;
use crate::propagate::Segment;

/// A guard reaching zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The guard's index in the mode.
    pub guard: usize,
    /// Local time of the crossing.
    pub tau: f64,
}

/// Bracketing samples over `(0, length]` for a mode with these eigenvalues: each decaying
/// time scale `1/|λ|` sampled geometrically while it is active (from 0.02 to 40 time
/// constants), every oscillation sixteen times a period while it lasts, and the whole
/// segment uniformly.
pub fn sample_times(values: &[Complex64], length: f64) -> Vec<f64> {
    const MAX_SAMPLES: usize = 20_000;
    let mut times = Vec::with_capacity(96);
    for v in values {
        let rate = v.norm();
        if rate == 0.0 || !rate.is_finite() {
            continue;
        }
        if v.re < 0.0 {
            let scale = 1.0 / rate;
            let mut t = 0.02 * scale;
            let end = (40.0 / -v.re).min(length);
            while t < end {
                times.push(t);
                t *= 1.8;
            }
        }
        if v.im != 0.0 {
            let spacing = 2.0 * std::f64::consts::PI / v.im.abs() / 16.0;
            let horizon = if v.re < 0.0 {
                (40.0 / -v.re).min(length)
            } else {
                length
            };
            let count = ((horizon / spacing) as usize).min(MAX_SAMPLES / 2);
            times.extend((1..=count).map(|k| k as f64 * spacing));
        }
    }
    let uniform = length / 32.0;
    times.extend((1..32).map(|k| k as f64 * uniform));
    times.push(length);
    times.retain(|t| *t > 0.0 && *t <= length);
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// The first crossing of an armed guard in `(0, length]`, arming guards seen negative.
///
/// The inputs are `u₀ + u₁ τ` over the segment.
pub fn first_crossing(
    mode: &NumericMode,
    segment: &mut Segment<'_>,
    u0: &[f64],
    u1: &[f64],
    length: f64,
    armed: &mut [bool],
) -> Option<Crossing> {
    if mode.guards.is_empty() || length <= 0.0 {
        return None;
    }
    let n = segment.dimension();
    let mut x = vec![0.0; n];
    let mut u = vec![0.0; u0.len()];
    // In eigen-coordinates each guard is Re(Σ_j c_j z_j(τ)) + a + b τ with c = G V,
    // a = H u₀ + R u₁ + k and b = H u₁: no change of coordinates per evaluation.
    let modal: Option<Vec<(Vec<Complex64>, f64, f64)>> = segment.vectors().map(|v| {
        mode.guards
            .iter()
            .map(|g| {
                let c = (0..n)
                    .map(|j| (0..n).map(|i| v[(i, j)] * g.row.state[i]).sum())
                    .collect();
                let a = crate::numeric::dot(&g.row.input, u0)
                    + crate::numeric::dot(&g.row.rate, u1)
                    + g.row.constant;
                (c, a, crate::numeric::dot(&g.row.input, u1))
            })
            .collect()
    });
    let mut evaluate = |segment: &mut Segment<'_>, tau: f64, values: &mut Vec<f64>| {
        values.clear();
        if let Some(guards) = &modal
            && let Some(z) = segment.modal_state(tau)
        {
            values.extend(guards.iter().map(|(c, a, b)| {
                let mut sum = a + b * tau;
                for (cj, zj) in c.iter().zip(z) {
                    sum += cj.re * zj.re - cj.im * zj.im;
                }
                sum
            }));
            return;
        }
        segment.state_into(tau, &mut x);
        for (k, slot) in u.iter_mut().enumerate() {
            *slot = u0[k] + u1[k] * tau;
        }
        values.extend(mode.guards.iter().map(|g| g.row.eval(&x, &u, u1)));
    };
    let mut previous = Vec::with_capacity(mode.guards.len());
    evaluate(segment, 0.0, &mut previous);
    // An armed guard already at zero fires at once (an event exactly at a breakpoint).
    if let Some(i) = (0..previous.len()).find(|&i| armed[i] && previous[i] >= 0.0) {
        return Some(Crossing { guard: i, tau: 0.0 });
    }
    for (i, value) in previous.iter().enumerate() {
        if *value < 0.0 {
            armed[i] = true;
        }
    }
    let times = sample_times(mode.propagator.eigenvalues(), length);
    let mut current = Vec::with_capacity(mode.guards.len());
    let mut previous_tau = 0.0;
    for &tau in &times {
        evaluate(segment, tau, &mut current);
        let mut best: Option<Crossing> = None;
        for i in 0..current.len() {
            if armed[i] && previous[i] < 0.0 && current[i] >= 0.0 {
                let mut values = Vec::with_capacity(current.len());
                let root = refine(previous_tau, tau, previous[i], current[i], |t| {
                    evaluate(segment, t, &mut values);
                    values[i]
                });
                if best.is_none_or(|b| root < b.tau) {
                    best = Some(Crossing {
                        guard: i,
                        tau: root,
                    });
                }
            }
        }
        if best.is_some() {
            return best;
        }
        for i in 0..current.len() {
            if current[i] < 0.0 {
                armed[i] = true;
            }
        }
        std::mem::swap(&mut previous, &mut current);
        previous_tau = tau;
    }
    None
}

/// Refines a bracket `[a, b]` with `f(a) < 0 <= f(b)` by Illinois-modified regula falsi with a
/// bisection safeguard; returns the smallest `τ` found with `f(τ) >= 0`, to within a few ulps.
fn refine(mut a: f64, mut b: f64, mut fa: f64, mut fb: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    // b stays on the non-negative side, a on the negative side.
    let mut side = 0i32;
    for _ in 0..200 {
        let width = b - a;
        if width <= 4.0 * f64::EPSILON * b.abs().max(f64::MIN_POSITIVE) {
            break;
        }
        let mut c = if fb - fa != 0.0 {
            b - fb * (b - a) / (fb - fa)
        } else {
            0.5 * (a + b)
        };
        // Stay well inside the bracket; fall back to bisection when interpolation stalls.
        let margin = 0.01 * width;
        if !(c > a + margin && c < b - margin) {
            c = 0.5 * (a + b);
        }
        let mut fc = f(c);
        if !fc.is_finite() {
            c = 0.5 * (a + b);
            fc = f(c);
        }
        if fc >= 0.0 {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refine_finds_a_root_to_machine_precision() {
        // e^{-t} - 0.3 = 0 at t = ln(1/0.3), written as a rising function.
        let f = |t: f64| 0.3 - (-t).exp();
        let root = refine(0.0, 5.0, f(0.0), f(5.0), f);
        assert!((root - (1.0f64 / 0.3).ln()).abs() < 1e-15);
        assert!(f(root) >= 0.0);
    }

    #[test]
    fn samples_cover_stiff_and_oscillating_scales() {
        let times = sample_times(
            &[Complex64::new(-2.5e17, 0.0), Complex64::new(-0.1, 10.0)],
            1.0,
        );
        assert!(times[0] <= 0.05 / 2.5e17);
        // The stiff scale is sampled from 0.02 to 40 time constants, then left alone.
        let stiff = times.iter().filter(|t| **t < 1e-15).count();
        assert!((8..=16).contains(&stiff), "{stiff}");
        assert_eq!(*times.last().unwrap(), 1.0);
        // An oscillation of period 2π/10 is sampled at least sixteen times a period.
        let period = 2.0 * std::f64::consts::PI / 10.0;
        let gaps = times
            .windows(2)
            .filter(|w| w[0] > 1e-3)
            .map(|w| w[1] - w[0]);
        assert!(gaps.fold(0.0, f64::max) <= period / 16.0 + 1e-12);
    }
}
