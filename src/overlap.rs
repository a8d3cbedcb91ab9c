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
//!    one cut segment in both faces ([`crate::cut`]). Each cut face is
//!    re-triangulated in its own plane by the constrained Delaunay
//!    triangulation of its split edges and cut segments: split along the
//!    cuts and ear-clipped where they run straight across it (96 % of cut
//!    faces on the corpus), with spade otherwise.
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
//!    flat cell with z = 0): the vertices of the clusters left uncut move by at
//!    most `NUDGE` of their shortest edge, which puts them in general
//!    position, and the pass runs again on its own output, up to `ROUNDS`
//!    times. The report counts the crossing pairs still left after the last.

use crate::bvh::{Aabb, Bvh};
use crate::cut::{self, Cuts};
use crate::geom::{self, P3};
use crate::hash::{FastMap, FastSet};
use crate::mesh::Mesh;
use crate::proof::{Near, Proven, prove};

/// Faces per BVH item: runs of consecutive faces of one part.
const RUN: usize = 16;

/// Owner of faces that belong to no proven part (the somas): compared with
/// everything, one face at a time.
pub const NO_OWNER: u32 = u32::MAX;

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
/// contact is degenerate or its pieces round badly), their vertices are nudged
/// and the pass runs again on its own output. The first nudge moves every
/// vertex of the clusters left uncut (a flat or grid-aligned cell has
/// degenerate contacts all along a curve); later ones only those of the faces
/// at fault, so a large cluster is not shaken into new trouble elsewhere.
const ROUNDS: usize = 6;

/// A nudge moves a vertex by up to this fraction of its shortest edge: far
/// below what the output shows, far above the f32 rounding that made the
/// contact degenerate.
const NUDGE: f64 = 1e-3;

/// Replaces `mesh` by the boundary of its union where its parts cross.
/// `owner[f]` is the part of face `f` ([`NO_OWNER`] for faces to compare with
/// everything). Where a crossing cannot be cut, its faces are left as they
/// were (see the module docs).
pub fn resolve(mesh: &mut Mesh, owner: &[u32]) -> Outcome {
    resolve_with_owner(mesh, owner).outcome
}

/// What [`resolve_with_owner`] tells besides the mesh.
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

/// [`resolve`], also telling the part of each face of the result and the
/// parts of the crossings it left.
pub fn resolve_with_owner(mesh: &mut Mesh, owner: &[u32]) -> Resolved {
    let mut owner: Vec<u32> = if owner.len() == mesh.faces.len() {
        owner.to_vec()
    } else {
        vec![NO_OWNER; mesh.faces.len()]
    };
    let mut out = Outcome::default();
    // After the first round, crossings can only involve a face of a cluster
    // left uncut or at a vertex the nudge moved: every other old face kept
    // its f32 corners, and its crossings were all cut; and the round's proof
    // showed that its pieces cross neither each other nor any old face outside
    // the clusters (a piece crossing a face left uncut is found from that face).
    let mut dirty: Option<Vec<u32>> = None;
    let mut left_parts = Vec::new();
    for round in 0..ROUNDS {
        let once = resolve_once(mesh, &mut owner, round == 0, dirty.as_deref());
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
    /// The vertices to nudge: of every face of the clusters left uncut
    /// (first round) or only of the faces at fault.
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
    whole: bool,
    dirty: Option<&[u32]>,
) -> Round {
    // The pass appends the new vertices: on the corpus a median 1 % (a
    // tenth at the 90th percentile), and growing the array copied it.
    let room = mesh.vertices.len() / 8;
    let pos: Vec<P3> = crate::parallel::map_with_room(&mesh.vertices, room, |v| v.map(f64::from));
    let boxes = run_boxes(&pos, &mesh.faces, owner);
    let bvh = Bvh::new(boxes.iter().map(|r| r.1).collect());
    let pairs = match dirty {
        None => crossing_pairs(&pos, &mesh.faces, owner, &boxes, &bvh),
        Some(d) => crossing_pairs_at(&pos, &mesh.faces, owner, &boxes, &bvh, d),
    };
    let mut out = Outcome {
        pairs: pairs.len() as u32,
        pairs_left: pairs.len() as u32,
        failure: None,
    };
    if pairs.is_empty() {
        return Round {
            outcome: out,
            stuck: Vec::new(),
            dirty: Vec::new(),
            left_parts: Vec::new(),
        };
    }
    match union(mesh, owner, pos, &pairs, &boxes, &bvh, whole) {
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
            let all: Vec<u32> = pairs.iter().flatten().copied().collect();
            let left_parts = parts_of(owner, &all);
            let dirty = vertices_of(&mesh.faces, &all);
            let stuck = if whole {
                dirty.clone()
            } else {
                vertices_of(&mesh.faces, &culprits)
            };
            Round {
                outcome: out,
                stuck,
                dirty,
                left_parts,
            }
        }
    }
}

