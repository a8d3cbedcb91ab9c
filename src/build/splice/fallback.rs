//! The fallback junctions, where no splice of the paper's kind is valid:
//! the tube's start reaches back into the surface it grows from, or, capped,
//! is joined to the nearest surface by a thin capsule.

use glam::DVec3;

use super::splicer::{Splicer, reach_toward};
use crate::build::tube::{self, Ring, Tube};
use crate::mesh::NO_OWNER;

impl Splicer<'_> {
    /// The last fallback, for a capped start: a capsule from inside the cap to
    /// just inside the surface nearest to the start, thinner than both, which
    /// the overlap pass merges with them. False (nothing built) without a
    /// surface in reach.
    pub(super) fn connector(&mut self, tube_id: u32, tube: &Tube, toward: DVec3) -> bool {
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
        tube::cap::capsule(
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
    pub(super) fn reach_back(&mut self, tube_id: u32, tube: &Tube, toward: DVec3) -> bool {
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
        let mut rings: Vec<Ring> = Vec::with_capacity(steps as usize + 1);
        for k in 0..steps {
            let t = f64::from(k) / f64::from(steps);
            let center = end + t * (r0.center - end);
            let scale = (r_end + t * (r0.radius - r_end)) / r0.radius;
            let first = self.surface.pos.len() as u32;
            for w in &offsets {
                self.surface.vertex(center + scale * *w, r0.label);
            }
            rings.push(Ring {
                center,
                first,
                radius: scale * r0.radius,
                ..r0
            });
        }
        rings.push(r0);
        for w in rings.windows(2) {
            let (a, b) = (tube::band::ring_loop(&w[0]), tube::band::ring_loop(&w[1]));
            tube::band::connect_loops_about(
                self.surface,
                &a,
                &b,
                w[0].center,
                w[1].center,
                r0.normal,
            );
        }
        tube::cap::cap(self.surface, &rings[0], self.cap_rings, false);
        true
    }
}
