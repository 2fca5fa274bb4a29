//! Exact propagation of one mode over a segment where the inputs vary linearly.
//!
//! Within a mode the equations are affine, `dx/dt = A x + B u(t) + c`, and the scenario's
//! inputs are piecewise linear, so between breakpoints `u(τ) = u₀ + u₁ τ` in the segment's
//! own local time `τ` (time since the segment began: restarting every segment at zero keeps
//! `e^{λτ}` meaningful even when `λ = -2.5e17` and the absolute time is 0.1 s). In
//! eigen-coordinates `z = V⁻¹ x` each component is solved in closed form:
//!
//! ```text
//! z(τ) = e^{λτ} z₀ + τ φ₁(λτ) w₀ + τ² φ₂(λτ) w₁,      w₀ = V⁻¹(B u₀ + c),  w₁ = V⁻¹ B u₁
//! ∫₀^τ z = τ φ₁(λτ) z₀ + τ² φ₂(λτ) w₀ + τ³ φ₃(λτ) w₁
//! ```
//!
//! with the φ-functions of exponential integrators, `φ₁(x) = (eˣ - 1)/x` and so on, evaluated
//! by series near zero so that neither a zero eigenvalue (a free integrator) nor a stiff one
//! loses precision. A defective matrix is propagated instead through the exponential of an
//! augmented matrix (see [`crate::linalg::expm`]).

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

use crate::linalg::{self, Eigen};

/// How a mode's state is propagated.
#[derive(Clone, Debug)]
pub enum Propagator {
    /// In eigen-coordinates (diagonalisable `A`).
    Modal(Modal),
    /// By the exponential of an augmented matrix (defective `A`).
    Exponential(Exponential),
}

/// The data of modal propagation.
#[derive(Clone, Debug)]
pub struct Modal {
    /// Shared by the propagators of one mode at parameter values that leave `A` as it is
    /// ([`Propagator::new_beside`]).
    eigen: Arc<Eigen>,
    /// `1/λ` (zero for a zero eigenvalue), for components that have decayed.
    inverse_values: Vec<Complex64>,
    /// `V⁻¹ B`.
    input: DMatrix<Complex64>,
    /// `V⁻¹ c`.
    affine: DVector<Complex64>,
}

impl Modal {
    /// The eigendecomposition behind it.
    pub fn eigen(&self) -> &Eigen {
        &self.eigen
    }

    /// The forcing in eigen-coordinates, `V⁻¹ (B u + c)`, into `out`.
    fn forcing_into(&self, u: &[f64], out: &mut [Complex64]) {
        times_real(&self.input, u, out);
        for (wj, cj) in out.iter_mut().zip(self.affine.iter()) {
            *wj += cj;
        }
    }
}

/// The data of propagation by the augmented matrix exponential.
#[derive(Clone, Debug)]
pub struct Exponential {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    c: DVector<f64>,
    /// Eigenvalues of `A` (from the Schur form), for the time scales.
    values: Vec<Complex64>,
}

impl Propagator {
    /// The propagator of `dx/dt = A x + B u + c`: modal when `A` is diagonalisable.
    pub fn new(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DVector<f64>) -> Self {
        match linalg::eigen(a) {
            Ok(eigen) => Self::modal(Arc::new(eigen), b, c),
            Err(_) => Self::exponential(a, b, c),
        }
    }

    /// [`Propagator::new`], reusing the eigendecomposition of `previous`, the propagator of
    /// `previous_a`, where `A` is that matrix exactly: a fit's trial values often change
    /// only `B u + c` (a Coulomb force, a breakaway force scanned, an input's gain), and
    /// the decomposition was a tenth of a steady sweep's `discover`. The same matrix gives
    /// the same decomposition, so the propagator is the one [`Propagator::new`] builds.
    pub fn new_beside(
        a: &DMatrix<f64>,
        b: &DMatrix<f64>,
        c: &DVector<f64>,
        previous_a: &DMatrix<f64>,
        previous: &Propagator,
    ) -> Self {
        if a != previous_a {
            return Self::new(a, b, c);
        }
        match previous {
            Propagator::Modal(m) => Self::modal(Arc::clone(&m.eigen), b, c),
            Propagator::Exponential(e) => Propagator::Exponential(Exponential {
                a: a.clone(),
                b: b.clone(),
                c: c.clone(),
                values: e.values.clone(),
            }),
        }
    }

    /// The modal propagator of `A = V Λ V⁻¹` (`eigen`) with forcing `B u + c`.
    fn modal(eigen: Arc<Eigen>, b: &DMatrix<f64>, c: &DVector<f64>) -> Self {
        let to_complex = |m: &DMatrix<f64>| m.map(|x| Complex64::new(x, 0.0));
        let input = &eigen.inverse * to_complex(b);
        let affine = &eigen.inverse * c.map(|x| Complex64::new(x, 0.0));
        let inverse_values = eigen
            .values
            .iter()
            .map(|v| {
                if v.norm() == 0.0 {
                    Complex64::new(0.0, 0.0)
                } else {
                    1.0 / v
                }
            })
            .collect();
        Propagator::Modal(Modal {
            eigen,
            inverse_values,
            input,
            affine,
        })
    }

