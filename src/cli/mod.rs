//! The `neuromesh` command line: a thin translation of flags into library
//! calls, run by the `neuromesh` binary and by the `neuromesh` command that
//! `pip install` gives (`neuromesh_rs._cli`, through `_run_cli`).
//!
//! Exit codes: 0 on success, 1 with `error: FILE:LINE: reason` on stderr for bad
//! input or a failed write (for `batch`: when any file failed, after meshing all
//! the others), 2 for usage errors (clap), 3 when `check --strict` finds a
//! defect, 4 when `mesh` or `batch` wrote a mesh that is not sound (open,
//! non-manifold, or with crossings the overlap pass left; the file is kept
//! for inspection, and `--allow-unsound` makes it a success), 130 when a
//! signal stopped it (its unfinished outputs removed).

mod batch;
mod ledger;

use std::path::PathBuf;
use std::time::Instant;

use crate::{Error, Mesh, Morphology, Params, Summary, io};
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "neuromesh",
    version,
    about = "Closed, manifold triangle meshes of neurons from SWC skeletons",
    long_about = "Turns a neuron skeleton (SWC) into a closed, 2-manifold triangle mesh of its \
                  membrane, and checks meshes from any tool."
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Mesh one SWC file into OBJ, PLY or STL.
    Mesh {
        /// Input SWC file (.swc, or gzip-compressed .swc.gz; - reads standard input).
        input: PathBuf,
        /// Output mesh; the extension picks the format (- writes standard
        /// output, in the format --format names).
        #[arg(short, long)]
        output: PathBuf,
        /// Format for -o - (standard output).
        #[arg(long, value_parser = ["obj", "ply", "stl"])]
        format: Option<String>,
        /// Also check the mesh and print the report (on stderr with -o -).
        #[arg(long)]
        check: bool,
        /// Print nothing on success.
        #[arg(short, long)]
        quiet: bool,
        /// Exit with 0 even when the mesh is not sound (see the exit codes).
        #[arg(long)]
        allow_unsound: bool,
        /// Refuse a file whose parent links form cycles (by default each
        /// cycle is broken where it first appears in the file, and said).
        #[arg(long)]
        strict: bool,
        #[command(flatten)]
        params: Params,
    },
    /// Mesh many SWC files in parallel into a folder.
    ///
    /// Goes on past a bad file, checks every mesh it writes (closed,
    /// manifold, no crossings left by the overlap pass), shows a progress bar
    /// on a terminal, and ends with a summary; exits with 1 if any file
    /// failed, else 4 if any mesh is not sound.
    Batch {
        /// SWC files, folders (their *.swc and *.swc.gz files) or quoted
        /// patterns such as 'cells/*.swc'.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Output folder (created if missing); each mesh is named after its SWC file.
        #[arg(short, long)]
        output: PathBuf,
        /// Output format.
        #[arg(long, default_value = "ply", value_parser = ["obj", "ply", "stl"])]
        format: String,
        /// Files meshed at once (default: one per core).
        #[arg(short = 'j', long)]
        jobs: Option<usize>,
        /// No progress bar; errors and the summary only.
        #[arg(short, long)]
        quiet: bool,
        /// Count unsound meshes in the summary but exit with 0 for them.
        #[arg(long)]
        allow_unsound: bool,
        /// Refuse a file whose parent links form cycles (by default each
        /// cycle is broken where it first appears in the file, and said).
        #[arg(long)]
        strict: bool,
        /// Leave out inputs whose output exists (resumes a batch: outputs
        /// are renamed into place whole, so an existing one is complete).
        #[arg(long)]
        skip_existing: bool,
        /// Also write the outcome of every input to this CSV file (input,
        /// output, status, triangles, seconds, message), even when the batch
        /// is interrupted.
        #[arg(long, value_name = "FILE.csv")]
        summary: Option<PathBuf>,
        #[command(flatten)]
        params: Params,
    },
    /// Summarise an SWC file: samples, soma, branching.
    Info {
        /// Input SWC file (.swc, or gzip-compressed .swc.gz; - reads standard input).
        input: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Also measure the union of the round cones (area and volume a
        /// membrane mesh should match; slower).
        #[arg(long)]
        union: bool,
        /// Refuse a file whose parent links form cycles (by default each
        /// cycle is broken where it first appears in the file, and said).
        #[arg(long)]
        strict: bool,
    },
    /// Check any OBJ, PLY or STL mesh for defects.
    Check {
        /// Mesh file (.obj, .ply or .stl).
        mesh: PathBuf,
        /// SWC the mesh came from: splits skeleton overlaps apart.
        #[arg(long)]
        swc: Option<PathBuf>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Exit with code 3 when the mesh is not valid.
        #[arg(long)]
        strict: bool,
    },
}

