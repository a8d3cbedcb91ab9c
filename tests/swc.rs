//! The SWC reader and morphology builder on the real corpus and on malformed input.

mod common;

use neuromesh::internals::input::swc::SwcFile;
use neuromesh::{Error, Morphology, SomaKind};

#[test]
fn every_real_file_reads_and_matches_its_manifest_row() {
    let rows = common::manifest();
    assert_eq!(rows.len(), 48);
    for row in rows {
        let path = common::real_dir().join(&row.file);
        let raw = SwcFile::read(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(raw.samples.len(), row.n_points, "{}", row.file);
        let m = Morphology::from_file(raw).unwrap_or_else(|e| panic!("{e}"));
        let kind = match m.soma_kind() {
            SomaKind::None => "none",
            SomaKind::SinglePoint => "single",
            SomaKind::ThreePoint => "3point",
            SomaKind::MultiPoint => "contour",
        };
        assert_eq!(kind, row.soma_kind, "{}", row.file);
        // Roots: the manifest notes say "N roots" when there are several.
        if let Some(n) = row.notes.split(';').find_map(|s| {
            s.trim()
                .strip_suffix(" roots")
                .and_then(|n| n.trim().parse::<usize>().ok())
        }) {
            // Roots at the very same place (fragments of one cell) are one.
            let copies = m.cleaning().copies_merged as usize;
            assert!(
                m.trees().len() <= n && m.trees().len() + copies >= n,
                "{}: {} trees, {n} roots, {copies} copies merged",
                row.file,
                m.trees().len()
            );
        }
        // Every radius is usable after cleaning, and every sample is in the order.
        assert!(
            m.radii().iter().all(|r| r.is_finite() && *r > 0.0),
            "{}",
            row.file
        );
        assert_eq!(m.order().len(), m.len(), "{}", row.file);
        // Re-rooted trees: the root of a tree with a soma is a soma sample.
        for t in m.trees() {
            if let Some(s) = &t.soma {
                assert!(s.samples.contains(&t.root), "{}", row.file);
                assert!(s.radius > 0.0, "{}", row.file);
            }
        }
        let max_children = (0..m.len() as u32)
            .map(|i| m.children(i).len())
            .max()
            .unwrap_or(0);
        assert!(
            max_children >= 1 || m.len() == m.trees().len(),
            "{}",
            row.file
        );
    }
}

#[test]
fn units_and_radius_quirks_are_cleaned() {
    let dir = common::real_dir();
    let m =
        Morphology::from_swc(dir.join("rat_neocortex_interneuron_C031097B-I4.CNG.swc")).unwrap();
    assert_eq!(m.cleaning().negative_radii, 815);
    let m = Morphology::from_swc(dir.join("retina_neuron_20161028_1.swc")).unwrap();
    assert_eq!(m.cleaning().zero_radii as usize, 7213);
    assert!(m.cleaning().radii_from_default > 7000);
    let m = Morphology::from_swc(dir.join("purkinje_p19_resaved_by_neutube.swc")).unwrap();
    assert!(m.cleaning().duplicates_merged >= 1000, "{:?}", m.cleaning());
    let m = Morphology::from_swc(dir.join("drosophila_DA1_PN_hemibrain_1734350788.swc")).unwrap();
    // The file's root is a type-0 node; the geometry tree is re-rooted at the soma.
    let soma = m.trees()[0].soma.as_ref().unwrap();
    assert_eq!(m.trees()[0].root, soma.samples[0]);
    assert_eq!(m.kinds()[m.trees()[0].root as usize], 1);
}

fn swc_error(text: &[u8]) -> (usize, String) {
    let r = SwcFile::parse(text, "bad.swc").and_then(Morphology::from_file);
    match r {
        Err(Error::Swc(e)) => {
            assert_eq!(e.path, "bad.swc");
            (e.line, e.reason)
        }
        other => panic!("expected an SWC error, got {other:?}"),
    }
}

#[test]
fn each_malformed_input_names_its_line() {
    let cases: [(&[u8], usize, &str); 7] = [
        (b"# h\n1 1 0 0 0 1 -1\n2 3 1 0\n", 3, "expected 7 fields"),
        (b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n", 2, "z is not a number"),
        (b"1 1 0 0 0 nan -1\n", 1, "radius must be finite"),
        (b"1 1 0 0 0 1 -1\n1 3 1 0 0 1 1\n", 2, "duplicate id 1"),
        (
            b"1 1 0 0 0 1 -1\n2 3 1 0 0 1 5\n",
            2,
            "parent id 5 does not exist",
        ),
        (b"", 1, "no samples"),
        (b"1 1 0 0 0 1 -1\n\x00\x01\x02binary", 2, "binary"),
    ];
    for (text, line, reason) in cases {
        let (l, r) = swc_error(text);
        assert_eq!(l, line, "{reason}: {r}");
        assert!(r.contains(reason), "expected `{reason}` in `{r}`");
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let e = Morphology::from_swc("does/not/exist.swc").unwrap_err();
    assert!(matches!(e, Error::Io { .. }));
    assert!(e.to_string().starts_with("does/not/exist.swc: "), "{e}");
}