    /// The propagator of a defective `A`, by the exponential of an augmented matrix.
    fn exponential(a: &DMatrix<f64>, b: &DMatrix<f64>, c: &DVector<f64>) -> Self {
        let values = nalgebra::Schur::try_new(a.clone(), f64::EPSILON, 10_000)
            .map(|s| s.complex_eigenvalues().iter().copied().collect())
            .unwrap_or_default();
        Propagator::Exponential(Exponential {
            a: a.clone(),
            b: b.clone(),
            c: c.clone(),
            values,
        })
    }

    /// The eigenvalues of `A`.
    pub fn eigenvalues(&self) -> &[Complex64] {
        match self {
            Propagator::Modal(m) => &m.eigen.values,
            Propagator::Exponential(e) => &e.values,
        }
    }

    /// Whether propagation is modal (exact on stiff matrices).
    pub fn is_modal(&self) -> bool {
        matches!(self, Propagator::Modal(_))
    }

    /// The straight line a trajectory from `x` under constant inputs `u` approaches once its
    /// decaying components have died out: `(x∞, ẋ∞)` with `x(τ) → x∞ + ẋ∞ τ`. Components with
    /// eigenvalues below `zero` in magnitude are integrators and drift; decaying components sit
    /// at their exact equilibria (`-w/λ`), free of the rounding noise a stiff mode puts into
    /// `A x + B u + c`. `None` if some component grows or oscillates undamped, or `A` is
    /// defective.
    pub fn asymptote(&self, x: &[f64], u: &[f64], zero: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        let Propagator::Modal(m) = self else {
            return None;
        };
        let n = x.len();
        let mut z = vec![Complex64::new(0.0, 0.0); n];
        let mut w = vec![Complex64::new(0.0, 0.0); n];
        times_real(&m.eigen.inverse, x, &mut z);
        m.forcing_into(u, &mut w);
        let mut position = vec![Complex64::new(0.0, 0.0); n];
        let mut rate = vec![Complex64::new(0.0, 0.0); n];
        for j in 0..n {
            let lambda = m.eigen.values[j];
            if lambda.norm() <= zero {
                position[j] = z[j];
                rate[j] = w[j];
            } else if lambda.re < -zero {
                position[j] = -w[j] / lambda;
            } else {
                return None;
            }
        }
        let mut x_limit = vec![0.0; n];
        let mut rate_limit = vec![0.0; n];
        to_real(&m.eigen.vectors, &position, &mut x_limit);
        to_real(&m.eigen.vectors, &rate, &mut rate_limit);
        Some((x_limit, rate_limit))
    }

    /// Whether the row `c·x` reads nothing of what an asymptote carries over from the state
    /// it starts from: its integrators (eigenvalues below `zero` in magnitude), whose
    /// components [`Propagator::asymptote`] keeps as it finds them. Then `c·x∞` is the same
    /// from every start, and does not drift: `c·v` is rounding (below 1e-9 of `Σ|cᵢ vᵢ|`)
    /// for each integrator's eigenvector `v`. False for a defective `A`.
    pub fn blind_to_integrators(&self, row: &[f64], zero: f64) -> bool {
        let Propagator::Modal(m) = self else {
            return false;
        };
        let vectors = &m.eigen.vectors;
        m.eigen
            .values
            .iter()
            .enumerate()
            .filter(|(_, lambda)| lambda.norm() <= zero)
            .all(|(j, _)| {
                let mut sum = Complex64::new(0.0, 0.0);
                let mut size = 0.0;
                for (i, &c) in row.iter().enumerate() {
                    sum += vectors[(i, j)] * c;
                    size += vectors[(i, j)].norm() * c.abs();
                }
                sum.norm() <= 1e-9 * size
            })
    }

    /// Starts a segment from state `x0` with inputs `u₀ + u₁ τ`.
    pub fn start(&self, x0: &[f64], u0: &[f64], u1: &[f64]) -> Segment<'_> {
        self.start_in(x0, u0, u1, SegmentBuffers::default())
    }

    /// [`Propagator::start`] in the vectors of an earlier segment
    /// ([`Segment::into_buffers`]): a simulation starts thousands of short segments.
    pub fn start_in(
        &self,
        x0: &[f64],
        u0: &[f64],
        u1: &[f64],
        buffers: SegmentBuffers,
    ) -> Segment<'_> {
        match self {
            Propagator::Modal(m) => {
                let n = x0.len();
                let zero = Complex64::new(0.0, 0.0);
                let SegmentBuffers {
                    mut z0,
                    mut w0,
                    mut w1,
                    mut scratch,
                } = buffers;
                for v in [&mut z0, &mut w0, &mut w1] {
                    v.clear();
                    v.resize(n, zero);
                }
                scratch.clear();
                scratch.resize(2 * n, zero);
                times_real(&m.eigen.inverse, x0, &mut z0);
                m.forcing_into(u0, &mut w0);
                times_real(&m.input, u1, &mut w1);
                Segment::Modal(ModalSegment {
                    modal: m,
                    z0,
                    w0,
                    w1,
                    scratch,
                })
            }
            Propagator::Exponential(e) => Segment::Exponential(ExponentialSegment {
                exponential: e,
                x0: DVector::from_column_slice(x0),
                forcing0: &e.b * DVector::from_column_slice(u0) + &e.c,
                forcing1: &e.b * DVector::from_column_slice(u1),
            }),
        }
    }
}

