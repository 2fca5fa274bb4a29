use super::*;
use crate::SymbolTable;

fn table() -> SymbolTable {
    SymbolTable::new(["b", "c", "g", "k", "l", "m"])
}

fn p(name: &str) -> Sym {
    let t = table();
    Sym::coefficient(RatFunc::symbol(t.get(name).unwrap()))
}

fn names(a: Atom) -> String {
    match a {
        Atom::State(0) => "q".into(),
        Atom::State(1) => "p".into(),
        Atom::Input(0) => "u".into(),
        Atom::Port => "flow".into(),
        other => format!("{other:?}"),
    }
}

fn text(s: &Sym) -> String {
    s.text(&table(), &names)
}

fn q() -> Sym {
    Sym::atom(Atom::State(0))
}

fn pm() -> Sym {
    Sym::atom(Atom::State(1))
}

#[test]
fn like_terms_collect_and_sums_flatten() {
    let x = Sym::add(&Sym::mul(&p("b"), &q()), &Sym::mul(&p("c"), &q()));
    assert_eq!(text(&x), "(b + c)*q");
    let zero = Sym::sub(&Sym::add(&q(), &pm()), &Sym::add(&pm(), &q()));
    assert!(zero.is_zero());
    let sum = Sym::add(
        &Sym::add(&Sym::one(), &q()),
        &Sym::add(&pm(), &Sym::integer(2)),
    );
    assert_eq!(text(&sum), "q + p + 3");
}

#[test]
fn products_merge_exponents_and_pull_out_coefficients() {
    let x = Sym::mul(&Sym::mul(&q(), &p("k")), &Sym::div(&pm(), &q()).unwrap());
    assert_eq!(text(&x), "k*p");
    let y = Sym::mul(&Sym::mul(&q(), &q()), &Sym::neg(&p("m")));
    assert_eq!(text(&y), "-m*q^2");
    let z = Sym::div(&pm(), &p("m")).unwrap();
    assert_eq!(text(&z), "p/m");
    let w = Sym::div(
        &Sym::mul(&p("c"), &Sym::call(Function::Sqrt, vec![q()])),
        &pm(),
    )
    .unwrap();
    assert_eq!(text(&w), "c*sqrt(q)/p");
}

#[test]
fn equal_expressions_print_equally_however_built() {
    let a = Sym::mul(
        &Sym::add(&p("b"), &p("c")),
        &Sym::call(Function::Sin, vec![q()]),
    );
    let b = Sym::add(
        &Sym::mul(&Sym::call(Function::Sin, vec![q()]), &p("c")),
        &Sym::mul(&p("b"), &Sym::call(Function::Sin, vec![q()])),
    );
    assert_eq!(a, b);
    assert_eq!(text(&a), "(b + c)*sin(q)");
}

#[test]
fn exact_constants_fold() {
    assert!(Sym::call(Function::Sin, vec![Sym::zero()]).is_zero());
    assert!(Sym::call(Function::Cos, vec![Sym::zero()]).is_one());
    assert_eq!(text(&Sym::call(Function::Sqrt, vec![Sym::integer(4)])), "2");
    assert_eq!(text(&Sym::call(Function::Abs, vec![Sym::integer(-3)])), "3");
    assert_eq!(
        text(&Sym::call(Function::Sign, vec![Sym::neg(&q())])),
        "-sign(q)"
    );
    assert_eq!(text(&Sym::call(Function::Sqrt, vec![p("g")])), "sqrt(g)");
    // (x^2)^(1/2) is |x|, not x: it is kept.
    let square_root = Sym::call(Function::Sqrt, vec![q().powi(2).unwrap()]);
    assert_eq!(text(&square_root), "sqrt(q^2)");
    let cube_root = q()
        .powi(3)
        .unwrap()
        .pow(Rational::new(1, 3).unwrap())
        .unwrap();
    assert_eq!(cube_root, q());
}

