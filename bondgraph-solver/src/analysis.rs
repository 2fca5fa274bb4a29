//! The numbers of a linear mode's analysis: eigenvalues and their time scales, roots of
//! polynomials, the exact step response and its metrics, and the frequency response.
//!
//! Poles are the eigenvalues of the state matrix that the transfer function keeps
//! ([`poles`]), not the roots of its denominator: a matrix balances (its eigenvalues come out
//! to their own precision on stiff modes) where a polynomial's coefficients spanning 1e301
//! lose the small roots. Polynomials are handled with coefficients in extended range
//! ([`Scaled`]) and the variable rescaled, so that coefficients beyond `f64` (the
//! characteristic polynomial of a 1e-300 kg mass) still give their roots and frequency
//! response; every root is then polished by Newton's method on the polynomial itself.
//!
//! The step response is the closed-form solution of `dx/dt = A x + b u + e du/dt`,
//! `y = c x + d u + f du/dt` from rest under a unit step, evaluated by the exact modal
//! propagator the simulator uses ([`crate::propagate`]): not a sampled simulation, so a
//! metric is as accurate as the root finding on the exact `y(t)` that produces it. The step's
//! rate is an impulse, so `e` makes the state jump to `e` at `0⁺` and `f` puts an impulse of
//! weight `f` into `y` at `t = 0` (reported, not plotted).

use bondgraph_core::symbolic::Scaled;
use nalgebra::{DMatrix, DVector};
pub use num_complex::Complex64;

use crate::linalg::{self, EigenError};
use crate::propagate::Propagator;

/// Why the numbers of an analysis could not be computed.
#[derive(Clone, Debug, PartialEq)]
pub enum AnalysisError {
    /// A matrix entry or polynomial coefficient is infinite or NaN (or the polynomial's
    /// coefficients span more than doubles can hold, even rescaled).
    NonFinite,
    /// The eigenvalue iteration did not converge within its budget.
    NoConvergence,
}

impl std::fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AnalysisError::NonFinite => write!(
                f,
                "a matrix entry or polynomial coefficient is not finite in double precision"
            ),
            AnalysisError::NoConvergence => write!(
                f,
                "the eigenvalue iteration did not converge in {SCHUR_ITERATIONS} iterations"
            ),
        }
    }
}

impl std::error::Error for AnalysisError {}

/// The budget of the real Schur iteration where the eigendecomposition fails.
const SCHUR_ITERATIONS: usize = 10_000;

/// Newton steps that polish a root on its polynomial.
const POLISH_STEPS: usize = 8;

/// One eigenvalue (or pole) and the time scales it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scale {
    /// The eigenvalue `λ`, 1/s.
    pub value: Complex64,
    /// `1/|Re λ|` in s (`None` for `Re λ = 0`): the decay (or growth) time of the mode.
    pub time_constant: Option<f64>,
    /// `|λ|` in rad/s.
    pub natural_frequency: f64,
    /// `-Re λ / |λ|` (`None` for `λ = 0`): 1 for a real decaying mode, below 1 for an
    /// oscillating one, negative for a growing one.
    pub damping_ratio: Option<f64>,
}

impl Scale {
    /// The time scales of `value`.
    pub fn of(value: Complex64) -> Self {
        let magnitude = value.norm();
        Scale {
            value,
            time_constant: (value.re != 0.0).then(|| 1.0 / value.re.abs()),
            natural_frequency: magnitude,
            damping_ratio: (magnitude > 0.0).then(|| -value.re / magnitude),
        }
    }
}

/// The eigenvalues of the square matrix with rows `rows`, as [`eigenvalues`].
///
/// # Errors
/// As [`eigenvalues`].
pub fn eigenvalues_of(rows: &[Vec<f64>]) -> Result<Vec<Complex64>, AnalysisError> {
    eigenvalues(&matrix(rows))
}

fn matrix(rows: &[Vec<f64>]) -> DMatrix<f64> {
    let columns = rows.first().map_or(0, Vec::len);
    DMatrix::from_fn(rows.len(), columns, |i, j| rows[i][j])
}

