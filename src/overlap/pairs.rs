//! Step 1: the pairs of faces of different parts that cross, found through
//! a BVH over runs of consecutive faces of one part, and their clusters.

use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::hash::FastMap;
use crate::kernel::vector::{P3, V3, at};
use crate::mesh::NO_OWNER;

/// Faces per BVH item: runs of consecutive faces of one part.
pub(super) const RUN: usize = 16;

/// Runs of up to [`RUN`] consecutive faces with one owner, and their boxes
/// (for the BVH, which keeps them: the runs do not keep a copy).
pub(super) fn run_boxes(
    pos: &[V3],
    faces: &[[u32; 3]],
    owner: &[u32],
) -> (Vec<std::ops::Range<u32>>, Vec<Aabb>) {
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
    let boxes = crate::kernel::parallel::map(&runs, |r| {
        let mut b = Aabb::EMPTY;
        for f in &faces[r.start as usize..r.end as usize] {
            for &k in f {
                b.add_point(at(pos, k));
            }
        }
        b
    });
    (runs, boxes)
}

pub(super) fn face_box(pos: &[V3], f: [u32; 3]) -> Aabb {
    Aabb::of(&f.map(|k| at(pos, k)))
}

/// Whether faces of these owners are compared: different parts, or faces
/// of no proven part.
pub(super) fn compared(a: u32, b: u32) -> bool {
    a != b || a == NO_OWNER
}

/// Whether face `fa` (corners `ta`, box `ba`) crosses face `b`.
pub(super) fn crosses(
    pos: &[V3],
    faces: &[[u32; 3]],
    fa: [u32; 3],
    ta: [P3; 3],
    ba: &Aabb,
    b: u32,
) -> bool {
    let fb = faces[b as usize];
    ba.overlaps(&face_box(pos, fb))
        && crate::kernel::predicates::pair_intersects(fa, fb, ta, fb.map(|k| at(pos, k)))
}

/// All intersecting pairs of faces of different owners, sorted.
pub(super) fn crossing_pairs(
    pos: &[V3],
    faces: &[[u32; 3]],
    owner: &[u32],
    runs: &[std::ops::Range<u32>],
    bvh: &Bvh,
) -> Vec<[u32; 2]> {
    let run_owner = |i: u32| owner[runs[i as usize].start as usize];
    let item_pairs = bvh.overlapping_pairs(|i, j| compared(run_owner(i), run_owner(j)));
    let mut pairs = crate::kernel::parallel::flat_map_range(item_pairs.len(), |k| {
        let [i, j] = item_pairs[k];
        let (ri, rj) = (&runs[i as usize], &runs[j as usize]);
        let (bi, bj) = (bvh.item_box(i), bvh.item_box(j));
        // The second run's faces that reach into the first run's box, with
        // their corners and boxes, gathered once rather than per face of
        // the first run (a run holds at most `RUN` faces: on the stack).
        let mut near = [(0u32, [0u32; 3], [[0.0; 3]; 3], Aabb::EMPTY); RUN];
        let mut n_near = 0;
        for b in rj.clone() {
            let fb = faces[b as usize];
            let tb = fb.map(|k| at(pos, k));
            let bb = Aabb::of(&tb);
            if bb.overlaps(bi) {
                near[n_near] = (b, fb, tb, bb);
                n_near += 1;
            }
        }
        let near = &near[..n_near];
        let mut out = Vec::new();
        if near.is_empty() {
            return out;
        }
        for a in ri.clone() {
            let fa = faces[a as usize];
            let ta = fa.map(|k| at(pos, k));
            let ba = Aabb::of(&ta);
            if !ba.overlaps(bj) {
                continue;
            }
            for (b, fb, tb, bb) in near {
                if ba.overlaps(bb) && crate::kernel::predicates::pair_intersects(fa, *fb, ta, *tb) {
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
pub(super) fn crossing_pairs_at(
    pos: &[V3],
    faces: &[[u32; 3]],
    owner: &[u32],
    runs: &[std::ops::Range<u32>],
    bvh: &Bvh,
    dirty: &[u32],
) -> Vec<[u32; 2]> {
    let mut marked = vec![false; pos.len()];
    for &v in dirty {
        marked[v as usize] = true;
    }
    let marked: Vec<bool> = faces
        .iter()
        .map(|f| f.iter().any(|&k| marked[k as usize]))
        .collect();
    let queries: Vec<u32> = (0..faces.len() as u32)
        .filter(|&f| marked[f as usize])
        .collect();
    let mut pairs = crate::kernel::parallel::flat_map_range(queries.len(), |k| {
        let a = queries[k];
        let fa = faces[a as usize];
        let ba = face_box(pos, fa);
        let ta = fa.map(|k| at(pos, k));
        let mut out = Vec::new();
        bvh.for_each_overlap(&ba, |i| {
            for b in runs[i as usize].clone() {
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
pub(super) fn clusters_of(pairs: &[[u32; 2]]) -> Vec<Vec<[u32; 2]>> {
    let mut index: FastMap<u32, u32> = FastMap::default();
    for p in pairs {
        for f in p {
            let next = index.len() as u32;
            index.entry(*f).or_insert(next);
        }
    }
    let mut uf = crate::kernel::disjoint_sets::UnionFind::new(index.len());
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
