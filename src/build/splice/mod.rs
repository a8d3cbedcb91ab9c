//! Mesh splicing at branch points (paper §3.2, "Mesh Splicing", Figs. 5–6).
//!
//! A secondary branch's tube starts open at its first contour C_1sec (the
//! contours that touch the primary's volume were never built, see
//! [`first_outside`](crate::build::coverage::first_outside)). Splicing joins that open end to the surface it grows out
//! of:
//!
//! 1. **Target.** A ray from C_1sec's centre towards the branch point; the
//!    nearest live triangle it hits (any part already built, usually the
//!    primary) is the target, and the hit point `h` the centre of the splice.
//! 2. **Region Q.** Triangles grown from the target across shared edges while
//!    their centres lie within the secondary's footprint (distance to the
//!    bridge axis at most its radius) and they face the secondary. Q must be a
//!    topological disk: one simple boundary loop C_Q and Euler characteristic 1.
//! 3. **Bridge.** C_loc, a contour in the target's plane centred at `h`, then
//!    N_mids middle contours from C_loc to C_1sec (N_mids = minimum vertex
//!    distance between C_loc and C_1sec divided by the mean edge of C_Q, as the
//!    paper has it), their vertices made from C_1sec's by projection. C_Q,
//!    the middle contours and C_1sec are joined by the contour connection of
//!    [`crate::build::tube::connect_loops`].
//! 4. **Proof.** The bridge is kept only if its contours clear each other and
//!    none of its triangles meets another triangle of the surface (exact
//!    predicates, neighbours handled as in [`crate::measure::check`]). Then Q is removed
//!    and the bridge stays.
//!
//! Where the paper's construction cannot give a valid junction (Q is not a
//! disk, the bridge would cross a neighbour, the ray is blocked), alternatives
//! are tried in order, and the result is counted by method:
//!
//! * *moved*: the same construction from the secondary's second or third
//!   contour (its first bands are dropped), and with a narrower or wider Q;
//! * *fallback*: the secondary's start is extended back to the branch point
//!   (as the skeleton's round cone between them is) or into the nearest
//!   surface, and capped there; where neither end lies behind its first
//!   contour, its start is capped and a thinner capsule reaches from the cap
//!   into the nearest surface. The overlap pass ([`crate::overlap`]) then
//!   replaces the crossing parts by the boundary of their union;
//! * *detached*: with no other surface near the junction at all (the
//!   capsule looks first within reach of the branch point, then anywhere the
//!   splicer indexes around the junction), the secondary keeps a cap at its
//!   start and stays a separate closed component; reported so it is never
//!   hidden.
//!
//! Deviations from the paper, and why: C_loc is centred at the ray's hit point
//! rather than at the target's barycentre (a thin branch on a coarse primary
//! would otherwise land up to an edge length off its axis); the middle contours'
//! normals turn smoothly from the target's normal to C_1sec's, which keeps
//! consecutive middle contours from crossing.

mod bridge;
pub mod index;
mod region;

use glam::DVec3;

use crate::build::splice::index::TriangleGrid;
use crate::build::surface::Surface;
use crate::build::tube::{self, Tube};
use crate::kernel::bvh::Aabb;
use crate::mesh::NO_OWNER;
use bridge::attempts;

/// A tube to attach to the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Join {
    /// Index of the tube in the tube list; its start is open.
    pub tube: u32,
    /// The point the ray aims at: the branch point (or where a piece split off).
    pub toward: DVec3,
}

/// How a junction was built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The paper's splice, first try.
    Paper,
    /// The paper's splice from a later contour or with another Q size.
    Moved,
    /// No splice was valid: the secondary reaches back into its parent and the
    /// overlap pass makes the two one surface (their union).
    Fallback,
    /// No valid junction: the secondary is capped and left separate.
    Detached,
}

