//! The long fuzz run, by hand: hostile variants of real files
//! (`input::mutate`) meshed by the `neuromesh` binary under a time limit and
//! a memory cap, until a time budget is spent.
//!
//! ```text
//! cargo build --profile ci --features cli
//! cargo run --profile ci --features internals --example fuzz -- \
//!     --neuromesh target/ci/neuromesh --minutes 30 [--seed 1] [--timeout 60] \
//!     [--memory-mb 6000] [--check] [--out fuzz-findings] tests/data/real/*.swc
//! ```
//!
//! Each run must end with exit 0 (a sound mesh) or 1 and a clear
//! `error: FILE:LINE: reason` (or `error: FILE: reason`). Anything else, a
//! timeout, a signal, exit 4 (an unsound mesh), an error that names no file,
//! is a finding: the mutant and its stderr are kept in the output folder.
//! The summary gives the runs and findings by mutation.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use neuromesh::internals::input::mutate::{KINDS, mutate};
use neuromesh::internals::kernel::rng::Rng;

struct Options {
    neuromesh: PathBuf,
    budget: Duration,
    seed: u64,
    timeout: u64,
    memory_mb: u64,
    check: bool,
    out: PathBuf,
    files: Vec<PathBuf>,
}

fn options() -> Options {
    let mut o = Options {
        neuromesh: PathBuf::from("target/ci/neuromesh"),
        budget: Duration::from_secs(600),
        seed: 1,
        timeout: 60,
        memory_mb: 6000,
        check: false,
        out: PathBuf::from("fuzz-findings"),
        files: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--neuromesh" => o.neuromesh = PathBuf::from(value()),
            "--minutes" => {
                o.budget = Duration::from_secs_f64(60.0 * value().parse::<f64>().expect("minutes"))
            }
            "--seed" => o.seed = value().parse().expect("seed"),
            "--timeout" => o.timeout = value().parse().expect("seconds"),
            "--memory-mb" => o.memory_mb = value().parse().expect("megabytes"),
            "--check" => o.check = true,
            "--out" => o.out = PathBuf::from(value()),
            _ => o.files.push(PathBuf::from(a)),
        }
    }
    assert!(!o.files.is_empty(), "give SWC files to mutate");
    o
}

/// What one run gave: `None` when it is as it must be, else why not.
fn run(o: &Options, input: &Path, output: &Path) -> (Option<String>, String) {
    let check = if o.check { " --check" } else { "" };
    let script = format!(
        "ulimit -v {}; exec timeout {} '{}' mesh '{}' -o '{}'{check}",
        o.memory_mb * 1024,
        o.timeout,
        o.neuromesh.display(),
        input.display(),
        output.display()
    );
    let result = Command::new("sh")
        .arg("-c")
        .arg(&script)
        .output()
        .expect("sh runs");
    let stderr = String::from_utf8_lossy(&result.stderr).into_owned();
    let name = input.display().to_string();
    let finding = match result.status.code() {
        Some(0) => None,
        Some(1) => {
            let last = stderr.lines().rev().find(|l| l.starts_with("error: "));
            match last {
                Some(l) if l.starts_with(&format!("error: {name}")) => None,
                _ => Some("exit 1 without an error naming the file".to_owned()),
            }
        }
        Some(124) => Some(format!("over {} s", o.timeout)),
        Some(4) => Some("unsound mesh (exit 4)".to_owned()),
        Some(c) => Some(format!("exit {c}")),
        None => Some("killed by a signal".to_owned()),
    };
    (finding, stderr)
}

fn main() {
    let o = options();
    std::fs::create_dir_all(&o.out).expect("output folder");
    let texts: Vec<(PathBuf, String)> = o
        .files
        .iter()
        .map(|f| {
            (
                f.clone(),
                String::from_utf8_lossy(&std::fs::read(f).expect("readable")).into_owned(),
            )
        })
        .collect();
    let mut rng = Rng::new(o.seed);
    let mutant = o.out.join("mutant.swc");
    let mesh = o.out.join("mutant.ply");
    let start = Instant::now();
    let mut runs: BTreeMap<&str, (usize, usize, f64)> = BTreeMap::new();
    let mut n = 0usize;
    while start.elapsed() < o.budget {
        let (file, text) = &texts[n % texts.len()];
        let kind = (n / texts.len()) % KINDS.len();
        n += 1;
        let Some(variant) = mutate(text, kind, &mut rng) else {
            continue;
        };
        std::fs::write(&mutant, &variant).expect("mutant written");
        let t = Instant::now();
        let (finding, stderr) = run(&o, &mutant, &mesh);
        let seconds = t.elapsed().as_secs_f64();
        let entry = runs.entry(KINDS[kind]).or_default();
        entry.0 += 1;
        entry.2 = entry.2.max(seconds);
        if let Some(why) = finding {
            entry.1 += 1;
            let stem = format!("{n:05}-{}", KINDS[kind].replace(' ', "-"));
            let kept = o.out.join(format!("{stem}.swc"));
            std::fs::copy(&mutant, &kept).expect("finding kept");
            std::fs::write(
                o.out.join(format!("{stem}.txt")),
                format!("{}\n{why}\n{stderr}", file.display()),
            )
            .expect("finding written");
            println!("finding: {} ({}): {why}", kept.display(), file.display());
        }
    }
    let _ = std::fs::remove_file(&mutant);
    let _ = std::fs::remove_file(&mesh);
    println!("| mutation | runs | findings | slowest (s) |");
    println!("| --- | ---: | ---: | ---: |");
    let (mut total, mut found) = (0, 0);
    for (kind, (r, f, s)) in &runs {
        println!("| {kind} | {r} | {f} | {s:.1} |");
        total += r;
        found += f;
    }
    println!(
        "{total} runs, {found} findings, {:.0} s",
        start.elapsed().as_secs_f64()
    );
}
