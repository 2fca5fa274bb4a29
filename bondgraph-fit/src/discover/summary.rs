//! Discovery as text: what the base model gets wrong, the candidates, the selection, the gain.

use super::verdicts::WORSE_THAN_THE_BASE;
use super::{Discovery, Estimate, Ranked, Residuals};
use crate::noise;

impl Discovery {
    /// A readable report: what the base model gets wrong, the candidates, the selection and
    /// the gain.
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        if self.observed.len() == 1 {
            self.one_column_header(&mut s);
        } else {
            self.columns_header(&mut s);
        }
        if let Some(test) = &self.lack_of_fit {
            let _ = writeln!(s, "  lack of fit of the base model: {}", test.text());
        }
        let _ = writeln!(
            s,
            "\nbase model, refitted: RMSE {:.3} on the fit, {:.3} held out",
            self.baseline.rmse_fit, self.baseline.rmse_heldout
        );
        for (name, e) in &self.baseline.params {
            let _ = writeln!(s, "  {name} = {}", estimate_text(e));
        }
        self.write_column_scores(&mut s, &self.baseline.columns);
        let _ = writeln!(s, "\nwhat it gets wrong (model minus measured):");
        write_residuals(&mut s, &self.residuals_before);
        for column in &self.columns {
            let _ = writeln!(s, "  `{}`, in its units:", column.column);
            write_residuals(&mut s, &column.residuals_before);
        }
        let _ = writeln!(s, "\ncandidates, best held-out RMSE first:");
        let _ = writeln!(
            s,
            "  {:<30} {:>9} {:>9} {:>8} {:>9}  verdict",
            "id", "fit", "held-out", "dAICc", "p"
        );
        for r in &self.ranking {
            let _ = writeln!(
                s,
                "  {:<30} {:>9.3} {:>9.3} {:>8.1} {:>9.2e}  {}",
                r.id, r.rmse_fit, r.rmse_heldout, r.score, r.p_value, r.verdict
            );
        }
        self.write_ranking_by_column(&mut s);
        match &self.selected {
            Some(id) => {
                let _ = writeln!(
                    s,
                    "\nselected: {id}: {}",
                    self.cause.as_deref().unwrap_or("")
                );
                if let Some(r) = self.ranking.iter().find(|r| &r.id == id) {
                    for (name, e) in &r.params {
                        let _ = writeln!(s, "  {name} = {}", estimate_text(e));
                    }
                    self.write_column_scores(&mut s, &r.columns);
                }
                if let Some(after) = &self.residuals_after {
                    let _ = writeln!(s, "residuals after:");
                    write_residuals(&mut s, after);
                }
                for column in &self.columns {
                    if let Some(after) = &column.residuals_after {
                        let _ = writeln!(s, "  `{}`, in its units:", column.column);
                        write_residuals(&mut s, after);
                    }
                }
            }
            None => {
                let _ = writeln!(
                    s,
                    "\nselected: null (no candidate gains beyond what the noise explains)"
                );
            }
        }
        let _ = writeln!(
            s,
            "held-out RMSE: {:.3} before, {:.3} after",
            self.gain.rmse_heldout_before, self.gain.rmse_heldout_after
        );
        if let Some(stability) = &self.stability {
            let _ = writeln!(s, "{}", stability.summary);
        }
        if !self.separation.is_empty() {
            let against = self.selected.as_deref().unwrap_or("the base model");
            let _ = writeln!(s, "\ncannot be told apart from {against} on this data:");
            for sep in &self.separation {
                let _ = writeln!(s, "  {}: {}", sep.id, sep.measurement);
            }
        }
        if !self.untestable.is_empty() {
            let _ = writeln!(
                s,
                "\nno effect on this data (untestable here): {}",
                self.untestable.join(", ")
            );
        }
        let worse: Vec<&Ranked> = self
            .ranking
            .iter()
            .filter(|r| r.verdict == WORSE_THAN_THE_BASE)
            .collect();
        if !worse.is_empty() {
            let _ = writeln!(
                s,
                "\nworse than the base model even at their no-effect values, so within their \
                 bounds they cannot contain it on this data (widen the bounds in the extension \
                 file):"
            );
            for r in worse {
                let _ = writeln!(
                    s,
                    "  {}: RMSE {:.3} against the base model's {:.3}",
                    r.id, r.rmse_fit, self.baseline.rmse_fit
                );
            }
        }
        crate::budget::write_failed_trials(&mut s, &self.failed_trials);
        s
    }
}

impl Discovery {
    /// The first line of one column's report: its name, noise and where the noise came from.
    fn one_column_header(&self, s: &mut String) {
        use std::fmt::Write;
        let (observed, source) = (&self.observed[0], &self.noise_source[0]);
        match self.noise[0] {
            Some(sd) => {
                let _ = writeln!(
                    s,
                    "{}: {} rows, observed `{observed}` (every RMSE and residual below is in its \
                     units); noise {sd:.3}, {source}",
                    self.data, self.rows
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "{}: {} rows, observed `{observed}` (every RMSE and residual below is in its \
                     units); noise: {source}",
                    self.data, self.rows
                );
                let _ = writeln!(
                    s,
                    "  so nothing below is judged in noise levels (no residual stands out of \
                     the noise; candidates count as indistinguishable only if they fit as well)"
                );
            }
        }
        // Replicates that did not give the noise level: too few, or a declared noise.
        if let Some(pe) = &self.pure_error[0]
            && (pe.dof < noise::MIN_PURE_ERROR_DOF || source == "declared in the experiment")
        {
            let _ = writeln!(
                s,
                "  replicates: pure error {:.3} of {} replicated condition(s) ({} dof{})",
                pe.sd,
                pe.groups,
                pe.dof,
                if pe.dof < noise::MIN_PURE_ERROR_DOF {
                    format!(", fewer than the {} needed", noise::MIN_PURE_ERROR_DOF)
                } else {
                    String::new()
                }
            );
        }
    }

