//! Steady states continued to nearby parameter values, without simulating again.
//!
//! A fit asks for the steady state of the same row at parameter values a hair apart: a
//! finite-difference Jacobian moves each parameter by a hundred-thousandth of its range, and a
//! descent near its optimum takes steps as small. Where the steady-state search ended at an
//! isolated, stable equilibrium `x*` of a nonlinear mode without guards (nothing can switch),
//! never having left it, the steady state at the nearby values is the equilibrium on the same
//! branch: Newton's
//! method on `f(x, u; p') = 0` from `x*(p)` converges to `x*(p')` in two or three iterations,
//! where the search integrates the whole transient again (a tank filling from empty: hundreds
//! of steps).
//!
//! That the trajectory from the row's start still reaches the continued equilibrium follows
//! from continuity: `x*` is hyperbolic and stable, so it and its basin move continuously with
//! the parameters, and the start, inside the basin at `p`, stays inside at `p'` close enough
//! to `p`. The continuation checks what it can: Newton converges, the point is stable, and
//! it moved little (a fraction [`MOST_MOVED`] of each state's scale, so a jump to another
//! branch is refused).
//!
//! A mode with guards is not continued to new trial values: whether the transient reaches a
//! guard depends on the parameters along the whole path (a stuck contact whose holding force
//! peaks just below its breakaway on the way breaks away at values a hair apart), which the
//! equilibrium alone does not tell. Such an equilibrium (its anchor is
//! [`Anchor::path_dependent`]) is continued only for a finite difference ([`continue_branch`]):
//! a Jacobian's column is then the derivative on the branch the row settled on, the slope a
//! descent follows, where a fresh search across a switch within the step would give the
//! whole jump over a hundred-thousandth of a range. The residuals a fit is judged by, its
//! trial values', are always simulated.
//!
//! What "close enough" means is the caller's: a fit continues only within a small radius of
//! the values a search was simulated at, never from one continued point to the next
//! ([`Anchor`]s come only from simulations).
//!
//! The state found is the equilibrium to double precision, as the search's own Newton polish
//! gives it ([`super`]), so a continued prediction agrees with a simulated one
//! to rounding.
//!
//! A linear mode's steady state is its asymptote, exact from the modal form: the decaying
//! components at their equilibria, the integrators (zero eigenvalues: a position, a slack
//! string's stretch) where the transient left them, drifting at a constant rate. Where the
//! outputs read none of the integrators, what they read depends on the mode and the values
//! only, not on the path, and the asymptote at nearby values is the continuation: no
//! iteration, no basin to leave. It is an [`Anchor`] on the same terms as a nonlinear
//! mode's (path-dependent where the mode has guards or the search changed mode on the way),
//! refused where the mode at the new values is no longer stable, its outputs come to read
//! an integrator, or a guard below zero rises along the asymptote. An output that reads an
//! integrator (a displacement in steady motion) makes no anchor.

use super::nonlinear::{GUARD_ROUNDING, newton, steady_at};
use super::{Steady, SteadySettings, next_crossing, on_asymptote};
use crate::hybrid::Simulator;
use crate::numeric::NumericMode;
use bondgraph_core::modes::Mode;

/// A steady state that can be continued ([`Steady::anchor`]): an isolated, stable
/// equilibrium of a nonlinear mode, or the asymptote of a linear mode whose outputs read
/// none of its integrators.
#[derive(Clone, Debug, PartialEq)]
pub struct Anchor {
    /// The mode it settled in.
    pub mode: Mode,
    /// The equilibrium (of a linear mode, the asymptote's point when it was reached), in
    /// the mode's own states.
    pub state: Vec<f64>,
    /// The constant inputs it settled at.
    pub inputs: Vec<f64>,
    /// Each state's scale: the largest magnitude it had on the way (a nonlinear mode's;
    /// empty for a linear mode's asymptote, continued exactly).
    pub scale: Vec<f64>,
    /// When the search judged it reached.
    pub time: f64,
    /// Whether the trajectory's reaching it depends on the parameters along the way: its
    /// mode has guards, or the search changed mode before it. Such an anchor is continued
    /// only for a finite difference ([`continue_branch`]), never by [`continue_steady`].
    pub path_dependent: bool,
    /// Which of the mode's guards were below zero there, in the mode's order.
    pub guards_below: Vec<bool>,
}

/// Newton iterations a continuation takes at most: from an equilibrium a hair away it
/// converges quadratically in two or three.
const ITERATIONS: usize = 12;

/// The most a continued equilibrium may move from its anchor, as a fraction of each state's
/// scale: a continuation within a fit's radius moves it by about that radius; a larger move
/// is a jump to another branch, or a fold nearby, and the search is run instead.
pub const MOST_MOVED: f64 = 1e-2;

/// The steady state at the simulator's current parameter values on the branch of `anchor`,
/// found at other values; `None` where it cannot be vouched for (the anchor is
/// [`Anchor::path_dependent`], Newton does not converge, the point is unstable or moved too
/// far), and the caller then runs the search.
pub fn continue_steady(
    simulator: &mut Simulator<'_>,
    anchor: &Anchor,
    settings: &SteadySettings,
) -> Option<Steady> {
    if anchor.path_dependent {
        return None;
    }
    continue_on_branch(simulator, anchor, settings).map(|(steady, _)| steady)
}