/// One mode propagated from a known state with given input slopes.
#[derive(Clone, Debug)]
pub enum Segment<'p> {
    /// Modal.
    Modal(ModalSegment<'p>),
    /// By the augmented exponential.
    Exponential(ExponentialSegment<'p>),
}

/// The vectors a modal segment works in, handed on from one segment to the next.
#[derive(Clone, Debug, Default)]
pub struct SegmentBuffers {
    z0: Vec<Complex64>,
    w0: Vec<Complex64>,
    w1: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

/// A modal segment: the eigen-coordinates of the initial state and the forcing.
#[derive(Clone, Debug)]
pub struct ModalSegment<'p> {
    modal: &'p Modal,
    z0: Vec<Complex64>,
    w0: Vec<Complex64>,
    w1: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

/// A segment propagated by the exponential of the augmented matrix.
#[derive(Clone, Debug)]
pub struct ExponentialSegment<'p> {
    exponential: &'p Exponential,
    x0: DVector<f64>,
    forcing0: DVector<f64>,
    forcing1: DVector<f64>,
}

impl Segment<'_> {
    /// The segment's vectors, for the next one ([`Propagator::start_in`]).
    pub fn into_buffers(self) -> SegmentBuffers {
        match self {
            Segment::Modal(s) => SegmentBuffers {
                z0: s.z0,
                w0: s.w0,
                w1: s.w1,
                scratch: s.scratch,
            },
            Segment::Exponential(_) => SegmentBuffers::default(),
        }
    }

    /// The state at local time `τ` into `out`.
    pub fn state_into(&mut self, tau: f64, out: &mut [f64]) {
        match self {
            Segment::Modal(s) => {
                for j in 0..s.z0.len() {
                    let [e, phi1, phi2, _] = phis(s.modal.eigen.values[j] * tau);
                    s.scratch[j] =
                        e * s.z0[j] + s.w0[j] * phi1 * tau + s.w1[j] * phi2 * (tau * tau);
                }
                to_real(&s.modal.eigen.vectors, &s.scratch[..s.z0.len()], out);
            }
            Segment::Exponential(s) => {
                let x = s.augmented(tau, false);
                out.copy_from_slice(x.as_slice());
            }
        }
    }

    /// The state at `τ` and, if `integral` is given, `∫₀^τ x dt`, sharing one evaluation of
    /// the φ-functions.
    pub fn state_and_integral_into(
        &mut self,
        tau: f64,
        state: &mut [f64],
        integral: Option<&mut [f64]>,
    ) {
        let Some(integral) = integral else {
            self.state_into(tau, state);
            return;
        };
        match self {
            Segment::Modal(s) => {
                let n = s.z0.len();
                s.scratch.resize(2 * n, Complex64::new(0.0, 0.0));
                for j in 0..n {
                    let [e, phi1, phi2, phi3] = phis(s.modal.eigen.values[j] * tau);
                    s.scratch[j] =
                        e * s.z0[j] + s.w0[j] * phi1 * tau + s.w1[j] * phi2 * (tau * tau);
                    s.scratch[n + j] = s.z0[j] * phi1 * tau
                        + s.w0[j] * phi2 * (tau * tau)
                        + s.w1[j] * phi3 * (tau * tau * tau);
                }
                to_real(&s.modal.eigen.vectors, &s.scratch[..n], state);
                to_real(&s.modal.eigen.vectors, &s.scratch[n..], integral);
            }
            Segment::Exponential(_) => {
                self.state_into(tau, state);
                self.integral_into(tau, integral);
            }
        }
    }

    /// The eigen-coordinates `z(τ)` of the state, for a modal segment (`None` otherwise):
    /// guards precomputed in eigen-coordinates evaluate from these directly.
    pub fn modal_state(&mut self, tau: f64) -> Option<&[Complex64]> {
        self.each_coordinate(tau, coordinate)
    }

    /// The rates of change of the eigen-coordinates at `τ`, for a modal segment (`None`
    /// otherwise): `ż = λ z + w₀ + w₁ τ`, written as `λ e^{λτ} z₀ + e^{λτ} w₀ + τ φ₁(λτ) w₁`
    /// so that a decayed stiff component, whose `λ z` all but cancels `w₀ + w₁ τ`, gives its
    /// true rate `-w₁/λ` instead of that cancellation's rounding.
    pub fn modal_rate(&mut self, tau: f64) -> Option<&[Complex64]> {
        self.each_coordinate(tau, coordinate_rate)
    }

    /// The eigen-coordinates and their rates at `τ`, `(z(τ), ż(τ))`, for a modal segment
    /// (`None` otherwise): [`Segment::modal_state`] and [`Segment::modal_rate`] sharing one
    /// evaluation of the φ-functions, as event location samples both.
    pub fn modal_state_and_rate(&mut self, tau: f64) -> Option<(&[Complex64], &[Complex64])> {
        self.each_coordinate_pair(tau, coordinate_and_rate)
    }

    /// `of(λ_j, 1/λ_j, τ, z₀_j, w₀_j, w₁_j)` for every eigen-coordinate, in the scratch
    /// space, for a modal segment (`None` otherwise).
    #[inline]
    fn each_coordinate(
        &mut self,
        tau: f64,
        of: impl Fn(Complex64, Complex64, f64, Complex64, Complex64, Complex64) -> Complex64,
    ) -> Option<&[Complex64]> {
        match self {
            Segment::Modal(s) => {
                let m = s.modal;
                for j in 0..s.z0.len() {
                    s.scratch[j] = of(
                        m.eigen.values[j],
                        m.inverse_values[j],
                        tau,
                        s.z0[j],
                        s.w0[j],
                        s.w1[j],
                    );
                }
                Some(&s.scratch[..s.z0.len()])
            }
            Segment::Exponential(_) => None,
        }
    }

    /// The eigen-coordinates of the state and of its integral at `τ`, `(z(τ), ∫₀^τ z)`, for a
    /// modal segment (`None` otherwise).
    pub fn modal_state_and_integral(&mut self, tau: f64) -> Option<(&[Complex64], &[Complex64])> {
        self.each_coordinate_pair(tau, coordinate_and_integral)
    }

    /// Two quantities `of(λ_j, 1/λ_j, τ, z₀_j, w₀_j, w₁_j)` for every eigen-coordinate, the
    /// first of each in the first half of the scratch space and the second in the second,
    /// for a modal segment (`None` otherwise).
    #[inline]
    fn each_coordinate_pair(
        &mut self,
        tau: f64,
        of: impl Fn(
            Complex64,
            Complex64,
            f64,
            Complex64,
            Complex64,
            Complex64,
        ) -> (Complex64, Complex64),
    ) -> Option<(&[Complex64], &[Complex64])> {
        match self {
            Segment::Modal(s) => {
                let n = s.z0.len();
                let m = s.modal;
                s.scratch.resize(2 * n, Complex64::new(0.0, 0.0));
                for j in 0..n {
                    let (first, second) = of(
                        m.eigen.values[j],
                        m.inverse_values[j],
                        tau,
                        s.z0[j],
                        s.w0[j],
                        s.w1[j],
                    );
                    s.scratch[j] = first;
                    s.scratch[n + j] = second;
                }
                Some(s.scratch.split_at(n))
            }
            Segment::Exponential(_) => None,
        }
    }

    /// Each eigen-coordinate's eigenvalue and terms `[λ, z₀, w₀, w₁]` of a modal segment
    /// (`None` otherwise), for bounds on a guard over a stretch of the segment.
    pub fn modal_terms(&self) -> Option<Vec<[Complex64; 4]>> {
        let mut terms = Vec::new();
        self.modal_terms_into(&mut terms).then_some(terms)
    }

    /// [`Segment::modal_terms`] into `terms`; false (and `terms` empty) for a segment that
    /// is not modal.
    pub fn modal_terms_into(&self, terms: &mut Vec<[Complex64; 4]>) -> bool {
        terms.clear();
        match self {
            Segment::Modal(s) => {
                terms.extend(
                    (0..s.z0.len()).map(|j| [s.modal.eigen.values[j], s.z0[j], s.w0[j], s.w1[j]]),
                );
                true
            }
            Segment::Exponential(_) => false,
        }
    }

    /// The eigenvector matrix `V` of a modal segment.
    pub fn vectors(&self) -> Option<&DMatrix<Complex64>> {
        match self {
            Segment::Modal(s) => Some(&s.modal.eigen.vectors),
            Segment::Exponential(_) => None,
        }
    }

    /// The state at local time `τ`.
    pub fn state(&mut self, tau: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dimension()];
        self.state_into(tau, &mut out);
        out
    }

    /// `∫₀^τ x dt` into `out`.
    pub fn integral_into(&mut self, tau: f64, out: &mut [f64]) {
        match self {
            Segment::Modal(s) => {
                for j in 0..s.z0.len() {
                    let [_, phi1, phi2, phi3] = phis(s.modal.eigen.values[j] * tau);
                    s.scratch[j] = s.z0[j] * phi1 * tau
                        + s.w0[j] * phi2 * (tau * tau)
                        + s.w1[j] * phi3 * (tau * tau * tau);
                }
                to_real(&s.modal.eigen.vectors, &s.scratch[..s.z0.len()], out);
            }
            Segment::Exponential(s) => {
                let x = s.augmented(tau, true);
                out.copy_from_slice(x.as_slice());
            }
        }
    }

    /// The number of states.
    pub fn dimension(&self) -> usize {
        match self {
            Segment::Modal(s) => s.z0.len(),
            Segment::Exponential(s) => s.x0.len(),
        }
    }
}

