//! The command line: every command, its arguments and their help, as `clap` reads them.
//! The formats map onto the views' plain enums, which know nothing of `clap`.

use std::path::PathBuf;

use bondgraph_core::equations::{Layout, Variables};
use bondgraph_fit::budget::Budget;
use bondgraph_view::formats::{ExplainFormat, GraphFormat};
use clap::{Parser, Subcommand, ValueEnum};

/// Bond-graph models in, state equations out.
#[derive(Parser, Debug)]
#[command(name = "bondgraph", version, about, long_about = None)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// The work a fit may do: each prediction of a row (or of a recorded run), and each fit. A
/// trial past its budget is a failed trial, counted in the report.
#[derive(clap::Args, Debug, Clone, Copy)]
pub(crate) struct BudgetArgs {
    /// Evaluations (predictions of every row at one trial point) one search of a fit may make
    /// (a fit runs several side by side, each with this budget).
    #[arg(long, value_name = "N", default_value_t = Budget::default().evaluations)]
    max_evaluations: usize,
    /// Mode changes one steady row may take to settle.
    #[arg(long, value_name = "N", default_value_t = Budget::default().mode_changes)]
    max_mode_changes: usize,
    /// Stretches one steady row's search may simulate (settling horizons, windows, the way
    /// to a predicted crossing).
    #[arg(long, value_name = "N", default_value_t = Budget::default().segments)]
    max_segments: usize,
    /// Integration steps and event-location samples one prediction may take.
    #[arg(long, value_name = "N", default_value_t = Budget::default().steps)]
    max_steps: u64,
}

