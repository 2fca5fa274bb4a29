//! Solving an expression for one of its variables, where that can be done symbolically:
//! how a resistor's law `flow: f(effort)` becomes `effort: f⁻¹(flow)`.
//!
//! The variable must occur once along a chain of invertible steps: a sum (`a + c·g(x)`), a
//! product (`c·g(x)^e` with an odd numerator of `e`, or a square root), `exp`, `ln`, `tanh`,
//! `atan`, `tan`, the odd power laws `sign(x)·|x|^e` that orifices and turbulent flow
//! follow, and the sum of a linear and a quadratic drag `a·u + b·u·|u|` (a pipe's laminar
//! and turbulent losses). Everything else (a `sin` of it, `x^2`, `x` twice) is not inverted: the law then
//! fixes its element's causality.

use crate::RatFunc;
use crate::function::Function;

use super::{Atom, Node, Rational, Sym};

impl Sym {
    /// The `x` with `self(x) = target`, if it can be found symbolically (see the module
    /// documentation).
    pub fn solve_for(&self, x: Atom, target: &Sym) -> Option<Sym> {
        if *self == Sym::atom(x) {
            return Some(target.clone());
        }
        if !self.mentions(x) {
            return None;
        }
        match self.node() {
            Node::Sum(constant, terms) => {
                let with: Vec<&(Sym, RatFunc)> =
                    terms.iter().filter(|(t, _)| t.mentions(x)).collect();
                let rest = Sym::sum(
                    std::iter::once((Sym::coefficient(constant.clone()), RatFunc::one())).chain(
                        terms
                            .iter()
                            .filter(|(t, _)| !t.mentions(x))
                            .map(|(t, c)| (t.clone(), c.clone())),
                    ),
                );
                let y = Sym::sub(target, &rest);
                match with.as_slice() {
                    [(term, c)] => term.solve_for(x, &y.scaled(&c.inv()?)),
                    [(t1, c1), (t2, c2)] => linear_and_quadratic(t1, c1, t2, c2, x, &y),
                    _ => None,
                }
            }
            Node::Product(factors) => {
                let with: Vec<&(Sym, Rational)> =
                    factors.iter().filter(|(b, _)| b.mentions(x)).collect();
                let rest = factors
                    .iter()
                    .filter(|(b, _)| !b.mentions(x))
                    .try_fold(Sym::one(), |acc, (b, e)| Some(Sym::mul(&acc, &b.pow(*e)?)))?;
                let y = Sym::div(target, &rest)?;
                match with.as_slice() {
                    [(base, e)] => invert_power(base, *e, x, &y),
                    [(a, ea), (b, eb)] => odd_power_law(a, *ea, b, *eb, x, &y),
                    _ => None,
                }
            }
            Node::Call(function, args) => {
                let a = &args[0];
                let inner = match function {
                    Function::Exp => Sym::call(Function::Ln, vec![target.clone()]),
                    Function::Ln => Sym::call(Function::Exp, vec![target.clone()]),
                    Function::Tan => Sym::call(Function::Atan, vec![target.clone()]),
                    Function::Atan => Sym::call(Function::Tan, vec![target.clone()]),
                    Function::Tanh => {
                        // atanh(y) = ln((1 + y)/(1 - y))/2
                        let ratio = Sym::div(
                            &Sym::add(&Sym::one(), target),
                            &Sym::sub(&Sym::one(), target),
                        )?;
                        Sym::call(Function::Ln, vec![ratio])
                            .scaled(&RatFunc::rational(1.into(), 2.into())?)
                    }
                    _ => return None,
                };
                a.solve_for(x, &inner)
            }
            _ => None,
        }
    }
}

/// `base^e = y` for `base`: real odd roots, and the principal branch of even roots of a
/// square root (`sqrt(b) = y` gives `b = y^2`).
fn invert_power(base: &Sym, e: Rational, x: Atom, y: &Sym) -> Option<Sym> {
    let inverse = Rational::new(e.denominator(), e.numerator())?;
    if e.numerator() % 2 == 0 {
        return None;
    }
    base.solve_for(x, &y.pow(inverse)?)
}

/// `sign(u)·|u|^e = y` (in either order) for `u`: `u = sign(y)·|y|^(1/e)`.
fn odd_power_law(a: &Sym, ea: Rational, b: &Sym, eb: Rational, x: Atom, y: &Sym) -> Option<Sym> {
    let (sign, magnitude, e) = match (a.node(), b.node()) {
        (Node::Call(Function::Sign, s), Node::Call(Function::Abs, m))
            if ea == Rational::integer(1) =>
        {
            (s, m, eb)
        }
        (Node::Call(Function::Abs, m), Node::Call(Function::Sign, s))
            if eb == Rational::integer(1) =>
        {
            (s, m, ea)
        }
        _ => return None,
    };
    if sign[0] != magnitude[0] {
        return None;
    }
    let inverse = Rational::new(e.denominator(), e.numerator())?;
    let root = Sym::mul(
        &Sym::call(Function::Sign, vec![y.clone()]),
        &Sym::call(Function::Abs, vec![y.clone()]).pow(inverse)?,
    );
    sign[0].solve_for(x, &root)
}

/// `a·u + b·u·|u| = y` (in either order; `b·sign(u)·u^2` too) for `u`:
/// `u = 2y / (a + sqrt(a^2 + 4b|y|))`, the root of the quadratic that keeps the sign of `y`,
/// written so that it stays finite, and gives `y/a`, where `b` is zero.
fn linear_and_quadratic(
    t1: &Sym,
    c1: &RatFunc,
    t2: &Sym,
    c2: &RatFunc,
    x: Atom,
    y: &Sym,
) -> Option<Sym> {
    let (u, a, b) = if is_signed_square_of(t2, t1) {
        (t1, c1, c2)
    } else if is_signed_square_of(t1, t2) {
        (t2, c2, c1)
    } else {
        return None;
    };
    let a = Sym::coefficient(a.clone());
    let discriminant = Sym::add(
        &a.powi(2)?,
        &Sym::call(Function::Abs, vec![y.clone()]).scaled(&(b * &RatFunc::integer(4))),
    );
    let denominator = Sym::add(&a, &Sym::call(Function::Sqrt, vec![discriminant]));
    let root = Sym::div(&y.scaled(&RatFunc::integer(2)), &denominator)?;
    u.solve_for(x, &root)
}

/// Whether `term` is `u·|u|` or `sign(u)·u^2` (either order of the factors).
fn is_signed_square_of(term: &Sym, u: &Sym) -> bool {
    let Node::Product(factors) = term.node() else {
        return false;
    };
    let one = Rational::integer(1);
    let is = |f: &(Sym, Rational), function: Function, e: Rational| {
        f.1 == e && matches!(f.0.node(), Node::Call(g, args) if *g == function && args[0] == *u)
    };
    match factors.as_slice() {
        [f, g] => {
            let plain = |f: &(Sym, Rational), e: Rational| f.1 == e && f.0 == *u;
            (plain(f, one) && is(g, Function::Abs, one))
                || (plain(g, one) && is(f, Function::Abs, one))
                || (plain(f, Rational::integer(2)) && is(g, Function::Sign, one))
                || (plain(g, Rational::integer(2)) && is(f, Function::Sign, one))
        }
        _ => false,
    }
}
