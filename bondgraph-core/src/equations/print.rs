//! State equations as a reader wants them: plain text, LaTeX, and a JSON document.
//!
//! Text lists one equation per state (`dp_mass/dt = -b/m*p_mass - k*q_spring + F`) and then
//! the matrices; LaTeX writes the matrix form the way papers do, one input column at a time;
//! JSON carries the fields other programs rely on (`states`, `inputs`, `A`, `B`, `c` and
//! their numeric `_value` twins, `E` where the inputs' rates enter, `C`, `D`, `F`, `d` for
//! outputs).

use serde::Serialize;

use crate::equations::{OutputEquation, Quantity, StateEquations, Variables};
use crate::linear::{LinearForm, Var};
use crate::symbolic::{RatFunc, latex_name, latex_subscript};

/// The JSON document of `bondgraph equations`.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct EquationsJson {
    /// The model's name.
    pub model: String,
    /// The mode, as a specification (`fr=stuck,...`); empty for a model without switching.
    pub mode: String,
    /// `energy` or `coenergy`.
    pub variables: Variables,
    /// The states.
    pub states: Vec<StateJson>,
    /// The inputs' names.
    pub inputs: Vec<String>,
    /// How `A`, `B` and `E` are written: `dense` or `sparse`.
    pub matrices: Layout,
    /// `A`, symbolic, row by row.
    pub A: Matrix<String>,
    /// `B`, symbolic.
    pub B: Matrix<String>,
    /// `c`, symbolic.
    pub c: Vec<String>,
    /// `A` with the parameter values substituted.
    pub A_value: Matrix<f64>,
    /// `B` with the parameter values substituted.
    pub B_value: Matrix<f64>,
    /// `c` with the parameter values substituted.
    pub c_value: Vec<f64>,
    /// `E`, symbolic (states × inputs): the coefficients of the inputs' rates, present only
    /// where they enter (`dx/dt = A x + B u + E du/dt + c`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub E: Option<Matrix<String>>,
    /// `E` with the parameter values substituted, where `E` is present.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub E_value: Option<Matrix<f64>>,
    /// Output equations requested.
    pub outputs: Vec<OutputJson>,
    /// What the derivation merged, held and solved.
    pub notes: Vec<String>,
}

/// How the JSON document writes the matrices `A`, `B` and `E`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// Rows of entries, zeros included: what small models are read as.
    Dense,
    /// The non-zero entries only ([`Triplets`]): memory linear in the non-zeros, for large
    /// models, whose dense matrices grow with the square of their states.
    Sparse,
}

impl Layout {
    /// The most states whose matrices [`Layout::for_states`] writes dense: 500 states make
    /// a dense `A` of 250,000 entries, a few megabytes of JSON.
    pub const DENSE_UP_TO: usize = 500;

    /// Dense up to [`Layout::DENSE_UP_TO`] states, sparse above.
    pub fn for_states(states: usize) -> Self {
        if states <= Self::DENSE_UP_TO {
            Self::Dense
        } else {
            Self::Sparse
        }
    }
}

/// A matrix of the JSON document, as its [`Layout`] says.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Matrix<T> {
    /// Rows of entries.
    Dense(Vec<Vec<T>>),
    /// The non-zero entries.
    Sparse(Triplets<T>),
}

impl<T> Matrix<T> {
    /// The rows, if the matrix is dense.
    pub fn rows(&self) -> Option<&[Vec<T>]> {
        match self {
            Self::Dense(rows) => Some(rows),
            Self::Sparse(_) => None,
        }
    }
}

/// A sparse matrix as its non-zero entries, named as scipy's coordinate format names them
/// (`scipy.sparse.coo_array((data, (row, col)), shape)`): entry `k` is `data[k]` at row
/// `row[k]`, column `col[k]`; rows ascending, and columns ascending within a row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Triplets<T> {
    /// Rows and columns.
    pub shape: [usize; 2],
    /// Each entry's row.
    pub row: Vec<usize>,
    /// Each entry's column.
    pub col: Vec<usize>,
    /// The entries.
    pub data: Vec<T>,
}

