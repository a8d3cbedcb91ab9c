//! Mesh splicing at branch points (paper §3.2, "Mesh Splicing", Figs. 5–6).
//!
//! A secondary branch's tube starts open at its first contour C_1sec (the
//! contours that touch the primary's volume were never built, see
//! [`first_outside`](crate::volume::first_outside)). Splicing joins that open end to the surface it grows out
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
//!    [`crate::tube::connect_loops`].
//! 4. **Proof.** The bridge is kept only if its contours clear each other and
//!    none of its triangles meets another triangle of the surface (exact
//!    predicates, neighbours handled as in [`crate::check`]). Then Q is removed
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

use glam::DVec3;

use crate::bvh::Aabb;
use crate::contour::DiscFrame;
use crate::grid::{TriangleGrid, tri_box};
use crate::surface::Surface;
use crate::tube::{self, Tube};

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
    /// Tube of each triangle (u32::MAX for bridges).
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
        let mut owner = vec![u32::MAX; surface.tris.len()];
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
    /// and [`crate::overlap::NO_OWNER`] for the somas (compared with everything).
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
            self.adopt(first, u32::MAX);
            self.release(tube);
            return Method::Fallback;
        }
        // Close the tube's start with a cap, and join it to the nearest
        // surface by a capsule if there is one within reach.
        tube::cap(self.surface, &tube.rings[0], self.cap_rings, false);
        self.adopt(first, join.tube);
        let first = self.surface.tris.len() as u32;
        let joined = self.connector(join.tube, tube, join.toward);
        self.adopt(first, u32::MAX);
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
                    o != tube_id && (o == u32::MAX || settled[o as usize])
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
        if owner == u32::MAX && first < n as u32 {
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

    /// One attempt: the bridge from ring `k` of `tube` with Q's footprint
    /// `rho_factor` times the ring's radius. Commits and returns true if valid.
    fn try_bridge(&mut self, tube_id: u32, tube: &Tube, a: Attempt, toward: DVec3) -> bool {
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

    fn bridge(
        &mut self,
        tube_id: u32,
        tube: &Tube,
        a: Attempt,
        toward: DVec3,
        dropped: &[u32],
    ) -> Result<(), &'static str> {
        let k = a.ring;
        let c1 = tube.rings[k];
        // 1. Target.
        let aim_point = match a.aim {
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
            o != tube_id && (o == u32::MAX || settled[o as usize])
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
        // An oblique secondary needs the tilted C_loc between it and the target.
        let min_cos = if a.tilted { 0.02 } else { 0.2 };
        if c1.normal.dot(n_t) < min_cos {
            return Err("secondary too oblique to the target");
        }
        // 2. Region Q.
        let rho = c1.radius * a.footprint;
        let Some(q) = self.grow_region(tube_id, target, h, axis, rho) else {
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
        let e1 = crate::contour::any_perpendicular(n_q);
        let e2 = n_q.cross(e1);
        let flat = |p: DVec3| [(p - h).dot(e1), (p - h).dot(e2)];
        let rim: Vec<[f64; 2]> = c_q
            .iter()
            .map(|&v| flat(self.surface.pos[v as usize]))
            .collect();
        if !crate::planar::inside_polygon([0.0, 0.0], &rim) {
            return Err("Q does not surround the hit point");
        }
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
        // 3. Bridge contours. The paper's C_loc lies in the target's plane; the
        // tilted variant turns it half-way towards C_1sec, for secondaries that
        // leave obliquely. Either way C_loc is lifted until the whole rim lies
        // behind its plane, so the skirt (a height field over the splice plane,
        // below C_loc) and the bands above C_loc cannot meet, and its
        // projection lies strictly inside the rim's.
        let n_loc = if a.tilted {
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
        let loc_flat: Vec<[f64; 2]> = loc.iter().map(|&p| flat(p)).collect();
        let Some(skirt) = crate::planar::triangulate_annulus(&rim, &loc_flat) else {
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
        // Build the bridge tentatively.
        let mark = self.surface.mark();
        for &t in &q {
            self.surface.alive[t as usize] = false;
        }
        let primary_label = self.surface.label[self.surface.tris[target as usize][0] as usize];
        let mut loops: Vec<Vec<u32>> = Vec::with_capacity(contours.len() + 1);
        for (i, c) in contours.iter().enumerate() {
            let label = if i == 0 { primary_label } else { c1.label };
            loops.push(c.iter().map(|&p| self.surface.vertex(p, label)).collect());
        }
        loops.push(tube::ring_loop(&c1));
        let first_tri = self.surface.tris.len() as u32;
        let skirt_vertex = |i: usize| {
            if i < c_q.len() {
                c_q[i]
            } else {
                loops[0][i - c_q.len()]
            }
        };
        for t in &skirt {
            let v = t.map(skirt_vertex);
            self.surface.triangle(v[0], v[1], v[2]);
        }
        for (i, w) in loops.windows(2).enumerate() {
            tube::connect_loops(
                self.surface,
                &w[0],
                &w[1],
                frames[i].center,
                frames[i + 1].center,
            );
        }
        // 4. Proof.
        let removed: Vec<u32> = q.iter().chain(dropped).copied().collect();
        if let Err(why) = self.bridge_is_clear(first_tri, &removed) {
            self.surface.rollback(mark);
            for &t in &q {
                self.surface.alive[t as usize] = true;
            }
            return Err(why);
        }
        self.adopt(first_tri, u32::MAX);
        Ok(())
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
                if o == own || reserved[t as usize] || (o != u32::MAX && !settled[o as usize]) {
                    return;
                }
                let f = surface.tris[t as usize];
                let q =
                    crate::geom::closest_point_on_triangle(p, f.map(|k| surface.pos[k as usize]));
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

    /// Grows Q from `target`; `None` if it cannot be a disk of live, unlocked,
    /// foreign triangles.
    fn grow_region(
        &mut self,
        tube_id: u32,
        target: u32,
        h: DVec3,
        axis: DVec3,
        rho: f64,
    ) -> Option<Vec<u32>> {
        let pad = 2.0 * rho;
        let ext = extent(&tri_box(self.surface, target));
        let query = Aabb::of(&[h.to_array()]).inflated(pad + 2.0 * ext);
        let inside = |t: u32, s: &Surface| -> bool {
            let f = s.tris[t as usize];
            let c = (s.pos[f[0] as usize] + s.pos[f[1] as usize] + s.pos[f[2] as usize]) / 3.0;
            let d = c - h;
            let perp = (d - d.dot(axis) * axis).length();
            perp <= rho && tri_normal(s, t).dot(axis) > 0.1
        };
        // Q only ever grows into `inside` triangles, so only they (and the
        // target) need to be in the local edge → triangles map.
        let mut near: Vec<u32> = vec![target];
        let surface = &*self.surface;
        self.grid.for_each_near(surface, &query, |t| {
            if t != target && inside(t, surface) {
                near.push(t);
            }
        });
        let mut edges: crate::hash::FastMap<(u32, u32), [u32; 2]> = crate::hash::FastMap::default();
        for &t in &near {
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let slot = edges.entry(key).or_insert([u32::MAX; 2]);
                if slot[0] == u32::MAX {
                    slot[0] = t;
                } else {
                    slot[1] = t;
                }
            }
        }
        let mut q = vec![target];
        let mut in_q: crate::hash::FastSet<u32> = crate::hash::FastSet::default();
        in_q.insert(target);
        let mut head = 0;
        while head < q.len() {
            let t = q[head];
            head += 1;
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                let Some(pair) = edges.get(&(a.min(b), a.max(b))) else {
                    continue;
                };
                for &n in pair {
                    if n == u32::MAX || in_q.contains(&n) {
                        continue;
                    }
                    if self.reserved[n as usize] || self.owner[n as usize] == tube_id {
                        continue;
                    }
                    in_q.insert(n);
                    q.push(n);
                }
            }
        }
        Some(q)
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
        let mut uses: crate::hash::FastMap<(u32, u32), (u32, u32)> =
            crate::hash::FastMap::default();
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
                if crate::check::pair_intersects(
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
    let mut hash: crate::hash::FastMap<[i64; 3], Vec<u32>> = crate::hash::FastMap::default();
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
struct Attempt {
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
fn attempts(tube: &Tube) -> Vec<Attempt> {
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
    for k in 1..tube.rings.len().min(40) {
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

fn extent(b: &Aabb) -> f64 {
    (0..3).map(|a| b.hi[a] - b.lo[a]).fold(0.0, f64::max)
}

fn tri_normal(s: &Surface, t: u32) -> DVec3 {
    let f = s.tris[t as usize];
    let (a, b, c) = (
        s.pos[f[0] as usize],
        s.pos[f[1] as usize],
        s.pos[f[2] as usize],
    );
    (b - a).cross(c - a).normalize_or_zero()
}

/// The boundary of a triangle set as one loop of vertices, following the
/// triangles' own edge directions; `None` unless the set is a topological disk
/// (a single simple boundary loop and Euler characteristic 1).
pub fn boundary_loop(s: &Surface, q: &[u32]) -> Option<Vec<u32>> {
    use crate::hash::FastMap as HashMap;
    let mut directed: HashMap<(u32, u32), u32> = HashMap::default();
    for &t in q {
        let f = s.tris[t as usize];
        for e in 0..3 {
            *directed.entry((f[e], f[(e + 1) % 3])).or_insert(0) += 1;
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::default();
    let mut edges_total = 0usize;
    for (&(a, b), &count) in &directed {
        if count > 1 {
            return None; // two triangles run an edge the same way: not oriented
        }
        if directed.contains_key(&(b, a)) {
            if a < b {
                edges_total += 1;
            }
            continue;
        }
        edges_total += 1;
        if next.insert(a, b).is_some() {
            return None; // a vertex with two outgoing boundary edges: a pinch
        }
    }
    let start = *next.keys().min()?;
    let mut lp = vec![start];
    let mut v = next[&start];
    while v != start {
        if lp.len() > next.len() {
            return None;
        }
        lp.push(v);
        v = *next.get(&v)?;
    }
    if lp.len() != next.len() {
        return None; // several boundary loops: Q has a hole
    }
    let mut verts: Vec<u32> = q.iter().flat_map(|&t| s.tris[t as usize]).collect();
    verts.sort_unstable();
    verts.dedup();
    let euler = verts.len() as i64 - edges_total as i64 + q.len() as i64;
    (euler == 1).then_some(lp)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring of `m` vertices about `center`, facing `normal`.
    fn ring_at(s: &mut Surface, center: DVec3, normal: DVec3, radius: f64, m: u32) -> tube::Ring {
        let u = crate::contour::any_perpendicular(normal);
        let first = s.pos.len() as u32;
        for p in crate::contour::ring(center, normal, u, radius, m) {
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
        let lp = boundary_loop(&s, &q).expect("a disk");
        assert_eq!(lp.len(), 6);
        // Two fans sharing nothing: not a disk.
        let two = [q[0], q[3]];
        assert!(boundary_loop(&s, &two).is_none());
        // A ring (annulus) is not a disk either.
        let annulus: Vec<u32> = q[..5].to_vec();
        assert!(
            boundary_loop(&s, &annulus).is_some(),
            "five of six fan triangles are still a disk"
        );
    }
}
