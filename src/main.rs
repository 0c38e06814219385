//! The `fringe` command line: `check` (the CI correctness gate).

use clap::{Parser, Subcommand, ValueEnum};
use fringe::harness::check::{self, CheckOptions, Format};
use std::path::PathBuf;
use std::process::ExitCode;

/// The first failed write to stdout other than a closed pipe (a full disk, an I/O error): the
/// command then exits non-zero instead of leaving a truncated output behind an exit 0.
static STDOUT_FAILURE: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// Write to stdout; a closed stdout (e.g. `fringe check | head`) stays quiet, any other failure
/// is remembered for the exit code (see [`finish_stdout`]).
fn emit(args: std::fmt::Arguments) {
    use std::io::Write as _;
    if let Err(e) = std::io::stdout().lock().write_fmt(args) {
        note_stdout_error(e);
    }
}

fn note_stdout_error(e: std::io::Error) {
    if e.kind() != std::io::ErrorKind::BrokenPipe
        && let Ok(mut f) = STDOUT_FAILURE.lock()
    {
        f.get_or_insert_with(|| e.to_string());
    }
}

/// Flush stdout and turn a failed write into exit code 2 (with one `error:` line), unless the
/// command already failed.
fn finish_stdout(code: ExitCode) -> ExitCode {
    use std::io::Write as _;
    if let Err(e) = std::io::stdout().lock().flush() {
        note_stdout_error(e);
    }
    match STDOUT_FAILURE.lock().ok().and_then(|f| f.clone()) {
        Some(e) if code == ExitCode::SUCCESS => {
            eprintln!("error: stdout: cannot write: {e}");
            ExitCode::from(2)
        }
        _ => code,
    }
}

/// `print!` to stdout through [`emit`].
macro_rules! out {
    ($($arg:tt)*) => {{
        emit(format_args!($($arg)*));
    }};
}

/// `println!` to stdout through [`emit`].
macro_rules! outln {
    ($($arg:tt)*) => {{
        emit(format_args!("{}\n", format_args!($($arg)*)));
    }};
}

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

#[derive(Clone, Copy, ValueEnum)]
enum IlluminantArg {
    D65,
    E,
}