/// The eigenvalues of `a`, sorted by real part then imaginary part; accurate on stiff
/// matrices ([`linalg::eigen`]), from the real Schur form where `a` is defective.
///
/// # Errors
/// [`AnalysisError::NonFinite`] for a matrix with an infinite or NaN entry,
/// [`AnalysisError::NoConvergence`] when the Schur iteration exhausts its budget.
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex64>, AnalysisError> {
    if a.nrows() == 0 {
        return Ok(Vec::new());
    }
    let mut values = match linalg::eigen(a) {
        Ok(eigen) => eigen.values,
        Err(EigenError::NonFinite) => return Err(AnalysisError::NonFinite),
        Err(_) => {
            let (balanced, _) = linalg::balance(a);
            nalgebra::Schur::try_new(balanced, f64::EPSILON, SCHUR_ITERATIONS)
                .map(|s| s.complex_eigenvalues().iter().copied().collect())
                .ok_or(AnalysisError::NoConvergence)?
        }
    };
    sort(&mut values);
    Ok(values)
}

/// Sorts, after snapping parts of rounding size (relative to the value) to zero, so that a
/// pendulum's `±3.13i` does not print with a real part of `1e-33`.
fn sort(values: &mut [Complex64]) {
    for v in values.iter_mut() {
        let size = v.norm();
        if v.re.abs() <= 1e-12 * size {
            v.re = 0.0;
        }
        if v.im.abs() <= 1e-12 * size {
            v.im = 0.0;
        }
    }
    values.sort_by(|x, y| {
        x.re.partial_cmp(&y.re)
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(x.im.partial_cmp(&y.im).unwrap_or(std::cmp::Ordering::Equal))
    });
}

/// The roots of the polynomial with `coefficients` (highest power first), as
/// [`roots_scaled`].
///
/// # Errors
/// As [`roots_scaled`].
pub fn roots(coefficients: &[f64]) -> Result<Vec<Complex64>, AnalysisError> {
    let scaled: Vec<Scaled> = coefficients.iter().map(|c| Scaled::from_f64(*c)).collect();
    roots_scaled(&scaled)
}

/// The roots of the polynomial with `coefficients` (highest power first, in extended
/// range), sorted as [`eigenvalues`]. Leading zero coefficients are dropped; trailing ones
/// are exact roots at zero. The variable is rescaled by a power of two (`s = σ t`, σ the
/// geometric mean of the roots' sizes) so that the coefficients fit in `f64`; degrees one
/// and two are solved by formula, higher ones as the companion matrix's eigenvalues; every
/// root is then polished by Newton's method on the polynomial itself.
///
/// # Errors
/// [`AnalysisError::NonFinite`] for a coefficient that is infinite or NaN, or coefficients
/// that span more than doubles hold even rescaled; [`AnalysisError::NoConvergence`] as
/// [`eigenvalues`].
pub fn roots_scaled(coefficients: &[Scaled]) -> Result<Vec<Complex64>, AnalysisError> {
    if coefficients.iter().any(|c| !c.is_finite()) {
        return Err(AnalysisError::NonFinite);
    }
    let start = coefficients
        .iter()
        .position(|c| !c.is_zero())
        .unwrap_or(coefficients.len());
    let mut p = &coefficients[start..];
    let mut out = Vec::new();
    while p.len() > 1 && p[p.len() - 1].is_zero() {
        out.push(Complex64::new(0.0, 0.0));
        p = &p[..p.len() - 1];
    }
    if p.len() > 1 {
        let degree = p.len() - 1;
        // σ = 2^e with e near log2(|constant/leading|)/degree: the product of the roots'
        // sizes is |constant/leading|, so σ is their geometric mean.
        let e = ((p[degree].log2_abs() - p[0].log2_abs()) / degree as f64).round() as i64;
        let rescaled: Vec<Scaled> = p
            .iter()
            .enumerate()
            .map(|(i, c)| c.times_power_of_two(e * (degree - i) as i64))
            .collect();
        let largest = rescaled
            .iter()
            .map(|c| c.abs())
            .fold(Scaled::ZERO, |a, b| if b > a { b } else { a });
        let unit = largest.log2_abs().round() as i64;
        let q: Vec<f64> = rescaled.iter().map(|c| c.mantissa_at(unit)).collect();
        if q[0] == 0.0 || q.iter().any(|c| !c.is_finite()) {
            return Err(AnalysisError::NonFinite);
        }
        let mut found = f64_roots(&q)?;
        let sigma = Scaled::ONE.times_power_of_two(e).to_f64();
        for z in &mut found {
            *z *= sigma;
        }
        polish(p, &mut found);
        out.extend(found);
    }
    sort(&mut out);
    Ok(out)
}

