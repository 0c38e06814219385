//! The `fringe` command line: `check` (the CI correctness gate).

use clap::{Parser, Subcommand, ValueEnum};
use fringe::check::{self, CheckOptions, Format};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "fringe",
    version,
    about = "Exact polarized ray tracing and a verification harness for light interference"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    Table,
    Json,
}

#[derive(Subcommand)]
enum Command {
    /// Run cases against their closed forms and golden files; exit 0 if all pass, 1 if a case
    /// fails, 2 on bad input.
    Check {
        /// Case names from the library (cases/) or paths to case files; none: the whole library.
        cases: Vec<String>,
        /// Output folder for profile.csv files and summary.json.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        #[arg(long, value_enum, default_value = "table")]
        format: FormatArg,
        /// Rewrite golden/<case>.csv from this run (the only way golden files change).
        #[arg(long)]
        bless: bool,
        /// The case library folder.
        #[arg(long, default_value = "cases")]
        cases_dir: PathBuf,
        /// The golden folder.
        #[arg(long, default_value = "golden")]
        golden_dir: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match cli.command {
        Command::Check {
            cases,
            out,
            format,
            bless,
            cases_dir,
            golden_dir,
        } => {
            let opts = CheckOptions {
                cases,
                cases_dir,
                golden_dir,
                out,
                format: match format {
                    FormatArg::Table => Format::Table,
                    FormatArg::Json => Format::Json,
                },
                bless,
            };
            match check::check(&opts) {
                Err(e) => {
                    eprintln!("error: {}", e.0);
                    ExitCode::from(2)
                }
                Ok(outcome) => {
                    match opts.format {
                        Format::Table => print!("{}", fringe::report::table(&outcome.rows)),
                        Format::Json => println!(
                            "{}",
                            serde_json::to_string_pretty(&outcome.rows).unwrap_or_default()
                        ),
                    }
                    if outcome.failed_cases.is_empty() {
                        eprintln!(
                            "all {} case(s) pass; reports in {}",
                            outcome.results.len(),
                            opts.out.display()
                        );
                        ExitCode::SUCCESS
                    } else {
                        eprintln!("FAILED: {}", outcome.failed_cases.join(", "));
                        ExitCode::from(1)
                    }
                }
            }
        }
    }
}
