//! Property tests: algebraic laws that must hold *structurally* because of the canonical
//! form, gcd properties that follow from unique factorisation, and agreement of symbolic
//! evaluation with direct floating-point evaluation.

use num_bigint::BigInt;
use num_traits::Signed;
use proptest::prelude::*;

use super::{Monomial, Poly, RatFunc, Symbol, SymbolTable, div_exact, gcd};

/// Polynomials in `vars` symbols with up to `max_terms` terms, exponents up to `max_exp`
/// and coefficients in `-coef..=coef`.
fn poly(vars: u32, max_terms: usize, max_exp: u32, coef: i64) -> impl Strategy<Value = Poly> {
    let term = (
        prop::collection::vec(0..=max_exp, vars as usize),
        -coef..=coef,
    );
    prop::collection::vec(term, 0..=max_terms).prop_map(|terms| {
        Poly::from_terms(terms.into_iter().map(|(exponents, c)| {
            let m = Monomial::new(
                exponents
                    .into_iter()
                    .enumerate()
                    .map(|(i, e)| (Symbol(i as u32), e)),
            );
            (m, BigInt::from(c))
        }))
    })
}

fn small_poly() -> impl Strategy<Value = Poly> {
    poly(4, 4, 2, 4)
}

fn nonzero_poly() -> impl Strategy<Value = Poly> {
    small_poly().prop_filter("nonzero", |p| !p.is_zero())
}

/// Rational functions in 3 symbols with small numerators and denominators.
fn ratfunc() -> impl Strategy<Value = RatFunc> {
    let part = || poly(3, 3, 2, 3);
    (part(), part().prop_filter("nonzero", |p| !p.is_zero()))
        .prop_map(|(n, d)| RatFunc::from_polys(n, d).unwrap_or_default())
}

fn nonzero_ratfunc() -> impl Strategy<Value = RatFunc> {
    ratfunc().prop_filter("nonzero", |r| !r.is_zero())
}

