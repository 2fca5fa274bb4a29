//! Textbook printing of rational functions, as plain text and as LaTeX.
//!
//! Terms print in canonical (alphabetical) order. A numerator whose terms are all negative
//! has its sign factored out (`-(b + K_p)/M`). In a fraction the integer and monomial
//! contents of numerator and denominator are pulled out for display (`m*(b_1 + b_2)`), and
//! multi-term or product parts are parenthesised as a reader expects (`1/(m_ct + m_ge)`,
//! `k/(m*n)`); LaTeX uses `\frac` and juxtaposition instead.

use std::fmt::Write;

use num_bigint::BigInt;
use num_traits::{One, Signed};

use super::{Monomial, Poly, RatFunc, SymbolTable};

/// Output flavour.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Style {
    Text,
    Latex,
}

impl RatFunc {
    /// Plain-text rendering: `-(b + K_p)/M`, `2*a*b^2`, `1/(m_ct + m_ge)`, `-1/2`.
    pub fn text(&self, table: &SymbolTable) -> String {
        join_sign(self.signed_text(table))
    }

    /// LaTeX rendering: `-\frac{b + K_{p}}{M}`, `2 a b^{2}`, `\frac{1}{m_{ct} + m_{ge}}`.
    pub fn latex(&self, table: &SymbolTable) -> String {
        join_sign(self.signed_latex(table))
    }

    /// Plain text split into a sign and a magnitude, so that callers can print sums as
    /// `a - (b + c)/d*x`: `(true, "(b + K_p)/M")` for `-(b + K_p)/M`, `(true, "k/m")` for
    /// `-k/m`. The sign is `true` only when every numerator term is negative; a mixed-sign
    /// polynomial such as `a - b` is `(false, "a - b")`. `text()` is the magnitude with a
    /// leading `-` when the sign is `true`.
    pub fn signed_text(&self, table: &SymbolTable) -> (bool, String) {
        signed(self, table, Style::Text)
    }

    /// LaTeX split into a sign and a magnitude, like [`RatFunc::signed_text`]:
    /// `(true, "\frac{b + K_{p}}{M}")` for `-\frac{b + K_{p}}{M}`.
    pub fn signed_latex(&self, table: &SymbolTable) -> (bool, String) {
        signed(self, table, Style::Latex)
    }
}

fn join_sign((negative, magnitude): (bool, String)) -> String {
    if negative {
        format!("-{magnitude}")
    } else {
        magnitude
    }
}

fn signed(r: &RatFunc, table: &SymbolTable, style: Style) -> (bool, String) {
    let num = r.numerator();
    let den = r.denominator();
    if num.is_zero() {
        return (false, "0".to_string());
    }
    let negative = num.terms().all(|(_, c)| c.is_negative());
    let magnitude = if negative { -num } else { num.clone() };

    if den.is_one() {
        let text = poly(&magnitude, table, style);
        return if negative && magnitude.term_count() > 1 {
            (true, format!("({text})"))
        } else {
            (negative, text)
        };
    }

    let num_factors = Factors::of(&magnitude);
    let den_factors = Factors::of(den);
    let text = match style {
        Style::Text => {
            let mut n = num_factors.render(table, style);
            if num_factors.is_single_sum() {
                n = format!("({n})");
            }
            let mut d = den_factors.render(table, style);
            if den_factors.count() > 1 || den_factors.is_single_sum() {
                d = format!("({d})");
            }
            format!("{n}/{d}")
        }
        Style::Latex => format!(
            "\\frac{{{}}}{{{}}}",
            num_factors.render(table, style),
            den_factors.render(table, style)
        ),
    };
    (negative, text)
}

/// A polynomial split for display as `content * monomial * rest`.
struct Factors {
    content: BigInt,
    monomial: Monomial,
    rest: Poly,
}

impl Factors {
    fn of(p: &Poly) -> Self {
        let content = p.content();
        let monomial = p.monomial_content();
        let rest = p.div_term(&monomial, &content).unwrap_or_else(|| p.clone());
        Factors {
            content,
            monomial,
            rest,
        }
    }

