//! Where a mesh misses (or adds) volume against the union of round cones
//! (developer tool). By default: samples points in each primitive (counted
//! once, by the lowest-index primitive holding them), tests them against the
//! mesh by ray parity, and prints the primitives with the most volume
//! missing. With `--extra`: samples each primitive's box grown by its radius
//! (counted once, by the lowest-index grown box), keeps the points inside the
//! mesh and outside every primitive, and prints the primitives with the most
//! such volume nearby (`EXTRA_POINTS=i` prints primitive i's points).
//! `GAPS_HIST=1` also sorts the primitives by the share of their own volume
//! the mesh misses, in tenths, with the union's volume each tenth loses.
//!
//! `cargo run --release --example volume_gaps -- FILE.swc [TOP] [--extra]`
use glam::DVec3;
use neuromesh::internals::kernel::bvh::{Aabb, Bvh};
use neuromesh::internals::kernel::round_cone::RoundCone;
use neuromesh::internals::mesh::Mesh;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let extra = args.iter().any(|a| a == "--extra");
    let mut rest = args.iter().filter(|a| *a != "--extra");
    let path = rest.next().expect("swc");
    let top: usize = rest.next().and_then(|s| s.parse().ok()).unwrap_or(15);
    let m = neuromesh::Morphology::from_swc(path).expect("swc");
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    let probe = Probe::new(&mesh);
    if extra {
        outside_the_union(&m, &mesh, &probe, top);
    } else {
        missing(&m, &mesh, &probe, top);
    }
}

/// The mesh's triangles, for inside tests by ray parity.
struct Probe {
    tris: Vec<[[f64; 3]; 3]>,
    bvh: Bvh,
}

impl Probe {
    fn new(mesh: &Mesh) -> Probe {
        let tris: Vec<[[f64; 3]; 3]> = mesh
            .faces
            .iter()
            .map(|f| f.map(|v| mesh.vertices[v as usize].map(f64::from)))
            .collect();
        let bvh = Bvh::new(tris.iter().map(|t| Aabb::of(t)).collect());
        Probe { tris, bvh }
    }

    fn inside(&self, p: DVec3) -> bool {
        let (o, dir) = (p.to_array(), [0.573_21, 0.611_17, 0.545_43]);
        let mut n = 0;
        self.bvh.for_each_on_ray(o, dir, f64::INFINITY, |i| {
            if neuromesh::internals::kernel::predicates::ray_triangle(o, dir, self.tris[i as usize])
                .is_some()
            {
                n += 1;
            }
        });
        n % 2 == 1
    }
}

/// Uniform numbers in [0, 1) from the crate's generator seeded with `seed`.
fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut rng = neuromesh::internals::kernel::rng::Rng::new(seed);
    move || rng.f64()
}

/// A uniform point in box `b`.
fn point_in(b: &Aabb, rnd: &mut impl FnMut() -> f64) -> DVec3 {
    DVec3::new(
        b.lo[0] + rnd() * (b.hi[0] - b.lo[0]),
        b.lo[1] + rnd() * (b.hi[1] - b.lo[1]),
        b.lo[2] + rnd() * (b.hi[2] - b.lo[2]),
    )
}

fn missing(m: &neuromesh::Morphology, mesh: &Mesh, probe: &Probe, top: usize) {
    let tris = &probe.tris;
    let cones = m.round_cones();
    let boxes: Vec<Aabb> = cones.iter().map(|c| aabb(c, 1.0)).collect();
    let cone_bvh = Bvh::new(boxes.clone());
    let mut rnd = uniform(0x1234_5678_9abc_def1);
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
    // The nodes at the ends of each primitive, in Morphology::round_cones' order.
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
            let p = point_in(b, &mut rnd);
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
            if !probe.inside(p) {
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
                            neuromesh::internals::kernel::predicates::closest_point_on_triangle(
                                p, t,
                            )
                            .distance(p)
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
    if std::env::var("GAPS_HIST").is_ok() {
        let mut h = [0.0f64; 10];
        let mut n = [0usize; 10];
        for &(lost, _, own) in &rows {
            if own > 0.0 {
                let b = ((lost / own * 10.0) as usize).min(9);
                h[b] += lost;
                n[b] += 1;
            }
        }
        for b in 0..10 {
            println!(
                "  cones missing {:3}-{:3} % of own: {:5} cones, {:6.2} % of union",
                b * 10,
                b * 10 + 10,
                n[b],
                100.0 * h[b] / total
            );
        }
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

fn outside_the_union(m: &neuromesh::Morphology, mesh: &Mesh, probe: &Probe, top: usize) {
    let cones = m.round_cones();
    let grown: Vec<Aabb> = cones.iter().map(|c| aabb(c, 2.0)).collect();
    let exact: Vec<Aabb> = cones.iter().map(|c| aabb(c, 1.0)).collect();
    let grown_bvh = Bvh::new(grown.clone());
    let exact_bvh = Bvh::new(exact);
    let mut rnd = uniform(0x2545_f491_4f6c_dd1d);
    let per = 2000;
    let mut rows: Vec<(f64, usize)> = Vec::new();
    let mut total = 0.0;
    for (i, b) in grown.iter().enumerate() {
        let box_volume: f64 = (0..3).map(|k| b.hi[k] - b.lo[k]).product();
        let mut extra = 0usize;
        for _ in 0..per {
            let p = point_in(b, &mut rnd);
            let q = Aabb::of(&[p.to_array()]);
            let mut lower = false;
            grown_bvh.for_each_overlap(&q, |j| lower |= (j as usize) < i);
            if lower {
                continue;
            }
            let mut in_union = false;
            exact_bvh.for_each_overlap(&q, |j| in_union |= cones[j as usize].sdf(p) < 0.0);
            if !in_union && probe.inside(p) {
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