/// One state in the JSON document.
#[derive(Clone, Debug, Serialize)]
pub struct StateJson {
    /// The state's name.
    pub name: String,
    /// Its storage element.
    pub element: String,
    /// `p`, `q`, `v` or `f`.
    pub quantity: Quantity,
    /// Elements merged into it.
    pub merged: Vec<String>,
    /// Its (merged) inertance or compliance.
    pub storage: String,
}

/// One output equation `y = C x + D u + d` in the JSON document.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct OutputJson {
    /// The output's name.
    pub name: String,
    /// The row of `C`.
    pub C: Vec<String>,
    /// The row of `D`.
    pub D: Vec<String>,
    /// The row of `F`: the coefficients of the inputs' rates (`y = C x + D u + F du/dt + d`),
    /// present only where they enter (storage driven directly by an input).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub F: Option<Vec<String>>,
    /// The constant `d`.
    pub d: String,
    /// `C` evaluated.
    pub C_value: Vec<f64>,
    /// `D` evaluated.
    pub D_value: Vec<f64>,
    /// `F` evaluated, where `F` is present.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub F_value: Option<Vec<f64>>,
    /// `d` evaluated.
    pub d_value: f64,
    /// Whether the output is the time integral of `y` (then `C`, `D`, `d` are its rate's).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub integral: bool,
}

impl StateEquations {
    /// The name of a variable in text: a state, an input, or an input's rate `der(u)`.
    pub fn var_name(&self, var: Var) -> String {
        match var {
            Var::State(i) => self.states[i as usize].name.clone(),
            Var::Input(i) => self.inputs[i as usize].clone(),
            Var::InputRate(i) => format!("der({})", self.inputs[i as usize]),
            other => other.to_string(),
        }
    }

    /// An affine form as text: `-b/m*p_mass - k*q_spring + F`.
    pub fn form_text(&self, form: &LinearForm) -> String {
        let mut out = String::new();
        for (var, coefficient) in form.terms() {
            let (negative, magnitude) = coefficient.signed_text(&self.symbols);
            let term = match var {
                Var::Constant => magnitude,
                _ => product_text(&magnitude, &self.var_name(*var)),
            };
            match (out.is_empty(), negative) {
                (true, false) => out.push_str(&term),
                (true, true) => {
                    out.push('-');
                    out.push_str(&term);
                }
                (false, false) => {
                    out.push_str(" + ");
                    out.push_str(&term);
                }
                (false, true) => {
                    out.push_str(" - ");
                    out.push_str(&term);
                }
            }
        }
        if out.is_empty() {
            out.push('0');
        }
        out
    }

