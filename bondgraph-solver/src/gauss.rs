//! The 8-point Gauss–Legendre rule on [-1, 1]: exact for polynomials of degree 15, used by
//! the energy books between samples and by the nonlinear modes' storage integrals.

/// Gauss–Legendre nodes and weights on [-1, 1], 8 points.
pub(crate) const NODES: [f64; 8] = [
    -0.960_289_856_497_536_3,
    -0.796_666_477_413_626_7,
    -0.525_532_409_916_329,
    -0.183_434_642_495_649_8,
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
pub(crate) const WEIGHTS: [f64; 8] = [
    0.101_228_536_290_376_26,
    0.222_381_034_453_374_47,
    0.313_706_645_877_887_3,
    0.362_683_783_378_362,
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_47,
    0.101_228_536_290_376_26,
];

#[cfg(test)]
mod tests {
    use super::{NODES, WEIGHTS};

    /// Exact for every degree up to 15 (∫ x^k over [-1, 1] is 2/(k+1) for even k, 0 for odd),
    /// and not for 16: the rule is the 8-point one.
    #[test]
    fn the_rule_is_exact_to_degree_fifteen() {
        let rule = |k: i32| -> f64 { NODES.iter().zip(WEIGHTS).map(|(x, w)| w * x.powi(k)).sum() };
        for k in 0..=15 {
            let exact = if k % 2 == 0 {
                2.0 / f64::from(k + 1)
            } else {
                0.0
            };
            assert!(
                (rule(k) - exact).abs() < 1e-15,
                "x^{k}: {} against {exact}",
                rule(k)
            );
        }
        assert!((rule(16) - 2.0 / 17.0).abs() > 1e-6);
    }
}
