//! Symbolic expressions for nonlinear laws: `m*g*l*sin(q_pendulum)`, `-c_d*sqrt(q_tank/C)`.
//!
//! A nonlinear law is no rational function of the parameters, so [`RatFunc`] alone cannot
//! hold it; but most of a nonlinear model is still linear algebra with exact parameter
//! coefficients (junction sums, constant ratios). A [`Sym`] therefore keeps every
//! parameter-only part as an exact [`RatFunc`] coefficient and adds only what is needed on
//! top: variables ([`Atom`]: states, inputs, bond variables), sums with coefficients,
//! products with rational exponents, real powers and the functions of
//! [`Function`].
//!
//! # Canonical form
//! Every constructor normalises, so equal things print equally however they were built:
//! - sums are flat, like terms are collected (`a*x + b*x` is `(a + b)*x`), zero terms are
//!   dropped and the constant is folded into one exact coefficient;
//! - products are flat, equal bases have their exponents added (`x*x^-1` is 1), and the
//!   numeric and parameter factors are pulled out as the term's coefficient;
//! - a coefficient times a sum is distributed, so affine parts stay affine;
//! - functions of exact constants fold where the value is exact (`sin(0)`, `exp(0)`,
//!   `sqrt(4)`), `sqrt(x)` is `x^(1/2)`;
//! - terms and factors are sorted by the first variable they mention (states first, in
//!   state order), then by shape, so equations print in the order of the states.
//!
//! Sums are not multiplied out (`r*(a + b)` stays a product): the form is canonical enough
//! for printing and comparison, not a decision procedure for equality.
//!
//! Submodules: `diff` (derivatives, for Jacobians), `print` (text and LaTeX), `tape`
//! (compilation to a flat evaluation program), `invert` (solving a law for its port
//! variable).
//!
//! # Example
//! ```
//! use bondgraph_symbolic::function::Function;
//! use bondgraph_symbolic::expr::{Atom, Sym};
//! use bondgraph_symbolic::{RatFunc, SymbolTable};
//!
//! let table = SymbolTable::new(["g", "l"]);
//! let (g, l) = (table.get("g").unwrap(), table.get("l").unwrap());
//! let q = Sym::atom(Atom::State(0));
//! let ratio = Sym::coefficient(RatFunc::symbol(g).checked_div(&RatFunc::symbol(l)).unwrap());
//! let f = Sym::neg(&Sym::mul(&ratio, &Sym::call(Function::Sin, vec![q.clone()])));
//! let names = |a: Atom| match a { Atom::State(0) => "q".to_string(), _ => "?".to_string() };
//! assert_eq!(f.text(&table, &names), "-g/l*sin(q)");
//! assert_eq!(f.diff(Atom::State(0)).text(&table, &names), "-g/l*cos(q)");
//! ```

mod diff;
mod invert;
mod print;
mod tape;

use std::cmp::Ordering;
use std::collections::BTreeSet;
use std::sync::Arc;

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{Signed, ToPrimitive};

use crate::RatFunc;
use crate::function::Function;

pub use tape::{Tape, TapeBuilder};

/// A variable of a symbolic expression.
///
/// The declaration order is the print order: states first, in state order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Atom {
    /// The `i`-th state.
    State(u32),
    /// The `i`-th input.
    Input(u32),
    /// The time derivative of the `i`-th input.
    InputRate(u32),
    /// The energy variable of storage element `i` (by element index), as laws name it
    /// (`q_spring`) before states are numbered.
    Storage(u32),
    /// The port variable of a resistor's law: its flow in `effort:` laws, its effort in
    /// `flow:` laws.
    Port,
    /// An auxiliary variable of a derivation: the output of the `i`-th nonlinear law.
    Auxiliary(u32),
    /// A bond variable: effort of bond `b` is `2b`, flow is `2b + 1`.
    Bond(u32),
}

/// An exact rational exponent `num/den`, `den > 0`, in lowest terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rational {
    num: i64,
    den: i64,
}

