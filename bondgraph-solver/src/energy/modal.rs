//! The books of a diagonalisable linear mode in closed form.
//!
//! Over a stretch `[a, a + h]` of a segment, in the stretch's own time `s = t h`, each
//! eigen-coordinate is `z(s) = e^{λs} z(a) + s φ₁(λs) w₀ + s² φ₂(λs) w₁`
//! (`w₀` the forcing at `a`), written in one of two forms:
//!
//! - **slow** (`|λh| ≤ 1`): its Taylor polynomial in `t`, of the degree that leaves less
//!   than 1e-17 of the terms' size (at most 18, since `|λh| ≤ 1`);
//! - **fast** (`|λh| > 1`): `α e^{λs} + β + γ s`, `β = -(w₀ + w₁/λ)/λ`, `γ = -w₁/λ`, the
//!   exponential anchored at the stretch's start (`α = z(a) - β`) when it decays and at its
//!   end (`z(a + h) - β - γh`) when it grows, so that no factor exceeds one. Writing `α`
//!   out costs at most `|w₀/λ| + |w₁/λ²|`, no more than the forcing's own size over the
//!   stretch once `|λh| > 1`.
//!
//! A port's effort or flow is then `Re Σ_fast A_j e^{λ_j s} + Σ_k R_k tᵏ`, and the integral of
//! a product needs three kinds of closed forms: `∫ e^{(λ_i+λ_j)s} ds = h φ₁((λ_i+λ_j)h)` (and
//! with `λ̄_j`, for `Re a Re b = (Re ab + Re a b̄)/2`), the moments `∫₀¹ tᵏ e^{xt} dt`
//! ([`moments`]), and `∫₀¹ t^{k+l} dt`. None of them depends on how many oscillations the
//! stretch holds.

use num_complex::Complex64;

use crate::numeric::{NumericMode, Row, dot};
use crate::propagate::{Segment, phis};

use super::Increment;

/// Past this `|λh|` a coordinate is fast.
const FAST: f64 = 1.0;
/// What a slow coordinate's Taylor polynomial may leave out, relative to its terms.
const TRUNCATION: f64 = 1e-17;
/// The highest Taylor degree: enough for `|λh| ≤ 1`.
const MAX_DEGREE: usize = 18;
/// Ulps of the terms' magnitudes taken as the rounding bound.
const ROUNDING: f64 = 16.0 * f64::EPSILON;

/// A port row in eigen-coordinates: `c = row V` (and `Σ |row_i| |V_ij|` for magnitudes).
struct ModalRow {
    c: Vec<Complex64>,
    magnitude: Vec<f64>,
}

/// A fast coordinate over one stretch.
struct Fast {
    lambda: Complex64,
    /// Anchored at the stretch's end (a growing exponential).
    at_end: bool,
    /// The anchored amplitude and the size of the terms it came from.
    amplitude: Complex64,
    amplitude_magnitude: f64,
    /// `∫₀¹ tᵏ e^{λh(t - anchor)} dt`, `k = 0..=degree`.
    moments: Vec<Complex64>,
}

/// One coordinate over one stretch: its polynomial part in `t` (all of a slow one, `β + γh t`
/// of a fast one), with the sizes of the terms of each coefficient, and which fast entry
/// holds its exponential, if any.
struct Coordinate {
    poly: Vec<Complex64>,
    poly_magnitude: Vec<f64>,
    fast: Option<usize>,
}

/// The books of one modal segment ([`super::SegmentBooks`]).
pub(super) struct ModalBooks {
    /// Effort and flow of each port, one after the other.
    rows: Vec<ModalRow>,
    u0: Vec<f64>,
    u1: Vec<f64>,
    /// `[λ, z₀, w₀, w₁]` of each coordinate, at the segment's start.
    terms: Vec<[Complex64; 4]>,
    // Buffers kept from stretch to stretch.
    start: Vec<Complex64>,
    end: Vec<Complex64>,
    fast: Vec<Fast>,
    coordinates: Vec<Coordinate>,
    pairs: Vec<Complex64>,
    conjugate_pairs: Vec<Complex64>,
    effort: Coefficients,
    flow: Coefficients,
}

/// A row over one stretch: `Re Σ A_j e^{λ_j s} + Σ R_k tᵏ`, with magnitudes.
#[derive(Default)]
struct Coefficients {
    fast: Vec<Complex64>,
    fast_magnitude: Vec<f64>,
    poly: Vec<f64>,
    poly_magnitude: Vec<f64>,
}