    /// The first lines of a report on several columns: each column's noise, which weighs it.
    fn columns_header(&self, s: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            s,
            "{}: {} rows, {} observed columns, each weighed by its noise (combined RMSEs and \
             residuals below are in noise levels; each column's in its units):",
            self.data,
            self.rows,
            self.observed.len()
        );
        for (k, column) in self.observed.iter().enumerate() {
            let noise = self.noise[k].map_or_else(|| "none".to_string(), |sd| number(sd, 4));
            let _ = writeln!(s, "  `{column}`: noise {noise}, {}", self.noise_source[k]);
        }
    }

    /// With several columns, each candidate's RMSEs (fit / held out) per column, in the
    /// columns' units.
    fn write_ranking_by_column(&self, s: &mut String) {
        use std::fmt::Write;
        if self.observed.len() < 2 {
            return;
        }
        let _ = write!(
            s,
            "  each column, fit / held-out in its units:\n  {:<30}",
            "id"
        );
        for column in &self.observed {
            let _ = write!(s, " {:>21}", format!("`{column}`"));
        }
        let _ = writeln!(s);
        let base = ("the base model", &self.baseline.columns);
        let rows =
            std::iter::once(base).chain(self.ranking.iter().map(|r| (r.id.as_str(), &r.columns)));
        for (id, columns) in rows {
            let _ = write!(s, "  {id:<30}");
            for c in columns {
                let pair = format!("{} / {}", number(c.rmse_fit, 3), number(c.rmse_heldout, 3));
                let _ = write!(s, " {pair:>21}");
            }
            let _ = writeln!(s);
        }
    }

    /// With several columns, a table of each column's RMSEs in its units.
    fn write_column_scores(&self, s: &mut String, columns: &[super::ColumnScore]) {
        use std::fmt::Write;
        if columns.is_empty() {
            return;
        }
        let _ = writeln!(s, "  {:<24} {:>12} {:>12}", "column", "fit", "held-out");
        for c in columns {
            let _ = writeln!(
                s,
                "  {:<24} {:>12} {:>12}",
                format!("`{}`", c.column),
                number(c.rmse_fit, 4),
                number(c.rmse_heldout, 4)
            );
        }
    }
}

/// An estimate as text: the value, `± SE`, the interval of a threshold, `(at its bound)`, or
/// that the data do not determine it.
pub fn estimate_text(e: &Estimate) -> String {
    let mut s = number(e.value, 6);
    if let Some(se) = e.std_error {
        s.push_str(&format!(" ± {se:.3e}"));
    }
    if let Some((lo, hi)) = e.interval {
        s.push_str(&format!(
            " (any value in [{}, {}] fits as well)",
            number(lo, 4),
            number(hi, 4)
        ));
    }
    if e.at_bound {
        s.push_str(" (at its bound)");
    }
    if e.std_error.is_none() && e.interval.is_none() && !e.at_bound {
        // Aliased with others, or moving the residuals too little to have an error.
        s.push_str(" (not determined by this data)");
    }
    s
}

/// `value` with `decimals` decimals, or in scientific notation with as many where fixed
/// decimals would hide it (a flow of 4e-7 m³/s) or bury it in digits.
pub(super) fn number(value: f64, decimals: usize) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        format!("{value:.decimals$}")
    } else {
        format!("{value:.decimals$e}")
    }
}

/// Residuals as text, one line per regime and per trend beyond the noise.
pub fn write_residuals(s: &mut String, residuals: &Residuals) {
    use std::fmt::Write;
    for r in &residuals.by_regime {
        let _ = writeln!(
            s,
            "  {:<18} {:>2} rows: mean {:+.3}, RMS {:.3}{}",
            r.regime,
            r.rows,
            r.mean,
            r.rmse,
            if r.stands_out {
                "  <- beyond the noise"
            } else {
                ""
            }
        );
    }
    for t in residuals.by_condition.iter().filter(|t| t.stands_out) {
        let _ = writeln!(
            s,
            "  trend along {} ({}): {:+.4} ± {:.4} per unit  <- beyond the noise",
            t.condition, t.regime, t.slope, t.std_error
        );
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn an_estimate_says_what_the_data_determine() {
        let e = |std_error, interval, at_bound| {
            super::estimate_text(&super::Estimate {
                value: 2.0,
                std_error,
                interval,
                at_bound,
            })
        };
        assert_eq!(e(Some(0.5), None, false), "2.000000 ± 5.000e-1");
        assert_eq!(
            e(None, Some((1.0, 3.0)), false),
            "2.000000 (any value in [1.0000, 3.0000] fits as well)"
        );
        assert_eq!(e(None, None, true), "2.000000 (at its bound)");
        assert_eq!(
            e(None, None, false),
            "2.000000 (not determined by this data)"
        );
    }

    #[test]
    fn numbers_keep_their_digits_at_any_scale() {
        assert_eq!(number(1234.5678, 2), "1234.57");
        assert_eq!(number(0.0, 6), "0.000000");
        assert_eq!(number(3.767e-7, 6), "3.767000e-7");
        assert_eq!(number(-2.5e8, 4), "-2.5000e8");
    }
}