/// The roots of `p` (highest power first, `p[0] ≠ 0`, coefficients of moderate size).
fn f64_roots(p: &[f64]) -> Result<Vec<Complex64>, AnalysisError> {
    let mut out = Vec::new();
    match p.len() {
        0 | 1 => {}
        2 => out.push(Complex64::new(-p[1] / p[0], 0.0)),
        3 => {
            let (a, b, c) = (p[0], p[1], p[2]);
            let discriminant = b * b - 4.0 * a * c;
            if discriminant >= 0.0 {
                // The root of larger magnitude first, then c/(a r) without cancellation.
                let q = -0.5 * (b + b.signum() * discriminant.sqrt());
                let q = if q == 0.0 {
                    -0.5 * discriminant.sqrt()
                } else {
                    q
                };
                out.push(Complex64::new(q / a, 0.0));
                out.push(Complex64::new(if q == 0.0 { 0.0 } else { c / q }, 0.0));
            } else {
                let re = -b / (2.0 * a);
                let im = (-discriminant).sqrt() / (2.0 * a.abs());
                out.push(Complex64::new(re, -im));
                out.push(Complex64::new(re, im));
            }
        }
        n => {
            let degree = n - 1;
            let mut companion = DMatrix::<f64>::zeros(degree, degree);
            for j in 0..degree {
                companion[(0, j)] = -p[j + 1] / p[0];
            }
            for i in 1..degree {
                companion[(i, i - 1)] = 1.0;
            }
            out.extend(eigenvalues(&companion)?);
        }
    }
    Ok(out)
}

/// `p(z)` for coefficients highest power first.
pub fn evaluate(coefficients: &[f64], z: Complex64) -> Complex64 {
    coefficients
        .iter()
        .fold(Complex64::new(0.0, 0.0), |acc, c| acc * z + c)
}

/// `p(z)` for `z ≠ 0` as `scale · value`, with `|value| ≤ Σ |terms| / scale ≤ degree + 1`:
/// the polynomial's terms `cₖ zᵏ` divided by the largest term's size before they are
/// summed, so that neither the coefficients nor the powers overflow. Also returns
/// `Σ k cₖ zᵏ / scale` (for `p'(z) = that · scale / z`) and `Σ |cₖ zᵏ| / scale`.
struct Terms {
    scale: Scaled,
    value: Complex64,
    weighted: Complex64,
    size: f64,
}

fn terms(p: &[Scaled], z: Complex64) -> Terms {
    let degree = p.len().saturating_sub(1);
    let r = Scaled::from_f64(z.norm());
    let sizes: Vec<Scaled> = p
        .iter()
        .enumerate()
        .map(|(i, c)| c.abs() * r.powi((degree - i) as u32))
        .collect();
    let scale = sizes
        .iter()
        .copied()
        .fold(Scaled::ZERO, |a, b| if b > a { b } else { a });
    let unit = z / z.norm();
    let mut value = Complex64::new(0.0, 0.0);
    let mut weighted = Complex64::new(0.0, 0.0);
    let mut size = 0.0;
    if scale.is_zero() {
        return Terms {
            scale,
            value,
            weighted,
            size,
        };
    }
    for (i, (c, t)) in p.iter().zip(&sizes).enumerate() {
        let power = (degree - i) as i32;
        let magnitude = (*t / scale).to_f64();
        let signed = if *c < Scaled::ZERO {
            -magnitude
        } else {
            magnitude
        };
        let term = unit.powi(power) * signed;
        value += term;
        weighted += term * f64::from(power);
        size += magnitude;
    }
    Terms {
        scale,
        value,
        weighted,
        size,
    }
}

/// `|p(z)| / Σ |cₖ zᵏ|`: 0 at a root, of rounding size near one, up to 1 elsewhere.
fn relative_residual(p: &[Scaled], z: Complex64) -> f64 {
    if z == Complex64::new(0.0, 0.0) {
        return match p.last() {
            Some(c) if !c.is_zero() => 1.0,
            _ => 0.0,
        };
    }
    let t = terms(p, z);
    if t.size == 0.0 {
        0.0
    } else {
        t.value.norm() / t.size
    }
}

