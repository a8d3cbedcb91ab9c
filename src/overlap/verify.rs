//! The proof that a try of the overlap pass is sound (step 4 of
//! [`crate::overlap`]): the kept faces close up along every cut, and in the
//! f32 output (the cut rounds its new vertices at once) no kept piece of a
//! cut face crosses another piece or a face left as it was.
//!
//! A try whose proof fails leaves the clusters at fault uncut, and the next
//! try is proven again. Between two tries only a few clusters change, and
//! a whole proof costs as much as the tries' other work: [`Proven`] keeps
//! what the tests already showed.

use crate::kernel::bits::Bits;
use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::hash::FastMap;
use crate::kernel::vector::{P3, V3, at};

/// The old faces around the pieces, for [`prove`]: the round's runs and
/// their BVH, and whether an old face is in a cluster.
pub(crate) struct Near<'a> {
    pub runs: &'a [std::ops::Range<u32>],
    pub bvh: &'a Bvh,
    pub in_cluster: &'a Bits,
}

/// What the proofs of a round's earlier tries showed: the faces kept when
/// each test last ran to its end.
///
/// A pair of faces kept then and kept now was tested then. Had it crossed,
/// the test named the old face of its piece (both pieces, for two pieces),
/// the cluster of that face was left uncut, and its pieces are gone now. So
/// a later test only needs the pairs with a face kept since; it finds the
/// same faces at fault as a test of every pair. Likewise the edges and fans
/// at a new vertex are made of its cluster's pieces alone: a cluster none
/// of whose pieces was kept or dropped since passed then, or it would have
/// been left uncut.
#[derive(Debug, Default)]
pub(crate) struct Proven {
    /// The faces kept when the edges and fans at new vertices were tested.
    edges: Option<Bits>,
    /// The faces kept when the pieces were last tested against each other.
    pieces: Option<Bits>,
    /// The faces kept when the pieces were last tested against old faces.
    old_faces: Option<Bits>,
}

impl Proven {
    /// Whether a test has run to its end.
    pub(crate) fn has_tested(&self) -> bool {
        self.edges.is_some()
    }
}

/// Checks the kept faces around the new vertices: every edge there shared by
/// two kept faces in opposite directions, one fan per vertex, no sliver, and,
/// in f32, no two kept pieces crossing each other and no kept
/// piece crossing an old face outside the clusters (of whatever part: a piece
/// of a tube that crosses a face of its own tube is caught here too). On
/// failure, the old faces at fault (`origin_of` names the old face of a
/// piece).
///
/// Each test only looks at what a change of verdicts since it last ran to
/// its end in this round can have changed (`proven`, updated here): the
/// edges and fans of the clusters with a piece kept or dropped since, the
/// crossing pairs with a face kept since. See [`Proven`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn prove(
    faces: &[[u32; 3]],
    kept: &[bool],
    all_pos: &[V3],
    first_piece: usize,
    n_old: u32,
    origin_of: &(impl Fn(usize) -> u32 + Sync),
    piece_cluster: &[u32],
    near: &Near,
    proven: &mut Proven,
) -> Result<(), (&'static str, Vec<u32>)> {
    let proof = Proof {
        faces,
        kept,
        all_pos,
        first_piece,
        origin_of,
        near,
        pieces: (first_piece..faces.len())
            .filter(|&f| kept[f])
            .map(|f| f as u32)
            .collect(),
    };
    let mut bad = proof.edges_and_fans(n_old, piece_cluster, proven.edges.as_ref());
    let mut why = "the kept faces are not manifold along a cut";
    // The same flags for each test that runs to its end.
    let kept_now = Bits::of_flags(kept);
    proven.edges = Some(kept_now.clone());
    if bad.is_empty() {
        bad = proof.slivers();
        why = "a cut face's piece is a sliver";
    }
    if bad.is_empty() {
        bad = proof.pieces_crossing(proven.pieces.as_ref());
        proven.pieces = Some(kept_now.clone());
        why = "rounded to f32, two kept pieces cross";
    }
    if bad.is_empty() {
        bad = proof.pieces_crossing_old(proven.old_faces.as_ref());
        proven.old_faces = Some(kept_now);
        why = "rounded to f32, a kept piece crosses a face";
    }
    if bad.is_empty() {
        return Ok(());
    }
    bad.sort_unstable();
    bad.dedup();
    Err((why, bad))
}

/// What one proof reads.
struct Proof<'a, O> {
    faces: &'a [[u32; 3]],
    kept: &'a [bool],
    all_pos: &'a [V3],
    first_piece: usize,
    origin_of: &'a O,
    near: &'a Near<'a>,
    /// The kept pieces, in order.
    pieces: Vec<u32>,
}