    /// Number of displayed factors: the content, each symbol power, the rest.
    fn count(&self) -> usize {
        usize::from(!self.content.is_one())
            + self.monomial.iter().count()
            + usize::from(!self.rest.is_one())
    }

    /// Whether the display is one parenthesis-free multi-term sum.
    fn is_single_sum(&self) -> bool {
        self.count() == 1 && self.rest.term_count() > 1
    }

    fn render(&self, table: &SymbolTable, style: Style) -> String {
        let mut parts: Vec<String> = Vec::new();
        if !self.content.is_one() {
            parts.push(integer(&self.content, style));
        }
        parts.extend(
            self.monomial
                .iter()
                .map(|(s, e)| power(table.name(s), e, style)),
        );
        if !self.rest.is_one() {
            // The rest is 1 for a single term (its content and monomial were taken out), so
            // here it has several terms.
            let sum = poly(&self.rest, table, style);
            if parts.is_empty() {
                parts.push(sum);
            } else {
                parts.push(format!("({sum})"));
            }
        }
        if parts.is_empty() {
            return "1".to_string();
        }
        parts.join(separator(style))
    }
}

fn separator(style: Style) -> &'static str {
    match style {
        Style::Text => "*",
        Style::Latex => " ",
    }
}

/// A polynomial as a sum of terms in canonical order: `-a + 2*b - 3`.
fn poly(p: &Poly, table: &SymbolTable, style: Style) -> String {
    let mut out = String::new();
    for (i, (m, c)) in p.terms().enumerate() {
        match (i, c.is_negative()) {
            (0, true) => out.push('-'),
            (0, false) => {}
            (_, true) => out.push_str(" - "),
            (_, false) => out.push_str(" + "),
        }
        out.push_str(&term(&c.abs(), m, table, style));
    }
    if out.is_empty() {
        out.push('0');
    }
    out
}

/// A term with a positive coefficient: `3`, `a*b^2`, `2*a`.
fn term(c: &BigInt, m: &Monomial, table: &SymbolTable, style: Style) -> String {
    let mut parts: Vec<String> = Vec::new();
    if !c.is_one() || m.is_one() {
        parts.push(integer(c, style));
    }
    parts.extend(m.iter().map(|(s, e)| power(table.name(s), e, style)));
    parts.join(separator(style))
}

/// Integers with more digits than this print in scientific notation where that is shorter.
const PLAIN_DIGITS: usize = 15;

/// An integer exactly, in scientific notation when it is long and that is shorter: a
/// coefficient `3e206` (an operating point of 1e103 squared) rather than 207 digits,
/// `2.5e-20` as `1/4e19` (the fraction's denominator); `\cdot 10^{206}` in LaTeX.
fn integer(n: &BigInt, style: Style) -> String {
    let digits = n.magnitude().to_string();
    let significant = digits.trim_end_matches('0');
    let exponent = digits.len() - 1;
    if digits.len() <= PLAIN_DIGITS || significant.len() + 6 >= digits.len() {
        return n.to_string();
    }
    let sign = if n.is_negative() { "-" } else { "" };
    let mantissa = match significant.len() {
        1 => significant.to_string(),
        _ => format!("{}.{}", &significant[..1], &significant[1..]),
    };
    match style {
        Style::Text => format!("{sign}{mantissa}e{exponent}"),
        Style::Latex => format!("{sign}{mantissa} \\cdot 10^{{{exponent}}}"),
    }
}

/// `name^e` (`a^2`, `b_{1}^{2}`), just the name for `e = 1`.
fn power(name: &str, e: u32, style: Style) -> String {
    match style {
        Style::Text if e == 1 => name.to_string(),
        Style::Text => format!("{name}^{e}"),
        Style::Latex if e == 1 => latex_name(name),
        Style::Latex => format!("{}^{{{e}}}", latex_name(name)),
    }
}

const GREEK: [&str; 33] = [
    "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa",
    "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi",
    "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Phi", "Psi", "Omega",
];

