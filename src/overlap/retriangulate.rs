//! Re-triangulating the cut faces (step 2 of [`crate::overlap`], after
//! [`super::cut`] found where they cross).
//!
//! Each cut face becomes a planar polygon: its corners and the new vertices
//! on its edges as the outline, the new vertices inside it and the cut
//! segments between them as constraints. Where two cut segments of a face
//! cross, three faces meet in one point: it becomes a new vertex (keyed by
//! the three faces, placed where their planes meet) that splits both
//! segments, in each of the three faces.
//!
//! A face whose segments only form chains from edge to edge (no triple
//! point, no loop: one or two intersection curves passing through it, by far
//! the common case) is split along them and each part ear-clipped
//! ([`crate::kernel::planar::triangulate_polygon`], the triangulation spade
//! would give, at a tenth of the cost of its bulk load); the rest go through
//! spade's constrained Delaunay triangulation.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::cut::{Cuts, Refusal, Refused};
use super::cut_memo::Memo;
use crate::kernel::hash::FastMap;
use crate::kernel::predicates::orient2d_sign;
use crate::kernel::vector::{P3, V3, at, cross, sub};

/// The pieces of the cut faces.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Pieces {
    /// Triangles, oriented as the faces they come from.
    pub faces: Vec<[u32; 3]>,
    /// The face each piece comes from.
    pub origin: Vec<u32>,
}

/// Re-triangulates every cut face with its split edges and cut segments as
/// constraints, in increasing face order, so the result is deterministic.
#[cfg(test)]
pub fn retriangulate(pos: &[V3], faces: &[[u32; 3]], cuts: &mut Cuts) -> Result<Pieces, Refusal> {
    retriangulate_with(pos, faces, cuts, None, None)
}

/// Every cut face re-triangulated (see the module docs), taking the pieces
/// of a face from `reuse` where its inputs are those it remembers, and
/// remembering in `record` what each face gave ([`super::cut_memo`]). The
/// pieces are those a re-triangulation without memos gives.
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

/// The plane a face is triangulated in: the coordinate plane its normal is
/// closest to, mirrored where the face looks down the dropped axis.
#[derive(Debug, Clone, Copy)]
struct Plane {
    axis: usize,
    flip: bool,
}

impl Plane {
    /// The plane of triangle `t`.
    fn of(t: [P3; 3]) -> Plane {
        let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
        let axis = (0..3)
            .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
            .unwrap_or(2);
        Plane {
            axis,
            flip: n[axis] < 0.0,
        }
    }

    /// Point `p` in the plane (not mirrored).
    fn flat(self, p: P3) -> [f64; 2] {
        match self.axis {
            0 => [p[1], p[2]],
            1 => [p[2], p[0]],
            _ => [p[0], p[1]],
        }
    }
}

/// One cut face laid out for triangulation: its vertices numbered locally
/// (the outline first), their positions in its plane and the constraint
/// edges.
struct Layout {
    /// The face's index.
    f: u32,
    /// The vertices: the `nb` of the outline in order, then the inner ones.
    ids: Vec<u32>,
    /// The local number of each vertex.
    local: FastMap<u32, usize>,
    /// The vertices in the face's plane (not mirrored).
    flat: Vec<[f64; 2]>,
    /// How many vertices the outline has.
    nb: usize,
    /// The outline's edges, then the cut segments' pieces, in local numbers.
    edges: Vec<[usize; 2]>,
    /// The face's plane.
    plane: Plane,
    /// This face and every face cutting it: the faces at fault if it fails.
    at_fault: Vec<u32>,
    /// How many cut segments cross the face.
    segments: usize,
    /// Whether two of them cross each other (at a triple point).
    crossed: bool,
}

impl Layout {
    /// A refusal of this face, naming every face at fault.
    fn refuse(&self, why: &'static str) -> Refusal {
        Refusal {
            why,
            faces: self.at_fault.clone(),
        }
    }

    /// A polygon of `nb` corners with `ni` inner vertices has `nb + 2 ni - 2`
    /// triangles.
    fn piece_count(&self) -> usize {
        self.nb + 2 * (self.ids.len() - self.nb) - 2
    }
}