impl Rational {
    /// `num/den` reduced; `None` when `den` is zero.
    pub fn new(num: i64, den: i64) -> Option<Self> {
        if den == 0 {
            return None;
        }
        let g = num.gcd(&den).max(1);
        let sign = if den < 0 { -1 } else { 1 };
        Some(Self {
            num: sign * num / g,
            den: sign * den / g,
        })
    }

    /// An integer exponent.
    pub fn integer(n: i64) -> Self {
        Self { num: n, den: 1 }
    }

    /// The numerator.
    pub fn numerator(self) -> i64 {
        self.num
    }

    /// The denominator (positive).
    pub fn denominator(self) -> i64 {
        self.den
    }

    /// Whether the exponent is an integer.
    pub fn is_integer(self) -> bool {
        self.den == 1
    }

    /// The exponent as a float.
    pub fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }

    fn add(self, other: Self) -> Option<Self> {
        let num = self
            .num
            .checked_mul(other.den)?
            .checked_add(other.num.checked_mul(self.den)?)?;
        Self::new(num, self.den.checked_mul(other.den)?)
    }

    fn mul(self, other: Self) -> Option<Self> {
        Self::new(
            self.num.checked_mul(other.num)?,
            self.den.checked_mul(other.den)?,
        )
    }

    /// The exact rational value of a constant coefficient, if it is one with small terms.
    fn from_ratfunc(value: &RatFunc) -> Option<Self> {
        let (num, den) = value.to_constant()?;
        Self::new(num.to_i64()?, den.to_i64()?)
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> Ordering {
        (i128::from(self.num) * i128::from(other.den))
            .cmp(&(i128::from(other.num) * i128::from(self.den)))
    }
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A symbolic expression in canonical form; cheap to clone (shared).
#[derive(Clone)]
pub struct Sym(Arc<Inner>);

struct Inner {
    node: Node,
    /// The first variable mentioned, in [`Atom`] order: the sort key of terms.
    lead: Option<Atom>,
    /// The node's hash, taken once when first asked for: a tape's builder looks every
    /// subexpression up by it, and hashing the tree below each lookup again made building a
    /// nonlinear mode's tapes (once per mode and trial of a fit) a twentieth of a fit's time.
    hash: std::sync::OnceLock<u64>,
}

/// The shape of a [`Sym`]; see the [module documentation](self) for the invariants.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A parameter-only exact value.
    Coefficient(RatFunc),
    /// A variable.
    Atom(Atom),
    /// `constant + Σ coefficientᵢ·termᵢ`: terms sorted and distinct, none a coefficient or
    /// a sum, no zero coefficient; not a single term with coefficient 1 and no constant.
    Sum(RatFunc, Vec<(Sym, RatFunc)>),
    /// `Π baseᵢ^exponentᵢ`: bases sorted and distinct, none a product or a sum with one
    /// term; exponents non-zero; not a single base with exponent 1. A coefficient is a base
    /// only with a non-integer exponent (`sqrt(g/l)`).
    Product(Vec<(Sym, Rational)>),
    /// `base^exponent` with an exponent that is not an exact rational constant.
    Power(Sym, Sym),
    /// A function applied to its arguments.
    Call(Function, Vec<Sym>),
}

impl PartialEq for Sym {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0) || self.0.node == other.0.node
    }
}

impl Eq for Sym {}

impl std::hash::Hash for Sym {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        // A fixed hasher (`DefaultHasher::new` has fixed keys), so that the value is a
        // function of the node alone; a child's hash is its own cached one.
        let hash = *self.0.hash.get_or_init(|| {
            use std::hash::Hasher;
            let mut hasher = std::hash::DefaultHasher::new();
            self.0.node.hash(&mut hasher);
            hasher.finish()
        });
        state.write_u64(hash);
    }
}

impl std::fmt::Debug for Sym {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.node.fmt(f)
    }
}

