//! Cutting crossing faces along their intersection (step 2 of
//! [`crate::overlap`]).
//!
//! Two crossing triangles in general position meet along a segment whose
//! ends are where an edge of one pierces the other. Each such piercing is one
//! new vertex, keyed by (edge, pierced face): the two faces sharing the edge
//! and the pierced face all refer to the same vertex, so the cut faces meet
//! their neighbours without cracks. Every decision (which side of a plane,
//! whether an edge pierces a face) uses exact orientation predicates on the
//! stored coordinates, so the two faces of an edge always agree. The new
//! vertices are rounded to f32 at once, the precision of the output, and the
//! re-triangulation works on those rounded points.
//!
//! Where an edge of each face passes (almost) through an edge of the other,
//! the two piercings lie within a few f32 steps of each other: they become
//! one vertex on both edges (`MERGE_STEPS`), since rounding them apart can
//! put the one inside a face on the wrong side of the edge it nearly touches.
//!
//! Other degenerate contacts (a vertex exactly on the other face's plane, two
//! faces sharing a vertex and crossing, a piercing that rounds onto a vertex)
//! are refused with a reason; the caller then leaves those faces as they were
//! and nudges them for another try.

use crate::kernel::hash::{FastMap, FastSet};
use crate::kernel::predicates::{orient3d, orient3d_sign};
use crate::kernel::vector::{P3, V3, at};

/// New vertices closer than this many f32 steps (of their coordinates'
/// magnitude) at an edge-edge crossing are one vertex.
const MERGE_STEPS: f64 = 16.0;

/// Why a cluster of crossings could not be cut, and the faces at fault (the
/// ones to nudge before trying again).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    /// The reason, for the report.
    pub why: &'static str,
    /// Old faces where it happened.
    pub faces: Vec<u32>,
}

impl Refusal {
    pub(super) fn new(why: &'static str, faces: &[u32]) -> Refusal {
        Refusal {
            why,
            faces: faces.to_vec(),
        }
    }
}

/// The refusals met while cutting one cluster, gathered rather than
/// stopping at the first: the nudge before the next round then moves every
/// place at fault at once. Stopping at the first, a large cluster shows a
/// new place each round and can still be uncut after the last.
#[derive(Debug, Default)]
pub(super) struct Refused(Option<Refusal>);

impl Refused {
    /// Keeps `result`'s refusal, if any: its reason if it is the first, its
    /// faces in any case.
    pub(super) fn note(&mut self, result: Result<(), Refusal>) {
        if let Err(r) = result {
            match &mut self.0 {
                None => self.0 = Some(r),
                Some(all) => all.faces.extend(r.faces),
            }
        }
    }

    /// `value` if nothing was refused.
    pub(super) fn or<T>(self, value: T) -> Result<T, Refusal> {
        match self.0 {
            None => Ok(value),
            Some(r) => Err(r),
        }
    }
}

/// The cuts of a mesh: new vertices, and per cut face its pierced-by points
/// and cut segments.
#[derive(Debug, Default)]
pub struct Cuts {
    /// Number of vertices before cutting; new vertex `i` is `n_old + i`.
    n_old: u32,
    /// Positions of the new vertices (already f32-exact).
    pub points: Vec<P3>,
    /// For each new vertex, an old vertex to take the label from (the pierced
    /// edge's first end).
    pub point_label_vertex: Vec<u32>,
    /// New vertices on each old edge (min, max), with their parameter from min.
    pub(super) edge_points: FastMap<(u32, u32), Vec<(f64, u32)>>,
    /// Per cut face: new vertices inside it, and cut segments.
    pub(super) faces: FastMap<u32, FaceCut>,
    /// Cut segments as (min, max) vertex pairs.
    pub(super) cut_edges: FastSet<(u32, u32)>,
    /// For each new vertex, the one it was merged into (itself if none).
    merged: Vec<u32>,
    /// For each new vertex, whether it is in a merge already.
    paired: Vec<bool>,
}

/// What crosses one cut face.
#[derive(Debug, Default, Clone)]
pub(super) struct FaceCut {
    /// The new vertices inside it.
    pub(super) inner: Vec<u32>,
    /// Cut segments, each with the face that cuts along it.
    pub(super) segments: Vec<([u32; 2], u32)>,
}

