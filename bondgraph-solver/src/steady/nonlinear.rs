//! The steady-state search of a nonlinear mode: it integrates until the motion settles, and
//! so finds the stable state a trajectory reaches, or steady motion (a constant drift).
//!
//! The search does not wait out the settling by integration where it need not: after each
//! window it solves `f(x*, u) = 0` by Newton's method from the state reached (the
//! `Polish`), and ends at `x*` once the trajectory is shown to be in `x*`'s basin: the same
//! `x*` from two successive windows, stable, the motion between them following the
//! linearisation at `x*`, and no guard on the way. A tank's 30 s time constant then costs a
//! few windows instead of 36 time constants of integration, and the state read is the exact
//! equilibrium, not the last integrated one. Whatever the rule does not vouch for (a drift,
//! an integrator, an unstable point, a trajectory still crossing between wells) is
//! integrated as before, so the search never ends at a state the trajectory would not reach.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use super::continuation::Anchor;
use super::{Search, Steady, SteadyError, SteadySettings};
use crate::hybrid::Stepper;
use crate::nonlinear::NonlinearNumeric;
use crate::numeric::NumericMode;
use crate::ode::Tolerances;

/// The steady state a simulation of a nonlinear mode settles in: integrated over windows
/// until `f` stops changing (the change of `f` over a window would move the state by less
/// than 1e-9 of its size), so that steady motion (a constant drift) counts.
///
/// The windows come from the mode's linearisation where the stepper stands: the first is its
/// fastest time scale, and each next one doubles, up to the settling horizon of the
/// linearisation at the point reached ([`crate::steady::settling_horizon`]: the slowest
/// decaying time constant times [`SteadySettings::settling_time_constants`]), so that the
/// windows reach a tank's 30 s time constant from its pipe's milliseconds in a few dozen
/// doublings, and a window never outgrows the motion it waits for (a window of days would
/// hold rounding in `f` against a millionth of the state's size). The search is bounded by
/// the settings' segments and mode changes and the simulator's steps, not by a time.
///
/// After each window the `Polish` may end the search at the equilibrium the trajectory is
/// shown to settle in, read there exactly.
///
/// # Errors
/// As [`crate::steady::steady_state`].
pub fn steady_by_integration(
    mut stepper: Stepper<'_, '_>,
    settings: &SteadySettings,
    own: Tolerances,
) -> Result<Steady, SteadyError> {
    // Whether the simulator's own tolerances are in force (see `SEARCH_TOLERANCES`).
    let mut finishing = settings.tolerances == own;
    let mut search = Search::new(settings);
    let mut scales = TimeScales::at(&stepper, settings)?;
    let mut window = scales.fastest;
    // Time spent in this mode since the search entered it.
    let mut waited = 0.0;
    let mut polish = Polish::entering(&stepper);
    loop {
        search.within_budget(&stepper)?;
        if at_rest(&stepper, settings) {
            let x = stepper.state().to_vec();
            let scale = polish.scale(&x);
            return Ok(settled_at(stepper, &search, settings, &x, Some(scale)));
        }
        let (u, _) = stepper.inputs_at(stepper.time());
        let before = stepper.mode().derivative(stepper.state(), &u);
        let Some(length) = window.or_else(|| drift_into_guard(&stepper)) else {
            // f does not depend on the state here, and the motion reaches no guard: it is
            // already steady.
            return Ok(settled(stepper, &search, settings));
        };
        let target = stepper.time() + length;
        if search.advance(&mut stepper, target)? {
            scales = TimeScales::at(&stepper, settings)?;
            window = scales.fastest;
            waited = 0.0;
            polish = Polish::entering(&stepper);
            continue;
        }
        waited += length;
        if let Some(equilibrium) = polish.after_window(&stepper, length, settings) {
            let scale = polish.scale(&equilibrium);
            return Ok(settled_at(
                stepper,
                &search,
                settings,
                &equilibrium,
                Some(scale),
            ));
        }
        let x = stepper.state().to_vec();
        let after = stepper.mode().derivative(&x, &u);
        let change: f64 = before
            .iter()
            .zip(&after)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let size: f64 = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
        // Past two settling horizons (every decaying component at e^-72 of its start), what
        // is left of a change in f is the integrator's error amplified by the fast modes
        // (a relative error of 1e-13 in a state moves the rate of a state 1e5 times faster
        // by more than the strict test allows): a looser test then.
        let long_enough = scales.settling.is_some_and(|h| waited >= 2.0 * h);
        let allowed = if long_enough { 1e-6 } else { 1e-9 };
        if change * length <= allowed * size + 1e-300 {
            if finishing {
                return Ok(settled(stepper, &search, settings));
            }
            // Settled at the search's tolerances: one more window at the simulator's own,
            // read at its end.
            stepper.set_tolerances(own);
            finishing = true;
            window = Some(length);
            continue;
        }
        // Still moving: wait longer, on the time scales of the point reached.
        scales = TimeScales::at(&stepper, settings)?;
        let mut next = 2.0 * length;
        if let Some(horizon) = scales.settling {
            next = next.min(horizon);
        }
        window = Some(scales.fastest.map_or(next, |fastest| next.max(fastest)));
    }
}