impl ExponentialSegment<'_> {
    /// `x(τ)` (or `∫₀^τ x`) from the exponential of
    /// `[[A, 0, B u₁, B u₀ + c], [I, 0, 0, 0], [0, 0, 0, 1], [0, 0, 0, 0]]`, whose flow carries
    /// `(x, ∫x, τ, 1)`.
    fn augmented(&self, tau: f64, integral: bool) -> DVector<f64> {
        let e = self.exponential;
        let n = e.a.nrows();
        let size = 2 * n + 2;
        let mut m = DMatrix::<f64>::zeros(size, size);
        m.view_mut((0, 0), (n, n)).copy_from(&(&e.a * tau));
        for i in 0..n {
            m[(n + i, i)] = tau;
            m[(i, 2 * n)] = self.forcing1[i] * tau;
            m[(i, 2 * n + 1)] = self.forcing0[i] * tau;
        }
        m[(2 * n, 2 * n + 1)] = tau;
        let mut start = DVector::<f64>::zeros(size);
        start.rows_mut(0, n).copy_from(&self.x0);
        start[2 * n + 1] = 1.0;
        let result = match linalg::expm(&m) {
            Some(exp) => exp * start,
            None => DVector::from_element(size, f64::NAN),
        };
        let offset = if integral { n } else { 0 };
        result.rows(offset, n).into_owned()
    }
}