impl Cuts {
    /// The cuts of `faces` for the crossing `pairs`.
    pub fn find(pos: &[V3], faces: &[[u32; 3]], pairs: &[[u32; 2]]) -> Result<Cuts, Refusal> {
        let mut cuts = Cuts {
            n_old: pos.len() as u32,
            ..Cuts::default()
        };
        let mut ids: FastMap<(u32, u32, u32), u32> = FastMap::default();
        let mut refused = Refused::default();
        for &[a, b] in pairs {
            refused.note(cuts.cut_pair(pos, faces, &mut ids, [a, b]));
        }
        refused.or(cuts)
    }

    /// The piercings and the cut segment of one crossing pair `[a, b]`.
    fn cut_pair(
        &mut self,
        pos: &[V3],
        faces: &[[u32; 3]],
        ids: &mut FastMap<(u32, u32, u32), u32>,
        [a, b]: [u32; 2],
    ) -> Result<(), Refusal> {
        let (fa, fb) = (faces[a as usize], faces[b as usize]);
        if fa.iter().any(|v| fb.contains(v)) {
            return Err(Refusal::new("crossing faces share a vertex", &[a, b]));
        }
        // Each end with whether an edge of `fa` (rather than `fb`) made it.
        let mut ends: Vec<(u32, bool)> = Vec::with_capacity(2);
        for (edges_of, face) in [(fa, b), (fb, a)] {
            let f = faces[face as usize];
            let t = f.map(|k| at(pos, k));
            let side: [i8; 3] = std::array::from_fn(|i| sign([f[0], f[1], f[2], edges_of[i]], pos));
            for i in 0..3 {
                let (u, v) = (edges_of[i], edges_of[(i + 1) % 3]);
                if side[i] == side[(i + 1) % 3] {
                    continue;
                }
                let (u, v) = (u.min(v), u.max(v));
                let o: [i8; 3] = std::array::from_fn(|j| sign([u, v, f[j], f[(j + 1) % 3]], pos));
                if o[0] != o[1] || o[1] != o[2] {
                    continue; // crosses the plane outside the face
                }
                let key = (u, v, face);
                let id = match ids.get(&key) {
                    Some(&id) => id,
                    None => {
                        let id = self
                            .pierce(pos, u, v, face, t)
                            .map_err(|why| Refusal::new(why, &[a, b]))?;
                        ids.insert(key, id);
                        id
                    }
                };
                ends.push((id, face == b));
            }
        }
        let [(p, from_a), (q, from_b)] = ends[..] else {
            return Err(Refusal::new(
                "a crossing pair without exactly two piercings",
                &[a, b],
            ));
        };
        // An edge of each face passing (almost) through the other's edge:
        // the cut runs through that edge-edge crossing, one vertex on both
        // edges. Kept apart, f32 rounding can throw the point inside one
        // face across the edge it nearly touches.
        if from_a != from_b && self.nearly_equal(p, q) {
            self.merge(p, q);
        }
        self.faces.entry(a).or_default().segments.push(([p, q], b));
        self.faces.entry(b).or_default().segments.push(([p, q], a));
        Ok(())
    }

    /// Whether new vertices `p` and `q` lie within a few f32 steps.
    fn nearly_equal(&self, p: u32, q: u32) -> bool {
        let point = |k: u32| self.points[(k - self.n_old) as usize];
        let (a, b) = (point(p), point(q));
        let scale = a.iter().chain(&b).fold(0f64, |m, x| m.max(x.abs()));
        let d = (0..3).fold(0f64, |m, i| m.max((a[i] - b[i]).abs()));
        d <= MERGE_STEPS * scale * f64::from(f32::EPSILON)
    }

    /// Merges new vertices `p` and `q` into one (the lower number; the other
    /// stays numbered but unused). A vertex is merged at most once: a chain of
    /// merges means the cut passes within a few f32 steps of an old vertex,
    /// where the merged vertex could land on two edges of one face; that
    /// contact is left to the nudge.
    fn merge(&mut self, p: u32, q: u32) {
        let (i, j) = ((p - self.n_old) as usize, (q - self.n_old) as usize);
        if self.paired[i] || self.paired[j] {
            return;
        }
        self.paired[i] = true;
        self.paired[j] = true;
        let (keep, gone) = (p.min(q), p.max(q));
        self.merged[(gone - self.n_old) as usize] = keep;
    }

