//! Step 2 with its own nudges: every cluster of crossing pairs cut, and the
//! clusters whose cut is refused nudged and cut again, within the round.
//!
//! A cut is refused where f32 coordinates make a contact degenerate (a
//! piercing exactly on an edge, a pair with one piercing, one rounding onto a
//! vertex). Left uncut for the rest of the round, such a cluster keeps the
//! patches holding its faces whole, the clusters sharing those patches fail
//! the proof too, and a whole round more over the whole mesh is needed to
//! cut them all again. Nudging the refused clusters here, before anything
//! else of the round is built, and cutting again only the clusters that
//! changed, costs a search around the nudged vertices and a refit of the BVH
//! instead.
//!
//! Only the vertices of the faces at fault move (the cut gathers every place
//! of a cluster it refuses, not just the first): moving every vertex of a
//! refused cluster finds new pairs around them that cost more than the
//! nudge saves.

use super::faces::{nudged, vertices_of};
use super::pairs::{clusters_of, crossing_pairs_at, run_boxes};
use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::hash::FastMap;
use crate::kernel::vector::{P3, V3, at};
use crate::mesh::Mesh;
use crate::overlap::cut::{Cuts, Refusal};
use crate::overlap::cut_memo::Memo;
use crate::overlap::retriangulate::{self, Pieces};

/// How many times a round nudges the clusters whose cut is refused and cuts
/// again before it goes on with them left uncut (a later round nudges them
/// again; see [`super::ROUNDS`]).
const PHASES: usize = 3;

/// A cluster's cut: its cuts and pieces, or why it was refused.
pub(super) type Built = Result<(Cuts, Pieces), Refusal>;

/// The round's crossing pairs, their clusters and each cluster's cut.
pub(super) struct Cut {
    /// Every crossing pair, sorted.
    pub(super) pairs: Vec<[u32; 2]>,
    /// The pairs grouped by intersection curve ([`clusters_of`]).
    pub(super) clusters: Vec<Vec<[u32; 2]>>,
    /// The cut of each cluster.
    pub(super) built: Vec<Built>,
    /// The pieces of the faces of large refused clusters, for their next
    /// cut ([`crate::overlap::cut_memo`]).
    memo: Memo,
}

/// Clusters of at least this many pairs remember their faces' pieces in
/// case their cut is refused: re-cutting a small one costs little, and
/// remembering costs a little on every cut.
const MEMO_PAIRS: usize = 2048;

/// Runs of faces and the BVH over their boxes (which keeps them): grown
/// and refitted when vertices move ([`Index::follow`]).
pub(super) struct Index {
    pub(super) runs: Vec<std::ops::Range<u32>>,
    pub(super) bvh: Bvh,
}

impl Index {
    pub(super) fn new(pos: &[V3], faces: &[[u32; 3]], owner: &[u32]) -> Index {
        let (runs, boxes) = run_boxes(pos, faces, owner);
        let bvh = Bvh::new(boxes);
        Index { runs, bvh }
    }

    /// Moves each of `moved` from its place in `pos` to its new place in
    /// `places` (in the same order), and grows every run box that held the
    /// old place to hold the new one as well: each face at a moved vertex
    /// lies in such a run. A box may come out larger than its run's faces
    /// by a nudge's length, which every use of it allows (each only skips
    /// the faces of boxes that miss a query, and tests the others one by
    /// one). A refit costs a small share of a new index.
    fn follow(&mut self, pos: &mut [V3], moved: &[u32], places: &[V3]) {
        let mut grown: Vec<(u32, P3)> = Vec::new();
        for (&v, &place) in moved.iter().zip(places) {
            let (old, new) = (at(pos, v), place.map(f64::from));
            let here = Aabb { lo: old, hi: old };
            self.bvh
                .for_each_containing(&here, |i| grown.push((i, new)));
            pos[v as usize] = place;
        }
        for (i, p) in grown {
            self.bvh.grow_item(i, p);
        }
        self.bvh.refit();
    }
}

/// Cuts every cluster of `pairs`; where a cut is refused, nudges the
/// vertices of the faces at fault, finds the pairs at the moved vertices
/// again and cuts the clusters that changed, up to [`PHASES`] times. `pos`
/// and `index` follow the moved vertices.
pub(super) fn cut_with_nudges(
    mesh: &Mesh,
    owner: &[u32],
    pos: &mut [V3],
    index: &mut Index,
    pairs: Vec<[u32; 2]>,
    round: usize,
) -> Cut {
    let clusters = clusters_of(&pairs);
    let (built, memo) = cut_all(pos, &mesh.faces, &clusters, &Memo::default());
    let mut now = Cut {
        pairs,
        clusters,
        built,
        memo,
    };
    for phase in 0..PHASES {
        let refused: Vec<usize> = (0..now.clusters.len())
            .filter(|&c| now.built[c].is_err())
            .collect();
        if refused.is_empty() {
            break;
        }
        let at_fault: Vec<u32> = refused
            .iter()
            .filter_map(|&c| now.built[c].as_ref().err())
            .flat_map(|r| r.faces.iter().copied())
            .collect();
        let moved = vertices_of(&mesh.faces, &at_fault);
        if moved.is_empty() {
            break;
        }
        // Salts of their own: the nudges between rounds use the round's number.
        // The round holds its vertices in `pos` alone (see `resolve_once`).
        let places = nudged(
            &mesh.faces,
            pos,
            &moved,
            (1 << 16) | ((round as u64) << 8) | phase as u64,
        );
        index.follow(pos, &moved, &places);
        now = cut_again(mesh, owner, pos, index, now, &moved);
    }
    now
}