#[test]
fn derivatives_follow_the_textbook_rules() {
    let f = Sym::mul(&Sym::neg(&p("k")), &Sym::call(Function::Sin, vec![q()]));
    assert_eq!(text(&f.diff(Atom::State(0))), "-k*cos(q)");
    let g = Sym::call(Function::Exp, vec![Sym::mul(&p("c"), &q())]);
    assert_eq!(text(&g.diff(Atom::State(0))), "c*exp(c*q)");
    let h = Sym::call(Function::Sqrt, vec![q()]);
    assert_eq!(text(&h.diff(Atom::State(0))), "1/(2*sqrt(q))");
    let cubic = Sym::mul(&p("k"), &q().powi(3).unwrap());
    assert_eq!(text(&cubic.diff(Atom::State(0))), "3*k*q^2");
    assert!(cubic.diff(Atom::State(1)).is_zero());
    let atan = Sym::call(Function::Atan, vec![q()]);
    assert_eq!(text(&atan.diff(Atom::State(0))), "1/(q^2 + 1)");
}

#[test]
fn derivatives_agree_with_finite_differences() {
    let exprs = [
        Sym::mul(&Sym::call(Function::Tanh, vec![q()]), &pm()),
        Sym::call(Function::Max, vec![q(), Sym::mul(&pm(), &pm())]),
        Sym::call(Function::Min, vec![q(), pm(), Sym::integer(1)]),
        Sym::powf(&pm(), &q()).unwrap(),
        Sym::mul(
            &Sym::call(Function::Sign, vec![q()]),
            &Sym::call(Function::Abs, vec![q()])
                .pow(Rational::new(3, 2).unwrap())
                .unwrap(),
        ),
        Sym::call(
            Function::Ln,
            vec![Sym::add(&q(), &Sym::call(Function::Tan, vec![pm()]))],
        ),
    ];
    let values = [0.3, 0.7];
    fn at(x: [f64; 2]) -> impl Fn(Atom) -> f64 {
        move |a: Atom| match a {
            Atom::State(i) => x[i as usize],
            _ => f64::NAN,
        }
    }
    for e in &exprs {
        for k in 0..2 {
            let d = e.diff(Atom::State(k as u32));
            let h = 1e-6;
            let mut plus = values;
            plus[k] += h;
            let mut minus = values;
            minus[k] -= h;
            let numeric = (e.eval(&at(plus), &[]) - e.eval(&at(minus), &[])) / (2.0 * h);
            let symbolic = d.eval(&at(values), &[]);
            assert!(
                (numeric - symbolic).abs() < 1e-7,
                "{} d/dx{k}: {numeric} vs {symbolic}",
                text(e)
            );
        }
    }
}

#[test]
fn a_tape_evaluated_in_place_leaves_its_inputs_for_the_next_tape() {
    // q p + q and sin(q) on one tape, p - q on another, read from the first's registers:
    // at q = 0.5, p = 2: 1.5, sin(0.5), 1.5, and the input registers still hold 0.5 and 2.
    let slot = |a: Atom| match a {
        Atom::State(i) => Some(i as usize),
        _ => None,
    };
    let mut first = TapeBuilder::new(2, &slot, &[]);
    first.push(&Sym::add(&Sym::mul(&q(), &pm()), &q())).unwrap();
    first.push(&Sym::call(Function::Sin, vec![q()])).unwrap();
    let first = first.finish();
    let mut second = TapeBuilder::new(2, &slot, &[]);
    second.push(&Sym::sub(&pm(), &q())).unwrap();
    let second = second.finish();
    let mut registers = first.scratch();
    registers[..2].copy_from_slice(&[0.5, 2.0]);
    let mut out = [0.0; 2];
    first.eval_in_place(&mut registers, &mut out);
    assert_eq!(out, [1.5, 0.5f64.sin()]);
    assert_eq!(registers[..2], [0.5, 2.0]);
    let mut difference = [0.0];
    second.eval(&registers[..2], &mut second.scratch(), &mut difference);
    assert_eq!(difference, [1.5]);
}