    /// The equations and matrices as plain text.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let variables = match self.variables {
            Variables::Energy => "energy variables",
            Variables::CoEnergy => "co-energy variables",
        };
        out.push_str(&format!(
            "model '{}': {} state{} in {variables}, {} input{}\n",
            self.model,
            self.states.len(),
            plural(self.states.len()),
            self.inputs.len(),
            plural(self.inputs.len())
        ));
        if !self.states.is_empty() {
            out.push_str("\nstates:\n");
            let width = self.states.iter().map(|s| s.name.len()).max().unwrap_or(0);
            for state in &self.states {
                let merged = if state.merged.is_empty() {
                    String::new()
                } else {
                    format!(
                        ", with {} merged (storage {})",
                        quoted(&state.merged),
                        state.storage.text(&self.symbols)
                    )
                };
                out.push_str(&format!(
                    "  {:width$}  {} of '{}'{merged}\n",
                    state.name,
                    state
                        .quantity
                        .description_in(state.domain, self.linear_graph),
                    state.element
                ));
            }
        }
        if !self.inputs.is_empty() {
            out.push_str(&format!("inputs: {}\n", self.inputs.join(", ")));
        }
        out.push('\n');
        let lhs: Vec<String> = self
            .states
            .iter()
            .map(|s| format!("d{}/dt", s.name))
            .collect();
        let width = lhs.iter().map(String::len).max().unwrap_or(0);
        for (name, row) in lhs.iter().zip(&self.derivatives) {
            out.push_str(&format!("{name:width$} = {}\n", self.form_text(row)));
        }
        if self.states.is_empty() {
            out.push_str("(no states in this mode)\n");
        } else if self.states.len() <= MAX_DENSE_TEXT {
            out.push('\n');
            out.push_str(&matrix_text("A", &self.text_entries(&self.a())));
            if !self.inputs.is_empty() {
                out.push_str(&matrix_text("B", &self.text_entries(&self.b())));
            }
            if self.has_input_rates() {
                out.push_str(&matrix_text("E", &self.text_entries(&self.e())));
            }
            let c = self.c();
            if c.iter().all(RatFunc::is_zero) {
                out.push_str("c = 0\n");
            } else {
                let c: Vec<Vec<RatFunc>> = c.into_iter().map(|e| vec![e]).collect();
                out.push_str(&matrix_text("c", &self.text_entries(&c)));
            }
        } else {
            out.push_str(&format!(
                "\n(matrices of {} states not printed as text; use --format json)\n",
                self.states.len()
            ));
        }
        if !self.notes.is_empty() {
            out.push_str("\nnotes:\n");
            for note in &self.notes {
                let text = note.text(&self.symbols);
                let text = match text.strip_prefix("derivative causality: ") {
                    Some(rest) if self.linear_graph => format!("dependent storage: {rest}"),
                    _ => text,
                };
                out.push_str(&format!("  - {text}\n"));
            }
        }
        out
    }

    fn text_entries(&self, matrix: &[Vec<RatFunc>]) -> Vec<Vec<String>> {
        matrix
            .iter()
            .map(|row| row.iter().map(|e| e.text(&self.symbols)).collect())
            .collect()
    }

    /// The matrix form `d/dt x = A x + B u + c` in LaTeX, one input column at a time.
    pub fn to_latex(&self) -> String {
        let states: Vec<String> = self.states.iter().map(state_latex).collect();
        let mut out = String::from("\\begin{equation}\n");
        if self.states.is_empty() {
            out.push_str("\\text{no states in this mode}\n\\end{equation}\n");
            return out;
        }
        let column = |entries: &[String]| {
            format!(
                "\\begin{{bmatrix}} {} \\end{{bmatrix}}",
                entries.join(" \\\\ ")
            )
        };
        out.push_str(&format!("\\frac{{d}}{{dt}} {} =\n", column(&states)));
        let a = self.a();
        let rows: Vec<String> = a
            .iter()
            .map(|row| {
                row.iter()
                    .map(|e| e.latex(&self.symbols))
                    .collect::<Vec<_>>()
                    .join(" & ")
            })
            .collect();
        out.push_str(&format!(
            "\\begin{{bmatrix}} {} \\end{{bmatrix}} {}\n",
            rows.join(" \\\\ "),
            column(&states)
        ));
        let b = self.b();
        for (j, input) in self.inputs.iter().enumerate() {
            let entries: Vec<&RatFunc> = b.iter().map(|row| &row[j]).collect();
            if let Some(text) = signed_column(&entries, &self.symbols) {
                out.push_str(&format!("{text} {}\n", latex_name(input)));
            }
        }
        let e = self.e();
        for (j, input) in self.inputs.iter().enumerate() {
            let entries: Vec<&RatFunc> = e.iter().map(|row| &row[j]).collect();
            if let Some(text) = signed_column(&entries, &self.symbols) {
                out.push_str(&format!("{text} \\frac{{d{}}}{{dt}}\n", latex_name(input)));
            }
        }
        let c = self.c();
        if let Some(text) = signed_column(&c.iter().collect::<Vec<_>>(), &self.symbols) {
            out.push_str(&text);
            out.push('\n');
        }
        out.push_str("\\end{equation}\n");
        out
    }

    /// The matrix form and output equations `y = C x + D u + F du/dt + d` in LaTeX, one
    /// equation per output after the state equations.
    pub fn to_latex_with_outputs(&self, outputs: &[OutputEquation]) -> String {
        let mut out = self.to_latex();
        for output in outputs {
            out.push_str("\\begin{equation}\n");
            out.push_str(&format!(
                "{} = {}\n",
                latex_output_name(&output.name),
                self.form_latex(&output.row)
            ));
            out.push_str("\\end{equation}\n");
        }
        out
    }

    /// An affine form in LaTeX: `\frac{b}{m} p_{mass} + F`.
    pub fn form_latex(&self, form: &LinearForm) -> String {
        let mut out = String::new();
        for (var, coefficient) in form.terms() {
            let (negative, magnitude) = coefficient.signed_latex(&self.symbols);
            let name = match var {
                Var::State(i) => state_latex(&self.states[*i as usize]),
                Var::Input(i) => latex_name(&self.inputs[*i as usize]),
                Var::InputRate(i) => {
                    format!("\\frac{{d{}}}{{dt}}", latex_name(&self.inputs[*i as usize]))
                }
                _ => String::new(),
            };
            let term = match (name.is_empty(), magnitude.as_str()) {
                (true, _) => magnitude,
                (false, "1") => name,
                (false, m) if m.contains(['+', '-']) => format!("\\left({m}\\right) {name}"),
                (false, m) => format!("{m} {name}"),
            };
            let sign = match (out.is_empty(), negative) {
                (true, false) => "",
                (true, true) => "-",
                (false, false) => " + ",
                (false, true) => " - ",
            };
            out.push_str(sign);
            out.push_str(&term);
        }
        if out.is_empty() {
            out.push('0');
        }
        out
    }

    /// The JSON document; `mode` is the mode's specification (empty for plain models). Its
    /// matrices are dense up to [`Layout::DENSE_UP_TO`] states and sparse above
    /// ([`StateEquations::to_json_as`] chooses).
    pub fn to_json(&self, mode: &str, outputs: &[OutputEquation]) -> EquationsJson {
        self.to_json_as(mode, outputs, Layout::for_states(self.states.len()))
    }

    /// The JSON document with its matrices written as `layout` says.
    pub fn to_json_as(
        &self,
        mode: &str,
        outputs: &[OutputEquation],
        layout: Layout,
    ) -> EquationsJson {
        let n = self.states.len();
        let columns =
            |m: usize, column: &dyn Fn(Var) -> Option<usize>| -> (Matrix<String>, Matrix<f64>) {
                match layout {
                    Layout::Dense => {
                        let dense: Vec<Vec<RatFunc>> = (0..n)
                            .map(|i| {
                                let mut row = vec![RatFunc::zero(); m];
                                for (var, entry) in self.derivatives[i].terms() {
                                    if let Some(j) = column(*var) {
                                        row[j] = entry.clone();
                                    }
                                }
                                row
                            })
                            .collect();
                        let values = dense
                            .iter()
                            .map(|row| row.iter().map(|e| self.evaluate(e)).collect())
                            .collect();
                        (
                            Matrix::Dense(self.text_entries(&dense)),
                            Matrix::Dense(values),
                        )
                    }
                    Layout::Sparse => {
                        let entries = self.nonzeros(column);
                        let row: Vec<usize> = entries.iter().map(|e| e.0).collect();
                        let col: Vec<usize> = entries.iter().map(|e| e.1).collect();
                        let texts = Triplets {
                            shape: [n, m],
                            row: row.clone(),
                            col: col.clone(),
                            data: entries.iter().map(|e| e.2.text(&self.symbols)).collect(),
                        };
                        let values = Triplets {
                            shape: [n, m],
                            row,
                            col,
                            data: entries.iter().map(|e| self.evaluate(e.2)).collect(),
                        };
                        (Matrix::Sparse(texts), Matrix::Sparse(values))
                    }
                }
            };
        let index = |i: &u32| Some(*i as usize);
        let (a, a_value) = columns(n, &|v| match &v {
            Var::State(i) => index(i),
            _ => None,
        });
        let inputs = self.inputs.len();
        let (b, b_value) = columns(inputs, &|v| match &v {
            Var::Input(i) => index(i),
            _ => None,
        });
        let e = self.has_input_rates().then(|| {
            columns(inputs, &|v| match &v {
                Var::InputRate(i) => index(i),
                _ => None,
            })
        });
        let (e, e_value) = e.map_or((None, None), |(e, v)| (Some(e), Some(v)));
        let c = self.c();
        EquationsJson {
            model: self.model.clone(),
            mode: mode.to_string(),
            variables: self.variables,
            states: self
                .states
                .iter()
                .map(|s| StateJson {
                    name: s.name.clone(),
                    element: s.element.clone(),
                    quantity: s.quantity,
                    merged: s.merged.clone(),
                    storage: s.storage.text(&self.symbols),
                })
                .collect(),
            inputs: self.inputs.clone(),
            matrices: layout,
            A: a,
            B: b,
            c: c.iter().map(|e| e.text(&self.symbols)).collect(),
            A_value: a_value,
            B_value: b_value,
            c_value: c.iter().map(|e| self.evaluate(e)).collect(),
            E: e,
            E_value: e_value,
            outputs: outputs.iter().map(|o| self.output_json(o)).collect(),
            notes: self.notes.iter().map(|n| n.text(&self.symbols)).collect(),
        }
    }

    fn output_json(&self, output: &OutputEquation) -> OutputJson {
        let row = |var: &dyn Fn(usize) -> Var, n: usize| -> Vec<RatFunc> {
            (0..n).map(|j| output.row.coefficient(var(j))).collect()
        };
        let c = row(&|j| Var::State(j as u32), self.states.len());
        let d = row(&|j| Var::Input(j as u32), self.inputs.len());
        let f = output
            .row
            .mentions(|v| matches!(v, Var::InputRate(_)))
            .then(|| row(&|j| Var::InputRate(j as u32), self.inputs.len()));
        let constant = output.row.coefficient(Var::Constant);
        OutputJson {
            name: output.name.clone(),
            C: c.iter().map(|e| e.text(&self.symbols)).collect(),
            D: d.iter().map(|e| e.text(&self.symbols)).collect(),
            F: f.as_ref()
                .map(|f| f.iter().map(|e| e.text(&self.symbols)).collect()),
            d: constant.text(&self.symbols),
            C_value: c.iter().map(|e| self.evaluate(e)).collect(),
            D_value: d.iter().map(|e| self.evaluate(e)).collect(),
            F_value: f
                .as_ref()
                .map(|f| f.iter().map(|e| self.evaluate(e)).collect()),
            d_value: self.evaluate(&constant),
            integral: output.integral,
        }
    }

    /// An output equation as text: `effort:damper = b/m*p_mass`.
    pub fn output_text(&self, output: &OutputEquation) -> String {
        if output.integral {
            return format!(
                "{} = integral of ({}) dt",
                output.name,
                self.form_text(&output.row)
            );
        }
        format!("{} = {}", output.name, self.form_text(&output.row))
    }
}