impl IlluminantArg {
    fn get(self) -> fringe::colour::Illuminant {
        match self {
            IlluminantArg::D65 => fringe::colour::Illuminant::D65,
            IlluminantArg::E => fringe::colour::Illuminant::E,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Run cases against their closed forms and golden files; exit 0 if all pass, 1 if a case
    /// fails, 2 on bad input. The verdict table goes to stdout, diagnostics to stderr.
    Check {
        /// Case names from the library (`fringe list`) or paths to case files; none: the whole
        /// library.
        cases: Vec<String>,
        /// Output folder of the reports (profile.csv per case, summary.json, index.html).
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
        /// Format of the verdict table on stdout.
        #[arg(long, value_enum, default_value = "table")]
        format: FormatArg,
        /// Rewrite the golden files from this run (the only way golden files change; only a
        /// passing run is written). A library case's golden file is <root>/golden/<case>.csv;
        /// a case file elsewhere gets golden/<case>.csv in its own folder.
        #[arg(long)]
        bless: bool,
        /// The case library folder [default: $FRINGE_ROOT/cases, else the cases/ of the
        /// checkout the binary was built from].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
        /// The golden folder of every case given [default: see --bless].
        #[arg(long)]
        golden_dir: Option<PathBuf>,
    },
    /// The case library: one line per case with its description (stdout).
    List {
        /// The case library folder [default: as for `check`].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
    },
    /// The JSON Schema of case files (draft 2020-12), generated from the case types: the text of
    /// cases/schema.json, on stdout.
    Schema,
    /// Render a case's picture (grid probe; a line probe becomes a strip): every pixel traced
    /// exactly, monochrome in the case's light or colour in white light (--samples).
    Render {
        /// A case name (the library or the figure scenes in figures/) or a path to a case file.
        case: String,
        /// Fidelity level(s), comma-separated: incoherent, scalar, scalar_jump, paper_rules,
        /// vector, or unpolarized_scalar_jump (the paper's Fig. 7 left model).
        #[arg(long, value_delimiter = ',', default_value = "vector")]
        fidelity: Vec<String>,
        /// White light with K wavelengths uniform over 380-780 nm (a colour picture), K ≥ 2.
        #[arg(long, conflicts_with = "wavelengths_nm")]
        samples: Option<usize>,
        /// White light at these wavelengths (nm, comma-separated, increasing).
        #[arg(long, value_delimiter = ',')]
        wavelengths_nm: Option<Vec<f64>>,
        /// Illuminant of white light: d65 (CIE daylight) or e (equal energy).
        #[arg(long, value_enum, default_value = "d65")]
        illuminant: IlluminantArg,
        /// Picture size WxH in pixels (default: the probe's pixels).
        #[arg(long)]
        size: Option<String>,
        /// Output picture, a .png file (default reports/render/<case>.png); several levels
        /// add _<level> before the extension.
        #[arg(short = 'o', long, alias = "output")]
        out: Option<PathBuf>,
        /// The case library folder [default: as for `check`].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
    },
    /// The paper's figures (Figs. 3, 5-8), Newton's colours and the colour error vs spectral
    /// samples into OUT/figures/, then OUT/index.html. Statistics go to stderr.
    Figures {
        /// Output folder (figures in OUT/figures/, the report OUT/index.html).
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
        /// Picture size WxH of the figures (the paper's is 900x900).
        #[arg(long, default_value = "240x240")]
        size: String,
        /// White-light wavelength samples of Figs. 5-8.
        #[arg(long, default_value_t = 31)]
        samples: usize,
        /// Illuminant of white light: d65 (CIE daylight) or e (equal energy).
        #[arg(long, value_enum, default_value = "d65")]
        illuminant: IlluminantArg,
    },
    /// The cost–accuracy trade: every fidelity level × bounce budget × spectral sample count
    /// per case, against the case's reference; writes OUT/tradeoff/tradeoff.csv and prints one
    /// verdict line per case. Settings are ranked by a deterministic cost count (path events,
    /// then the simpler level); a setting that cannot be traced is a row with its reason.
    Tradeoff {
        /// Case names or files (none: the whole library).
        cases: Vec<String>,
        /// Output folder (OUT/tradeoff/ and the report OUT/index.html).
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
        /// Timed runs per setting (min, median and max reported; timings do not rank).
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// The case library folder [default: as for `check`].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
    },
    /// Random valid scenes of every family with a closed form, each checked at `vector`
    /// against its primary reference; failures are shrunk into case files in --out. Exit 0
    /// if no scene fails, 1 if one does, 2 on a usage error.
    Fuzz {
        /// Families (comma-separated): young_exact, lloyd, two_beam_plate, airy, wedge,
        /// rhomb_retardance, plane_wave_beams, michelson, incoherent_sum, coherence_gaussian.
        /// Default: all.
        #[arg(long, value_delimiter = ',')]
        family: Vec<String>,
        /// Scenes per family.
        #[arg(long, default_value_t = 100)]
        count: usize,
        /// Seed of the scene draws (the same seed draws the same scenes).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Skip scenes carrying any of these region tags (comma-separated), e.g. medium,rotated.
        #[arg(long, value_delimiter = ',')]
        skip: Vec<String>,
        /// Folder for the shrunk case file of each failure.
        #[arg(short = 'o', long, default_value = "reports/fuzz")]
        out: PathBuf,
    },
    /// Renderer mode: forward ray fans into pixels, each estimator against the exact result,
    /// over rays per pixel and pixel size; writes OUT/forward/forward.csv and forward.png.
    Forward {
        /// Output folder (OUT/forward/ and the report OUT/index.html).
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
        /// Seed of the ray fans.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Rays per source channel, comma-separated (each 1 to 1e8).
        #[arg(long, value_delimiter = ',', default_value = "10000,40000,160000")]
        rays: Vec<usize>,
        /// Pixels per screen side, comma-separated (each 1 to 4096).
        #[arg(long, value_delimiter = ',', default_value = "4,8,16,32")]
        pixels: Vec<usize>,
    },
    /// The thin-layer models renderers ship (pbrt/Mitsuba thin dielectric, Belcour-Barla, ...)
    /// against exact Airy over angle x thickness x wavelength; writes OUT/models/ and prints the
    /// error table.
    Models {
        /// Output folder (OUT/models/).
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
    },
    /// Conformance packs: per case, what another tracer needs to reproduce it (scene, probes,
    /// wavelengths, observables, conventions, expected values, tolerances) in OUT/<case>/.
    Export {
        /// Case names or files (none: the whole library).
        cases: Vec<String>,
        /// Output folder of the packs.
        #[arg(short = 'o', long)]
        out: PathBuf,
        /// The case library folder [default: as for `check`].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
    },
    /// Grade another tracer's values at a case's probes: verdict rows as `check`, the closest
    /// fidelity rung; exit 0 pass, 1 fail, 2 bad input.
    Grade {
        /// A case name (the library) or a path to a case file.
        case: String,
        /// The value file (quantity,coordinate,value; see values_exact.csv of `fringe export`).
        #[arg(long)]
        values: PathBuf,
        /// The rung whose tolerance judges the values.
        #[arg(long, default_value = "vector")]
        level: String,
        /// Output folder of the grade report.
        #[arg(short = 'o', long, default_value = "reports")]
        out: PathBuf,
        /// The case library folder [default: as for `check`].
        #[arg(long)]
        cases_dir: Option<PathBuf>,
        /// Format of the verdict table on stdout.
        #[arg(long, value_enum, default_value = "table")]
        format: FormatArg,
    },
}

/// The library folder: `--cases-dir`, else `<root>/cases` ([`check::library_root`]).
fn cases_dir_or_default(dir: Option<PathBuf>) -> PathBuf {
    dir.unwrap_or_else(|| check::library_root().join("cases"))
}

/// A progress bar over `len` steps on stderr, hidden when stderr is not a terminal.
fn progress_bar(len: usize, what: &str) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len as u64);
    let template =
        format!("{what} [{{bar:40}}] {{pos}}/{{len}} {{msg}}, {{elapsed}} elapsed, ~{{eta}} left");
    if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// `fringe list`: every library case with the first sentence of its description.
fn list_command(cases_dir: &std::path::Path) -> ExitCode {
    let names = check::library_names(cases_dir);
    if names.is_empty() {
        eprintln!(
            "error: {}: no case library here (no *.json case files); set {} or --cases-dir",
            cases_dir.display(),
            check::ROOT_VARIABLE
        );
        return ExitCode::from(2);
    }
    let width = names.iter().map(|n| n.len()).max().unwrap_or(0);
    for n in &names {
        let file = cases_dir.join(format!("{n}.json"));
        let description = std::fs::read_to_string(&file)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v.get("description")?.as_str().map(one_line))
            .unwrap_or_else(|| "(no description)".into());
        outln!("{n:width$}  {description}");
    }
    eprintln!("{} case(s) in {}", names.len(), cases_dir.display());
    ExitCode::SUCCESS
}