/// How long to simulate a motion whose rates do not depend on the state (a block stuck to a
/// belt, stretching a hardening spring) before looking again: twice the time to the first
/// guard below zero and rising, at its rate now (the event stops the advance where it
/// happens; a guard that bends away is looked at again, within the search's budget). `None`
/// when no guard rises: the motion is steady.
fn drift_into_guard(stepper: &Stepper<'_, '_>) -> Option<f64> {
    let mode = stepper.mode();
    if let Some(nl) = &mode.nonlinear {
        // Rates of rounding size (within [`AT_REST`] of their terms) do not move.
        let input = tape_input(stepper);
        let f = nl.f.eval_alloc(&input);
        let magnitude = nl.f_magnitude.eval_alloc(&input);
        if f.iter()
            .zip(&magnitude)
            .all(|(r, m)| r.abs() <= AT_REST * m)
        {
            return None;
        }
    }
    let (u, rate) = stepper.inputs_at(stepper.time());
    let x = stepper.state();
    mode.guards
        .iter()
        .filter_map(|guard| {
            let value = guard.row.eval(x, &u, &rate);
            let slope = mode.row_rate(&guard.row, x, &u, &rate);
            (value < 0.0 && slope > 0.0).then(|| -2.0 * value / slope)
        })
        .filter(|t| t.is_finite())
        .reduce(f64::min)
}

/// A nonlinear mode's tape input where the stepper stands: `[x, u, u̇ = 0]` (a steady search
/// holds its inputs constant).
fn tape_input(stepper: &Stepper<'_, '_>) -> Vec<f64> {
    let (u, _) = stepper.inputs_at(stepper.time());
    crate::nonlinear::tape_input(stepper.state(), &u, &vec![0.0; u.len()])
}

/// A rate within this fraction of the magnitude of its terms is zero: rounding.
const AT_REST: f64 = 1e-12;

/// Whether the stepper's state is a stable equilibrium where it stands: every rate zero to
/// the rounding of its terms ([`AT_REST`] of their magnitude), and every eigenvalue of the
/// Jacobian there decaying. Two heated blocks with the heaters off in a room at their
/// temperature radiate `σ((T + 0)^4 - T^4)`, zero but for rounding of its 0.4 W terms: the
/// state then moves by rounding (1e-16 K/s), which no test of its motion relative to its own
/// size (1e-13 K) sees settle, and the search ran out of its steps.
fn at_rest(stepper: &Stepper<'_, '_>, settings: &SteadySettings) -> bool {
    let Some(nl) = stepper.mode().nonlinear.as_ref() else {
        return false;
    };
    let input = tape_input(stepper);
    let n = nl.n;
    let f = nl.f_and_jacobian.eval_alloc(&input);
    let magnitude = nl.f_magnitude.eval_alloc(&input);
    let still = f[..n]
        .iter()
        .zip(&magnitude)
        .all(|(r, size)| r.is_finite() && r.abs() <= AT_REST * size);
    if !still || f[n..].iter().any(|v| !v.is_finite()) {
        return false;
    }
    let jacobian = DMatrix::from_row_slice(n, n, &f[n..n + n * n]);
    jacobian_eigenvalues(&jacobian)
        .is_ok_and(|values| values.iter().all(|v| v.re < -settings.zero_eigenvalue))
}

