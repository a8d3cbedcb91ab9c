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
//!    [`crate::build::tube::band::connect_loops`].
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
//!   into the nearest surface. The overlap pass (stage 6) then
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
mod fallback;
pub mod index;
mod region;
mod splicer;

pub use splicer::{Join, Splicer};

use crate::build::tube::{self, Tube};
use crate::mesh::NO_OWNER;
use bridge::attempts;

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

impl Splicer<'_> {
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
        tube::cap::cap(self.surface, &tube.rings[0], self.cap_rings, false);
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::surface::Surface;
    use glam::DVec3;

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
        tube::cap::capsule(
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
            tube::band::connect(&mut s, &w[0], &w[1]);
            bands.push(s.tris.len() as u32);
        }
        let (end_cap, _) = tube::cap::cap(&mut s, &rings[3], 2, true);
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