/// A symbol name in LaTeX: `m_ct` is `m_{\mathrm{ct}}`, `F_S_ge` is `F_{\mathrm{S\_ge}}`,
/// `R_a` is `R_{a}`, `Delta_v` is `\Delta_{v}`, `dv` is `\mathrm{dv}`, `m1` is `m_{1}`.
///
/// One rule for parameters, inputs and states (whose names are a letter, `_` and an
/// element's name: `q_tyre` is `q_{\mathrm{tyre}}`), so that one document writes one name
/// one way. The name is split at its first `_`: the base before it is a single character
/// plain (italic in mathematics), a Greek letter's name its command, anything else upright;
/// the rest is one subscript, written by [`latex_subscript`]. A name without `_` that is a
/// letter and digits is the letter numbered (`m1` is `m_{1}`). A name with an empty part
/// (`_x`, `a__b`, `a_`) prints upright as a whole, with its underscores escaped. A
/// sub-model's symbol prints its prefix upright before the part's own name: `front.k_s` is
/// `\mathrm{front}.k_{s}`.
pub fn latex_name(name: &str) -> String {
    // A sub-model's symbol (`front.k_s`): its prefix upright, then the part's own name.
    if let Some((prefix, leaf)) = name.rsplit_once('.') {
        return format!(
            "\\mathrm{{{}}}.{}",
            prefix.replace('_', "\\_"),
            latex_name(leaf)
        );
    }
    if name.split('_').any(str::is_empty) {
        return format!("\\mathrm{{{}}}", name.replace('_', "\\_"));
    }
    let (base, subscript) = match name.split_once('_') {
        Some((base, rest)) => (base, Some(rest)),
        None => (name, None),
    };
    // A letter followed by digits is a numbered symbol: `m1` is `m_{1}`.
    let digits = base.trim_start_matches(|c: char| c.is_ascii_alphabetic());
    let letters = &base[..base.len() - digits.len()];
    if subscript.is_none()
        && letters.chars().count() == 1
        && !digits.is_empty()
        && digits.chars().all(|c| c.is_ascii_digit())
    {
        return format!("{letters}_{{{digits}}}");
    }
    let mut out = if base.chars().count() == 1 {
        base.to_string()
    } else if GREEK.contains(&base) {
        format!("\\{base}")
    } else {
        format!("\\mathrm{{{base}}}")
    };
    if let Some(subscript) = subscript {
        let _ = write!(out, "_{{{}}}", latex_subscript(subscript));
    }
    out
}