/// Newton's step `p(z)/p'(z)`, or `None` where `p'(z)` vanishes.
fn newton_step(p: &[Scaled], z: Complex64) -> Option<Complex64> {
    let n = p.len();
    if n < 2 {
        return None;
    }
    if z == Complex64::new(0.0, 0.0) {
        let (c0, c1) = (p[n - 1], p[n - 2]);
        if c1.is_zero() {
            return None;
        }
        return Some(Complex64::new((c0 / c1).to_f64(), 0.0));
    }
    let t = terms(p, z);
    if t.weighted == Complex64::new(0.0, 0.0) {
        return None;
    }
    // p/p' = (value · scale) / (weighted · scale / z) = z · value / weighted.
    let step = z * (t.value / t.weighted);
    (step.re.is_finite() && step.im.is_finite()).then_some(step)
}

/// Polishes each of `roots` by Newton's method on `p` while the relative residual falls,
/// and only by steps well short of the distance to the next root (so that no root moves
/// onto another). A real root stays real.
fn polish(p: &[Scaled], roots: &mut [Complex64]) {
    let original = roots.to_vec();
    for (k, z) in roots.iter_mut().enumerate() {
        let reach = original
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != k)
            .map(|(_, w)| (*w - original[k]).norm())
            .fold(f64::INFINITY, f64::min)
            / 4.0;
        // At a root to full precision the relative residual is of rounding size; a step
        // from there would only move the root by rounding noise.
        let rounding = p.len() as f64 * f64::EPSILON;
        let mut residual = relative_residual(p, *z);
        for _ in 0..POLISH_STEPS {
            if residual <= rounding {
                break;
            }
            let Some(mut step) = newton_step(p, *z) else {
                break;
            };
            if z.im == 0.0 {
                step.im = 0.0;
            }
            let next = *z - step;
            let next_residual = relative_residual(p, next);
            if (next - original[k]).norm() > reach || next_residual >= residual {
                break;
            }
            *z = next;
            residual = next_residual;
        }
    }
}

/// `values` (eigenvalues of a matrix) polished by Newton's method on `polynomial` (its
/// characteristic polynomial, highest power first), sorted: an eigenvalue far below the
/// matrix's own precision (`-2.5e-308` beside `±7i`) comes out to the polynomial's.
pub fn polished(values: &[Complex64], polynomial: &[Scaled]) -> Vec<Complex64> {
    let mut out = values.to_vec();
    polish(polynomial, &mut out);
    sort(&mut out);
    out
}

/// The poles of a transfer function whose states have `eigenvalues`: all of them (with an
/// extra 0 for an integral output, which the caller appends) but the roots of `cancelled`,
/// the factor that cancelled between numerator and denominator (highest power first; `[1]`
/// when none did). Which eigenvalues cancelled is read off `cancelled`'s residuals, one
/// root at a time; the poles kept are then polished on `denominator` (the transfer
/// function's, highest power first).
pub fn poles(
    eigenvalues: &[Complex64],
    cancelled: &[Scaled],
    denominator: &[Scaled],
) -> Vec<Complex64> {
    let start = cancelled
        .iter()
        .position(|c| !c.is_zero())
        .unwrap_or(cancelled.len());
    let cancelled = &cancelled[start..];
    let count = cancelled.len().saturating_sub(1).min(eigenvalues.len());
    let mut residuals: Vec<(f64, usize)> = eigenvalues
        .iter()
        .enumerate()
        .map(|(i, z)| (relative_residual(cancelled, *z), i))
        .collect();
    residuals.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let dropped: Vec<usize> = residuals.iter().take(count).map(|(_, i)| *i).collect();
    let mut kept: Vec<Complex64> = eigenvalues
        .iter()
        .enumerate()
        .filter(|(i, _)| !dropped.contains(i))
        .map(|(_, z)| *z)
        .collect();
    polish(denominator, &mut kept);
    sort(&mut kept);
    kept
}

/// One input-output channel with numbers, for its step response.
#[derive(Clone, Debug)]
pub struct StepSystem {
    /// `A` (states × states), by rows.
    pub a: Vec<Vec<f64>>,
    /// The input's column of `B`.
    pub b: Vec<f64>,
    /// The input's column of `E`.
    pub e: Vec<f64>,
    /// The output's row of `C`.
    pub c: Vec<f64>,
    /// The output's `D` entry.
    pub d: f64,
    /// The output's `F` entry: the weight of the impulse in `y` at `t = 0`.
    pub f: f64,
    /// Whether the output is the time integral of `c x + d u + f du/dt`.
    pub integral: bool,
}

