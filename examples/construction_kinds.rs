//! Counts a mesh's construction self-intersections (see
//! `check::is_skeleton_overlap`) by kind: between two components (a detached
//! junction's tube against the surface it overlaps) or inside one component
//! (developer tool). `cargo run --release --example construction_kinds -- FILE...`

fn main() {
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        let view = mesh.view();
        let comp = neuromesh::internals::kernel::disjoint_sets::face_components(
            view.faces,
            view.vertices.len(),
        );
        let depth = neuromesh::internals::measure::check::tree_depths(&m);
        let (mut across, mut within) = (0, 0);
        let mut samples: std::collections::BTreeMap<u32, u32> = Default::default();
        for p in neuromesh::internals::measure::check::self_intersections(&view) {
            if neuromesh::internals::measure::check::is_skeleton_overlap(&view, &m, &depth, p) {
                continue;
            }
            if comp[p[0] as usize] == comp[p[1] as usize] {
                within += 1;
                let s = mesh.vertex_sample[mesh.faces[p[0] as usize][0] as usize];
                *samples.entry(s).or_default() += 1;
            } else {
                across += 1;
            }
        }
        let mut worst: Vec<_> = samples.into_iter().collect();
        worst.sort_by_key(|&(_, n)| std::cmp::Reverse(n));
        worst.truncate(8);
        println!("{path}: {across} across components, {within} within; worst samples {worst:?}");
    }
}
