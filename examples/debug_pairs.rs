//! Lists intersecting face pairs and non-manifold vertices of one file's mesh (developer tool).
fn main() {
    let path = std::env::args().nth(1).expect("swc path");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    let view = mesh.view();
    let comp = neuromesh::kernel::disjoint_sets::face_components(view.faces, view.vertices.len());
    let pairs = neuromesh::measure::check::self_intersections(&view);
    let mut shown = 0;
    for p in pairs
        .iter()
        .filter(|p| comp[p[0] as usize] == comp[p[1] as usize])
    {
        let fa = mesh.faces[p[0] as usize];
        let fb = mesh.faces[p[1] as usize];
        let la: Vec<u32> = fa.iter().map(|&k| mesh.vertex_sample[k as usize]).collect();
        let lb: Vec<u32> = fb.iter().map(|&k| mesh.vertex_sample[k as usize]).collect();
        let depth = neuromesh::measure::check::tree_depths(&m);
        let sk = neuromesh::measure::check::is_skeleton_overlap(&view, &m, &depth, *p);
        if sk && std::env::var_os("SHOW_SKELETON").is_none() {
            continue;
        }
        println!(
            "skeleton={sk} pair {:?}: faces {:?} {:?} labels {:?} {:?} at {:?}",
            p, fa, fb, la, lb, mesh.vertices[fa[0] as usize]
        );
        shown += 1;
        if shown > 12 {
            break;
        }
    }
    // non-manifold vertices
    let mut star: std::collections::HashMap<u32, Vec<[u32; 3]>> = Default::default();
    for f in &mesh.faces {
        for &k in f {
            star.entry(k).or_default().push(*f);
        }
    }
    let mut count = 0;
    for (v, fs) in &star {
        let mut edges: Vec<(u32, u32)> = fs
            .iter()
            .map(|f| {
                let i = f.iter().position(|&k| k == *v).unwrap();
                (f[(i + 1) % 3], f[(i + 2) % 3])
            })
            .collect();
        // walk the fan
        let start = edges[0];
        let mut cur = start.1;
        let mut n = 1;
        edges.remove(0);
        while let Some(i) = edges.iter().position(|e| e.0 == cur) {
            cur = edges[i].1;
            edges.remove(i);
            n += 1;
        }
        if !edges.is_empty() && count < 5 {
            println!(
                "nonmanifold vertex {v} label {} at {:?}: fan {n} + {} left; faces {:?}",
                mesh.vertex_sample[*v as usize],
                mesh.vertices[*v as usize],
                edges.len(),
                fs
            );
            count += 1;
        }
    }
}