impl Ord for Sym {
    fn cmp(&self, other: &Self) -> Ordering {
        if Arc::ptr_eq(&self.0, &other.0) {
            return Ordering::Equal;
        }
        // Terms mentioning a variable come before constants, in variable order.
        let lead = |s: &Sym| (s.0.lead.is_none(), s.0.lead);
        lead(self)
            .cmp(&lead(other))
            .then_with(|| rank(&self.0.node).cmp(&rank(&other.0.node)))
            .then_with(|| cmp_nodes(&self.0.node, &other.0.node))
    }
}

impl PartialOrd for Sym {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

fn rank(node: &Node) -> u8 {
    match node {
        Node::Atom(_) => 0,
        Node::Product(_) => 1,
        Node::Power(..) => 2,
        Node::Call(..) => 3,
        Node::Sum(..) => 4,
        Node::Coefficient(_) => 5,
    }
}

fn cmp_nodes(a: &Node, b: &Node) -> Ordering {
    match (a, b) {
        (Node::Coefficient(x), Node::Coefficient(y)) => cmp_ratfunc(x, y),
        (Node::Atom(x), Node::Atom(y)) => x.cmp(y),
        (Node::Sum(k1, t1), Node::Sum(k2, t2)) => cmp_list(t1, t2, |(s1, c1), (s2, c2)| {
            s1.cmp(s2).then_with(|| cmp_ratfunc(c1, c2))
        })
        .then_with(|| cmp_ratfunc(k1, k2)),
        (Node::Product(f1), Node::Product(f2)) => {
            cmp_list(f1, f2, |(b1, e1), (b2, e2)| b1.cmp(b2).then(e1.cmp(e2)))
        }
        (Node::Power(b1, e1), Node::Power(b2, e2)) => b1.cmp(b2).then_with(|| e1.cmp(e2)),
        (Node::Call(f1, a1), Node::Call(f2, a2)) => {
            f1.cmp(f2).then_with(|| cmp_list(a1, a2, Sym::cmp))
        }
        _ => rank(a).cmp(&rank(b)),
    }
}

fn cmp_list<T>(a: &[T], b: &[T], mut cmp: impl FnMut(&T, &T) -> Ordering) -> Ordering {
    for (x, y) in a.iter().zip(b) {
        let c = cmp(x, y);
        if c != Ordering::Equal {
            return c;
        }
    }
    a.len().cmp(&b.len())
}

/// A fixed total order on rational functions (by their terms), for sorting.
fn cmp_ratfunc(a: &RatFunc, b: &RatFunc) -> Ordering {
    let key = |p: &crate::Poly| -> Vec<(Vec<(usize, u32)>, BigInt)> {
        p.terms()
            .map(|(m, c)| (m.iter().map(|(s, e)| (s.index(), e)).collect(), c.clone()))
            .collect()
    };
    key(a.numerator())
        .cmp(&key(b.numerator()))
        .then_with(|| key(a.denominator()).cmp(&key(b.denominator())))
}

impl Sym {
    fn from_node(node: Node) -> Self {
        let lead = match &node {
            Node::Coefficient(_) => None,
            Node::Atom(a) => Some(*a),
            Node::Sum(_, terms) => terms.iter().filter_map(|(t, _)| t.0.lead).min(),
            Node::Product(factors) => factors.iter().filter_map(|(b, _)| b.0.lead).min(),
            Node::Power(b, e) => [b.0.lead, e.0.lead].into_iter().flatten().min(),
            Node::Call(_, args) => args.iter().filter_map(|a| a.0.lead).min(),
        };
        Sym(Arc::new(Inner {
            node,
            lead,
            hash: std::sync::OnceLock::new(),
        }))
    }

    /// The node, to inspect the expression's shape.
    pub fn node(&self) -> &Node {
        &self.0.node
    }

    /// An exact parameter-only value.
    pub fn coefficient(value: RatFunc) -> Self {
        Self::from_node(Node::Coefficient(value))
    }

    /// An integer.
    pub fn integer(n: i64) -> Self {
        Self::coefficient(RatFunc::integer(n))
    }

