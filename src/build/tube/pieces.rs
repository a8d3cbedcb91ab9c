//! Building a branch's tube piece by piece, with a guarantee of no
//! self-intersection.
//!
//! The paper keeps a contour when it does not cross its predecessor and
//! connects it to the last kept one. That alone does not stop a tube from
//! running into an earlier, non-adjacent part of itself: a branch that curls
//! back closer than its radius, a thin stretch that passes through a much
//! thicker one, a hairpin. So every band (and every cap) is checked against
//! the earlier bands of its piece before it is kept (`tube::guard`).
//!
//! A band that would collide ends the piece there; the rest of the branch
//! starts a new piece (a separate closed tube now, spliced onto this one like
//! a secondary branch by [`crate::build::splice`]). An end cap that would
//! collide is pulled back one contour at a time.

use std::ops::Range;

use glam::DVec3;

use super::guard::{Guard, Part};
use crate::build::coverage::Skipped;
use crate::build::surface::Surface;
use crate::build::tube::{self, Ring, Tube};
use crate::skeleton::track::{Track, may_follow};

/// How to close a piece's ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Caps {
    /// Cap the start of the branch's first piece (false when it will be
    /// spliced onto something).
    pub first_start: bool,
    /// Cap the start of later pieces (false when they will be spliced).
    pub later_starts: bool,
    /// Rings per start cap (see [`tube::cap::cap`]; 0: flat).
    pub rings: u32,
    /// Rings per end cap.
    pub end_rings: u32,
}

/// What [`build_pieces`] built and found missing.
#[derive(Debug, Default)]
pub struct Pieces {
    /// The tube pieces, in order along the branch.
    pub tubes: Vec<Tube>,
    /// Contours skipped (they would have crossed their predecessor or an
    /// earlier band).
    pub skipped: u32,
    /// The original segments (index of their first point) whose contours
    /// no piece took reach out of what the pieces hold, with the volume left
    /// out, estimated: each gets a filler of its own round cone
    /// ([`crate::build::filler`]).
    pub segments: Vec<Skipped>,
}

/// Builds the tube of one branch into `surface`, starting at track point
/// `first`, as one or more pieces, with what the pieces leave out (see
/// [`Pieces`]).
///
/// `anchor` is the point the first piece grows out of (its branch point, for a
/// secondary); a later piece's anchor is where it split off. A later piece that
/// will be spliced (`caps.later_starts == false`) starts at its first contour
/// clear of the previous piece's volume.
pub fn build_pieces(
    surface: &mut Surface,
    track: &Track,
    labels: &[u32],
    branch: u32,
    first: usize,
    anchor: DVec3,
    caps: Caps,
) -> Pieces {
    let n = track.samples.len();
    let mut radii: Vec<f64> = track.radii.clone();
    radii.sort_by(f64::total_cmp);
    let cell = (4.0 * radii[radii.len() / 2])
        .max(2.0 * track.edge)
        .max(1e-300);
    let mut out = Pieces::default();
    let mut start = first.min(n - 1);
    let mut anchor = anchor;
    loop {
        let cap_start = if out.tubes.is_empty() {
            caps.first_start
        } else {
            caps.later_starts
        };
        let mut piece = Piece::start(surface, track, labels, start, cap_start, caps.rings, cell);
        let split_at = piece.extend(surface, track, labels, &mut out.skipped);
        let end_cap = piece.close(surface, caps.end_rings, &mut out.skipped);
        let last = piece.rings[piece.rings.len() - 1];
        let piece_start = piece.rings[0].resampled as usize;
        // Split only when the rest of the branch is worth a piece of its own;
        // otherwise the contours past the end cap are this piece's to cover.
        let next = split_at.filter(|&k| {
            track.arc[n - 1] - track.arc[k] > track.samples[last.resampled as usize].radius
        });
        let tail = if next.is_some() {
            last.resampled as usize + 1
        } else {
            n
        };
        let dome = cap_height(&last, caps.end_rings);
        let kept: Vec<usize> = piece.rings.iter().map(|r| r.resampled as usize).collect();
        out.segments
            .extend(crate::build::coverage::skipped_segments(
                track, &kept, tail, dome,
            ));
        out.tubes.push(piece.into_tube(branch, end_cap, anchor));
        let Some(next) = next else {
            break;
        };
        // The next piece aims its splice at where this one ends.
        anchor = last.center;
        if caps.later_starts {
            start = next;
            continue;
        }
        match spliced_start(
            track,
            piece_start,
            &last,
            caps.end_rings,
            next,
            &mut out.segments,
        ) {
            Some(k) => start = k,
            None => break,
        }
    }
    out.segments.sort_by_key(|s| s.segment);
    out.segments.dedup_by(|b, a| {
        let same = a.segment == b.segment;
        if same {
            *a = a.merged(*b);
        }
        same
    });
    out
}