/// The first sentence of a description, on one line: up to the first ". " before a capital
/// letter that does not end an abbreviation ("Fig. 3", "eq. 5").
fn one_line(text: &str) -> String {
    let flat = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut from = 0;
    while let Some(k) = flat[from..].find(". ").map(|k| k + from) {
        let word = flat[..k].rsplit(' ').next().unwrap_or("");
        let abbreviation =
            ["Fig", "Figs", "Eq", "eq", "eqs", "e.g", "i.e", "cf", "Ref"].contains(&word);
        let capital = flat[k + 2..].starts_with(|c: char| c.is_uppercase());
        if capital && !abbreviation {
            return flat[..=k].to_string();
        }
        from = k + 2;
    }
    flat
}

fn main() -> ExitCode {
    let code = run_cli();
    finish_stdout(code)
}

fn run_cli() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match cli.command {
        Command::Export {
            cases,
            out,
            cases_dir,
        } => match fringe::harness::grade::export::export(
            &cases,
            &cases_dir_or_default(cases_dir),
            &out,
        ) {
            Ok(lines) => {
                for l in lines {
                    outln!("{l}");
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {}", e.0);
                ExitCode::from(2)
            }
        },
        Command::Grade {
            case,
            values,
            level,
            out,
            cases_dir,
            format,
        } => grade_command(
            case,
            values,
            &level,
            out,
            cases_dir_or_default(cases_dir),
            format,
        ),
        Command::List { cases_dir } => list_command(&cases_dir_or_default(cases_dir)),
        Command::Schema => {
            out!("{}", fringe::harness::case::schema::case_schema_text());
            ExitCode::SUCCESS
        }
        Command::Models { out } => match fringe::cli::models(&out) {
            Ok(table) => {
                out!("{table}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Command::Tradeoff {
            cases,
            out,
            repeats,
            cases_dir,
        } => {
            let cases_dir = cases_dir_or_default(cases_dir);
            let loaded = match check::resolve_cases(&cases, &cases_dir).and_then(|files| {
                files
                    .iter()
                    .map(|f| fringe::harness::case::load::load(f).map_err(check::InputError::from))
                    .collect::<Result<Vec<_>, _>>()
            }) {
                Ok(c) => c,
                Err(e) => {
                    eprintln!("error: {}", e.0);
                    return ExitCode::from(2);
                }
            };
            let mut all = Vec::new();
            let mut summaries = String::new();
            let bar = progress_bar(loaded.len(), "tradeoff");
            for case in &loaded {
                let name = &case.spec.name;
                bar.set_message(name.clone());
                let rows = fringe::harness::tradeoff::measure(case, repeats);
                bar.inc(1);
                let line = fringe::harness::tradeoff::summary(name, &rows);
                bar.suspend(|| outln!("{line}"));
                summaries.push_str(&line);
                summaries.push('\n');
                let path = out.join("tradeoff").join(format!("{name}_pareto.png"));
                let written = fringe::output::report::tradeoff_plot::pareto_png(name, &rows)
                    .and_then(|png| {
                        fringe::io::write_atomic(&path, &png).map_err(|e| e.to_string())
                    });
                if let Err(e) = written {
                    eprintln!("error: {}: {e}", path.display());
                    return ExitCode::from(2);
                }
                all.extend(rows);
            }
            bar.finish_and_clear();
            let path = out.join("tradeoff").join("tradeoff.csv");
            if let Err(e) =
                fringe::io::write_atomic(&path, fringe::harness::tradeoff::csv(&all).as_bytes())
            {
                eprintln!("error: {}: cannot write: {e}", path.display());
                return ExitCode::from(2);
            }
            let path = out.join("tradeoff").join("summary.txt");
            if let Err(e) = fringe::io::write_atomic(&path, summaries.as_bytes()) {
                eprintln!("error: {}: cannot write: {e}", path.display());
                return ExitCode::from(2);
            }
            // The report page shows the verdicts and the Pareto plots.
            if let Err(e) = fringe::output::report::html::write_index(&out) {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
            eprintln!(
                "tradeoff: tradeoff.csv, summary.txt and the Pareto plots in {}, report {}",
                out.join("tradeoff").display(),
                out.join("index.html").display()
            );
            ExitCode::SUCCESS
        }
        Command::Render {
            case,
            fidelity,
            samples,
            wavelengths_nm,
            illuminant,
            size,
            out,
            cases_dir,
        } => match render_command(
            &case,
            &fidelity,
            samples,
            wavelengths_nm,
            illuminant.get(),
            size.as_deref(),
            out,
            &cases_dir_or_default(cases_dir),
        ) {
            // What was written and how it was normalised: information, so stderr.
            Ok(lines) => {
                for l in lines {
                    eprintln!("{l}");
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        },
        Command::Figures {
            out,
            size,
            samples,
            illuminant,
        } => {
            let run = || -> Result<(), String> {
                let opts = fringe::output::figures::FigureOptions {
                    size: fringe::output::render::parse_size(&size)?,
                    samples,
                    illuminant: illuminant.get(),
                    progress: true,
                    ..fringe::output::figures::FigureOptions::check_default()
                };
                let m = fringe::output::figures::generate(&out, &opts)?;
                for e in &m.fig8 {
                    eprint!(
                        "{}",
                        fringe::output::figures::fig8_text(&e.left, &e.right, &e.stats)
                    );
                }
                for (what, secs) in &m.timings {
                    eprintln!("{what}: {secs:.2} s");
                }
                fringe::output::report::html::write_index(&out)?;
                eprintln!(
                    "figures in {}, report {}",
                    out.join("figures").display(),
                    out.join("index.html").display()
                );
                Ok(())
            };
            match run() {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Command::Fuzz {
            family,
            count,
            seed,
            skip,
            out,
        } => fuzz_command(&family, count, seed, skip, &out),
        Command::Forward {
            out,
            seed,
            rays,
            pixels,
        } => {
            if rays
                .iter()
                .chain(&pixels)
                .any(|&n| n == 0 || n > 100_000_000)
                || pixels.iter().any(|&p| p > 4096)
            {
                eprintln!("error: --rays must be 1..=1e8 and --pixels 1..=4096");
                return ExitCode::from(2);
            }
            let bar = progress_bar(
                fringe::harness::forward_study::steps(&rays, &pixels),
                "forward",
            );
            let rows =
                fringe::harness::forward_study::run_observed(seed, &rays, &pixels, || bar.inc(1));
            bar.finish_and_clear();
            let text = fringe::harness::forward_study::csv(&rows);
            let csv_path = out.join("forward").join("forward.csv");
            let path = out.join("forward").join("forward.csv");
            if let Err(e) = fringe::io::write_atomic(&path, text.as_bytes()) {
                eprintln!("error: {}: cannot write: {e}", path.display());
                return ExitCode::from(2);
            }
            let path = out.join("forward").join("forward.png");
            let written = fringe::output::report::tradeoff_plot::forward_png(&rows)
                .and_then(|png| fringe::io::write_atomic(&path, &png).map_err(|e| e.to_string()));
            if let Err(e) = written {
                eprintln!("error: {}: {e}", path.display());
                return ExitCode::from(2);
            }
            // The report page shows the study's plot and table.
            if let Err(e) = fringe::output::report::html::write_index(&out) {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
            eprintln!(
                "forward: {} rows in {}, plot {}, report {}",
                rows.len(),
                csv_path.display(),
                path.display(),
                out.join("index.html").display()
            );
            ExitCode::SUCCESS
        }
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
                cases_dir: cases_dir_or_default(cases_dir),
                golden_dir,
                out,
                format: match format {
                    FormatArg::Table => Format::Table,
                    FormatArg::Json => Format::Json,
                },
                bless,
            };
            match fringe::cli::check(&opts) {
                Err(e) => {
                    eprintln!("error: {}", e.0);
                    ExitCode::from(2)
                }
                Ok(outcome) => {
                    if outcome.bless_refused {
                        eprintln!(
                            "not blessed: golden files are written only for a passing run; none changed"
                        );
                    }
                    match opts.format {
                        Format::Table => out!("{}", fringe::output::report::table(&outcome.rows)),
                        Format::Json => outln!(
                            "{}",
                            serde_json::to_string_pretty(&outcome.rows).unwrap_or_default()
                        ),
                    }
                    if outcome.failed_cases.is_empty() {
                        eprintln!(
                            "all {} case(s) pass, and all {} stability checks; reports in {}",
                            outcome.results.len(),
                            outcome
                                .stability
                                .rows
                                .iter()
                                .filter(|r| r.pass.is_some())
                                .count(),
                            opts.out.display()
                        );
                        ExitCode::SUCCESS
                    } else {
                        print_failed_rows(&outcome.rows);
                        eprintln!("FAILED: {}", outcome.failed_cases.join(", "));
                        ExitCode::from(1)
                    }
                }
            }
        }
    }
}

/// The rows that failed their tolerance, one line each on stderr (`check` and `grade`).
fn print_failed_rows(rows: &[fringe::harness::verdict::Row]) {
    for r in rows.iter().filter(|r| r.pass == Some(false)) {
        eprintln!(
            "  {} {} {}: max|dev| {:e} > {:e}; {}",
            r.case,
            r.fidelity,
            r.metric,
            r.max_abs_dev,
            r.tolerance.unwrap_or(f64::NAN),
            r.note
        );
    }
}

/// `fringe grade`: judge a value file, print the verdict rows and the closest rungs.
fn grade_command(
    case: String,
    values: PathBuf,
    level: &str,
    out: PathBuf,
    cases_dir: PathBuf,
    format: FormatArg,
) -> ExitCode {
    use fringe::harness::grade::grading;
    let Some(level) = fringe::accumulate::fidelity::Fidelity::parse(level) else {
        eprintln!(
            "error: --level {level:?}: allowed: incoherent, scalar, scalar_jump, paper_rules, vector"
        );
        return ExitCode::from(2);
    };
    let opts = grading::GradeOptions {
        case,
        values,
        cases_dir,
        out,
        level,
    };
    match fringe::cli::grade(&opts) {
        Err(e) => {
            eprintln!("error: {}", e.0);
            ExitCode::from(2)
        }
        Ok(outcome) => {
            match format {
                FormatArg::Table => out!("{}", fringe::output::report::table(&outcome.rows)),
                FormatArg::Json => outln!(
                    "{}",
                    serde_json::to_string_pretty(&outcome.rows).unwrap_or_default()
                ),
            }
            for l in grading::closest_lines(&outcome) {
                eprintln!("{l}");
            }
            if outcome.failed {
                print_failed_rows(&outcome.rows);
                eprintln!("FAILED: {}", outcome.case);
                ExitCode::from(1)
            } else {
                ExitCode::SUCCESS
            }
        }
    }
}

/// `fringe render`: parse the arguments into a [`fringe::output::render::Command`] and run it.
#[allow(clippy::too_many_arguments)]
fn render_command(
    case: &str,
    fidelity: &[String],
    samples: Option<usize>,
    wavelengths_nm: Option<Vec<f64>>,
    illuminant: fringe::colour::Illuminant,
    size: Option<&str>,
    output: Option<PathBuf>,
    cases_dir: &std::path::Path,
) -> Result<Vec<String>, String> {
    // The picture is a PNG: any other extension is refused rather than mislabelled.
    if let Some(o) = &output {
        let png = o
            .extension()
            .and_then(|x| x.to_str())
            .is_some_and(|x| x.eq_ignore_ascii_case("png"));
        if !png {
            return Err(format!(
                "-o {}: the picture is written as PNG; allowed extension: .png",
                o.display()
            ));
        }
    }
    use fringe::colour::WavelengthGrid;
    let shadings = fidelity
        .iter()
        .map(|f| fringe::output::render::parse_shading(f))
        .collect::<Result<Vec<_>, _>>()?;
    // The options get the case file's caps (src/harness/case/load/mod.rs `limits`).
    use fringe::harness::case::load::limits::{MAX_SPECTRAL_SAMPLES, WAVELENGTH_NM};
    let white = match (samples, wavelengths_nm) {
        (Some(k), _) => {
            if !(2..=MAX_SPECTRAL_SAMPLES).contains(&k) {
                return Err(format!(
                    "--samples {k}: 2 to {MAX_SPECTRAL_SAMPLES} spectral samples"
                ));
            }
            Some((
                fringe::output::figures::visible_grid(k)
                    .map_err(|e| format!("--samples {k}: {e}"))?,
                illuminant,
            ))
        }
        (None, Some(list)) => {
            let (lo, hi) = WAVELENGTH_NM;
            if list.is_empty() || list.len() > MAX_SPECTRAL_SAMPLES {
                return Err(format!(
                    "--wavelengths-nm: 1 to {MAX_SPECTRAL_SAMPLES} wavelengths, got {}",
                    list.len()
                ));
            }
            if let Some(bad) = list
                .iter()
                .find(|nm| !(nm.is_finite() && **nm >= lo && **nm <= hi))
            {
                return Err(format!(
                    "--wavelengths-nm: a wavelength (nm) must be in [{lo}, {hi}], got {bad}"
                ));
            }
            if list.windows(2).any(|w| w[1] <= w[0]) {
                return Err("--wavelengths-nm: wavelengths must be strictly increasing".to_string());
            }
            Some((
                WavelengthGrid::from_list(list.iter().map(|nm| nm * 1e-9).collect())
                    .map_err(|e| format!("--wavelengths-nm: {e}"))?,
                illuminant,
            ))
        }
        (None, None) => None,
    };
    let cmd = fringe::output::render::Command {
        case: render_case(case, cases_dir)?,
        shadings,
        white,
        size: size.map(fringe::output::render::parse_size).transpose()?,
        output,
        progress: true,
    };
    fringe::output::render::run_command(&cmd)
}

/// `fringe fuzz`: check the options, run, print the report, write the shrunk failures.
fn fuzz_command(
    family: &[String],
    count: usize,
    seed: u64,
    skip: Vec<String>,
    out: &std::path::Path,
) -> ExitCode {
    use fringe::harness::fuzz::{self, Family};
    let families: Result<Vec<Family>, String> = if family.is_empty() {
        Ok(Family::ALL.to_vec())
    } else {
        family
            .iter()
            .map(|f| {
                Family::parse(f).ok_or_else(|| {
                    format!(
                        "--family: unknown family {f:?}; allowed: {}",
                        Family::ALL.map(|f| f.name()).join(", ")
                    )
                })
            })
            .collect()
    };
    let families = match families {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if count == 0 || count > 10_000_000 {
        eprintln!("error: --count: 1 to 10000000 scenes per family, got {count}");
        return ExitCode::from(2);
    }
    let opts = fuzz::FuzzOptions {
        families,
        count,
        seed,
        skip,
        ..fuzz::FuzzOptions::default()
    };
    let report = fuzz::run(&opts);
    if let Err(e) = report.write_failures(out) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    out!("{}", report.text(Some(out)));
    let total = report.total();
    if total.fail == 0 {
        eprintln!(
            "no failures in {} scene(s) (seed {seed}); {} refused ({:.2}%), {} skipped",
            total.run(),
            total.refused,
            100.0 * total.refusal_rate(),
            total.skipped
        );
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "FAILED: {} of {} scene(s) (seed {seed}); shrunk cases in {}",
            total.fail,
            total.run(),
            out.display()
        );
        ExitCode::from(1)
    }
}

/// The case file `fringe render NAME` draws: a path as given; a name from the library
/// `cases_dir`, else from the figure scenes `<root>/figures/`.
fn render_case(name: &str, cases_dir: &std::path::Path) -> Result<PathBuf, String> {
    let plain = !name.is_empty()
        && name
            .chars()
            .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_');
    if !plain {
        return fringe::output::render::resolve_case(name, cases_dir);
    }
    let figures = check::library_root().join("figures");
    for dir in [cases_dir, figures.as_path()] {
        let p = dir.join(format!("{name}.json"));
        if p.is_file() {
            return Ok(p);
        }
    }
    let known: Vec<String> = check::library_names(cases_dir)
        .into_iter()
        .chain(check::library_names(&figures))
        .collect();
    Err(format!(
        "{name}: no case of that name in {} or {}{}",
        cases_dir.display(),
        figures.display(),
        check::did_you_mean(name, known.iter().map(String::as_str))
    ))
}
