//! The few distributions and linear-algebra helpers that selection needs.
//!
//! Deciding whether a better fit is "beyond what the noise explains" is an F-test: the
//! F distribution's tail comes from the regularised incomplete beta function, computed here
//! by its continued fraction (Lentz's method) rather than pulled in with a statistics crate.
//! The normal equations of calibration have at most a handful of unknowns, so a dense
//! Cholesky solve is all the linear algebra needed.

/// `ln Γ(x)` for `x > 0` (Lanczos, g = 7, n = 9; relative error below 1e-13).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection.
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised incomplete beta function `I_x(a, b)`.
pub fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    // The continued fraction converges fast for x < (a + 1)/(a + b + 2); use symmetry above.
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let mut c = 1.0;
    let mut d = 1.0 - (a + b) * x / (a + 1.0);
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..300 {
        let m = m as f64;
        let even = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
        d = 1.0 + even * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + even / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        h *= d * c;
        let odd = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
        d = 1.0 + odd * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + odd / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// `P(F > f)` for the F distribution with `d1` and `d2` degrees of freedom.
pub fn f_survival(f: f64, d1: f64, d2: f64) -> f64 {
    if f <= 0.0 {
        return 1.0;
    }
    incomplete_beta(d2 / (d2 + d1 * f), d2 / 2.0, d1 / 2.0)
}

/// The regularised upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)`, for `a > 0`,
/// `x >= 0`: its series below `x = a + 1`, its continued fraction (Lentz's method) above
/// (Numerical Recipes' split; relative error near 1e-15).
pub fn upper_incomplete_gamma(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    let front = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = x^a e^-x / Γ(a + 1) · Σ x^n / ((a + 1)···(a + n)).
        let (mut term, mut sum, mut denominator) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - front * sum).max(0.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let i = f64::from(i);
            let an = -i * (i - a);
            b += 2.0;
            d = an * d + b;
            d = if d.abs() < TINY { TINY } else { d };
            c = b + an / c;
            c = if c.abs() < TINY { TINY } else { c };
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        front * h
    }
}

/// `P(X > x)` for the chi-square distribution with `dof` degrees of freedom:
/// `Q(dof/2, x/2)`.
pub fn chi_square_survival(x: f64, dof: f64) -> f64 {
    upper_incomplete_gamma(dof / 2.0, x / 2.0)
}

/// Solves the symmetric positive definite system `m x = rhs` (`m` row-major, `n x n`);
/// `None` when `m` is not positive definite to working precision.
pub fn cholesky_solve(m: &[f64], rhs: &[f64]) -> Option<Vec<f64>> {
    let n = rhs.len();
    let l = cholesky(m, n)?;
    let mut y = vec![0.0; n];
    for i in 0..n {
        let s: f64 = (0..i).map(|k| l[i * n + k] * y[k]).sum();
        y[i] = (rhs[i] - s) / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..n).map(|k| l[k * n + i] * x[k]).sum();
        x[i] = (y[i] - s) / l[i * n + i];
    }
    Some(x)
}

/// The inverse of a symmetric positive definite matrix, or `None`.
pub fn spd_inverse(m: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut inverse = vec![0.0; n * n];
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let column = cholesky_solve(m, &e)?;
        for i in 0..n {
            inverse[i * n + j] = column[i];
        }
    }
    Some(inverse)
}

fn cholesky(m: &[f64], n: usize) -> Option<Vec<f64>> {
    let scale = (0..n).map(|i| m[i * n + i].abs()).fold(0.0, f64::max);
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum();
            if i == j {
                let d = m[i * n + i] - s;
                if d <= scale * 1e-13 || !d.is_finite() {
                    return None;
                }
                l[i * n + i] = d.sqrt();
            } else {
                l[i * n + j] = (m[i * n + j] - s) / l[j * n + j];
            }
        }
    }
    Some(l)
}

