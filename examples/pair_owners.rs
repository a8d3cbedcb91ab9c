//! Which parts the construction intersections of a mesh are between (developer tool).
fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let params = neuromesh::Params::default();
    let mut stage = neuromesh::mesher::build_tubes(&m, &params).expect("tubes");
    neuromesh::mesher::build_somas(&mut stage);
    neuromesh::mesher::splice_all(&mut stage, &params);
    neuromesh::mesher::build_fillers(&mut stage, &params);
    let fp = stage.filler_parts;
    println!("tubes {}", stage.tubes.len());
    let (mut mesh, owner) = stage
        .surface
        .into_mesh_with(stage.stats.clone(), stage.owner.clone());
    let before = neuromesh::check::self_intersections(&mesh.view());
    let same: usize = before
        .iter()
        .filter(|p| owner[p[0] as usize] == owner[p[1] as usize])
        .count();
    println!(
        "before: {} pairs, {} within one part; filler parts from {fp}",
        before.len(),
        same
    );
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
    let after = neuromesh::check::self_intersections(&mesh.view());
    println!("after: {} pairs", after.len());
    for p in after.iter().take(8) {
        println!(
            "  parts {} {} faces {:?}",
            r.owner[p[0] as usize], r.owner[p[1] as usize], p
        );
    }
}
