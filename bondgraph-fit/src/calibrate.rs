//! Bounded nonlinear least squares, built for steady-state models.
//!
//! The forward model is a steady state of a switching system, which makes the residuals
//! piecewise smooth in the parameters: a viscous coefficient moves every sliding row, but a
//! breakaway force only decides *which* rows slide, so the residuals are flat in it almost
//! everywhere and jump where a row changes regime. Levenberg–Marquardt handles the first
//! kind; for the second (a Jacobian column that is zero), a one-dimensional scan over the
//! parameter's bounds finds the interval of values that fit best, takes its middle, and
//! reports the interval as the uncertainty, which is the honest answer for a threshold.
//!
//! Parameters are moved in unit coordinates (`0` at the low bound, `1` at the high one), so
//! a force in newtons and a resistance of `1e10` are stepped alike; a step that would leave
//! the box is projected back onto it, and a parameter held at a bound by its gradient is
//! left out of the step. Uncertainty comes from the Jacobian at the optimum,
//! `σ̂² (JᵀJ)⁻¹` with `σ̂² = SSE/(n - p)`, for parameters that are neither flat nor at a bound.

use crate::stats::{cholesky_solve, spd_inverse};

/// How a calibration searches.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Levenberg–Marquardt iterations, at most.
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the sum of squares by less than this fraction.
    pub tolerance: f64,
    /// Forward-difference step, in unit coordinates.
    pub step: f64,
    /// Stop when an accepted step moves no parameter by more than this, in unit coordinates
    /// (a thousandth of a forward-difference step). A descent pressed against a face where
    /// the model cannot be evaluated (a Coulomb force at its breakaway force) otherwise
    /// crawls towards it in ever smaller steps, each still lowering the sum of squares a
    /// little.
    pub min_stride: f64,
    /// Points of the scan of a flat parameter over its bounds.
    pub scan_points: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_iterations: 60,
            tolerance: 1e-9,
            step: 1e-5,
            min_stride: 1e-8,
            scan_points: 13,
        }
    }
}

/// Rounds of descent then scanning: a scan that finds a better point between its grid points
/// hands it to the next round's descent.
const ROUNDS: usize = 5;

/// The result of a calibration.
#[derive(Clone, Debug)]
pub struct Fit {
    /// The fitted values.
    pub values: Vec<f64>,
    /// The residuals at the fitted values (model minus data).
    pub residuals: Vec<f64>,
    /// Their sum of squares.
    pub sse: f64,
    /// The standard error of each value, where the Jacobian determines it.
    pub std_errors: Vec<Option<f64>>,
    /// For a parameter the residuals are flat in (a threshold), the interval of equally
    /// good values.
    pub intervals: Vec<Option<(f64, f64)>>,
    /// Whether each value ended on a bound.
    pub at_bound: Vec<bool>,
    /// The Jacobian at the fitted values, `d residual_i / d value_j`, row-major.
    pub jacobian: Vec<f64>,
    /// Forward-model evaluations used.
    pub evaluations: usize,
}

impl Fit {
    /// This fit with the parameters marked `idle` put back among its own: each at its value
    /// in `values`, changing no residual (a zero Jacobian column), so any value within its
    /// `bounds` fits as well. `idle`, `values` and `bounds` cover every parameter; the fit,
    /// those not idle, in order.
    ///
    /// # Panics
    /// When the fit does not have one value per parameter not idle.
    #[must_use]
    pub fn with_idle(self, idle: &[bool], values: &[f64], bounds: &[(f64, f64)]) -> Fit {
        let active = idle.iter().filter(|i| !**i).count();
        assert_eq!(
            self.values.len(),
            active,
            "one fitted value per active parameter"
        );
        if active == idle.len() {
            return self;
        }
        let (n, p) = (self.residuals.len(), idle.len());
        let source: Vec<Option<usize>> = idle
            .iter()
            .scan(0, |next, i| {
                Some((!*i).then(|| {
                    *next += 1;
                    *next - 1
                }))
            })
            .collect();
        let pick = |j: usize| source[j];
        Fit {
            values: (0..p)
                .map(|j| pick(j).map_or(values[j], |a| self.values[a]))
                .collect(),
            std_errors: (0..p)
                .map(|j| pick(j).and_then(|a| self.std_errors[a]))
                .collect(),
            intervals: (0..p)
                .map(|j| pick(j).map_or(Some(bounds[j]), |a| self.intervals[a]))
                .collect(),
            at_bound: (0..p)
                .map(|j| pick(j).is_some_and(|a| self.at_bound[a]))
                .collect(),
            jacobian: (0..n * p)
                .map(|k| pick(k % p).map_or(0.0, |a| self.jacobian[(k / p) * active + a]))
                .collect(),
            residuals: self.residuals,
            sse: self.sse,
            evaluations: self.evaluations,
        }
    }
}

/// Why a calibration failed.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationError(pub String);

impl std::fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CalibrationError {}

/// What a least-squares fit minimises: the residuals at a point of the parameters, `None`
/// where the model cannot be evaluated (a simulation that does not settle). It may keep
/// caches (the modes derived so far), so it is called mutably. Any
/// `FnMut(&[f64]) -> Option<Vec<f64>>` is one.
pub trait ResidualFunction {
    /// The residuals at `x`; `None` where the model cannot be evaluated there.
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>>;

    /// The residuals at `x`, a finite-difference step from `from`, the point whose residuals
    /// the difference is taken against (asked last, or before the other steps of the same
    /// Jacobian). A model may answer on the branch it settled on at `from` (a steady state
    /// continued by Newton's method where a fresh simulation would switch within the step),
    /// so that the column is the slope a descent follows; by default, the residuals at `x`.
    fn differenced(&mut self, x: &[f64], from: &[f64]) -> Option<Vec<f64>> {
        let _ = from;
        self.residuals(x)
    }

    /// The sum of squared residuals at `x`, or any value above `limit` once it is known to
    /// exceed it: a search that keeps only the best few points, or a scan that asks only
    /// whether a point is as good as the best, need not predict the rest of a point's rows
    /// once the rows predicted so far already put it out. By default, the whole sum.
    fn sum_of_squares(&mut self, x: &[f64], limit: f64) -> Option<f64> {
        let _ = limit;
        self.residuals(x).map(|r| sse(&r))
    }
}

impl<F: FnMut(&[f64]) -> Option<Vec<f64>>> ResidualFunction for F {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        self(x)
    }
}