/// Runs the command line `args` (the program's name first) and gives the
/// exit code. Usage errors, `--help` and `--version` print as clap prints
/// them and give their codes (2, 0) instead of ending the process, so a
/// Python interpreter can call this. With `handle_signals`, SIGINT, SIGTERM
/// and SIGHUP remove the unfinished outputs, print a batch's summary so far
/// and end the process with 130 (for a process that is only this command).
pub fn main<I, T>(args: I, handle_signals: bool) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return u8::try_from(e.exit_code()).unwrap_or(2);
        }
    };
    if handle_signals {
        // 130 is the shell's code for a process stopped so.
        let _ = ctrlc::set_handler(|| {
            ledger::interrupted();
            std::process::exit(130);
        });
    }
    match run(cli.cmd) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}

/// Says on stderr when the radii cannot be in the coordinates' units (the
/// output is made all the same).
fn warn_radii(input: &std::path::Path, m: &Morphology) {
    if let Some(why) = m.radius_warning() {
        eprintln!("warning: {}: {why}", input.display());
    }
}

/// The format of `output`: `--format` for `-` (standard output), else its
/// extension (which `--format`, if given, must agree with).
fn output_format(output: &std::path::Path, format: Option<&str>) -> Result<io::Format, Error> {
    let named = format.and_then(io::Format::from_extension);
    if output == std::path::Path::new("-") {
        return named.ok_or_else(|| Error::InvalidParam {
            name: "format",
            reason: "writing to standard output (-o -) needs --format obj, ply or stl".to_owned(),
        });
    }
    let by_extension = io::Format::from_path(output)?;
    match named {
        Some(f) if f != by_extension => Err(Error::InvalidParam {
            name: "format",
            reason: format!(
                "--format {} disagrees with the extension of {}",
                f.extension(),
                output.display()
            ),
        }),
        _ => Ok(by_extension),
    }
}

/// Triangles (before thinning) above which `mesh` says, before it starts,
/// how large the mesh will be.
const ANNOUNCED: f64 = 10e6;

/// Says on stderr, before meshing, when the mesh will be large, and what
/// would make it smaller.
fn announce_size(input: &std::path::Path, m: &Morphology, params: &Params) {
    let e = crate::estimate(m, params);
    if e.faces > ANNOUNCED {
        eprintln!(
            "note: {}: about {:.0} M triangles expected (before straight stretches are \
             thinned); --resolution below 1 or a smaller --min-vertices make fewer",
            input.display(),
            e.faces / 1e6
        );
    }
}

/// Says on stderr every change meshing makes to the file's geometry
/// ([`crate::repairs`]).
fn warn_repairs(input: &std::path::Path, m: &Morphology, params: &Params) {
    for change in crate::repairs(m, params) {
        eprintln!("warning: {}: {change}", input.display());
    }
}