/// The exact unit-step response of a [`StepSystem`], evaluable at any time.
pub struct StepResponse {
    propagator: Propagator,
    x0: Vec<f64>,
    c: Vec<f64>,
    d: f64,
}

impl StepSystem {
    /// The response to a unit step at `t = 0` from rest.
    pub fn response(&self) -> StepResponse {
        let n = self.a.len();
        let a_n = matrix(&self.a);
        if !self.integral {
            return StepResponse {
                propagator: Propagator::new(
                    &a_n,
                    &DMatrix::from_column_slice(n, 1, &self.b),
                    &DVector::zeros(n),
                ),
                x0: self.e.clone(),
                c: self.c.clone(),
                d: self.d,
            };
        }
        // The integral as one more state: dz/dt = c x + d u, z(0+) = f.
        let mut a = DMatrix::<f64>::zeros(n + 1, n + 1);
        a.view_mut((0, 0), (n, n)).copy_from(&a_n);
        for j in 0..n {
            a[(n, j)] = self.c[j];
        }
        let mut b = DMatrix::<f64>::zeros(n + 1, 1);
        for i in 0..n {
            b[(i, 0)] = self.b[i];
        }
        b[(n, 0)] = self.d;
        let mut x0 = self.e.clone();
        x0.push(self.f);
        let mut c = vec![0.0; n + 1];
        c[n] = 1.0;
        StepResponse {
            propagator: Propagator::new(&a, &b, &DVector::zeros(n + 1)),
            x0,
            c,
            d: 0.0,
        }
    }
}

impl StepResponse {
    /// `y(t)` at each of `times` (s, from `0⁺`).
    pub fn at(&self, times: &[f64]) -> Vec<f64> {
        let mut segment = self.propagator.start(&self.x0, &[1.0], &[0.0]);
        let mut x = vec![0.0; self.x0.len()];
        times
            .iter()
            .map(|&t| {
                segment.state_into(t, &mut x);
                self.c.iter().zip(&x).map(|(c, x)| c * x).sum::<f64>() + self.d
            })
            .collect()
    }

    fn one(&self, t: f64) -> f64 {
        self.at(&[t])[0]
    }
}

/// Step-response metrics; `None` where a metric is not defined (an unstable or undamped
/// response has no final value; a zero final value no rise time or overshoot).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepMetrics {
    /// `y(0⁺)`.
    pub initial_value: f64,
    /// The value `y` settles to (the DC gain), if it settles.
    pub final_value: Option<f64>,
    /// Time from 10 % to 90 % of the final value, s.
    pub rise_time: Option<f64>,
    /// Last time `y` is outside ±2 % of the final value, s.
    pub settling_time: Option<f64>,
    /// Largest excess over the final value, percent of it (0 if none).
    pub overshoot_percent: Option<f64>,
    /// When the largest excess occurs, s.
    pub peak_time: Option<f64>,
    /// The response's value there.
    pub peak_value: Option<f64>,
    /// The time span the metrics looked at (and a plot should show), s.
    pub horizon: f64,
}