/// The eigenvalues of a mode's Jacobian, in no particular order: in closed form for one or
/// two states ([`crate::linalg::closed_form_eigenvalues`]), else refined
/// ([`crate::analysis::eigenvalues`]). The search asks after every window.
pub(super) fn jacobian_eigenvalues(
    jacobian: &DMatrix<f64>,
) -> Result<Vec<Complex64>, crate::analysis::AnalysisError> {
    match crate::linalg::closed_form_eigenvalues(jacobian) {
        Some(values) => Ok(values),
        None => crate::analysis::eigenvalues(jacobian),
    }
}

/// A mode's time scales where the stepper stands: of a linear mode's matrix, or of a
/// nonlinear mode's linearisation there.
struct TimeScales {
    /// `1/max|λ|`; `None` when no rate depends on the state (nothing to wait for).
    fastest: Option<f64>,
    /// The settling horizon, [`crate::steady::settling_horizon`]; `None` when nothing decays.
    settling: Option<f64>,
}

impl TimeScales {
    /// # Errors
    /// When the linearisation shows no finite time scale but has entries that are not
    /// finite (every rate infinitely sensitive there): nothing says how long to wait.
    fn at(stepper: &Stepper<'_, '_>, settings: &SteadySettings) -> Result<Self, SteadyError> {
        let mode = stepper.mode();
        let mut singular = false;
        let eigenvalues = match &mode.nonlinear {
            Some(nl) => {
                let n = nl.n;
                let out = nl.f_and_jacobian.eval_alloc(&tape_input(stepper));
                // An entry that is not finite (a square root's slope at zero) says nothing
                // of the time scales the others show.
                let finite: Vec<f64> = out[n..n + n * n]
                    .iter()
                    .map(|&v| {
                        singular |= !v.is_finite();
                        if v.is_finite() { v } else { 0.0 }
                    })
                    .collect();
                let jacobian = DMatrix::from_row_slice(n, n, &finite);
                if singular {
                    sketched_eigenvalues(&jacobian).unwrap_or_else(|| rates(&jacobian))
                } else {
                    jacobian_eigenvalues(&jacobian).unwrap_or_else(|_| rates(&jacobian))
                }
            }
            None => mode.propagator.eigenvalues().to_vec(),
        };
        let fastest = eigenvalues
            .iter()
            .map(|v| v.norm())
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        if fastest == 0.0 && singular {
            return Err(crate::steady::not_steady(
                stepper,
                "its linearisation where the search entered it has no finite time scale, so \
                 nothing says how long to wait"
                    .into(),
            ));
        }
        Ok(Self {
            fastest: (fastest > 0.0).then(|| 1.0 / fastest),
            settling: crate::steady::settling_horizon(
                &eigenvalues,
                settings.settling_time_constants,
                settings.zero_eigenvalue,
            ),
        })
    }
}

/// The Schur iterations [`sketched_eigenvalues`] takes at most per state: LAPACK's budget
/// (`dhseqr`: 30 per eigenvalue, for at least 10).
const SKETCH_ITERATIONS_PER_STATE: usize = 30;

/// The eigenvalues of a Jacobian whose entries that were not finite were set to zero (a
/// square root's slope at zero, where a tank starts empty): a sketch of the time scales
/// whose accuracy does not matter, so the balanced matrix's real Schur form within a small
/// budget. The refined eigendecomposition ([`crate::analysis::eigenvalues`]) may spend
/// thousands of iterations on such a matrix (a zero eigenvalue where the slope was lost; its
/// Francis iteration stalls on the symmetrised form), a millisecond a steady row. `None`
/// when the iteration does not converge.
fn sketched_eigenvalues(jacobian: &DMatrix<f64>) -> Option<Vec<Complex64>> {
    let n = jacobian.nrows();
    let (balanced, _) = crate::linalg::balance(jacobian);
    let budget = SKETCH_ITERATIONS_PER_STATE * n.max(10);
    nalgebra::Schur::try_new(balanced, f64::EPSILON, budget)
        .map(|schur| schur.complex_eigenvalues().iter().copied().collect())
}

