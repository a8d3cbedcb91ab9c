//! How far a mesh's surface lies from the union of round cones (developer
//! tool): each face's centroid's signed distance to the union (the least
//! round-cone `sdf`), in units of the nearest primitive's radius, as a
//! histogram of area, and the area-weighted mean distance.
//!
//! `OFFSETS_TOP=n` also prints the n samples whose round cones lie nearest
//! the most area more than half a radius out.
//!
//! `cargo run --release --example surface_offsets -- FILE.swc...`
use glam::DVec3;
use neuromesh::internals::kernel::bvh::{Aabb, Bvh};

/// Bucket edges, in radii of the nearest primitive.
const EDGES: [f64; 8] = [-0.5, -0.2, -0.1, -0.03, 0.03, 0.1, 0.2, 0.5];

fn main() {
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        let (cones, labels): (Vec<_>, Vec<u32>) = m.labelled_round_cones().unzip();
        let mut far_out = vec![0.0; cones.len()];
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
            let (mut best, mut radius, mut nearest) = (f64::INFINITY, 1.0, 0);
            bvh.for_each_overlap(&Aabb::of(&[c.to_array()]), |j| {
                let cone = &cones[j as usize];
                let s = cone.sdf(c);
                if s < best {
                    best = s;
                    radius = cone.ra.max(cone.rb);
                    nearest = j as usize;
                }
            });
            let a = mesh.view().face_area(f);
            let k = EDGES.iter().take_while(|&&e| best / radius > e).count();
            hist[k] += a;
            if k == EDGES.len() && best.is_finite() {
                far_out[nearest] += a;
            }
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
        // The samples whose cones lie nearest the area more than half a
        // radius out, most first.
        let top: usize = std::env::var("OFFSETS_TOP")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(0);
        let mut order: Vec<usize> = (0..cones.len()).filter(|&j| far_out[j] > 0.0).collect();
        order.sort_by(|&x, &y| far_out[y].total_cmp(&far_out[x]));
        for &j in order.iter().take(top) {
            let c = &cones[j];
            println!(
                "  {:6.3} % of the area more than 0.5 r out, nearest sample {} (r {:.3}..{:.3}, length {:.3})",
                100.0 * far_out[j] / total,
                m.ids()[labels[j] as usize],
                c.ra,
                c.rb,
                (c.b - c.a).length()
            );
        }
    }
}