/// Where a piece that will be spliced begins after the piece before ended
/// at ring `last` (its first contour at `piece_start`) and would have gone
/// on at track point `next`: at the first contour clear of that piece's
/// volume (its round cones and end cap), if any. The contours between the
/// pieces that reach out of that volume go into `segments`: where the
/// branch turns back on itself (a zig-zag of segments shorter than their
/// radius, a hairpin) they are its only cover, and without a filler most of
/// a segment is lost. What lies outside the next piece's first stretch
/// (four radii along the track) counts too, which covers the gap's end.
fn spliced_start(
    track: &Track,
    piece_start: usize,
    last: &Ring,
    end_rings: u32,
    next: usize,
    segments: &mut Vec<Skipped>,
) -> Option<usize> {
    let n = track.samples.len();
    let mut volume = crate::build::coverage::cones(track, piece_start, last.resampled as usize);
    let h = cap_height(last, end_rings);
    volume.push(crate::kernel::round_cone::RoundCone::sphere(last.center, h));
    let found = crate::build::coverage::first_outside_from(track, next, &volume);
    let after = last.resampled as usize + 1;
    let end = found.unwrap_or(n);
    if let Some(k) = found {
        let reach = track.arc[k] + 4.0 * track.radii[k];
        let far = k + track.arc[k..].partition_point(|&a| a <= reach);
        volume.extend(crate::build::coverage::cones(track, k, far));
    }
    segments.extend(crate::build::coverage::segment_gains(
        track,
        after..end,
        &volume,
    ));
    found
}

/// One piece as it is built: its rings and bands, its start cap, and the
/// guard that keeps its parts apart.
struct Piece {
    guard: Guard,
    first_tri: u32,
    rings: Vec<Ring>,
    /// First triangle of each band.
    bands: Vec<u32>,
    /// The guard's part of each band.
    part_ids: Vec<u32>,
    start_cap: Range<u32>,
    start_cap_vertices: Range<u32>,
    /// The guard's part of the start cap, if there is one.
    start_part: Option<u32>,
}

impl Piece {
    /// A piece at track point `start`: its first ring, capped with `rings`
    /// rings if `cap`.
    fn start(
        surface: &mut Surface,
        track: &Track,
        labels: &[u32],
        start: usize,
        cap: bool,
        rings: u32,
        cell: f64,
    ) -> Piece {
        let first_tri = surface.tris.len() as u32;
        let mut guard = Guard::new(cell);
        let ring0 = tube::place_ring(surface, track, start, track.frames[start], labels);
        let (mut start_cap, mut start_cap_vertices) = (0..0, 0..0);
        let mut start_part = None;
        if cap {
            let (tris, verts) = tube::cap::cap(surface, &ring0, rings, false);
            start_part = Some(guard.add(Part::cap(
                &ring0,
                false,
                cap_height(&ring0, rings),
                tris.clone(),
            )));
            start_cap = tris;
            start_cap_vertices = verts;
        }
        Piece {
            guard,
            first_tri,
            rings: vec![ring0],
            bands: Vec::new(),
            part_ids: Vec::new(),
            start_cap,
            start_cap_vertices,
            start_part,
        }
    }