    /// Zero.
    pub fn zero() -> Self {
        Self::integer(0)
    }

    /// One.
    pub fn one() -> Self {
        Self::integer(1)
    }

    /// A variable.
    pub fn atom(atom: Atom) -> Self {
        Self::from_node(Node::Atom(atom))
    }

    /// The exact value, if the expression is parameter-only and rational.
    pub fn as_coefficient(&self) -> Option<&RatFunc> {
        match &self.0.node {
            Node::Coefficient(c) => Some(c),
            _ => None,
        }
    }

    /// Whether the expression is exactly zero.
    pub fn is_zero(&self) -> bool {
        self.as_coefficient().is_some_and(RatFunc::is_zero)
    }

    /// Whether the expression is exactly one.
    pub fn is_one(&self) -> bool {
        self.as_coefficient().is_some_and(RatFunc::is_one)
    }

    /// Whether the expression mentions no variable (it may still call functions of
    /// parameters, as `sqrt(g/l)` does).
    pub fn is_parameter_only(&self) -> bool {
        self.0.lead.is_none()
    }

    /// Whether `atom` occurs in the expression.
    pub fn mentions(&self, atom: Atom) -> bool {
        self.mentions_any(&|a| a == atom)
    }

    /// Whether any variable satisfying `predicate` occurs in the expression.
    pub fn mentions_any(&self, predicate: &dyn Fn(Atom) -> bool) -> bool {
        if self.0.lead.is_none() {
            return false;
        }
        match &self.0.node {
            Node::Coefficient(_) => false,
            Node::Atom(a) => predicate(*a),
            Node::Sum(_, terms) => terms.iter().any(|(t, _)| t.mentions_any(predicate)),
            Node::Product(factors) => factors.iter().any(|(b, _)| b.mentions_any(predicate)),
            Node::Power(b, e) => b.mentions_any(predicate) || e.mentions_any(predicate),
            Node::Call(_, args) => args.iter().any(|a| a.mentions_any(predicate)),
        }
    }

    /// Every variable the expression mentions, in order.
    pub fn atoms(&self) -> BTreeSet<Atom> {
        let mut out = BTreeSet::new();
        self.collect_atoms(&mut out);
        out
    }

    /// Every parameter symbol the expression's coefficients use (`g` and `l` in
    /// `sqrt(g/l)*sin(q_pendulum)`).
    pub fn parameters(&self) -> BTreeSet<crate::Symbol> {
        let mut out = BTreeSet::new();
        self.collect_parameters(&mut out);
        out
    }

    fn collect_parameters(&self, out: &mut BTreeSet<crate::Symbol>) {
        match &self.0.node {
            Node::Coefficient(c) => out.extend(c.symbols()),
            Node::Atom(_) => {}
            Node::Sum(constant, terms) => {
                out.extend(constant.symbols());
                for (term, coefficient) in terms {
                    out.extend(coefficient.symbols());
                    term.collect_parameters(out);
                }
            }
            Node::Product(factors) => factors.iter().for_each(|(b, _)| b.collect_parameters(out)),
            Node::Power(b, e) => {
                b.collect_parameters(out);
                e.collect_parameters(out);
            }
            Node::Call(_, args) => args.iter().for_each(|a| a.collect_parameters(out)),
        }
    }

    fn collect_atoms(&self, out: &mut BTreeSet<Atom>) {
        if self.0.lead.is_none() {
            return;
        }
        match &self.0.node {
            Node::Coefficient(_) => {}
            Node::Atom(a) => {
                out.insert(*a);
            }
            Node::Sum(_, terms) => terms.iter().for_each(|(t, _)| t.collect_atoms(out)),
            Node::Product(factors) => factors.iter().for_each(|(b, _)| b.collect_atoms(out)),
            Node::Power(b, e) => {
                b.collect_atoms(out);
                e.collect_atoms(out);
            }
            Node::Call(_, args) => args.iter().for_each(|a| a.collect_atoms(out)),
        }
    }

