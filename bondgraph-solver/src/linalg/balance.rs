//! Balancing by powers of two: the exact diagonal similarities that make a graded matrix's
//! rows and columns comparable before its eigenvalues or exponential are computed.

use nalgebra::DMatrix;

/// Each scaling step moves a row's and a column's sums 4 times apart, and finite doubles
/// span 2^2098: more steps than this cannot be needed.
const MAX_SCALING_STEPS: usize = 1100;

/// Balances `a` by a diagonal similarity of powers of two (Parlett and Reinsch, as LAPACK's
/// `gebal` without permutations): returns `B = D⁻¹ A D` and the diagonal of `D`.
///
/// A row or column whose off-diagonal sum is not finite (an infinite or NaN entry, or finite
/// entries whose sum overflows) cannot be judged and is left unscaled; callers that need
/// finite matrices refuse them before ([`eigen`](super::eigen), [`expm`](super::expm)). Every loop is bounded, so no
/// input keeps it from returning.
pub fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let n = a.nrows();
    let mut b = a.clone();
    let mut scale = vec![1.0; n];
    const RADIX: f64 = 2.0;
    let mut converged = false;
    let mut sweeps = 0;
    while !converged && sweeps < 100 {
        converged = true;
        sweeps += 1;
        for i in 0..n {
            let column: f64 = (0..n).filter(|&r| r != i).map(|r| b[(r, i)].abs()).sum();
            let row: f64 = (0..n).filter(|&c| c != i).map(|c| b[(i, c)].abs()).sum();
            let total = column + row;
            if column == 0.0 || row == 0.0 || !total.is_finite() {
                continue;
            }
            let mut f = 1.0;
            let mut c = column;
            let mut r = row;
            let mut steps = 0;
            while c < r / RADIX && steps < MAX_SCALING_STEPS {
                c *= RADIX * RADIX;
                r /= RADIX * RADIX;
                f *= RADIX;
                steps += 1;
            }
            while c >= r * RADIX && steps < MAX_SCALING_STEPS {
                c /= RADIX * RADIX;
                r *= RADIX * RADIX;
                f /= RADIX;
                steps += 1;
            }
            if (c + r) < 0.95 * total && f.is_finite() && f > 0.0 {
                converged = false;
                scale[i] *= f;
                for k in 0..n {
                    b[(i, k)] /= f;
                    b[(k, i)] *= f;
                }
            }
        }
    }
    (b, scale)
}

/// The matrix [`symmetrize`] gives: `B = D⁻¹ A D` and the energy weights that `D`, of powers
/// of two, leaves out.
pub(super) struct Scaled {
    /// `B`, exactly similar to `A`.
    pub(super) matrix: DMatrix<f64>,
    /// The diagonal of `D`, powers of two.
    pub(super) scale: Vec<f64>,
    /// Weights `w_k` (between 1/2 and 2) with `|w_i b_ij| = |w_j b_ji|` for a network's
    /// coupling pairs: `diag(w)` is `B`'s energy norm, up to a constant.
    pub(super) weights: Vec<f64>,
}