/// State shared by the junctions of one mesh.
pub struct Splicer<'a> {
    surface: &'a mut Surface,
    grid: TriangleGrid,
    /// Tube of each triangle ([`NO_OWNER`] for bridges).
    owner: Vec<u32>,
    /// Triangles no Q may take: the first band of every tube whose start is
    /// still open, since its ring borders a hole its own junction will fill.
    reserved: Vec<bool>,
    cap_rings: u32,
    /// Tubes already part of their tree's surface: those without a join, and
    /// those whose join is done. A junction may only land on these (or on
    /// bridges and somas): landing on a tube still waiting for its own join
    /// could close a loop of tubes joined only to each other.
    settled: Vec<bool>,
    /// Why attempts failed, for diagnostics.
    pub failures: std::collections::BTreeMap<&'static str, u32>,
    /// The triangle ranges of the bridges, extensions and connectors, each
    /// proven (or built) not to cross itself: each becomes a part of its own
    /// for the overlap pass, which then never compares a bridge with itself.
    units: Vec<[u32; 2]>,
    tube_count: u32,
}

impl<'a> Splicer<'a> {
    /// Prepares to splice `joins` into `surface`, whose triangles belong to
    /// `tubes`. Only triangles within reach of some junction are indexed.
    pub fn new(
        surface: &'a mut Surface,
        tubes: &[Tube],
        joins: &[Join],
        cap_rings: u32,
    ) -> Splicer<'a> {
        let mut owner = vec![NO_OWNER; surface.tris.len()];
        for (i, t) in tubes.iter().enumerate() {
            for k in t.tris.clone() {
                owner[k as usize] = i as u32;
            }
        }
        let grid = TriangleGrid::new_where(surface, near_a_junction(tubes, joins));
        let mut reserved = vec![false; surface.tris.len()];
        for t in tubes {
            if t.start_cap.is_empty() {
                for k in first_band(surface, t) {
                    reserved[k as usize] = true;
                }
            }
        }
        let mut settled = vec![true; tubes.len()];
        for j in joins {
            settled[j.tube as usize] = false;
        }
        Splicer {
            surface,
            grid,
            owner,
            reserved,
            cap_rings,
            settled,
            failures: std::collections::BTreeMap::new(),
            units: Vec::new(),
            tube_count: tubes.len() as u32,
        }
    }

    /// The part of every triangle of the surface, for the overlap pass: its
    /// tube, a number after the tubes' for each bridge, extension or connector,
    /// and [`crate::mesh::NO_OWNER`] for the somas (compared with everything).
    pub fn into_owner(self) -> Vec<u32> {
        let mut owner = self.owner;
        for (k, &[first, end]) in self.units.iter().enumerate() {
            let part = self.tube_count + k as u32;
            for o in &mut owner[first as usize..end as usize] {
                *o = part;
            }
        }
        owner
    }

    /// Joins `tube`'s open start to the surface, trying the alternatives in
    /// order; always leaves the surface closed.
    pub fn join(&mut self, tubes: &[Tube], join: &Join) -> Method {
        let tube = &tubes[join.tube as usize];
        self.settled[join.tube as usize] = true;
        for (i, a) in attempts(tube).into_iter().enumerate() {
            if self.try_bridge(join.tube, tube, a, join.toward) {
                self.release(tube);
                return if i == 0 { Method::Paper } else { Method::Moved };
            }
        }
        let first = self.surface.tris.len() as u32;
        if self.reach_back(join.tube, tube, join.toward) {
            // Its faces cross the surface it reaches into: compared with
            // everything by the overlap pass, which joins the two.
            self.adopt(first, NO_OWNER);
            self.release(tube);
            return Method::Fallback;
        }
        // Close the tube's start with a cap, and join it to the nearest
        // surface by a capsule if there is one within reach.
        tube::cap(self.surface, &tube.rings[0], self.cap_rings, false);
        self.adopt(first, join.tube);
        let first = self.surface.tris.len() as u32;
        let joined = self.connector(join.tube, tube, join.toward);
        self.adopt(first, NO_OWNER);
        self.release(tube);
        if joined {
            Method::Fallback
        } else {
            Method::Detached
        }
    }

    /// The last fallback, for a capped start: a capsule from inside the cap to
    /// just inside the surface nearest to the start, thinner than both, which
    /// the overlap pass merges with them. False (nothing built) without a
    /// surface in reach.
    fn connector(&mut self, tube_id: u32, tube: &Tube, toward: DVec3) -> bool {
        let r0 = tube.rings[0];
        // Where the parent's own contours around the branch point were all
        // skipped (a jittered trace), the nearest joined surface can lie
        // farther than the branch point: the capsule then reaches it at any
        // distance, so the tree stays one surface (the capsule is thinner
        // than the branch, a sliver beside the segment fillers built later).
        // A jittered blowfly cell had one such start: the nearest surface lay
        // 3.2 units from it, its reach was 2.7.
        // Only the triangles the splicer indexes around its junctions are
        // found (see `near_a_junction`), a few of the branch's radii and
        // contour spacings away.
        let Some(end) = self
            .inside_nearest(tube_id, &r0, reach_toward(&r0, toward), 0.5)
            .or_else(|| {
                let far = self.extent_from(r0.center);
                self.inside_nearest(tube_id, &r0, far, 0.5)
            })
        else {
            return false;
        };
        // Inside the cap's dome (a hemisphere of radius r0 behind the ring).
        let start = r0.center - 0.3 * r0.radius * r0.normal;
        let radius =
            (0.5 * self.clearance(tube_id, &r0, end)).clamp(0.1 * r0.radius, 0.5 * r0.radius);
        tube::capsule(
            self.surface,
            start,
            end,
            radius,
            r0.m,
            r0.label,
            self.cap_rings,
        );
        true
    }

    /// The fallback junction: the tube's open start is extended back into the
    /// surface it grows from and capped there. The extension ends at the branch
    /// point `toward` when the way there crosses that surface (as the round
    /// cone between them would), else just inside the surface nearest to the
    /// start (the parent's tube may not cover its own branch point where its
    /// contours were skipped). Rings parallel to the first one, shrinking to
    /// at most half the distance from the end to the nearest other surface,
    /// stacked in disjoint slabs: the extension cannot cross itself. False
    /// (and nothing built) when that end is not behind the first ring.
    fn reach_back(&mut self, tube_id: u32, tube: &Tube, toward: DVec3) -> bool {
        let r0 = tube.rings[0];
        let dist = toward.distance(r0.center);
        if dist <= 1e-9 * r0.radius {
            return false;
        }
        // Only surfaces already joined to their tree count, as for a splice's
        // target: reaching into a descendant would join nothing to the tree.
        let (owner, settled) = (&self.owner, &self.settled);
        let crosses = self
            .grid
            .raycast(
                self.surface,
                r0.center,
                (toward - r0.center) / dist,
                dist,
                |t| {
                    let o = owner[t as usize];
                    o != tube_id && (o == NO_OWNER || settled[o as usize])
                },
            )
            .is_some();
        // Where to end: the branch point when the way there enters the
        // surface, else just inside the surface nearest to the start.
        let mut ends = Vec::with_capacity(2);
        if crosses {
            ends.push(toward);
        }
        ends.extend(self.inside_nearest(tube_id, &r0, reach_toward(&r0, toward), 1.0));
        let behind = |end: &DVec3| (r0.center - *end).dot(r0.normal) >= 0.5 * r0.radius;
        let Some(end) = ends.into_iter().find(behind) else {
            return false;
        };
        let depth = (r0.center - end).dot(r0.normal);
        let r_end = (0.5 * self.clearance(tube_id, &r0, end)).clamp(0.2 * r0.radius, r0.radius);
        let edge = std::f64::consts::TAU * r0.radius / f64::from(r0.m);
        let steps = ((depth / edge).ceil() as u32).clamp(1, 64);
        let offsets: Vec<DVec3> = (0..r0.m)
            .map(|j| self.surface.pos[r0.vertex(j) as usize] - r0.center)
            .collect();
        let mut rings: Vec<tube::Ring> = Vec::with_capacity(steps as usize + 1);
        for k in 0..steps {
            let t = f64::from(k) / f64::from(steps);
            let center = end + t * (r0.center - end);
            let scale = (r_end + t * (r0.radius - r_end)) / r0.radius;
            let first = self.surface.pos.len() as u32;
            for w in &offsets {
                self.surface.vertex(center + scale * *w, r0.label);
            }
            rings.push(tube::Ring {
                center,
                first,
                radius: scale * r0.radius,
                ..r0
            });
        }
        rings.push(r0);
        for w in rings.windows(2) {
            let (a, b) = (tube::ring_loop(&w[0]), tube::ring_loop(&w[1]));
            tube::connect_loops_about(self.surface, &a, &b, w[0].center, w[1].center, r0.normal);
        }
        tube::cap(self.surface, &rings[0], self.cap_rings, false);
        true
    }

    /// A point `depth` times `r0`'s radius beyond the surface point nearest to
    /// `r0`'s centre (other than its own tube's), within `reach` of it
    /// (usually [`reach_toward`]): just inside that surface, seen from the ring.
    fn inside_nearest(
        &mut self,
        tube_id: u32,
        r0: &tube::Ring,
        reach: f64,
        depth: f64,
    ) -> Option<DVec3> {
        let q = self.nearest_surface_point(tube_id, r0.center, r0.radius, reach)?;
        let way = (q - r0.center).normalize_or_zero();
        (way != DVec3::ZERO).then(|| q + way * (depth * r0.radius))
    }

    /// The largest distance from `p` to a vertex of the surface: the reach
    /// that finds any surface there is.
    fn extent_from(&self, p: DVec3) -> f64 {
        self.surface
            .pos
            .iter()
            .map(|q| q.distance_squared(p))
            .fold(0.0, f64::max)
            .sqrt()
    }

    /// Distance from `p` to the nearest surface other than the tube's own,
    /// looked for within four of `r0`'s radii (`r0`'s radius if none).
    fn clearance(&mut self, tube_id: u32, r0: &tube::Ring, p: DVec3) -> f64 {
        self.nearest_surface_point(tube_id, p, r0.radius, 4.0 * r0.radius)
            .map_or(r0.radius, |q| q.distance(p))
    }

    /// Registers triangles from `first` to the end of the surface.
    fn adopt(&mut self, first: u32, owner: u32) {
        let n = self.surface.tris.len();
        if owner == NO_OWNER && first < n as u32 {
            self.units.push([first, n as u32]);
        }
        self.owner.resize(n, owner);
        self.reserved.resize(n, false);
        for t in first..n as u32 {
            self.owner[t as usize] = owner;
            self.grid.insert(self.surface, t);
        }
    }

    /// The tube's start is no longer open: its first band is free for others.
    fn release(&mut self, tube: &Tube) {
        for k in first_band(self.surface, tube) {
            self.reserved[k as usize] = false;
        }
    }

    /// The point of a live triangle (not of tube `own`, not reserved) nearest to
    /// `p`, among those whose boxes come within `reach` of `p` (per axis).
    ///
    /// The search box starts at `first` and doubles until the best point found
    /// lies within it: any nearer triangle then overlaps the box too, so the
    /// answer is the one the whole `reach` box gives, at the cost of a box about
    /// as large as the distance found (reaches span a whole branch's length).
    fn nearest_surface_point(
        &mut self,
        own: u32,
        p: DVec3,
        first: f64,
        reach: f64,
    ) -> Option<DVec3> {
        let mut half = first.min(reach).max(1e-12 * reach);
        loop {
            let query = Aabb::of(&[p.to_array()]).inflated(half);
            let mut best: Option<(f64, DVec3)> = None;
            let (surface, owner, reserved) = (&*self.surface, &self.owner, &self.reserved);
            let settled = &self.settled;
            self.grid.for_each_near(surface, &query, |t| {
                let o = owner[t as usize];
                if o == own || reserved[t as usize] || (o != NO_OWNER && !settled[o as usize]) {
                    return;
                }
                let f = surface.tris[t as usize];
                let q = crate::kernel::predicates::closest_point_on_triangle(
                    p,
                    f.map(|k| surface.pos[k as usize]),
                );
                let d = q.distance(p);
                if best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, q));
                }
            });
            if half >= reach || best.is_some_and(|(d, _)| d <= half) {
                return best.map(|(_, q)| q);
            }
            half = (half * 2.0).min(reach);
        }
    }
}

