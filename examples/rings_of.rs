//! The rings each tube piece of one branch keeps (developer tool):
//! `rings_of FILE.swc BRANCH`. A built stage keeps a piece's first
//! `tube::KEPT_RINGS` rings, so a longer piece shows only those.
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let m = neuromesh::Morphology::from_swc(&a[1]).expect("swc");
    let b: u32 = a[2].parse().expect("branch");
    let (_, _, tubes, _) =
        neuromesh::pipeline::build(&m, &neuromesh::Params::default()).expect("build");
    for t in tubes.iter().filter(|t| t.branch == b) {
        let r: Vec<u32> = t.rings.iter().map(|r| r.resampled).collect();
        println!("piece: {r:?}");
    }
}
