//! `bondgraph`: bond-graph models in RON to symbolic state equations.
//!
//! This binary only parses arguments ([`args`]), calls the libraries and writes their results
//! in the requested format (the documents are `bondgraph-view`'s); diagnostics from the
//! libraries are rendered here with a snippet of the model file, and any failure exits
//! non-zero.

mod args;
mod run;

use std::io::Write;
use std::process::ExitCode;

use bondgraph_core::DiagnosticKind;
use bondgraph_view::{
    Failure, analyze, calibrate, check, compare, derive, diagnostics, discover, explain_bg, graph,
    load, output, parse_mode, print,
};
use clap::Parser;

use args::{Cli, Command, Format, GraphArg, ModesFormat, ReproduceFormat, StatesArg};

/// Fits evaluate thousands of steady states, each a handful of short-lived vectors: a
/// thread-caching allocator takes a fifth off their time.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
    match dispatch(cli).and_then(|()| {
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

fn dispatch(cli: Cli) -> Result<(), Failure> {
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
            collapse,
        } => {
            let (model, source) = load(&model)?;
            let mode = parse_mode(&model, mode.as_deref(), &source)?;
            print(&drawing(&model, &mode, &source, format, collapse)?);
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
        } => run::simulate(
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
            explain_bg::run(&model, &mode, &source, format.into())
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
        Command::Reproduce { out, format } => run::reproduce(&out, format == ReproduceFormat::Json),
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
        } => run::discover(&discover::Args {
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
        } => run::extend(&model, &extensions, out.as_deref()),
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

/// `bondgraph graph`: the drawing in `format`, each sub-model collapsed to a box if asked
/// (DOT only).
fn drawing(
    model: &bondgraph_core::model::Model,
    mode: &bondgraph_core::modes::Mode,
    source: &std::sync::Arc<bondgraph_core::source::SourceFile>,
    format: GraphArg,
    collapse: bool,
) -> Result<String, Failure> {
    match (collapse, format) {
        (false, _) => graph::render(model, mode, source, format.into()),
        (true, GraphArg::Dot) => graph::render_collapsed(model, mode, source),
        (true, _) => Err(Failure::message(
            DiagnosticKind::Submodel,
            "--collapse draws with --format dot",
        )),
    }
}
