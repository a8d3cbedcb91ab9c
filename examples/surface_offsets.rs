//! How far a mesh's surface lies from the union of round cones (developer
//! tool): each face's centroid's signed distance to the union (the least
//! round-cone `sdf`), in units of the nearest primitive's radius, as a
//! histogram of area, and the area-weighted mean distance.
//!
//! `cargo run --release --example surface_offsets -- FILE.swc...`
use glam::DVec3;
use neuromesh::bvh::{Aabb, Bvh};
use neuromesh::union::skeleton_primitives;

/// Bucket edges, in radii of the nearest primitive.
const EDGES: [f64; 8] = [-0.5, -0.2, -0.1, -0.03, 0.03, 0.1, 0.2, 0.5];

fn main() {
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        let cones = skeleton_primitives(&m);
        let reach = cones.iter().map(|c| c.ra.max(c.rb)).fold(0.0, f64::max);
        // Each cone's box grown by the largest radius: enough to find the
        // nearest cone of a face within that distance of the union.
        let boxes: Vec<Aabb> = cones.iter().map(|c| c.aabb().inflated(reach)).collect();
        let bvh = Bvh::new(boxes);
        let mut hist = [0.0; EDGES.len() + 1];
        let (mut total, mut mean_abs) = (0.0, 0.0);
        for (f, face) in mesh.faces.iter().enumerate() {
            let c = face
                .iter()
                .map(|&v| DVec3::from_array(mesh.position(v as usize)))
                .sum::<DVec3>()
                / 3.0;
            let (mut best, mut radius) = (f64::INFINITY, 1.0);
            bvh.for_each_overlap(&Aabb::of(&[c.to_array()]), |j| {
                let cone = &cones[j as usize];
                let s = cone.sdf(c);
                if s < best {
                    best = s;
                    radius = cone.ra.max(cone.rb);
                }
            });
            let a = mesh.view().face_area(f);
            let k = EDGES.iter().take_while(|&&e| best / radius > e).count();
            hist[k] += a;
            total += a;
            if best.is_finite() {
                mean_abs += a * best.abs();
            }
        }
        println!(
            "{path}: area {total:.4e}, mean |distance| {:.4e}",
            mean_abs / total
        );
        let mut lo = "-inf".to_owned();
        for (k, a) in hist.iter().enumerate() {
            let hi = EDGES.get(k).map_or("inf".to_owned(), |e| format!("{e:+}"));
            println!(
                "  {lo:>5} .. {hi:>5} r: {:6.2} % of the area",
                100.0 * a / total
            );
            lo = hi;
        }
    }
}
