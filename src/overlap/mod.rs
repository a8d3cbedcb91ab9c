//! Resolving overlaps: the finished mesh made the boundary of its own union.
//!
//! The tube, splice and soma stages each build closed, outward surfaces whose
//! parts do not cross *themselves*, but two parts can still cross each other:
//! branches of the skeleton that pass through one another (a Purkinje cell has
//! hundreds of such places), a sibling running inside its parent, a branch
//! that a junction could not join (capped, left inside its parent). The
//! membrane is the boundary of the union of all of them, so this pass computes
//! that boundary exactly where parts cross:
//!
//! 1. **Crossings.** Pairs of faces of different parts that intersect, found
//!    through a BVH over runs of consecutive faces of one part (faces of one
//!    tube piece, and of one bridge, are proven not to cross each other when
//!    it is built, so pairs inside one part are never tested).
//! 2. **Cuts.** Every edge that pierces a face gives one new vertex, shared by
//!    both faces on the edge and by the pierced face; each crossing pair gives
//!    one cut segment in both faces ([`crate::overlap::cut`]). Each cut face is
//!    re-triangulated in its own plane by the constrained Delaunay
//!    triangulation of its split edges and cut segments: split along the
//!    cuts and ear-clipped where they run straight across it (nearly every
//!    cut face), with spade otherwise ([`crate::overlap::retriangulate`]).
//! 3. **Patches.** Faces connected without crossing a cut form patches. A patch
//!    is kept when a point of it lies outside every *other* part: the winding
//!    number of the rest of the surface there is 0 (counted along one ray
//!    that passes clear of every face's border, or else by three rays that
//!    vote). That is exactly the union's boundary; once anything is cut, it
//!    also drops parts wholly inside others.
//! 4. **Proof.** Every edge at a new vertex must be shared by exactly two kept
//!    faces running it in opposite directions, and once the new vertices are
//!    rounded to the f32 output the kept pieces of cut faces must cross
//!    neither each other nor any face left as it was, of whatever part.
//!    Crossing pairs are grouped into clusters (one intersection curve each);
//!    a cluster that fails (a degenerate contact, a rounding flip) is left as
//!    it was while the others are cut.
//! 5. **Nudges.** A contact is degenerate because f32 coordinates put points
//!    exactly on each other's planes (tubes of one radius traced on a grid, a
//!    flat cell with z = 0): the vertices of the faces at fault (the cut and
//!    the proof name them all along a cluster) move by at most `NUDGE` of
//!    their shortest edge, which puts them in general position. A cluster
//!    whose cut is refused is nudged and cut again at once, before the
//!    patches (up to three times, in `settle.rs`); clusters still refused,
//!    and those the proof leaves uncut, are nudged and the pass runs again
//!    on its own output, up to `ROUNDS` times. The report counts the
//!    crossing pairs still left after the last.

mod assembly;
mod boundary;
pub mod cut;
pub mod cut_memo;
mod faces;
mod pairs;
mod patches;
pub mod retriangulate;
mod settle;
mod verify;

use crate::kernel::vector::V3;
use crate::mesh::{Mesh, NO_OWNER};
use boundary::union;
use faces::{nudge, parts_of, vertices_of};
use pairs::{crossing_pairs, crossing_pairs_at};
use settle::{Index, cut_with_nudges};

/// What the pass did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outcome {
    /// Intersecting pairs of faces of different parts found.
    pub pairs: u32,
    /// Pairs still in the mesh (0 when the union was built).
    pub pairs_left: u32,
    /// Why the union was not built, if it was not.
    pub failure: Option<&'static str>,
}

/// Rounds of the pass: after a round that leaves crossings uncut (their
/// contact is degenerate or its pieces round badly), the vertices of the
/// faces at fault are nudged and the pass runs again on its own output. The
/// cut and the proof name every face at fault in a cluster, not just the
/// first, so a flat or grid-aligned cell (degenerate contacts all along a
/// curve) is moved in one go, and a large cluster is not shaken into new
/// trouble elsewhere.
const ROUNDS: usize = 6;

/// What [`resolve`] tells besides the mesh.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// What the pass did.
    pub outcome: Outcome,
    /// The part of each face of the result.
    pub owner: Vec<u32>,
    /// The parts of the faces in crossing pairs still left, sorted, once
    /// each (empty when the union was built).
    pub left_parts: Vec<u32>,
}