    /// `a + b`.
    pub fn add(a: &Sym, b: &Sym) -> Sym {
        Sym::sum([(a.clone(), RatFunc::one()), (b.clone(), RatFunc::one())])
    }

    /// `a - b`.
    pub fn sub(a: &Sym, b: &Sym) -> Sym {
        Sym::sum([
            (a.clone(), RatFunc::one()),
            (b.clone(), RatFunc::integer(-1)),
        ])
    }

    /// `-a`.
    pub fn neg(a: &Sym) -> Sym {
        a.scaled(&RatFunc::integer(-1))
    }

    /// `Σ coefficientᵢ·exprᵢ`, in canonical form.
    pub fn sum(parts: impl IntoIterator<Item = (Sym, RatFunc)>) -> Sym {
        let mut constant = RatFunc::zero();
        let mut terms: Vec<(Sym, RatFunc)> = Vec::new();
        for (expr, factor) in parts {
            if factor.is_zero() {
                continue;
            }
            match &expr.0.node {
                Node::Coefficient(c) => constant += c * &factor,
                Node::Sum(k, inner) => {
                    constant += k * &factor;
                    terms.extend(inner.iter().map(|(t, c)| (t.clone(), c * &factor)));
                }
                _ => terms.push((expr.clone(), factor)),
            }
        }
        terms.sort_by(|a, b| a.0.cmp(&b.0));
        let mut merged: Vec<(Sym, RatFunc)> = Vec::with_capacity(terms.len());
        for (term, c) in terms {
            match merged.last_mut() {
                Some((last, total)) if *last == term => *total += c,
                _ => merged.push((term, c)),
            }
        }
        merged.retain(|(_, c)| !c.is_zero());
        match merged.len() {
            0 => Sym::coefficient(constant),
            1 if constant.is_zero() && merged[0].1.is_one() => merged.pop().expect("one term").0,
            _ => Sym::from_node(Node::Sum(constant, merged)),
        }
    }

    /// `factor·self`, distributed over a sum.
    pub fn scaled(&self, factor: &RatFunc) -> Sym {
        if factor.is_one() {
            return self.clone();
        }
        Sym::sum([(self.clone(), factor.clone())])
    }

    /// The expression as `coefficient · Π factors`, for multiplication.
    fn split_product(&self) -> (RatFunc, Vec<(Sym, Rational)>) {
        match &self.0.node {
            Node::Coefficient(c) => (c.clone(), Vec::new()),
            Node::Sum(k, terms) if k.is_zero() && terms.len() == 1 => {
                let (inner, mut factors) = terms[0].0.split_product();
                debug_assert!(inner.is_one());
                factors.shrink_to_fit();
                (terms[0].1.clone(), factors)
            }
            Node::Product(factors) => (RatFunc::one(), factors.clone()),
            _ => (RatFunc::one(), vec![(self.clone(), Rational::integer(1))]),
        }
    }

    /// `coefficient · Π factors` in canonical form.
    fn from_product(coefficient: RatFunc, mut factors: Vec<(Sym, Rational)>) -> Sym {
        if coefficient.is_zero() {
            return Sym::zero();
        }
        factors.sort_by(|a, b| a.0.cmp(&b.0));
        let mut merged: Vec<(Sym, Rational)> = Vec::with_capacity(factors.len());
        for (base, exponent) in factors {
            match merged.last_mut() {
                Some((last, total)) if *last == base => match total.add(exponent) {
                    Some(sum) => *total = sum,
                    None => merged.push((base, exponent)),
                },
                _ => merged.push((base, exponent)),
            }
        }
        merged.retain(|(_, e)| e.num != 0);
        let mut coefficient = coefficient;
        // A coefficient base left with an integer exponent folds into the coefficient.
        merged.retain(|(base, e)| match base.as_coefficient() {
            Some(c) if e.is_integer() => match c.powi(e.num as i32) {
                Some(power) => {
                    coefficient *= &power;
                    false
                }
                None => true,
            },
            _ => true,
        });
        let core = match merged.len() {
            0 => return Sym::coefficient(coefficient),
            1 if merged[0].1 == Rational::integer(1) => merged.pop().expect("one factor").0,
            _ => Sym::from_node(Node::Product(merged)),
        };
        core.scaled(&coefficient)
    }

