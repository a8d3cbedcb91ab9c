//! The track of the branch holding one SWC sample (developer tool):
//! `track_of FILE.swc ID`.
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let m = neuromesh::Morphology::from_swc(&a[1]).expect("swc");
    let id: i64 = a[2].parse().expect("id");
    let params = neuromesh::Params::default();
    let k = m.ids().iter().position(|&i| i == id).expect("id") as u32;
    let branches = neuromesh::skeleton::branch::identify(&m, params.angle_threshold);
    let geometry = neuromesh::skeleton::geometry::Geometry::new(&m, &params);
    let tracks = neuromesh::skeleton::tracks(
        &geometry,
        &branches,
        &params,
        neuromesh::skeleton::track::SWEEP_CAP,
    );
    for (bi, b) in branches.iter().enumerate() {
        if !b.samples[1..].contains(&k) {
            continue;
        }
        let ids: Vec<i64> = b.samples.iter().map(|&s| m.ids()[s as usize]).collect();
        println!("branch {bi} {:?}: ids {ids:?}", b.attachment);
        let t = &tracks[bi];
        for i in 0..t.samples.len() {
            let s = &t.samples[i];
            println!(
                "{i:3} {} src {:3} pos {:.2} r {:.3} poly {:.3} m {} tan {:.2}",
                if s.original { "*" } else { " " },
                ids[s.source as usize],
                s.pos,
                s.radius,
                t.radii[i],
                t.counts[i],
                s.tangent
            );
        }
    }
}
