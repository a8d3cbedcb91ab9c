//! Which parts the construction intersections of a mesh are between (developer tool).
fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let params = neuromesh::Params::default();
    let mut stage = neuromesh::pipeline::build_tubes(&m, &params).expect("tubes");
    neuromesh::pipeline::build_somas(&mut stage);
    neuromesh::pipeline::splice_all(&mut stage, &params);
    neuromesh::pipeline::build_fillers(&mut stage, &params);
    let fp = stage.filler_parts;
    let filler_of_part = stage.filler_of_part.clone();
    let fillers = stage.fillers.clone();
    let straight: Vec<bool> = stage.filler_straight.iter().map(Option::is_some).collect();
    println!("tubes {}", stage.tubes.len());
    let (mut mesh, owner) = stage
        .surface
        .into_mesh_with(stage.stats.clone(), stage.owner.clone());
    let before = neuromesh::measure::check::self_intersections(&mesh.view());
    let same: usize = before
        .iter()
        .filter(|p| owner[p[0] as usize] == owner[p[1] as usize])
        .count();
    println!(
        "before: {} pairs, {} within one part; filler parts from {fp}",
        before.len(),
        same
    );
    // Pairs by kind: between two tube/soma parts, a filler and a tube, two fillers.
    let mut kinds = [0usize; 3];
    for p in &before {
        let n = p
            .iter()
            .filter(|&&f| owner[f as usize] >= fp && owner[f as usize] != u32::MAX)
            .count();
        kinds[n] += 1;
    }
    println!(
        "  tube-tube {}, filler-tube {}, filler-filler {}",
        kinds[0], kinds[1], kinds[2]
    );
    // Pairs per filler (counted once for each filler face in a pair).
    let mut per: std::collections::BTreeMap<u32, usize> = Default::default();
    for p in &before {
        for &f in p {
            let o = owner[f as usize];
            if o >= fp && o != u32::MAX {
                *per.entry(filler_of_part[(o - fp) as usize]).or_default() += 1;
            }
        }
    }
    // And the parts each filler crosses, with the pairs with each.
    let mut with: std::collections::BTreeMap<(u32, u32), usize> = Default::default();
    for p in &before {
        let (a, b) = (owner[p[0] as usize], owner[p[1] as usize]);
        for (f, o) in [(a, b), (b, a)] {
            if f >= fp && f != u32::MAX {
                *with
                    .entry((filler_of_part[(f - fp) as usize], o))
                    .or_default() += 1;
            }
        }
    }
    for (k, n) in &per {
        let (b, from, to) = fillers[*k as usize];
        let parts: Vec<String> = with
            .range((*k, 0)..(*k + 1, 0))
            .map(|((_, o), c)| {
                if *o >= fp && *o != u32::MAX {
                    format!("filler {}: {c}", filler_of_part[(*o - fp) as usize])
                } else {
                    format!("part {o}: {c}")
                }
            })
            .collect();
        println!(
            "  filler {k}: branch {b} track {from}..{to} {} pairs {n} ({})",
            if straight[*k as usize] {
                "straight"
            } else {
                "along"
            },
            parts.join(", ")
        );
    }
    for p in before
        .iter()
        .filter(|p| owner[p[0] as usize] == owner[p[1] as usize])
        .take(5)
    {
        let ids: Vec<i64> = mesh.faces[p[0] as usize]
            .iter()
            .chain(&mesh.faces[p[1] as usize])
            .map(|&v| m.ids()[mesh.vertex_sample[v as usize] as usize])
            .collect();
        println!(
            "  within part {} faces {:?} sample ids {ids:?}",
            owner[p[0] as usize], p
        );
    }
    let r = neuromesh::overlap::resolve_with_owner(&mut mesh, &owner);
    println!("{:?}", r.outcome);
    let after = neuromesh::measure::check::self_intersections(&mesh.view());
    println!("after: {} pairs", after.len());
    for p in after.iter().take(8) {
        println!(
            "  parts {} {} faces {:?}",
            r.owner[p[0] as usize], r.owner[p[1] as usize], p
        );
    }
}