/// Minimises the sum of squared `residuals(values)` over the box `bounds`, from `start`.
///
/// `residuals` returns `None` where the model cannot be evaluated (a simulation that does
/// not settle); such points are treated as infinitely bad.
///
/// # Errors
/// When the model cannot be evaluated at the start, or a bound is not a finite interval.
pub fn least_squares(
    residuals: &mut dyn ResidualFunction,
    start: &[f64],
    bounds: &[(f64, f64)],
    settings: &Settings,
) -> Result<Fit, CalibrationError> {
    least_squares_toward(residuals, start, bounds, settings, f64::INFINITY).map(|(fit, _)| fit)
}

/// Descents a hundredth of their sum of squares or less apart over [`PACE_WINDOW`] accepted
/// steps crawl (Levenberg–Marquardt's damping grown large in a curved valley, or a descent
/// along a threshold): at that pace a sum of squares falls by at most a tenth over the rest
/// of a fit's iterations.
const CRAWL: f64 = 1e-2;

/// Accepted steps over which a descent's pace is measured.
const PACE_WINDOW: usize = 5;

/// As [`least_squares`], for one of several local fits of a search whose best start has
/// the sum of squares `bar`, so that some local fit ends at `bar` or below: a descent still
/// above `bar` that crawls ([`CRAWL`]) or slows (its last [`PACE_WINDOW`] steps fell by a
/// smaller fraction than the five before), and that at its pace over the last
/// [`PACE_WINDOW`] steps would still be above `bar` after the rest of its iterations,
/// cannot make this fit the search's best by descending on, and its round of descent ends
/// there. The scans of
/// the parameters the residuals are flat in follow as after any descent: a threshold that
/// held the descent in a narrow valley (a breakaway force deciding which rows slide) moves
/// there, and the next round descends from the better point (a crawl at sixty times the
/// search's best has ended its round so, and its next rounds reached that best; ending the
/// fit outright lost it). Returns the fit and how its last round ended.
///
/// Only crawls and slowing descents are extrapolated: a descent from far away that still
/// falls steeply (a tenth of its sum of squares a step), and no slower than before, may
/// reach the best optimum of all, from thousands of times `bar`.
///
/// # Errors
/// As [`least_squares`].
pub(crate) fn least_squares_toward(
    residuals: &mut dyn ResidualFunction,
    start: &[f64],
    bounds: &[(f64, f64)],
    settings: &Settings,
    bar: f64,
) -> Result<(Fit, Ending), CalibrationError> {
    for (i, &(lo, hi)) in bounds.iter().enumerate() {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(CalibrationError(format!(
                "parameter {i}: bounds ({lo}, {hi}) are not a finite interval"
            )));
        }
    }
    let mut u: Vec<f64> = start
        .iter()
        .zip(bounds)
        .map(|(&x, &(lo, hi))| ((x - lo) / (hi - lo)).clamp(0.0, 1.0))
        .collect();
    let mut problem = Problem {
        residuals,
        bounds,
        origin: u
            .iter()
            .zip(start)
            .zip(bounds)
            .map(|((&u, &x), &(lo, hi))| (u, x.clamp(lo, hi)))
            .collect(),
        evaluations: 0,
        last_jacobian: None,
    };
    let mut r = problem.eval(&u).ok_or_else(|| {
        CalibrationError("the model cannot be evaluated at the starting values".into())
    })?;
    let mut intervals = vec![None; u.len()];
    let mut ending = Ending::Unfinished;
    for round in 0..ROUNDS {
        let (next_u, next_r, descent) = problem.levenberg_marquardt(u, r, settings, bar);
        u = next_u;
        r = next_r;
        ending = descent;
        // Parameters the residuals do not move: scan them.
        let jacobian = problem.jacobian(&u, &r, settings.step);
        let moves = moving_columns(&jacobian, r.len(), u.len());
        let mut moved = false;
        for j in 0..u.len() {
            if moves[j] {
                intervals[j] = None;
                continue;
            }
            let (best, interval, best_r) = problem.scan(&u, j, &r, settings.scan_points);
            // Another round only for a gain a descent would not stop at: a point of the
            // same flat interval whose sum of squares differs by rounding is no gain.
            let gain = sse(&r) - sse(&best_r);
            moved |= (best - u[j]).abs() > 1e-9 && gain > settings.tolerance * sse(&r);
            u[j] = best;
            r = best_r;
            intervals[j] = Some(interval);
        }
        if !moved {
            break;
        }
        if round + 1 == ROUNDS {
            ending = Ending::Unfinished;
        }
    }
    let jacobian_u = problem.jacobian(&u, &r, settings.step);
    let n = r.len();
    let p = u.len();
    let scale: Vec<f64> = bounds.iter().map(|(lo, hi)| hi - lo).collect();
    let jacobian: Vec<f64> = (0..n * p).map(|k| jacobian_u[k] / scale[k % p]).collect();
    let at_bound: Vec<bool> = u.iter().map(|&v| v <= 1e-9 || v >= 1.0 - 1e-9).collect();
    let total = sse(&r);
    // Covariance over the parameters the data determines smoothly.
    let free: Vec<usize> = (0..p)
        .filter(|&j| intervals[j].is_none() && !at_bound[j])
        .collect();
    let mut std_errors = vec![None; p];
    if n > free.len() && !free.is_empty() {
        let sigma2 = total / (n - free.len()) as f64;
        let m = free.len();
        // In the bounds-scaled coordinates the columns are comparable (a flow of 1e-7 m³/s
        // beside a viscous coefficient of 1e3 N·s/m would make the normal matrix look
        // singular in SI units); an error in u is one in x times the bounds' width.
        let jtj = normal_matrix(&jacobian_u, n, p, &free);
        if let Some(inverse) = spd_inverse(&jtj, m) {
            for (a, &j) in free.iter().enumerate() {
                std_errors[j] = Some((sigma2 * inverse[a * m + a]).sqrt() * scale[j]);
            }
        } else {
            // A parameter the residuals barely move (a column a ten-thousandth of the longest
            // in norm) makes the normal matrix numerically singular and would cost every
            // other parameter its error: it is undetermined, the others are not. (Aliased
            // parameters, whose columns are long but collinear, still get none.)
            let norm2 = |j: usize| (0..n).map(|i| jacobian_u[i * p + j].powi(2)).sum::<f64>();
            let longest = free.iter().map(|&j| norm2(j)).fold(0.0, f64::max);
            let determined: Vec<usize> = free
                .iter()
                .copied()
                .filter(|&j| norm2(j) > 1e-8 * longest)
                .collect();
            let m = determined.len();
            if m < free.len() && m > 0 {
                let sigma2 = total / (n - m) as f64;
                let jtj = normal_matrix(&jacobian_u, n, p, &determined);
                if let Some(inverse) = spd_inverse(&jtj, m) {
                    for (a, &j) in determined.iter().enumerate() {
                        std_errors[j] = Some((sigma2 * inverse[a * m + a]).sqrt() * scale[j]);
                    }
                }
            }
        }
    }
    let to_x = |j: usize, v: f64| bounds[j].0 + v * scale[j];
    let fit = Fit {
        values: problem.values(&u),
        sse: total,
        residuals: r,
        std_errors,
        intervals: intervals
            .iter()
            .enumerate()
            .map(|(j, i)| i.map(|(a, b)| (to_x(j, a), to_x(j, b))))
            .collect(),
        at_bound,
        jacobian,
        evaluations: problem.evaluations,
    };
    Ok((fit, ending))
}