    /// `a · b`.
    pub fn mul(a: &Sym, b: &Sym) -> Sym {
        if let Some(c) = a.as_coefficient() {
            return b.scaled(c);
        }
        if let Some(c) = b.as_coefficient() {
            return a.scaled(c);
        }
        let (ca, mut fa) = a.split_product();
        let (cb, fb) = b.split_product();
        fa.extend(fb);
        Sym::from_product(&ca * &cb, fa)
    }

    /// `a / b`; `None` when `b` is exactly zero.
    pub fn div(a: &Sym, b: &Sym) -> Option<Sym> {
        if b.is_zero() {
            return None;
        }
        Some(Sym::mul(a, &b.powi(-1)?))
    }

    /// `self^n`; `None` for zero to a negative power.
    pub fn powi(&self, n: i64) -> Option<Sym> {
        self.pow(Rational::integer(n))
    }

    /// `self^exponent` for an exact rational exponent; `None` for zero to a negative power.
    ///
    /// `(x^a)^b` becomes `x^(a·b)` only where that is true for every real `x` (an integer
    /// `b`); `(x^2)^(1/2)` stays as it is (it is `|x|`, not `x`).
    pub fn pow(&self, exponent: Rational) -> Option<Sym> {
        if exponent.num == 0 {
            return Some(Sym::one());
        }
        if exponent == Rational::integer(1) {
            return Some(self.clone());
        }
        if let Some(c) = self.as_coefficient() {
            if c.is_zero() {
                return (exponent.num > 0).then(Sym::zero);
            }
            if exponent.is_integer() {
                return c
                    .powi(i32::try_from(exponent.num).ok()?)
                    .map(Sym::coefficient);
            }
            if let Some(root) = exact_root(c, exponent) {
                return Some(Sym::coefficient(root));
            }
            return Some(Sym::from_node(Node::Product(vec![(
                self.clone(),
                exponent,
            )])));
        }
        if exponent.is_integer() {
            let (c, factors) = self.split_product();
            let power = c.powi(i32::try_from(exponent.num).ok()?)?;
            let factors = factors
                .into_iter()
                .map(|(b, e)| e.mul(exponent).map(|e| (b, e)))
                .collect::<Option<Vec<_>>>()?;
            return Some(Sym::from_product(power, factors));
        }
        // A fractional power of x^a with an odd a, of a positive-coefficient product, and
        // the like would need sign reasoning; only a single base with an integer exponent
        // that keeps the sign of its base (`(x^3)^(1/3)` is x) is simplified.
        if let Node::Product(factors) = &self.0.node
            && let [(base, e)] = factors.as_slice()
            && e.num % 2 != 0
        {
            let combined = e.mul(exponent)?;
            return Some(Sym::from_product(
                RatFunc::one(),
                vec![(base.clone(), combined)],
            ));
        }
        Some(Sym::from_node(Node::Product(vec![(
            self.clone(),
            exponent,
        )])))
    }

    /// `self^exponent` for any exponent: exact where the exponent is a small rational
    /// constant, a real power otherwise.
    pub fn powf(&self, exponent: &Sym) -> Option<Sym> {
        if let Some(e) = exponent.as_coefficient().and_then(Rational::from_ratfunc) {
            return self.pow(e);
        }
        if self.is_one() {
            return Some(Sym::one());
        }
        Some(Sym::from_node(Node::Power(self.clone(), exponent.clone())))
    }

