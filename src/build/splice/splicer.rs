//! The splicer's state: the surface being spliced, which part each of its
//! triangles belongs to, the index of the triangles near the junctions, and
//! the queries every junction method asks of them.

use glam::DVec3;

use super::index::TriangleGrid;
use crate::build::surface::Surface;
use crate::build::tube::{Ring, Tube};
use crate::kernel::bvh::Aabb;
use crate::mesh::NO_OWNER;

/// A tube to attach to the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Join {
    /// Index of the tube in the tube list; its start is open.
    pub tube: u32,
    /// The point the ray aims at: the branch point (or where a piece split off).
    pub toward: DVec3,
}

/// State shared by the junctions of one mesh.
pub struct Splicer<'a> {
    pub(super) surface: &'a mut Surface,
    pub(super) grid: TriangleGrid,
    /// Tube of each triangle ([`NO_OWNER`] for bridges).
    pub(super) owner: Vec<u32>,
    /// Triangles no Q may take: the first band of every tube whose start is
    /// still open, since its ring borders a hole its own junction will fill.
    pub(super) reserved: Vec<bool>,
    pub(super) cap_rings: u32,
    /// Tubes already part of their tree's surface: those without a join, and
    /// those whose join is done. A junction may only land on these (or on
    /// bridges and somas): landing on a tube still waiting for its own join
    /// could close a loop of tubes joined only to each other.
    pub(super) settled: Vec<bool>,
    /// Why attempts failed, for diagnostics.
    pub failures: std::collections::BTreeMap<&'static str, u32>,
    /// The triangle ranges of the bridges, extensions and connectors, each
    /// proven (or built) not to cross itself: each becomes a part of its own
    /// for the overlap pass, which then never compares a bridge with itself.
    pub(super) units: Vec<[u32; 2]>,
    pub(super) tube_count: u32,
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

    /// A point `depth` times `r0`'s radius beyond the surface point nearest to
    /// `r0`'s centre (other than its own tube's), within `reach` of it
    /// (usually [`reach_toward`]): just inside that surface, seen from the ring.
    pub(super) fn inside_nearest(
        &mut self,
        tube_id: u32,
        r0: &Ring,
        reach: f64,
        depth: f64,
    ) -> Option<DVec3> {
        let q = self.nearest_surface_point(tube_id, r0.center, r0.radius, reach)?;
        let way = (q - r0.center).normalize_or_zero();
        (way != DVec3::ZERO).then(|| q + way * (depth * r0.radius))
    }

    /// The largest distance from `p` to a vertex of the surface: the reach
    /// that finds any surface there is.
    pub(super) fn extent_from(&self, p: DVec3) -> f64 {
        self.surface
            .pos
            .iter()
            .map(|q| q.distance_squared(p))
            .fold(0.0, f64::max)
            .sqrt()
    }

    /// Distance from `p` to the nearest surface other than the tube's own,
    /// looked for within four of `r0`'s radii (`r0`'s radius if none).
    pub(super) fn clearance(&mut self, tube_id: u32, r0: &Ring, p: DVec3) -> f64 {
        self.nearest_surface_point(tube_id, p, r0.radius, 4.0 * r0.radius)
            .map_or(r0.radius, |q| q.distance(p))
    }

    /// Registers triangles from `first` to the end of the surface.
    pub(super) fn adopt(&mut self, first: u32, owner: u32) {
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
    pub(super) fn release(&mut self, tube: &Tube) {
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
    pub(super) fn nearest_surface_point(
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
pub(super) fn first_band(surface: &Surface, tube: &Tube) -> Vec<u32> {
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
pub(super) fn reach_toward(r0: &Ring, toward: DVec3) -> f64 {
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
