//! Derivatives of symbolic expressions, for Jacobians.
//!
//! The rules are the textbook ones; `|x|' = sign(x)`, `sign' = 0` (almost everywhere), and
//! `min`/`max` are differentiated through `min(a, b) = (a + b)/2 - |a - b|/2`, so the
//! derivative takes the branch that is active.

use crate::RatFunc;
use crate::function::Function;

use super::{Atom, Node, Rational, Sym};

impl Sym {
    /// `∂self/∂atom`.
    pub fn diff(&self, atom: Atom) -> Sym {
        if !self.mentions(atom) {
            return Sym::zero();
        }
        match self.node() {
            Node::Coefficient(_) => Sym::zero(),
            Node::Atom(a) => {
                if *a == atom {
                    Sym::one()
                } else {
                    Sym::zero()
                }
            }
            Node::Sum(_, terms) => Sym::sum(terms.iter().map(|(t, c)| (t.diff(atom), c.clone()))),
            Node::Product(factors) => {
                // d Π bᵢ^eᵢ = Σᵢ eᵢ bᵢ^(eᵢ-1) dbᵢ Π_{j≠i} bⱼ^eⱼ
                let mut parts = Vec::new();
                for (i, (base, exponent)) in factors.iter().enumerate() {
                    let d = base.diff(atom);
                    if d.is_zero() {
                        continue;
                    }
                    let lowered = base
                        .pow(
                            Rational::new(
                                exponent.numerator() - exponent.denominator(),
                                exponent.denominator(),
                            )
                            .expect("non-zero denominator"),
                        )
                        .unwrap_or_else(Sym::zero);
                    let mut term = Sym::mul(&lowered, &d);
                    for (j, (other, e)) in factors.iter().enumerate() {
                        if j != i {
                            term = Sym::mul(&term, &other.pow(*e).unwrap_or_else(Sym::zero));
                        }
                    }
                    let factor = RatFunc::rational(
                        exponent.numerator().into(),
                        exponent.denominator().into(),
                    )
                    .expect("non-zero denominator");
                    parts.push((term, factor));
                }
                Sym::sum(parts)
            }
            Node::Power(base, exponent) => {
                // d b^e = b^e (e' ln b + e b'/b)
                let ln = Sym::call(Function::Ln, vec![base.clone()]);
                let inner = Sym::add(
                    &Sym::mul(&exponent.diff(atom), &ln),
                    &Sym::div(&Sym::mul(exponent, &base.diff(atom)), base)
                        .unwrap_or_else(Sym::zero),
                );
                Sym::mul(self, &inner)
            }
            Node::Call(function, args) => call_derivative(*function, args, atom),
        }
    }
}

fn call_derivative(function: Function, args: &[Sym], atom: Atom) -> Sym {
    let a = &args[0];
    let da = a.diff(atom);
    let square = |x: &Sym| x.powi(2).expect("a square exists");
    let outer = match function {
        Function::Sin => Sym::call(Function::Cos, vec![a.clone()]),
        Function::Cos => Sym::neg(&Sym::call(Function::Sin, vec![a.clone()])),
        Function::Tan => Sym::add(
            &Sym::one(),
            &square(&Sym::call(Function::Tan, vec![a.clone()])),
        ),
        Function::Exp => Sym::call(Function::Exp, vec![a.clone()]),
        Function::Ln => a.powi(-1).unwrap_or_else(Sym::zero),
        Function::Sqrt => Sym::div(
            &Sym::integer(1),
            &Sym::call(Function::Sqrt, vec![a.clone()]),
        )
        .map(|s| s.scaled(&RatFunc::rational(1.into(), 2.into()).expect("1/2")))
        .unwrap_or_else(Sym::zero),
        Function::Abs => Sym::call(Function::Sign, vec![a.clone()]),
        Function::Sign => Sym::zero(),
        Function::Tanh => Sym::sub(
            &Sym::one(),
            &square(&Sym::call(Function::Tanh, vec![a.clone()])),
        ),
        Function::Atan => Sym::add(&Sym::one(), &square(a))
            .powi(-1)
            .unwrap_or_else(Sym::zero),
        Function::Min | Function::Max => {
            // Fold to two arguments: min(a, b, c) = min(min(a, b), c).
            let (first, rest) = args.split_at(args.len() - 1);
            let left = if first.len() == 1 {
                first[0].clone()
            } else {
                Sym::call(function, first.to_vec())
            };
            let right = &rest[0];
            let (dl, dr) = (left.diff(atom), right.diff(atom));
            let half = RatFunc::rational(1.into(), 2.into()).expect("1/2");
            let switch = Sym::call(Function::Sign, vec![Sym::sub(&left, right)]);
            let sign = if function == Function::Max { 1 } else { -1 };
            return Sym::sum([
                (Sym::add(&dl, &dr), half.clone()),
                (
                    Sym::mul(&switch, &Sym::sub(&dl, &dr)),
                    &half * &RatFunc::integer(sign),
                ),
            ]);
        }
    };
    Sym::mul(&outer, &da)
}