    /// `function(args)`, folded where the value is exact.
    pub fn call(function: Function, args: Vec<Sym>) -> Sym {
        let zero = || args.first().is_some_and(Sym::is_zero);
        let constant = args.first().and_then(|a| a.as_coefficient().cloned());
        let sign_of = |c: &RatFunc| c.to_constant().map(|(n, _)| n.signum());
        match function {
            Function::Sin | Function::Tan | Function::Tanh | Function::Atan if zero() => {
                return Sym::zero();
            }
            Function::Cos | Function::Exp if zero() => return Sym::one(),
            Function::Ln if args.first().is_some_and(Sym::is_one) => return Sym::zero(),
            Function::Sqrt => {
                return args[0]
                    .pow(Rational { num: 1, den: 2 })
                    .unwrap_or_else(|| Sym::from_node(Node::Call(function, args)));
            }
            Function::Abs => {
                if let Some(s) = constant.as_ref().and_then(sign_of) {
                    let c = constant.expect("checked");
                    return Sym::coefficient(if s.is_negative() { -c } else { c });
                }
                if let Node::Call(Function::Abs | Function::Exp, _) = args[0].node() {
                    return args[0].clone();
                }
                // |−x| is |x|: a sum whose terms are all negative flips.
                if let Some(flipped) = negated_if_negative(&args[0]) {
                    return Sym::call(Function::Abs, vec![flipped]);
                }
            }
            Function::Sign => {
                if let Some(s) = constant.as_ref().and_then(sign_of) {
                    return Sym::integer(s.to_i64().unwrap_or(0));
                }
                if let Some(flipped) = negated_if_negative(&args[0]) {
                    return Sym::neg(&Sym::call(Function::Sign, vec![flipped]));
                }
            }
            Function::Min | Function::Max => {
                let mut args = args;
                args.sort();
                args.dedup();
                if args.len() == 1 {
                    return args.pop().expect("one argument");
                }
                return Sym::from_node(Node::Call(function, args));
            }
            _ => {}
        }
        Sym::from_node(Node::Call(function, args))
    }

    /// Replaces every variable for which `replacement` gives an expression.
    pub fn substitute(&self, replacement: &dyn Fn(Atom) -> Option<Sym>) -> Sym {
        if self.0.lead.is_none() {
            return self.clone();
        }
        match &self.0.node {
            Node::Coefficient(_) => self.clone(),
            Node::Atom(a) => replacement(*a).unwrap_or_else(|| self.clone()),
            Node::Sum(k, terms) => Sym::sum(
                std::iter::once((Sym::coefficient(k.clone()), RatFunc::one())).chain(
                    terms
                        .iter()
                        .map(|(t, c)| (t.substitute(replacement), c.clone())),
                ),
            ),
            Node::Product(factors) => {
                let mut result = Sym::one();
                for (base, exponent) in factors {
                    let base = base.substitute(replacement);
                    let power = base.pow(*exponent).unwrap_or_else(|| {
                        Sym::from_node(Node::Product(vec![(base.clone(), *exponent)]))
                    });
                    result = Sym::mul(&result, &power);
                }
                result
            }
            Node::Power(b, e) => {
                let (b, e) = (b.substitute(replacement), e.substitute(replacement));
                b.powf(&e)
                    .unwrap_or_else(|| Sym::from_node(Node::Power(b.clone(), e.clone())))
            }
            Node::Call(f, args) => {
                Sym::call(*f, args.iter().map(|a| a.substitute(replacement)).collect())
            }
        }
    }

    /// The value in floating point, with `atoms` giving each variable's value and `values`
    /// the parameters' (indexed like a model's `values`).
    pub fn eval(&self, atoms: &dyn Fn(Atom) -> f64, values: &[f64]) -> f64 {
        match &self.0.node {
            Node::Coefficient(c) => c.eval(values),
            Node::Atom(a) => atoms(*a),
            Node::Sum(k, terms) => terms.iter().fold(k.eval(values), |acc, (t, c)| {
                acc + c.eval(values) * t.eval(atoms, values)
            }),
            Node::Product(factors) => factors
                .iter()
                .fold(1.0, |acc, (b, e)| acc * power(b.eval(atoms, values), *e)),
            Node::Power(b, e) => b.eval(atoms, values).powf(e.eval(atoms, values)),
            Node::Call(f, args) => {
                let values: Vec<f64> = args.iter().map(|a| a.eval(atoms, values)).collect();
                f.apply(&values)
            }
        }
    }

