//! Prints the geometry of two mesh faces and the predicates on them (developer tool).
fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("swc");
    let fa: usize = args.next().unwrap().parse().unwrap();
    let fb: usize = args.next().unwrap().parse().unwrap();
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    let o = mesh.center();
    let tri = |f: usize| -> [[f64; 3]; 3] {
        mesh.faces[f].map(|k| {
            let v = mesh.vertices[k as usize];
            [
                f64::from(v[0]) - o[0],
                f64::from(v[1]) - o[1],
                f64::from(v[2]) - o[2],
            ]
        })
    };
    let (a, b) = (tri(fa), tri(fb));
    println!(
        "A {:?} {:?}\nB {:?} {:?}",
        mesh.faces[fa], a, mesh.faces[fb], b
    );
    println!("plain {}", neuromesh::geom::triangles_intersect(a, b));
    let (ia, ib) = (0..9)
        .map(|k| (k / 3, k % 3))
        .find(|&(i, j)| mesh.faces[fa][i] == mesh.faces[fb][j])
        .unwrap_or((0, 0));
    let ra = [a[ia], a[(ia + 1) % 3], a[(ia + 2) % 3]];
    let rb = [b[ib], b[(ib + 1) % 3], b[(ib + 2) % 3]];
    println!(
        "sharing vertex {}",
        neuromesh::geom::triangles_intersect_sharing_vertex(ra, rb)
    );
    for i in 0..3 {
        println!(
            "orient B[{i}] vs A: {:e}",
            neuromesh::geom::orient3d(a[0], a[1], a[2], b[i])
        );
    }
}
#[allow(dead_code)]
fn unused() {}
