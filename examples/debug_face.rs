//! Explains where faces come from: tube, ring, band or cap (developer tool).
//! Usage: debug_face FILE.swc FACE [FACE...] (face indices of the built surface,
//! which equal the mesh's while no triangle has been removed).
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("swc");
    let faces: Vec<u32> = args.map(|a| a.parse().expect("face index")).collect();
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let (surface, branches, tubes, _) =
        neuromesh::pipeline::build(&m, &neuromesh::Params::default()).expect("build");
    for f in faces {
        for (ti, t) in tubes.iter().enumerate() {
            let where_ = if t.start_cap.contains(&f) {
                Some("start cap".to_owned())
            } else if t.end_cap.contains(&f) {
                Some("end cap".to_owned())
            } else {
                t.bands
                    .windows(2)
                    .position(|w| (w[0]..w[1]).contains(&f))
                    .map(|b| format!("band {b}"))
            };
            if let Some(w) = where_ {
                let b = &branches[t.branch as usize];
                println!(
                    "face {f}: tube {ti} (branch {}, {} samples, {:?}) {w}",
                    t.branch,
                    b.samples.len(),
                    b.attachment
                );
                if let Some(k) = w
                    .strip_prefix("band ")
                    .and_then(|k| k.parse::<usize>().ok())
                {
                    // A built stage keeps only the first `tube::KEPT_RINGS`.
                    let near = k.saturating_sub(1)..(k + 3).min(t.rings.len());
                    for r in t.rings.get(near).unwrap_or_default() {
                        println!(
                            "   ring first {} m {} c {:?} n {:?} r {:.4} label {} resampled {}",
                            r.first, r.m, r.center, r.normal, r.radius, r.label, r.resampled
                        );
                    }
                }
                println!("   tri {:?}", surface.tris[f as usize]);
            }
        }
    }
}