    /// The terms of the expression as a sum: `(constant, [(term, coefficient)])`.
    pub fn as_sum(&self) -> (RatFunc, Vec<(Sym, RatFunc)>) {
        match &self.0.node {
            Node::Coefficient(c) => (c.clone(), Vec::new()),
            Node::Sum(k, terms) => (k.clone(), terms.clone()),
            _ => (RatFunc::zero(), vec![(self.clone(), RatFunc::one())]),
        }
    }

    /// `Σ |termᵢ|`: the size of the expression's terms, the scale against which a value
    /// near zero is judged (as linear forms of the model do with their terms).
    pub fn magnitude(&self) -> Sym {
        let (constant, terms) = self.as_sum();
        let parts = std::iter::once(Sym::coefficient(constant))
            .chain(terms.into_iter().map(|(t, c)| t.scaled(&c)))
            .map(|part| (Sym::call(Function::Abs, vec![part]), RatFunc::one()));
        Sym::sum(parts)
    }
}

/// `x^e` in floating point, odd roots of negative numbers real (`(-8)^(1/3)` is -2).
pub fn power(x: f64, e: Rational) -> f64 {
    if e.is_integer()
        && let Ok(n) = i32::try_from(e.num)
    {
        return x.powi(n);
    }
    if x < 0.0 && e.den % 2 != 0 {
        let magnitude = (-x).powf(e.to_f64());
        return if e.num % 2 == 0 {
            magnitude
        } else {
            -magnitude
        };
    }
    // Halves and quarters by square roots, the powers laws use most (an orifice's square
    // root, free convection's 5/4): several times faster than `powf`, and within two ulps of
    // it. Zero, infinities and NaN keep `powf`'s conventions.
    if x.is_finite() && x > 0.0 && (e.den == 2 || e.den == 4) {
        let whole = i32::try_from(e.num.div_euclid(e.den));
        let root = match (e.den, e.num.rem_euclid(e.den)) {
            (2, 1) | (4, 2) => x.sqrt(),
            (4, 1) => x.sqrt().sqrt(),
            (4, 3) => {
                let half = x.sqrt();
                half * half.sqrt()
            }
            _ => 1.0,
        };
        // A whole part of a few multiplications keeps the error at a couple of ulps.
        if let Ok(whole @ -4..=4) = whole {
            return if whole == 0 {
                root
            } else {
                x.powi(whole) * root
            };
        }
    }
    x.powf(e.to_f64())
}

/// `-x` if every term of `x` (and its constant) is negative, so that `|−x|` is `|x|`.
fn negated_if_negative(x: &Sym) -> Option<Sym> {
    let (constant, terms) = x.as_sum();
    let negative = |c: &RatFunc| c.to_constant().is_some_and(|(n, _)| n.is_negative());
    let all = terms.iter().all(|(_, c)| negative(c))
        && (constant.is_zero() || negative(&constant))
        && !terms.is_empty();
    all.then(|| Sym::neg(x))
}

/// The exact `c^e` of a constant rational `c` when it is a perfect power (`4^(1/2)` is 2).
fn exact_root(c: &RatFunc, e: Rational) -> Option<RatFunc> {
    let (num, den) = c.to_constant()?;
    if num.is_negative() && e.den % 2 == 0 {
        return None;
    }
    let root = |n: &BigInt| -> Option<BigInt> {
        let degree = u32::try_from(e.den).ok()?;
        let magnitude = n.abs();
        let r = magnitude.nth_root(degree);
        (r.pow(degree) == magnitude).then(|| if n.is_negative() { -r } else { r })
    };
    let (num_root, den_root) = (root(&num)?, root(&den)?);
    let base = RatFunc::rational(num_root, den_root)?;
    base.powi(i32::try_from(e.num).ok()?)
}

#[cfg(test)]
mod tests;