#[test]
fn the_tape_evaluates_like_the_tree() {
    let exprs = [
        Sym::mul(&Sym::neg(&p("k")), &Sym::call(Function::Sin, vec![q()])),
        Sym::add(&Sym::div(&pm(), &p("m")).unwrap(), &Sym::integer(2)),
        Sym::mul(
            &Sym::call(Function::Sign, vec![q()]),
            &Sym::call(Function::Sqrt, vec![Sym::call(Function::Abs, vec![q()])]),
        ),
        Sym::powf(&Sym::add(&pm(), &Sym::one()), &Sym::mul(&q(), &p("c"))).unwrap(),
        Sym::call(Function::Max, vec![q(), pm(), Sym::neg(&p("b"))]),
        q().pow(Rational::new(-1, 3).unwrap()).unwrap(),
    ];
    let values = [0.5, 2.0, 9.81, 3.0, 1.0, 1.5];
    let slot = |a: Atom| match a {
        Atom::State(i) => Some(i as usize),
        _ => None,
    };
    let mut builder = TapeBuilder::new(2, &slot, &values);
    for e in &exprs {
        builder.push(e).unwrap();
    }
    assert_eq!(
        builder.push(&Sym::atom(Atom::Input(0))),
        Err(Atom::Input(0))
    );
    let tape = builder.finish();
    for x in [[-0.4, 1.3], [0.25, 0.5]] {
        let out = tape.eval_alloc(&x);
        for (e, v) in exprs.iter().zip(&out) {
            let tree = e.eval(
                &|a| match a {
                    Atom::State(i) => x[i as usize],
                    _ => f64::NAN,
                },
                &values,
            );
            assert!(
                (tree - v).abs() <= 1e-14 * tree.abs().max(1.0),
                "{}: {tree} vs {v}",
                text(e)
            );
        }
    }
}

#[test]
fn laws_invert_where_they_can() {
    let port = Sym::atom(Atom::Port);
    let y = Sym::atom(Atom::Input(0));
    // An orifice: c*sign(e)*sqrt(|e|) = y gives e = sign(y/c)*|y/c|^2.
    let orifice = Sym::mul(
        &Sym::mul(&p("c"), &Sym::call(Function::Sign, vec![port.clone()])),
        &Sym::call(
            Function::Sqrt,
            vec![Sym::call(Function::Abs, vec![port.clone()])],
        ),
    );
    let inverse = orifice.solve_for(Atom::Port, &y).unwrap();
    let check = |e: &Sym, v: f64, c: f64| {
        e.eval(
            &|a| match a {
                Atom::Input(0) | Atom::Port => v,
                _ => f64::NAN,
            },
            &[0.0, c, 0.0, 0.0, 0.0, 0.0],
        )
    };
    for v in [-2.0, 0.5, 3.0] {
        let e = check(&inverse, v, 0.7);
        assert!((check(&orifice, e, 0.7) - v).abs() < 1e-12);
    }
    // A diode: I_s*(exp(e/V_T) - 1) = y.
    let diode = Sym::mul(
        &p("c"),
        &Sym::sub(
            &Sym::call(Function::Exp, vec![Sym::div(&port, &p("b")).unwrap()]),
            &Sym::one(),
        ),
    );
    let inverse = diode.solve_for(Atom::Port, &y).unwrap();
    assert_eq!(text(&inverse), "b*ln(u/c + 1)");
    // Not invertible: a sine, a square, the variable twice.
    assert!(
        Sym::call(Function::Sin, vec![port.clone()])
            .solve_for(Atom::Port, &y)
            .is_none()
    );
    assert!(port.powi(2).unwrap().solve_for(Atom::Port, &y).is_none());
    assert!(
        Sym::add(&port, &Sym::call(Function::Exp, vec![port.clone()]))
            .solve_for(Atom::Port, &y)
            .is_none()
    );
    // A cubic spring law and a linear one invert.
    let cubic = Sym::mul(&p("k"), &port.powi(3).unwrap());
    assert_eq!(
        text(&cubic.solve_for(Atom::Port, &y).unwrap()),
        "(u/k)^(1/3)"
    );
}

