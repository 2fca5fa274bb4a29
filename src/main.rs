//! `bondgraph`: bond-graph models in RON to symbolic state equations.
//!
//! This binary only parses arguments, calls the libraries and writes their results in the
//! requested format; diagnostics from the libraries are rendered here with a snippet of the
//! model file, and any failure exits non-zero.

use bondgraph::graph::GraphFormat;
use bondgraph::{
    Failure, analyze, calibrate, check, compare, count, derive, diagnostics, discover, explain_bg,
    json, load, output, parse_mode, print, read_source, reproduce, simulate, write_file,
};

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::{Layout, Variables};
use bondgraph_fit::budget::Budget;
use clap::{Parser, Subcommand, ValueEnum};

/// Fits evaluate thousands of steady states, each a handful of short-lived vectors: a
/// thread-caching allocator takes a fifth off their time.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Bond-graph models in, state equations out.
#[derive(Parser, Debug)]
#[command(name = "bondgraph", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The work a fit may do: each prediction of a row (or of a recorded run), and each fit. A
/// trial past its budget is a failed trial, counted in the report.
#[derive(clap::Args, Debug, Clone, Copy)]
struct BudgetArgs {
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
enum Command {
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
        #[arg(long, value_enum, default_value_t = GraphFormat::Text)]
        format: GraphFormat,
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
        #[arg(long, value_enum, default_value_t = explain_bg::ExplainFormat::Text)]
        format: explain_bg::ExplainFormat,
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
enum ReproduceFormat {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SimulateFormat {
    Csv,
    Json,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ModesFormat {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum MatricesArg {
    Auto,
    Dense,
    Sparse,
}

impl MatricesArg {
    fn layout(self) -> Option<Layout> {
        match self {
            Self::Auto => None,
            Self::Dense => Some(Layout::Dense),
            Self::Sparse => Some(Layout::Sparse),
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum StatesArg {
    Energy,
    Coenergy,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Format {
    Text,
    Latex,
    Json,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Command::Compare {
        model,
        answer,
        mode,
        format,
    } = &cli.command
    {
        // Its own exit codes: 0 equal or similar, 1 different, 2 error.
        return match compare::run(
            model,
            answer,
            mode.as_deref(),
            *format == ReproduceFormat::Json,
        )
        .and_then(|same| {
            output::finish()
                .map(|()| same)
                .map_err(|message| Failure::message(DiagnosticKind::Io, message))
        }) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::from(1),
            Err(failure) => {
                report(failure);
                ExitCode::from(2)
            }
        };
    }
    match run(cli).and_then(|()| {
        output::finish().map_err(|message| Failure::message(DiagnosticKind::Io, message))
    }) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            report(failure);
            ExitCode::FAILURE
        }
    }
}

/// Writes a failure's diagnostics to stderr, with snippets of the files they point into.
fn report(failure: Failure) {
    {
        {
            let mut stderr = std::io::stderr().lock();
            for diagnostic in failure.diagnostics.iter() {
                let source = diagnostic.location.as_ref().and_then(|location| {
                    failure
                        .sources
                        .iter()
                        .find(|s| s.name() == location.file)
                        .map(|s| s.as_ref())
                });
                let _ = writeln!(stderr, "{}", diagnostics::render(diagnostic, source));
            }
            let count = failure.diagnostics.0.len();
            if count > 1 {
                let _ = writeln!(stderr, "error: {count} problems found");
            }
        }
    }
}

fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Check { model } => {
            let (model, source) = load(&model)?;
            print(&format!("{}\n", check::summary(&model, &source)?));
            Ok(())
        }
        Command::Graph {
            model,
            mode,
            format,
        } => {
            let (model, source) = load(&model)?;
            let mode = parse_mode(&model, mode.as_deref(), &source)?;
            print(&bondgraph::graph::render(&model, &mode, &source, format)?);
            Ok(())
        }
        Command::Equations {
            model,
            mode,
            states,
            format,
            outputs,
            at,
            equilibrium,
            matrices,
        } => {
            let (model, source) = load(&model)?;
            let request = derive::Request {
                mode,
                variables: states.map(StatesArg::variables),
                outputs,
                at,
                equilibrium,
                matrices: matrices.layout(),
            };
            let derived = derive::derive(&model, &source, &request)?;
            print(&match format {
                Format::Text => derived.text(),
                Format::Latex => derived.latex(),
                Format::Json => derived.json()?,
            });
            Ok(())
        }
        Command::Simulate {
            model,
            scenario,
            format,
            out,
            plot,
            panels,
        } => simulate(
            &model,
            &scenario,
            format,
            out.as_deref(),
            plot.as_deref(),
            &panels,
        ),
        Command::Explain {
            model,
            mode,
            format,
        } => {
            let (model, source) = load(&model)?;
            let mode = parse_mode(&model, mode.as_deref(), &source)?;
            explain_bg::run(&model, &mode, &source, format)
        }
        Command::Analyze {
            model,
            mode,
            input,
            output,
            format,
            bode,
            step,
            at,
            equilibrium,
        } => analyze::run(&analyze::Args {
            model,
            request: analyze::Request {
                mode,
                input,
                output,
                at,
                equilibrium,
            },
            json: format == ReproduceFormat::Json,
            bode,
            step,
        }),
        // Dispatched in `main`, for its exit codes.
        Command::Compare { .. } => Ok(()),
        Command::Reproduce { out, format } => reproduce::run(&out, format == ReproduceFormat::Json),
        Command::Calibrate {
            model,
            data,
            experiment,
            format,
            budget,
        } => calibrate::run(&calibrate::Args {
            model,
            data,
            experiment,
            json: format == ReproduceFormat::Json,
            budget: budget.into(),
        }),
        Command::Discover {
            model,
            data,
            experiment,
            extensions,
            format,
            out,
            budget,
            resamples,
        } => discover::run(&discover::Args {
            model,
            data,
            experiment,
            extensions,
            json: format == ReproduceFormat::Json,
            out,
            budget: budget.into(),
            resamples,
        }),
        Command::Extend {
            model,
            extensions,
            out,
        } => extend(&model, &extensions, out.as_deref()),
        Command::Modes {
            model,
            states,
            format,
        } => {
            let (model, source) = load(&model)?;
            let variables = states.map(StatesArg::variables);
            print(&check::modes(
                &model,
                &source,
                variables,
                format == ModesFormat::Json,
            )?);
            Ok(())
        }
    }
}

/// `bondgraph simulate`.
fn simulate(
    model: &Path,
    scenario: &Path,
    format: SimulateFormat,
    out: Option<&Path>,
    plot: Option<&Path>,
    panels: &[String],
) -> Result<(), Failure> {
    let run = simulate::simulate(&read_source(model)?, &read_source(scenario)?)?;
    let text = match format {
        SimulateFormat::Csv => run.csv(),
        SimulateFormat::Json => json(&run.json())?,
    };
    match out {
        Some(path) => write_file(path, &text)?,
        None => print(&text),
    }
    if let Some(path) = plot {
        write_file(path, &run.plot(panels)?)?;
    }
    let trajectory = &run.trajectory;
    eprintln!(
        "simulated {} s of '{}' in {:.3} ms: {} events, {} modes, {} segments",
        trajectory.final_time,
        run.scenario.name,
        run.elapsed.as_secs_f64() * 1e3,
        trajectory.stats.events,
        trajectory.stats.modes,
        trajectory.stats.segments
    );
    if let Some(books) = &trajectory.energy {
        // The books bound their own rounding; past a millionth of their largest term the
        // terms of the powers have cancelled (a mode whose rates differ by more than
        // rounding can tell apart), and the figures are only that good.
        let share = books.error / books.scale();
        if share > 1e-6 {
            eprintln!(
                "warning: the energy books are uncertain to {:e} J, {share:.1e} of their largest \
                 term: the terms of the powers cancel below rounding",
                books.error
            );
        }
    }
    Ok(())
}

/// Merges extensions into a model, checks the result and prints or writes it.
fn extend(model: &Path, extensions: &[PathBuf], out: Option<&Path>) -> Result<(), Failure> {
    use bondgraph_core::model::extension::{self, Extension};
    let base = read_source(model)?;
    let mut sources = vec![base.clone()];
    let mut fragments = Vec::new();
    for path in extensions {
        let source = read_source(path)?;
        sources.push(source.clone());
        let fragment = Extension::load(&source).map_err(|d| Failure {
            diagnostics: d,
            sources: sources.clone(),
        })?;
        fragments.push(fragment);
    }
    let failure = |diagnostics| Failure {
        diagnostics,
        sources: sources.clone(),
    };
    let extended = extension::merge(&base, &fragments).map_err(failure)?;
    let merged = extended.check().map_err(failure)?;
    match out {
        Some(path) => {
            write_file(path, extended.file.text())?;
            let parts = match &merged.linear_graph {
                Some(graph) => format!(
                    "{}, {}",
                    count(graph.nodes.len(), "node"),
                    count(graph.branches.len(), "branch")
                ),
                None => format!(
                    "{}, {}",
                    count(merged.elements.len(), "element"),
                    count(merged.bonds.len(), "bond")
                ),
            };
            eprintln!(
                "{}: model '{}' written ({parts})",
                path.display(),
                merged.name,
            );
        }
        None => print(extended.file.text()),
    }
    Ok(())
}

impl StatesArg {
    fn variables(self) -> Variables {
        match self {
            StatesArg::Energy => Variables::Energy,
            StatesArg::Coenergy => Variables::CoEnergy,
        }
    }
}