/// One eigen-coordinate at `τ`: `e^{λτ} z₀ + τ φ₁(λτ) w₀ + τ² φ₂(λτ) w₁`. Once a real
/// eigenvalue's component has decayed to nothing (`λτ < -745`, where `e^{λτ}` is exactly zero
/// in floating point) this is `-w₀/λ - w₁ (1/λ + τ)/λ`, with no exponential or division: the
/// stiff components of a mode spend almost all their time there. A real eigenvalue's
/// φ-functions are real, and multiply as such (half the multiplications of complex ones).
#[inline]
fn coordinate(
    lambda: Complex64,
    inverse: Complex64,
    tau: f64,
    z0: Complex64,
    w0: Complex64,
    w1: Complex64,
) -> Complex64 {
    if lambda.im == 0.0 && lambda.re * tau < -745.0 {
        return -(w0 * inverse) - w1 * (inverse + tau) * inverse;
    }
    if lambda.im == 0.0 {
        let [e, phi1, phi2, _] = real_phis(lambda.re * tau);
        return z0 * e + w0 * phi1 * tau + w1 * phi2 * (tau * tau);
    }
    let [e, phi1, phi2, _] = phis(lambda * tau);
    e * z0 + w0 * phi1 * tau + w1 * phi2 * (tau * tau)
}

/// The rate of one eigen-coordinate at `τ`: `λ e^{λτ} z₀ + e^{λτ} w₀ + τ φ₁(λτ) w₁`, which
/// is `-w₁/λ` once a real eigenvalue's component has decayed (the derivative of
/// [`coordinate`]'s shortcut).
#[inline]
fn coordinate_rate(
    lambda: Complex64,
    inverse: Complex64,
    tau: f64,
    z0: Complex64,
    w0: Complex64,
    w1: Complex64,
) -> Complex64 {
    if lambda.im == 0.0 && lambda.re * tau < -745.0 {
        return -(w1 * inverse);
    }
    if lambda.im == 0.0 {
        let [e, phi1, _, _] = real_phis(lambda.re * tau);
        return z0 * (lambda.re * e) + w0 * e + w1 * phi1 * tau;
    }
    let [e, phi1, _, _] = phis(lambda * tau);
    lambda * e * z0 + e * w0 + w1 * phi1 * tau
}

/// `(coordinate, its rate)`: [`coordinate`] and [`coordinate_rate`] from one evaluation of
/// the φ-functions, with their shortcuts for decayed components.
#[inline]
fn coordinate_and_rate(
    lambda: Complex64,
    inverse: Complex64,
    tau: f64,
    z0: Complex64,
    w0: Complex64,
    w1: Complex64,
) -> (Complex64, Complex64) {
    if lambda.im == 0.0 && lambda.re * tau < -745.0 {
        return (
            -(w0 * inverse) - w1 * (inverse + tau) * inverse,
            -(w1 * inverse),
        );
    }
    if lambda.im == 0.0 {
        let [e, phi1, phi2, _] = real_phis(lambda.re * tau);
        return (
            z0 * e + w0 * phi1 * tau + w1 * phi2 * (tau * tau),
            z0 * (lambda.re * e) + w0 * e + w1 * phi1 * tau,
        );
    }
    let [e, phi1, phi2, _] = phis(lambda * tau);
    (
        e * z0 + w0 * phi1 * tau + w1 * phi2 * (tau * tau),
        lambda * e * z0 + e * w0 + w1 * phi1 * tau,
    )
}