/// How a fit's last round of descent ended ([`least_squares_toward`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Ending {
    /// No step improved it further and its scans moved nothing: a fit started where it
    /// ended would only repeat its last differences and scans.
    Converged,
    /// A crawl that could not reach the search's bar.
    Crawled,
    /// Its iterations or its rounds ran out while it still descended.
    Unfinished,
}

/// `JᵀJ` over the columns `columns` of the row-major `n × p` Jacobian.
fn normal_matrix(jacobian: &[f64], n: usize, p: usize, columns: &[usize]) -> Vec<f64> {
    let m = columns.len();
    let mut jtj = vec![0.0; m * m];
    for (a, &ja) in columns.iter().enumerate() {
        for (b, &jb) in columns.iter().enumerate() {
            jtj[a * m + b] = (0..n)
                .map(|i| jacobian[i * p + ja] * jacobian[i * p + jb])
                .sum();
        }
    }
    jtj
}

/// Which parameters move the residuals: a Jacobian column that is not negligible beside
/// the largest (rounding in a steady state gives columns of 1e-11 where a parameter has no
/// effect at all).
fn moving_columns(jacobian: &[f64], n: usize, p: usize) -> Vec<bool> {
    let norms: Vec<f64> = (0..p)
        .map(|j| (0..n).map(|i| jacobian[i * p + j].powi(2)).sum())
        .collect();
    let largest = norms.iter().copied().fold(0.0, f64::max);
    norms
        .iter()
        .map(|&c| c > 1e-16 * largest && c > 0.0)
        .collect()
}

fn sse(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

struct Problem<'a> {
    residuals: &'a mut dyn ResidualFunction,
    bounds: &'a [(f64, f64)],
    /// Each parameter's start in unit coordinates and its value there: a parameter a step
    /// leaves where it started keeps that value exactly, not its round trip through the
    /// unit coordinates (an ulp away; a model at a knife edge, a Coulomb force tied to its
    /// breakaway force, could evaluate at one and not the other).
    origin: Vec<(f64, f64)>,
    evaluations: usize,
    /// The last full Jacobian and where it was taken: a descent ends where it last
    /// differenced every column, and the scans and the standard errors need the same one.
    last_jacobian: Option<(Vec<f64>, Vec<f64>)>,
}