impl ModalBooks {
    /// `None` when the segment is not modal.
    pub fn new(mode: &NumericMode, segment: &Segment<'_>, u0: &[f64], u1: &[f64]) -> Option<Self> {
        let vectors = segment.vectors()?;
        let mut terms = Vec::new();
        if !segment.modal_terms_into(&mut terms) {
            return None;
        }
        let n = terms.len();
        let modal_row = |row: &Row| {
            let c = (0..n)
                .map(|j| (0..n).map(|i| vectors[(i, j)] * row.state[i]).sum())
                .collect();
            let magnitude = (0..n)
                .map(|j| {
                    (0..n)
                        .map(|i| vectors[(i, j)].norm() * row.state[i].abs())
                        .sum()
                })
                .collect();
            ModalRow { c, magnitude }
        };
        let rows = mode
            .ports
            .iter()
            .flat_map(|p| [modal_row(&p.effort), modal_row(&p.flow)])
            .collect();
        Some(ModalBooks {
            rows,
            u0: u0.to_vec(),
            u1: u1.to_vec(),
            terms,
            start: Vec::new(),
            end: Vec::new(),
            fast: Vec::new(),
            coordinates: Vec::new(),
            pairs: Vec::new(),
            conjugate_pairs: Vec::new(),
            effort: Coefficients::default(),
            flow: Coefficients::default(),
        })
    }

    /// The books over `[a, b]` (local times, `b > a`).
    pub fn over(
        &mut self,
        mode: &NumericMode,
        segment: &mut Segment<'_>,
        a: f64,
        b: f64,
    ) -> Increment {
        let h = b - a;
        self.start.clear();
        self.start
            .extend_from_slice(segment.modal_state(a).expect("a modal segment"));
        let grows = self
            .terms
            .iter()
            .any(|[lambda, ..]| lambda.re > 0.0 && lambda.norm() * h > FAST);
        self.end.clear();
        if grows {
            self.end
                .extend_from_slice(segment.modal_state(b).expect("a modal segment"));
        }

        let degree = self.taylor_degree(h);

        self.forms(a, h, degree);

        // `∫₀¹` of each pair of fast exponentials, and of one with the other's conjugate.
        self.pairs.clear();
        self.conjugate_pairs.clear();
        for p in &self.fast {
            for q in &self.fast {
                self.pairs
                    .push(pair(p.lambda, p.at_end, q.lambda, q.at_end, h));
                self.conjugate_pairs
                    .push(pair(p.lambda, p.at_end, q.lambda.conj(), q.at_end, h));
            }
        }

        let u: Vec<f64> = self
            .u0
            .iter()
            .zip(&self.u1)
            .map(|(u0, u1)| u0 + u1 * a)
            .collect();
        let mut increment = Increment::default();
        for (k, port) in mode.ports.iter().enumerate() {
            self.effort.fill(
                &self.rows[2 * k],
                &port.effort,
                &self.fast,
                &self.coordinates,
                &u,
                &self.u1,
                h,
                degree,
            );
            self.flow.fill(
                &self.rows[2 * k + 1],
                &port.flow,
                &self.fast,
                &self.coordinates,
                &u,
                &self.u1,
                h,
                degree,
            );
            let (value, magnitude) = self.power_integral(degree);
            increment.book(port.source, h * value, ROUNDING * h * magnitude);
        }
        increment
    }

    /// The Taylor degree the slowest-converging slow coordinate needs over a stretch of
    /// length `h` (at least 1; 2 or more when any coordinate is slow).
    fn taylor_degree(&self, h: f64) -> usize {
        let rho = self
            .terms
            .iter()
            .map(|[lambda, ..]| lambda.norm() * h)
            .filter(|x| *x <= FAST)
            .fold(0.0, f64::max);
        let any_slow = self.terms.iter().any(|[l, ..]| l.norm() * h <= FAST);
        let mut degree = 1;
        if any_slow {
            degree = 2;
            while degree < MAX_DEGREE
                && rho.powi(degree as i32 - 1) / factorial(degree + 1) > TRUNCATION
            {
                degree += 1;
            }
        }
        degree
    }