/// Rates a Jacobian shows without its eigenvalues (when their iteration fails): each state's
/// own rate `J_ii` (decaying when negative), and each pair's oscillation `√|J_ij J_ji|`; both
/// in 1/s whatever the states' units.
fn rates(jacobian: &DMatrix<f64>) -> Vec<Complex64> {
    let n = jacobian.nrows();
    let mut values = Vec::new();
    for i in 0..n {
        values.push(Complex64::new(jacobian[(i, i)], 0.0));
        for j in i + 1..n {
            let swing = (jacobian[(i, j)] * jacobian[(j, i)]).abs().sqrt();
            values.push(Complex64::new(0.0, swing));
        }
    }
    values
}

/// The steady state where the stepper stands.
fn settled(stepper: Stepper<'_, '_>, search: &Search<'_>, settings: &SteadySettings) -> Steady {
    let x = stepper.state().to_vec();
    settled_at(stepper, search, settings, &x, None)
}

/// The steady state `x` of the stepper's mode, judged reached at the stepper's time: the
/// outputs and their rates read at `x`. `equilibrium` holds each state's scale where `x` is
/// a stable equilibrium shown to be reached: it is then an [`Anchor`], path-dependent where
/// the search left a mode on the way or the mode has guards (whether a transient reaches a
/// guard depends on the parameters along the whole path, not at the equilibrium alone; a
/// contact stuck at rest whose holding force peaked just below its breakaway on the way
/// breaks away at values a hair apart).
fn settled_at(
    stepper: Stepper<'_, '_>,
    search: &Search<'_>,
    settings: &SteadySettings,
    x: &[f64],
    equilibrium: Option<Vec<f64>>,
) -> Steady {
    let mode = stepper.mode().clone();
    let (u, rate) = stepper.inputs_at(stepper.time());
    let anchor = equilibrium
        .filter(|_| rate.iter().all(|r| *r == 0.0))
        .map(|scale| Anchor {
            mode: mode.mode.clone(),
            state: x.to_vec(),
            inputs: u.clone(),
            scale,
            time: stepper.time(),
            path_dependent: stepper.event_count() > 0 || !mode.guards.is_empty(),
            guards_below: mode
                .guards
                .iter()
                .map(|g| g.row.eval(x, &u, &rate) < 0.0)
                .collect(),
        });
    Steady {
        anchor,
        work: search.work(&stepper),
        events: if settings.events {
            stepper.events()
        } else {
            Vec::new()
        },
        ..steady_at(&mode, x, &u, &rate, stepper.time())
    }
}

/// Newton's method on a nonlinear mode's `f(x, u) = 0` from `input` (`[x, u, u̇]`, the tapes'
/// order), at most `iterations` steps: converged when every step is below [`POLISH_STEP`] of
/// its state's `scale` at the current point (or below the smallest normal double). The
/// equilibrium and the Jacobian there, or `None` when it does not converge or meets a value
/// that is not finite. The search's polish and the continuation of an anchor share it.
pub(super) fn newton(
    nl: &NonlinearNumeric,
    mut input: Vec<f64>,
    iterations: usize,
    scale: &dyn Fn(&[f64]) -> Vec<f64>,
) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let n = nl.n;
    let tape = &nl.f_and_jacobian;
    let mut scratch = tape.scratch();
    let mut out = vec![0.0; tape.output_count()];
    let mut converged = false;
    for _ in 0..iterations {
        tape.eval(&input, &mut scratch, &mut out);
        if out.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let jacobian = DMatrix::from_row_slice(n, n, &out[n..n + n * n]);
        let f = DVector::from_column_slice(&out[..n]);
        let step = jacobian.lu().solve(&(-f))?;
        if step.iter().any(|d| !d.is_finite()) {
            return None;
        }
        let scale = scale(&input[..n]);
        converged = step
            .iter()
            .zip(&scale)
            .all(|(d, s)| d.abs() <= POLISH_STEP * s || d.abs() <= f64::MIN_POSITIVE);
        for (x, d) in input.iter_mut().zip(step.iter()) {
            *x += d;
        }
        if converged {
            break;
        }
    }
    if !converged {
        return None;
    }
    tape.eval(&input, &mut scratch, &mut out);
    if out.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let jacobian = DMatrix::from_row_slice(n, n, &out[n..n + n * n]);
    Some((input[..n].to_vec(), jacobian))
}

