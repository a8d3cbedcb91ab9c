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

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::kernel::hash::{FastMap, FastSet};
use crate::kernel::predicates::{orient2d_sign, orient3d, orient3d_sign};
use crate::kernel::vector::{P3, V3, at};
use crate::overlap::cut_memo::Memo;

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
    fn new(why: &'static str, faces: &[u32]) -> Refusal {
        Refusal {
            why,
            faces: faces.to_vec(),
        }
    }
}

/// The refusals met while cutting one cluster, gathered rather than
/// stopping at the first: the nudge before the next round then moves every
/// place at fault at once. Stopping at the first, a cluster of 89,000
/// crossing pairs (a fly medulla neuron's crowded fillers) showed a new
/// place each round and was still uncut after the last.
#[derive(Debug, Default)]
struct Refused(Option<Refusal>);

impl Refused {
    /// Keeps `result`'s refusal, if any: its reason if it is the first, its
    /// faces in any case.
    fn note(&mut self, result: Result<(), Refusal>) {
        if let Err(r) = result {
            match &mut self.0 {
                None => self.0 = Some(r),
                Some(all) => all.faces.extend(r.faces),
            }
        }
    }

    /// `value` if nothing was refused.
    fn or<T>(self, value: T) -> Result<T, Refusal> {
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
    edge_points: FastMap<(u32, u32), Vec<(f64, u32)>>,
    /// Per cut face: new vertices inside it, and cut segments.
    faces: FastMap<u32, FaceCut>,
    /// Cut segments as (min, max) vertex pairs.
    cut_edges: FastSet<(u32, u32)>,
    /// For each new vertex, the one it was merged into (itself if none).
    merged: Vec<u32>,
    /// For each new vertex, whether it is in a merge already.
    paired: Vec<bool>,
}

#[derive(Debug, Default, Clone)]
struct FaceCut {
    inner: Vec<u32>,
    /// Cut segments, each with the face that cuts along it.
    segments: Vec<([u32; 2], u32)>,
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
    fn rep(&self, k: u32) -> u32 {
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
    fn triple_point(
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

/// The pieces of the cut faces.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Pieces {
    /// Triangles, oriented as the faces they come from.
    pub faces: Vec<[u32; 3]>,
    /// The face each piece comes from.
    pub origin: Vec<u32>,
}

/// Re-triangulates every cut face with its split edges and cut segments as
/// constraints (in increasing face order, so the result is deterministic).
///
/// Where two cut segments of a face cross, three faces meet in one point: it
/// becomes a new vertex (keyed by the three faces, placed where their planes
/// meet) that splits both segments, in each of the three faces.
///
/// A face whose segments only form chains from edge to edge (no triple
/// point, no loop: one or two intersection curves passing through it, by far
/// the common case) is split along them and each part triangulated on its own
/// ([`crate::kernel::planar::triangulate_polygon`], the same triangulation spade
/// would give); on a cell with a few thousand cut faces that takes a tenth of
/// the instructions of spade's bulk load, which remains for the rest.
#[cfg(test)]
pub fn retriangulate(pos: &[V3], faces: &[[u32; 3]], cuts: &mut Cuts) -> Result<Pieces, Refusal> {
    retriangulate_with(pos, faces, cuts, None, None)
}

/// [`retriangulate`], taking the pieces of a face from `reuse` where its
/// inputs are those it remembers, and remembering in `record` what each
/// face gave ([`crate::overlap::cut_memo`]). The pieces are those [`retriangulate`]
/// gives.
pub fn retriangulate_with(
    pos: &[V3],
    faces: &[[u32; 3]],
    cuts: &mut Cuts,
    reuse: Option<&Memo>,
    record: Option<&mut Memo>,
) -> Result<Pieces, Refusal> {
    let mut order: Vec<u32> = cuts.faces.keys().copied().collect();
    order.sort_unstable();
    let mut triples: FastMap<[u32; 3], u32> = FastMap::default();
    let mut out = Pieces::default();
    let mut refused = Refused::default();
    let mut memo = Remembering {
        reuse,
        record,
        inputs: Vec::new(),
    };
    for f in order {
        refused.note(cut_face(
            pos,
            faces,
            cuts,
            f,
            &mut triples,
            &mut out,
            &mut memo,
        ));
    }
    refused.or(out)
}

/// What [`cut_face`] takes from and gives to memos, and its scratch space.
struct Remembering<'a> {
    reuse: Option<&'a Memo>,
    record: Option<&'a mut Memo>,
    /// The inputs of the face being cut, as bits.
    inputs: Vec<u64>,
}

impl Remembering<'_> {
    fn active(&self) -> bool {
        self.reuse.is_some() || self.record.is_some()
    }
}

/// Cut face `f` re-triangulated along its cut segments, its pieces appended
/// to `out` (see [`retriangulate`]).
fn cut_face(
    pos: &[V3],
    faces: &[[u32; 3]],
    cuts: &mut Cuts,
    f: u32,
    triples: &mut FastMap<[u32; 3], u32>,
    out: &mut Pieces,
    memo: &mut Remembering,
) -> Result<(), Refusal> {
    let face = faces[f as usize];
    // Each face is cut once: its record is taken, not copied.
    let cut = cuts
        .faces
        .get_mut(&f)
        .map(std::mem::take)
        .unwrap_or_default();
    // The boundary: corners and the new vertices on each edge, in order.
    let mut boundary: Vec<u32> = Vec::with_capacity(3 + cut.segments.len());
    for e in 0..3 {
        let (a, b) = (face[e], face[(e + 1) % 3]);
        boundary.push(a);
        if let Some(on_edge) = cuts.edge_points.get(&(a.min(b), a.max(b))) {
            let mut on_edge = on_edge.clone();
            on_edge.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            if a > b {
                on_edge.reverse();
            }
            boundary.extend(on_edge.iter().map(|x| cuts.rep(x.1)));
        }
    }
    // Merged vertices: a point inside this face may now be on its edge,
    // and a segment between two merged points is gone.
    let mut inner: Vec<u32> = cut
        .inner
        .iter()
        .map(|&k| cuts.rep(k))
        .filter(|k| !boundary.contains(k))
        .collect();
    let segments: Vec<([u32; 2], u32)> = cut
        .segments
        .iter()
        .map(|&(s, g)| (s.map(|k| cuts.rep(k)), g))
        .filter(|(s, _)| s[0] != s[1])
        .collect();
    // This face and every face cutting it.
    let at_fault = |why| {
        let mut at: Vec<u32> = vec![f];
        at.extend(segments.iter().map(|x| x.1));
        Refusal { why, faces: at }
    };
    let t = face.map(|k| at(pos, k));
    let n = crate::kernel::vector::cross(
        crate::kernel::vector::sub(t[1], t[0]),
        crate::kernel::vector::sub(t[2], t[0]),
    );
    let axis = (0..3)
        .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .unwrap_or(2);
    let flip = n[axis] < 0.0;
    let flat = |p: P3| match axis {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    };
    // Triple points: crossings of segments that come from different faces.
    let segs = &segments;
    let mut splits: Vec<Vec<(f64, u32)>> = vec![Vec::new(); segs.len()];
    for i in 0..segs.len() {
        for j in i + 1..segs.len() {
            let ((s, g), (r, h)) = (segs[i], segs[j]);
            if g == h || s.iter().any(|k| r.contains(k)) {
                continue;
            }
            let [a, b, c, d] = [s[0], s[1], r[0], r[1]].map(|k| flat(cuts.at(pos, k)));
            let o = [
                orient2d_sign(a, b, c),
                orient2d_sign(a, b, d),
                orient2d_sign(c, d, a),
                orient2d_sign(c, d, b),
            ];
            if o[0] * o[1] > 0 || o[2] * o[3] > 0 {
                continue;
            }
            if o.contains(&0) {
                return Err(Refusal::new(
                    "two cut segments touch inside a face",
                    &[f, g, h],
                ));
            }
            let mut key = [f, g, h];
            key.sort_unstable();
            let id = match triples.get(&key) {
                Some(&id) => id,
                None => {
                    let id = cuts
                        .triple_point(pos, faces, key)
                        .map_err(|why| Refusal::new(why, &key))?;
                    triples.insert(key, id);
                    id
                }
            };
            // Order along each segment by the 2D crossing parameter.
            let den = (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]);
            let ta = ((c[0] - a[0]) * (d[1] - c[1]) - (c[1] - a[1]) * (d[0] - c[0])) / den;
            let tc = ((c[0] - a[0]) * (b[1] - a[1]) - (c[1] - a[1]) * (b[0] - a[0])) / den;
            splits[i].push((ta, id));
            splits[j].push((tc, id));
            inner.push(id);
        }
    }
    inner.sort_unstable();
    inner.dedup();
    let ids: Vec<u32> = boundary.iter().chain(&inner).copied().collect();
    let local: FastMap<u32, usize> = ids.iter().enumerate().map(|(i, &k)| (k, i)).collect();
    if local.len() != ids.len() {
        return Err(at_fault(
            "a new vertex is both on an edge and inside a face",
        ));
    }
    let pts2: Vec<[f64; 2]> = ids.iter().map(|&k| flat(cuts.at(pos, k))).collect();
    let nb = boundary.len();
    let mut edges: Vec<[usize; 2]> = (0..nb).map(|i| [i, (i + 1) % nb]).collect();
    for (k, (s, _)) in segs.iter().enumerate() {
        let mut chain = vec![s[0]];
        let mut cuts_on = splits[k].clone();
        cuts_on.sort_by(|x, y| x.0.total_cmp(&y.0));
        chain.extend(cuts_on.iter().map(|x| x.1));
        chain.push(s[1]);
        for w in chain.windows(2) {
            edges.push([local[&w[0]], local[&w[1]]]);
            cuts.cut_edges.insert((w[0].min(w[1]), w[0].max(w[1])));
        }
    }
    let before = out.faces.len();
    // The pieces are a function of the face's corners, the points in `ids`
    // (triple points made) and the segments between them: a face cut from
    // the same as the last time takes its pieces from then.
    if memo.active() {
        let inputs = &mut memo.inputs;
        inputs.clear();
        inputs.extend([nb as u64, ids.len() as u64, segs.len() as u64]);
        inputs.extend(t.iter().flatten().map(|x| x.to_bits()));
        inputs.extend(pts2.iter().flatten().map(|x| x.to_bits()));
        inputs.extend(
            edges[nb..]
                .iter()
                .map(|e| ((e[0] as u64) << 32) | e[1] as u64),
        );
        if let Some(tris) = memo.reuse.and_then(|m| m.get(f, &memo.inputs)) {
            out.faces
                .extend(tris.iter().map(|t| t.map(|i| ids[i as usize])));
            out.origin.extend(std::iter::repeat_n(f, tris.len()));
            // Remembered again, for a cut after this one.
            if let Some(record) = memo.record.as_deref_mut() {
                record.put(f, &memo.inputs, tris.iter().copied());
            }
            return Ok(());
        }
    }
    // Remembers the pieces made since `before` (as local numbers); `inputs`
    // were filled above whenever there is a record.
    let keep = |memo: &mut Remembering, out: &Pieces| {
        if let Some(record) = memo.record.as_deref_mut() {
            let pieces = out.faces[before..].iter();
            record.put(f, &memo.inputs, pieces.map(|t| t.map(|k| local[&k] as u32)));
        }
    };
    // One or more curves straight across the face, the common case: split
    // and clip ears (in the plane mirrored where the face looks down, so
    // that its boundary runs counter-clockwise).
    if splits.iter().all(Vec::is_empty) {
        let local_segs: Vec<[usize; 2]> = segs.iter().map(|(s, _)| s.map(|k| local[&k])).collect();
        let seen: std::borrow::Cow<[[f64; 2]]> = if flip {
            pts2.iter().map(|p| [-p[0], p[1]]).collect()
        } else {
            (&pts2[..]).into()
        };
        let clipped = chains(nb, ids.len(), &local_segs)
            .and_then(|c| crate::kernel::planar::split_by_chains(nb, &c))
            .and_then(|pieces| {
                let mut tris = Vec::new();
                for p in &pieces {
                    tris.extend(crate::kernel::planar::triangulate_polygon(&seen, p)?);
                }
                Some(tris)
            });
        if let Some(tris) = clipped {
            out.faces.extend(tris.iter().map(|t| t.map(|i| ids[i])));
            out.origin.extend(std::iter::repeat_n(f, tris.len()));
            if out.faces.len() - before != nb + 2 * inner.len() - 2 {
                return Err(at_fault("a cut face's pieces do not cover it"));
            }
            keep(memo, out);
            return Ok(());
        }
    }
    let mut conflict = false;
    let points: Vec<Point2<f64>> = pts2.iter().map(|p| Point2::new(p[0], p[1])).collect();
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, edges, |_| conflict = true)
            .map_err(|_| at_fault("a cut face cannot be triangulated"))?;
    if conflict {
        return Err(at_fault("cut segments cross inside a face after rounding"));
    }
    if cdt.num_vertices() != ids.len() {
        return Err(at_fault("two new vertices round to one point"));
    }
    let outline: Vec<[f64; 2]> = pts2[..nb].to_vec();
    for (ccw, c) in crate::kernel::planar::triangles_with_centroids(&cdt, &pts2) {
        if !crate::kernel::planar::inside_polygon(c, &outline) {
            continue;
        }
        let w = if flip { [ccw[0], ccw[2], ccw[1]] } else { ccw };
        out.faces.push(w.map(|i| ids[i]));
        out.origin.push(f);
    }
    // A polygon of nb corners with ni inner vertices has nb + 2 ni - 2 triangles.
    if out.faces.len() - before != nb + 2 * inner.len() - 2 {
        return Err(at_fault("a cut face's pieces do not cover it"));
    }
    keep(memo, out);
    Ok(())
}

