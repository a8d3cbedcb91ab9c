//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use neuromesh::internals::build::tubes::{self, Tubes};
use neuromesh::internals::build::{FIRST_REACH, plan};
use neuromesh::internals::measure::check::self_intersections;
use neuromesh::internals::skeleton;
use neuromesh::{Mesh, Morphology, Params};

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

/// Stages 1 to 3 of `m` at the default parameters: its tubes.
pub fn build_tubes(m: &Morphology) -> Tubes {
    let params = Params::default();
    let skeleton = skeleton::prepare(m, &params, FIRST_REACH.sweep_cap).expect("skeleton");
    let starts = plan::plan(&skeleton, &params);
    tubes::build(&skeleton, &starts, &params)
}

/// The tube stage alone (before splicing): no piece of any branch crosses
/// itself. Returns the number of pieces.
pub fn assert_pieces_sound(m: &Morphology, what: &str) -> usize {
    let stage = build_tubes(m);
    let s = &stage.surface;
    // Each piece as a mesh of its own vertices only: a copy of the whole
    // cell's vertices per piece made this test quadratic in the cell's size.
    let mut local = vec![u32::MAX; s.pos.len()];
    for (i, t) in stage.tubes.iter().enumerate() {
        let mut used: Vec<u32> = Vec::new();
        let mut faces: Vec<[u32; 3]> = Vec::new();
        for f in t.tris.start..t.tris.end {
            if !s.alive[f as usize] {
                continue;
            }
            faces.push(s.tris[f as usize].map(|k| {
                if local[k as usize] == u32::MAX {
                    local[k as usize] = used.len() as u32;
                    used.push(k);
                }
                local[k as usize]
            }));
        }
        assert!(!faces.is_empty(), "{what}: piece {i} has no triangles");
        let vertices: Vec<[f32; 3]> = used
            .iter()
            .map(|&k| s.pos[k as usize].as_vec3().to_array())
            .collect();
        for &k in &used {
            local[k as usize] = u32::MAX;
        }
        let piece = Mesh::new(vertices, faces).expect("valid piece");
        let pairs = self_intersections(&piece.view());
        assert!(
            pairs.is_empty(),
            "{what}: piece {i} of branch {} crosses itself in {} pairs, e.g. {:?}",
            t.branch,
            pairs.len(),
            &pairs[..pairs.len().min(5)]
        );
    }
    stage.tubes.len()
}
