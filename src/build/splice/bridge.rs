//! Step 3 and 4 of a junction: the bridge from C_Q to C_1sec (C_loc and the
//! middle contours) and its proof, and the attempts tried in order.

use glam::DVec3;

use super::region::{boundary_loop, tri_normal};
use super::splicer::Splicer;
use crate::build::splice::index::tri_box;
use crate::build::surface::{Mark, Surface};
use crate::build::tube::{self, Ring, Tube};
use crate::kernel::bvh::Aabb;
use crate::mesh::NO_OWNER;
use crate::skeleton::frame::DiscFrame;

impl Splicer<'_> {
    /// One attempt: the bridge from ring `k` of `tube` with Q's footprint
    /// `rho_factor` times the ring's radius. Commits and returns true if valid.
    pub(super) fn try_bridge(
        &mut self,
        tube_id: u32,
        tube: &Tube,
        a: Attempt,
        toward: DVec3,
    ) -> bool {
        let k = a.ring;
        // Bands before ring k (the "moved" variants) leave with the attempt;
        // only those still alive are taken, so a failure restores exactly them.
        let dropped: Vec<u32> = if k > 0 {
            (tube.bands[0]..tube.bands[k])
                .filter(|&t| self.surface.alive[t as usize])
                .collect()
        } else {
            Vec::new()
        };
        for &t in &dropped {
            self.surface.alive[t as usize] = false;
        }
        let result = self.bridge(tube_id, tube, a, toward, &dropped);
        if let Err(why) = result {
            *self.failures.entry(why).or_insert(0) += 1;
        }
        let ok = result.is_ok();
        if !ok {
            for &t in &dropped {
                self.surface.alive[t as usize] = true;
            }
        }
        ok
    }

    /// The bridge of attempt `a` from ring `a.ring` of `tube` (steps 1 to 4
    /// of the module docs), committed if its proof holds.
    fn bridge(
        &mut self,
        tube_id: u32,
        tube: &Tube,
        a: Attempt,
        toward: DVec3,
        dropped: &[u32],
    ) -> Result<(), &'static str> {
        let c1 = tube.rings[a.ring];
        // An oblique secondary needs the tilted C_loc between it and the target.
        let min_cos = if a.tilted { 0.02 } else { 0.2 };
        let landing = self.land(tube_id, &c1, a.aim, toward, min_cos)?;
        let region = self.open_region(tube_id, &c1, &landing, a.footprint, min_cos)?;
        let contours = self.bridge_contours(&c1, &landing, &region, a.tilted)?;
        let (mark, first_tri) = self.lay_bridge(&c1, &landing, &region, &contours);
        let removed: Vec<u32> = region.q.iter().chain(dropped).copied().collect();
        if let Err(why) = self.bridge_is_clear(first_tri, &removed) {
            self.surface.rollback(mark);
            for &t in &region.q {
                self.surface.alive[t as usize] = true;
            }
            return Err(why);
        }
        self.adopt(first_tri, NO_OWNER);
        Ok(())
    }

    /// Step 1: where a ray from ring `c1` toward `aim` lands on a surface the
    /// tube may join.
    fn land(
        &mut self,
        tube_id: u32,
        c1: &Ring,
        aim: Aim,
        toward: DVec3,
        min_cos: f64,
    ) -> Result<Landing, &'static str> {
        let aim_point = match aim {
            Aim::BranchPoint => Some(toward),
            Aim::NearestSurface => self.nearest_surface_point(
                tube_id,
                toward,
                c1.radius,
                c1.center.distance(toward) + 4.0 * c1.radius,
            ),
            Aim::NearestToStart => self.nearest_surface_point(
                tube_id,
                c1.center,
                c1.radius,
                c1.center.distance(toward) + 4.0 * c1.radius,
            ),
            Aim::Backwards => None,
        };
        let (mut dir, len) = match aim_point {
            Some(p) => (p - c1.center, p.distance(c1.center)),
            None => (-c1.normal, toward.distance(c1.center)),
        };
        if aim_point.is_none() || len <= 1e-9 * c1.radius {
            dir = -c1.normal;
        } else {
            dir /= len;
        }
        let reach = len.max(c1.radius) * 2.0 + 4.0 * c1.radius;
        let (owner, settled) = (&self.owner, &self.settled);
        let Some((target, s)) = self.grid.raycast(self.surface, c1.center, dir, reach, |t| {
            let o = owner[t as usize];
            o != tube_id && (o == NO_OWNER || settled[o as usize])
        }) else {
            return Err("ray hits nothing");
        };
        if self.reserved[target as usize] {
            return Err("ray hits an open tube's first band");
        }
        let h = c1.center + dir * s;
        let n_t = tri_normal(self.surface, target);
        let axis = (c1.center - h).normalize_or_zero();
        if n_t.dot(c1.center - h) <= 0.0 || axis == DVec3::ZERO {
            return Err("target faces away");
        }
        if c1.normal.dot(n_t) < min_cos {
            return Err("secondary too oblique to the target");
        }
        Ok(Landing { target, h, axis })
    }

    /// Step 2: region Q around the landing, `footprint` times the ring's
    /// radius across, and the plane of the splice.
    fn open_region(
        &mut self,
        tube_id: u32,
        c1: &Ring,
        landing: &Landing,
        footprint: f64,
        min_cos: f64,
    ) -> Result<Region, &'static str> {
        let h = landing.h;
        let rho = c1.radius * footprint;
        let Some(q) = self.grow_region(tube_id, landing.target, h, landing.axis, rho) else {
            return Err("region Q could not be grown");
        };
        let Some(c_q) = boundary_loop(self.surface, &q) else {
            return Err("Q is not a disk");
        };
        // The plane of the splice: Q's mean normal, facing the secondary.
        let n_q = q
            .iter()
            .map(|&t| {
                let f = self.surface.tris[t as usize];
                let (a, b, c) = (
                    self.surface.pos[f[0] as usize],
                    self.surface.pos[f[1] as usize],
                    self.surface.pos[f[2] as usize],
                );
                (b - a).cross(c - a)
            })
            .sum::<DVec3>()
            .normalize_or_zero();
        if n_q.dot(c1.center - h) <= 0.0 || c1.normal.dot(n_q) < min_cos {
            return Err("Q faces away from the secondary");
        }
        let e1 = crate::kernel::vector::any_perpendicular(n_q);
        let e2 = n_q.cross(e1);
        let mut region = Region {
            q,
            c_q,
            n_q,
            e1,
            e2,
            rim: Vec::new(),
        };
        region.rim = region
            .c_q
            .iter()
            .map(|&v| region.flat(h, self.surface.pos[v as usize]))
            .collect();
        if !crate::kernel::planar::inside_polygon([0.0, 0.0], &region.rim) {
            return Err("Q does not surround the hit point");
        }
        Ok(region)
    }

    /// Step 3: the bridge contours. The paper's C_loc lies in the target's
    /// plane; the tilted variant turns it half-way towards C_1sec, for
    /// secondaries that leave obliquely. Either way C_loc is lifted until the
    /// whole rim lies behind its plane, so the skirt (a height field over the
    /// splice plane, below C_loc) and the bands above C_loc cannot meet, and
    /// its projection lies strictly inside the rim's.
    fn bridge_contours(
        &self,
        c1: &Ring,
        landing: &Landing,
        region: &Region,
        tilted: bool,
    ) -> Result<Contours, &'static str> {
        let (h, n_q, rim, c_q) = (landing.h, region.n_q, &region.rim, &region.c_q);
        // Distance from the hit point to the rim's edges, in projection.
        let inradius = (0..rim.len())
            .map(|i| point_segment_2d([0.0, 0.0], rim[i], rim[(i + 1) % rim.len()]))
            .fold(f64::INFINITY, f64::min);
        let e_ave = {
            let n = c_q.len();
            (0..n)
                .map(|i| {
                    self.surface.pos[c_q[i] as usize]
                        .distance(self.surface.pos[c_q[(i + 1) % n] as usize])
                })
                .sum::<f64>()
                / n as f64
        };
        let n_loc = if tilted {
            (n_q + c1.normal).normalize_or_zero()
        } else {
            n_q
        };
        let margin = 0.1 * e_ave.min(c1.radius);
        let lift = c_q
            .iter()
            .map(|&v| ((self.surface.pos[v as usize] - h).dot(n_loc) + margin) / n_q.dot(n_loc))
            .fold(0.0, f64::max);
        let loc_center = h + n_q * lift;
        let r_loc = c1.radius.min(0.8 * inradius);
        let offsets: Vec<DVec3> = (0..c1.m)
            .map(|j| self.surface.pos[c1.vertex(j) as usize] - c1.center)
            .collect();
        let contour_at = |center: DVec3, normal: DVec3, radius: f64| -> Option<Vec<DVec3>> {
            offsets
                .iter()
                .map(|w| {
                    let p = *w - w.dot(normal) * normal;
                    let l = p.length();
                    (l > 1e-12 * radius).then(|| center + p * (radius / l))
                })
                .collect()
        };
        let Some(loc) = contour_at(loc_center, n_loc, r_loc) else {
            return Err("degenerate C_loc");
        };
        let loc_flat: Vec<[f64; 2]> = loc.iter().map(|&p| region.flat(h, p)).collect();
        let Some(skirt) = crate::kernel::planar::triangulate_annulus(rim, &loc_flat) else {
            return Err("skirt cannot be triangulated");
        };
        let d_min = loc
            .iter()
            .flat_map(|a| offsets.iter().map(move |w| a.distance(c1.center + *w)))
            .fold(f64::INFINITY, f64::min);
        let n_mids = (d_min / e_ave.max(1e-300)).floor().clamp(0.0, 64.0) as usize;
        let mut frames: Vec<DiscFrame> = vec![DiscFrame {
            center: loc_center,
            normal: n_loc,
            radius: r_loc,
        }];
        let mut contours: Vec<Vec<DVec3>> = vec![loc];
        for t in 1..n_mids {
            let f = t as f64 / n_mids as f64;
            let center = loc_center.lerp(c1.center, f);
            let normal = n_loc.lerp(c1.normal, f).normalize_or_zero();
            let radius = r_loc + (c1.radius - r_loc) * f;
            let Some(c) = contour_at(center, normal, radius) else {
                return Err("degenerate middle contour");
            };
            frames.push(DiscFrame {
                center,
                normal,
                radius,
            });
            contours.push(c);
        }
        frames.push(c1.disc());
        if frames.windows(2).any(|w| !w[0].clears(&w[1], 0.0)) {
            return Err("middle contours cross");
        }
        Ok(Contours {
            frames,
            contours,
            skirt,
        })
    }

    /// The bridge built tentatively: Q removed, the skirt from its rim to
    /// C_loc and the bands through the middle contours to C_1sec. The mark
    /// to roll back to and the bridge's first triangle.
    fn lay_bridge(
        &mut self,
        c1: &Ring,
        landing: &Landing,
        region: &Region,
        bridge: &Contours,
    ) -> (Mark, u32) {
        let mark = self.surface.mark();
        for &t in &region.q {
            self.surface.alive[t as usize] = false;
        }
        let target = landing.target;
        let primary_label = self.surface.label[self.surface.tris[target as usize][0] as usize];
        let mut loops: Vec<Vec<u32>> = Vec::with_capacity(bridge.contours.len() + 1);
        for (i, c) in bridge.contours.iter().enumerate() {
            let label = if i == 0 { primary_label } else { c1.label };
            loops.push(c.iter().map(|&p| self.surface.vertex(p, label)).collect());
        }
        loops.push(tube::band::ring_loop(c1));
        let first_tri = self.surface.tris.len() as u32;
        let c_q = &region.c_q;
        let skirt_vertex = |i: usize| {
            if i < c_q.len() {
                c_q[i]
            } else {
                loops[0][i - c_q.len()]
            }
        };
        for t in &bridge.skirt {
            let v = t.map(skirt_vertex);
            self.surface.triangle(v[0], v[1], v[2]);
        }
        let frames = &bridge.frames;
        for (i, w) in loops.windows(2).enumerate() {
            tube::band::connect_loops(
                self.surface,
                &w[0],
                &w[1],
                frames[i].center,
                frames[i + 1].center,
            );
        }
        (mark, first_tri)
    }

    /// Whether the triangles from `first` on meet no other live triangle
    /// (except where they share vertices or edges properly), and every edge
    /// they or the `removed` triangles had is now either gone or shared by
    /// exactly two live triangles running it in opposite directions.
    fn bridge_is_clear(&mut self, first: u32, removed: &[u32]) -> Result<(), &'static str> {
        let n = self.surface.tris.len() as u32;
        let mut b = Aabb::EMPTY;
        for t in (first..n).chain(removed.iter().copied()) {
            b.add(&tri_box(self.surface, t));
        }
        // Grown by a few f32 steps: the test below is on rounded positions.
        let scale = (0..3).fold(0f64, |m, a| m.max(b.lo[a].abs()).max(b.hi[a].abs()));
        let b = b.inflated(4.0 * scale * f64::from(f32::EPSILON));
        let mut near: Vec<u32> = Vec::new();
        self.grid.for_each_near(self.surface, &b, |t| near.push(t));
        near.extend(first..n);
        // Topology: every edge of the bridge must end up in exactly two live
        // triangles that run it in opposite directions.
        let mut uses: crate::kernel::hash::FastMap<(u32, u32), (u32, u32)> =
            crate::kernel::hash::FastMap::default();
        for t in (first..n).chain(removed.iter().copied()) {
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, c) = (f[e], f[(e + 1) % 3]);
                uses.insert((a.min(c), a.max(c)), (0, 0));
            }
        }

        for &t in &near {
            if !self.surface.alive[t as usize] {
                continue;
            }
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, c) = (f[e], f[(e + 1) % 3]);
                if let Some(u) = uses.get_mut(&(a.min(c), a.max(c))) {
                    if a < c {
                        u.0 += 1;
                    } else {
                        u.1 += 1;
                    }
                }
            }
        }
        if uses.values().any(|&u| u != (1, 1) && u != (0, 0)) {
            return Err("bridge is not manifold with its surroundings");
        }
        // At the output's precision: a bridge clear in f64 can cross itself
        // once rounded to f32 (a FlyWire neuron, in nanometres near 5·10⁵,
        // has f32 steps of 0.03 and skirt triangles not much larger).
        let pos = |t: u32, s: &Surface| {
            s.tris[t as usize].map(|k| s.pos[k as usize].to_array().map(|x| f64::from(x as f32)))
        };
        let rounded_box = |t: u32, s: &Surface| Aabb::of(&pos(t, s));
        // Sweep along x: the live neighbours sorted by their boxes' low x, so
        // each bridge triangle visits only those whose x-range can meet its own.
        let mut others: Vec<(Aabb, u32)> = near
            .iter()
            .filter(|&&o| self.surface.alive[o as usize])
            .map(|&o| (rounded_box(o, self.surface), o))
            .collect();
        others.sort_unstable_by(|a, b| a.0.lo[0].total_cmp(&b.0.lo[0]).then(a.1.cmp(&b.1)));
        let width = others
            .iter()
            .map(|(b, _)| b.hi[0] - b.lo[0])
            .fold(0.0, f64::max);
        for t in first..n {
            let (ft, pt) = (self.surface.tris[t as usize], pos(t, self.surface));
            let bt = rounded_box(t, self.surface);
            let start = others.partition_point(|(b, _)| b.lo[0] < bt.lo[0] - width);
            for &(bo, o) in &others[start..] {
                if bo.lo[0] > bt.hi[0] {
                    break;
                }
                if o == t || (o >= first && o < t) || !bt.overlaps(&bo) {
                    continue;
                }
                if crate::kernel::predicates::pair_intersects(
                    ft,
                    self.surface.tris[o as usize],
                    pt,
                    pos(o, self.surface),
                ) {
                    return Err(if o >= first {
                        "bridge crosses itself"
                    } else {
                        "bridge crosses the surface"
                    });
                }
            }
        }
        Ok(())
    }
}

