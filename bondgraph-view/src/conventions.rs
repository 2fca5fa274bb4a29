//! Rendering of [`bondgraph_core::conventions`] and of the LaTeX preamble note: what the
//! printed equations assume of the reader's file and of their LaTeX document.

use bondgraph_core::model::Model;

/// The `conventions:` block after the state equations: what each source's direction and
/// each transformer's ratio mean, in words (empty if the model has none).
pub fn text(model: &Model) -> String {
    let lines = bondgraph_core::conventions::describe(model);
    if lines.is_empty() {
        return String::new();
    }
    let mut text = String::from("\nconventions (as written in the file):\n");
    for line in lines {
        text.push_str(&format!("  {line}\n"));
    }
    text
}

/// The comment opening `--format latex` output: the packages it needs.
pub fn latex_preamble(model: &Model) -> String {
    format!(
        "% State equations of '{}' (bondgraph). The matrices need \\usepackage{{amsmath}}:\n\
         % put this inside \\begin{{document}}...\\end{{document}} of a document whose preamble\n\
         % has \\documentclass{{article}} and \\usepackage{{amsmath}}.\n",
        model.name()
    )
}