/// The parts `owner[f]` for each `f` in `which`, sorted, once each.
fn parts_of(owner: &[u32], which: &[u32]) -> Vec<u32> {
    let mut p: Vec<u32> = which.iter().map(|&f| owner[f as usize]).collect();
    p.sort_unstable();
    p.dedup();
    p
}

/// The vertices of `faces[f]` for each `f` in `which`, sorted, once each.
fn vertices_of(faces: &[[u32; 3]], which: &[u32]) -> Vec<u32> {
    let mut v: Vec<u32> = which.iter().flat_map(|&f| faces[f as usize]).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Moves each of `vertices` by a pseudo-random offset of up to [`NUDGE`]
/// times its shortest edge (at least a few f32 steps), the same for every
/// run: general position for contacts that f32 coordinates made degenerate.
fn nudge(mesh: &mut Mesh, vertices: &[u32], round: u64) {
    // Only the edges at a nudged vertex are measured: a few hundred of a
    // million (the lengths of them all took 5 % of a small cell's meshing).
    let mut shortest = vec![f64::NAN; mesh.vertices.len()];
    for &v in vertices {
        shortest[v as usize] = f64::INFINITY;
    }
    for f in &mesh.faces {
        if f.iter().all(|&k| shortest[k as usize].is_nan()) {
            continue;
        }
        for e in 0..3 {
            let (a, b) = (f[e] as usize, f[(e + 1) % 3] as usize);
            if shortest[a].is_nan() && shortest[b].is_nan() {
                continue;
            }
            let d = crate::mesh::sub(
                mesh.vertices[a].map(f64::from),
                mesh.vertices[b].map(f64::from),
            );
            let l = crate::mesh::dot(d, d).sqrt();
            for k in [a, b] {
                // NaN (not nudged) stays NaN: `min` would replace it.
                if !shortest[k].is_nan() {
                    shortest[k] = shortest[k].min(l);
                }
            }
        }
    }
    for &v in vertices {
        let p = &mut mesh.vertices[v as usize];
        let scale = p.iter().fold(0f32, |m, x| m.max(x.abs()));
        let step = 8.0 * f64::from(scale.max(f32::MIN_POSITIVE)) * f64::from(f32::EPSILON);
        let amp = (NUDGE * shortest[v as usize]).max(step);
        let mut h = crate::hash::mix64(u64::from(v) ^ (round << 40) ^ 0x9e37_79b9_7f4a_7c15);
        for c in p.iter_mut() {
            h = crate::hash::mix64(h);
            let unit = (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            *c = (f64::from(*c) + amp * unit) as f32;
        }
    }
}

/// Runs of up to [`RUN`] consecutive faces with one owner, with their boxes.
fn run_boxes(pos: &[P3], faces: &[[u32; 3]], owner: &[u32]) -> Vec<(std::ops::Range<u32>, Aabb)> {
    let mut runs = Vec::with_capacity(faces.len() / RUN + 1);
    let mut start = 0usize;
    while start < faces.len() {
        let mut end = start + 1;
        // Faces with no proven part are compared with every other face.
        let run = if owner[start] == NO_OWNER { 1 } else { RUN };
        while end < faces.len() && end - start < run && owner[end] == owner[start] {
            end += 1;
        }
        runs.push(start as u32..end as u32);
        start = end;
    }
    crate::parallel::map(&runs, |r| {
        let mut b = Aabb::EMPTY;
        for f in &faces[r.start as usize..r.end as usize] {
            for &k in f {
                b.add_point(pos[k as usize]);
            }
        }
        (r.clone(), b)
    })
}

fn face_box(pos: &[P3], f: [u32; 3]) -> Aabb {
    Aabb::of(&f.map(|k| pos[k as usize]))
}

/// Whether faces of these owners are compared: different parts, or faces
/// of no proven part.
fn compared(a: u32, b: u32) -> bool {
    a != b || a == NO_OWNER
}

/// Whether face `fa` (corners `ta`, box `ba`) crosses face `b`.
fn crosses(pos: &[P3], faces: &[[u32; 3]], fa: [u32; 3], ta: [P3; 3], ba: &Aabb, b: u32) -> bool {
    let fb = faces[b as usize];
    ba.overlaps(&face_box(pos, fb))
        && crate::check::pair_intersects(fa, fb, ta, fb.map(|k| pos[k as usize]))
}

/// All intersecting pairs of faces of different owners, sorted.
fn crossing_pairs(
    pos: &[P3],
    faces: &[[u32; 3]],
    owner: &[u32],
    runs: &[(std::ops::Range<u32>, Aabb)],
    bvh: &Bvh,
) -> Vec<[u32; 2]> {
    let run_owner = |i: u32| owner[runs[i as usize].0.start as usize];
    let item_pairs = bvh.overlapping_pairs(|i, j| compared(run_owner(i), run_owner(j)));
    let mut pairs = crate::parallel::flat_map_range(item_pairs.len(), |k| {
        let [i, j] = item_pairs[k];
        let (ri, rj) = (&runs[i as usize], &runs[j as usize]);
        // The second run's faces that reach into the first run's box, with
        // their corners and boxes, gathered once rather than per face of
        // the first run (a run holds at most `RUN` faces: on the stack).
        let mut near = [(0u32, [0u32; 3], [[0.0; 3]; 3], Aabb::EMPTY); RUN];
        let mut n_near = 0;
        for b in rj.0.clone() {
            let fb = faces[b as usize];
            let tb = fb.map(|k| pos[k as usize]);
            let bb = Aabb::of(&tb);
            if bb.overlaps(&ri.1) {
                near[n_near] = (b, fb, tb, bb);
                n_near += 1;
            }
        }
        let near = &near[..n_near];
        let mut out = Vec::new();
        if near.is_empty() {
            return out;
        }
        for a in ri.0.clone() {
            let fa = faces[a as usize];
            let ta = fa.map(|k| pos[k as usize]);
            let ba = Aabb::of(&ta);
            if !ba.overlaps(&rj.1) {
                continue;
            }
            for (b, fb, tb, bb) in near {
                if ba.overlaps(bb) && crate::check::pair_intersects(fa, *fb, ta, *tb) {
                    out.push([a.min(*b), a.max(*b)]);
                }
            }
        }
        out
    });
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// The intersecting pairs of faces of different owners of which at least one
/// face has a corner in `dirty` (sorted vertices), sorted: what
/// [`crossing_pairs`] finds when every other crossing is known to be gone.
fn crossing_pairs_at(
    pos: &[P3],
    faces: &[[u32; 3]],
    owner: &[u32],
    runs: &[(std::ops::Range<u32>, Aabb)],
    bvh: &Bvh,
    dirty: &[u32],
) -> Vec<[u32; 2]> {
    let mut at = vec![false; pos.len()];
    for &v in dirty {
        at[v as usize] = true;
    }
    let marked: Vec<bool> = faces
        .iter()
        .map(|f| f.iter().any(|&k| at[k as usize]))
        .collect();
    let queries: Vec<u32> = (0..faces.len() as u32)
        .filter(|&f| marked[f as usize])
        .collect();
    let mut pairs = crate::parallel::flat_map_range(queries.len(), |k| {
        let a = queries[k];
        let fa = faces[a as usize];
        let ba = face_box(pos, fa);
        let ta = fa.map(|k| pos[k as usize]);
        let mut out = Vec::new();
        bvh.for_each_overlap(&ba, |i| {
            for b in runs[i as usize].0.clone() {
                // A pair of two marked faces is found from its first face.
                if b == a || (marked[b as usize] && b < a) {
                    continue;
                }
                if compared(owner[a as usize], owner[b as usize])
                    && crosses(pos, faces, fa, ta, &ba, b)
                {
                    out.push([a.min(b), a.max(b)]);
                }
            }
        });
        out
    });
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Crossing pairs grouped into clusters: pairs joined through shared faces
/// (an intersection curve runs through adjacent faces, so one curve is one
/// cluster). Each cluster is cut, or left as it was, on its own.
fn clusters_of(pairs: &[[u32; 2]]) -> Vec<Vec<[u32; 2]>> {
    let mut index: FastMap<u32, u32> = FastMap::default();
    for p in pairs {
        for f in p {
            let next = index.len() as u32;
            index.entry(*f).or_insert(next);
        }
    }
    let mut uf = crate::check::UnionFind::new(index.len());
    for p in pairs {
        uf.union(index[&p[0]], index[&p[1]]);
    }
    let mut number: FastMap<u32, usize> = FastMap::default();
    let mut out: Vec<Vec<[u32; 2]>> = Vec::new();
    for p in pairs {
        let root = uf.find(index[&p[0]]);
        let next = out.len();
        let c = *number.entry(root).or_insert(next);
        if c == out.len() {
            out.push(Vec::new());
        }
        out[c].push(*p);
    }
    out
}

/// What one round of the pass built.
struct Built {
    /// Part of each face of the mesh.
    owner: Vec<u32>,
    /// Crossing pairs in clusters left uncut.
    pairs_left: u32,
    /// The first reason a cluster was left uncut.
    failure: Option<&'static str>,
    /// Vertices to nudge (of faces of clusters left uncut).
    stuck: Vec<u32>,
    /// The vertices of the faces of clusters left uncut.
    dirty: Vec<u32>,
    /// The parts of the faces of clusters left uncut.
    left_parts: Vec<u32>,
}

/// The union's boundary where it could be built.
///
/// Works in `mesh`'s face list and `pos` (the old faces and vertices stay
/// first, the pieces and new vertices go after them) rather than in copies;
/// on failure `mesh` is left as it was.
fn union(
    mesh: &mut Mesh,
    owner: &[u32],
    pos: Vec<P3>,
    pairs: &[[u32; 2]],
    runs: &[(std::ops::Range<u32>, Aabb)],
    bvh: &Bvh,
    whole: bool,
) -> Result<Built, (&'static str, Vec<u32>)> {
    let clusters = clusters_of(pairs);
    let built: Vec<Result<(Cuts, cut::Pieces), cut::Refusal>> =
        crate::parallel::map(&clusters, |c| {
            let mut cuts = Cuts::find(&pos, &mesh.faces, c)?;
            let pieces = cut::retriangulate(&pos, &mesh.faces, &mut cuts)?;
            Ok((cuts, pieces))
        });
    let mut ok: Vec<bool> = built.iter().map(Result::is_ok).collect();
    let mut failure = built.iter().find_map(|b| b.as_ref().err().map(|r| r.why));
    // Old faces where a cluster failed: the ones to nudge for another round.
    let mut culprits: Vec<u32> = built
        .iter()
        .filter_map(|b| b.as_ref().err())
        .flat_map(|r| r.faces.iter().copied())
        .collect();
    // Cluster of each old face (u32::MAX: in none), and the faces in one.
    let mut face_cluster: Vec<u32> = vec![u32::MAX; mesh.faces.len()];
    for (c, pairs) in clusters.iter().enumerate() {
        for p in pairs {
            face_cluster[p[0] as usize] = c as u32;
            face_cluster[p[1] as usize] = c as u32;
        }
    }
    let mut in_clusters: Vec<u32> = pairs.iter().flatten().copied().collect();
    in_clusters.sort_unstable();
    in_clusters.dedup();
    let n_old = pos.len() as u32;
    // Every cut cluster's new vertices and pieces, numbered once: old
    // vertices, then each cluster's new ones; old faces, then the pieces.
    // Each round only changes which of them are alive.
    let mut offset = vec![0u32; clusters.len()];
    let (new_points, new_faces) = built
        .iter()
        .filter_map(|b| b.as_ref().ok())
        .fold((0, 0), |(p, f), (cuts, pieces)| {
            (p + cuts.points.len(), f + pieces.faces.len())
        });
    let mut all_pos: Vec<P3> = pos;
    all_pos.reserve(new_points);
    let mut new_cluster: Vec<u32> = Vec::new();
    let mut cut_edges: FastSet<(u32, u32)> = FastSet::default();
    let mut faces: Vec<[u32; 3]> = std::mem::take(&mut mesh.faces);
    faces.reserve(new_faces);
    let mut origin: Vec<u32> = Vec::new();
    let mut piece_cluster: Vec<u32> = Vec::new();
    let first_piece = faces.len();
    for (c, b) in built.iter().enumerate() {
        if let Ok((cuts, pieces)) = b {
            offset[c] = all_pos.len() as u32 - n_old;
            all_pos.extend_from_slice(&cuts.points);
            new_cluster.extend(std::iter::repeat_n(c as u32, cuts.points.len()));
            let r = |k: u32| if k < n_old { k } else { k + offset[c] };
            cut_edges.extend(cuts.cut_edges().map(|(a, b)| {
                let (a, b) = (r(a), r(b));
                (a.min(b), a.max(b))
            }));
            faces.extend(pieces.faces.iter().map(|f| f.map(r)));
            origin.extend_from_slice(&pieces.origin);
            piece_cluster.extend(std::iter::repeat_n(c as u32, pieces.faces.len()));
        }
    }
    // The old face a face is (part of).
    let origin_of = |f: usize| {
        if f < first_piece {
            f as u32
        } else {
            origin[f - first_piece]
        }
    };
    // The patches, live faces and kept faces with the clusters `ok` names cut.
    let full_try = |ok: &[bool]| {
        let alive: Vec<bool> = (0..faces.len())
            .map(|f| {
                if f < first_piece {
                    !(face_cluster[f] != u32::MAX && ok[face_cluster[f] as usize])
                } else {
                    ok[piece_cluster[f - first_piece] as usize]
                }
            })
            .collect();
        let (patch, n_patches) = patches(&faces, &alive, n_old as usize, &cut_edges);
        // A patch holding faces of a cluster left uncut may lie partly
        // inside and partly outside: it is always kept (the proof then
        // finds any cut next to it that this leaves inconsistent).
        let mut uncertain = vec![false; n_patches];
        for f in &in_clusters {
            if alive[*f as usize] {
                uncertain[patch[*f as usize] as usize] = true;
            }
        }
        let outside = classify(
            &faces,
            &alive,
            &all_pos,
            &patch,
            n_patches,
            &origin_of,
            &faces[..first_piece],
            &all_pos[..n_old as usize],
            runs,
            bvh,
        );
        let kept: Vec<bool> = (0..faces.len())
            .map(|f| alive[f] && (uncertain[patch[f] as usize] || outside[patch[f] as usize]))
            .collect();
        Tried {
            patch,
            n_patches,
            alive,
            kept,
        }
    };
    // The first try finds the patches and casts their rays; a try after a
    // failed proof only leaves more clusters uncut ([`leave_uncut`]).
    let mut tried: Option<Tried> = None;
    let mut reverted: Vec<usize> = Vec::new();
    let mut proven = Proven::default();
    loop {
        if !ok.contains(&true) {
            faces.truncate(first_piece);
            mesh.faces = faces;
            return Err((failure.unwrap_or("no crossing could be cut"), culprits));
        }
        match &mut tried {
            None => tried = Some(full_try(&ok)),
            Some(t) => {
                let back: Vec<u32> = reverted
                    .iter()
                    .flat_map(|&c| clusters[c].iter().flatten().copied())
                    .collect();
                leave_uncut(
                    &faces,
                    n_old as usize,
                    first_piece,
                    &back,
                    |f| !ok[piece_cluster[f - first_piece] as usize],
                    t,
                );
                reverted.clear();
                debug_assert!(
                    full_try(&ok).kept == t.kept,
                    "leaving clusters uncut keeps what a full try keeps"
                );
            }
        }
        let Some(Tried { kept, .. }) = &tried else {
            unreachable!("the first try fills it")
        };
        let cluster_of_vertex = |v: u32| new_cluster[(v - n_old) as usize];
        let near = Near {
            runs,
            bvh,
            in_cluster: &face_cluster,
        };
        let proof = |proven: &mut Proven| {
            prove(
                &faces,
                kept,
                &all_pos,
                first_piece,
                n_old,
                &origin_of,
                &piece_cluster,
                &near,
                proven,
            )
        };
        let later = proven.has_tested();
        let proved = proof(&mut proven);
        debug_assert!(
            !later || proved == proof(&mut Proven::default()),
            "a proof that only tests what changed finds what a whole proof finds"
        );
        match proved {
            Ok(()) => {
                let left: usize = (0..clusters.len())
                    .filter(|&c| !ok[c])
                    .map(|c| clusters[c].len())
                    .sum();
                let remap = renumbering(&faces, kept, all_pos.len());
                // Faces of uncut clusters keep their vertices, renumbered.
                let uncut: Vec<u32> = (0..clusters.len())
                    .filter(|&c| !ok[c])
                    .flat_map(|c| clusters[c].iter().flatten().copied())
                    .collect();
                let to_nudge = if whole { &uncut } else { &culprits };
                let mut stuck: Vec<u32> = vertices_of(&faces[..first_piece], to_nudge)
                    .into_iter()
                    .map(|k| remap[k as usize])
                    .filter(|&k| k != u32::MAX)
                    .collect();
                stuck.sort_unstable();
                let mut dirty: Vec<u32> = vertices_of(&faces[..first_piece], &uncut)
                    .into_iter()
                    .map(|k| remap[k as usize])
                    .filter(|&k| k != u32::MAX)
                    .collect();
                dirty.sort_unstable();
                let out_owner = assemble(
                    mesh,
                    faces,
                    kept,
                    &all_pos,
                    &remap,
                    |f| owner[origin_of(f) as usize],
                    |k| {
                        if k < n_old {
                            k
                        } else {
                            let c = cluster_of_vertex(k);
                            let Ok((cuts, _)) = &built[c as usize] else {
                                unreachable!("only cut clusters have new vertices")
                            };
                            cuts.point_label_vertex[(k - n_old - offset[c as usize]) as usize]
                        }
                    },
                );
                return Ok(Built {
                    owner: out_owner,
                    pairs_left: left as u32,
                    failure,
                    stuck,
                    dirty,
                    left_parts: parts_of(owner, &uncut),
                });
            }
            Err((why, at_fault)) => {
                failure.get_or_insert(why);
                for &f in &at_fault {
                    let c = face_cluster[f as usize] as usize;
                    if ok[c] {
                        ok[c] = false;
                        reverted.push(c);
                    }
                }
                culprits.extend(at_fault);
            }
        }
    }
}

/// One try of the union: the patches (numbered `0..n_patches`) with the
/// clusters cut then, the live faces and the kept ones.
struct Tried {
    patch: Vec<u32>,
    n_patches: usize,
    alive: Vec<bool>,
    kept: Vec<bool>,
}

/// The faces kept once clusters more are left uncut, updating the try
/// before in place (its patches stay as they were numbered): the old faces
/// `back` of those clusters live again and are kept, the pieces `gone`
/// accepts die, and every patch with a live face at a corner of `back` is
/// kept whole.
///
/// That is the verdict fresh patches would get. Patches join only through
/// the faces that came back, and a patch holding one of them is always
/// kept; a piece that went joined its patch only through an old corner of
/// its cluster (its new corners are its cluster's alone), so what a patch
/// splits into still reaches a corner of `back`. Every other patch keeps its
/// faces, so its sample face and verdict. Two passes over the flags replace
/// the disjoint sets, the face areas and the rays of a full try.
fn leave_uncut(
    faces: &[[u32; 3]],
    n_old: usize,
    first_piece: usize,
    back: &[u32],
    gone: impl Fn(usize) -> bool,
    tried: &mut Tried,
) {
    let Tried {
        patch,
        n_patches,
        alive,
        kept,
    } = tried;
    let mut corner = vec![false; n_old];
    for &f in back {
        alive[f as usize] = true;
        kept[f as usize] = true;
        for k in faces[f as usize] {
            corner[k as usize] = true;
        }
    }
    for f in first_piece..faces.len() {
        if alive[f] && gone(f) {
            alive[f] = false;
            kept[f] = false;
        }
    }
    let mut touched = vec![false; *n_patches];
    for (f, face) in faces.iter().enumerate() {
        if alive[f]
            && face
                .iter()
                .any(|&k| (k as usize) < n_old && corner[k as usize])
        {
            touched[patch[f] as usize] = true;
        }
    }
    for (f, k) in kept.iter_mut().enumerate() {
        if alive[f] && touched[patch[f] as usize] {
            *k = true;
        }
    }
}

/// New number of every vertex used by a kept face, in the vertices' order
/// (`u32::MAX` for the others): the numbering [`assemble`] gives. A vertex
/// never moves up, so the old ones compact in place.
fn renumbering(faces: &[[u32; 3]], kept: &[bool], n_vertices: usize) -> Vec<u32> {
    let mut remap = vec![u32::MAX; n_vertices];
    for (face, _) in faces.iter().zip(kept).filter(|x| *x.1) {
        for &k in face {
            remap[k as usize] = 0;
        }
    }
    let mut next = 0;
    for slot in &mut remap {
        if *slot == 0 {
            *slot = next;
            next += 1;
        }
    }
    remap
}

/// Makes `mesh` the kept faces with their used vertices renumbered by `remap`
/// (from [`renumbering`]), all compacted in place (the old vertices and labels
/// in `mesh`, the faces in `faces`), and returns the part of each face
/// (`owner_of(f)` for face `f`); `label_from(k)` names the old vertex whose
/// label vertex `k` takes. In place, because on a large cell fresh arrays of
/// the mesh's size cost more in page faults than the copying itself.
fn assemble(
    mesh: &mut Mesh,
    mut faces: Vec<[u32; 3]>,
    kept: &[bool],
    all_pos: &[P3],
    remap: &[u32],
    owner_of: impl Fn(usize) -> u32,
    label_from: impl Fn(u32) -> u32,
) -> Vec<u32> {
    let n_old = mesh.vertices.len();
    let labels = !mesh.vertex_sample.is_empty();
    // The new vertices' labels, read before the old labels move.
    let new_labels: Vec<u32> = if labels {
        (n_old..all_pos.len())
            .filter(|&k| remap[k] != u32::MAX)
            .map(|k| mesh.vertex_sample[label_from(k as u32) as usize])
            .collect()
    } else {
        Vec::new()
    };
    let mut w = 0;
    for k in 0..n_old {
        if remap[k] != u32::MAX {
            debug_assert_eq!(remap[k] as usize, w);
            mesh.vertices[w] = mesh.vertices[k];
            if labels {
                mesh.vertex_sample[w] = mesh.vertex_sample[k];
            }
            w += 1;
        }
    }
    mesh.vertices.truncate(w);
    mesh.vertex_sample.truncate(w);
    for k in n_old..all_pos.len() {
        if remap[k] != u32::MAX {
            let p = all_pos[k];
            mesh.vertices.push([p[0] as f32, p[1] as f32, p[2] as f32]);
        }
    }
    mesh.vertex_sample.extend_from_slice(&new_labels);
    // Kept faces move down (never up), so the list compacts in place.
    let mut out_owner = Vec::with_capacity(faces.len());
    let mut w = 0;
    for f in 0..faces.len() {
        if kept[f] {
            faces[w] = faces[f].map(|k| remap[k as usize]);
            out_owner.push(owner_of(f));
            w += 1;
        }
    }
    faces.truncate(w);
    mesh.faces = faces;
    out_owner
}

/// Patch number of every face: faces joined through an old vertex (a cut
/// never passes through one) or through an uncut edge between new vertices
/// (an edge with an old end joins its faces through that end), and the
/// number of patches. Numbered in order of their first face; a dead face is
/// a patch of its own.
///
/// The disjoint sets are over the old vertices, a face standing for its
/// first old one, plus one set per live face with none: half the items of
/// sets over faces, and two unions per face instead of three.
fn patches(
    faces: &[[u32; 3]],
    alive: &[bool],
    n_old_vertices: usize,
    cut_edges: &FastSet<(u32, u32)>,
) -> (Vec<u32>, usize) {
    let n_old = n_old_vertices as u32;
    // Live faces without an old corner, in order, after the old vertices.
    let mut extra = 0u32;
    let node: Vec<u32> = faces
        .iter()
        .zip(alive)
        .map(|(face, &a)| {
            if !a {
                return u32::MAX;
            }
            face.iter()
                .copied()
                .find(|&k| k < n_old)
                .unwrap_or_else(|| {
                    extra += 1;
                    n_old + extra - 1
                })
        })
        .collect();
    let mut uf = crate::check::UnionFind::new(n_old_vertices + extra as usize);
    let mut new_edges: FastMap<(u32, u32), u32> = FastMap::default();
    for (f, face) in faces.iter().enumerate() {
        let here = node[f];
        if here == u32::MAX {
            continue;
        }
        // The face's set's root, carried from corner to corner: one find
        // per corner instead of two per union.
        let mut root = uf.find(here);
        for e in 0..3 {
            let (v, w) = (face[e], face[(e + 1) % 3]);
            if v < n_old {
                if v != here {
                    let rv = uf.find(v);
                    root = uf.link(root, rv);
                }
                continue;
            }
            if w < n_old {
                continue;
            }
            let key = (v.min(w), v.max(w));
            if cut_edges.contains(&key) {
                continue;
            }
            if let Some(&other) = new_edges.get(&key) {
                let ro = uf.find(other);
                root = uf.link(root, ro);
            } else {
                new_edges.insert(key, here);
            }
        }
    }
    let mut number = vec![u32::MAX; n_old_vertices + extra as usize];
    let mut next = 0u32;
    let mut fresh = || {
        next += 1;
        next - 1
    };
    let patch = node
        .iter()
        .map(|&k| {
            if k == u32::MAX {
                return fresh();
            }
            let root = uf.find(k) as usize;
            if number[root] == u32::MAX {
                number[root] = fresh();
            }
            number[root]
        })
        .collect();
    (patch, next as usize)
}

/// Whether each patch lies outside every other part: the winding number of
/// the original surface without the face a sample point lies on, at that
/// point, along one ray clear of every face's border or else by a vote of
/// three rays.
#[allow(clippy::too_many_arguments)]
fn classify(
    faces: &[[u32; 3]],
    alive: &[bool],
    all_pos: &[P3],
    patch: &[u32],
    n_patches: usize,
    origin_of: &(impl Fn(usize) -> u32 + Sync),
    old_faces: &[[u32; 3]],
    old_pos: &[P3],
    runs: &[(std::ops::Range<u32>, Aabb)],
    bvh: &Bvh,
) -> Vec<bool> {
    // The largest face of each patch: its centroid is far from the cuts.
    // (Measured per live face in one pass: a separate parallel pass over the
    // areas was slower, on one thread and on two, for the array it fills.)
    let mut best: Vec<(f64, u32)> = vec![(-1.0, u32::MAX); n_patches];
    for (f, face) in faces.iter().enumerate() {
        if !alive[f] {
            continue;
        }
        let t = face.map(|k| all_pos[k as usize]);
        let n = crate::mesh::cross(crate::mesh::sub(t[1], t[0]), crate::mesh::sub(t[2], t[0]));
        let area = crate::mesh::dot(n, n);
        let slot = &mut best[patch[f] as usize];
        if area > slot.0 {
            *slot = (area, f as u32);
        }
    }
    let mut bounds = Aabb::EMPTY;
    for r in runs {
        bounds.add(&r.1);
    }
    // A patch of dead faces only has no sample, and is never kept.
    let samples: Vec<u32> = best
        .iter()
        .map(|b| b.1)
        .filter(|&f| f != u32::MAX)
        .collect();
    let verdicts = crate::parallel::map(&samples, |&f| {
        let t = faces[f as usize].map(|k| all_pos[k as usize]);
        let c = [
            (t[0][0] + t[1][0] + t[2][0]) / 3.0,
            (t[0][1] + t[1][1] + t[2][1]) / 3.0,
            (t[0][2] + t[1][2] + t[2][2]) / 3.0,
        ];
        let skip = origin_of(f as usize);
        // Counted without the face the point lies on, a ray gives the winding
        // number on the side of that face it leaves towards: so every ray
        // leaves towards the outside.
        let o = old_faces[skip as usize].map(|k| old_pos[k as usize]);
        let n = crate::mesh::cross(crate::mesh::sub(o[1], o[0]), crate::mesh::sub(o[2], o[0]));
        let rays = ray_directions(c, n, &bounds);
        let mut votes = [0u32; 2];
        for (k, d) in rays.into_iter().enumerate() {
            let (w, near) = winding(c, d, skip, old_faces, old_pos, runs, bvh);
            // A first ray that passes clear of every face's border counts
            // exactly: it decides alone (on the 48 corpus files every first
            // ray did, which halved the rays cast).
            if k == 0 && !near {
                return w == 0;
            }
            votes[usize::from(w == 0)] += 1;
            if votes[0] == 2 || votes[1] == 2 {
                break;
            }
        }
        votes[1] >= 2
    });
    let mut verdict = verdicts.into_iter();
    best.iter()
        .map(|b| b.1 != u32::MAX && verdict.next().unwrap_or(false))
        .collect()
}

/// Ray directions for the vote: fixed, in general position (no axis, no
/// diagonal, so a cell traced on a grid meets no ray edge-on), a clear angle
/// into the side `n` points to, and of those the three that leave `bounds`
/// soonest. The cost of a ray is the faces along it: one along a long cell's
/// axis meets every branch on the way, one across it a few.
fn ray_directions(c: P3, n: P3, bounds: &Aabb) -> [P3; 3] {
    const DIRS: [P3; 14] = [
        [0.982_246, 0.131_105, 0.132_617],
        [-0.958_471, 0.201_927, -0.201_352],
        [0.137_104, 0.972_664, 0.186_871],
        [-0.176_871, -0.968_414, 0.175_723],
        [0.156_223, -0.149_876, 0.976_282],
        [-0.123_985, 0.187_113, -0.974_482],
        [0.612_437, 0.541_228, 0.576_140],
        [-0.552_173, 0.601_553, 0.577_337],
        [0.598_662, -0.567_218, 0.565_508],
        [0.541_009, 0.589_702, -0.599_642],
        [-0.588_233, -0.553_712, 0.589_324],
        [-0.561_284, 0.578_903, -0.591_327],
        [0.603_715, -0.548_338, -0.578_631],
        [-0.569_802, -0.596_114, -0.565_702],
    ];
    let len = crate::mesh::norm(n);
    let mut ranked: Vec<(f64, f64, P3)> = DIRS
        .iter()
        .map(|&d| {
            let cos = if len > 0.0 {
                crate::mesh::dot(d, n) / len
            } else {
                0.0
            };
            let d = if cos < 0.0 { d.map(|x| -x) } else { d };
            let exit = (0..3)
                .map(|a| {
                    if d[a] > 0.0 {
                        (bounds.hi[a] - c[a]) / d[a]
                    } else {
                        (bounds.lo[a] - c[a]) / d[a]
                    }
                })
                .fold(f64::INFINITY, f64::min)
                .max(0.0);
            (cos.abs(), exit, d)
        })
        .collect();
    // A clear angle first (a ray nearly in the face's plane leaves it on
    // rounding), then the shortest.
    ranked.sort_by(|a, b| (b.0 >= 0.25).cmp(&(a.0 >= 0.25)).then(a.1.total_cmp(&b.1)));
    [ranked[0].2, ranked[1].2, ranked[2].2]
}

/// Winding number of the faces other than `skip` at `c`, counted along the ray
/// from `c` in direction `d` (+1 for each face the ray leaves through), and
/// whether the ray came near a face's border ([`geom::ray_triangle_near`]),
/// where the count may be off.
fn winding(
    c: P3,
    d: P3,
    skip: u32,
    faces: &[[u32; 3]],
    pos: &[P3],
    runs: &[(std::ops::Range<u32>, Aabb)],
    bvh: &Bvh,
) -> (i32, bool) {
    let mut w = 0;
    let mut near = false;
    bvh.for_each_on_ray(c, d, f64::INFINITY, |i| {
        for f in runs[i as usize].0.clone() {
            if f == skip {
                continue;
            }
            let t = faces[f as usize].map(|k| pos[k as usize]);
            let (hit, close) = geom::ray_triangle_near(c, d, t);
            near |= close;
            if hit.is_some_and(|s| s > 0.0) {
                let n =
                    crate::mesh::cross(crate::mesh::sub(t[1], t[0]), crate::mesh::sub(t[2], t[0]));
                w += if crate::mesh::dot(n, d) > 0.0 { 1 } else { -1 };
            }
        }
    });
    (w, near)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::cube;

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
        let out = resolve(&mut m, &owner);
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
        let pos: Vec<P3> = m.vertices.iter().map(|v| v.map(f64::from)).collect();
        let runs = run_boxes(&pos, &m.faces, &owner);
        let bvh = Bvh::new(runs.iter().map(|r| r.1).collect());
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
        let out = resolve(&mut m, &owner);
        assert!(out.pairs > 0 && out.pairs_left == 0, "{out:?}");
        let r = m.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        // The union is the box 1.5 × 1 × 1, up to the nudges (1e-3 of an edge).
        assert!((m.volume() - 1.5).abs() < 1e-2, "{}", m.volume());
        assert!((m.area() - 8.0).abs() < 2e-2, "{}", m.area());
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
        let out = resolve(&mut m, &owner);
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
                    let h = crate::hash::mix64(i * 3 + k as u64);
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
        let out = resolve(&mut m, &owner);
        assert_eq!(out, Outcome::default());
        assert_eq!(m, before);
    }

    #[test]
    fn apart_and_within_one_part_are_left_alone() {
        let (mut m, _) = two_cubes([3.0, 0.0, 0.0]);
        let before = m.clone();
        assert_eq!(resolve(&mut m, &[]).pairs, 0);
        assert_eq!(m, before);
        // Crossing faces of one proven part are not looked at.
        let (mut m, _) = two_cubes([0.3, 0.4, 0.45]);
        let one = vec![0; m.faces.len()];
        assert_eq!(resolve(&mut m, &one).pairs, 0);
    }
}
