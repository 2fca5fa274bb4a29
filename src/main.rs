//! `bondgraph`: bond-graph models in RON to symbolic state equations.
//!
//! This binary only parses arguments, calls the libraries and writes their results in the
//! requested format; diagnostics from the libraries are rendered here with a snippet of the
//! model file, and any failure exits non-zero.

mod conventions;
mod lg_graph;
mod nonlinear;

use bondgraph::{
    Failure, analyze, bg_svg, calibrate, compare, count, diagnostics, discover, explain_bg, json,
    lg_svg, load, output, parse_mode, plot, print, read_source, reproduce, trajectory, with_source,
    write_file,
};

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use bondgraph_core::equations::{self, Variables};
use bondgraph_core::model::Model;
use bondgraph_core::scenario::Record;
use bondgraph_core::{DiagnosticKind, causality, graph, laws, modes};
use clap::{Parser, Subcommand, ValueEnum};

/// Bond-graph models in, state equations out.
#[derive(Parser, Debug)]
#[command(name = "bondgraph", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
    },
    /// Merge extensions (bond-graph fragments, RON) into a model; print the extended model file.
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
enum StatesArg {
    Energy,
    Coenergy,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum GraphFormat {
    Text,
    Dot,
    Svg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
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
            if model.is_nonlinear() {
                return nonlinear::check(&model, &source);
            }
            let reachable = modes::reachable(&model, &equations::Options::default())
                .map_err(|d| with_source(d, &source))?;
            let initial = &reachable.modes[0].equations;
            let mode_count = if reachable.initial.is_empty() {
                String::new()
            } else {
                format!(", {}", count(reachable.modes.len(), "reachable mode"))
            };
            let (kind, parts) = match &model.linear_graph {
                Some(graph) => (
                    "linear graph",
                    [
                        (graph.nodes.len(), "node"),
                        (graph.branches.len(), "branch"),
                    ],
                ),
                None => (
                    "model",
                    [
                        (model.elements.len(), "element"),
                        (model.bonds.len(), "bond"),
                    ],
                ),
            };
            print(&format!(
                "{}: ok: {kind} '{}' with {}, {}, {}, {} and {}{mode_count}\n",
                source.name(),
                model.name,
                count(parts[0].0, parts[0].1),
                count(parts[1].0, parts[1].1),
                count(model.parameters.len(), "parameter"),
                count(model.inputs.len(), "input"),
                count(initial.state_count(), "state"),
            ));
            Ok(())
        }
        Command::Graph {
            model,
            mode,
            format,
        } => {
            let (model, source) = load(&model)?;
            let mode = parse_mode(&model, mode.as_deref(), &source)?;
            if model.linear_graph.is_some() {
                return lg_graph::run(&model, &mode, format, &source);
            }
            let laws = laws::for_mode(&model, &mode);
            let causality =
                causality::assign(&model, &laws).map_err(|d| with_source(d, &source))?;
            // A graph of a mode whose equations cannot be derived (a zero resistance in
            // conductance causality) would be a drawing of a model `check` rejects.
            if !model.is_nonlinear() {
                equations::derive(&model, &laws, &equations::Options::default())
                    .map_err(|d| with_source(d, &source))?;
            }
            let text = match format {
                GraphFormat::Text => format!(
                    "{}\n{}",
                    graph::describe(&model),
                    graph::describe_causality(&model, &laws, &causality)
                ),
                GraphFormat::Dot => graph::to_dot_titled(
                    &model,
                    Some(&causality),
                    Some(&bg_svg::title(&model, &mode.spec(&model))),
                ),
                GraphFormat::Svg => bg_svg::draw(&model, &mode, &causality),
            };
            print(&text);
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
        } => {
            let (model, source) = load(&model)?;
            let mode = parse_mode(&model, mode.as_deref(), &source)?;
            let options = equations::Options {
                variables: variables(states, &model),
            };
            if model.is_nonlinear() {
                return nonlinear::equations(&nonlinear::EquationsArgs {
                    model: &model,
                    source: &source,
                    mode: &mode,
                    options,
                    format,
                    outputs: &outputs,
                    at: at.as_deref(),
                    equilibrium,
                });
            }
            if equilibrium {
                return Err(Failure::message(
                    DiagnosticKind::NotLinear,
                    "--equilibrium is for nonlinear models; a linear mode's equilibria solve A x + B u + c = 0",
                ));
            }
            let derived =
                modes::derive(&model, &mode, &options).map_err(|d| with_source(d, &source))?;
            let equations = &derived.equations;
            if let Some(at) = &at {
                // A linear mode's matrices do not depend on the point; the point is checked.
                let names: Vec<String> = equations.states.iter().map(|s| s.name.clone()).collect();
                equations::nonlinear::OperatingPoint::parse(&names, &equations.inputs, at)
                    .map_err(|d| with_source(d, &source))?;
            }
            let outputs = outputs
                .iter()
                .map(|spec| {
                    Record::parse_output(&model, spec).map(|(record, spec)| {
                        let mut output = equations.output(&spec);
                        output.integral = matches!(record, Record::Integral(_));
                        output.name = record.name();
                        output
                    })
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(|d| with_source(d, &source))?;
            let text = match format {
                Format::Text => {
                    let mut text = String::new();
                    if !mode.is_empty() {
                        text.push_str(&format!("mode {}\n", mode.spec(&model)));
                    }
                    text.push_str(&equations.to_text());
                    if !outputs.is_empty() {
                        text.push_str("\noutputs:\n");
                        for output in &outputs {
                            text.push_str(&format!("  {}\n", equations.output_text(output)));
                        }
                    }
                    if !derived.guards.is_empty() {
                        text.push_str("\nguards:\n");
                        for guard in &derived.guards {
                            let element = &model.element(guard.element).name;
                            text.push_str(&format!(
                                "  {element}: {} -> {element}={}\n",
                                guard.condition_text(equations),
                                guard.leaves_to.name()
                            ));
                        }
                    }
                    text.push_str(&conventions::text(&model));
                    text
                }
                Format::Latex => format!(
                    "{}{}",
                    conventions::latex_preamble(&model),
                    equations.to_latex_with_outputs(&outputs)
                ),
                Format::Json => json(&equations.to_json(&mode.spec(&model), &outputs))?,
            };
            print(&text);
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
        } => calibrate::run(&calibrate::Args {
            model,
            data,
            experiment,
            json: format == ReproduceFormat::Json,
        }),
        Command::Discover {
            model,
            data,
            experiment,
            extensions,
            format,
            out,
        } => discover::run(&discover::Args {
            model,
            data,
            experiment,
            extensions,
            json: format == ReproduceFormat::Json,
            out,
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
            let options = equations::Options {
                variables: variables(states, &model),
            };
            if model.is_nonlinear() {
                return nonlinear::modes(&model, &source, &options, format == ModesFormat::Json);
            }
            let reachable =
                modes::reachable(&model, &options).map_err(|d| with_source(d, &source))?;
            let text = match format {
                ModesFormat::Text => reachable.to_text(&model),
                ModesFormat::Json => json(&reachable.to_json(&model))?,
            };
            print(&text);
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
    let model_source = read_source(model)?;
    let scenario_source = read_source(scenario)?;
    let sources = vec![model_source.clone(), scenario_source.clone()];
    let loaded =
        bondgraph_core::scenario::load(&scenario_source, &model_source).map_err(|d| Failure {
            diagnostics: d,
            sources: sources.clone(),
        })?;
    let started = std::time::Instant::now();
    let trajectory = bondgraph_solver::scenario::run(&loaded, false)
        .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
    let elapsed = started.elapsed();
    let text = match format {
        SimulateFormat::Csv => trajectory::to_csv(&trajectory),
        SimulateFormat::Json => json(&trajectory::to_json(
            &trajectory,
            &loaded.model.name,
            &loaded.name,
        ))?,
    };
    match out {
        Some(path) => write_file(path, &text)?,
        None => print(&text),
    }
    if let Some(path) = plot {
        let title = format!("{}: scenario {}", loaded.model.name, loaded.name);
        let panels = plot::panels(&trajectory, panels)
            .map_err(|e| Failure::message(DiagnosticKind::BadOutput, e))?;
        // Axes say what each output is and its unit, where the model's units tell them.
        let mut labelled = trajectory.clone();
        for name in &mut labelled.output_names {
            if let Some(record) = loaded.record.iter().find(|r| r.name() == *name) {
                *name = bondgraph_core::units::label::axis_label(&loaded.model, record);
            }
        }
        let svg = plot::plot_svg(&labelled, &title, &panels)
            .map_err(|e| Failure::message(DiagnosticKind::Io, format!("cannot plot: {e}")))?;
        write_file(path, &svg)?;
    }
    eprintln!(
        "simulated {} s of '{}' in {:.3} ms: {} events, {} modes, {} segments",
        trajectory.final_time,
        loaded.name,
        elapsed.as_secs_f64() * 1e3,
        trajectory.stats.events,
        trajectory.stats.modes,
        trajectory.stats.segments
    );
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
            eprintln!(
                "{}: model '{}' written ({}, {})",
                path.display(),
                merged.name,
                count(merged.elements.len(), "element"),
                count(merged.bonds.len(), "bond")
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

/// The variables asked for, or the model's own: co-energy for a linear graph (as Rowell &
/// Wormley write its states), energy for a bond graph.
fn variables(states: Option<StatesArg>, model: &Model) -> Variables {
    states.map_or_else(|| Variables::preferred(model), StatesArg::variables)
}