/// The triangles of `tube` that touch its first ring (its first band, or for a
/// single-ring tube the start of its end cap).
fn first_band(surface: &Surface, tube: &Tube) -> Vec<u32> {
    let r0 = tube.rings[0];
    let on_ring = |v: u32| (r0.first..r0.first + r0.m).contains(&v);
    let end = tube.bands.get(1).copied().unwrap_or(tube.tris.end);
    (tube.bands[0]..end)
        .filter(|&t| surface.tris[t as usize].iter().any(|&v| on_ring(v)))
        .collect()
}

/// A test for "within reach of some junction": a ball around each junction's
/// first contour large enough for every attempt (the ray's reach, Q, the
/// bridge, later contours), looked up through a coarse hash of the balls.
/// How far from ring `r0` a junction looks for the surface its branch grows
/// out of: to the branch point `toward` and four radii beyond.
fn reach_toward(r0: &tube::Ring, toward: DVec3) -> f64 {
    toward.distance(r0.center) + 4.0 * r0.radius
}

fn near_a_junction(tubes: &[Tube], joins: &[Join]) -> impl Fn(&Aabb) -> bool + use<> {
    let balls: Vec<(DVec3, f64)> = joins
        .iter()
        .map(|j| {
            // Every attempt's ray, region Q and bridge lie within this distance of
            // the first contour (see `attempts` and `bridge`).
            let t = &tubes[j.tube as usize];
            let c1 = t.rings[0];
            let rings = &t.rings[..t.rings.len().min(8)];
            let far = rings
                .iter()
                .map(|r| r.center.distance(c1.center))
                .fold(0.0, f64::max);
            let r = rings.iter().map(|r| r.radius).fold(0.0, f64::max);
            let reach = 2.0 * (j.toward.distance(c1.center) + far).max(r) + 4.0 * r;
            (c1.center, far + reach + 4.0 * r)
        })
        .collect();
    let mut sizes: Vec<f64> = balls.iter().map(|b| b.1).collect();
    sizes.sort_by(f64::total_cmp);
    let cell = sizes
        .get(sizes.len() / 2)
        .copied()
        .unwrap_or(1.0)
        .max(1e-300)
        * 2.0;
    let mut hash: crate::kernel::hash::FastMap<[i64; 3], Vec<u32>> =
        crate::kernel::hash::FastMap::default();
    for (i, &(c, r)) in balls.iter().enumerate() {
        // Padded by half a cell: a small triangle touching the ball has its
        // centre within that margin.
        let lo = ((c - DVec3::splat(r + 0.5 * cell)) / cell)
            .floor()
            .as_i64vec3();
        let hi = ((c + DVec3::splat(r + 0.5 * cell)) / cell)
            .floor()
            .as_i64vec3();
        let n = (hi - lo + 1).as_dvec3();
        if n.x * n.y * n.z > 4096.0 {
            hash.entry([i64::MAX; 3]).or_default().push(i as u32); // huge ball: always checked
            continue;
        }
        for x in lo.x..=hi.x {
            for y in lo.y..=hi.y {
                for z in lo.z..=hi.z {
                    hash.entry([x, y, z]).or_default().push(i as u32);
                }
            }
        }
    }
    move |b: &Aabb| {
        let center = DVec3::from_array([
            (b.lo[0] + b.hi[0]) / 2.0,
            (b.lo[1] + b.hi[1]) / 2.0,
            (b.lo[2] + b.hi[2]) / 2.0,
        ]);
        let half = DVec3::from_array([b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]])
            .length()
            / 2.0;
        if half > 0.5 * cell {
            return true; // large triangles are few: always indexed
        }
        let key = (center / cell).floor().as_i64vec3();
        let touches = |ids: &Vec<u32>| {
            ids.iter()
                .any(|&i| balls[i as usize].0.distance(center) <= balls[i as usize].1 + half)
        };
        hash.get(&[i64::MAX; 3]).is_some_and(touches)
            || hash.get(&[key.x, key.y, key.z]).is_some_and(touches)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring of `m` vertices about `center`, facing `normal`.
    fn ring_at(s: &mut Surface, center: DVec3, normal: DVec3, radius: f64, m: u32) -> tube::Ring {
        let u = crate::kernel::vector::any_perpendicular(normal);
        let first = s.pos.len() as u32;
        for p in crate::skeleton::contour::ring(center, normal, u, radius, m) {
            s.vertex(p, 0);
        }
        tube::Ring {
            center,
            normal,
            u,
            radius,
            skeleton_radius: radius,
            m,
            first,
            label: 0,
            source: 0,
            resampled: 0,
        }
    }

    #[test]
    fn a_start_far_from_every_surface_is_still_joined() {
        // A closed parent (a soma-like part, owned by no tube) along x, and a
        // tube starting 7 units above it whose ray aims sideways, at a branch
        // point with no surface around it (its parent's contours were skipped):
        // nothing lies within the usual reach of the start (3 units).
        let mut s = Surface::default();
        tube::capsule(
            &mut s,
            DVec3::new(-5.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
            1.0,
            12,
            0,
            2,
        );
        let first_tri = s.tris.len() as u32;
        let rings: Vec<tube::Ring> = (0..4)
            .map(|k| {
                ring_at(
                    &mut s,
                    DVec3::new(0.0, 0.0, 8.0 + f64::from(k)),
                    DVec3::Z,
                    0.5,
                    12,
                )
            })
            .collect();
        let mut bands = vec![first_tri];
        for w in rings.windows(2) {
            tube::connect(&mut s, &w[0], &w[1]);
            bands.push(s.tris.len() as u32);
        }
        let (end_cap, _) = tube::cap(&mut s, &rings[3], 2, true);
        let toward = DVec3::new(1.0, 0.0, 8.0);
        let t = Tube {
            branch: 1,
            rings,
            bands,
            start_cap: first_tri..first_tri,
            end_cap,
            start_cap_vertices: 0..0,
            tris: first_tri..s.tris.len() as u32,
            anchor: toward,
        };
        let join = Join { tube: 0, toward };
        let tubes = [t];
        let method = Splicer::new(&mut s, &tubes, &[join], 2).join(&tubes, &join);
        assert_eq!(method, Method::Fallback);
        // The connector is a capsule reaching into the parent: some of its
        // vertices lie inside it.
        let built = &s.tris[tubes[0].tris.end as usize..];
        assert!(!built.is_empty());
        let inside = built.iter().flatten().any(|&v| {
            let p = s.pos[v as usize];
            p.x.abs() < 5.0 && (p.y * p.y + p.z * p.z).sqrt() < 1.0
        });
        assert!(inside, "the connector ends inside the parent");
    }

    #[test]
    fn boundary_of_a_fan_is_its_rim() {
        let mut s = Surface::default();
        let c = s.vertex(DVec3::ZERO, 0);
        let rim: Vec<u32> = (0..6)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 6.0;
                s.vertex(DVec3::new(a.cos(), a.sin(), 0.0), 0)
            })
            .collect();
        let q: Vec<u32> = (0..6)
            .map(|i| s.triangle(c, rim[i], rim[(i + 1) % 6]))
            .collect();
        let lp = region::boundary_loop(&s, &q).expect("a disk");
        assert_eq!(lp.len(), 6);
        // Two fans sharing nothing: not a disk.
        let two = [q[0], q[3]];
        assert!(region::boundary_loop(&s, &two).is_none());
        // A ring (annulus) is not a disk either.
        let annulus: Vec<u32> = q[..5].to_vec();
        assert!(
            region::boundary_loop(&s, &annulus).is_some(),
            "five of six fan triangles are still a disk"
        );
    }
}