#[test]
fn latex_reads_like_a_paper() {
    let f = Sym::sub(
        &Sym::mul(
            &Sym::neg(&Sym::div(&p("g"), &p("l")).unwrap()),
            &Sym::call(Function::Sin, vec![q()]),
        ),
        &Sym::div(&pm(), &p("m")).unwrap(),
    );
    assert_eq!(
        f.latex(&table(), &names),
        "-\\frac{g}{l} \\sin\\left(q\\right) - \\frac{1}{m} p"
    );
}

#[test]
fn a_linear_and_quadratic_drag_inverts_and_stays_finite_without_its_quadratic_term() {
    // R_2*u + K_o*u*|u| = y: for R_2 = 4, K_o = 0.5, y = 6 the root is u = 1.2915...
    // (0.5u^2 + 4u - 6 = 0, u = -4 + sqrt(16 + 12) = 1.29150262...), and for y = -6 its
    // negative. With K_o = 0 it is y/R_2.
    let port = Sym::atom(Atom::Port);
    let y = Sym::atom(Atom::Input(0));
    let law = Sym::add(
        &Sym::mul(&p("b"), &port),
        &Sym::mul(
            &p("c"),
            &Sym::mul(&port, &Sym::call(Function::Abs, vec![port.clone()])),
        ),
    );
    let inverse = law.solve_for(Atom::Port, &y).unwrap();
    let at = |e: &Sym, v: f64, b: f64, c: f64| {
        e.eval(
            &|a| match a {
                Atom::Input(0) | Atom::Port => v,
                _ => f64::NAN,
            },
            &[b, c, 0.0, 0.0, 0.0, 0.0],
        )
    };
    let root = -4.0 + 28f64.sqrt();
    assert!((at(&inverse, 6.0, 4.0, 0.5) - root).abs() < 1e-12);
    assert!((at(&inverse, -6.0, 4.0, 0.5) + root).abs() < 1e-12);
    assert!((at(&inverse, 6.0, 4.0, 0.0) - 1.5).abs() < 1e-15);
    // sign(u)*u^2 is the same law.
    let signed = Sym::add(
        &Sym::mul(&p("b"), &port),
        &Sym::mul(
            &p("c"),
            &Sym::mul(
                &Sym::call(Function::Sign, vec![port.clone()]),
                &port.powi(2).unwrap(),
            ),
        ),
    );
    let inverse = signed.solve_for(Atom::Port, &y).unwrap();
    assert!((at(&inverse, -6.0, 4.0, 0.5) + root).abs() < 1e-12);
}

/// Halves and quarters are taken by square roots: exact where the answer is a small integer
/// (16^(5/4) = 32, 81^(3/4) = 27, 4^(-1/2) = 1/2), within 3 ulps of `powf` elsewhere, and
/// `powf`'s conventions at zero and infinity.
#[test]
fn halves_and_quarters_by_square_roots() {
    let r = |n, d| Rational::new(n, d).unwrap();
    assert_eq!(power(16.0, r(5, 4)), 32.0);
    assert_eq!(power(81.0, r(3, 4)), 27.0);
    assert_eq!(power(4.0, r(-1, 2)), 0.5);
    assert_eq!(power(256.0, r(-7, 4)), 1.0 / 16384.0);
    assert_eq!(power(0.0, r(5, 4)), 0.0);
    assert_eq!(power(0.0, r(-3, 4)), f64::INFINITY);
    assert_eq!(power(f64::INFINITY, r(-1, 4)), 0.0);
    let mut x = 1.234_567e-7;
    while x < 1e9 {
        for (n, d) in [
            (1, 2),
            (3, 2),
            (5, 2),
            (1, 4),
            (3, 4),
            (5, 4),
            (7, 4),
            (-5, 4),
            (-3, 2),
        ] {
            let fast = power(x, r(n, d));
            let reference = x.powf(n as f64 / d as f64);
            assert!(
                (fast - reference).abs() <= 3.0 * f64::EPSILON * reference,
                "{x}^({n}/{d}): {fast} against {reference}"
            );
        }
        x *= 1.7;
    }
}
