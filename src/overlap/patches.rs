//! Step 3: patches (faces joined without crossing a cut) and whether each
//! lies outside every other part, by the winding number along rays.

use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::hash::{FastMap, FastSet};
use crate::kernel::predicates;
use crate::kernel::vector::{P3, V3, at};

/// Patch number of every face: faces joined through an old vertex (a cut
/// never passes through one) or through an uncut edge between new vertices
/// (an edge with an old end joins its faces through that end), and the
/// number of patches. Numbered in order of their first face; a dead face is
/// a patch of its own.
///
/// The disjoint sets are over the old vertices, a face standing for its
/// first old one, plus one set per live face with none: half the items of
/// sets over faces, and two unions per face instead of three.
pub(super) fn patches(
    faces: &[[u32; 3]],
    alive: &[bool],
    n_old_vertices: usize,
    cut_edges: &FastSet<(u32, u32)>,
) -> (Vec<u32>, usize) {
    let n_old = n_old_vertices as u32;
    // The set standing for each face is found again in each of the two
    // passes (its first old corner, or the next number after the old
    // vertices) rather than kept in an array of the mesh's size, which on
    // a large cell costs more in fresh pages than the finds.
    let node_of = |face: &[u32; 3], extra: &mut u32| {
        face.iter()
            .copied()
            .find(|&k| k < n_old)
            .unwrap_or_else(|| {
                *extra += 1;
                n_old + *extra - 1
            })
    };
    let n_extra = faces
        .iter()
        .zip(alive)
        .filter(|(face, a)| **a && face.iter().all(|&k| k >= n_old))
        .count();
    let mut uf = crate::kernel::disjoint_sets::UnionFind::new(n_old_vertices + n_extra);
    let mut new_edges: FastMap<(u32, u32), u32> = FastMap::default();
    let mut extra = 0u32;
    // The last live face's corners, all in the set of `last_root` (still a
    // root: nothing was joined since). Faces come in strips that share two
    // corners with the face before: those need no find.
    let mut last = [u32::MAX; 3];
    let mut last_root = u32::MAX;
    for (face, _) in faces.iter().zip(alive).filter(|(_, a)| **a) {
        let here = node_of(face, &mut extra);
        // The face's set's root, carried from corner to corner: one find
        // per corner instead of two per union.
        // (A face without an old corner stands for a number of its own,
        // which may equal a new vertex of the last face.)
        let here_in_last = here < n_old && last.contains(&here);
        let mut root = if here_in_last {
            last_root
        } else {
            uf.find(here)
        };
        for e in 0..3 {
            let (v, w) = (face[e], face[(e + 1) % 3]);
            if v < n_old {
                if v != here && !(here_in_last && last.contains(&v)) {
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
        (last, last_root) = (*face, root);
    }
    // Numbered in the sets' own array: no second array of the vertices'
    // size at the pass's peak.
    let mut numbering = uf.into_numbering();
    let mut extra = 0u32;
    let patch = faces
        .iter()
        .zip(alive)
        .map(|(face, &a)| {
            if a {
                numbering.number(node_of(face, &mut extra))
            } else {
                numbering.fresh()
            }
        })
        .collect();
    (patch, numbering.count())
}

/// Whether each patch lies outside every other part: the winding number of
/// the original surface without the face a sample point lies on, at that
/// point, along one ray clear of every face's border or else by a vote of
/// three rays.
#[allow(clippy::too_many_arguments)]
pub(super) fn classify(
    faces: &[[u32; 3]],
    alive: &[bool],
    all_pos: &[V3],
    patch: &[u32],
    n_patches: usize,
    origin_of: &(impl Fn(usize) -> u32 + Sync),
    old_faces: &[[u32; 3]],
    old_pos: &[V3],
    runs: &[std::ops::Range<u32>],
    bvh: &Bvh,
) -> Vec<bool> {
    // The largest face of each patch: its centroid is far from the cuts.
    // Measured per live face in one serial pass: a parallel pass would need
    // an array of every face's area, which costs more than it saves.
    let mut best: Vec<(f64, u32)> = vec![(-1.0, u32::MAX); n_patches];
    for (f, face) in faces.iter().enumerate() {
        if !alive[f] {
            continue;
        }
        let t = face.map(|k| at(all_pos, k));
        let n = crate::kernel::vector::cross(
            crate::kernel::vector::sub(t[1], t[0]),
            crate::kernel::vector::sub(t[2], t[0]),
        );
        let area = crate::kernel::vector::dot(n, n);
        let slot = &mut best[patch[f] as usize];
        if area > slot.0 {
            *slot = (area, f as u32);
        }
    }
    let mut bounds = Aabb::EMPTY;
    for i in 0..bvh.len() {
        bounds.add(bvh.item_box(i as u32));
    }
    // A patch of dead faces only has no sample, and is never kept.
    let samples: Vec<u32> = best
        .iter()
        .map(|b| b.1)
        .filter(|&f| f != u32::MAX)
        .collect();
    let verdicts = crate::kernel::parallel::map(&samples, |&f| {
        let t = faces[f as usize].map(|k| at(all_pos, k));
        let c = [
            (t[0][0] + t[1][0] + t[2][0]) / 3.0,
            (t[0][1] + t[1][1] + t[2][1]) / 3.0,
            (t[0][2] + t[1][2] + t[2][2]) / 3.0,
        ];
        let skip = origin_of(f as usize);
        // Counted without the face the point lies on, a ray gives the winding
        // number on the side of that face it leaves towards: so every ray
        // leaves towards the outside.
        let o = old_faces[skip as usize].map(|k| at(old_pos, k));
        let n = crate::kernel::vector::cross(
            crate::kernel::vector::sub(o[1], o[0]),
            crate::kernel::vector::sub(o[2], o[0]),
        );
        let rays = ray_directions(c, n, &bounds);
        let mut votes = [0u32; 2];
        for (k, d) in rays.into_iter().enumerate() {
            let (w, near) = winding(c, d, skip, old_faces, old_pos, runs, bvh);
            // A first ray that passes clear of every face's border counts
            // exactly: it decides alone, which is nearly always.
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
pub(super) fn ray_directions(c: P3, n: P3, bounds: &Aabb) -> [P3; 3] {
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
    let len = crate::kernel::vector::norm(n);
    let mut ranked: Vec<(f64, f64, P3)> = DIRS
        .iter()
        .map(|&d| {
            let cos = if len > 0.0 {
                crate::kernel::vector::dot(d, n) / len
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
/// whether the ray came near a face's border ([`predicates::ray_triangle_near`]),
/// where the count may be off.
pub(super) fn winding(
    c: P3,
    d: P3,
    skip: u32,
    faces: &[[u32; 3]],
    pos: &[V3],
    runs: &[std::ops::Range<u32>],
    bvh: &Bvh,
) -> (i32, bool) {
    let mut w = 0;
    let mut near = false;
    bvh.for_each_on_ray(c, d, f64::INFINITY, |i| {
        for f in runs[i as usize].clone() {
            if f == skip {
                continue;
            }
            let t = faces[f as usize].map(|k| at(pos, k));
            let (hit, close) = predicates::ray_triangle_near(c, d, t);
            near |= close;
            if hit.is_some_and(|s| s > 0.0) {
                let n = crate::kernel::vector::cross(
                    crate::kernel::vector::sub(t[1], t[0]),
                    crate::kernel::vector::sub(t[2], t[0]),
                );
                w += if crate::kernel::vector::dot(n, d) > 0.0 {
                    1
                } else {
                    -1
                };
            }
        }
    });
    (w, near)
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
