//! Steps 2 to 4 of one round: the crossing faces cut and re-triangulated,
//! the patches kept or dropped, the result proven and assembled in place;
//! clusters that fail are left uncut.

use super::patches::{classify, patches};
use super::settle::{Cut, Index};
use super::{parts_of, vertices_of};
use crate::kernel::bits::Bits;
use crate::kernel::hash::FastSet;
use crate::kernel::vector::V3;
use crate::mesh::Mesh;
use crate::overlap::verify::{Near, Proven, prove};

/// What one round of the pass built.
pub(super) struct Built {
    /// Part of each face of the mesh.
    pub(super) owner: Vec<u32>,
    /// Crossing pairs in clusters left uncut.
    pub(super) pairs_left: u32,
    /// The first reason a cluster was left uncut.
    pub(super) failure: Option<&'static str>,
    /// Vertices to nudge (of faces of clusters left uncut).
    pub(super) stuck: Vec<u32>,
    /// The vertices of the faces of clusters left uncut.
    pub(super) dirty: Vec<u32>,
    /// The parts of the faces of clusters left uncut.
    pub(super) left_parts: Vec<u32>,
}

/// The union's boundary where it could be built.
///
/// Works in `mesh`'s face list and `pos` (the old faces and vertices stay
/// first, the pieces and new vertices go after them) rather than in copies.
/// `pos` (the mesh's vertices, taken by the round) becomes `mesh`'s
/// vertices again, compacted; on failure `mesh` is left as it was. The
/// round's `index` is dropped before the assembly, the pass's peak.
pub(super) fn union(
    mesh: &mut Mesh,
    owner: &[u32],
    pos: Vec<V3>,
    cut: &Cut,
    index: Index,
) -> Result<Built, (&'static str, Vec<u32>)> {
    let Index { runs, bvh } = index;
    let Cut {
        pairs,
        clusters,
        built,
        ..
    } = cut;
    debug_assert_eq!(
        pairs.len(),
        clusters.iter().map(Vec::len).sum::<usize>(),
        "the clusters hold every pair"
    );
    let mut ok: Vec<bool> = built.iter().map(Result::is_ok).collect();
    let mut failure = built.iter().find_map(|b| b.as_ref().err().map(|r| r.why));
    // Old faces where a cluster failed: the ones to nudge for another round.
    let mut culprits: Vec<u32> = built
        .iter()
        .filter_map(|b| b.as_ref().err())
        .flat_map(|r| r.faces.iter().copied())
        .collect();
    // Cluster of each old face (u32::MAX: in none), and the faces in one.
    let face_cluster = FaceClusters::new(mesh.faces.len(), clusters);
    let in_clusters = &face_cluster.faces;
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
    let mut all_pos: Vec<V3> = pos;
    all_pos.reserve(new_points);
    let mut new_cluster: Vec<u32> = Vec::new();
    let mut cut_edges: FastSet<(u32, u32)> = FastSet::default();
    let mut faces: Vec<[u32; 3]> = std::mem::take(&mut mesh.faces);
    // Until the assembly the vertices are `pos` alone (the round took them
    // from the mesh, see `resolve_once`); the assembly compacts them to what
    // is kept and hands them back.
    debug_assert!(
        mesh.vertices.is_empty(),
        "the round holds its vertices in pos"
    );
    faces.reserve(new_faces);
    let mut origin: Vec<u32> = Vec::new();
    let mut piece_cluster: Vec<u32> = Vec::new();
    let first_piece = faces.len();
    for (c, b) in built.iter().enumerate() {
        if let Ok((cuts, pieces)) = b {
            offset[c] = all_pos.len() as u32 - n_old;
            // The cut rounds its new vertices to f32 at once.
            debug_assert!(
                cuts.points
                    .iter()
                    .flatten()
                    .all(|&x| f64::from(x as f32) == x),
                "the new vertices are f32"
            );
            all_pos.extend(cuts.points.iter().map(|p| p.map(|x| x as f32)));
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
                    !face_cluster.get(f as u32).is_some_and(|c| ok[c as usize])
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
        for f in in_clusters {
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
            &runs,
            &bvh,
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
            all_pos.truncate(n_old as usize);
            mesh.vertices = all_pos;
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
            runs: &runs,
            bvh: &bvh,
            in_cluster: &face_cluster.bits,
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
                // The assembly builds the new mesh's arrays beside the old:
                // what only the tries needed goes first. On the
                // million-sample tree that was 1.2 of the 4.6 GB at the peak.
                let Some(Tried {
                    patch, alive, kept, ..
                }) = tried.take()
                else {
                    unreachable!("the first try fills it")
                };
                drop((patch, alive, face_cluster, runs, bvh, proven));
                let kept = &kept[..];
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
                let renumbered = |which: &[u32]| {
                    let mut v: Vec<u32> = vertices_of(&faces[..first_piece], which)
                        .into_iter()
                        .map(|k| remap[k as usize])
                        .filter(|&k| k != u32::MAX)
                        .collect();
                    v.sort_unstable();
                    v
                };
                let dirty = renumbered(&uncut);
                let stuck = renumbered(&culprits);
                debug_assert!(
                    left == 0 || !stuck.is_empty(),
                    "the clusters left uncut have faces at fault"
                );
                let out_owner = assemble(
                    mesh,
                    n_old as usize,
                    faces,
                    kept,
                    all_pos,
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
                    let Some(c) = face_cluster.get(f) else {
                        unreachable!("a face at fault is in a cluster")
                    };
                    let c = c as usize;
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

/// The cluster of each old face in one: a bit per face says whether it is,
/// and the faces in clusters, sorted, beside their clusters say which. A
/// number per face was 260 MB at the million-sample tree's peak, for the
/// few per cent of faces that cross.
struct FaceClusters {
    bits: Bits,
    /// The faces in clusters, sorted, once each.
    faces: Vec<u32>,
    /// The cluster of each of `faces`.
    cluster: Vec<u32>,
}

impl FaceClusters {
    fn new(n_faces: usize, clusters: &[Vec<[u32; 2]>]) -> FaceClusters {
        let mut of: Vec<(u32, u32)> = clusters
            .iter()
            .enumerate()
            .flat_map(|(c, pairs)| pairs.iter().flatten().map(move |&f| (f, c as u32)))
            .collect();
        // A face is in one cluster (clusters are joined through shared faces).
        of.sort_unstable();
        of.dedup_by_key(|x| x.0);
        let bits = Bits::of(n_faces, of.iter().map(|x| x.0));
        let (faces, cluster) = of.into_iter().unzip();
        FaceClusters {
            bits,
            faces,
            cluster,
        }
    }

    fn get(&self, f: u32) -> Option<u32> {
        if !self.bits.has(f) {
            return None;
        }
        let i = self.faces.binary_search(&f).ok()?;
        Some(self.cluster[i])
    }
}

/// One try of the union: the patches (numbered `0..n_patches`) with the
/// clusters cut then, the live faces and the kept ones.
pub(super) struct Tried {
    pub(super) patch: Vec<u32>,
    pub(super) n_patches: usize,
    pub(super) alive: Vec<bool>,
    pub(super) kept: Vec<bool>,
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
pub(super) fn leave_uncut(
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
pub(super) fn renumbering(faces: &[[u32; 3]], kept: &[bool], n_vertices: usize) -> Vec<u32> {
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
/// (from [`renumbering`]), all compacted in place (the labels in `mesh`, the
/// faces in `faces`), and returns the part of each face (`owner_of(f)` for
/// face `f`); `label_from(k)` names the old vertex whose label vertex `k`
/// takes. In place, because on a large cell fresh arrays of the mesh's size
/// cost more in page faults than the copying itself. `all_pos` (the `n_old`
/// old vertices, then the new ones) is compacted the same way and becomes
/// `mesh.vertices`.
#[allow(clippy::too_many_arguments)]
pub(super) fn assemble(
    mesh: &mut Mesh,
    n_old: usize,
    mut faces: Vec<[u32; 3]>,
    kept: &[bool],
    mut all_pos: Vec<V3>,
    remap: &[u32],
    owner_of: impl Fn(usize) -> u32,
    label_from: impl Fn(u32) -> u32,
) -> Vec<u32> {
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
    if labels {
        let mut w = 0;
        for k in 0..n_old {
            if remap[k] != u32::MAX {
                debug_assert_eq!(remap[k] as usize, w);
                mesh.vertex_sample[w] = mesh.vertex_sample[k];
                w += 1;
            }
        }
        mesh.vertex_sample.truncate(w);
        // Exactly: pushed past its length, the array would double.
        mesh.vertex_sample.reserve_exact(new_labels.len());
        mesh.vertex_sample.extend_from_slice(&new_labels);
    }
    // Used vertices move down (never up).
    let mut w = 0;
    for k in 0..all_pos.len() {
        if remap[k] != u32::MAX {
            all_pos[w] = all_pos[k];
            w += 1;
        }
    }
    all_pos.truncate(w);
    mesh.vertices = all_pos;
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