/// The steady state `x` of `mode` at constant inputs `u` (rates `rate`), judged reached at
/// `time`: the outputs and their rates read at `x`, the full state rebuilt; no work, events
/// or anchor (the caller adds its own).
pub(super) fn steady_at(
    mode: &NumericMode,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
    time: f64,
) -> Steady {
    let drift = mode
        .outputs
        .iter()
        .map(|r| mode.row_rate(r, x, u, rate))
        .collect();
    super::read_at(mode, x, u, rate, drift, time)
}

/// Newton iterations a polish takes at most: from a state the integration brought near an
/// equilibrium, Newton's method converges quadratically in a handful; one that needs more is
/// far from it, and integrating on is the answer.
pub const POLISH_ITERATIONS: usize = 30;

/// A Newton step smaller than this fraction of each state's scale is the equilibrium to
/// double precision (the next step would be below rounding).
const POLISH_STEP: f64 = 1e-12;

/// How closely the motion over a window must follow the linearisation at the candidate
/// equilibrium: the trajectory's end may differ from the predicted end by this fraction of
/// the predicted motion.
const LINEAR_AGREEMENT: f64 = 0.1;

/// Two polished equilibria closer than this fraction of each state's scale are the same.
const SAME_EQUILIBRIUM: f64 = 1e-9;

/// Points on the predicted path from the state reached to the equilibrium at which the
/// guards are looked at, in doubling times from the mode's fastest time scale.
const GUARD_LOOKS: usize = 64;

/// A fraction of the terms of a guard within which it is at its threshold (as the events'
/// location judges it).
pub(super) const GUARD_ROUNDING: f64 = 1e-9;

/// The Newton polish of a nonlinear mode's steady-state search: after each window, Newton's
/// method on `f(x*, u) = 0` from the state reached, and a rule for when `x*` is the state the
/// trajectory settles in, so that the search ends there instead of integrating on.
///
/// `x*` is accepted only when all of these hold:
/// - Newton converged ([`POLISH_ITERATIONS`], steps below [`POLISH_STEP`] of each state's
///   scale, the largest magnitude it had since the mode was entered);
/// - the Jacobian at `x*` is stable, every eigenvalue with `Re λ < -zero_eigenvalue`: an
///   integrator (a free body's position, steady drift) or an unstable point is left to the
///   integration;
/// - the previous window's polish found the same `x*`, and the motion over this window
///   followed the linearisation at `x*`: with `e = x - x*` at the two window ends, `e₁`
///   differs from `e^{J L} e₀` by at most [`LINEAR_AGREEMENT`] of the predicted motion
///   `e₀ - e^{J L} e₀`, and `|e₁| < |e₀|`. Where the motion follows the linearisation the
///   nonlinear remainder is small against the linear part, and a stable linear part then
///   draws the state in: it is in `x*`'s basin. A Newton solve from an early state may land
///   on another equilibrium than the one the trajectory heads for (the other well of a
///   double well); the motion then does not follow that equilibrium's linearisation, or the
///   next window's polish lands elsewhere;
/// - no guard of the mode changes sign along the predicted path `x* + e^{J t} e₁` (looked at
///   in doubling times from the fastest time scale to the settling horizon), and none is at
///   its threshold at `x*`: the state stays in the mode.
///
/// Otherwise the integration goes on as before, so the search never ends at a state the
/// trajectory would not reach; the outputs are then read at `x*`, not at the last state
/// integrated.
struct Polish {
    /// Per state, the largest magnitude seen at a window's end since the mode was entered.
    reach: Vec<f64>,
    /// The last window's candidate.
    previous: Option<Candidate>,
}