/// Replaces `mesh` by the boundary of its union where its parts cross.
/// `owner[f]` is the part of face `f` ([`NO_OWNER`] for faces to compare with
/// everything; owners of the wrong length count as all [`NO_OWNER`]). Where
/// a crossing cannot be cut, its faces are left as they were (see the module
/// docs). The owners are taken rather than copied: a copy would add to the
/// pass's peak memory.
pub fn resolve(mesh: &mut Mesh, owner: Vec<u32>) -> Resolved {
    let mut owner = owner;
    if owner.len() != mesh.faces.len() {
        owner = vec![NO_OWNER; mesh.faces.len()];
    }
    let mut out = Outcome::default();
    // After the first round, crossings can only involve a face of a cluster
    // left uncut or at a vertex the nudge moved: every other old face kept
    // its f32 corners, and its crossings were all cut; and the round's proof
    // showed that its pieces cross neither each other nor any old face outside
    // the clusters (a piece crossing a face left uncut is found from that face).
    let mut dirty: Option<Vec<u32>> = None;
    let mut left_parts = Vec::new();
    for round in 0..ROUNDS {
        let once = resolve_once(mesh, &mut owner, round, dirty.as_deref());
        if round == 0 {
            out.pairs = once.outcome.pairs;
        }
        out.pairs_left = once.outcome.pairs_left;
        out.failure = once.outcome.failure;
        left_parts = once.left_parts;
        if once.stuck.is_empty() || round + 1 == ROUNDS {
            break;
        }
        nudge(mesh, &once.stuck, round as u64);
        let mut next = once.dirty;
        next.extend_from_slice(&once.stuck);
        next.sort_unstable();
        next.dedup();
        dirty = Some(next);
    }
    Resolved {
        outcome: out,
        owner,
        left_parts,
    }
}

/// What one round did and left to the next.
struct Round {
    outcome: Outcome,
    /// The vertices to nudge: of the faces at fault (every refusal and
    /// every failed proof names them).
    stuck: Vec<u32>,
    /// The vertices of faces that may still cross something: those of the
    /// clusters left uncut.
    dirty: Vec<u32>,
    /// The parts of the faces of the clusters left uncut ([`Resolved`]).
    left_parts: Vec<u32>,
}