/// Where a bridge's ray lands (step 1).
struct Landing {
    /// The triangle hit.
    target: u32,
    /// The point hit.
    h: DVec3,
    /// The unit direction from the hit point back to the ring's centre.
    axis: DVec3,
}

/// Region Q and the plane of the splice (step 2).
struct Region {
    /// Q's triangles.
    q: Vec<u32>,
    /// Q's rim C_Q, a vertex loop.
    c_q: Vec<u32>,
    /// Q's mean normal.
    n_q: DVec3,
    /// A basis of the splice plane.
    e1: DVec3,
    e2: DVec3,
    /// The rim in the splice plane, around the hit point.
    rim: Vec<[f64; 2]>,
}

impl Region {
    /// Point `p` in the splice plane around the hit point `h`.
    fn flat(&self, h: DVec3, p: DVec3) -> [f64; 2] {
        [(p - h).dot(self.e1), (p - h).dot(self.e2)]
    }
}

/// The bridge's contours (step 3): C_loc and the middle contours, their
/// discs (with C_1sec's last), and the skirt from the rim to C_loc (rim
/// vertices first, then C_loc's).
struct Contours {
    frames: Vec<DiscFrame>,
    contours: Vec<Vec<DVec3>>,
    skirt: Vec<[usize; 3]>,
}