    /// Each coordinate's form over the stretch from `a` of length `h`: a polynomial of
    /// `degree` for a slow one, an exponential (in `self.fast`) plus the polynomial part for
    /// a fast one.
    fn forms(&mut self, a: f64, h: f64, degree: usize) {
        let n = self.terms.len();
        // The fast ones' polynomial parts go with the slow ones.
        self.fast.clear();
        self.coordinates.clear();
        for j in 0..n {
            let [lambda, _, w0, w1] = self.terms[j];
            let z = self.start[j];
            let forcing = w0 + w1 * a;
            let x = lambda * h;
            if x.norm() <= FAST {
                let (big_w0, big_w1) = (forcing * h, w1 * (h * h));
                let mut coefficients = vec![Complex64::new(0.0, 0.0); degree + 1];
                let mut magnitudes = vec![0.0; degree + 1];
                coefficients[0] = z;
                magnitudes[0] = z.norm();
                coefficients[1] = x * z + big_w0;
                magnitudes[1] = x.norm() * z.norm() + big_w0.norm();
                coefficients[2] = 0.5 * (x * coefficients[1] + big_w1);
                magnitudes[2] = 0.5 * (x.norm() * magnitudes[1] + big_w1.norm());
                for k in 3..=degree {
                    coefficients[k] = x * coefficients[k - 1] / k as f64;
                    magnitudes[k] = x.norm() * magnitudes[k - 1] / k as f64;
                }
                self.coordinates.push(Coordinate {
                    poly: coefficients,
                    poly_magnitude: magnitudes,
                    fast: None,
                });
            } else {
                let inverse = 1.0 / lambda;
                let gamma = -w1 * inverse;
                let beta = -(forcing + w1 * inverse) * inverse;
                let size = (forcing * inverse).norm() + (w1 * inverse * inverse).norm();
                let at_end = lambda.re > 0.0;
                let amplitude = if at_end {
                    self.end[j] - beta - gamma * h
                } else {
                    z - beta
                };
                let anchor_size = if at_end { self.end[j].norm() } else { z.norm() };
                let mut moments = vec![Complex64::new(0.0, 0.0); degree + 1];
                self::moments(x, at_end, &mut moments);
                self.fast.push(Fast {
                    lambda,
                    at_end,
                    amplitude,
                    amplitude_magnitude: anchor_size + size,
                    moments,
                });
                let mut coefficients = vec![Complex64::new(0.0, 0.0); degree + 1];
                let mut magnitudes = vec![0.0; degree + 1];
                coefficients[0] = beta;
                magnitudes[0] = size;
                coefficients[1] = gamma * h;
                magnitudes[1] = (gamma * h).norm();
                self.coordinates.push(Coordinate {
                    poly: coefficients,
                    poly_magnitude: magnitudes,
                    fast: Some(self.fast.len() - 1),
                });
            }
        }
    }

    /// `∫₀¹ e·f` of the effort and flow just filled (in the stretch's unit time): its value
    /// and the magnitude its rounding scales with.
    fn power_integral(&self, degree: usize) -> (f64, f64) {
        let f = self.fast.len();
        let (e, fl) = (&self.effort, &self.flow);
        let (mut value, mut magnitude) = (0.0, 0.0);
        for i in 0..f {
            for j in 0..f {
                let (pij, cij) = (self.pairs[i * f + j], self.conjugate_pairs[i * f + j]);
                value += 0.5
                    * ((e.fast[i] * fl.fast[j] * pij).re
                        + (e.fast[i] * fl.fast[j].conj() * cij).re);
                magnitude +=
                    0.5 * e.fast_magnitude[i] * fl.fast_magnitude[j] * (pij.norm() + cij.norm());
            }
        }
        for (j, fast) in self.fast.iter().enumerate() {
            for (kk, moment) in fast.moments.iter().enumerate() {
                value +=
                    (e.fast[j] * moment).re * fl.poly[kk] + (fl.fast[j] * moment).re * e.poly[kk];
                magnitude += moment.norm()
                    * (e.fast_magnitude[j] * fl.poly_magnitude[kk]
                        + fl.fast_magnitude[j] * e.poly_magnitude[kk]);
            }
        }
        for k in 0..=degree {
            for l in 0..=degree {
                let weight = 1.0 / (k + l + 1) as f64;
                value += e.poly[k] * fl.poly[l] * weight;
                magnitude += e.poly_magnitude[k] * fl.poly_magnitude[l] * weight;
            }
        }
        (value, magnitude)
    }
}