/// One round; with `dirty` (vertices), only faces at one of them are looked
/// at for crossings.
fn resolve_once(
    mesh: &mut Mesh,
    owner: &mut Vec<u32>,
    round: usize,
    dirty: Option<&[u32]>,
) -> Round {
    // Through the round the vertices are `pos`, taken from the mesh (where
    // the union's assembly or a round without crossings puts them back),
    // read in f64 where they are used. New vertices go after them, a few
    // per cent at most, reserved at once so that growing never copies the
    // array; later rounds append few.
    let mut pos: Vec<V3> = std::mem::take(&mut mesh.vertices);
    pos.reserve_exact(pos.len() / 8);
    let mut index = Index::new(&pos, &mesh.faces, owner);
    let pairs = match dirty {
        None => crossing_pairs(&pos, &mesh.faces, owner, &index.runs, &index.bvh),
        Some(d) => crossing_pairs_at(&pos, &mesh.faces, owner, &index.runs, &index.bvh, d),
    };
    let mut out = Outcome {
        pairs: pairs.len() as u32,
        pairs_left: pairs.len() as u32,
        failure: None,
    };
    if pairs.is_empty() {
        mesh.vertices = pos;
        return Round {
            outcome: out,
            stuck: Vec::new(),
            dirty: Vec::new(),
            left_parts: Vec::new(),
        };
    }
    let cut = cut_with_nudges(mesh, owner, &mut pos, &mut index, pairs, round);
    match union(mesh, owner, pos, &cut, index) {
        Ok(built) => {
            out.pairs_left = built.pairs_left;
            out.failure = built.failure;
            *owner = built.owner;
            Round {
                outcome: out,
                stuck: built.stuck,
                dirty: built.dirty,
                left_parts: built.left_parts,
            }
        }
        Err((why, culprits)) => {
            out.failure = Some(why);
            out.pairs_left = cut.pairs.len() as u32;
            let all: Vec<u32> = cut.pairs.iter().flatten().copied().collect();
            let left_parts = parts_of(owner, &all);
            let dirty = vertices_of(&mesh.faces, &all);
            let stuck = vertices_of(&mesh.faces, &culprits);
            debug_assert!(!stuck.is_empty(), "a refusal names its faces");
            Round {
                outcome: out,
                stuck,
                dirty,
                left_parts,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::pairs::run_boxes;
    use super::*;
    use crate::kernel::bvh::Bvh;
    use crate::mesh::tests::cube;

    /// The pass on `m` with a copy of `owner`, and what it did.
    fn resolved(m: &mut Mesh, owner: &[u32]) -> Outcome {
        resolve(m, owner.to_vec()).outcome
    }

    /// Two unit cubes, the second moved by `d`, as one mesh with two parts.
    fn two_cubes(d: [f32; 3]) -> (Mesh, Vec<u32>) {
        let mut m = cube();
        let mut other = cube();
        for v in &mut other.vertices {
            for (c, s) in v.iter_mut().zip(d) {
                *c += s;
            }
        }
        m.append(&other);
        let owner = (0..m.faces.len() as u32).map(|f| f / 12).collect();
        (m, owner)
    }

    #[test]
    fn crossing_cubes_become_their_union() {
        let d = [0.3, 0.4, 0.45];
        let (mut m, owner) = two_cubes(d);
        let out = resolved(&mut m, &owner);
        assert!(out.pairs > 0 && out.pairs_left == 0, "{out:?}");
        let r = m.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        // Exact: 2 − (1 − 0.3)(1 − 0.4)(1 − 0.45).
        let overlap = (1.0 - 0.3) * (1.0 - 0.4) * (1.0 - 0.45);
        assert!(
            (m.volume() - (2.0 - overlap)).abs() < 1e-6,
            "{}",
            m.volume()
        );
        let area = 12.0 - 2.0 * (0.7 * 0.6 + 0.6 * 0.55 + 0.7 * 0.55);
        assert!((m.area() - area).abs() < 1e-6, "{}", m.area());
    }

    #[test]
    fn the_search_at_marked_vertices_finds_the_pairs_at_them() {
        let (m, owner) = two_cubes([0.3, 0.4, 0.45]);
        let pos: Vec<V3> = m.vertices.clone();
        let (runs, boxes) = run_boxes(&pos, &m.faces, &owner);
        let bvh = Bvh::new(boxes);
        let all = crossing_pairs(&pos, &m.faces, &owner, &runs, &bvh);
        assert!(!all.is_empty());
        let every: Vec<u32> = (0..pos.len() as u32).collect();
        assert_eq!(
            crossing_pairs_at(&pos, &m.faces, &owner, &runs, &bvh, &every),
            all
        );
        // Only the corner of the second cube inside the first: its faces' pairs.
        let corner = 8;
        let some = crossing_pairs_at(&pos, &m.faces, &owner, &runs, &bvh, &[corner]);
        let at = |f: u32| m.faces[f as usize].contains(&corner);
        let want: Vec<[u32; 2]> = all
            .iter()
            .copied()
            .filter(|p| at(p[0]) || at(p[1]))
            .collect();
        assert!(!want.is_empty());
        assert_eq!(some, want);
    }

    #[test]
    fn coplanar_faces_are_nudged_apart_and_joined() {
        // Four faces of each cube lie in the planes of the other's: no
        // crossing is in general position until the nudge.
        let (mut m, owner) = two_cubes([0.5, 0.0, 0.0]);
        let out = resolved(&mut m, &owner);
        assert!(out.pairs > 0 && out.pairs_left == 0, "{out:?}");
        let r = m.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        // The union is the box 1.5 × 1 × 1, up to the nudges (1e-3 of an edge).
        assert!((m.volume() - 1.5).abs() < 1e-2, "{}", m.volume());
        assert!((m.area() - 8.0).abs() < 2e-2, "{}", m.area());
    }

    #[test]
    fn remembered_pieces_are_those_of_a_fresh_cut() {
        use crate::overlap::cut::Cuts;
        use crate::overlap::cut_memo::Memo;
        use crate::overlap::retriangulate::{retriangulate, retriangulate_with};
        let (mut m, owner) = two_cubes([0.3, 0.4, 0.45]);
        let positions = |m: &Mesh| -> Vec<V3> { m.vertices.clone() };
        let pairs_of = |pos: &[V3], m: &Mesh| {
            let (runs, boxes) = run_boxes(pos, &m.faces, &owner);
            let bvh = Bvh::new(boxes);
            crossing_pairs(pos, &m.faces, &owner, &runs, &bvh)
        };
        let fresh = |pos: &[V3], m: &Mesh, pairs: &[[u32; 2]]| {
            let mut cuts = Cuts::find(pos, &m.faces, pairs).expect("cut");
            retriangulate(pos, &m.faces, &mut cuts).expect("pieces")
        };
        let pos = positions(&m);
        let pairs = pairs_of(&pos, &m);
        let mut memo = Memo::default();
        let mut cuts = Cuts::find(&pos, &m.faces, &pairs).expect("cut");
        let first = retriangulate_with(&pos, &m.faces, &mut cuts, None, Some(&mut memo));
        assert_eq!(first.expect("pieces"), fresh(&pos, &m, &pairs));
        assert!(!memo.is_empty());
        // Unchanged: every face takes its pieces from the memo.
        let mut cuts = Cuts::find(&pos, &m.faces, &pairs).expect("cut");
        let again = retriangulate_with(&pos, &m.faces, &mut cuts, Some(&memo), None);
        assert_eq!(again.expect("pieces"), fresh(&pos, &m, &pairs));
        // With the remembered corners turned, each reused piece shows it.
        let turn = |t: [u32; 3]| [t[1], t[2], t[0]];
        let turned = memo.turned();
        let mut cuts = Cuts::find(&pos, &m.faces, &pairs).expect("cut");
        let all = retriangulate_with(&pos, &m.faces, &mut cuts, Some(&turned), None);
        let want = fresh(&pos, &m, &pairs);
        let all = all.expect("pieces");
        assert_eq!(all.origin, want.origin);
        assert!(
            all.faces
                .iter()
                .zip(&want.faces)
                .all(|(a, w)| *a == turn(*w))
        );
        // A corner of the second cube inside the first moves: the faces at
        // it are cut anew, the others reused, all as a fresh cut.
        m.vertices[8] = [0.31, 0.42, 0.47];
        let pos = positions(&m);
        let pairs = pairs_of(&pos, &m);
        let want = fresh(&pos, &m, &pairs);
        let mut cuts = Cuts::find(&pos, &m.faces, &pairs).expect("cut");
        let moved = retriangulate_with(&pos, &m.faces, &mut cuts, Some(&memo), None);
        assert_eq!(moved.expect("pieces"), want);
        let mut cuts = Cuts::find(&pos, &m.faces, &pairs).expect("cut");
        let moved = retriangulate_with(&pos, &m.faces, &mut cuts, Some(&turned), None);
        let moved = moved.expect("pieces");
        let reused = (moved.faces.iter().zip(&want.faces))
            .filter(|(a, w)| **a == turn(**w) && a != w)
            .count();
        let anew = (moved.faces.iter().zip(&want.faces))
            .filter(|(a, w)| a == w)
            .count();
        assert_eq!(reused + anew, want.faces.len());
        assert!(reused > 0 && anew > 0, "{reused} reused, {anew} cut anew");
    }

    #[test]
    fn a_refused_cut_is_nudged_and_cut_again_within_the_round() {
        // Coplanar faces: the plain cut refuses some cluster.
        let (m, mut owner) = two_cubes([0.5, 0.0, 0.0]);
        let mut pos: Vec<V3> = m.vertices.clone();
        let mut index = Index::new(&pos, &m.faces, &owner);
        let pairs = crossing_pairs(&pos, &m.faces, &owner, &index.runs, &index.bvh);
        let plain: Vec<bool> = pairs::clusters_of(&pairs)
            .iter()
            .map(|c| settle::cut_one(&pos, &m.faces, c).is_ok())
            .collect();
        assert!(plain.contains(&false), "{plain:?}");
        let before = pos.clone();
        let cut = cut_with_nudges(&m, &owner, &mut pos, &mut index, pairs, 0);
        assert!(cut.built.iter().all(Result::is_ok));
        assert_ne!(pos, before, "the refused cluster's vertices moved");
        // The index follows them.
        assert_eq!(
            cut.pairs,
            crossing_pairs(&pos, &m.faces, &owner, &index.runs, &index.bvh)
        );
        let fresh = Index::new(&pos, &m.faces, &owner);
        assert_eq!(
            cut.pairs,
            crossing_pairs(&pos, &m.faces, &owner, &fresh.runs, &fresh.bvh)
        );
        // So the first round builds the union, with nothing left for a second.
        let (mut m, _) = two_cubes([0.5, 0.0, 0.0]);
        let once = resolve_once(&mut m, &mut owner, 0, None);
        assert_eq!(once.outcome.pairs_left, 0, "{:?}", once.outcome);
        assert!(once.stuck.is_empty());
        assert!(m.check().is_valid());
    }

    /// A unit cube turned by a generic rotation `r` (rows), placed so that the
    /// midpoint of its edge from corner 0 to corner 1 is at `at`.
    fn turned_cube(r: [[f64; 3]; 3], at: [f64; 3]) -> Mesh {
        let mut m = cube();
        for v in &mut m.vertices {
            let c = [f64::from(v[0]) - 0.5, f64::from(v[1]), f64::from(v[2])];
            *v = std::array::from_fn(|i| {
                (at[i] + r[i][0] * c[0] + r[i][1] * c[1] + r[i][2] * c[2]) as f32
            });
        }
        m
    }

    #[test]
    fn an_edge_through_an_edge_is_cut() {
        // The turned cube's edge passes through the middle of the unit cube's
        // edge from (1, 1, 0) to (1, 1, 1): the cut goes through that point,
        // where the two piercings merge into one vertex (without the merge,
        // the nudge; with neither, this fails).
        let (a, b, c) = (0.3f64, 0.5f64, 0.7f64);
        let rx = [
            [1.0, 0.0, 0.0],
            [0.0, a.cos(), -a.sin()],
            [0.0, a.sin(), a.cos()],
        ];
        let ry = [
            [b.cos(), 0.0, b.sin()],
            [0.0, 1.0, 0.0],
            [-b.sin(), 0.0, b.cos()],
        ];
        let rz = [
            [c.cos(), -c.sin(), 0.0],
            [c.sin(), c.cos(), 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mul = |p: [[f64; 3]; 3], q: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|k| p[i][k] * q[k][j]).sum())
            })
        };
        let r = mul(rz, mul(ry, rx));
        let at = [1.0, 1.0, 0.5];
        let mut m = cube();
        m.append(&turned_cube(r, at));
        let owner: Vec<u32> = (0..m.faces.len() as u32).map(|f| f / 12).collect();
        let out = resolved(&mut m, &owner);
        assert!(out.pairs > 0 && out.pairs_left == 0, "{out:?}");
        let rep = m.check();
        assert!(rep.is_valid(), "{rep}");
        assert_eq!(rep.components, 1);
        // The union's volume by sampling: inside the unit cube, or inside the
        // turned one (its local coordinates in [0, 1]³).
        let inside = |p: [f64; 3]| {
            if p.iter().all(|x| (0.0..=1.0).contains(x)) {
                return true;
            }
            let d = [p[0] - at[0], p[1] - at[1], p[2] - at[2]];
            let l: [f64; 3] = std::array::from_fn(|j| (0..3).map(|i| r[i][j] * d[i]).sum());
            [l[0] + 0.5, l[1], l[2]]
                .iter()
                .all(|x| (0.0..=1.0).contains(x))
        };
        let (lo, hi) = (-1.0, 3.0);
        let n = 400_000u64;
        let hits = (0..n)
            .filter(|&i| {
                let p: [f64; 3] = std::array::from_fn(|k| {
                    let h = crate::kernel::hash::mix64(i * 3 + k as u64);
                    lo + (hi - lo) * ((h >> 11) as f64 / (1u64 << 53) as f64)
                });
                inside(p)
            })
            .count();
        let want = (hi - lo).powi(3) * hits as f64 / n as f64;
        assert!(
            (m.volume() / want - 1.0).abs() < 0.02,
            "{} against {want}",
            m.volume()
        );
    }

    #[test]
    fn a_part_inside_another_without_crossings_is_left() {
        let (mut m, owner) = two_cubes([0.0; 3]);
        let mut inner = cube();
        for v in &mut inner.vertices {
            for c in v.iter_mut() {
                *c = 0.25 + 0.5 * *c;
            }
        }
        m.faces.truncate(12);
        m.vertices.truncate(8);
        m.append(&inner);
        // No face crosses another: nothing to do, the mesh stays as it is.
        let before = m.clone();
        let out = resolved(&mut m, &owner);
        assert_eq!(out, Outcome::default());
        assert_eq!(m, before);
    }

    #[test]
    fn apart_and_within_one_part_are_left_alone() {
        let (mut m, _) = two_cubes([3.0, 0.0, 0.0]);
        let before = m.clone();
        assert_eq!(resolved(&mut m, &[]).pairs, 0);
        assert_eq!(m, before);
        // Crossing faces of one proven part are not looked at.
        let (mut m, _) = two_cubes([0.3, 0.4, 0.45]);
        let one = vec![0; m.faces.len()];
        assert_eq!(resolved(&mut m, &one).pairs, 0);
    }
}