/// For a finite difference only: the equilibrium at the simulator's current parameter values
/// on the branch of `anchor`, path-dependent or not, whether or not a fresh search from the
/// row's start would still reach it (see the module's documentation). Besides
/// [`continue_steady`]'s checks, every guard of the mode must be on the side it was at the
/// anchor, and clear of its threshold (a continued contact must still hold, or still slide).
pub fn continue_branch(
    simulator: &mut Simulator<'_>,
    anchor: &Anchor,
    settings: &SteadySettings,
) -> Option<Steady> {
    let (steady, x) = continue_on_branch(simulator, anchor, settings)?;
    let mode = simulator.mode(&anchor.mode).ok()?;
    let rate = vec![0.0; anchor.inputs.len()];
    let u = &anchor.inputs;
    let same_side = mode.guards.len() == anchor.guards_below.len()
        && mode
            .guards
            .iter()
            .zip(&anchor.guards_below)
            .all(|(guard, &below)| {
                let value = guard.row.eval(&x, u, &rate);
                (value < 0.0) == below
                    && value.abs() > GUARD_ROUNDING * guard.row.magnitude(&x, u, &rate)
            });
    same_side.then_some(steady)
}

/// Newton's method on the anchor's branch, as [`continue_steady`] checks it, whatever the
/// anchor's path: the steady state, and the equilibrium in the mode's own states.
fn continue_on_branch(
    simulator: &mut Simulator<'_>,
    anchor: &Anchor,
    settings: &SteadySettings,
) -> Option<(Steady, Vec<f64>)> {
    let mode = simulator.mode(&anchor.mode).ok()?;
    let Some(nl) = mode.nonlinear.as_ref() else {
        return continue_linear(&mode, anchor, settings);
    };
    if anchor.state.len() != nl.n || anchor.inputs.len() != nl.m {
        return None;
    }
    let rate = vec![0.0; nl.m];
    let input: Vec<f64> = anchor
        .state
        .iter()
        .chain(&anchor.inputs)
        .chain(&rate)
        .copied()
        .collect();
    let (x, jacobian) = newton(nl, input, ITERATIONS, &|_: &[f64]| anchor.scale.clone())?;
    let moved_little = x
        .iter()
        .zip(&anchor.state)
        .zip(&anchor.scale)
        .all(|((a, b), s)| (a - b).abs() <= MOST_MOVED * s);
    if !moved_little {
        return None;
    }
    let eigenvalues = super::nonlinear::jacobian_eigenvalues(&jacobian).ok()?;
    if !eigenvalues.iter().all(|v| v.re < -settings.zero_eigenvalue) {
        return None;
    }
    let steady = steady_at(&mode, &x, &anchor.inputs, &rate, anchor.time);
    Some((steady, x))
}

/// The anchor of a linear mode's steady state: its asymptote `x` reached at `time` under
/// constant inputs `u`, where every output reads none of the mode's integrators
/// ([`Propagator::blind_to_integrators`](crate::propagate::Propagator::blind_to_integrators)),
/// so that what they read at the asymptote does not depend on where the transient left the
/// integrators (a slack string's stretch, a position), only on the mode and the values.
/// Path-dependent where the search left a mode on the way (`left_a_mode`) or the mode has
/// guards, as for a nonlinear mode.
pub(super) fn linear_anchor(
    mode: &NumericMode,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
    time: f64,
    left_a_mode: bool,
    settings: &SteadySettings,
) -> Option<Anchor> {
    let constant = rate.iter().all(|r| *r == 0.0);
    (constant && outputs_blind(mode, settings)).then(|| Anchor {
        mode: mode.mode.clone(),
        state: x.to_vec(),
        inputs: u.to_vec(),
        // A linear continuation is exact: no Newton steps to scale, no move to bound.
        scale: Vec::new(),
        time,
        path_dependent: left_a_mode || !mode.guards.is_empty(),
        guards_below: mode
            .guards
            .iter()
            .map(|g| g.row.eval(x, u, rate) < 0.0)
            .collect(),
    })
}

/// Whether every output of a linear mode reads none of its integrators.
fn outputs_blind(mode: &NumericMode, settings: &SteadySettings) -> bool {
    mode.outputs.iter().all(|row| {
        row.program.is_none()
            && mode
                .propagator
                .blind_to_integrators(&row.state, settings.zero_eigenvalue)
    })
}

/// A linear mode's steady state at the simulator's current values, on the branch of
/// `anchor`: the asymptote from the anchor's point, exact (no iteration), where the mode is
/// still stable, its outputs still read none of its integrators, and no guard below zero
/// rises along the asymptote (the search would follow it to the crossing).
fn continue_linear(
    mode: &NumericMode,
    anchor: &Anchor,
    settings: &SteadySettings,
) -> Option<(Steady, Vec<f64>)> {
    let u = &anchor.inputs;
    if anchor.state.len() != mode.a.nrows() || u.len() != mode.b.ncols() {
        return None;
    }
    let (x, drift) = mode
        .propagator
        .asymptote(&anchor.state, u, settings.zero_eigenvalue)?;
    if !outputs_blind(mode, settings) {
        return None;
    }
    let rate = vec![0.0; u.len()];
    if next_crossing(mode, &x, u, &rate, &drift).is_finite() {
        return None;
    }
    let steady = on_asymptote(mode, &x, u, &rate, &drift, anchor.time);
    Some((steady, x))
}
