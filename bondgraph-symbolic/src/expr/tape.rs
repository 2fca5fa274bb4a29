//! Compilation of symbolic expressions to a flat evaluation program: the solver's inner loop.
//!
//! A [`Tape`] is a list of register operations. Common subexpressions are computed once
//! (the same `sin(q)` in `f` and in its Jacobian is one register), parameter-only parts are
//! folded into constants when the tape is built, and evaluation writes into a scratch
//! buffer the caller keeps, so it allocates nothing.
//!
//! # Example
//! ```
//! use bondgraph_symbolic::function::Function;
//! use bondgraph_symbolic::expr::{Atom, Sym, TapeBuilder};
//!
//! let q = Sym::atom(Atom::State(0));
//! let f = Sym::mul(&Sym::integer(3), &Sym::call(Function::Sin, vec![q.clone()]));
//! let slot = |a: Atom| match a { Atom::State(0) => Some(0), _ => None };
//! let mut builder = TapeBuilder::new(1, &slot, &[]);
//! builder.push(&f).unwrap();
//! builder.push(&f.diff(Atom::State(0))).unwrap();
//! let tape = builder.finish();
//! let mut scratch = tape.scratch();
//! let mut out = [0.0; 2];
//! tape.eval(&[0.5], &mut scratch, &mut out);
//! assert_eq!(out, [3.0 * 0.5f64.sin(), 3.0 * 0.5f64.cos()]);
//! ```

use std::collections::HashMap;

use crate::function::Function;

use super::{Atom, Node, Rational, Sym, power};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Add(u32, u32, u32),
    Sub(u32, u32, u32),
    Mul(u32, u32, u32),
    Div(u32, u32, u32),
    /// `dst = acc + c * t`.
    MulAdd(u32, u32, u32, u32),
    PowI(u32, u32, i32),
    PowR(u32, u32, Rational),
    PowF(u32, u32, u32),
    Call(u32, Function, u32),
    Min(u32, u32, u32),
    Max(u32, u32, u32),
}

/// A compiled set of expressions; see the module documentation of `symbolic::expr::tape`.
#[derive(Clone, Debug)]
pub struct Tape {
    inputs: usize,
    /// Register contents before evaluation: zeros for inputs and temporaries, the folded
    /// constants in their registers.
    initial: Vec<f64>,
    ops: Vec<Op>,
    outputs: Vec<u32>,
}

impl Tape {
    /// A scratch buffer for [`Tape::eval`], holding the tape's constants.
    pub fn scratch(&self) -> Vec<f64> {
        self.initial.clone()
    }

    /// The number of expressions compiled.
    pub fn output_count(&self) -> usize {
        self.outputs.len()
    }

    /// The number of inputs the tape reads.
    pub fn input_count(&self) -> usize {
        self.inputs
    }

    /// Evaluates every expression at `input` into `out` (one value per expression pushed),
    /// using `scratch` from [`Tape::scratch`].
    pub fn eval(&self, input: &[f64], scratch: &mut [f64], out: &mut [f64]) {
        scratch[..self.inputs].copy_from_slice(&input[..self.inputs]);
        self.eval_in_place(scratch, out);
    }