/// The cut segments `segs` (local vertex numbers: the `nb` boundary vertices
/// first, then the `n - nb` inner ones) as chains from a boundary vertex to
/// another through inner vertices, if that is all they are: every inner
/// vertex on two segments, every boundary vertex on at most one, no loop.
fn chains(nb: usize, n: usize, segs: &[[usize; 2]]) -> Option<Vec<Vec<usize>>> {
    let mut at: Vec<[usize; 2]> = vec![[usize::MAX; 2]; n];
    let mut degree = vec![0usize; n];
    for (k, s) in segs.iter().enumerate() {
        for &v in s {
            if degree[v] == 2 {
                return None;
            }
            at[v][degree[v]] = k;
            degree[v] += 1;
        }
    }
    if (0..nb).any(|v| degree[v] > 1) || (nb..n).any(|v| degree[v] != 2) {
        return None;
    }
    let mut used = vec![false; segs.len()];
    let mut out = Vec::new();
    for start in 0..nb {
        if degree[start] != 1 || used[at[start][0]] {
            continue;
        }
        let mut chain = vec![start];
        let (mut v, mut k) = (start, at[start][0]);
        loop {
            used[k] = true;
            v = if segs[k][0] == v {
                segs[k][1]
            } else {
                segs[k][0]
            };
            chain.push(v);
            if v < nb {
                break;
            }
            k = if at[v][0] == k { at[v][1] } else { at[v][0] };
        }
        out.push(chain);
    }
    // Segments not reached from the boundary close a loop inside the face.
    used.iter().all(|&u| u).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::chains;

    #[test]
    fn cut_segments_become_chains_across_the_face_or_none() {
        // Boundary 0..5, inner 5 and 6: one curve 1 → 5 → 6 → 4, given in any
        // order and direction.
        assert_eq!(
            chains(5, 7, &[[6, 4], [5, 1], [5, 6]]),
            Some(vec![vec![1, 5, 6, 4]])
        );
        // Two curves, each a single segment.
        assert_eq!(
            chains(7, 7, &[[1, 3], [4, 6]]),
            Some(vec![vec![1, 3], vec![4, 6]])
        );
        // A loop inside the face, an inner end, a boundary vertex on two.
        assert_eq!(chains(3, 6, &[[3, 4], [4, 5], [5, 3]]), None);
        assert_eq!(chains(5, 6, &[[1, 5]]), None);
        assert_eq!(chains(5, 6, &[[1, 5], [5, 2], [1, 3]]), None);
    }
}