/// Scales `a` by a diagonal similarity of powers of two so that its couplings come in pairs
/// of nearly equal magnitude (see [`Scaled`]).
///
/// A passive network's mode matrix is `(J - R) Q`: a skew-symmetric junction structure `J`
/// (it conserves power), a dissipation `R` and the energy's Hessian `Q`. Scaled to energy
/// coordinates (`D = Q^{-1/2}`) it is `J̃ - R̃`, whose skew part carries the frequencies and
/// whose symmetric part carries the damping, apart. That scaling is found from the matrix
/// alone: wherever `a_ij` and `a_ji` are both nonzero, `|b_ij| = |b_ji|` asks
/// `(d_j/d_i)² = |a_ji/a_ij|`, which is set along a spanning tree of such pairs (consistent
/// on cycles for a network, by the same argument). Each connected set keeps the mean level
/// that [`balance`] gives it, and [`balance`] alone scales the rest.
///
/// `D` keeps the power of two nearest to each of those factors, so `B` is `A` with exact
/// exponents changed; the remaining factors, within `√2` of one, become the weights.
pub(super) fn symmetrize(a: &DMatrix<f64>) -> Scaled {
    let (balanced, mut scale) = balance(a);
    let n = balanced.nrows();
    let unweighted = |matrix: DMatrix<f64>, scale: Vec<f64>| Scaled {
        matrix,
        scale,
        weights: vec![1.0; n],
    };
    let mut exponent: Vec<Option<f64>> = vec![None; n];
    for root in 0..n {
        if exponent[root].is_some() {
            continue;
        }
        exponent[root] = Some(0.0);
        let mut component = vec![root];
        let mut head = 0;
        while let Some(&i) = component.get(head) {
            head += 1;
            let level = exponent[i].unwrap_or(0.0);
            for j in 0..n {
                let (forward, backward) = (balanced[(i, j)], balanced[(j, i)]);
                if j == i || exponent[j].is_some() || forward == 0.0 || backward == 0.0 {
                    continue;
                }
                exponent[j] = Some(level + 0.5 * (backward.abs().log2() - forward.abs().log2()));
                component.push(j);
            }
        }
        let mean = component
            .iter()
            .map(|&i| exponent[i].unwrap_or(0.0))
            .sum::<f64>()
            / component.len() as f64;
        for &i in &component {
            exponent[i] = exponent[i].map(|e| e - mean);
        }
    }
    let exponent: Vec<f64> = exponent.into_iter().map(|e| e.unwrap_or(0.0)).collect();
    // Far outside the range of floating point (a ratio of couplings near 1e600) the factors
    // overflow; the balanced matrix is then as good as it gets.
    if exponent.iter().any(|e| e.abs() > 2.0 * f64::MAX_EXP as f64) {
        return unweighted(balanced, scale);
    }
    let whole: Vec<i32> = exponent.iter().map(|e| e.round() as i32).collect();
    let scaled = DMatrix::from_fn(n, n, |i, j| {
        times_power_of_two(balanced[(i, j)], whole[j] - whole[i])
    });
    // A factor that would take an entry out of the normal range would cost it precision.
    let representable = scaled
        .iter()
        .zip(balanced.iter())
        .all(|(s, b)| s.is_finite() && (*s == 0.0) == (*b == 0.0) && (*s == 0.0 || s.is_normal()));
    let rescaled: Vec<f64> = scale
        .iter()
        .zip(&whole)
        .map(|(s, w)| times_power_of_two(*s, *w))
        .collect();
    if !representable || rescaled.iter().any(|s| !s.is_normal()) {
        return unweighted(balanced, scale);
    }
    scale = rescaled;
    let weights = energy_weights(&scaled, &exponent, &whole);
    Scaled {
        matrix: scaled,
        scale,
        weights,
    }
}

/// The weights of [`Scaled`]: along the same spanning tree of couplings that [`symmetrize`]
/// followed, `w_j = w_i |b_ij| / |b_ji|` from the scaled entries themselves, each root given
/// `2^(-2 f)`, `f` the fraction of its exponent the powers of two left out. Read off the
/// exponents' fractions instead, a weight carries the rounding of a base-two logarithm near
/// 330 (a 1e-200 kg mass), 5e-14 of itself: a spring's two terms then no longer cancel to
/// rounding in [`oscillation_decay`], and a 7e100 rad/s oscillation grew at 5e36 /s.
fn energy_weights(scaled: &DMatrix<f64>, exponent: &[f64], whole: &[i32]) -> Vec<f64> {
    let n = scaled.nrows();
    let mut weights: Vec<Option<f64>> = vec![None; n];
    for root in 0..n {
        if weights[root].is_some() {
            continue;
        }
        weights[root] = Some((-2.0 * (exponent[root] - f64::from(whole[root]))).exp2());
        let mut component = vec![root];
        let mut head = 0;
        while let Some(&i) = component.get(head) {
            head += 1;
            let weight = weights[i].unwrap_or(1.0);
            for j in 0..n {
                let (forward, backward) = (scaled[(i, j)], scaled[(j, i)]);
                if j == i || weights[j].is_some() || forward == 0.0 || backward == 0.0 {
                    continue;
                }
                weights[j] = Some(weight * forward.abs() / backward.abs());
                component.push(j);
            }
        }
    }
    weights.into_iter().map(|w| w.unwrap_or(1.0)).collect()
}

/// `x 2^k`, exactly unless the result leaves the range of floating point.
fn times_power_of_two(mut x: f64, mut k: i32) -> f64 {
    // 2^k itself is representable for |k| ≤ 1000; larger ones are applied in steps.
    const STEP: i32 = 1000;
    while k > STEP {
        x *= 2f64.powi(STEP);
        k -= STEP;
    }
    while k < -STEP {
        x *= 2f64.powi(-STEP);
        k += STEP;
    }
    x * 2f64.powi(k)
}
