//! An upper bound of a guard over a stretch of a modal segment, to pass over stretches where
//! no guard can reach zero without sampling them.
//!
//! In eigen-coordinates a guard is `g(τ) = a + b τ + Re Σ_j c_j z_j(τ)` (see
//! [`super::first_crossing`]), and each coordinate is known in closed form,
//! `z(τ) = e^{λτ} z₀ + τ φ₁(λτ) w₀ + τ² φ₂(λτ) w₁`. For `λ ≠ 0` that is a wave on a
//! straight line, `e^{λτ} K + L + M τ` with `M = -w₁/λ`, `L = -(w₀ + w₁/λ)/λ` and
//! `K = z₀ - L`; for `λ = 0` (a free integrator) it is the parabola
//! `z₀ + w₀ τ + w₁ τ²/2`. So `g` is a parabola plus waves of amplitude `|c_j K_j| e^{Re λ τ}`,
//! and over `[t₀, t₁]` it is at most the parabola's maximum plus every amplitude at its
//! largest. For a single swing on a trend (a slack string's extension while its cart swings
//! on a spring) the bound is exact. A real eigenvalue's wave `Re(c K) e^{λτ}` does not swing:
//! it is monotonic, so its larger end bounds it (a fast transient that settles onto its line
//! from below then adds nothing, where its amplitude would add the whole gap).
//!
//! A coordinate whose `|λ| t₁` is small is taken as its parabola with the remainder bounded
//! (`|eˣ - 1| ≤ |x| e^{|x|}`, `|φ₁(x) - 1| ≤ |x| e^{|x|}/2`, `|φ₂(x) - 1/2| ≤ |x| e^{|x|}/6`),
//! because `K` and `L` would then be large and cancel. A margin of `1e-12` of the size of
//! the terms covers the rounding of the bound itself.

use num_complex::Complex64;

/// Below this `|λ| t₁` a coordinate is bounded by its parabola and a remainder.
const SMALL: f64 = 1e-6;

/// A guard's terms in one modal segment, to bound it over stretches of the segment.
#[derive(Debug)]
pub(super) struct Envelope {
    /// The coordinates the guard depends on, their pieces worked out once.
    terms: Vec<Term>,
    /// The guard's terms in the inputs: `a + b τ`.
    a: f64,
    b: f64,
}

/// One coordinate's share `Re(c z(τ))` of a guard, in both of its forms.
#[derive(Debug)]
struct Term {
    /// `|λ|`, which decides the form for a stretch ending at `t₁`: `|λ| t₁ <= SMALL`.
    rate: f64,
    /// `Re λ`.
    growth: f64,
    /// As a parabola: `Re(c z₀)`, `Re(c w₀)`, `Re(c w₁)/2`, and the sizes `|c| |z₀|`,
    /// `|c| |w₀|`, `|c| |w₁|`.
    parabola: [f64; 3],
    parabola_size: [f64; 3],
    /// As a wave on a line: `Re(c L)`, `Re(c M)`, the wave's amplitude `|c K|`, and the
    /// sizes of the line's terms (`|c| (|L| + |z₀|) + |c K|` and `|c| |M|`); `None` for a
    /// zero eigenvalue, which is always a parabola.
    wave: Option<([f64; 2], f64, [f64; 2])>,
    /// For a real eigenvalue, `Re(c K)`: the wave is then `Re(c K) e^{λτ}`, monotonic, and
    /// bounded by its larger end rather than by its amplitude (a fast electrical transient
    /// that decays towards the line from below would otherwise add its whole amplitude).
    real_wave: Option<f64>,
}

/// One eigen-coordinate's pieces, `λ`, `z₀`, `w₀`, `w₁`, and for `λ ≠ 0` its line
/// `L + M τ` and wave `K`, with their sizes: worked out once per segment and shared by
/// every guard's envelope (only the guard's coefficient differs).
#[derive(Clone, Copy, Debug)]
pub(super) struct Coordinate {
    lambda: Complex64,
    z0: Complex64,
    w0: Complex64,
    w1: Complex64,
    /// `|λ|`.
    rate: f64,
    /// `|z₀|`, `|w₀|`, `|w₁|`.
    sizes: [f64; 3],
    /// `(L, M, K, |L|, |M|)`; `None` for a zero eigenvalue.
    line: Option<(Complex64, Complex64, Complex64, f64, f64)>,
}