/// The metrics of the step response of `system`, whose transfer function has `poles` and
/// DC gain `dc_gain`.
///
/// # Errors
/// [`AnalysisError::NonFinite`] when the closed form does not give a finite response (a
/// mode beyond what double precision can propagate), rather than metrics of NaN.
///
/// # Complexity
/// A few thousand evaluations of the closed form, each `O(n²)`, plus bisections.
pub fn step_metrics(
    system: &StepSystem,
    poles: &[Complex64],
    dc_gain: Option<f64>,
) -> Result<StepMetrics, AnalysisError> {
    let response = system.response();
    let initial_value = response.one(0.0);
    if !initial_value.is_finite() {
        return Err(AnalysisError::NonFinite);
    }
    let stable = poles.iter().all(|p| p.re < 0.0);
    let nonzero: Vec<f64> = poles
        .iter()
        .map(|p| p.norm())
        .filter(|m| *m > 0.0)
        .collect();
    let slowest_decay = poles
        .iter()
        .map(|p| p.re.abs())
        .filter(|r| *r > 0.0)
        .fold(f64::INFINITY, f64::min);
    let fastest = nonzero.iter().copied().fold(0.0, f64::max);
    let horizon = if slowest_decay.is_finite() {
        8.0 / slowest_decay
    } else if let Some(slowest) = nonzero.iter().copied().reduce(f64::min) {
        // Undamped oscillation: a few periods.
        4.0 * std::f64::consts::TAU / slowest
    } else {
        1.0
    };
    // A mode slower than any time a double holds: look as far as doubles reach.
    let mut horizon = horizon.min(LONGEST_HORIZON);
    let mut metrics = StepMetrics {
        initial_value,
        horizon,
        ..StepMetrics::default()
    };
    let final_value = match (stable, dc_gain) {
        (true, Some(g)) => g,
        _ => return Ok(metrics),
    };
    metrics.final_value = Some(final_value);
    if poles.is_empty() {
        // A static gain (or no dynamics the output sees): at its final value from 0⁺.
        metrics.rise_time = (final_value != 0.0).then_some(0.0);
        metrics.settling_time = Some(0.0);
        metrics.overshoot_percent = (final_value != 0.0).then_some(0.0);
        return Ok(metrics);
    }
    if final_value == 0.0 {
        return Ok(metrics);
    }
    let r = |t: f64| response.one(t) / final_value;
    for _ in 0..8 {
        let times = grid(horizon, fastest);
        let values: Vec<f64> = response
            .at(&times)
            .iter()
            .map(|y| y / final_value)
            .collect();
        if values.iter().any(|v| !v.is_finite()) {
            return Err(AnalysisError::NonFinite);
        }
        let outside = values.iter().rposition(|v| (v - 1.0).abs() > 0.02);
        if outside == Some(values.len() - 1) {
            if horizon >= LONGEST_HORIZON {
                // Not settled by the end of time in doubles: no metric to give.
                metrics.horizon = horizon;
                return Ok(metrics);
            }
            horizon = (horizon * 2.0).min(LONGEST_HORIZON);
            continue;
        }
        metrics.horizon = horizon;
        let crossing = |level: f64| -> Option<f64> {
            let k = values.iter().position(|v| *v >= level)?;
            if k == 0 {
                return Some(0.0);
            }
            Some(bisect(&|t| r(t) - level, times[k - 1], times[k]))
        };
        if let (Some(t10), Some(t90)) = (crossing(0.1), crossing(0.9)) {
            metrics.rise_time = Some(t90 - t10);
        }
        metrics.settling_time = Some(match outside {
            None => 0.0,
            Some(k) => bisect(&|t| (r(t) - 1.0).abs() - 0.02, times[k], times[k + 1]),
        });
        let (k, peak) = values
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |best, (i, v)| {
                if *v > best.1 { (i, *v) } else { best }
            });
        if peak > 1.0 {
            let lo = times[k.saturating_sub(1)];
            let hi = times[(k + 1).min(times.len() - 1)];
            let t = golden_max(&r, lo, hi);
            let value = r(t).max(peak);
            metrics.overshoot_percent = Some((value - 1.0) * 100.0);
            metrics.peak_time = Some(t);
            metrics.peak_value = Some(value * final_value);
        } else {
            metrics.overshoot_percent = Some(0.0);
        }
        return Ok(metrics);
    }
    Ok(metrics)
}

/// The longest span the step metrics look at, s: the largest double.
const LONGEST_HORIZON: f64 = f64::MAX;