impl Problem<'_> {
    /// The parameter values at unit coordinates `u`.
    fn values(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(self.bounds)
            .zip(&self.origin)
            .map(|((&v, &(lo, hi)), &(u0, x0))| if v == u0 { x0 } else { lo + v * (hi - lo) })
            .collect()
    }

    fn eval(&mut self, u: &[f64]) -> Option<Vec<f64>> {
        self.evaluations += 1;
        let x = self.values(u);
        self.residuals
            .residuals(&x)
            .filter(|r| r.iter().all(|v| v.is_finite()))
    }

    /// The sum of squares at `u`, or a value above `limit` once it is known to exceed it
    /// ([`ResidualFunction::sum_of_squares`]); infinite where the model cannot be evaluated.
    fn sse_below(&mut self, u: &[f64], limit: f64) -> f64 {
        self.evaluations += 1;
        let x = self.values(u);
        self.residuals
            .sum_of_squares(&x, limit)
            .filter(|c| c.is_finite())
            .unwrap_or(f64::INFINITY)
    }

    /// The residuals at `u`, a difference step from `from` ([`ResidualFunction::differenced`]).
    fn eval_differenced(&mut self, u: &[f64], from: &[f64]) -> Option<Vec<f64>> {
        self.evaluations += 1;
        let (x, from) = (self.values(u), self.values(from));
        self.residuals
            .differenced(&x, &from)
            .filter(|r| r.iter().all(|v| v.is_finite()))
    }

    /// Forward differences in unit coordinates (backwards at the upper bound, or where the
    /// forward point cannot be evaluated: a Coulomb force tied to its breakaway force can
    /// only move down); a column whose perturbed points both fail is zero.
    fn jacobian(&mut self, u: &[f64], r: &[f64], h: f64) -> Vec<f64> {
        self.jacobian_columns(u, r, h, &vec![true; u.len()])
    }

    /// The columns `wanted` of the Jacobian at `u` (the others zero), taken again only where
    /// the last full one was not taken at `u`.
    fn jacobian_columns(&mut self, u: &[f64], r: &[f64], h: f64, wanted: &[bool]) -> Vec<f64> {
        if let Some((at, jacobian)) = &self.last_jacobian
            && at.as_slice() == u
        {
            return jacobian.clone();
        }
        let jacobian = self.difference_columns(u, r, h, wanted);
        if wanted.iter().all(|w| *w) {
            self.last_jacobian = Some((u.to_vec(), jacobian.clone()));
        }
        jacobian
    }

    /// Forward differences of the columns `wanted` at `u` (the others zero).
    fn difference_columns(&mut self, u: &[f64], r: &[f64], h: f64, wanted: &[bool]) -> Vec<f64> {
        let (n, p) = (r.len(), u.len());
        let mut jacobian = vec![0.0; n * p];
        for j in (0..p).filter(|&j| wanted[j]) {
            let first = if u[j] + h > 1.0 { -h } else { h };
            for step in [first, -first] {
                if !(0.0..=1.0).contains(&(u[j] + step)) {
                    continue;
                }
                let mut moved = u.to_vec();
                moved[j] += step;
                if let Some(rj) = self.eval_differenced(&moved, u) {
                    for i in 0..n {
                        jacobian[i * p + j] = (rj[i] - r[i]) / step;
                    }
                    break;
                }
            }
        }
        jacobian
    }

    /// A descent from `(u, r)`: where it ends, and how ([`least_squares_toward`]).
    fn levenberg_marquardt(
        &mut self,
        mut u: Vec<f64>,
        mut r: Vec<f64>,
        settings: &Settings,
        bar: f64,
    ) -> (Vec<f64>, Vec<f64>, Ending) {
        let p = u.len();
        let mut lambda = 1e-3;
        let mut cost = sse(&r);
        // The sums of squares after each accepted step, the start's first.
        let mut costs = vec![cost];
        // A column that nothing moved (a threshold between its rows' switching points) is
        // left out of the next differences, which saves an evaluation of every row per
        // iteration; before stopping, every column is differenced again, and the descent goes
        // on if one has come to move.
        let mut wanted = vec![true; p];
        for iteration in 0..settings.max_iterations {
            let every_column = wanted.iter().all(|w| *w);
            let jacobian = self.jacobian_columns(&u, &r, settings.step, &wanted);
            let n = r.len();
            let gradient: Vec<f64> = (0..p)
                .map(|j| (0..n).map(|i| jacobian[i * p + j] * r[i]).sum())
                .collect();
            // Held at a bound by the gradient, or not moved by anything: out of this step.
            let moves = moving_columns(&jacobian, n, p);
            let free: Vec<usize> = (0..p)
                .filter(|&j| {
                    moves[j]
                        && !(u[j] <= 0.0 && gradient[j] > 0.0)
                        && !(u[j] >= 1.0 && gradient[j] < 0.0)
                })
                .collect();
            if every_column {
                wanted.clone_from(&moves);
            }
            if free.is_empty() {
                if every_column {
                    return (u, r, Ending::Converged);
                }
                wanted = vec![true; p];
                continue;
            }
            let m = free.len();
            let jtj = normal_matrix(&jacobian, n, p, &free);
            let rhs: Vec<f64> = free.iter().map(|&j| -gradient[j]).collect();
            // Marquardt's scaling, with a floor so that a weakly determined parameter is not
            // thrown across its whole range by a tiny curvature.
            let largest = (0..m).map(|a| jtj[a * m + a]).fold(0.0, f64::max);
            let mut improved = false;
            // What the undamped Gauss–Newton step promises, `gᵀ (JᵀJ)⁻¹ g`: below the
            // tolerance, no step is an improvement the descent would go on from, so only
            // that step is tried, as the last (damped steps at an optimum meet only the
            // rounding of the predictions: a dozen evaluations each time).
            let last = cholesky_solve(&jtj, &rhs).filter(|step| {
                let promised: f64 = step.iter().zip(&rhs).map(|(d, g)| d * g).sum();
                promised <= settings.tolerance * cost
            });
            let attempts = if last.is_some() { 1 } else { 12 };
            for _ in 0..attempts {
                let delta = match &last {
                    Some(step) => step.clone(),
                    None => {
                        let mut damped = jtj.clone();
                        for a in 0..m {
                            damped[a * m + a] += lambda * jtj[a * m + a].max(1e-6 * largest);
                        }
                        let Some(delta) = cholesky_solve(&damped, &rhs) else {
                            lambda *= 10.0;
                            continue;
                        };
                        delta
                    }
                };
                let mut trial = u.clone();
                for (a, &j) in free.iter().enumerate() {
                    trial[j] = (u[j] + delta[a]).clamp(0.0, 1.0);
                }
                match self.eval(&trial) {
                    Some(trial_r) if sse(&trial_r) < cost => {
                        let trial_cost = sse(&trial_r);
                        let decrease = (cost - trial_cost) / cost.max(1e-300);
                        let stride = trial
                            .iter()
                            .zip(&u)
                            .map(|(a, b)| (a - b).abs())
                            .fold(0.0, f64::max);
                        u = trial;
                        r = trial_r;
                        cost = trial_cost;
                        lambda = (lambda / 3.0).max(1e-9);
                        improved = decrease > settings.tolerance && stride > settings.min_stride;
                        costs.push(cost);
                        break;
                    }
                    _ => lambda *= 4.0,
                }
            }
            if improved && cost > bar && costs.len() > PACE_WINDOW {
                let pace = cost / costs[costs.len() - 1 - PACE_WINDOW];
                let windows_left =
                    (settings.max_iterations - iteration - 1) as f64 / PACE_WINDOW as f64;
                let n = costs.len();
                let slowing = n > 2 * PACE_WINDOW
                    && pace >= costs[n - 1 - PACE_WINDOW] / costs[n - 1 - 2 * PACE_WINDOW];
                if (1.0 - pace < CRAWL || slowing) && cost * pace.powf(windows_left) > bar {
                    return (u, r, Ending::Crawled);
                }
            }
            if !improved {
                if every_column {
                    return (u, r, Ending::Converged);
                }
                wanted = vec![true; p];
            }
        }
        (u, r, Ending::Unfinished)
    }

    /// The best value of parameter `j` on a grid over its bounds (others fixed), refined to
    /// the edges of the best interval by bisection: `(middle, interval, residuals there)`.
    fn scan(
        &mut self,
        u: &[f64],
        j: usize,
        r: &[f64],
        points: usize,
    ) -> (f64, (f64, f64), Vec<f64>) {
        let at = |v: f64| {
            let mut w = u.to_vec();
            w[j] = v;
            w
        };
        let grid: Vec<f64> = (0..points)
            .map(|k| k as f64 / (points - 1) as f64)
            .collect();
        // Only whether a point is as good as the best, or better, matters until the end: a
        // point is evaluated until its rows put it above that.
        let current = sse(r);
        let costs: Vec<f64> = grid
            .iter()
            .map(|&v| self.sse_below(&at(v), current))
            .collect();
        let best_cost = costs.iter().copied().fold(current, f64::min);
        let same = |c: f64| c <= best_cost * (1.0 + 1e-12) + 1e-300;
        // The best grid interval that holds the current value if it is among the best,
        // else the one around the first best grid point.
        let seed = if same(current) {
            u[j]
        } else {
            grid[costs.iter().position(|&c| same(c)).expect("a best point")]
        };
        // From the seed, through the grid points as good as it on either side; the first
        // worse point on each side bounds the interval (a grid point below the seed that
        // cannot be evaluated, a Coulomb force above its breakaway force, is not in it).
        let below = grid.iter().rposition(|&g| g <= seed).unwrap_or(0);
        let above = grid.iter().position(|&g| g >= seed).unwrap_or(points - 1);
        let (mut lo, mut lo_bad) = (seed, None);
        if same(costs[below]) {
            let mut k = below;
            while k > 0 && same(costs[k - 1]) {
                k -= 1;
            }
            lo = grid[k];
            lo_bad = k.checked_sub(1).map(|k| grid[k]);
        } else if grid[below] < seed {
            lo_bad = Some(grid[below]);
        }
        let (mut hi, mut hi_bad) = (seed, None);
        if same(costs[above]) {
            let mut k = above;
            while k + 1 < points && same(costs[k + 1]) {
                k += 1;
            }
            hi = grid[k];
            hi_bad = (k + 1 < points).then(|| grid[k + 1]);
        } else if grid[above] > seed {
            hi_bad = Some(grid[above]);
        }
        // Bisect each edge between the last good and the first bad grid point. A point
        // better than every grid point (between two grid points, a row that slides just
        // above its threshold) is taken at once: the next round fits from there.
        let mut better: Option<(f64, f64)> = None;
        let mut refine = |good: f64, bad: f64, this: &mut Self| {
            let (mut good, mut bad) = (good, bad);
            for _ in 0..10 {
                let mid = 0.5 * (good + bad);
                let c = this.sse_below(&at(mid), best_cost);
                if c < best_cost * (1.0 - 1e-9) && better.is_none_or(|(_, b)| c < b) {
                    better = Some((mid, c));
                }
                if same(c) {
                    good = mid;
                } else {
                    bad = mid;
                }
            }
            good
        };
        if let Some(bad) = lo_bad {
            lo = refine(lo, bad, self);
        }
        if let Some(bad) = hi_bad {
            hi = refine(hi, bad, self);
        }
        if let Some((point, _)) = better
            && let Some(point_r) = self.eval(&at(point))
        {
            return (point, (point, point), point_r);
        }
        let middle = 0.5 * (lo + hi);
        match self.eval(&at(middle)) {
            Some(middle_r) if same(sse(&middle_r)) => (middle, (lo, hi), middle_r),
            _ => (
                seed,
                (lo, hi),
                self.eval(&at(seed)).unwrap_or_else(|| r.to_vec()),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fit_started_at_its_optimum_tries_one_step() {
        // The line y = 2 + 3 t through four exact points, started at (2, 3): the residuals
        // are zero, so the Gauss–Newton step promises nothing. The fit evaluates the start,
        // differences each of the two columns once and tries that step alone (it tried
        // twelve damped steps, each meeting only the rounding of the residuals).
        let t = [0.0, 1.0, 2.0, 3.0];
        let mut count = 0;
        let mut residuals = |x: &[f64]| {
            count += 1;
            Some(
                t.iter()
                    .map(|&t| x[0] + x[1] * t - (2.0 + 3.0 * t))
                    .collect(),
            )
        };
        let fit = least_squares(
            &mut residuals,
            &[2.0, 3.0],
            &[(-10.0, 10.0), (-10.0, 10.0)],
            &Settings::default(),
        )
        .unwrap();
        assert_eq!(fit.values, vec![2.0, 3.0]);
        assert_eq!(fit.evaluations, 4);
        assert_eq!(count, 4);
    }

    #[test]
    fn a_parameter_no_step_moves_keeps_its_start_exactly() {
        // A model evaluable only at its start's exact value of the first parameter (a
        // Coulomb force tied to its breakaway force: a knife edge). Through the unit
        // coordinates of its bounds that value comes back an ulp away, so the fit could not
        // start ("cannot be evaluated at the starting values"); kept exactly, it fits the
        // second parameter to the data's 2.
        let (k0, (lo, hi)) = (0.03186021586121698, (0.005, 0.1));
        assert_ne!(lo + ((k0 - lo) / (hi - lo)) * (hi - lo), k0);
        let mut residuals = |x: &[f64]| (x[0] == k0).then(|| vec![x[1] - 2.0, 2.0 - x[1]]);
        let fit = least_squares(
            &mut residuals,
            &[k0, 1.0],
            &[(lo, hi), (0.0, 5.0)],
            &Settings::default(),
        )
        .unwrap();
        assert_eq!(fit.values[0], k0);
        assert!((fit.values[1] - 2.0).abs() < 1e-9, "{:?}", fit.values);
    }

    fn fit(
        mut f: impl FnMut(&[f64]) -> Option<Vec<f64>>,
        start: &[f64],
        bounds: &[(f64, f64)],
    ) -> Fit {
        least_squares(&mut f, start, bounds, &Settings::default()).unwrap()
    }

    #[test]
    fn idle_parameters_go_back_in_place_changing_nothing() {
        // A fit of (a, c) with b idle between them: b takes its given value, no error, its
        // whole bounds as the interval, and a zero Jacobian column; a and c keep theirs.
        let fit = Fit {
            values: vec![1.0, 3.0],
            residuals: vec![0.5, -0.5],
            sse: 0.5,
            std_errors: vec![Some(0.1), None],
            intervals: vec![None, Some((2.0, 4.0))],
            at_bound: vec![false, false],
            jacobian: vec![1.0, 2.0, 3.0, 4.0],
            evaluations: 7,
        };
        let full = fit.with_idle(
            &[false, true, false],
            &[0.0, 8.0, 0.0],
            &[(0.0, 1.0), (5.0, 9.0), (0.0, 1.0)],
        );
        assert_eq!(full.values, vec![1.0, 8.0, 3.0]);
        assert_eq!(full.std_errors, vec![Some(0.1), None, None]);
        assert_eq!(
            full.intervals,
            vec![None, Some((5.0, 9.0)), Some((2.0, 4.0))]
        );
        assert_eq!(full.at_bound, vec![false, false, false]);
        assert_eq!(full.jacobian, vec![1.0, 0.0, 2.0, 3.0, 0.0, 4.0]);
        assert_eq!((full.sse, full.evaluations), (0.5, 7));
    }

    #[test]
    fn a_straight_line_with_the_textbook_standard_errors() {
        // y = 1 + 2x with residuals +1, -1, -1, +1 at x = 0..3 (orthogonal to 1 and x):
        // the fit is exactly a = 1, b = 2, SSE = 4, σ̂² = 4/2, and
        // SE(b) = sqrt(σ̂²/Sxx) = sqrt(2/5), SE(a) = sqrt(σ̂² Σx²/(n Sxx)) = sqrt(2·14/20).
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [2.0, 2.0, 4.0, 8.0];
        let result = fit(
            |p| Some(x.iter().zip(&y).map(|(x, y)| p[0] + p[1] * x - y).collect()),
            &[0.0, 0.0],
            &[(-10.0, 10.0), (-10.0, 10.0)],
        );
        assert!((result.values[0] - 1.0).abs() < 1e-6, "{:?}", result.values);
        assert!((result.values[1] - 2.0).abs() < 1e-6);
        assert!((result.sse - 4.0).abs() < 1e-9);
        assert!((result.std_errors[1].unwrap() - (0.4f64).sqrt()).abs() < 1e-6);
        assert!((result.std_errors[0].unwrap() - (1.4f64).sqrt()).abs() < 1e-6);
    }

    #[test]
    fn standard_errors_do_not_depend_on_the_units_of_the_parameters() {
        // The same line as above with the intercept in units of 1e-7 and the slope in units
        // of 1e3 (a flow in m³/s beside a viscous coefficient in N·s/m): the errors are the
        // textbook ones in those units, sqrt(1.4)·1e-7 and sqrt(0.4)·1e3. In SI units the
        // normal matrix's diagonal spans 1e20 and looked singular.
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [2.0, 2.0, 4.0, 8.0];
        let result = fit(
            |p| {
                Some(
                    x.iter()
                        .zip(&y)
                        .map(|(x, y)| p[0] * 1e7 + p[1] * 1e-3 * x - y)
                        .collect(),
                )
            },
            &[0.0, 0.0],
            &[(-1e-6, 1e-6), (-1e4, 1e4)],
        );
        assert!(
            (result.values[0] - 1e-7).abs() < 1e-13,
            "{:?}",
            result.values
        );
        assert!((result.values[1] - 2e3).abs() < 1e-3);
        let (se_intercept, se_slope) =
            (result.std_errors[0].unwrap(), result.std_errors[1].unwrap());
        assert!((se_intercept / (1.4f64.sqrt() * 1e-7) - 1.0).abs() < 1e-6);
        assert!((se_slope / (0.4f64.sqrt() * 1e3) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn an_exponential_decay_is_recovered() {
        // Noise-free y = 3 exp(-0.7 t): the minimum is exact.
        let t: Vec<f64> = (0..20).map(|k| k as f64 * 0.25).collect();
        let result = fit(
            |p| {
                Some(
                    t.iter()
                        .map(|&t| p[0] * (-p[1] * t).exp() - 3.0 * (-0.7 * t).exp())
                        .collect(),
                )
            },
            &[1.0, 0.1],
            &[(0.0, 10.0), (0.0, 5.0)],
        );
        assert!((result.values[0] - 3.0).abs() < 1e-5, "{:?}", result.values);
        assert!((result.values[1] - 0.7).abs() < 1e-5);
    }

    /// `r = (x - 1, 10 - 0.04995 (x - 1)²)`: one minimum, at x = 1 with S = 100, where the
    /// Gauss–Newton curvature (1) is a thousand times the true one (1 - 0.999): each step
    /// goes a thousandth of the way, a crawl by construction.
    fn crawl(x: &[f64]) -> Option<Vec<f64>> {
        let e = x[0] - 1.0;
        Some(vec![e, 10.0 - 0.04995 * e * e])
    }

    #[test]
    fn a_crawl_that_cannot_reach_the_bar_ends_its_descent() {
        let settings = Settings::default();
        let (start, bounds) = ([1.5], [(0.0, 3.0)]);
        // Another start of the search is at 50: this descent, at 100 and above, cannot be
        // the search's best.
        let (abandoned, gave_up) =
            least_squares_toward(&mut crawl, &start, &bounds, &settings, 50.0).unwrap();
        assert_eq!(gave_up, Ending::Crawled);
        assert!(abandoned.sse > 100.0, "{}", abandoned.sse);
        // Its pace is measured over five accepted steps of two evaluations (one difference,
        // one trial), after the start's.
        assert!(
            abandoned.evaluations <= 1 + 2 * (PACE_WINDOW + 1),
            "{}",
            abandoned.evaluations
        );
        // Left to itself, it crawls through its sixty iterations and stays far from x = 1.
        let (whole, ending) =
            least_squares_toward(&mut crawl, &start, &bounds, &settings, f64::INFINITY).unwrap();
        assert_eq!(ending, Ending::Unfinished);
        assert!(whole.evaluations >= 100, "{}", whole.evaluations);
        assert!(whole.values[0] > 1.3, "{:?}", whole.values);
        // Below the bar, a crawl is the search's best so far and goes on.
        let (below, kept_on) =
            least_squares_toward(&mut crawl, &start, &bounds, &settings, 200.0).unwrap();
        assert_eq!(kept_on, Ending::Unfinished);
        assert_eq!(below.evaluations, whole.evaluations);
    }

    /// `r = (x - 1, 1 - 0.45 (x - 1)²)`: one minimum, at x = 1 with S = 1. A Gauss–Newton
    /// step goes `(1 - 2ac + 2a²e²)/(1 + 4a²e²)` of the distance `e` to it (a = 0.45,
    /// c = 1): about half of it far away, a tenth near it, so that a descent from afar
    /// slows window after window before it crawls.
    fn slowing(x: &[f64]) -> Option<Vec<f64>> {
        let e = x[0] - 1.0;
        Some(vec![e, 1.0 - 0.45 * e * e])
    }

    #[test]
    fn a_slowing_descent_that_cannot_reach_the_bar_ends_before_it_crawls() {
        // From x = 30 (S about 143,000) with the search's best at 0: the descent's second window
        // of five accepted steps is slower than its first, and at that pace it stays above
        // 0, so it ends there: the start, ten steps of two evaluations (a difference, a
        // trial) and the difference at its end. (Ended only as a crawl, a hundredth a
        // window, it took 34.)
        let settings = Settings::default();
        let (start, bounds) = ([30.0], [(0.0, 31.0)]);
        let (abandoned, gave_up) =
            least_squares_toward(&mut slowing, &start, &bounds, &settings, 0.0).unwrap();
        assert_eq!(gave_up, Ending::Crawled);
        assert_eq!(abandoned.evaluations, 1 + 2 * 2 * PACE_WINDOW + 1);
        // Left to itself it reaches the minimum.
        let whole = least_squares(&mut slowing, &start, &bounds, &settings).unwrap();
        assert!((whole.sse - 1.0).abs() < 1e-3, "{}", whole.sse);
        assert!(abandoned.sse > whole.sse, "{} {}", abandoned.sse, whole.sse);
    }

    #[test]
    fn a_threshold_is_scanned_after_a_crawl_and_the_descent_goes_on_below_the_bar() {
        // The crawl in x beside a threshold t that adds 10 to a residual below t = 0.5: from
        // (1.5, 0.2) the sum of squares is 200, above the bar of 150, and the descent in x
        // crawls; its round ends, the scan moves t past 0.5 (100 less), and from there, below
        // the bar, the next round descends to the end of its iterations.
        let mut thresholded = |x: &[f64]| -> Option<Vec<f64>> {
            let mut r = crawl(&x[..1])?;
            r.push(if x[1] < 0.5 { 10.0 } else { 0.0 });
            Some(r)
        };
        let (fit, crawled) = least_squares_toward(
            &mut thresholded,
            &[1.5, 0.2],
            &[(0.0, 3.0), (0.0, 1.0)],
            &Settings::default(),
            150.0,
        )
        .unwrap();
        assert_ne!(crawled, Ending::Crawled);
        assert!(fit.values[1] >= 0.5, "{:?}", fit.values);
        assert!(fit.sse > 99.0 && fit.sse < 100.1, "{}", fit.sse);
    }

    #[test]
    fn a_steep_descent_from_far_above_the_bar_goes_on() {
        // y = 3 exp(-0.7 t) from (10, 0.05), far above a bar of 0 (another start at the
        // exact optimum): it falls steeply, never crawls, and reaches the optimum.
        let t: Vec<f64> = (0..20).map(|k| k as f64 * 0.25).collect();
        let mut decay = |p: &[f64]| -> Option<Vec<f64>> {
            Some(
                t.iter()
                    .map(|&t| p[0] * (-p[1] * t).exp() - 3.0 * (-0.7 * t).exp())
                    .collect(),
            )
        };
        let (fit, gave_up) = least_squares_toward(
            &mut decay,
            &[10.0, 0.05],
            &[(0.0, 10.0), (0.0, 5.0)],
            &Settings::default(),
            0.0,
        )
        .unwrap();
        assert_eq!(gave_up, Ending::Converged);
        assert!((fit.values[0] - 3.0).abs() < 1e-5, "{:?}", fit.values);
        assert!((fit.values[1] - 0.7).abs() < 1e-5, "{:?}", fit.values);
    }

    #[test]
    fn a_bound_holds_a_parameter_the_data_would_push_past_it() {
        // Data y = -1 with a model y = c, c in [0, 5]: the best c is the bound 0.
        let result = fit(|p| Some(vec![p[0] + 1.0; 4]), &[2.0], &[(0.0, 5.0)]);
        assert_eq!(result.values[0], 0.0);
        assert!(result.at_bound[0]);
        assert_eq!(result.std_errors[0], None);
    }

    #[test]
    fn a_threshold_is_located_by_its_interval() {
        // Rows at "pressures" 1..=10; a row moves (residual 0) when its pressure exceeds
        // the threshold, else it is off by 1. Rows 6..=10 move in the data, so every
        // threshold in [5, 6) fits perfectly and nothing else does.
        let pressures: Vec<f64> = (1..=10).map(f64::from).collect();
        let result = fit(
            |p| {
                Some(
                    pressures
                        .iter()
                        .map(|&x| f64::from(u8::from((x > p[0]) != (x >= 6.0))))
                        .collect(),
                )
            },
            &[2.0],
            &[(0.0, 12.0)],
        );
        assert_eq!(result.sse, 0.0);
        let (lo, hi) = result.intervals[0].unwrap();
        assert!(
            (lo - 5.0).abs() < 0.02 && (hi - 6.0).abs() < 0.02,
            "{lo} {hi}"
        );
        assert!(result.values[0] >= 5.0 && result.values[0] < 6.0);
    }

    /// The rows of [`a_threshold_is_located_by_its_interval`], as a model that predicts them
    /// one at a time: a bounded sum of squares stops once its partial sum is past the limit.
    struct Thresholded {
        rows_predicted: usize,
    }

    impl Thresholded {
        fn row(&mut self, k: usize, threshold: f64) -> f64 {
            self.rows_predicted += 1;
            let x = (k + 1) as f64;
            f64::from(u8::from((x > threshold) != (x >= 6.0)))
        }
    }

    impl ResidualFunction for Thresholded {
        fn residuals(&mut self, p: &[f64]) -> Option<Vec<f64>> {
            Some((0..10).map(|k| self.row(k, p[0])).collect())
        }

        fn sum_of_squares(&mut self, p: &[f64], limit: f64) -> Option<f64> {
            let mut partial = 0.0;
            for k in 0..10 {
                partial += self.row(k, p[0]).powi(2);
                if partial > limit * (1.0 + 1e-9) {
                    break;
                }
            }
            Some(partial)
        }
    }

    #[test]
    fn a_scan_predicts_a_worse_point_only_until_it_is_worse() {
        // The threshold of `a_threshold_is_located_by_its_interval`: from 2 the scan finds
        // [5, 6) whether its points are summed whole or only until they are worse than the
        // best (a point is never needed beyond that), with the same evaluations; bounded,
        // every worse point stops at its first wrong row, so fewer rows are predicted.
        let whole = {
            let mut rows_predicted = 0;
            let fit = least_squares(
                &mut |p: &[f64]| {
                    let mut model = Thresholded { rows_predicted: 0 };
                    let r = model.residuals(p);
                    rows_predicted += model.rows_predicted;
                    r
                },
                &[2.0],
                &[(0.0, 12.0)],
                &Settings::default(),
            )
            .expect("fits");
            (fit, rows_predicted)
        };
        let mut model = Thresholded { rows_predicted: 0 };
        let bounded =
            least_squares(&mut model, &[2.0], &[(0.0, 12.0)], &Settings::default()).expect("fits");
        assert_eq!(bounded.sse, 0.0);
        assert_eq!(bounded.values, whole.0.values);
        assert_eq!(bounded.intervals, whole.0.intervals);
        assert_eq!(bounded.evaluations, whole.0.evaluations);
        let (lo, hi) = bounded.intervals[0].unwrap();
        assert!(
            (lo - 5.0).abs() < 0.02 && (hi - 6.0).abs() < 0.02,
            "{lo} {hi}"
        );
        // The grid's points outside [5, 6) and the bisections' bad halves stop at the row
        // that puts them past the best (542 rows of 720 when written).
        assert!(
            model.rows_predicted < whole.1,
            "{} rows predicted bounded, {} whole",
            model.rows_predicted,
            whole.1
        );
    }

    #[test]
    fn a_threshold_between_two_scan_points_is_found() {
        // A contact pushed by 1..=20 N: stuck up to its breakaway force F_S = x[2], sliding
        // above at (P - F_C)/b; undefined for F_C > F_S. The data: F_C = F_S = 9, b = 2. From
        // (0, 25, 15) the descent reaches F_C = 9, b = 2 with F_S at 10, where the row P = 10
        // sticks (residual -0.5); every value in (9, 10) fits exactly, but the scan's grid
        // (1.25 N apart) has no point there: the bisection towards the infeasible 8.75 N
        // passes through them and must keep what it finds.
        let velocity = |p: f64, x: &[f64]| if p <= x[2] { 0.0 } else { (p - x[0]) / x[1] };
        let result = fit(
            |x| {
                (x[0] <= x[2]).then(|| {
                    (1..=20)
                        .map(|p| {
                            let p = f64::from(p);
                            velocity(p, x) - velocity(p, &[9.0, 2.0, 9.0])
                        })
                        .collect()
                })
            },
            &[0.0, 25.0, 15.0],
            &[(0.0, 30.0), (0.1, 50.0), (0.0, 30.0)],
        );
        assert!(result.sse < 1e-20, "{result:?}");
        assert!((result.values[0] - 9.0).abs() < 1e-9);
        assert!((result.values[1] - 2.0).abs() < 1e-9);
        let (lo, hi) = result.intervals[2].unwrap();
        assert!(
            (lo - 9.0).abs() < 0.01 && (hi - 10.0).abs() < 0.01,
            "{lo} {hi}"
        );
    }

    #[test]
    fn a_parameter_that_only_rounding_moves_does_not_stall_the_others() {
        // The line of the first test, plus a parameter c whose whole effect is rounding
        // (1e-11 per unit) and which cannot be evaluated above 0.6 (as a friction model
        // cannot with its Coulomb force above its breakaway force). Its tiny curvature must
        // not throw c to its bound at every trial: the line is still fitted exactly.
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [2.0, 2.0, 4.0, 8.0];
        let result = fit(
            |p| {
                (p[2] <= 0.6).then(|| {
                    x.iter()
                        .zip(&y)
                        .map(|(x, y)| p[0] + p[1] * x - y + 1e-11 * p[2] * x)
                        .collect()
                })
            },
            &[0.0, 0.0, 0.5],
            &[(-10.0, 10.0), (-10.0, 10.0), (0.0, 1.0)],
        );
        assert!((result.values[0] - 1.0).abs() < 1e-6, "{:?}", result.values);
        assert!((result.values[1] - 2.0).abs() < 1e-6, "{:?}", result.values);
    }

    #[test]
    fn a_parameter_the_residuals_barely_move_leaves_the_others_their_errors() {
        // The line of the first test plus 2.6e-6·c·g with g = (1, 1, 0, 0), orthogonal to
        // the line's residuals (+1, -1, -1, +1) and outside the span of 1 and x: c changes
        // the fit by nothing that matters, and its Jacobian column is 1e-7 of the slope's in
        // norm, which makes the 3×3 normal matrix numerically singular. c is undetermined;
        // a and b keep the textbook errors of the line, SE(b) = sqrt(2/5), SE(a) = sqrt(1.4)
        // (σ̂² = SSE/(n - 2) = 4/2).
        let x = [0.0, 1.0, 2.0, 3.0];
        let g = [1.0, 1.0, 0.0, 0.0];
        let y = [2.0, 2.0, 4.0, 8.0];
        let result = fit(
            |p| {
                Some(
                    (0..4)
                        .map(|i| p[0] + p[1] * x[i] + 2.6e-6 * p[2] * g[i] - y[i])
                        .collect(),
                )
            },
            &[0.0, 0.0, 0.5],
            &[(-10.0, 10.0), (-10.0, 10.0), (-1.0, 1.0)],
        );
        assert!((result.sse - 4.0).abs() < 1e-9, "{result:?}");
        assert_eq!(result.std_errors[2], None);
        let (se_a, se_b) = (result.std_errors[0].unwrap(), result.std_errors[1].unwrap());
        assert!((se_b - 0.4f64.sqrt()).abs() < 1e-6, "{se_b}");
        assert!((se_a - 1.4f64.sqrt()).abs() < 1e-6, "{se_a}");
    }

    #[test]
    fn a_slope_at_a_face_is_taken_from_the_side_that_can_be_evaluated() {
        // y = c·x with c the data's 2, and the model undefined for c > 2 (a Coulomb force
        // tied to its breakaway force): c's column comes from the backward difference, so c
        // is fitted smoothly with its error, not scanned as a threshold. The residuals
        // (0, -0.1, 0.1) are orthogonal to x = (1, 2, 2), so c stays at 2 with
        // SE = sqrt(σ̂²/Σx²) = sqrt((0.02/2)/9).
        let x = [1.0, 2.0, 2.0];
        let y = [2.0, 4.1, 3.9];
        let result = fit(
            |p| (p[0] <= 2.0).then(|| x.iter().zip(&y).map(|(x, y)| p[0] * x - y).collect()),
            &[2.0],
            &[(0.0, 5.0)],
        );
        assert!((result.values[0] - 2.0).abs() < 1e-9, "{result:?}");
        assert_eq!(result.intervals[0], None);
        let se = result.std_errors[0].unwrap();
        assert!((se - (0.01f64 / 9.0).sqrt()).abs() < 1e-6, "{se}");
    }

    #[test]
    fn aliased_parameters_have_no_standard_errors() {
        // y = (a + b) x: only the sum is determined.
        let x = [1.0, 2.0, 3.0];
        let result = fit(
            |p| {
                Some(
                    x.iter()
                        .map(|x| (p[0] + p[1]) * x - 3.0 * x + 0.01 * x * x)
                        .collect(),
                )
            },
            &[0.5, 0.5],
            &[(0.0, 10.0), (0.0, 10.0)],
        );
        assert!((result.values[0] + result.values[1] - 3.0).abs() < 0.1);
        assert_eq!(result.std_errors, vec![None, None]);
    }
}
