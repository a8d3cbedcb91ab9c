//! Where a mesh holds volume outside the union of round cones (developer
//! tool): samples points in each primitive's box grown by its radius,
//! counted once (by the lowest-index grown box holding them), keeps those
//! inside the mesh and outside every primitive, and prints the primitives
//! with the most such volume nearby.
//!
//! `cargo run --release --example volume_extra -- FILE.swc [TOP]`
use glam::DVec3;
use neuromesh::bvh::{Aabb, Bvh};
use neuromesh::union::{RoundCone, skeleton_primitives};

fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let top: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(15);
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    let tris: Vec<[[f64; 3]; 3]> = mesh
        .faces
        .iter()
        .map(|f| f.map(|v| mesh.vertices[v as usize].map(f64::from)))
        .collect();
    let tri_bvh = Bvh::new(tris.iter().map(|t| Aabb::of(t)).collect());
    let dir = [0.573_21, 0.611_17, 0.545_43];
    let inside_mesh = |p: DVec3| {
        let o = p.to_array();
        let mut n = 0;
        tri_bvh.for_each_on_ray(o, dir, f64::INFINITY, |i| {
            if neuromesh::geom::ray_triangle(o, dir, tris[i as usize]).is_some() {
                n += 1;
            }
        });
        n % 2 == 1
    };
    let cones = skeleton_primitives(&m);
    let grown: Vec<Aabb> = cones.iter().map(|c| aabb(c, 2.0)).collect();
    let exact: Vec<Aabb> = cones.iter().map(|c| aabb(c, 1.0)).collect();
    let grown_bvh = Bvh::new(grown.clone());
    let exact_bvh = Bvh::new(exact);
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let per = 2000;
    let mut rows: Vec<(f64, usize)> = Vec::new();
    let mut total = 0.0;
    for (i, b) in grown.iter().enumerate() {
        let box_volume: f64 = (0..3).map(|k| b.hi[k] - b.lo[k]).product();
        let mut extra = 0usize;
        for _ in 0..per {
            let p = DVec3::new(
                b.lo[0] + rnd() * (b.hi[0] - b.lo[0]),
                b.lo[1] + rnd() * (b.hi[1] - b.lo[1]),
                b.lo[2] + rnd() * (b.hi[2] - b.lo[2]),
            );
            let q = Aabb::of(&[p.to_array()]);
            let mut lower = false;
            grown_bvh.for_each_overlap(&q, |j| lower |= (j as usize) < i);
            if lower {
                continue;
            }
            let mut in_union = false;
            exact_bvh.for_each_overlap(&q, |j| in_union |= cones[j as usize].sdf(p) < 0.0);
            if !in_union && inside_mesh(p) {
                extra += 1;
                if std::env::var("EXTRA_POINTS").is_ok_and(|v| v.parse() == Ok(i)) {
                    let mut near = (f64::INFINITY, 0usize);
                    for (j, c) in cones.iter().enumerate() {
                        let d = c.sdf(p);
                        if d < near.0 {
                            near = (d, j);
                        }
                    }
                    let c = &cones[near.1];
                    let u = (c.b - c.a).normalize_or_zero();
                    let x = (p - c.a).dot(u);
                    let y = (p - c.a - x * u).length();
                    println!(
                        "  extra at {p:.2} |p-a| {:.2} nearest {} (sdf {:.3}) axial {x:.2} radial {y:.2}",
                        p.distance(c.a),
                        near.1,
                        near.0
                    );
                }
            }
        }
        let v = box_volume * extra as f64 / per as f64;
        total += v;
        rows.push((v, i));
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    println!("mesh {:.4e}, outside the union ~{total:.4e}", mesh.volume());
    for &(v, i) in rows.iter().take(top) {
        let c = &cones[i];
        println!(
            "{v:.3e}  a {:.2} ra {:.3} b {:.2} rb {:.3} len {:.3}",
            c.a,
            c.ra,
            c.b,
            c.rb,
            c.a.distance(c.b)
        );
    }
}

fn aabb(c: &RoundCone, grow: f64) -> Aabb {
    let r = DVec3::splat(grow * c.ra.max(c.rb));
    Aabb::of(&[(c.a.min(c.b) - r).to_array(), (c.a.max(c.b) + r).to_array()])
}