/// Where an attempt casts its ray from C_1sec's centre.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Aim {
    /// At the branch point (the paper).
    BranchPoint,
    /// At the point of the existing surface nearest to the branch point (for
    /// branch points that lie outside their primary's mesh, where it cuts a
    /// corner or splits).
    NearestSurface,
    /// At the point of the existing surface nearest to C_1sec's centre (a
    /// secondary that clears a crowd of neighbours far from its branch point
    /// grows out of the nearest of them).
    NearestToStart,
    /// Straight back along the secondary's axis.
    Backwards,
}

/// One way to try a junction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Attempt {
    /// Which ring of the secondary's tube serves as C_1sec (0 = its first).
    ring: usize,
    /// Where the ray goes.
    aim: Aim,
    /// Q's footprint radius over C_1sec's radius.
    footprint: f64,
    /// C_loc turned half-way towards C_1sec.
    tilted: bool,
}

/// The attempts for a tube, the paper's construction first. Later C_1sec
/// candidates go as far as three radii along the secondary.
pub(super) fn attempts(tube: &Tube) -> Vec<Attempt> {
    let paper = Attempt {
        ring: 0,
        aim: Aim::BranchPoint,
        footprint: 1.0,
        tilted: false,
    };
    let variant = |ring: usize, aim: Aim, footprint: f64, tilted: bool| Attempt {
        ring,
        aim,
        footprint,
        tilted,
    };
    let mut out = vec![
        paper,
        variant(0, Aim::BranchPoint, 0.7, false),
        variant(0, Aim::BranchPoint, 1.0, true),
        variant(0, Aim::NearestSurface, 1.0, false),
        variant(0, Aim::NearestSurface, 1.0, true),
        variant(0, Aim::NearestToStart, 1.0, false),
        variant(0, Aim::NearestToStart, 1.0, true),
        variant(0, Aim::Backwards, 1.0, false),
        variant(0, Aim::Backwards, 1.0, true),
    ];
    let r0 = tube.rings[0];
    for k in 1..tube.rings.len().min(8) {
        if tube.rings[k].center.distance(r0.center) > 3.0 * r0.radius.max(tube.rings[k].radius) {
            break;
        }
        out.push(variant(k, Aim::BranchPoint, 1.0, false));
        out.push(variant(k, Aim::BranchPoint, 1.0, true));
        out.push(variant(k, Aim::NearestSurface, 1.0, true));
        out.push(variant(k, Aim::NearestToStart, 1.0, true));
        out.push(variant(k, Aim::Backwards, 1.0, true));
    }
    // Last resort before detaching: a C_1sec farther out, up to ten radii.
    let far_limit = 10.0 * r0.radius;
    for k in 1..tube.rings.len().min(crate::build::tube::KEPT_RINGS) {
        let d = tube.rings[k].center.distance(r0.center);
        if d <= 3.0 * r0.radius.max(tube.rings[k].radius) {
            continue;
        }
        if d > far_limit.max(3.0 * tube.rings[k].radius) {
            break;
        }
        out.push(variant(k, Aim::NearestToStart, 1.0, true));
        out.push(variant(k, Aim::BranchPoint, 1.0, true));
    }
    out
}

fn point_segment_2d(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p[0] - a[0] - t * dx).powi(2) + (p[1] - a[1] - t * dy).powi(2)).sqrt()
}
