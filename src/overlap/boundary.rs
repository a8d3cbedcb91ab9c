//! Steps 2 to 4 of one round: the crossing faces cut and re-triangulated,
//! the patches kept or dropped, the result proven and assembled in place;
//! clusters that fail are left uncut.

use super::assembly::{assemble, renumbering};
use super::faces::{parts_of, vertices_of};
use super::patches::{Tried, classify, leave_uncut, patches};
use super::settle::{self, Cut, Index};
use std::ops::Range;

use crate::kernel::bits::Bits;
use crate::kernel::bvh::Bvh;
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
///
/// Each try keeps the patches outside the rest with the clusters `ok` names
/// cut, and proves the result; a failed proof names the faces at fault, and
/// their clusters are left uncut in the next try.
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
    let face_cluster = FaceClusters::new(mesh.faces.len(), clusters);
    // Until the assembly the vertices are `pos` alone (the round took them
    // from the mesh, see `resolve_once`); the assembly compacts them to what
    // is kept and hands them back.
    debug_assert!(
        mesh.vertices.is_empty(),
        "the round holds its vertices in pos"
    );
    let g = Gathered::new(pos, std::mem::take(&mut mesh.faces), built);
    // The first try finds the patches and casts their rays; a try after a
    // failed proof only leaves more clusters uncut ([`leave_uncut`]).
    let mut tried: Option<Tried> = None;
    let mut reverted: Vec<usize> = Vec::new();
    let mut proven = Proven::default();
    loop {
        if !ok.contains(&true) {
            g.give_back(mesh);
            return Err((failure.unwrap_or("no crossing could be cut"), culprits));
        }
        match &mut tried {
            None => tried = Some(g.try_all(&ok, &face_cluster, &runs, &bvh)),
            Some(t) => {
                let back: Vec<u32> = reverted
                    .iter()
                    .flat_map(|&c| clusters[c].iter().flatten().copied())
                    .collect();
                leave_uncut(
                    &g.faces,
                    g.n_old as usize,
                    g.first_piece,
                    &back,
                    |f| !ok[g.piece_cluster[f - g.first_piece] as usize],
                    t,
                );
                reverted.clear();
                debug_assert!(
                    g.try_all(&ok, &face_cluster, &runs, &bvh).kept == t.kept,
                    "leaving clusters uncut keeps what a full try keeps"
                );
            }
        }
        let Some(Tried { kept, .. }) = &tried else {
            unreachable!("the first try fills it")
        };
        let near = Near {
            runs: &runs,
            bvh: &bvh,
            in_cluster: &face_cluster.bits,
        };
        let later = proven.has_tested();
        let proved = g.prove(kept, &near, &mut proven);
        debug_assert!(
            !later || proved == g.prove(kept, &near, &mut Proven::default()),
            "a proof that only tests what changed finds what a whole proof finds"
        );
        match proved {
            Ok(()) => {
                // The assembly builds the new mesh's arrays beside the old:
                // what only the tries needed goes first (on the
                // million-sample tree, a quarter of the peak).
                let Some(Tried { kept, .. }) = tried.take() else {
                    unreachable!("the first try fills it")
                };
                drop((face_cluster, runs, bvh, proven));
                let left = Left::of(clusters, &ok, culprits);
                return Ok(g.assemble(mesh, owner, &kept, built, left, failure));
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

/// Every cut cluster's new vertices and pieces, numbered once: old
/// vertices, then each cluster's new ones; old faces, then the pieces. Each
/// try only changes which of them are alive.
struct Gathered {
    /// The old vertices, then the new ones.
    pos: Vec<V3>,
    /// The old faces, then the pieces.
    faces: Vec<[u32; 3]>,
    /// How many vertices are old.
    n_old: u32,
    /// The first piece's index in `faces`.
    first_piece: usize,
    /// Per cluster, where its new vertices begin after the old ones.
    offset: Vec<u32>,
    /// The cluster of each new vertex.
    new_cluster: Vec<u32>,
    /// The cut edges, by their vertices in the numbering above.
    cut_edges: FastSet<(u32, u32)>,
    /// The old face each piece is part of.
    origin: Vec<u32>,
    /// The cluster of each piece.
    piece_cluster: Vec<u32>,
}

impl Gathered {
    /// The old vertices `pos` and faces `faces` with the new vertices and
    /// pieces of every cluster `built` cut.
    fn new(pos: Vec<V3>, faces: Vec<[u32; 3]>, built: &[settle::Built]) -> Gathered {
        let (new_points, new_faces) = built
            .iter()
            .filter_map(|b| b.as_ref().ok())
            .fold((0, 0), |(p, f), (cuts, pieces)| {
                (p + cuts.points.len(), f + pieces.faces.len())
            });
        let n_old = pos.len() as u32;
        let first_piece = faces.len();
        let mut g = Gathered {
            pos,
            faces,
            n_old,
            first_piece,
            offset: vec![0u32; built.len()],
            new_cluster: Vec::new(),
            cut_edges: FastSet::default(),
            origin: Vec::new(),
            piece_cluster: Vec::new(),
        };
        g.pos.reserve(new_points);
        g.faces.reserve(new_faces);
        for (c, b) in built.iter().enumerate() {
            if let Ok((cuts, pieces)) = b {
                g.offset[c] = g.pos.len() as u32 - n_old;
                // The cut rounds its new vertices to f32 at once.
                debug_assert!(
                    cuts.points
                        .iter()
                        .flatten()
                        .all(|&x| f64::from(x as f32) == x),
                    "the new vertices are f32"
                );
                g.pos
                    .extend(cuts.points.iter().map(|p| p.map(|x| x as f32)));
                g.new_cluster
                    .extend(std::iter::repeat_n(c as u32, cuts.points.len()));
                let off = g.offset[c];
                let r = |k: u32| if k < n_old { k } else { k + off };
                g.cut_edges.extend(cuts.cut_edges().map(|(a, b)| {
                    let (a, b) = (r(a), r(b));
                    (a.min(b), a.max(b))
                }));
                g.faces.extend(pieces.faces.iter().map(|f| f.map(r)));
                g.origin.extend_from_slice(&pieces.origin);
                g.piece_cluster
                    .extend(std::iter::repeat_n(c as u32, pieces.faces.len()));
            }
        }
        g
    }

    /// The old face face `f` is (part of).
    fn origin_of(&self, f: usize) -> u32 {
        if f < self.first_piece {
            f as u32
        } else {
            self.origin[f - self.first_piece]
        }
    }

    /// The patches, live faces and kept faces with the clusters `ok` names
    /// cut.
    fn try_all(
        &self,
        ok: &[bool],
        face_cluster: &FaceClusters,
        runs: &[Range<u32>],
        bvh: &Bvh,
    ) -> Tried {
        let (faces, first_piece) = (&self.faces, self.first_piece);
        let alive: Vec<bool> = (0..faces.len())
            .map(|f| {
                if f < first_piece {
                    !face_cluster.get(f as u32).is_some_and(|c| ok[c as usize])
                } else {
                    ok[self.piece_cluster[f - first_piece] as usize]
                }
            })
            .collect();
        let (patch, n_patches) = patches(faces, &alive, self.n_old as usize, &self.cut_edges);
        // A patch holding faces of a cluster left uncut may lie partly
        // inside and partly outside: it is always kept (the proof then
        // finds any cut next to it that this leaves inconsistent).
        let mut uncertain = vec![false; n_patches];
        for f in &face_cluster.faces {
            if alive[*f as usize] {
                uncertain[patch[*f as usize] as usize] = true;
            }
        }
        let outside = classify(
            faces,
            &alive,
            &self.pos,
            &patch,
            n_patches,
            &|f| self.origin_of(f),
            &faces[..first_piece],
            &self.pos[..self.n_old as usize],
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
    }

    /// Whether the faces `kept` are free of crossings near the cuts
    /// ([`prove`]).
    fn prove(
        &self,
        kept: &[bool],
        near: &Near<'_>,
        proven: &mut Proven,
    ) -> Result<(), (&'static str, Vec<u32>)> {
        prove(
            &self.faces,
            kept,
            &self.pos,
            self.first_piece,
            self.n_old,
            &|f| self.origin_of(f),
            &self.piece_cluster,
            near,
            proven,
        )
    }

    /// `mesh` as it was: the old faces and vertices handed back.
    fn give_back(mut self, mesh: &mut Mesh) {
        self.faces.truncate(self.first_piece);
        mesh.faces = self.faces;
        self.pos.truncate(self.n_old as usize);
        mesh.vertices = self.pos;
    }

    /// Makes `mesh` the faces `kept`, their vertices renumbered, and tells
    /// what the round built and `left` uncut.
    fn assemble(
        self,
        mesh: &mut Mesh,
        owner: &[u32],
        kept: &[bool],
        built: &[settle::Built],
        left: Left,
        failure: Option<&'static str>,
    ) -> Built {
        let remap = renumbering(&self.faces, kept, self.pos.len());
        // Faces of uncut clusters keep their vertices, renumbered.
        let renumbered = |which: &[u32]| {
            let mut v: Vec<u32> = vertices_of(&self.faces[..self.first_piece], which)
                .into_iter()
                .map(|k| remap[k as usize])
                .filter(|&k| k != u32::MAX)
                .collect();
            v.sort_unstable();
            v
        };
        let dirty = renumbered(&left.faces);
        let stuck = renumbered(&left.culprits);
        debug_assert!(
            left.pairs == 0 || !stuck.is_empty(),
            "the clusters left uncut have faces at fault"
        );
        let Gathered {
            pos,
            faces,
            n_old,
            first_piece,
            offset,
            new_cluster,
            origin,
            ..
        } = self;
        let origin_of = |f: usize| {
            if f < first_piece {
                f as u32
            } else {
                origin[f - first_piece]
            }
        };
        // The old vertex whose label a vertex takes: itself, or for a new
        // vertex the one its cut names.
        let label_from = |k: u32| {
            if k < n_old {
                return k;
            }
            let c = new_cluster[(k - n_old) as usize] as usize;
            let Ok((cuts, _)) = &built[c] else {
                unreachable!("only cut clusters have new vertices")
            };
            cuts.point_label_vertex[(k - n_old - offset[c]) as usize]
        };
        let out_owner = assemble(
            mesh,
            n_old as usize,
            faces,
            kept,
            pos,
            &remap,
            |f| owner[origin_of(f) as usize],
            label_from,
        );
        Built {
            owner: out_owner,
            pairs_left: left.pairs as u32,
            failure,
            stuck,
            dirty,
            left_parts: parts_of(owner, &left.faces),
        }
    }
}

/// What a round leaves uncut.
struct Left {
    /// Crossing pairs in the clusters left uncut.
    pairs: usize,
    /// The old faces of those clusters.
    faces: Vec<u32>,
    /// The old faces at fault, to nudge.
    culprits: Vec<u32>,
}

impl Left {
    /// The clusters `ok` does not name, and the faces at fault `culprits`.
    fn of(clusters: &[Vec<[u32; 2]>], ok: &[bool], culprits: Vec<u32>) -> Left {
        let uncut = || (0..clusters.len()).filter(|&c| !ok[c]);
        Left {
            pairs: uncut().map(|c| clusters[c].len()).sum(),
            faces: uncut()
                .flat_map(|c| clusters[c].iter().flatten().copied())
                .collect(),
            culprits,
        }
    }
}

/// The cluster of each old face in one: a bit per face says whether it is,
/// and the faces in clusters, sorted, beside their clusters say which: a
/// number per face would hold the pass's peak memory for the few per cent
/// of faces that cross.
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