    /// The vertex `k` stands for after merges.
    pub(super) fn rep(&self, k: u32) -> u32 {
        if k < self.n_old {
            k
        } else {
            self.merged[(k - self.n_old) as usize]
        }
    }

    /// New vertex where edge (u, v), u < v, pierces face `face` (corners `t`).
    fn pierce(
        &mut self,
        pos: &[V3],
        u: u32,
        v: u32,
        face: u32,
        t: [P3; 3],
    ) -> Result<u32, &'static str> {
        let (pu, pv) = (at(pos, u), at(pos, v));
        let (du, dv) = (
            orient3d(t[0], t[1], t[2], pu),
            orient3d(t[0], t[1], t[2], pv),
        );
        if du == dv {
            return Err("a piercing edge lies in the pierced face's plane");
        }
        let s = (du / (du - dv)).clamp(0.0, 1.0);
        let p: P3 = std::array::from_fn(|i| f64::from((pu[i] + s * (pv[i] - pu[i])) as f32));
        if p == pu || p == pv {
            return Err("a piercing rounds onto a vertex");
        }
        let id = self.n_old + self.points.len() as u32;
        self.points.push(p);
        self.merged.push(id);
        self.paired.push(false);
        self.point_label_vertex.push(u);
        self.edge_points.entry((u, v)).or_default().push((s, id));
        self.faces.entry(face).or_default().inner.push(id);
        Ok(id)
    }

    /// Position of vertex `k`, old or new.
    pub fn at(&self, pos: &[V3], k: u32) -> P3 {
        if k < self.n_old {
            at(pos, k)
        } else {
            self.points[(k - self.n_old) as usize]
        }
    }

    /// New vertex where the planes of three faces meet.
    pub(super) fn triple_point(
        &mut self,
        pos: &[V3],
        faces: &[[u32; 3]],
        key: [u32; 3],
    ) -> Result<u32, &'static str> {
        use crate::kernel::vector::{cross, dot, sub};
        let planes: [(P3, f64); 3] = key.map(|f| {
            let t = faces[f as usize].map(|k| at(pos, k));
            let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
            (n, dot(n, t[0]))
        });
        let (n1, n2, n3) = (planes[0].0, planes[1].0, planes[2].0);
        let det = dot(n1, cross(n2, n3));
        if det == 0.0 || !det.is_finite() {
            return Err("three crossing faces have no common point");
        }
        let (c23, c31, c12) = (cross(n2, n3), cross(n3, n1), cross(n1, n2));
        let p: P3 = std::array::from_fn(|i| {
            let x = (planes[0].1 * c23[i] + planes[1].1 * c31[i] + planes[2].1 * c12[i]) / det;
            f64::from(x as f32)
        });
        if !p.iter().all(|x| x.is_finite()) {
            return Err("three crossing faces have no common point");
        }
        let id = self.n_old + self.points.len() as u32;
        self.points.push(p);
        self.merged.push(id);
        self.paired.push(false);
        self.point_label_vertex.push(faces[key[0] as usize][0]);
        Ok(id)
    }

    /// The cut segments (and their pieces between triple points).
    pub fn cut_edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.cut_edges.iter().copied()
    }
}

/// The exact sign of `orient3d` of four vertices, with ties (four coplanar
/// points) broken by the parity of the permutation that sorts their indices:
/// a rule that depends only on the four vertices, so every test that meets the
/// same quadruple decides it the same way, and is antisymmetric as the
/// determinant is.
fn sign(v: [u32; 4], pos: &[V3]) -> i8 {
    let s = orient3d_sign(at(pos, v[0]), at(pos, v[1]), at(pos, v[2]), at(pos, v[3]));
    if s != 0 {
        return s;
    }
    let mut inversions = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            if v[i] > v[j] {
                inversions += 1;
            }
        }
    }
    if inversions % 2 == 0 { 1 } else { -1 }
}
