//! Lists the samples a mesh leaves outside, with what they are (developer
//! tool): `cargo run --release --example outside_samples -- FILE.swc`.
use neuromesh::internals::measure::fidelity::fidelity;

fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    let f = fidelity(&mesh.view(), &m);
    // The distance from a point to the mesh's surface (nearest triangle).
    let tris: Vec<[glam::DVec3; 3]> = (0..mesh.face_count())
        .map(|k| mesh.faces[k].map(|v| glam::DVec3::from_array(mesh.position(v as usize))))
        .collect();
    let distance = |p: glam::DVec3| {
        tris.iter()
            .map(|t| {
                neuromesh::internals::kernel::predicates::closest_point_on_triangle(p, *t)
                    .distance(p)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (pos, r, parents) = (m.positions(), m.radii(), m.parents());
    for &s in &f.outside {
        let s = s as usize;
        let kids = m.children(s as u32).len();
        let p = parents[s];
        let seg = if p == neuromesh::NO_PARENT {
            0.0
        } else {
            let q = pos[p as usize];
            ((pos[s][0] - q[0]).powi(2) + (pos[s][1] - q[1]).powi(2) + (pos[s][2] - q[2]).powi(2))
                .sqrt()
        };
        let turn = if p != neuromesh::NO_PARENT && kids == 1 {
            let c = m.children(s as u32)[0] as usize;
            let q = pos[p as usize];
            let a = [pos[s][0] - q[0], pos[s][1] - q[1], pos[s][2] - q[2]];
            let b = [
                pos[c][0] - pos[s][0],
                pos[c][1] - pos[s][1],
                pos[c][2] - pos[s][2],
            ];
            let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            let na = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            let nb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
            (dot / (na * nb)).clamp(-1.0, 1.0).acos().to_degrees()
        } else {
            f64::NAN
        };
        let out = distance(glam::DVec3::from_array(pos[s]));
        println!(
            "sample {s} id {} r {:.3} out {:.3} ({:.2} r) children {kids} segment {:.3} ({:.1} r) turn {:.0}°",
            m.ids()[s],
            r[s],
            out,
            out / r[s],
            seg,
            seg / r[s],
            turn
        );
    }
    println!("{} of {} outside", f.samples_outside, f.samples);
}