impl From<BudgetArgs> for Budget {
    fn from(args: BudgetArgs) -> Self {
        Budget {
            mode_changes: args.max_mode_changes,
            segments: args.max_segments,
            steps: args.max_steps,
            evaluations: args.max_evaluations,
            ..Budget::default()
        }
    }
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Parse and validate a model; print a one-line summary or its diagnostics.
    Check {
        /// The model file (RON).
        model: PathBuf,
    },
    /// Show the bond graph and its causal strokes (a linear graph: its nodes, branches and
    /// normal tree), as text, Graphviz DOT or SVG.
    Graph {
        /// The model file (RON).
        model: PathBuf,
        /// The mode of the switching elements, e.g. fr=stuck,string=taut (default: initial).
        #[arg(long, value_name = "SPEC")]
        mode: Option<String>,
        /// Output format: text, dot (render with `dot -Tsvg`), or svg (drawn by the program).
        #[arg(long, value_enum, default_value_t = GraphArg::Text)]
        format: GraphArg,
        /// Draw each sub-model as one box, its bonds labelled with their ports (with
        /// --format dot); without it, each sub-model's elements are grouped in a box.
        #[arg(long)]
        collapse: bool,
    },
    /// Walk through the derivation as a teacher would on the board (a linear graph: the
    /// normal tree's construction, its primary and secondary variables, and the cut-set and
    /// loop equations).
    Explain {
        /// The model file (RON).
        model: PathBuf,
        /// The mode of the switching elements (default: initial).
        #[arg(long, value_name = "SPEC")]
        mode: Option<String>,
        /// Output format: text, or Markdown for lecture notes.
        #[arg(long, value_enum, default_value_t = ExplainArg::Text)]
        format: ExplainArg,
    },
    /// Derive the state equations dx/dt = A x + B u + c of a model.
    Equations {
        /// The model file (RON).
        model: PathBuf,
        /// The mode of the switching elements, e.g. fr=stuck,string=taut (default: initial).
        #[arg(long, value_name = "SPEC")]
        mode: Option<String>,
        /// Energy variables (momenta p, displacements q) or co-energy (velocities v, forces
        /// f); default energy for a bond graph, co-energy for a linear graph.
        #[arg(long, value_enum)]
        states: Option<StatesArg>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
        /// Also derive an output equation: effort:ELEMENT, flow:ELEMENT, effort:FROM->TO, or
        /// across:BRANCH, through:BRANCH of a linear graph, or integral:OUTPUT for an
        /// output's time integral.
        #[arg(long = "output", value_name = "SPEC")]
        outputs: Vec<String>,
        /// An operating point, NAME=VALUE,... over states and inputs (others are 0): a
        /// nonlinear mode's Jacobians are evaluated there, as A and B.
        #[arg(long, value_name = "NAME=VALUE,...")]
        at: Option<String>,
        /// Find an equilibrium f(x, u) = 0 of a nonlinear mode (inputs as --at gives them,
        /// starting from its states) and linearise there.
        #[arg(long)]
        equilibrium: bool,
        /// How --format json writes A, B and E: rows of entries (dense), or the non-zero
        /// entries as row, col, data (sparse); auto is dense up to 500 states.
        #[arg(long, value_enum, default_value_t = MatricesArg::Auto)]
        matrices: MatricesArg,
    },
    /// Poles, time constants, the transfer function, zeros, DC gain and step response of a
    /// linear mode (a nonlinear model: of its linearisation).
    Analyze {
        /// The model file (RON).
        model: PathBuf,
        /// The mode of the switching elements (default: initial).
        #[arg(long, value_name = "SPEC")]
        mode: Option<String>,
        /// The input of the transfer function (default: the first).
        #[arg(long, value_name = "NAME")]
        input: Option<String>,
        /// The output: a state's name, effort:ELEMENT, flow:ELEMENT, across:BRANCH,
        /// through:BRANCH or integral:OUTPUT (default: the first state).
        #[arg(long, value_name = "SPEC")]
        output: Option<String>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ReproduceFormat::Text)]
        format: ReproduceFormat,
        /// Also draw the Bode diagram, as SVG.
        #[arg(long, value_name = "FILE.svg")]
        bode: Option<PathBuf>,
        /// Also draw the step response, as SVG.
        #[arg(long, value_name = "FILE.svg")]
        step: Option<PathBuf>,
        /// A nonlinear model's operating point, NAME=VALUE,... (others 0).
        #[arg(long, value_name = "NAME=VALUE,...")]
        at: Option<String>,
        /// Linearise a nonlinear model at the equilibrium found from --at (or from 0).
        #[arg(long)]
        equilibrium: bool,
    },
    /// Check an answer's A and B (RON) against a model's equations: exit 0 if equal or equal
    /// up to a change of state variables, 1 if different, 2 on error.
    Compare {
        /// The model file (RON).
        model: PathBuf,
        /// The answer file (RON): Answer(states: [...], A: [[...]], B: [[...]]).
        answer: PathBuf,
        /// The mode of the switching elements (default: initial).
        #[arg(long, value_name = "SPEC")]
        mode: Option<String>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ReproduceFormat::Text)]
        format: ReproduceFormat,
    },
    /// Simulate a model driven by a scenario file; print the trajectory as CSV or JSON.
    Simulate {
        /// The model file (RON).
        model: PathBuf,
        /// The scenario file (RON): inputs, initial mode and state, duration, outputs.
        #[arg(long)]
        scenario: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value_t = SimulateFormat::Csv)]
        format: SimulateFormat,
        /// Write the trajectory to this file instead of standard output.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// Also plot the recorded outputs against time, with the modes shaded, as SVG.
        #[arg(long, value_name = "FILE.svg")]
        plot: Option<PathBuf>,
        /// With --plot: one panel of these recorded outputs, comma-separated (repeat for
        /// more panels, top to bottom); default one panel per output.
        #[arg(long = "panel", value_name = "OUTPUT,...")]
        panels: Vec<String>,
    },
    /// The main job: the flagship eversion robot against the paper's tables and Fig. 6.
    Reproduce {
        /// Where to write the report, tables, plots and JSON.
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
        /// What to print: a summary, or the results as JSON.
        #[arg(long, value_enum, default_value_t = ReproduceFormat::Text)]
        format: ReproduceFormat,
    },
    /// Fit the experiment's parameters to measured data: values, standard errors, intervals
    /// of thresholds, residuals by regime and by condition.
    Calibrate {
        /// The model file (RON).
        #[arg(long)]
        model: PathBuf,
        /// The measured data (CSV, the columns the experiment names); repeat to fit several
        /// files together.
        #[arg(long, required = true)]
        data: Vec<PathBuf>,
        /// The experiment file (default: experiment.ron beside the model).
        #[arg(long)]
        experiment: Option<PathBuf>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ReproduceFormat::Text)]
        format: ReproduceFormat,
        #[command(flatten)]
        budget: BudgetArgs,
    },
    /// What a model gets wrong on measured data, and which candidate extension explains it.
    Discover {
        /// The model file (RON).
        #[arg(long)]
        model: PathBuf,
        /// The measured data (CSV, the columns the experiment names); repeat to analyse
        /// several files together.
        #[arg(long, required = true)]
        data: Vec<PathBuf>,
        /// The experiment file (default: experiment.ron beside the model).
        #[arg(long)]
        experiment: Option<PathBuf>,
        /// The folder of candidate extensions (default: extensions/ beside the model).
        #[arg(long, value_name = "DIR")]
        extensions: Option<PathBuf>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ReproduceFormat::Text)]
        format: ReproduceFormat,
        /// Also write the report, the JSON, the extended model and residual plots here.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        #[command(flatten)]
        budget: BudgetArgs,
        /// Rerun the selection on N complementary half-samples of the data and report how
        /// often each candidate is selected (0: none; default: 20 when they cost less than
        /// the search itself).
        #[arg(long, value_name = "N")]
        resamples: Option<usize>,
    },
    /// Merge extensions (bond-graph fragments, or linear-graph fragments into a linear graph; RON) into a model; print the extended model file.
    Extend {
        /// The model file (RON).
        model: PathBuf,
        /// The extension files (RON), merged in order.
        #[arg(required = true)]
        extensions: Vec<PathBuf>,
        /// Write the extended model to this file instead of standard output.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// List the modes reachable from the initial mode, their states and their guards.
    Modes {
        /// The model file (RON).
        model: PathBuf,
        /// Energy or co-energy variables, for the guards' expressions (default as for
        /// equations).
        #[arg(long, value_enum)]
        states: Option<StatesArg>,
        /// Output format.
        #[arg(long, value_enum, default_value_t = ModesFormat::Text)]
        format: ModesFormat,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum ReproduceFormat {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum SimulateFormat {
    Csv,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum ModesFormat {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum MatricesArg {
    Auto,
    Dense,
    Sparse,
}

impl MatricesArg {
    pub(crate) fn layout(self) -> Option<Layout> {
        match self {
            Self::Auto => None,
            Self::Dense => Some(Layout::Dense),
            Self::Sparse => Some(Layout::Sparse),
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum StatesArg {
    Energy,
    Coenergy,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    Text,
    Latex,
    Json,
}

/// `--format` of `graph`, mapped onto [`GraphFormat`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum GraphArg {
    /// The elements, bonds and causality (a linear graph: nodes, branches, normal tree).
    Text,
    /// Graphviz DOT (render with `dot -Tsvg`).
    Dot,
    /// SVG, drawn by the program.
    Svg,
}

impl From<GraphArg> for GraphFormat {
    fn from(arg: GraphArg) -> Self {
        match arg {
            GraphArg::Text => GraphFormat::Text,
            GraphArg::Dot => GraphFormat::Dot,
            GraphArg::Svg => GraphFormat::Svg,
        }
    }
}

/// `--format` of `explain`, mapped onto [`ExplainFormat`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum ExplainArg {
    /// Plain text.
    Text,
    /// Markdown (headings, numbered lists), for lecture notes.
    Markdown,
}

impl From<ExplainArg> for ExplainFormat {
    fn from(arg: ExplainArg) -> Self {
        match arg {
            ExplainArg::Text => ExplainFormat::Text,
            ExplainArg::Markdown => ExplainFormat::Markdown,
        }
    }
}

impl StatesArg {
    pub(crate) fn variables(self) -> Variables {
        match self {
            StatesArg::Energy => Variables::Energy,
            StatesArg::Coenergy => Variables::CoEnergy,
        }
    }
}