/// A state's name in LaTeX: its quantity's letter with the element's name as subscript,
/// by the rule parameters follow ([`latex_name`]): `q_{\mathrm{tyre}}`,
/// `p_{\mathrm{load\_inertia}}`, `q_{c}`.
pub(crate) fn state_latex(state: &crate::equations::StateVariable) -> String {
    // A state named with `symbol:` is written as any symbol is.
    if state.name != crate::model::state_symbol(state.quantity.letter(), &state.element) {
        return latex_name(&state.name);
    }
    // A sub-model's state (`front.q_spring`): its prefix upright, as for its parameters.
    let (prefix, element) = match state.element.rsplit_once('.') {
        Some((prefix, leaf)) => (format!("\\mathrm{{{}}}.", prefix.replace('_', "\\_")), leaf),
        None => (String::new(), state.element.as_str()),
    };
    format!(
        "{prefix}{}_{{{}}}",
        state.quantity.letter(),
        latex_subscript(element)
    )
}

/// An output's name in LaTeX: `flow:mass` as `\mathrm{flow}(\mathrm{mass})`.
pub(crate) fn latex_output_name(name: &str) -> String {
    let escape = |t: &str| t.trim().replace('_', "\\_").replace("->", "\\to ");
    match name.split_once(':') {
        Some((quantity, target)) => format!(
            "\\mathrm{{{}}}(\\mathrm{{{}}})",
            escape(quantity),
            escape(target)
        ),
        None => format!("\\mathrm{{{}}}", escape(name)),
    }
}