/// Evaluation times on `[0, horizon]`: uniform, plus logarithmic from the fastest pole's
/// time scale so that fast transients are not stepped over.
fn grid(horizon: f64, fastest: f64) -> Vec<f64> {
    let mut times: Vec<f64> = (0..=4000).map(|i| horizon * (i as f64 / 4000.0)).collect();
    if fastest > 0.0 {
        let start = (0.01 / fastest).min(horizon / 4000.0);
        let decades = (horizon / start).log10();
        let count = (decades * 50.0).ceil().max(1.0) as usize;
        times.extend((0..=count).map(|i| start * 10f64.powf(decades * i as f64 / count as f64)));
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// A root of `g` in `[lo, hi]` where `g` changes sign, by bisection to rounding.
fn bisect(g: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let g_lo = g(lo);
    for _ in 0..200 {
        let mid = lo + 0.5 * (hi - lo);
        if mid <= lo || mid >= hi {
            break;
        }
        if (g(mid) > 0.0) == (g_lo > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo + 0.5 * (hi - lo)
}

/// The maximiser of a unimodal `g` on `[lo, hi]`, by golden-section search.
fn golden_max(g: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        if hi - lo <= 1e-15 * hi.abs().max(f64::MIN_POSITIVE) {
            break;
        }
        let a = hi - ratio * (hi - lo);
        let b = lo + ratio * (hi - lo);
        if g(a) >= g(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    lo + 0.5 * (hi - lo)
}

/// One point of a Bode plot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodePoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// `20 log₁₀ |G(jω)|`, dB.
    pub magnitude_db: f64,
    /// `arg G(jω)`, degrees, unwrapped along the frequencies.
    pub phase_deg: f64,
}

/// The frequency response of `numerator / denominator` (highest power first) over the
/// frequencies its nonzero poles and zeros span, two decades either side; as
/// [`bode_scaled`].
pub fn bode(numerator: &[f64], denominator: &[f64], singularities: &[Complex64]) -> Vec<BodePoint> {
    let scaled = |p: &[f64]| -> Vec<Scaled> { p.iter().map(|c| Scaled::from_f64(*c)).collect() };
    bode_scaled(&scaled(numerator), &scaled(denominator), singularities)
}

/// `N(z)/D(z)` without overflow in between: each polynomial's terms are summed relative
/// to its largest, and only the ratio of the two scales is rounded to `f64`.
pub fn ratio_at(numerator: &[Scaled], denominator: &[Scaled], z: Complex64) -> Complex64 {
    let (direction, scale) = ratio_parts(numerator, denominator, z);
    direction * scale.to_f64()
}

/// `N(z)/D(z)` as `direction · scale`, `direction` of moderate size.
fn ratio_parts(numerator: &[Scaled], denominator: &[Scaled], z: Complex64) -> (Complex64, Scaled) {
    if z == Complex64::new(0.0, 0.0) {
        let (n, d) = (
            numerator.last().copied().unwrap_or(Scaled::ZERO),
            denominator.last().copied().unwrap_or(Scaled::ZERO),
        );
        return (Complex64::new(1.0, 0.0), n / d);
    }
    let (n, d) = (terms(numerator, z), terms(denominator, z));
    (n.value / d.value, n.scale / d.scale)
}

/// The frequency response of `numerator / denominator` (highest power first, in extended
/// range) over the frequencies its nonzero poles and zeros span, two decades either side.
/// Evaluated by [`ratio_at`], so that coefficients and powers of `jω` beyond `f64` do not
/// overflow.
pub fn bode_scaled(
    numerator: &[Scaled],
    denominator: &[Scaled],
    singularities: &[Complex64],
) -> Vec<BodePoint> {
    let magnitudes: Vec<f64> = singularities
        .iter()
        .map(|z| z.norm())
        .filter(|m| *m > 0.0 && m.is_finite())
        .collect();
    let lo = magnitudes.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = magnitudes.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = if lo.is_finite() {
        (lo / 100.0, hi * 100.0)
    } else {
        (0.1, 10.0)
    };
    let decades = (hi / lo).log10();
    let count = ((decades * 60.0).ceil() as usize).clamp(100, 1500);
    let mut out: Vec<BodePoint> = Vec::with_capacity(count + 1);
    let mut previous: Option<f64> = None;
    for i in 0..=count {
        let omega = lo * 10f64.powf(decades * i as f64 / count as f64);
        let s = Complex64::new(0.0, omega);
        let (direction, scale) = ratio_parts(numerator, denominator, s);
        let g = direction * scale.to_f64().signum();
        let mut phase = g.arg().to_degrees();
        if let Some(p) = previous {
            while phase - p > 180.0 {
                phase -= 360.0;
            }
            while phase - p < -180.0 {
                phase += 360.0;
            }
        }
        previous = Some(phase);
        out.push(BodePoint {
            omega,
            magnitude_db: 20.0
                * (direction.norm().log10() + scale.log2_abs() * std::f64::consts::LOG10_2),
            phase_deg: phase,
        });
    }
    out
}