impl Coordinate {
    /// The coordinate of terms `[λ, z₀, w₀, w₁]`
    /// (from [`crate::propagate::Segment::modal_terms`]).
    pub fn of([lambda, z0, w0, w1]: [Complex64; 4]) -> Self {
        let rate = lambda.norm();
        let line = (rate != 0.0).then(|| {
            let inverse = 1.0 / lambda;
            let m = -(w1 * inverse);
            let l = -((w0 + w1 * inverse) * inverse);
            (l, m, z0 - l, l.norm(), m.norm())
        });
        Coordinate {
            lambda,
            z0,
            w0,
            w1,
            rate,
            sizes: [z0.norm(), w0.norm(), w1.norm()],
            line,
        }
    }
}

impl Envelope {
    /// The guard `a + b τ + Re Σ c_j z_j(τ)` of a segment with these coordinates.
    pub fn new(c: &[Complex64], a: f64, b: f64, coordinates: &[Coordinate]) -> Self {
        let mut envelope = Envelope {
            terms: Vec::with_capacity(c.len()),
            a,
            b,
        };
        envelope.reset(c, a, b, coordinates);
        envelope
    }

    /// Makes this the envelope [`Envelope::new`] would make, keeping its allocation: one
    /// is made for every guard of every segment.
    pub fn reset(&mut self, c: &[Complex64], a: f64, b: f64, coordinates: &[Coordinate]) {
        self.a = a;
        self.b = b;
        self.terms.clear();
        self.terms.extend(
            c.iter()
                .zip(coordinates)
                .filter(|(cj, _)| cj.norm() != 0.0)
                .map(|(c, z)| {
                    let cn = c.norm();
                    let [z0_size, w0_size, w1_size] = z.sizes;
                    let wave = z.line.map(|(l, m, k, l_size, m_size)| {
                        let amplitude = (c * k).norm();
                        (
                            [(c * l).re, (c * m).re],
                            amplitude,
                            [cn * (l_size + z0_size) + amplitude, cn * m_size],
                        )
                    });
                    let real_wave = z
                        .line
                        .filter(|_| z.lambda.im == 0.0)
                        .map(|(_, _, k, _, _)| (c * k).re);
                    Term {
                        rate: z.rate,
                        growth: z.lambda.re,
                        parabola: [(c * z.z0).re, (c * z.w0).re, 0.5 * (c * z.w1).re],
                        parabola_size: [cn * z0_size, cn * w0_size, cn * w1_size],
                        wave,
                        real_wave,
                    }
                }),
        );
    }