/// The cut of one cluster.
#[cfg(test)]
pub(super) fn cut_one(pos: &[V3], faces: &[[u32; 3]], cluster: &[[u32; 2]]) -> Built {
    cut_remembering(pos, faces, cluster, &Memo::default()).0
}

/// The cut of one cluster, taking the pieces of its faces from `reuse`
/// where they are the same, and what a large cluster's faces gave if its
/// cut is refused.
fn cut_remembering(
    pos: &[V3],
    faces: &[[u32; 3]],
    cluster: &[[u32; 2]],
    reuse: &Memo,
) -> (Built, Option<Memo>) {
    let mut cuts = match Cuts::find(pos, faces, cluster) {
        Ok(c) => c,
        Err(r) => return (Err(r), None),
    };
    let mut record = (cluster.len() >= MEMO_PAIRS).then(Memo::default);
    let reuse = (!reuse.is_empty()).then_some(reuse);
    match retriangulate::retriangulate_with(pos, faces, &mut cuts, reuse, record.as_mut()) {
        Ok(pieces) => (Ok((cuts, pieces)), None),
        Err(r) => (Err(r), record),
    }
}

/// The cuts of `clusters` ([`cut_remembering`]), and what the refused ones
/// remember, together.
fn cut_all(
    pos: &[V3],
    faces: &[[u32; 3]],
    clusters: &[impl AsRef<[[u32; 2]]> + Sync],
    reuse: &Memo,
) -> (Vec<Built>, Memo) {
    let done =
        crate::kernel::parallel::map(clusters, |c| cut_remembering(pos, faces, c.as_ref(), reuse));
    let mut memo = Memo::default();
    let built = done
        .into_iter()
        .map(|(b, m)| {
            if let Some(m) = m {
                memo.absorb(m);
            }
            b
        })
        .collect();
    (built, memo)
}

/// The pairs once the vertices `moved` (sorted) have moved: those without a
/// face at a moved vertex stay, the others are found again; a cluster that
/// comes out with the same pairs and no face at a moved vertex keeps its
/// cut, the others are cut anew.
fn cut_again(
    mesh: &Mesh,
    owner: &[u32],
    pos: &[V3],
    index: &Index,
    before: Cut,
    moved: &[u32],
) -> Cut {
    let mut marked = vec![false; pos.len()];
    for &v in moved {
        marked[v as usize] = true;
    }
    let touches = |f: u32| mesh.faces[f as usize].iter().any(|&k| marked[k as usize]);
    let mut pairs: Vec<[u32; 2]> = before
        .pairs
        .iter()
        .copied()
        .filter(|p| !touches(p[0]) && !touches(p[1]))
        .collect();
    pairs.extend(crossing_pairs_at(
        pos,
        &mesh.faces,
        owner,
        &index.runs,
        &index.bvh,
        moved,
    ));
    pairs.sort_unstable();
    pairs.dedup();
    let clusters = clusters_of(&pairs);
    // A cluster's pairs are sorted: its first pair names it.
    let by_first: FastMap<[u32; 2], usize> = before
        .clusters
        .iter()
        .enumerate()
        .map(|(k, c)| (c[0], k))
        .collect();
    let mut old: Vec<Option<Built>> = before.built.into_iter().map(Some).collect();
    let mut kept: Vec<Option<Built>> = clusters
        .iter()
        .map(|c| {
            let &k = by_first.get(&c[0])?;
            let same = before.clusters[k] == *c
                && old[k].as_ref().is_some_and(Result::is_ok)
                && !c.iter().flatten().any(|&f| touches(f));
            if same { old[k].take() } else { None }
        })
        .collect();
    let todo: Vec<usize> = (0..clusters.len()).filter(|&c| kept[c].is_none()).collect();
    let todo_pairs: Vec<&[[u32; 2]]> = todo.iter().map(|&c| &clusters[c][..]).collect();
    let (fresh, memo) = cut_all(pos, &mesh.faces, &todo_pairs, &before.memo);
    for (c, b) in todo.into_iter().zip(fresh) {
        kept[c] = Some(b);
    }
    Cut {
        pairs,
        clusters,
        built: kept
            .into_iter()
            .map(|b| b.expect("every cluster is cut or kept"))
            .collect(),
        memo,
    }
}