impl<O: Fn(usize) -> u32 + Sync> Proof<'_, O> {
    /// Face `f` as the output holds it (the vertices are f32).
    fn tri(&self, f: u32) -> [P3; 3] {
        self.faces[f as usize].map(|k| at(self.all_pos, k))
    }

    /// A BVH over the triangles of `which`.
    fn bvh_of(&self, which: &[u32]) -> Bvh {
        Bvh::new(which.iter().map(|&f| Aabb::of(&self.tri(f))).collect())
    }

    /// Whether faces `a` and `b` cross.
    fn crossing(&self, a: u32, b: u32) -> bool {
        crate::kernel::predicates::pair_intersects(
            self.faces[a as usize],
            self.faces[b as usize],
            self.tri(a),
            self.tri(b),
        )
    }

    /// The old face piece `f` is part of.
    fn origin(&self, f: u32) -> u32 {
        (self.origin_of)(f as usize)
    }

    /// The old faces around the new vertices (from `n_old` on) where an edge
    /// is not shared by two kept faces in opposite directions, or the kept
    /// faces around a vertex are not one fan. Only the clusters with a
    /// piece kept or dropped since the faces `before` were kept are looked at.
    fn edges_and_fans(&self, n_old: u32, piece_cluster: &[u32], before: Option<&Bits>) -> Vec<u32> {
        let (faces, kept, first_piece) = (self.faces, self.kept, self.first_piece);
        let is_new = |v: u32| v >= n_old;
        let mut uses: FastMap<(u32, u32), (u32, u32)> = FastMap::default();
        // Around each new vertex: (next, previous) vertex and face of each kept face.
        let mut fan: FastMap<u32, Vec<(u32, u32, u32)>> = FastMap::default();
        // The edges and fans at a new vertex are those of its cluster's pieces:
        // only clusters with a piece kept or dropped since the last test are
        // tested again.
        let changed: Option<Vec<bool>> = before.map(|before| {
            let n = piece_cluster.iter().max().map_or(0, |&c| c as usize + 1);
            let mut changed = vec![false; n];
            for f in first_piece..faces.len() {
                if kept[f] != before.has(f as u32) {
                    changed[piece_cluster[f - first_piece] as usize] = true;
                }
            }
            changed
        });
        for &f in &self.pieces {
            if changed
                .as_ref()
                .is_some_and(|c| !c[piece_cluster[f as usize - first_piece] as usize])
            {
                continue;
            }
            let face = faces[f as usize];
            for e in 0..3 {
                let (a, b) = (face[e], face[(e + 1) % 3]);
                if !(is_new(a) || is_new(b)) {
                    continue;
                }
                let u = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    u.0 += 1;
                } else {
                    u.1 += 1;
                }
                if is_new(a) {
                    fan.entry(a).or_default().push((b, face[(e + 2) % 3], f));
                }
            }
        }
        // The old faces around new vertex `v`.
        let around = |v: u32| -> Vec<u32> {
            fan.get(&v)
                .map(|x| x.iter().map(|t| self.origin(t.2)).collect())
                .unwrap_or_default()
        };
        let mut bad: Vec<u32> = uses
            .iter()
            .filter(|(_, u)| **u != (1, 1))
            .flat_map(|(e, _)| around(if is_new(e.0) { e.0 } else { e.1 }))
            .collect();
        // Two fans touching at a vertex pass the edge test: walk each vertex's
        // faces from one to the next across shared edges; all must be reached.
        for (&v, ring) in &fan {
            let (start, _, _) = ring[0];
            let mut next = start;
            let mut steps = 0;
            // The face whose previous vertex is `next` follows.
            while let Some(&(n, _, _)) = ring.iter().find(|x| x.1 == next) {
                next = n;
                steps += 1;
                if next == start || steps > ring.len() {
                    break;
                }
            }
            if steps != ring.len() {
                bad.extend(around(v));
            }
        }
        bad
    }

    /// The old faces of kept pieces the checker would call degenerate (as
    /// `check` measures it).
    fn slivers(&self) -> Vec<u32> {
        use crate::kernel::vector::{cross, dot, sub};
        let mut bad = Vec::new();
        for &f in &self.pieces {
            let [a, b, c] = self.tri(f);
            let (e1, e2, e3) = (sub(b, a), sub(c, a), sub(c, b));
            let longest = dot(e1, e1).max(dot(e2, e2)).max(dot(e3, e3));
            let n = cross(e1, e2);
            if dot(n, n).sqrt() <= 1e-9 * longest {
                bad.push(self.origin(f));
            }
        }
        bad
    }

    /// The old faces of kept pieces that cross each other, rounded to f32;
    /// with `before`, only the pairs with a piece kept since then.
    ///
    /// The pieces of one face clear each other: they are a triangulation of
    /// its rounded points projected to a plane (see
    /// [`super::retriangulate`]), and two lifted triangles can only meet
    /// where their projections do, at a shared vertex or edge.
    fn pieces_crossing(&self, before: Option<&Bits>) -> Vec<u32> {
        let pieces = &self.pieces;
        let apart = |a: u32, b: u32| self.origin(a) != self.origin(b);
        let pairs: Vec<[u32; 2]> = match before {
            None => {
                let bvh = self.bvh_of(pieces);
                bvh.overlapping_pairs(|i, j| {
                    let (a, b) = (pieces[i as usize], pieces[j as usize]);
                    apart(a, b) && self.crossing(a, b)
                })
                .into_iter()
                .map(|[i, j]| [pieces[i as usize], pieces[j as usize]])
                .collect()
            }
            Some(before) => {
                let fresh = before.not_in(pieces);
                let bvh = self.bvh_of(&fresh);
                crate::kernel::parallel::flat_map_range(pieces.len(), |k| {
                    let a = pieces[k];
                    let a_fresh = !before.has(a);
                    let mut out = Vec::new();
                    bvh.for_each_overlap(&Aabb::of(&self.tri(a)), |i| {
                        let b = fresh[i as usize];
                        // A pair of two fresh pieces is tested from its first.
                        if !(a_fresh && b <= a) && apart(a, b) && self.crossing(a, b) {
                            out.push([a, b]);
                        }
                    });
                    out
                })
            }
        };
        pairs.iter().flatten().map(|&p| self.origin(p)).collect()
    }

    /// Whether kept old face `b` is left as it was (in no cluster).
    fn outside(&self, b: u32) -> bool {
        self.kept[b as usize] && !self.near.in_cluster.has(b)
    }

    /// The old faces of kept pieces that cross an old face left as it was,
    /// rounded to f32; with `before`, only the pairs with a face kept since
    /// then. The old faces sit in the round's BVH at their own (f32)
    /// coordinates.
    fn pieces_crossing_old(&self, before: Option<&Bits>) -> Vec<u32> {
        let pieces = &self.pieces;
        let hits = match before {
            None => self.crossing_old(pieces),
            Some(before) => {
                // Pieces kept since, against every old face; the other
                // pieces, against the old faces kept since.
                let fresh = before.not_in(pieces);
                let mut hits = self.crossing_old(&fresh);
                let fresh_old: Vec<u32> = (0..self.first_piece as u32)
                    .filter(|&b| self.outside(b) && !before.has(b))
                    .collect();
                if !fresh_old.is_empty() {
                    let bvh = self.bvh_of(&fresh_old);
                    hits.extend(crate::kernel::parallel::flat_map_range(pieces.len(), |k| {
                        let p = pieces[k];
                        let mut hit = false;
                        if before.has(p) {
                            bvh.for_each_overlap(&Aabb::of(&self.tri(p)), |i| {
                                hit = hit || self.crossing(p, fresh_old[i as usize]);
                            });
                        }
                        if hit { vec![p] } else { Vec::new() }
                    }));
                }
                hits
            }
        };
        hits.iter().map(|&p| self.origin(p)).collect()
    }

    /// The pieces of `pieces` (kept, in order) that cross an old face left as
    /// it was, one piece named per old face they were cut from. The pieces of
    /// one old face are consecutive: the old faces near them are looked up
    /// once, with the box of all of them.
    fn crossing_old(&self, pieces: &[u32]) -> Vec<u32> {
        let near = self.near;
        let mut groups: Vec<std::ops::Range<usize>> = Vec::new();
        for k in 0..pieces.len() {
            match groups.last_mut() {
                Some(g) if self.origin(pieces[g.start]) == self.origin(pieces[k]) => {
                    g.end = k + 1;
                }
                _ => groups.push(k..k + 1),
            }
        }
        crate::kernel::parallel::flat_map_range(groups.len(), |g| {
            let group = &pieces[groups[g].clone()];
            let mut bounds = Aabb::EMPTY;
            for &p in group {
                bounds.add(&Aabb::of(&self.tri(p)));
            }
            let mut near_faces: Vec<(u32, Aabb)> = Vec::new();
            near.bvh.for_each_overlap(&bounds, |i| {
                for b in near.runs[i as usize].clone() {
                    if !self.outside(b) {
                        continue;
                    }
                    let bb = Aabb::of(&self.tri(b));
                    if bb.overlaps(&bounds) {
                        near_faces.push((b, bb));
                    }
                }
            });
            if near_faces.is_empty() {
                return Vec::new();
            }
            let hit = group.iter().any(|&p| {
                let bp = Aabb::of(&self.tri(p));
                near_faces
                    .iter()
                    .any(|(b, bb)| bp.overlaps(bb) && self.crossing(p, *b))
            });
            if hit { vec![group[0]] } else { Vec::new() }
        })
    }
}