/// Dense matrices wider than this are not printed as text.
const MAX_DENSE_TEXT: usize = 16;

/// `coefficient * name`, written the way a textbook would: `p_mass/m` rather than
/// `1/m*p_mass`, parentheses around a bare sum.
fn product_text(magnitude: &str, name: &str) -> String {
    if magnitude == "1" {
        name.to_string()
    } else if let Some(denominator) = magnitude.strip_prefix("1/") {
        format!("{name}/{denominator}")
    } else if has_top_level_sum(magnitude) {
        format!("({magnitude})*{name}")
    } else {
        format!("{magnitude}*{name}")
    }
}

/// Whether `text` has a `+` or `-` outside parentheses (after its first character).
fn has_top_level_sum(text: &str) -> bool {
    let mut depth = 0i32;
    for (i, c) in text.char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            '+' | '-' if depth == 0 && i > 0 => return true,
            _ => {}
        }
    }
    false
}

/// A column vector with its sign pulled out when every non-zero entry is negative, as papers
/// write `- [F_C/m; 0] sgn(v)`; `None` for an all-zero column.
fn signed_column(entries: &[&RatFunc], symbols: &crate::symbolic::SymbolTable) -> Option<String> {
    if entries.iter().all(|e| e.is_zero()) {
        return None;
    }
    let all_negative = entries
        .iter()
        .filter(|e| !e.is_zero())
        .all(|e| e.signed_latex(symbols).0);
    let texts: Vec<String> = entries
        .iter()
        .map(|e| {
            if all_negative {
                (-(*e).clone()).latex(symbols)
            } else {
                e.latex(symbols)
            }
        })
        .collect();
    Some(format!(
        "{} \\begin{{bmatrix}} {} \\end{{bmatrix}}",
        if all_negative { "-" } else { "+" },
        texts.join(" \\\\ ")
    ))
}

