//! Dense LU decomposition with partial pivoting, in place, for the integrator's small
//! systems.

// The kernels index stages and components as the method's formulas do.
#![allow(clippy::needless_range_loop)]

/// `a` (row-major, `n × n`) replaced by its LU factors; `pivots` records the row swaps.
/// Returns false when the matrix is singular to working precision.
pub(crate) fn factor(a: &mut [f64], n: usize, pivots: &mut [usize]) -> bool {
    for k in 0..n {
        let mut p = k;
        let mut best = a[k * n + k].abs();
        for r in k + 1..n {
            let v = a[r * n + k].abs();
            if v > best {
                best = v;
                p = r;
            }
        }
        pivots[k] = p;
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        let pivot = a[k * n + k];
        for r in k + 1..n {
            let factor = a[r * n + k] / pivot;
            a[r * n + k] = factor;
            if factor != 0.0 {
                for j in k + 1..n {
                    a[r * n + j] -= factor * a[k * n + j];
                }
            }
        }
    }
    true
}

/// Solves `LU x = b` in place in `b`.
pub(crate) fn solve(lu: &[f64], n: usize, pivots: &[usize], b: &mut [f64]) {
    for k in 0..n {
        b.swap(k, pivots[k]);
    }
    for r in 0..n {
        let mut sum = b[r];
        for j in 0..r {
            sum -= lu[r * n + j] * b[j];
        }
        b[r] = sum;
    }
    for r in (0..n).rev() {
        let mut sum = b[r];
        for j in r + 1..n {
            sum -= lu[r * n + j] * b[j];
        }
        b[r] = sum / lu[r * n + r];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let original = a.clone();
        let mut pivots = vec![0; 3];
        assert!(factor(&mut a, 3, &mut pivots));
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3)
            .map(|r| (0..3).map(|j| original[r * 3 + j] * x[j]).sum())
            .collect();
        solve(&a, 3, &pivots, &mut b);
        for (got, want) in b.iter().zip(x) {
            assert!((got - want).abs() < 1e-14);
        }
        let mut singular = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!factor(&mut singular, 2, &mut [0; 2]));
    }
}