/// Cut face `f` re-triangulated along its cut segments, its pieces appended
/// to `out` (see the module docs).
fn cut_face(
    pos: &[V3],
    faces: &[[u32; 3]],
    cuts: &mut Cuts,
    f: u32,
    triples: &mut FastMap<[u32; 3], u32>,
    out: &mut Pieces,
    memo: &mut Remembering,
) -> Result<(), Refusal> {
    let corners = faces[f as usize].map(|k| at(pos, k));
    let layout = lay_out(pos, faces, cuts, f, triples)?;
    let before = out.faces.len();
    // The pieces are a function of the face's corners, the points in `ids`
    // (triple points made) and the segments between them: a face cut from
    // the same as the last time takes its pieces from then.
    if memo.active() && recall(memo, &layout, corners, out) {
        return Ok(());
    }
    let chained = if layout.crossed {
        None
    } else {
        clip_along_chains(&layout)
    };
    match chained {
        Some(tris) => {
            let ids = &layout.ids;
            out.faces.extend(tris.iter().map(|t| t.map(|i| ids[i])));
            out.origin.extend(std::iter::repeat_n(f, tris.len()));
        }
        None => triangulate_constrained(&layout, out)?,
    }
    if out.faces.len() - before != layout.piece_count() {
        return Err(layout.refuse("a cut face's pieces do not cover it"));
    }
    if let Some(record) = memo.record.as_deref_mut() {
        // The pieces as local numbers; the inputs were filled by `recall`.
        let pieces = out.faces[before..].iter();
        let local = &layout.local;
        record.put(f, &memo.inputs, pieces.map(|t| t.map(|k| local[&k] as u32)));
    }
    Ok(())
}

/// Face `f` laid out for triangulation: its outline (corners and the new
/// vertices on its edges, in order), the new vertices inside it and the
/// triple points where its cut segments cross, and the constraint edges.
fn lay_out(
    pos: &[V3],
    faces: &[[u32; 3]],
    cuts: &mut Cuts,
    f: u32,
    triples: &mut FastMap<[u32; 3], u32>,
) -> Result<Layout, Refusal> {
    let face = faces[f as usize];
    // Each face is cut once: its record is taken, not copied.
    let cut = cuts
        .faces
        .get_mut(&f)
        .map(std::mem::take)
        .unwrap_or_default();
    let boundary = outline(cuts, face);
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
    let mut at_fault: Vec<u32> = vec![f];
    at_fault.extend(segments.iter().map(|x| x.1));
    let plane = Plane::of(face.map(|k| at(pos, k)));
    let splits = triple_points(pos, faces, cuts, f, &segments, plane, triples)?;
    inner.extend(splits.iter().flatten().map(|x| x.1));
    inner.sort_unstable();
    inner.dedup();
    let ids: Vec<u32> = boundary.iter().chain(&inner).copied().collect();
    let local: FastMap<u32, usize> = ids.iter().enumerate().map(|(i, &k)| (k, i)).collect();
    let nb = boundary.len();
    let mut layout = Layout {
        f,
        flat: Vec::new(),
        nb,
        edges: (0..nb).map(|i| [i, (i + 1) % nb]).collect(),
        plane,
        at_fault,
        ids,
        local,
        segments: segments.len(),
        crossed: splits.iter().any(|s| !s.is_empty()),
    };
    if layout.local.len() != layout.ids.len() {
        return Err(layout.refuse("a new vertex is both on an edge and inside a face"));
    }
    layout.flat = layout
        .ids
        .iter()
        .map(|&k| plane.flat(cuts.at(pos, k)))
        .collect();
    for (k, (s, _)) in segments.iter().enumerate() {
        let mut chain = vec![s[0]];
        let mut cuts_on = splits[k].clone();
        cuts_on.sort_by(|x, y| x.0.total_cmp(&y.0));
        chain.extend(cuts_on.iter().map(|x| x.1));
        chain.push(s[1]);
        for w in chain.windows(2) {
            layout
                .edges
                .push([layout.local[&w[0]], layout.local[&w[1]]]);
            cuts.cut_edges.insert((w[0].min(w[1]), w[0].max(w[1])));
        }
    }
    Ok(layout)
}

/// The outline of `face`: its corners and the new vertices on each edge, in
/// order.
fn outline(cuts: &Cuts, face: [u32; 3]) -> Vec<u32> {
    let mut boundary: Vec<u32> = Vec::with_capacity(3);
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
    boundary
}