/// A matrix as text, `name = [ ... ]` row by row; a blank `name` indents the rows without
/// a name (a matrix's values under its symbolic form).
pub(crate) fn matrix_text(name: &str, entries: &[Vec<String>]) -> String {
    let columns = entries.first().map_or(0, Vec::len);
    let widths: Vec<usize> = (0..columns)
        .map(|j| entries.iter().map(|row| row[j].len()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    for (i, row) in entries.iter().enumerate() {
        let prefix = if i == 0 && !name.trim().is_empty() {
            format!("{name} = ")
        } else {
            " ".repeat(name.len() + 3)
        };
        let cells: Vec<String> = row
            .iter()
            .zip(&widths)
            .map(|(cell, w)| format!("{cell:>w$}"))
            .collect();
        out.push_str(&format!("{prefix}[ {} ]\n", cells.join("  ")));
    }
    out
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_read_like_a_textbook() {
        assert_eq!(product_text("1", "p"), "p");
        assert_eq!(product_text("1/m", "p"), "p/m");
        assert_eq!(product_text("1/(m_1 + m_2)", "p"), "p/(m_1 + m_2)");
        assert_eq!(product_text("(b + K_p)/M", "v"), "(b + K_p)/M*v");
        assert_eq!(product_text("a + b", "v"), "(a + b)*v");
        assert_eq!(product_text("k", "q"), "k*q");
    }

    #[test]
    fn states_and_parameters_follow_one_subscript_rule() {
        // A tyre, a load inertia and a one-letter spring, with parameters named like
        // states: each state prints as the parameter of its name would.
        let text = r#"Model(name: "names",
            parameters: {"m_load_inertia": (value: 1.0), "k_t": (value: 2.0), "k_c": (value: 3.0),
                         "F_S_ge": (value: 1.0)},
            inputs: {"F": ()},
            elements: {"f": Se(effort: "F*F_S_ge"), "j": One, "load_inertia": I(inertance: "m_load_inertia"),
                       "tyre": C(stiffness: "k_t"), "c": C(stiffness: "k_c")},
            bonds: [("f", "j"), ("j", "load_inertia"), ("j", "tyre"), ("j", "c")])"#;
        let model = crate::testing::model(text);
        let eq = crate::equations::derive(
            &model,
            &crate::laws::plain_laws(&model),
            &crate::equations::Options::default(),
        )
        .expect("equations");
        let latex = eq.to_latex();
        for state in &eq.states {
            assert_eq!(
                state_latex(state),
                latex_name(&state.name),
                "{}",
                state.name
            );
        }
        for written in [
            "p_{\\mathrm{load\\_inertia}}",
            "q_{\\mathrm{tyre}}",
            "q_{c}",
            "m_{\\mathrm{load\\_inertia}}",
            "k_{t}",
            "F_{\\mathrm{S\\_ge}}",
        ] {
            assert!(latex.contains(written), "no {written} in\n{latex}");
        }
        // Nowhere a subscript of a subscript.
        assert!(!latex.contains("}}_{"), "{latex}");
    }
}
