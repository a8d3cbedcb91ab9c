//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The repository's copy of the real SWC corpus.
pub fn real_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/real")
}

/// Every real SWC file, sorted by name. Set `NEUROMESH_SWC_DIR` to run the same
/// tests over another folder (for example a holdout set).
pub fn real_files() -> Vec<PathBuf> {
    let dir = std::env::var_os("NEUROMESH_SWC_DIR").map_or_else(real_dir, PathBuf::from);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("swc")))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no SWC files in {}", dir.display());
    files
}

/// One row of MANIFEST.tsv.
pub struct ManifestRow {
    pub file: String,
    pub n_points: usize,
    pub soma_kind: String,
    pub max_children: usize,
    pub notes: String,
}

/// The manifest of the real corpus.
pub fn manifest() -> Vec<ManifestRow> {
    let text = std::fs::read_to_string(real_dir().join("MANIFEST.tsv")).expect("MANIFEST.tsv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split('\t').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let (f, n, s, c, notes) = (
        col("file"),
        col("n_points"),
        col("soma_kind"),
        col("max_children"),
        col("notes"),
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: Vec<&str> = l.split('\t').collect();
            ManifestRow {
                file: cells[f].to_owned(),
                n_points: cells[n].parse().expect("n_points"),
                soma_kind: cells[s].to_owned(),
                max_children: cells[c].parse().expect("max_children"),
                notes: cells[notes].to_owned(),
            }
        })
        .collect()
}
