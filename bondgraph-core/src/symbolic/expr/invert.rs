//! Solving an expression for one of its variables, where that can be done symbolically:
//! how a resistor's law `flow: f(effort)` becomes `effort: f⁻¹(flow)`.
//!
//! The variable must occur once along a chain of invertible steps: a sum (`a + c·g(x)`), a
//! product (`c·g(x)^e` with an odd numerator of `e`, or a square root), `exp`, `ln`, `tanh`,
//! `atan`, `tan`, and the odd power laws `sign(x)·|x|^e` that orifices and turbulent flow
//! follow. Everything else (a `sin` of it, `x^2`, `x` twice) is not inverted: the law then
//! fixes its element's causality.

use crate::expr::Function;
use crate::symbolic::RatFunc;

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
                let mut with: Vec<&(Sym, RatFunc)> =
                    terms.iter().filter(|(t, _)| t.mentions(x)).collect();
                if with.len() != 1 {
                    return None;
                }
                let (term, c) = with.pop().expect("one term");
                let rest = Sym::sum(
                    std::iter::once((Sym::coefficient(constant.clone()), RatFunc::one())).chain(
                        terms
                            .iter()
                            .filter(|(t, _)| !t.mentions(x))
                            .map(|(t, c)| (t.clone(), c.clone())),
                    ),
                );
                let inner = Sym::sub(target, &rest).scaled(&c.inv()?);
                term.solve_for(x, &inner)
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
