//! Guard crossings within one integrated step, bracketed on its dense output.
//!
//! An integrated step is looked at a few times (its dense output at a quarter, half,
//! three quarters and its end); a crossing is bracketed between two looks where a guard goes
//! from below zero to zero or above, and refined by Brent's method on the dense output. Two
//! ways a guard can be met between looks without a sign change at the looks, both first
//! found and fixed in the closed-form locator ([`crate::events::first_crossing`]), are
//! handled here the same way:
//!
//! - A guard that rises above zero and falls back between two looks (a contact's velocity
//!   touching the belt's for 34 µs of a 17 ms swing): below zero at both, it has a maximum
//!   between them, where its rate changes sign from rising to falling; the peak is found from
//!   the rates, and a peak at or above zero brackets the guard's first zero before it. That
//!   also keeps a bracket that ends above zero from holding two roots; a peak found below
//!   zero (one of several extrema) leaves such a bracket as it was, rather than losing it.
//! - A guard at zero (to rounding) that is falling when its mode is entered is left at once:
//!   it is armed then, as if seen below zero, or a dip shorter than the first look (a string
//!   that goes slack and is pulled taut again within a microsecond) would never arm it. Its
//!   first bracket then starts where it is below zero, found by halving towards the start,
//!   or Brent's method would find the zero it starts from.

use crate::events;

/// The guards' values and rates along the motion at one point.
#[derive(Clone, Debug, Default)]
pub(super) struct Look {
    pub values: Vec<f64>,
    pub rates: Vec<f64>,
}

/// The guards to arm at once at a segment's start: not armed yet, armed below zero (not
/// resting after a declined switch), at zero to rounding (`1e-9` of the size of their terms)
/// and falling. They are armed, their start value made negative, and they are returned as
/// armed at zero.
pub(super) fn arm_at_zero(
    start: &mut Look,
    magnitudes: &[f64],
    armed: &mut [bool],
    arm_below: &[f64],
) -> Vec<bool> {
    let mut from_zero = vec![false; armed.len()];
    for k in 0..armed.len() {
        let level = 1e-9 * magnitudes[k];
        if !armed[k] && arm_below[k] >= 0.0 && start.values[k] <= level && start.rates[k] < 0.0 {
            armed[k] = true;
            from_zero[k] = true;
            start.values[k] = start.values[k].min(-f64::MIN_POSITIVE);
        }
    }
    from_zero
}

/// How far from zero, in units of a guard's change over a step, every guard must stay at
/// both ends of the step for the step to be looked at only at its end ([`clear_of_zero`]).
const CLEAR_MARGIN: f64 = 2.0;

/// Whether every guard stays clear of zero over a step of `step` seconds, judged from the
/// looks at its start and end: on the same side of zero at both, each end farther from zero
/// than [`CLEAR_MARGIN`] times the change the ends show (the difference of the values plus
/// the step times each end's rate). A cubic through the ends' values and rates strays from
/// the values by at most 4/27 of the step times the rates, a seventh of that; a guard
/// clear of zero so is neither crossed nor touched between the looks, nor pulled below the
/// level that arms it, and the looks inside the step (and the dense output they need, three
/// evaluations of `f` for DOP853) are saved. A guard near zero or moving fast against its
/// distance from it is looked at as before.
pub(super) fn clear_of_zero(start: &Look, end: &Look, step: f64) -> bool {
    (0..start.values.len()).all(|k| {
        let (a, b) = (start.values[k], end.values[k]);
        let change = (b - a).abs() + step * (start.rates[k].abs() + end.rates[k].abs());
        a.signum() == b.signum()
            && a != 0.0
            && a.abs().min(b.abs()) > CLEAR_MARGIN * change
            && change.is_finite()
    })
}