/// An equilibrium polished from the state at a window's end.
struct Candidate {
    point: Vec<f64>,
    /// The state polished from.
    from: Vec<f64>,
    jacobian: DMatrix<f64>,
}

impl Polish {
    /// A polish of the mode the stepper has just entered, with a candidate from its state
    /// there.
    fn entering(stepper: &Stepper<'_, '_>) -> Self {
        let mut polish = Self {
            reach: stepper.state().iter().map(|v| v.abs()).collect(),
            previous: None,
        };
        polish.previous = polish.candidate(stepper);
        polish
    }

    /// After a window of `length` seconds: the equilibrium the trajectory is shown to settle
    /// in, if the rule of `Polish` accepts one.
    fn after_window(
        &mut self,
        stepper: &Stepper<'_, '_>,
        length: f64,
        settings: &SteadySettings,
    ) -> Option<Vec<f64>> {
        for (r, v) in self.reach.iter_mut().zip(stepper.state()) {
            *r = r.max(v.abs());
        }
        let now = self.candidate(stepper);
        let before = std::mem::replace(&mut self.previous, now);
        let (before, now) = (before?, self.previous.as_ref()?);
        let scale = self.scale(&now.point);
        let same = before
            .point
            .iter()
            .zip(&now.point)
            .zip(&scale)
            .all(|((a, b), s)| (a - b).abs() <= SAME_EQUILIBRIUM * s);
        if !same {
            return None;
        }
        let flow = crate::linalg::expm(&(&now.jacobian * length))?;
        let deviation = |x: &[f64]| {
            DVector::from_iterator(x.len(), x.iter().zip(&now.point).map(|(x, p)| x - p))
        };
        let (start, end) = (deviation(&before.from), deviation(&now.from));
        let predicted = &flow * &start;
        let norm = |v: &DVector<f64>| weighted(v.as_slice(), &scale);
        let motion = norm(&(&start - &predicted));
        let mismatch = norm(&(&end - &predicted));
        let follows = motion > 0.0 && mismatch <= LINEAR_AGREEMENT * motion;
        if !(follows && norm(&end) < norm(&start)) {
            return None;
        }
        let eigenvalues = jacobian_eigenvalues(&now.jacobian).ok()?;
        let stable = eigenvalues.iter().all(|v| v.re < -settings.zero_eigenvalue);
        (stable && self.guards_clear(stepper, now, &eigenvalues, settings))
            .then(|| now.point.clone())
    }

    /// Each state's scale: the largest of its magnitude at `point` and along the way.
    fn scale(&self, point: &[f64]) -> Vec<f64> {
        self.reach
            .iter()
            .zip(point)
            .map(|(r, p)| r.max(p.abs()))
            .collect()
    }

    /// Newton's method from the stepper's state; the equilibrium if it converged (whether it
    /// is stable is asked only of one the motion is seen to follow: eigenvalues cost more
    /// than the Newton solve).
    fn candidate(&self, stepper: &Stepper<'_, '_>) -> Option<Candidate> {
        let nl = stepper.mode().nonlinear.as_ref()?;
        let (point, jacobian) = newton(
            nl,
            tape_input(stepper),
            POLISH_ITERATIONS,
            &|x: &[f64]| self.scale(x),
        )?;
        Some(Candidate {
            from: stepper.state().to_vec(),
            point,
            jacobian,
        })
    }