impl Coefficients {
    /// The row's coefficients over the stretch, its inputs `u` at its start and `u1` their
    /// rates.
    #[allow(clippy::too_many_arguments)]
    fn fill(
        &mut self,
        modal: &ModalRow,
        row: &Row,
        fast: &[Fast],
        coordinates: &[Coordinate],
        u: &[f64],
        u1: &[f64],
        h: f64,
        degree: usize,
    ) {
        let zero = Complex64::new(0.0, 0.0);
        self.fast.clear();
        self.fast.resize(fast.len(), zero);
        self.fast_magnitude.clear();
        self.fast_magnitude.resize(fast.len(), 0.0);
        self.poly.clear();
        self.poly.resize(degree + 1, 0.0);
        self.poly_magnitude.clear();
        self.poly_magnitude.resize(degree + 1, 0.0);
        for (j, coordinate) in coordinates.iter().enumerate() {
            let (c, size) = (modal.c[j], modal.magnitude[j]);
            if size == 0.0 {
                continue;
            }
            for k in 0..=degree {
                self.poly[k] += (c * coordinate.poly[k]).re;
                self.poly_magnitude[k] += size * coordinate.poly_magnitude[k];
            }
            if let Some(index) = coordinate.fast {
                self.fast[index] = c * fast[index].amplitude;
                self.fast_magnitude[index] = size * fast[index].amplitude_magnitude;
            }
        }
        self.poly[0] += dot(&row.input, u) + dot(&row.rate, u1) + row.constant;
        self.poly_magnitude[0] +=
            abs_dot(&row.input, u) + abs_dot(&row.rate, u1) + row.constant.abs();
        self.poly[1] += dot(&row.input, u1) * h;
        self.poly_magnitude[1] += abs_dot(&row.input, u1) * h;
    }
}

/// `Σ |a_i b_i|`.
fn abs_dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x * y).abs()).sum()
}

fn factorial(k: usize) -> f64 {
    (1..=k).map(|j| j as f64).product()
}

/// `φ₁(x) = (eˣ - 1)/x`, exact near zero.
fn phi1(x: Complex64) -> Complex64 {
    phis(x)[1]
}

/// `(1/h) ∫₀^h e^{λ_p (s - t_p)} e^{λ_q (s - t_q)} ds`, each exponential anchored at the
/// stretch's start (`t = 0`) or end (`t = h`): `e^{-λ_p t_p - λ_q t_q} φ₁(μh)` with
/// `μ = λ_p + λ_q`, or, where `Re μ > 0`, the same moved to the end,
/// `e^{λ_p (h - t_p) + λ_q (h - t_q)} φ₁(-μh)`. Anchors put growing exponentials at the end
/// and decaying ones at the start, so the exponential factor never exceeds one.
fn pair(lp: Complex64, p_end: bool, lq: Complex64, q_end: bool, h: f64) -> Complex64 {
    let mu = (lp + lq) * h;
    // Each exponential's shift to the point of reference, `c - t`: 0, h or -h.
    let shift = |lambda: Complex64, at_end: bool, reference_end: bool| match (at_end, reference_end)
    {
        (false, false) | (true, true) => Complex64::new(0.0, 0.0),
        (true, false) => -lambda * h,
        (false, true) => lambda * h,
    };
    let (reference_end, phi) = if mu.re <= 0.0 {
        (false, phi1(mu))
    } else {
        (true, phi1(-mu))
    };
    let exponent = shift(lp, p_end, reference_end) + shift(lq, q_end, reference_end);
    if exponent == Complex64::new(0.0, 0.0) {
        phi
    } else {
        exponent.exp() * phi
    }
}