    /// An upper bound of the guard over `[t0, t1]` (`0 <= t0 < t1`); not finite when
    /// nothing can be said.
    pub fn upper_bound(&self, t0: f64, t1: f64) -> f64 {
        // The parabola p₀ + p₁ τ + p₂ τ², the sizes of its terms (for the rounding margin),
        // and the waves' amplitudes with the small coordinates' remainders.
        let mut p = [self.a, self.b, 0.0];
        let mut size = [self.a.abs(), self.b.abs(), 0.0];
        let mut waves = 0.0;
        for term in &self.terms {
            match term.wave {
                Some((line, amplitude, line_size)) if term.rate * t1 > SMALL => {
                    p[0] += line[0];
                    p[1] += line[1];
                    size[0] += line_size[0];
                    size[1] += line_size[1];
                    let (start, end) = ((term.growth * t0).exp(), (term.growth * t1).exp());
                    waves += match term.real_wave {
                        Some(wave) => (wave * start).max(wave * end),
                        None => amplitude * start.max(end),
                    };
                }
                _ => {
                    let [z0, w0, w1] = term.parabola_size;
                    for k in 0..3 {
                        p[k] += term.parabola[k];
                        size[k] += term.parabola_size[k];
                    }
                    waves += 2.0 * term.rate * t1 * (z0 + t1 * w0 / 2.0 + t1 * t1 * w1 / 6.0);
                }
            }
        }
        let q = |t: f64| p[0] + p[1] * t + p[2] * t * t;
        let mut top = q(t0).max(q(t1));
        if p[2] < 0.0 {
            let vertex = -p[1] / (2.0 * p[2]);
            if vertex > t0 && vertex < t1 {
                top = top.max(q(vertex));
            }
        }
        let margin = 1e-12 * (size[0] + size[1] * t1 + size[2] * t1 * t1);
        top + waves + margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(re: f64, im: f64) -> Complex64 {
        Complex64::new(re, im)
    }

    /// `g = -0.941 + 0.001 τ - 0.01 cos 9.7τ` as an integrator and a conjugate pair:
    /// `z₁ = -0.941 + 0.001 τ`, `z₂,₃ = -0.005 e^{±9.7iτ}`.
    fn creeping() -> Envelope {
        let w = 9.7;
        let terms = [
            [c(0.0, 0.0), c(-0.941, 0.0), c(0.001, 0.0), c(0.0, 0.0)],
            [c(0.0, w), c(-0.005, 0.0), c(0.0, 0.0), c(0.0, 0.0)],
            [c(0.0, -w), c(-0.005, 0.0), c(0.0, 0.0), c(0.0, 0.0)],
        ];
        Envelope::new(&[c(1.0, 0.0); 3], 0.0, 0.0, &terms.map(Coordinate::of))
    }

    #[test]
    fn a_swing_on_a_trend_is_bounded_by_its_trend_plus_its_amplitude() {
        let envelope = creeping();
        // Over [0, 900]: at most -0.941 + 0.9 + 0.01 = -0.031.
        let bound = envelope.upper_bound(0.0, 900.0);
        assert!((bound + 0.031).abs() < 1e-9, "{bound}");
        // Over [900, 940] it may reach zero (it does, at 931.13 s).
        assert!(envelope.upper_bound(900.0, 940.0) > 0.0);
    }

    #[test]
    fn a_decaying_wave_is_bounded_by_its_amplitude_at_the_start() {
        // g = -0.5 - 2 e^{-τ} cos 3τ: z = -e^{(-1±3i)τ}, the constant in a.
        let terms = [
            [c(-1.0, 3.0), c(-1.0, 0.0), c(0.0, 0.0), c(0.0, 0.0)],
            [c(-1.0, -3.0), c(-1.0, 0.0), c(0.0, 0.0), c(0.0, 0.0)],
        ];
        let envelope = Envelope::new(&[c(1.0, 0.0); 2], -0.5, 0.0, &terms.map(Coordinate::of));
        let bound = envelope.upper_bound(2.0, 5.0);
        let expected = -0.5 + 2.0 * (-2.0f64).exp();
        assert!(
            (bound - expected).abs() < 1e-9,
            "{bound} against {expected}"
        );
    }

    #[test]
    fn a_real_transient_rising_to_its_line_is_bounded_by_its_end() {
        // z' = -1000 z + 1000 from z = 0: z = 1 - e^{-1000 τ} (a fast electrical mode
        // settling from below); the guard z - 1.5 is at most -0.5 - e^{-10} over [0, 0.01],
        // at its end. Bounding the transient by its amplitude (1) would put the bound at
        // +0.5, so that the stretch could not be passed over.
        let terms = [[c(-1000.0, 0.0), c(0.0, 0.0), c(1000.0, 0.0), c(0.0, 0.0)]];
        let envelope = Envelope::new(&[c(1.0, 0.0)], -1.5, 0.0, &terms.map(Coordinate::of));
        let exact = |t: f64| 1.0 - (-1000.0 * t).exp() - 1.5;
        let bound = envelope.upper_bound(0.0, 0.01);
        assert!((bound - exact(0.01)).abs() < 1e-9, "{bound}");
        // A transient falling to its line from above is bounded by its start.
        let terms = [[c(-1000.0, 0.0), c(2.0, 0.0), c(1000.0, 0.0), c(0.0, 0.0)]];
        let envelope = Envelope::new(&[c(1.0, 0.0)], -1.5, 0.0, &terms.map(Coordinate::of));
        let bound = envelope.upper_bound(0.001, 0.01);
        let exact = |t: f64| 1.0 + (-1000.0 * t).exp() - 1.5;
        assert!((bound - exact(0.001)).abs() < 1e-9, "{bound}");
    }

    #[test]
    fn a_forced_coordinate_is_bounded_above_its_values() {
        // z' = λ z + w₀ + w₁ τ with λ = -0.3 + 2i: sample the exact solution densely and
        // check the bound is above every sample, for small and large windows.
        let lambda = c(-0.3, 2.0);
        let (z0, w0, w1) = (c(0.2, -0.1), c(0.5, 0.3), c(-0.05, 0.02));
        let terms = [
            [lambda, z0, w0, w1],
            [lambda.conj(), z0.conj(), w0.conj(), w1.conj()],
        ];
        let envelope = Envelope::new(&[c(0.5, 0.0); 2], 0.1, -0.01, &terms.map(Coordinate::of));
        let exact = |t: f64| {
            let l = -(w0 + w1 / lambda) / lambda;
            let z = (lambda * t).exp() * (z0 - l) + l - w1 / lambda * t;
            0.1 - 0.01 * t + z.re
        };
        for (t0, t1) in [(0.0, 1e-9), (0.0, 0.5), (1.0, 4.0), (3.0, 30.0)] {
            let bound = envelope.upper_bound(t0, t1);
            for k in 0..=1000 {
                let t = t0 + (t1 - t0) * k as f64 / 1000.0;
                assert!(
                    exact(t) <= bound,
                    "[{t0}, {t1}] at {t}: {} > {bound}",
                    exact(t)
                );
            }
        }
    }
}