/// The canonical-form invariants of the module documentation.
fn assert_canonical(r: &RatFunc) -> Result<(), TestCaseError> {
    let (num, den) = (r.numerator(), r.denominator());
    prop_assert!(den.leading_coefficient().is_positive());
    if num.is_zero() {
        prop_assert!(den.is_one());
    } else {
        prop_assert!(gcd(num, den).is_one(), "not reduced: {:?}", r);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn exact_division_undoes_multiplication(a in small_poly(), c in nonzero_poly()) {
        let product = &a * &c;
        prop_assert_eq!(div_exact(&product, &c), Some(a.clone()));
        prop_assert_eq!(div_exact(&product, &a).is_some(), !a.is_zero());
    }

    #[test]
    fn gcd_divides_both_and_is_normalised(a in small_poly(), b in small_poly()) {
        let g = gcd(&a, &b);
        prop_assert_eq!(&g, &gcd(&b, &a));
        if a.is_zero() && b.is_zero() {
            prop_assert!(g.is_zero());
        } else {
            prop_assert!(g.leading_coefficient().is_positive());
            let qa = div_exact(&a, &g);
            let qb = div_exact(&b, &g);
            prop_assert!(qa.is_some() && qb.is_some());
            // The cofactors have no common factor left.
            let (qa, qb) = (qa.unwrap_or_default(), qb.unwrap_or_default());
            prop_assert!(gcd(&qa, &qb).is_one());
        }
    }

    /// In the unique factorisation domain Z[x, y, z, w], gcd(a c, b c) = c gcd(a, b) up to
    /// sign.
    #[test]
    fn gcd_of_multiples(a in small_poly(), b in small_poly(), c in nonzero_poly()) {
        let left = gcd(&(&a * &c), &(&b * &c));
        let right = (&c * &gcd(&a, &b)).normalise_sign();
        prop_assert_eq!(left, right);
    }

    #[test]
    fn results_are_canonical(x in ratfunc(), y in ratfunc()) {
        assert_canonical(&x)?;
        assert_canonical(&(&x + &y))?;
        assert_canonical(&(&x - &y))?;
        assert_canonical(&(&x * &y))?;
        if let Some(q) = x.checked_div(&y) {
            assert_canonical(&q)?;
        }
        if let Some(p) = x.powi(-2) {
            assert_canonical(&p)?;
        }
    }

    #[test]
    fn scaling_numerator_and_denominator_changes_nothing(
        n in small_poly(),
        d in nonzero_poly(),
        c in nonzero_poly(),
    ) {
        let plain = RatFunc::from_polys(n.clone(), d.clone());
        let scaled = RatFunc::from_polys(&n * &c, &d * &c);
        prop_assert_eq!(plain, scaled);
    }

    #[test]
    fn field_axioms_hold_structurally(x in ratfunc(), y in ratfunc(), z in ratfunc()) {
        prop_assert_eq!(&(&x + &y) + &z, &x + &(&y + &z));
        prop_assert_eq!(&x + &y, &y + &x);
        prop_assert_eq!(&(&x * &y) * &z, &x * &(&y * &z));
        prop_assert_eq!(&x * &y, &y * &x);
        prop_assert_eq!(&x * &(&y + &z), &(&x * &y) + &(&x * &z));
        prop_assert_eq!(&x + &RatFunc::zero(), x.clone());
        prop_assert_eq!(&x * &RatFunc::one(), x.clone());
        prop_assert!((&x - &x).is_zero());
        prop_assert_eq!(&x - &y, &x + &(-&y));
        prop_assert_eq!(-(-x.clone()), x.clone());
        // Structural equality is mathematical equality.
        prop_assert_eq!((&x - &y).is_zero(), x == y);
    }

    #[test]
    fn division_inverts_multiplication(x in ratfunc(), y in nonzero_ratfunc()) {
        let q = x.checked_div(&y);
        prop_assert!(q.is_some());
        let q = q.unwrap_or_default();
        prop_assert_eq!(&q * &y, x.clone());
        prop_assert!((&y * &y.inv().unwrap_or_default()).is_one());
        prop_assert_eq!(x.checked_div(&RatFunc::zero()), None);
        prop_assert_eq!(y.powi(-1), y.inv());
        prop_assert_eq!(y.powi(2).unwrap_or_default(), &y * &y);
        prop_assert_eq!(y.powi(-3).unwrap_or_default() * y.powi(3).unwrap_or_default(), RatFunc::one());
    }

    #[test]
    fn operator_forms_agree(x in ratfunc(), y in ratfunc()) {
        let sum = &x + &y;
        prop_assert_eq!(x.clone() + y.clone(), sum.clone());
        prop_assert_eq!(x.clone() + &y, sum.clone());
        prop_assert_eq!(&x + y.clone(), sum.clone());
        let mut acc = x.clone();
        acc += &y;
        prop_assert_eq!(acc, sum);
        let mut acc = x.clone();
        acc -= y.clone();
        prop_assert_eq!(acc, &x - &y);
        let mut acc = x.clone();
        acc *= &y;
        prop_assert_eq!(acc, &x * &y);
    }

    #[test]
    fn printing_is_consistent(x in ratfunc()) {
        let table = SymbolTable::new(["a", "b_1", "Delta_v"]);
        let (negative, magnitude) = x.signed_text(&table);
        let text = x.text(&table);
        prop_assert_eq!(&text, &if negative { format!("-{magnitude}") } else { magnitude });
        let (negative_latex, magnitude) = x.signed_latex(&table);
        prop_assert_eq!(negative_latex, negative);
        prop_assert_eq!(x.latex(&table), if negative { format!("-{magnitude}") } else { magnitude });
        // A negative value never prints with a leading "--".
        prop_assert!(!text.starts_with("--"));
    }
}

/// Expressions with positive constants and only `+`, `*`, `/` and small powers: with
/// positive symbol values there is no cancellation, so direct `f64` evaluation is accurate
/// and must agree with evaluating the canonical form.
#[derive(Clone, Debug)]
enum Expr {
    Symbol(u32),
    Int(i64),
    Add(Box<Expr>, Box<Expr>),
    Mul(Box<Expr>, Box<Expr>),
    Div(Box<Expr>, Box<Expr>),
    Pow(Box<Expr>, i32),
}

impl Expr {
    fn direct(&self, values: &[f64]) -> f64 {
        match self {
            Expr::Symbol(i) => values[*i as usize],
            Expr::Int(n) => *n as f64,
            Expr::Add(a, b) => a.direct(values) + b.direct(values),
            Expr::Mul(a, b) => a.direct(values) * b.direct(values),
            Expr::Div(a, b) => a.direct(values) / b.direct(values),
            Expr::Pow(a, n) => a.direct(values).powi(*n),
        }
    }

    fn symbolic(&self) -> RatFunc {
        match self {
            Expr::Symbol(i) => RatFunc::symbol(Symbol(*i)),
            Expr::Int(n) => RatFunc::integer(*n),
            Expr::Add(a, b) => a.symbolic() + b.symbolic(),
            Expr::Mul(a, b) => a.symbolic() * b.symbolic(),
            Expr::Div(a, b) => a.symbolic().checked_div(&b.symbolic()).unwrap_or_default(),
            Expr::Pow(a, n) => a.symbolic().powi(*n).unwrap_or_default(),
        }
    }
}

fn expr() -> impl Strategy<Value = Expr> {
    let leaf = prop_oneof![
        (0u32..4).prop_map(Expr::Symbol),
        (1i64..=5).prop_map(Expr::Int)
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Add(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Mul(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| Expr::Div(Box::new(a), Box::new(b))),
            (inner, -2i32..=3).prop_map(|(a, n)| Expr::Pow(Box::new(a), n)),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn evaluation_matches_direct_arithmetic(
        e in expr(),
        values in prop::collection::vec(0.5f64..2.0, 4),
    ) {
        let direct = e.direct(&values);
        let symbolic = e.symbolic().eval(&values);
        prop_assert!(
            (symbolic - direct).abs() <= 1e-9 * direct.abs(),
            "{:?}: symbolic {} vs direct {}", e, symbolic, direct
        );
    }
}