/// `∫₀¹ tᵏ e^{x(t - t₀)} dt` for `k = 0..out.len()`, `t₀` the anchor (1 if `at_end`, else
/// 0), for any complex `x` (the caller anchors so that `Re x(t - t₀) ≤ 0`). With `E` the
/// exponential at `t = 1`, integration by parts gives `M_k = (E - k M_{k-1})/x`: upwards it
/// multiplies errors by `k/|x|`, downwards (`M_{k-1} = (E - x M_k)/k`) by `|x|/k`. So the
/// moments up to `|x|` come from `M₀ = φ₁(±x)` upwards, and the rest downwards from far
/// above, where `M_N ≈ E/(N + 1 + x)`: sixty-four steps at most `|x|/k < 1` shrink that
/// guess's error below rounding (Miller's method).
pub(super) fn moments(x: Complex64, at_end: bool, out: &mut [Complex64]) {
    let Some(last) = out.len().checked_sub(1) else {
        return;
    };
    let one = Complex64::new(1.0, 0.0);
    let (unit, first) = if at_end {
        (one, phi1(-x))
    } else {
        (x.exp(), phi1(x))
    };
    out[0] = first;
    // Up to |x| (saturating: a huge |x| goes all the way up).
    let upward = (x.norm().floor() as usize).min(last);
    for k in 1..=upward {
        out[k] = (unit - k as f64 * out[k - 1]) / x;
    }
    if upward < last {
        let top = last + 64;
        let mut value = unit / (top as f64 + 1.0 + x);
        for k in (upward + 2..=top).rev() {
            value = (unit - x * value) / k as f64;
            if k - 1 <= last {
                out[k - 1] = value;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::{NODES, WEIGHTS};

    /// `∫₀¹ f` by 8-point Gauss–Legendre on `panels` equal panels: an independent reference
    /// for smooth integrands.
    fn quadrature(f: impl Fn(f64) -> Complex64, panels: usize) -> Complex64 {
        let width = 1.0 / panels as f64;
        let mut sum = Complex64::new(0.0, 0.0);
        for p in 0..panels {
            let mid = (p as f64 + 0.5) * width;
            for (node, weight) in NODES.iter().zip(WEIGHTS) {
                sum += f(mid + 0.5 * width * node) * (0.5 * width * weight);
            }
        }
        sum
    }

    #[test]
    fn moments_match_quadrature_on_either_side_of_their_turning_point() {
        let c = Complex64::new;
        // Small, moderate and large |x|, real and complex, decaying (anchored at the start)
        // and growing (anchored at the end): the upward and downward recurrences meet at |x|.
        for (x, at_end) in [
            (c(0.0, 0.0), false),
            (c(-0.3, 0.2), false),
            (c(-1.5, 0.0), false),
            (c(-4.0, 7.0), false),
            (c(-0.02, 12.5), false),
            (c(-17.5, 3.0), false),
            (c(-60.0, 0.0), false),
            (c(0.0, 40.0), false),
            (c(2.5, -1.0), true),
            (c(30.0, 5.0), true),
        ] {
            let mut got = [c(0.0, 0.0); 19];
            moments(x, at_end, &mut got);
            let anchor = if at_end { 1.0 } else { 0.0 };
            for (k, value) in got.iter().enumerate() {
                let integrand = |t: f64| t.powi(k as i32) * (x * (t - anchor)).exp();
                let reference = quadrature(integrand, 64);
                // Rounding is relative to the integrand's size, not to what is left of it
                // where an oscillation cancels itself.
                let size = quadrature(|t| integrand(t).norm().into(), 64).re;
                assert!(
                    (value - reference).norm() <= 1e-14 * size,
                    "x = {x}, end {at_end}, k = {k}: {value} against {reference}"
                );
            }
        }
    }

    #[test]
    fn moments_of_a_stiff_exponential_are_its_asymptotic_series() {
        // x = -2.5e14: ∫₀¹ tᵏ e^{xt} dt = k!/(-x)^{k+1} to within e^{x}, nothing.
        let x = Complex64::new(-2.5e14, 0.0);
        let mut got = [Complex64::new(0.0, 0.0); 6];
        moments(x, false, &mut got);
        for (k, value) in got.iter().enumerate() {
            let exact = factorial(k) / 2.5e14f64.powi(k as i32 + 1);
            assert!(
                (value.re - exact).abs() <= 1e-14 * exact,
                "k = {k}: {value}"
            );
            assert_eq!(value.im, 0.0);
        }
    }

    #[test]
    fn pair_integrals_keep_their_exponentials_at_most_one() {
        let c = Complex64::new;
        let h = 0.7;
        // A decaying and a growing exponential, each anchored on its own side: e^{λp s} and
        // e^{λq (s - h)}.
        for (lp, lq) in [
            (c(-3.0, 20.0), c(2.0, -5.0)),
            (c(-1.0, 0.0), c(8.0, 1.0)),
            (c(-9.0, 0.0), c(2.0, 0.0)),
        ] {
            let got = pair(lp, false, lq, true, h);
            let reference = quadrature(|t| (lp * t * h).exp() * (lq * (t * h - h)).exp(), 64);
            assert!(
                (got - reference).norm() <= 1e-14 * reference.norm(),
                "{got} {reference}"
            );
        }
        // The steady part of a lightly damped swing: λ + λ̄ = 2σ ≈ 0, over 1600 periods.
        let lambda = c(-2.5e-3, 10.0);
        let got = pair(lambda, false, lambda.conj(), false, 1000.0);
        let exact = (1.0 - (-5.0f64).exp()) / 5.0;
        assert!(
            (got.re - exact).abs() <= 1e-15 && got.im.abs() <= 1e-15,
            "{got}"
        );
    }
}