/// The first crossing of an armed guard within a step, as `(guard, θ)` with `θ` the fraction
/// of the step, from the look at its start (`previous`, replaced by the last look taken) and
/// looks at `thetas`; `look(θ, out)` evaluates the guards on the dense output. Guards seen
/// below their `arm_below` level are armed. `from_zero` marks the guards armed at zero at the
/// start of this step, which is the start of their segment.
pub(super) fn first_crossing(
    previous: &mut Look,
    thetas: &[f64],
    armed: &mut [bool],
    arm_below: &[f64],
    from_zero: &[bool],
    mut look: impl FnMut(f64, &mut Look),
) -> Option<(usize, f64)> {
    let count = armed.len();
    let mut current = Look::default();
    let mut probe = Look::default();
    let mut theta_before = 0.0;
    for &theta in thetas {
        look(theta, &mut current);
        let mut found: Option<(usize, f64)> = None;
        for k in 0..count {
            if !(armed[k] && previous.values[k] < 0.0) {
                continue;
            }
            let mut bracket = (current.values[k] >= 0.0).then_some((theta, current.values[k]));
            if previous.rates[k] > 0.0 && current.rates[k] < 0.0 {
                // Rising at the first look and falling at the second: the guard's first
                // zero, if any, is before its peak.
                let peak = events::refine(
                    theta_before,
                    theta,
                    -previous.rates[k],
                    -current.rates[k],
                    |th| {
                        look(th, &mut probe);
                        -probe.rates[k]
                    },
                );
                look(peak, &mut probe);
                if probe.values[k] >= 0.0 {
                    bracket = Some((peak, probe.values[k]));
                }
                // (A peak below zero is not the last: the rates found one of several
                // extrema, and a guard at or above zero at the second look still crossed.)
            }
            let Some((end, value)) = bracket else {
                continue;
            };
            let (mut start, mut f_start) = (theta_before, previous.values[k]);
            if from_zero[k] && theta_before == 0.0 {
                let mut at = end;
                loop {
                    at *= 0.5;
                    look(at, &mut probe);
                    if probe.values[k] < 0.0 || at < f64::MIN_POSITIVE {
                        break;
                    }
                }
                if probe.values[k] >= 0.0 {
                    continue;
                }
                (start, f_start) = (at, probe.values[k]);
            }
            let root = events::refine(start, end, f_start, value, |th| {
                look(th, &mut probe);
                probe.values[k]
            });
            if found.is_none_or(|(_, r)| root < r) {
                found = Some((k, root));
            }
        }
        if found.is_some() {
            return found;
        }
        for k in 0..count {
            if current.values[k] < arm_below[k] {
                armed[k] = true;
            }
        }
        std::mem::swap(previous, &mut current);
        theta_before = theta;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Looks at `g(θ)` and its derivative `dg(θ)`, one guard.
    fn looker(g: impl Fn(f64) -> f64, dg: impl Fn(f64) -> f64) -> impl FnMut(f64, &mut Look) {
        move |th, out| {
            out.values = vec![g(th)];
            out.rates = vec![dg(th)];
        }
    }

    #[test]
    fn a_guard_is_clear_of_zero_only_far_from_it_against_its_change() {
        let look = |value: f64, rate: f64| Look {
            values: vec![value],
            rates: vec![rate],
        };
        // A speed of -0.1 m/s changing by 1e-4 m/s over the step: clear.
        assert!(clear_of_zero(&look(-0.1, 0.05), &look(-0.0999, 0.05), 1e-3));
        // The same guard approaching zero fast (1 m/s² for 0.05 s): looked at inside.
        assert!(!clear_of_zero(&look(-0.1, 1.0), &look(-0.05, 1.0), 0.05));
        // Rising and falling back between the looks (the dip above zero found by
        // `a_dip_above_zero_between_two_looks_is_found_before_its_peak`: -0.36 at the start,
        // -0.16 at the end, rates 1.2 and -0.8 per unit step): not clear.
        assert!(!clear_of_zero(&look(-0.36, 1.2), &look(-0.16, -0.8), 1.0));
        // On either side of zero, or at zero: not clear.
        assert!(!clear_of_zero(&look(-0.1, 0.0), &look(0.1, 0.0), 1e-3));
        assert!(!clear_of_zero(&look(0.0, 0.0), &look(-0.1, 0.0), 1e-3));
        // Above zero and far from it (a guard resting above its threshold): clear.
        assert!(clear_of_zero(&look(3.0, 0.0), &look(3.0, 0.0), 1e-3));
    }

    #[test]
    fn a_dip_above_zero_between_two_looks_is_found_before_its_peak() {
        // g = 1e-6 - (θ - 0.6)², above zero on (0.599, 0.601) only: negative at every
        // look, rising at 0.5 and falling at 0.75.
        let g = |th: f64| 1e-6 - (th - 0.6) * (th - 0.6);
        let dg = |th: f64| -2.0 * (th - 0.6);
        let mut previous = Look {
            values: vec![g(0.0)],
            rates: vec![dg(0.0)],
        };
        let mut armed = [true];
        let found = first_crossing(
            &mut previous,
            &[0.25, 0.5, 0.75, 1.0],
            &mut armed,
            &[0.0],
            &[false],
            looker(g, dg),
        );
        let (k, root) = found.expect("the dip is found");
        assert_eq!(k, 0);
        assert!((root - 0.599).abs() < 1e-12, "{root}");
    }

    #[test]
    fn a_crossing_past_a_peak_below_zero_is_still_found() {
        // g' = -(θ - 0.1)(θ - 0.3)(θ - r) with g(0) = -0.002: a maximum below zero at 0.1,
        // a minimum at 0.3, a maximum above zero at r, and falling but above zero at the
        // look at 1. Whichever extremum the rates lead to, the guard crosses zero before 1
        // (at r = 0.85 they led to the maximum below zero, and the crossing was lost).
        for r in [0.95, 0.9, 0.85] {
            let c = 0.4 + r;
            let d = 0.03 + 0.4 * r;
            let e = 0.03 * r;
            let g = move |th: f64| {
                -th.powi(4) / 4.0 + c / 3.0 * th.powi(3) - d / 2.0 * th * th + e * th - 0.002
            };
            let dg = move |th: f64| -(th - 0.1) * (th - 0.3) * (th - r);
            assert!(g(1.0) > 0.0 && dg(1.0) < 0.0 && g(0.1) < 0.0, "r = {r}");
            let root = {
                // The first zero, by bisection between the minimum and the maximum above 0.
                let (mut a, mut b) = (0.3, r);
                for _ in 0..200 {
                    let m = 0.5 * (a + b);
                    if g(m) < 0.0 { a = m } else { b = m }
                }
                b
            };
            let mut previous = Look {
                values: vec![g(0.0)],
                rates: vec![dg(0.0)],
            };
            let mut armed = [true];
            let found = first_crossing(
                &mut previous,
                &[1.0],
                &mut armed,
                &[0.0],
                &[false],
                looker(g, dg),
            );
            let (_, at) = found.unwrap_or_else(|| panic!("r = {r}: the crossing is lost"));
            assert!((at - root).abs() < 1e-12, "r = {r}: {at} against {root}");
        }
    }

    #[test]
    fn a_guard_falling_from_zero_is_armed_and_its_return_found() {
        // g = θ (θ - 0.01): zero at the start and falling, back at zero at θ = 0.01, before
        // the first look.
        let g = |th: f64| th * (th - 0.01);
        let dg = |th: f64| 2.0 * th - 0.01;
        let mut start = Look {
            values: vec![g(0.0)],
            rates: vec![dg(0.0)],
        };
        let mut armed = [false];
        let from_zero = arm_at_zero(&mut start, &[1.0], &mut armed, &[0.0]);
        assert_eq!((armed, from_zero.as_slice()), ([true], [true].as_slice()));
        let found = first_crossing(
            &mut start,
            &[0.25, 0.5, 0.75, 1.0],
            &mut armed,
            &[0.0],
            &from_zero,
            looker(g, dg),
        );
        let (_, root) = found.expect("the return is found");
        assert!((root - 0.01).abs() < 1e-15, "{root}");
    }

    #[test]
    fn a_guard_rising_from_zero_or_resting_is_not_armed_at_once() {
        let mut start = Look {
            values: vec![0.0, 0.0],
            rates: vec![1.0, -1.0],
        };
        let mut armed = [false, false];
        let from_zero = arm_at_zero(&mut start, &[1.0, 1.0], &mut armed, &[0.0, -1e-9]);
        assert_eq!(armed, [false, false]);
        assert_eq!(from_zero, [false, false]);
    }
}