/// Where the cut segments of face `f` from different faces cross: per
/// segment, the triple points on it with their parameter along it.
fn triple_points(
    pos: &[V3],
    faces: &[[u32; 3]],
    cuts: &mut Cuts,
    f: u32,
    segs: &[([u32; 2], u32)],
    plane: Plane,
    triples: &mut FastMap<[u32; 3], u32>,
) -> Result<Vec<Vec<(f64, u32)>>, Refusal> {
    let mut splits: Vec<Vec<(f64, u32)>> = vec![Vec::new(); segs.len()];
    for i in 0..segs.len() {
        for j in i + 1..segs.len() {
            let ((s, g), (r, h)) = (segs[i], segs[j]);
            if g == h || s.iter().any(|k| r.contains(k)) {
                continue;
            }
            let [a, b, c, d] = [s[0], s[1], r[0], r[1]].map(|k| plane.flat(cuts.at(pos, k)));
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
        }
    }
    Ok(splits)
}

/// Fills `memo`'s inputs with those of `layout` (and the face's `corners`)
/// and, if the memo to reuse remembers the same inputs for its face, appends
/// the pieces it remembers to `out` (remembering them again in the record):
/// whether it did.
fn recall(memo: &mut Remembering, layout: &Layout, corners: [P3; 3], out: &mut Pieces) -> bool {
    let (nb, f) = (layout.nb, layout.f);
    let inputs = &mut memo.inputs;
    inputs.clear();
    inputs.extend([nb as u64, layout.ids.len() as u64, layout.segments as u64]);
    inputs.extend(corners.iter().flatten().map(|x| x.to_bits()));
    inputs.extend(layout.flat.iter().flatten().map(|x| x.to_bits()));
    inputs.extend(
        layout.edges[nb..]
            .iter()
            .map(|e| ((e[0] as u64) << 32) | e[1] as u64),
    );
    let Some(tris) = memo.reuse.and_then(|m| m.get(f, &memo.inputs)) else {
        return false;
    };
    out.faces
        .extend(tris.iter().map(|t| t.map(|i| layout.ids[i as usize])));
    out.origin.extend(std::iter::repeat_n(f, tris.len()));
    // Remembered again, for a cut after this one.
    if let Some(record) = memo.record.as_deref_mut() {
        record.put(f, &memo.inputs, tris.iter().copied());
    }
    true
}

/// One or more curves straight across the face, the common case: the face
/// split along them and each part ear-clipped (in the plane mirrored where
/// the face looks down, so that its outline runs counter-clockwise), in
/// local numbers; `None` where the cut segments are not such chains.
fn clip_along_chains(layout: &Layout) -> Option<Vec<[usize; 3]>> {
    let nb = layout.nb;
    let local_segs = &layout.edges[nb..];
    let seen: std::borrow::Cow<[[f64; 2]]> = if layout.plane.flip {
        layout.flat.iter().map(|p| [-p[0], p[1]]).collect()
    } else {
        (&layout.flat[..]).into()
    };
    let chains = chains(nb, layout.ids.len(), local_segs)?;
    let pieces = crate::kernel::planar::split_by_chains(nb, &chains)?;
    let mut tris = Vec::new();
    for p in &pieces {
        tris.extend(crate::kernel::planar::triangulate_polygon(&seen, p)?);
    }
    Some(tris)
}

/// The face's pieces by spade's constrained Delaunay triangulation of its
/// layout, those inside its outline appended to `out`.
fn triangulate_constrained(layout: &Layout, out: &mut Pieces) -> Result<(), Refusal> {
    let mut conflict = false;
    let points: Vec<Point2<f64>> = layout
        .flat
        .iter()
        .map(|p| Point2::new(p[0], p[1]))
        .collect();
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, layout.edges.clone(), |_| {
            conflict = true
        })
        .map_err(|_| layout.refuse("a cut face cannot be triangulated"))?;
    if conflict {
        return Err(layout.refuse("cut segments cross inside a face after rounding"));
    }
    if cdt.num_vertices() != layout.ids.len() {
        return Err(layout.refuse("two new vertices round to one point"));
    }
    let outline: Vec<[f64; 2]> = layout.flat[..layout.nb].to_vec();
    for (ccw, c) in crate::kernel::planar::triangles_with_centroids(&cdt, &layout.flat) {
        if !crate::kernel::planar::inside_polygon(c, &outline) {
            continue;
        }
        let w = if layout.plane.flip {
            [ccw[0], ccw[2], ccw[1]]
        } else {
            ccw
        };
        out.faces.push(w.map(|i| layout.ids[i]));
        out.origin.push(layout.f);
    }
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