/// Ordinary least squares of `y` on `x` with an intercept: `(slope, its standard error)`;
/// `None` with fewer than three points or no spread in `x`.
pub fn slope(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    if x.len() < 3 {
        return None;
    }
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    if sxx <= 1e-12 * (1.0 + mx * mx) * n {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let b = sxy / sxx;
    let sse: f64 = x
        .iter()
        .zip(y)
        .map(|(a, c)| (c - my - b * (a - mx)).powi(2))
        .sum();
    Some((b, (sse / (n - 2.0) / sxx).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_matches_factorials() {
        // Γ(n) = (n - 1)!, Γ(1/2) = √π.
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(10.0) - 362_880f64.ln()).abs() < 1e-11);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-12);
    }

    #[test]
    fn f_tail_matches_closed_forms_and_tables() {
        // F(2, d2): P(F > f) = (1 + 2f/d2)^(-d2/2) exactly.
        for &(f, d2) in &[(0.5f64, 10.0f64), (3.0, 20.0), (7.5, 4.0)] {
            let exact = (1.0 + 2.0 * f / d2).powf(-d2 / 2.0);
            assert!((f_survival(f, 2.0, d2) - exact).abs() < 1e-12, "{f} {d2}");
        }
        // Tabulated 1% critical values: F(1, 20) = 8.096, F(3, 23) = 4.765.
        assert!((f_survival(8.096, 1.0, 20.0) - 0.01).abs() < 2e-5);
        assert!((f_survival(4.765, 3.0, 23.0) - 0.01).abs() < 2e-5);
    }

    #[test]
    fn chi_square_tail_matches_closed_forms_and_tables() {
        // Two degrees of freedom: P(X > x) = e^(-x/2) exactly; one: erfc(sqrt(x/2)), and
        // erfc(1) = 0.157299207050285 (x = 2).
        for &x in &[0.1f64, 1.0, 4.0, 30.0] {
            let exact = (-x / 2.0).exp();
            assert!((chi_square_survival(x, 2.0) - exact).abs() < 1e-14 * (1.0 + 1.0 / exact));
        }
        assert!((chi_square_survival(2.0, 1.0) - 0.157_299_207_050_285).abs() < 1e-13);
        // Tabulated 5% and 1% critical values.
        for &(x, dof, p) in &[
            (3.84146f64, 1.0f64, 0.05f64),
            (18.307, 10.0, 0.05),
            (6.63490, 1.0, 0.01),
            (37.5662, 20.0, 0.01),
        ] {
            let q = chi_square_survival(x, dof);
            assert!((q - p).abs() < 2e-6, "{x} {dof}: {q}");
        }
        assert_eq!(chi_square_survival(0.0, 3.0), 1.0);
    }

    #[test]
    fn cholesky_solves_and_refuses_singular_matrices() {
        let m = [4.0, 2.0, 2.0, 3.0];
        let x = cholesky_solve(&m, &[2.0, 1.0]).unwrap();
        // By hand: 4x + 2y = 2, 2x + 3y = 1 gives x = 0.5, y = 0.
        assert!((x[0] - 0.5).abs() < 1e-15 && x[1].abs() < 1e-15);
        assert!(cholesky_solve(&[1.0, 2.0, 2.0, 4.0], &[1.0, 1.0]).is_none());
        let inverse = spd_inverse(&m, 2).unwrap();
        // [[3, -2], [-2, 4]] / 8.
        assert!((inverse[0] - 0.375).abs() < 1e-15 && (inverse[1] + 0.25).abs() < 1e-15);
    }

    #[test]
    fn slope_of_a_line_with_known_scatter() {
        // y = 2x + 1 with residuals +1, -1, -1, +1 at x = 0..3: slope 2 exactly
        // (the residuals are orthogonal to x - 1.5), SE = sqrt(4/2 / 5).
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [2.0, 2.0, 4.0, 8.0];
        let (b, se) = slope(&x, &y).unwrap();
        assert!((b - 2.0).abs() < 1e-12);
        assert!((se - (2.0f64 / 5.0).sqrt()).abs() < 1e-12);
    }
}
