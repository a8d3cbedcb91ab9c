//! Where a mesh misses (or adds) volume against the union of round cones
//! (developer tool): samples points in each primitive (counted once, by the
//! lowest-index primitive holding them), tests them against the mesh by ray
//! parity, and prints the primitives with the most volume missing.
//!
//! `cargo run --release --example volume_gaps -- FILE.swc [TOP]`
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
    let boxes: Vec<Aabb> = cones.iter().map(aabb).collect();
    let cone_bvh = Bvh::new(boxes.clone());
    let mut seed = 0x1234_5678_9abc_def1u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    // Per primitive: (volume missing, volume in the mesh only nearby is not measured).
    let per = 400;
    let mut rows: Vec<(f64, usize, f64)> = Vec::new();
    let (mut total, mut missing) = (0.0, 0.0);
    let (parents, lines) = (m.parents(), m.lines());
    let pos = m.positions();
    // The line of the sample a primitive ends at (its child).
    let line_of = |i: usize| {
        let c = &cones[i];
        (0..m.len())
            .find(|&k| DVec3::from_array(pos[k]) == c.b && parents[k] != u32::MAX)
            .map(|k| lines[k])
    };
    // The nodes at the ends of each primitive, in skeleton_primitives' order.
    let soma = m.soma_mask();
    let mut ends: Vec<[usize; 2]> = Vec::new();
    for t in m.trees() {
        if let Some(s) = &t.soma {
            ends.push([s.samples[0] as usize; 2]);
        }
    }
    for i in 0..m.len() {
        let p = parents[i];
        if p == u32::MAX {
            if !soma[i] {
                ends.push([i, i]);
            }
        } else if !(soma[i] && soma[p as usize]) {
            ends.push([p as usize, i]);
        }
    }
    assert_eq!(ends.len(), cones.len());
    let class_of = |k: usize| {
        if soma[k] {
            0
        } else if parents[k] == u32::MAX {
            2
        } else if soma[parents[k] as usize] {
            1
        } else {
            match m.children(k as u32).len() {
                0 => 2,
                1 => 3,
                _ => 4,
            }
        }
    };
    let names = ["soma", "trunk start", "tip", "mid", "fork"];
    let mut by_class = [0.0f64; 5];
    let mut by_turn = [0.0f64; 6];
    for (i, c) in cones.iter().enumerate() {
        let b = &boxes[i];
        let mut missed: Vec<DVec3> = Vec::new();
        let box_volume: f64 = (0..3).map(|k| b.hi[k] - b.lo[k]).product();
        let (mut hit, mut owned, mut miss) = (0usize, 0usize, 0usize);
        let mut tries = 0;
        while hit < per && tries < per * 50 {
            tries += 1;
            let p = DVec3::new(
                b.lo[0] + rnd() * (b.hi[0] - b.lo[0]),
                b.lo[1] + rnd() * (b.hi[1] - b.lo[1]),
                b.lo[2] + rnd() * (b.hi[2] - b.lo[2]),
            );
            if c.sdf(p) > 0.0 {
                continue;
            }
            hit += 1;
            let mut lower = false;
            cone_bvh.for_each_overlap(&Aabb::of(&[p.to_array()]), |j| {
                if (j as usize) < i && cones[j as usize].sdf(p) < 0.0 {
                    lower = true;
                }
            });
            if lower {
                continue;
            }
            owned += 1;
            if !inside_mesh(p) {
                miss += 1;
                missed.push(p);
                let watched = std::env::var("GAPS_LINE")
                    .ok()
                    .and_then(|l| l.parse::<u32>().ok());
                if watched.is_some() && watched == line_of(i) {
                    let ab = c.b - c.a;
                    let t = (p - c.a).dot(ab) / ab.length_squared();
                    let radial = (p - c.a - t * ab).length();
                    let depth = tris
                        .iter()
                        .map(|t| {
                            let t = t.map(DVec3::from_array);
                            neuromesh::geom::closest_point_on_triangle(p, t).distance(p)
                        })
                        .fold(f64::INFINITY, f64::min);
                    println!("  miss t {t:+.3} radial {radial:.3} depth {depth:.3}");
                }
            }
        }
        let vol = box_volume * hit as f64 / tries as f64;
        let own = vol * owned as f64 / hit.max(1) as f64;
        let lost = vol * miss as f64 / hit.max(1) as f64;
        for &p in &missed {
            let mut best = (f64::INFINITY, 0usize);
            cone_bvh.for_each_overlap(&Aabb::of(&[p.to_array()]), |j| {
                for k in ends[j as usize] {
                    let d = p.distance(DVec3::from_array(pos[k])) - m.radii()[k];
                    if d < best.0 {
                        best = (d, k);
                    }
                }
            });
            by_class[class_of(best.1)] += vol / hit.max(1) as f64;
            let k = best.1;
            if class_of(k) == 3 {
                let c = m.children(k as u32)[0] as usize;
                let pp = parents[k] as usize;
                let (a, b, d) = (
                    DVec3::from_array(pos[pp]),
                    DVec3::from_array(pos[k]),
                    DVec3::from_array(pos[c]),
                );
                let turn = (b - a).angle_between(d - b).to_degrees();
                by_turn[((turn / 30.0) as usize).min(5)] += vol / hit.max(1) as f64;
            }
        }
        total += own;
        missing += lost;
        rows.push((lost, i, own));
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    println!(
        "union ~{total:.4e}, missing {missing:.4e} ({:.2} %), mesh {:.4e}",
        100.0 * missing / total,
        mesh.volume()
    );
    for (name, v) in names.iter().zip(by_class) {
        println!("  near {name:12} {:6.2} %", 100.0 * v / total);
    }
    for (b, v) in by_turn.iter().enumerate() {
        println!(
            "  mid, turn {:3}-{:3} deg {:6.2} %",
            b * 30,
            b * 30 + 30,
            100.0 * v / total
        );
    }
    for &(lost, i, own) in rows.iter().take(top) {
        let c = &cones[i];
        println!(
            "{:5.2} % of union  own {own:.3e}  ra {:.3} rb {:.3} len {:.3}  line {}",
            100.0 * lost / total,
            c.ra,
            c.rb,
            c.a.distance(c.b),
            line_of(i).unwrap_or(0),
        );
    }
}

fn aabb(c: &RoundCone) -> Aabb {
    let r = DVec3::splat(c.ra.max(c.rb));
    Aabb::of(&[(c.a.min(c.b) - r).to_array(), (c.a.max(c.b) + r).to_array()])
}