    /// Adds the contours after the last ring that may follow it, each with
    /// its band, up to the first band that would meet an earlier part of
    /// the piece or a gap of skipped contours too long to bridge: the track
    /// point the piece stops at, if it stops before the track's end.
    /// Contours left out are counted in `skipped`.
    fn extend(
        &mut self,
        surface: &mut Surface,
        track: &Track,
        labels: &[u32],
        skipped: &mut u32,
    ) -> Option<usize> {
        let start = self.rings[0].resampled as usize;
        for k in start + 1..track.samples.len() {
            let last = self.rings[self.rings.len() - 1];
            let j = last.resampled as usize;
            if !may_follow(track, j, k) {
                *skipped += 1;
                let reach =
                    4.0 * track.samples[j].radius.max(track.samples[k].radius) + 2.0 * track.edge;
                if track.arc[k] - track.arc[j] > reach {
                    return Some(k);
                }
                continue;
            }
            let mark = surface.mark();
            let u =
                crate::skeleton::frame::push_forward(last.u, last.normal, track.samples[k].tangent);
            let ring = tube::place_ring(surface, track, k, u, labels);
            let t0 = surface.tris.len() as u32;
            tube::band::connect(surface, &last, &ring);
            let part = Part::band(&last, &ring, t0..surface.tris.len() as u32);
            let neighbour = self.part_ids.last().copied().or(self.start_part);
            if self.guard.collides(surface, &part, neighbour.as_slice()) {
                surface.rollback(mark);
                return Some(k);
            }
            self.part_ids.push(self.guard.add(part));
            self.bands.push(t0);
            self.rings.push(ring);
        }
        None
    }

    /// The end cap with `end_rings` rings, pulled back one contour at a time
    /// while it would meet an earlier band (each contour given up counted
    /// in `skipped`): its triangles.
    fn close(&mut self, surface: &mut Surface, end_rings: u32, skipped: &mut u32) -> Range<u32> {
        loop {
            let last = self.rings[self.rings.len() - 1];
            let mark = surface.mark();
            let (tris, _) = tube::cap::cap(surface, &last, end_rings, true);
            let part = Part::cap(&last, true, cap_height(&last, end_rings), tris.clone());
            let mut skip: Vec<u32> = self.part_ids.last().copied().into_iter().collect();
            if self.rings.len() == 1 {
                skip.extend(self.start_part);
            }
            if self.rings.len() == 1 || !self.guard.collides(surface, &part, &skip) {
                return tris;
            }
            // Drop the last ring and its band (they are the newest vertices and
            // triangles before the cap) and try again one contour earlier.
            surface.rollback(mark);
            let band_start = self.bands.pop().expect("a band per ring after the first");
            let ring = self.rings.pop().expect("more than one ring");
            surface.rollback(crate::build::surface::Mark {
                vertices: ring.first as usize,
                triangles: band_start as usize,
            });
            self.guard.pop();
            self.part_ids.pop();
            *skipped += 1;
        }
    }

    /// The finished piece, closed by `end_cap`, growing out of `anchor`.
    fn into_tube(mut self, branch: u32, end_cap: Range<u32>, anchor: DVec3) -> Tube {
        self.bands.push(end_cap.start);
        Tube {
            branch,
            rings: self.rings,
            bands: self.bands,
            start_cap: self.start_cap,
            end_cap: end_cap.clone(),
            start_cap_vertices: self.start_cap_vertices,
            tris: self.first_tri..end_cap.end,
            anchor,
        }
    }
}