    /// [`Tape::eval`] with the input already in the first [`Tape::input_count`] registers
    /// of `scratch` (from [`Tape::scratch`]): for a caller that evaluates one tape many
    /// times and writes its few inputs there itself, saving a copy per evaluation. Every
    /// operation writes a register of its own past the inputs, so the input registers are
    /// left as they were, for the next tape reading the same input.
    pub fn eval_in_place(&self, scratch: &mut [f64], out: &mut [f64]) {
        let r = scratch;
        for op in &self.ops {
            match *op {
                Op::Add(d, a, b) => r[d as usize] = r[a as usize] + r[b as usize],
                Op::Sub(d, a, b) => r[d as usize] = r[a as usize] - r[b as usize],
                Op::Mul(d, a, b) => r[d as usize] = r[a as usize] * r[b as usize],
                Op::Div(d, a, b) => r[d as usize] = r[a as usize] / r[b as usize],
                Op::MulAdd(d, acc, c, t) => {
                    r[d as usize] = multiply_add(r[c as usize], r[t as usize], r[acc as usize]);
                }
                Op::PowI(d, a, n) => r[d as usize] = r[a as usize].powi(n),
                Op::PowR(d, a, e) => r[d as usize] = power(r[a as usize], e),
                Op::PowF(d, a, b) => r[d as usize] = r[a as usize].powf(r[b as usize]),
                Op::Call(d, f, a) => r[d as usize] = f.apply(std::slice::from_ref(&r[a as usize])),
                Op::Min(d, a, b) => r[d as usize] = r[a as usize].min(r[b as usize]),
                Op::Max(d, a, b) => r[d as usize] = r[a as usize].max(r[b as usize]),
            }
        }
        for (slot, register) in out.iter_mut().zip(&self.outputs) {
            *slot = r[*register as usize];
        }
    }

    /// Evaluates every expression, allocating: for occasional use (checks at events).
    pub fn eval_alloc(&self, input: &[f64]) -> Vec<f64> {
        let mut scratch = self.scratch();
        let mut out = vec![0.0; self.outputs.len()];
        self.eval(input, &mut scratch, &mut out);
        out
    }
}

/// `a b + c`: fused where the build targets a processor with the instruction, else in two
/// roundings. Without it, `f64::mul_add` is a call into the software routine (about a tenth
/// of a nonlinear model's evaluation on a baseline x86-64 build), for an accuracy a rate's
/// terms do not need.
#[inline(always)]
fn multiply_add(a: f64, b: f64, c: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// Builds a [`Tape`] from expressions, sharing what they have in common.
pub struct TapeBuilder<'a> {
    inputs: usize,
    slot_of: &'a dyn Fn(Atom) -> Option<usize>,
    values: &'a [f64],
    registers: HashMap<Sym, u32>,
    constants: HashMap<u64, u32>,
    initial: Vec<f64>,
    ops: Vec<Op>,
    outputs: Vec<u32>,
}

impl<'a> TapeBuilder<'a> {
    /// A builder for a tape reading `inputs` values; `slot_of` says where each variable is
    /// in the input (`None`: the variable may not appear), `values` are the parameter values.
    pub fn new(
        inputs: usize,
        slot_of: &'a dyn Fn(Atom) -> Option<usize>,
        values: &'a [f64],
    ) -> Self {
        Self {
            inputs,
            slot_of,
            values,
            registers: HashMap::new(),
            constants: HashMap::new(),
            initial: vec![0.0; inputs],
            ops: Vec::new(),
            outputs: Vec::new(),
        }
    }

    /// Adds `expr` as the next output; returns its index.
    ///
    /// # Errors
    /// The first variable of `expr` that has no input slot.
    pub fn push(&mut self, expr: &Sym) -> Result<usize, Atom> {
        let register = self.compile(expr)?;
        self.outputs.push(register);
        Ok(self.outputs.len() - 1)
    }

    /// The finished tape.
    pub fn finish(self) -> Tape {
        Tape {
            inputs: self.inputs,
            initial: self.initial,
            ops: self.ops,
            outputs: self.outputs,
        }
    }

    fn constant(&mut self, value: f64) -> u32 {
        let key = value.to_bits();
        if let Some(r) = self.constants.get(&key) {
            return *r;
        }
        let r = self.initial.len() as u32;
        self.initial.push(value);
        self.constants.insert(key, r);
        r
    }

    fn temporary(&mut self) -> u32 {
        self.initial.push(0.0);
        (self.initial.len() - 1) as u32
    }

    fn emit(&mut self, make: impl FnOnce(u32) -> Op) -> u32 {
        let d = self.temporary();
        self.ops.push(make(d));
        d
    }