/// A subscript in LaTeX, the same for a parameter's and a state's: a single character or a
/// number as is (`a`, `12`), a Greek letter's name its command (`\mu`), anything else
/// upright with its underscores escaped, as a word or a label is set (`\mathrm{ct}`,
/// `\mathrm{load\_inertia}`), never a subscript of a subscript.
pub fn latex_subscript(text: &str) -> String {
    if text.chars().count() == 1 || (!text.is_empty() && text.chars().all(|c| c.is_ascii_digit())) {
        text.to_string()
    } else if GREEK.contains(&text) {
        format!("\\{text}")
    } else {
        format!("\\mathrm{{{}}}", text.replace('_', "\\_"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table and a constructor for its symbols by name.
    struct Names(SymbolTable);

    impl Names {
        fn new(names: &[&str]) -> Self {
            Names(SymbolTable::new(names.iter().copied()))
        }
        fn s(&self, name: &str) -> RatFunc {
            RatFunc::symbol(self.0.get(name).unwrap())
        }
        fn text(&self, r: &RatFunc) -> String {
            r.text(&self.0)
        }
        fn latex(&self, r: &RatFunc) -> String {
            r.latex(&self.0)
        }
    }

    fn n(k: i64) -> RatFunc {
        RatFunc::integer(k)
    }

    fn div(a: &RatFunc, b: &RatFunc) -> RatFunc {
        a.checked_div(b).unwrap()
    }

    #[test]
    fn symbols_coefficients_and_powers() {
        let t = Names::new(&["a", "b"]);
        let (a, b) = (t.s("a"), t.s("b"));
        assert_eq!(t.text(&a), "a");
        assert_eq!(t.text(&-&a), "-a");
        assert_eq!(t.text(&(n(2) * &a * &b * &b)), "2*a*b^2");
        assert_eq!(t.latex(&(n(2) * &a * &b * &b)), "2 a b^{2}");
        assert_eq!(t.latex(&(n(2) * &a)), "2 a");
        assert_eq!(t.text(&(&a * &a + &a * &b + &b * &b)), "a^2 + a*b + b^2");
        assert_eq!(t.text(&(&a + n(1))), "a + 1");
        assert_eq!(t.text(&(n(1) + &a)), "a + 1");
        assert_eq!(t.latex(&(&a * &a - n(3))), "a^{2} - 3");
    }

    #[test]
    fn alphabetical_order_and_sign() {
        let t = Names::new(&["M", "K_p", "b", "m_ge", "m_ct"]);
        let (m, kp, b) = (t.s("M"), t.s("K_p"), t.s("b"));
        assert_eq!(t.text(&(&kp + &b)), "b + K_p");
        assert_eq!(t.text(&(t.s("m_ge") + t.s("m_ct"))), "m_ct + m_ge");
        // -a + b stays in canonical order; a - b likewise.
        assert_eq!(t.text(&(&kp - &b)), "-b + K_p");
        assert_eq!(t.text(&(&b - &kp)), "b - K_p");
        // All terms negative: the sign is factored out.
        assert_eq!(t.text(&(-&b - &kp)), "-(b + K_p)");
        let r = div(&(-&b - &kp), &m);
        assert_eq!(t.text(&r), "-(b + K_p)/M");
        assert_eq!(t.latex(&r), "-\\frac{b + K_{p}}{M}");
        // Within a product, factors are in the same (alphabetical) order as in sums.
        assert_eq!(t.latex(&(t.s("m_ge") * &kp)), "K_{p} m_{\\mathrm{ge}}");
    }

    #[test]
    fn fractions() {
        let t = Names::new(&["b", "K_p", "M", "m_ct", "m_ge", "k", "m", "n", "b_1", "b_2"]);
        let (b, kp, m_big) = (t.s("b"), t.s("K_p"), t.s("M"));
        let (k, m, nn) = (t.s("k"), t.s("m"), t.s("n"));
        let (b1, b2) = (t.s("b_1"), t.s("b_2"));
        assert_eq!(t.text(&div(&(&b + &kp), &m_big)), "(b + K_p)/M");
        let r = div(&n(1), &(t.s("m_ct") + t.s("m_ge")));
        assert_eq!(t.text(&r), "1/(m_ct + m_ge)");
        assert_eq!(
            t.latex(&r),
            "\\frac{1}{m_{\\mathrm{ct}} + m_{\\mathrm{ge}}}"
        );
        let r = div(&k, &(&m * &nn));
        assert_eq!(t.text(&r), "k/(m*n)");
        assert_eq!(t.latex(&r), "\\frac{k}{m n}");
        assert_eq!(t.text(&div(&b, &n(2))), "b/2");
        assert_eq!(t.latex(&div(&b, &n(2))), "\\frac{b}{2}");
        let r = div(&-&k, &m);
        assert_eq!(t.text(&r), "-k/m");
        assert_eq!(t.latex(&r), "-\\frac{k}{m}");
        assert_eq!(t.text(&div(&n(1), &m)), "1/m");
        // -b_1 b_2 / (b_1 m + b_2 m): the denominator's common factor m is pulled out.
        let r = div(&-(&b1 * &b2), &(&b1 * &m + &b2 * &m));
        assert_eq!(t.text(&r), "-b_1*b_2/(m*(b_1 + b_2))");
        assert_eq!(t.latex(&r), "-\\frac{b_{1} b_{2}}{m (b_{1} + b_{2})}");
        let r = div(&(&b * &b), &(&m * &m * &m));
        assert_eq!(t.text(&r), "b^2/m^3");
        assert_eq!(t.latex(&r), "\\frac{b^{2}}{m^{3}}");
        // (2a + 2b)/c: the numerator's integer content is pulled out.
        let r = div(&(n(2) * &b + n(2) * &kp), &m);
        assert_eq!(t.text(&r), "2*(b + K_p)/m");
        assert_eq!(t.latex(&r), "\\frac{2 (b + K_{p})}{m}");
        // a/(2b)
        let r = div(&k, &(n(2) * &m));
        assert_eq!(t.text(&r), "k/(2*m)");
        assert_eq!(t.latex(&r), "\\frac{k}{2 m}");
        // Mixed-sign numerators keep their order inside the parentheses.
        let r = div(&(&b - &kp), &m);
        assert_eq!(t.text(&r), "(b - K_p)/m");
        let r = div(&(&kp - &b), &m);
        assert_eq!(t.text(&r), "(-b + K_p)/m");
    }

    #[test]
    fn single_letter_examples() {
        let t = Names::new(&["a", "b", "c"]);
        let (a, b, c) = (t.s("a"), t.s("b"), t.s("c"));
        assert_eq!(t.text(&(-&a - &b)), "-(a + b)");
        assert_eq!(t.latex(&(-&a - &b)), "-(a + b)");
        let r = div(&(n(2) * &a + n(2) * &b), &c);
        assert_eq!(t.text(&r), "2*(a + b)/c");
        assert_eq!(t.latex(&r), "\\frac{2 (a + b)}{c}");
        let r = div(&(&a * &a), &(&b * &b * &b));
        assert_eq!(t.text(&r), "a^2/b^3");
        assert_eq!(t.latex(&r), "\\frac{a^{2}}{b^{3}}");
        // A numerator with a common monomial factor: (a^2 b + a b^2)/c = a*b*(a + b)/c.
        let r = div(&(&a * &a * &b + &a * &b * &b), &c);
        assert_eq!(t.text(&r), "a*b*(a + b)/c");
        assert_eq!(t.latex(&r), "\\frac{a b (a + b)}{c}");
        // Integer and monomial content together in a denominator.
        let r = div(&n(1), &(n(6) * &a * &b + n(4) * &a * &c));
        assert_eq!(t.text(&r), "1/(2*a*(3*b + 2*c))");
        assert_eq!(t.latex(&r), "\\frac{1}{2 a (3 b + 2 c)}");
    }

    #[test]
    fn numbers() {
        let t = Names::new(&[]);
        assert_eq!(t.text(&n(3)), "3");
        assert_eq!(t.text(&n(-3)), "-3");
        assert_eq!(t.text(&n(0)), "0");
        let half = RatFunc::rational(BigInt::from(-1), BigInt::from(2)).unwrap();
        assert_eq!(t.text(&half), "-1/2");
        assert_eq!(t.latex(&half), "-\\frac{1}{2}");
        let r = RatFunc::rational(BigInt::from(3), BigInt::from(2)).unwrap();
        assert_eq!(t.text(&r), "3/2");
        assert_eq!(t.latex(&r), "\\frac{3}{2}");
        assert_eq!(t.latex(&n(0)), "0");
    }

    #[test]
    fn long_round_integers_print_in_scientific_notation() {
        let t = Names::new(&["k"]);
        let k = t.s("k");
        let big = |text: &str| RatFunc::from_decimal(text).unwrap();
        // 3e206 exactly, times a symbol and alone; its inverse is 1/3e206.
        assert_eq!(t.text(&(big("3e206") * &k)), "3e206*k");
        assert_eq!(t.text(&big("3e206")), "3e206");
        assert_eq!(t.text(&-big("1.5e207")), "-1.5e207");
        assert_eq!(t.text(&big("2.5e-20")), "1/4e19");
        assert_eq!(t.latex(&(big("3e206") * &k)), "3 \\cdot 10^{206} k");
        // Up to 15 digits, and wherever it is not shorter, an integer prints as it is.
        assert_eq!(t.text(&big("1e14")), "100000000000000");
        assert_eq!(t.text(&big("123456789012345678")), "123456789012345678");
        assert_eq!(t.text(&(big("1e20") + n(1))), "100000000000000000001");
        // The sum of a huge and an ordinary term keeps both.
        assert_eq!(t.text(&(big("3e206") * &k + n(1))), "3e206*k + 1");
    }

    #[test]
    fn signed_forms() {
        let t = Names::new(&["b", "K_p", "M", "k", "m", "a"]);
        let (a, b, kp, m_big, k, m) =
            (t.s("a"), t.s("b"), t.s("K_p"), t.s("M"), t.s("k"), t.s("m"));
        let r = div(&(-&b - &kp), &m_big);
        assert_eq!(r.signed_text(&t.0), (true, "(b + K_p)/M".to_string()));
        assert_eq!(
            r.signed_latex(&t.0),
            (true, "\\frac{b + K_{p}}{M}".to_string())
        );
        let r = div(&-&k, &m);
        assert_eq!(r.signed_text(&t.0), (true, "k/m".to_string()));
        assert_eq!((&a - &b).signed_text(&t.0), (false, "a - b".to_string()));
        assert_eq!((&b - &a).signed_text(&t.0), (false, "-a + b".to_string()));
        assert_eq!((-&a - &b).signed_text(&t.0), (true, "(a + b)".to_string()));
        assert_eq!((-&a - &b).latex(&t.0), "-(a + b)");
        assert_eq!((n(-2) * &a).signed_text(&t.0), (true, "2*a".to_string()));
        assert_eq!(n(-4).signed_latex(&t.0), (true, "4".to_string()));
        assert_eq!(n(4).signed_text(&t.0), (false, "4".to_string()));
    }

    #[test]
    fn latex_names() {
        // Multi-letter subscripts upright, single letters and numbers as they are, the name
        // split at its first underscore only.
        assert_eq!(latex_name("m_ct"), "m_{\\mathrm{ct}}");
        assert_eq!(latex_name("K_p"), "K_{p}");
        assert_eq!(latex_name("F_S_ge"), "F_{\\mathrm{S\\_ge}}");
        assert_eq!(latex_name("v_ct_des"), "v_{\\mathrm{ct\\_des}}");
        assert_eq!(latex_name("q_tyre"), "q_{\\mathrm{tyre}}");
        assert_eq!(latex_name("p_load_inertia"), "p_{\\mathrm{load\\_inertia}}");
        assert_eq!(latex_name("k_12"), "k_{12}");
        assert_eq!(latex_name("Delta_v"), "\\Delta_{v}");
        assert_eq!(latex_name("mu"), "\\mu");
        assert_eq!(latex_name("omega"), "\\omega");
        assert_eq!(latex_name("Omega"), "\\Omega");
        assert_eq!(latex_name("alpha_mu"), "\\alpha_{\\mu}");
        assert_eq!(latex_name("dv"), "\\mathrm{dv}");
        assert_eq!(latex_name("Beta"), "\\mathrm{Beta}");
        assert_eq!(latex_name("x"), "x");
        assert_eq!(latex_name("x1_b"), "\\mathrm{x1}_{b}");
        assert_eq!(latex_name("m1"), "m_{1}");
        assert_eq!(latex_name("b12"), "b_{12}");
        assert_eq!(latex_name("ab1"), "\\mathrm{ab1}");
        assert_eq!(latex_name("_x"), "\\mathrm{\\_x}");
        assert_eq!(latex_name("a__b"), "\\mathrm{a\\_\\_b}");
        // A sub-model's symbols: the prefix upright, the part's own name as it would be.
        assert_eq!(latex_name("front.k_s"), "\\mathrm{front}.k_{s}");
        assert_eq!(
            latex_name("front.rear_axle.p_wheel"),
            "\\mathrm{front.rear\\_axle}.p_{\\mathrm{wheel}}"
        );
        assert_eq!(latex_name(""), "\\mathrm{}");
    }

    #[test]
    fn latex_powers_of_named_symbols() {
        let t = Names::new(&["mu", "m_ct", "dv"]);
        let r = t.s("mu") * t.s("mu") * t.s("m_ct") * n(3);
        assert_eq!(t.latex(&r), "3 m_{\\mathrm{ct}} \\mu^{2}");
        assert_eq!(t.text(&r), "3*m_ct*mu^2");
        assert_eq!(t.latex(&(t.s("dv") * t.s("dv"))), "\\mathrm{dv}^{2}");
    }
}