/// `(coordinate, ∫₀^τ coordinate)`, with the same shortcut for decayed components:
/// `∫ = -z₀/λ - w₀ (1/λ + τ)/λ - w₁ ((1/λ + τ)/λ + τ²/2)/λ`.
#[inline]
fn coordinate_and_integral(
    lambda: Complex64,
    inverse: Complex64,
    tau: f64,
    z0: Complex64,
    w0: Complex64,
    w1: Complex64,
) -> (Complex64, Complex64) {
    if lambda.im == 0.0 && lambda.re * tau < -745.0 {
        let a = (inverse + tau) * inverse;
        return (
            -(w0 * inverse) - w1 * a,
            -(z0 * inverse) - w0 * a - w1 * (a + 0.5 * tau * tau) * inverse,
        );
    }
    let [e, phi1, phi2, phi3] = phis(lambda * tau);
    (
        e * z0 + w0 * phi1 * tau + w1 * phi2 * (tau * tau),
        z0 * phi1 * tau + w0 * phi2 * (tau * tau) + w1 * phi3 * (tau * tau * tau),
    )
}

/// `M v` for a complex matrix and a real vector, into `out`.
fn times_real(m: &DMatrix<Complex64>, v: &[f64], out: &mut [Complex64]) {
    for (i, slot) in out.iter_mut().enumerate() {
        let mut sum = Complex64::new(0.0, 0.0);
        for (j, vj) in v.iter().enumerate() {
            sum += m[(i, j)] * Complex64::new(*vj, 0.0);
        }
        *slot = sum;
    }
}

fn to_real(vectors: &DMatrix<Complex64>, z: &[Complex64], out: &mut [f64]) {
    for (i, slot) in out.iter_mut().enumerate() {
        let mut sum = 0.0;
        for (j, zj) in z.iter().enumerate() {
            let v = vectors[(i, j)];
            sum += v.re * zj.re - v.im * zj.im;
        }
        *slot = sum;
    }
}

/// `[φ₀, φ₁, φ₂, φ₃]` at `x` in one pass, in real arithmetic when `x` is real: the hot path
/// of propagation and event location.
pub fn phis(x: Complex64) -> [Complex64; 4] {
    if x.im == 0.0 {
        let [a, b, c, d] = real_phis(x.re);
        let r = |v: f64| Complex64::new(v, 0.0);
        return [r(a), r(b), r(c), r(d)];
    }
    if x.norm() < 0.5 {
        let phi3 = phi(3, x);
        let phi2 = 0.5 + x * phi3;
        let phi1 = 1.0 + x * phi2;
        return [1.0 + x * phi1, phi1, phi2, phi3];
    }
    let e = x.exp();
    let phi1 = (e - 1.0) / x;
    let phi2 = (phi1 - 1.0) / x;
    let phi3 = (phi2 - 0.5) / x;
    [e, phi1, phi2, phi3]
}

fn real_phis(x: f64) -> [f64; 4] {
    if x.abs() < 0.5 {
        // φ₃ by its series, then φ_{k-1} = 1/(k-1)! + x φ_k.
        let mut term = 1.0 / 6.0;
        let mut phi3 = term;
        for j in 1..20 {
            term *= x / (j + 3) as f64;
            phi3 += term;
            if term.abs() < 1e-17 * phi3.abs() {
                break;
            }
        }
        let phi2 = 0.5 + x * phi3;
        let phi1 = 1.0 + x * phi2;
        return [1.0 + x * phi1, phi1, phi2, phi3];
    }
    // Below -745 the exponential underflows to zero anyway.
    let e = if x < -745.0 { 0.0 } else { x.exp() };
    let phi1 = (e - 1.0) / x;
    let phi2 = (phi1 - 1.0) / x;
    let phi3 = (phi2 - 0.5) / x;
    [e, phi1, phi2, phi3]
}

/// The φ-functions of exponential integrators: `φ₀(x) = eˣ`,
/// `φ_k(x) = (φ_{k-1}(x) - 1/(k-1)!)/x`, i.e. `Σ_j x^j/(j+k)!`.
pub fn phi(k: u32, x: Complex64) -> Complex64 {
    if x.norm() < 0.5 {
        // The series converges fast: 20 terms reach machine precision for |x| < 0.5.
        let mut term = Complex64::new(1.0 / factorial(k), 0.0);
        let mut sum = term;
        for j in 1..20 {
            term = term * x / (j + k) as f64;
            sum += term;
        }
        return sum;
    }
    let mut value = x.exp();
    for j in 1..=k {
        value = (value - Complex64::new(1.0 / factorial(j - 1), 0.0)) / x;
    }
    value
}