fn run(cmd: Cmd) -> Result<u8, Error> {
    match cmd {
        Cmd::Mesh {
            input,
            output,
            format,
            check,
            quiet,
            allow_unsound,
            strict,
            params,
        } => {
            params.validate()?;
            let to_stdout = output == std::path::Path::new("-");
            let format = output_format(&output, format.as_deref())?;
            let start = Instant::now();
            let morphology = Morphology::from_swc(&input)?;
            if strict {
                morphology.refuse_cycles()?;
            }
            warn_radii(&input, &morphology);
            announce_size(&input, &morphology, &params);
            let mesh: Mesh = crate::mesh_morphology(&morphology, &params)?;
            warn_repairs(&input, &morphology, &params);
            let meshed = start.elapsed();
            if to_stdout {
                let mut w = std::io::BufWriter::new(std::io::stdout().lock());
                io::write_to(&mut w, &mesh, format)
                    .and_then(|()| std::io::Write::flush(&mut w))
                    .map_err(|e| Error::io(&output, e))?;
            } else {
                io::write_as(&output, &mesh, format)?;
            }
            if let Some(why) = io::precision_warning(&mesh, format) {
                eprintln!("warning: {}: {why}", output.display());
            }
            // With the mesh on standard output, what is said goes to stderr.
            let say = |text: String| {
                if to_stdout {
                    eprintln!("{text}");
                } else {
                    println!("{text}");
                }
            };
            if !quiet {
                say(format!(
                    "wrote {}: {} vertices, {} triangles ({:.1} ms meshing, {:.1} ms total)",
                    output.display(),
                    mesh.vertices.len(),
                    mesh.faces.len(),
                    meshed.as_secs_f64() * 1e3,
                    start.elapsed().as_secs_f64() * 1e3
                ));
            }
            let sound = if check {
                let scaled = morphology.scaled(params.scale)?;
                let report = mesh.check_with(&scaled);
                say(report.to_string());
                report.is_sound()
            } else {
                true
            };
            let defects = mesh.quick_defects();
            if sound && defects.is_empty() {
                return Ok(0);
            }
            eprintln!(
                "{}: {}: the mesh written is not sound ({}){}",
                if allow_unsound { "warning" } else { "error" },
                output.display(),
                if defects.is_empty() {
                    "self-intersections; see the check above".to_owned()
                } else {
                    defects.join(", ")
                },
                if allow_unsound {
                    ""
                } else {
                    "; kept for inspection, --allow-unsound exits 0"
                }
            );
            Ok(if allow_unsound { 0 } else { 4 })
        }
        Cmd::Batch {
            inputs,
            output,
            format,
            jobs,
            quiet,
            allow_unsound,
            strict,
            skip_existing,
            summary,
            params,
        } => batch::run(
            &inputs,
            &batch::Options {
                out_dir: &output,
                format: &format,
                jobs,
                quiet,
                allow_unsound,
                strict,
                skip_existing,
                summary,
            },
            &params,
        ),
        Cmd::Info {
            input,
            json,
            union,
            strict,
        } => {
            let m = Morphology::from_swc(&input)?;
            if strict {
                m.refuse_cycles()?;
            }
            warn_radii(&input, &m);
            let s = if union {
                Summary::with_union(&m)
            } else {
                Summary::of(&m)
            };
            if json {
                println!("{}", s.to_json());
            } else {
                println!("{s}");
            }
            Ok(0)
        }
        Cmd::Check {
            mesh,
            swc,
            json,
            strict,
        } => {
            let m = io::read(&mesh)?;
            let report = match swc {
                Some(path) => {
                    let morphology = Morphology::from_swc(&path)?;
                    if m.vertex_sample.len() != m.vertices.len() {
                        eprintln!(
                            "note: {} has no per-vertex sample labels (write PLY to keep them); \
                             self-intersections cannot be classified",
                            mesh.display()
                        );
                    }
                    m.check_with(&morphology)
                }
                None => m.check(),
            };
            if json {
                println!("{}", report.to_json());
            } else {
                println!("{report}");
            }
            if strict && !report.is_valid() {
                return Ok(3);
            }
            Ok(0)
        }
    }
}
