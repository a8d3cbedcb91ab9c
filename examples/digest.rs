//! Prints a digest of the mesh of each SWC file in a folder (vertices and faces,
//! bit for bit), to show that a change leaves the output identical (developer
//! tool): `cargo run --release --example digest -- [folder] > before.txt`.

use std::hash::{DefaultHasher, Hash, Hasher};

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "tests/data/real".to_owned());
    // The folder's *.swc files, sorted, as `neuromesh batch` takes them.
    let files = neuromesh::batch::expand_inputs(&[dir.into()]).expect("SWC files");
    for f in files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let m = match neuromesh::Morphology::from_swc(&f) {
            Ok(m) => m,
            Err(e) => {
                println!("{name} error: {e}");
                continue;
            }
        };
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        let mut h = DefaultHasher::new();
        for v in &mesh.vertices {
            v.map(f32::to_bits).hash(&mut h);
        }
        mesh.faces.hash(&mut h);
        println!("{name} {} {:016x}", mesh.faces.len(), h.finish());
    }
}