    /// Whether no guard of the mode changes sign along the path the linearisation predicts
    /// from the stepper's state to `candidate`, nor is at its threshold there.
    fn guards_clear(
        &self,
        stepper: &Stepper<'_, '_>,
        candidate: &Candidate,
        eigenvalues: &[Complex64],
        settings: &SteadySettings,
    ) -> bool {
        let mode = stepper.mode();
        if mode.guards.is_empty() {
            return true;
        }
        let (u, rate) = stepper.inputs_at(stepper.time());
        let here = stepper.state();
        let signs: Vec<bool> = mode
            .guards
            .iter()
            .map(|g| g.row.eval(here, &u, &rate) < 0.0)
            .collect();
        let on_side = |x: &[f64]| {
            mode.guards
                .iter()
                .zip(&signs)
                .all(|(g, &below)| (g.row.eval(x, &u, &rate) < 0.0) == below)
        };
        let at = &candidate.point;
        let clear_of_threshold = mode.guards.iter().all(|g| {
            g.row.eval(at, &u, &rate).abs() > GUARD_ROUNDING * g.row.magnitude(at, &u, &rate)
        });
        if !(clear_of_threshold && on_side(at)) {
            return false;
        }
        let fastest = eigenvalues.iter().map(|v| v.norm()).fold(0.0, f64::max);
        let Some(horizon) = crate::steady::settling_horizon(
            eigenvalues,
            settings.settling_time_constants,
            settings.zero_eigenvalue,
        ) else {
            return false;
        };
        let deviation = DVector::from_iterator(here.len(), here.iter().zip(at).map(|(x, p)| x - p));
        let mut t = 1.0 / fastest;
        // The flow over each doubled time is the last one squared; only the last look, cut
        // at the horizon, takes an exponential of its own.
        let mut flow = None;
        for _ in 0..GUARD_LOOKS {
            let doubled = flow.as_ref().filter(|_| t < horizon).map(|f| f * f);
            flow = doubled.or_else(|| crate::linalg::expm(&(&candidate.jacobian * t)));
            let Some(flow) = &flow else {
                return false;
            };
            let x: Vec<f64> = at
                .iter()
                .zip((flow * &deviation).iter())
                .map(|(p, e)| p + e)
                .collect();
            if !on_side(&x) {
                return false;
            }
            if t >= horizon {
                return true;
            }
            t = (2.0 * t).min(horizon);
        }
        false
    }
}

/// `max |vᵢ| / sᵢ` over the states with a scale (one without never moved from zero).
fn weighted(v: &[f64], scale: &[f64]) -> f64 {
    v.iter()
        .zip(scale)
        .filter(|(_, s)| **s > 0.0)
        .map(|(x, s)| x.abs() / s)
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two-tank rig's Jacobian with both tanks empty, the orifice's infinite slope set
    /// to zero: `[[0, -a, 0], [b, -c, -b], [0, a, 0]]` with `a = A_p/(ρ L_p) = 2.618e-8`,
    /// `b = ρ g/A = 981000`, `c = R₁₂ A_p/(ρ L_p) = 0.1309`. Its characteristic polynomial is
    /// `λ (λ² + c λ + 2 a b)`: `λ = 0` and `λ = (-c ± √(c² - 8 a b))/2`
    /// `= -0.06545 ± 0.2169826202717644 i`. The refined eigendecomposition's Francis iteration
    /// stalls on its symmetrised form; the sketch finds the values.
    #[test]
    fn the_sketch_finds_the_time_scales_of_an_empty_tank() {
        let (a, b, c) = (2.618e-8, 981000.0, 0.1309);
        let jacobian = DMatrix::from_row_slice(3, 3, &[0.0, -a, 0.0, b, -c, -b, 0.0, a, 0.0]);
        let mut values = sketched_eigenvalues(&jacobian).unwrap();
        values.sort_by(|x, y| x.im.total_cmp(&y.im));
        let imaginary = (8.0 * a * b - c * c).sqrt() / 2.0;
        let expected = [
            Complex64::new(-c / 2.0, -imaginary),
            Complex64::new(0.0, 0.0),
            Complex64::new(-c / 2.0, imaginary),
        ];
        for (value, expected) in values.iter().zip(&expected) {
            assert!((value - expected).norm() < 1e-12, "{values:?}");
        }
    }
}
