//! What a batch did with each file, kept as it happens: the summary printed
//! at the end, or when a signal stops the batch, and the CSV written for
//! `--summary`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};
use std::time::Instant;

/// What became of one input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Meshed and written, sound.
    Meshed,
    /// Written, but not sound (`Mesh::quick_defects`).
    Unsound,
    /// Not written: an error.
    Failed,
    /// Not meshed: its output existed (`--skip-existing`).
    Skipped,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Meshed => "meshed",
            Status::Unsound => "unsound",
            Status::Failed => "failed",
            Status::Skipped => "skipped",
        }
    }
}

/// One input's line of the summary.
#[derive(Debug, Clone)]
pub struct Row {
    /// Its place among the inputs (the CSV keeps input order).
    pub index: usize,
    pub input: PathBuf,
    pub output: Option<PathBuf>,
    pub status: Status,
    pub triangles: usize,
    pub seconds: f64,
    /// The error, or why the mesh is not sound.
    pub message: String,
}

/// The batch under way.
pub struct Ledger {
    rows: Mutex<Vec<Row>>,
    total: usize,
    csv: Option<PathBuf>,
    output: String,
    threads: usize,
    start: Instant,
}

static LEDGER: OnceLock<Ledger> = OnceLock::new();

/// Starts the ledger of a batch of `total` inputs; `csv` is `--summary`'s file.
pub fn open(total: usize, csv: Option<PathBuf>, output: String, threads: usize) -> &'static Ledger {
    LEDGER.get_or_init(|| Ledger {
        rows: Mutex::new(Vec::with_capacity(total)),
        total,
        csv,
        output,
        threads,
        start: Instant::now(),
    })
}

/// What a signal does: removes the temporary files of the writes under way,
/// and, in a batch, prints and writes what was done so far. The caller exits.
pub fn interrupted() {
    let removed = crate::io::remove_unfinished();
    if let Some(ledger) = LEDGER.get() {
        eprintln!(
            "\ninterrupted: {removed} unfinished output{} removed",
            if removed == 1 { "" } else { "s" }
        );
        ledger.finish(true);
    }
}

impl Ledger {
    /// Records one input's outcome.
    pub fn record(&self, row: Row) {
        self.rows
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(row);
    }

    /// Prints the summary and writes the CSV; returns the counts of failed
    /// and unsound files.
    pub fn finish(&self, interrupted: bool) -> (usize, usize) {
        let mut rows = self
            .rows
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone();
        rows.sort_by_key(|r| r.index);
        let count = |s: Status| rows.iter().filter(|r| r.status == s).count();
        let (meshed, unsound, failed, skipped) = (
            count(Status::Meshed),
            count(Status::Unsound),
            count(Status::Failed),
            count(Status::Skipped),
        );
        let wall = self.start.elapsed().as_secs_f64();
        let triangles: usize = rows.iter().map(|r| r.triangles).sum();
        let busy = rows.iter().fold(0.0, |s, r| s + r.seconds);
        let mut out = std::io::stdout().lock();
        let not_done = if interrupted {
            format!(", {} not done: interrupted", self.total - rows.len())
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "files      {} ({} meshed, {failed} failed{}{}){not_done}",
            self.total,
            meshed + unsound,
            if skipped > 0 {
                format!(", {skipped} skipped")
            } else {
                String::new()
            },
            if unsound > 0 {
                format!(", {unsound} unsound")
            } else {
                String::new()
            },
        );
        let _ = writeln!(out, "output     {}", self.output);
        let _ = writeln!(
            out,
            "triangles  {triangles} ({:.2} M/s)",
            triangles as f64 / wall.max(1e-9) / 1e6
        );
        let _ = writeln!(
            out,
            "time       {wall:.2} s wall, {busy:.2} s summed over files, {} thread{}",
            self.threads,
            if self.threads == 1 { "" } else { "s" }
        );
        if unsound > 0 {
            let _ = writeln!(out, "unsound    {unsound} (written; reasons above)");
        }
        if failed > 0 {
            let _ = writeln!(out, "failed     {failed} (reasons above)");
        }
        if let Some(csv) = &self.csv {
            match write_csv(csv, &rows) {
                Ok(()) => {
                    let _ = writeln!(out, "summary    {}", csv.display());
                }
                Err(e) => eprintln!("error: {}: {e}", csv.display()),
            }
        }
        let _ = out.flush();
        (failed, unsound)
    }
}

/// The rows as CSV: input, output, status, triangles, seconds, message.
fn write_csv(path: &Path, rows: &[Row]) -> std::io::Result<()> {
    let mut text = String::from("input,output,status,triangles,seconds,message\n");
    for r in rows {
        let output = r
            .output
            .as_ref()
            .map_or_else(String::new, |p| p.display().to_string());
        text += &format!(
            "{},{},{},{},{:.3},{}\n",
            field(&r.input.display().to_string()),
            field(&output),
            r.status.name(),
            r.triangles,
            r.seconds,
            field(&r.message)
        );
    }
    std::fs::write(path, text)
}

/// A CSV field, quoted where it holds a comma, a quote or a line end.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}