/// Height of the dome [`tube::cap::cap`] builds on `ring` (its enlarged radius).
fn cap_height(ring: &Ring, rings: u32) -> f64 {
    crate::skeleton::contour::polygon_radius(ring.radius, 4 * (rings + 1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::BuildStats;
    use crate::params::Params;

    const CAPS: Caps = Caps {
        first_start: true,
        later_starts: true,
        rings: 3,
        end_rings: 3,
    };

    fn build(pts: &[DVec3], radii: &[f64]) -> (Vec<Tube>, crate::mesh::Mesh) {
        let track = Track::new(pts, radii, &Params::DEFAULT, None);
        let mut s = Surface::default();
        let labels: Vec<u32> = (0..pts.len() as u32).collect();
        let tubes = build_pieces(&mut s, &track, &labels, 0, 0, pts[0], CAPS).tubes;
        (tubes, s.into_mesh(BuildStats::default()))
    }

    fn assert_pieces_sound(mesh: &crate::mesh::Mesh) {
        let r = mesh.view().check_topology();
        assert!(r.is_closed() && r.is_manifold() && r.is_outward(), "{r}");
        let comp = crate::kernel::disjoint_sets::face_components(&mesh.faces, mesh.vertices.len());
        let inside = crate::measure::check::self_intersections(&mesh.view())
            .into_iter()
            .filter(|p| comp[p[0] as usize] == comp[p[1] as usize])
            .count();
        assert_eq!(inside, 0);
    }

    #[test]
    fn straight_tube_is_one_piece() {
        let pts: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(f64::from(i) * 2.0, 0.0, 0.0))
            .collect();
        let (tubes, mesh) = build(&pts, &[1.0; 5]);
        assert_eq!(tubes.len(), 1);
        assert_pieces_sound(&mesh);
        assert_eq!(mesh.check().euler_characteristic, 2);
    }

    #[test]
    fn a_loop_closing_on_itself_splits() {
        // A circle of radius 3 with a tube of radius 1, going round 1.1 times.
        let pts: Vec<DVec3> = (0..=40)
            .map(|i| {
                let t = f64::from(i) / 40.0 * std::f64::consts::TAU * 1.1;
                DVec3::new(3.0 * t.cos(), 3.0 * t.sin(), 0.0)
            })
            .collect();
        let (tubes, mesh) = build(&pts, &vec![1.0; pts.len()]);
        assert!(tubes.len() >= 2);
        assert_pieces_sound(&mesh);
    }

    #[test]
    fn hairpin_splits_into_pieces() {
        let mut pts: Vec<DVec3> = (0..10)
            .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
            .collect();
        pts.push(DVec3::new(9.5, 0.5, 0.0));
        pts.extend((0..10).map(|i| DVec3::new(9.0 - f64::from(i), 1.0, 0.0)));
        let (tubes, mesh) = build(&pts, &vec![1.0; pts.len()]);
        assert!(tubes.len() >= 2);
        assert_pieces_sound(&mesh);
    }

    #[test]
    fn radius_exploding_over_a_short_distance() {
        // Radii from a real file whose radius column holds codes (40 → 2765 over 1.2 units).
        let pts = [
            DVec3::new(116.43106, 123.68894, 26.68),
            DVec3::new(116.49914, 123.97046, 26.68),
            DVec3::new(116.60678, 124.41758, 26.68),
            DVec3::new(116.71488, 124.86470, 26.68),
        ];
        let (_, mesh) = build(&pts, &[40.0, 692.1, 1728.4, 2764.7]);
        assert_pieces_sound(&mesh);
    }

    #[test]
    fn thin_stretch_passing_a_thick_point() {
        // A fat point followed by a thin path that swings back past it.
        let pts = [
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(6.0, 3.0, 0.0),
            DVec3::new(3.0, 5.0, 0.0),
            DVec3::new(-1.0, 6.0, 0.0),
        ];
        let (_, mesh) = build(&pts, &[9.0, 0.05, 0.05, 0.05, 0.05]);
        assert_pieces_sound(&mesh);
    }
}