    fn compile(&mut self, expr: &Sym) -> Result<u32, Atom> {
        if let Some(r) = self.registers.get(expr) {
            return Ok(*r);
        }
        let register = match expr.node() {
            Node::Coefficient(c) => {
                let value = c.eval(self.values);
                self.constant(value)
            }
            Node::Atom(a) => match (self.slot_of)(*a) {
                Some(slot) => slot as u32,
                None => return Err(*a),
            },
            Node::Sum(constant, terms) => {
                let mut acc: Option<u32> = None;
                if !constant.is_zero() {
                    let value = constant.eval(self.values);
                    acc = Some(self.constant(value));
                }
                for (term, c) in terms {
                    let t = self.compile(term)?;
                    let value = c.eval(self.values);
                    acc = Some(match acc {
                        None if value == 1.0 => t,
                        None => {
                            let c = self.constant(value);
                            self.emit(|d| Op::Mul(d, c, t))
                        }
                        Some(a) if value == 1.0 => self.emit(|d| Op::Add(d, a, t)),
                        Some(a) if value == -1.0 => self.emit(|d| Op::Sub(d, a, t)),
                        Some(a) => {
                            let c = self.constant(value);
                            self.emit(|d| Op::MulAdd(d, a, c, t))
                        }
                    });
                }
                match acc {
                    Some(a) => a,
                    None => self.constant(0.0),
                }
            }
            Node::Product(factors) => {
                let mut numerator: Option<u32> = None;
                let mut denominator: Option<u32> = None;
                for (base, exponent) in factors {
                    let b = self.compile(base)?;
                    let (slot, e) = if exponent.numerator() < 0 {
                        (
                            &mut denominator,
                            Rational::new(-exponent.numerator(), exponent.denominator())
                                .expect("non-zero"),
                        )
                    } else {
                        (&mut numerator, *exponent)
                    };
                    let p = if e == Rational::integer(1) {
                        b
                    } else if e.numerator() == 1 && e.denominator() == 2 {
                        let d = (self.initial.len()) as u32;
                        self.initial.push(0.0);
                        self.ops.push(Op::Call(d, Function::Sqrt, b));
                        d
                    } else if e.is_integer() && i32::try_from(e.numerator()).is_ok() {
                        let n = e.numerator() as i32;
                        let d = (self.initial.len()) as u32;
                        self.initial.push(0.0);
                        self.ops.push(Op::PowI(d, b, n));
                        d
                    } else {
                        let d = (self.initial.len()) as u32;
                        self.initial.push(0.0);
                        self.ops.push(Op::PowR(d, b, e));
                        d
                    };
                    let current = *slot;
                    *slot = Some(match current {
                        None => p,
                        Some(a) => {
                            let d = (self.initial.len()) as u32;
                            self.initial.push(0.0);
                            self.ops.push(Op::Mul(d, a, p));
                            d
                        }
                    });
                }
                match (numerator, denominator) {
                    (Some(n), None) => n,
                    (Some(n), Some(m)) => self.emit(|d| Op::Div(d, n, m)),
                    (None, Some(m)) => {
                        let one = self.constant(1.0);
                        self.emit(|d| Op::Div(d, one, m))
                    }
                    (None, None) => self.constant(1.0),
                }
            }
            Node::Power(base, exponent) => {
                let (b, e) = (self.compile(base)?, self.compile(exponent)?);
                self.emit(|d| Op::PowF(d, b, e))
            }
            Node::Call(function, args) => match function {
                Function::Min | Function::Max => {
                    let mut acc = self.compile(&args[0])?;
                    for arg in &args[1..] {
                        let b = self.compile(arg)?;
                        acc = if *function == Function::Min {
                            self.emit(|d| Op::Min(d, acc, b))
                        } else {
                            self.emit(|d| Op::Max(d, acc, b))
                        };
                    }
                    acc
                }
                _ => {
                    let a = self.compile(&args[0])?;
                    self.emit(|d| Op::Call(d, *function, a))
                }
            },
        };
        self.registers.insert(expr.clone(), register);
        Ok(register)
    }
}