fn factorial(k: u32) -> f64 {
    (1..=k).map(f64::from).product()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance * b.abs().max(1.0)
    }

    #[test]
    fn a_coordinates_rate_obeys_its_equation() {
        // z solves ż = λ z + w₀ + w₁ τ; its rate must be that, and once a real component has
        // decayed (λτ < -745) exactly -w₁/λ, with no cancellation.
        let c = Complex64::new;
        let (z0, w0, w1) = (c(0.3, -1.2), c(2.0, 0.5), c(-0.7, 0.25));
        for (lambda, tau) in [
            (c(-2.0, 3.0), 0.37),
            (c(-0.5, 0.0), 1.9),
            (c(0.2, 0.0), 0.8),
        ] {
            let z = coordinate(lambda, 1.0 / lambda, tau, z0, w0, w1);
            let rate = coordinate_rate(lambda, 1.0 / lambda, tau, z0, w0, w1);
            let expected = lambda * z + w0 + w1 * tau;
            assert!(
                (rate - expected).norm() < 1e-12 * expected.norm().max(1.0),
                "{rate} {expected}"
            );
            // Both from one evaluation of the exponentials: exactly what each gives alone.
            let both = coordinate_and_rate(lambda, 1.0 / lambda, tau, z0, w0, w1);
            assert_eq!(both, (z, rate));
        }
        let (lambda, inverse) = (c(-2.5e17, 0.0), c(-4e-18, 0.0));
        let rate = coordinate_rate(lambda, inverse, 1e-3, z0, w0, w1);
        assert_eq!(rate, -(w1 * inverse));
        let z = coordinate(lambda, inverse, 1e-3, z0, w0, w1);
        let both = coordinate_and_rate(lambda, inverse, 1e-3, z0, w0, w1);
        assert_eq!(both, (z, rate));
    }

    /// A propagator at new `B` and `c` beside one of the same `A` shares its
    /// eigendecomposition and propagates exactly as one built afresh; at another `A` it is
    /// built afresh.
    #[test]
    fn a_propagator_beside_one_of_the_same_matrix_shares_its_decomposition() {
        let a = DMatrix::from_row_slice(2, 2, &[-1.0, 2.0, 0.0, -3.0]);
        let previous = Propagator::new(
            &a,
            &DMatrix::from_row_slice(2, 1, &[1.0, 0.5]),
            &DVector::from_column_slice(&[0.1, 0.0]),
        );
        let (b, c) = (
            DMatrix::from_row_slice(2, 1, &[2.0, 1.0]),
            DVector::from_column_slice(&[0.0, 0.3]),
        );
        let beside = Propagator::new_beside(&a, &b, &c, &a, &previous);
        let fresh = Propagator::new(&a, &b, &c);
        let eigen = |p: &Propagator| match p {
            Propagator::Modal(m) => Arc::clone(&m.eigen),
            Propagator::Exponential(_) => panic!("a diagonalisable matrix"),
        };
        assert!(Arc::ptr_eq(&eigen(&beside), &eigen(&previous)));
        let (x0, u0, u1) = ([0.4, -0.2], [1.5], [0.25]);
        assert_eq!(
            beside.start(&x0, &u0, &u1).state(0.7),
            fresh.start(&x0, &u0, &u1).state(0.7)
        );
        // x₂ from 0 under 0.3 + u: the second row alone, ẋ₂ = -3 x₂ + u + 0.3.
        let x2 = fresh.start(&[0.0, 0.0], &[0.0], &[0.0]).state(0.7)[1];
        assert!(close(x2, 0.1 * (1.0 - (-2.1f64).exp()), 1e-14), "{x2}");

        let other = DMatrix::from_row_slice(2, 2, &[-1.0, 2.0, 0.0, -4.0]);
        let rebuilt = Propagator::new_beside(&other, &b, &c, &a, &previous);
        assert!(!Arc::ptr_eq(&eigen(&rebuilt), &eigen(&previous)));
        assert_eq!(
            rebuilt.eigenvalues(),
            Propagator::new(&other, &b, &c).eigenvalues()
        );
    }

    #[test]
    fn phi_functions_match_their_definitions() {
        for x in [1e-12, 0.3, -0.7, 2.0, -40.0, -1e6] {
            let z = Complex64::new(x, 0.0);
            let e = x.exp();
            let expected1 = if x.abs() < 1e-8 {
                1.0 + x / 2.0
            } else {
                (e - 1.0) / x
            };
            assert!(close(phi(1, z).re, expected1, 1e-13), "phi1({x})");
            if x.abs() > 0.5 {
                assert!(
                    close(phi(2, z).re, (e - 1.0 - x) / (x * x), 1e-13),
                    "phi2({x})"
                );
                assert!(
                    close(
                        phi(3, z).re,
                        (e - 1.0 - x - x * x / 2.0) / (x * x * x),
                        1e-12
                    ),
                    "phi3({x})"
                );
            }
        }
        // Limits at zero: 1/k!.
        assert_eq!(phi(2, Complex64::new(0.0, 0.0)).re, 0.5);
        assert!(close(phi(3, Complex64::new(0.0, 0.0)).re, 1.0 / 6.0, 1e-16));
    }

    #[test]
    fn fused_phis_agree_with_the_definitions() {
        for (re, im) in [
            (1e-9, 0.0),
            (0.3, 0.0),
            (-0.7, 0.0),
            (2.0, 0.0),
            (-800.0, 0.0),
            (0.2, 0.3),
            (-3.0, 40.0),
        ] {
            let x = Complex64::new(re, im);
            let fused = phis(x);
            for k in 0..4 {
                let reference = phi(k, x);
                assert!(
                    (fused[k as usize] - reference).norm() <= 1e-13 * reference.norm().max(1e-300),
                    "phi{k}({x}): {} vs {reference}",
                    fused[k as usize]
                );
            }
        }
    }

    #[test]
    fn decayed_components_take_the_shortcut_exactly() {
        // Past λτ = -745 the shortcut and the φ-functions must agree.
        let (lambda, tau) = (Complex64::new(-2.5e17, 0.0), 1e-12);
        let (z0, w0, w1) = (
            Complex64::new(0.3, 0.0),
            Complex64::new(7e16, 0.0),
            Complex64::new(-2e17, 0.0),
        );
        let inverse = 1.0 / lambda;
        let [e, phi1, phi2, phi3] = phis(lambda * tau);
        let full = e * z0 + w0 * phi1 * tau + w1 * phi2 * (tau * tau);
        let full_integral =
            z0 * phi1 * tau + w0 * phi2 * (tau * tau) + w1 * phi3 * (tau * tau * tau);
        assert!(
            (coordinate(lambda, inverse, tau, z0, w0, w1) - full).norm() <= 1e-15 * full.norm()
        );
        let (z, integral) = coordinate_and_integral(lambda, inverse, tau, z0, w0, w1);
        assert!((z - full).norm() <= 1e-15 * full.norm());
        assert!((integral - full_integral).norm() <= 1e-14 * full_integral.norm());
    }

    #[test]
    fn first_order_lag_with_a_ramp_is_exact() {
        // dx/dt = -a x + u with u = u0 + u1 t and x(0) = x0. By hand:
        // x(t) = x0 e^{-at} + (u0/a)(1 - e^{-at}) + (u1/a)(t - (1 - e^{-at})/a).
        let (a, x0, u0, u1) = (3.0, 2.0, 1.5, -0.8);
        let p = Propagator::new(
            &DMatrix::from_element(1, 1, -a),
            &DMatrix::from_element(1, 1, 1.0),
            &DVector::from_element(1, 0.0),
        );
        assert!(p.is_modal());
        let mut s = p.start(&[x0], &[u0], &[u1]);
        for t in [0.0, 0.1, 1.0, 7.0] {
            let e = (-a * t).exp();
            let exact = x0 * e + u0 / a * (1.0 - e) + u1 / a * (t - (1.0 - e) / a);
            assert!(close(s.state(t)[0], exact, 1e-14), "t = {t}");
        }
        // Its integral from 0 to t, by hand:
        // x0 (1 - e)/a + (u0/a)(t - (1 - e)/a) + (u1/a)(t²/2 - (t - (1 - e)/a)/a).
        let t = 1.7;
        let e = (-a * t).exp();
        let exact = x0 * (1.0 - e) / a
            + u0 / a * (t - (1.0 - e) / a)
            + u1 / a * (t * t / 2.0 - (t - (1.0 - e) / a) / a);
        let mut out = [0.0];
        s.integral_into(t, &mut out);
        assert!(close(out[0], exact, 1e-14));
    }

    #[test]
    fn stiff_mode_settles_exactly_at_its_quasi_steady_state() {
        // A light tip on a slack string: m dv/dt = F - b v, m = 5e-15, b = 1250.
        // After 1e-3 s the exact solution is F/b to machine precision.
        let (m, b, force) = (0.5e-14, 1250.0, 2.875);
        let p = Propagator::new(
            &DMatrix::from_element(1, 1, -b / m),
            &DMatrix::from_element(1, 1, 1.0 / m),
            &DVector::from_element(1, 0.0),
        );
        let mut s = p.start(&[0.0], &[force], &[0.0]);
        assert!(close(s.state(1e-3)[0], force / b, 1e-15));
        assert!(close(
            s.state(4e-18)[0],
            force / b * (1.0 - (-1.0f64).exp()),
            1e-12
        ));
    }

    #[test]
    fn defective_matrix_uses_the_exponential_and_is_exact() {
        // A free mass pushed by a constant force F = 2 (p' = F, x' = p/m with m = 1):
        // p(t) = F t, x(t) = F t²/2 from rest; with a ramp F = 2 + 3t: p = 2t + 1.5t², x = t² + t³/2.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 0.0, 1.0, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[1.0, 0.0]);
        let p = Propagator::new(&a, &b, &DVector::zeros(2));
        assert!(!p.is_modal());
        let mut s = p.start(&[0.0, 0.0], &[2.0], &[3.0]);
        let t = 1.3;
        let x = s.state(t);
        assert!(close(x[0], 2.0 * t + 1.5 * t * t, 1e-13));
        assert!(close(x[1], t * t + t * t * t / 2.0, 1e-13));
        let mut out = [0.0; 2];
        s.integral_into(t, &mut out);
        assert!(close(out[1], t.powi(3) / 3.0 + t.powi(4) / 8.0, 1e-13));
    }
}
