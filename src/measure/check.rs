//! The mesh quality checks: is it a valid closed surface, and how far from
//! one ([`MeshReport`]).
//!
//! [`Mesh::check`] answers the questions every test and every user asks of a
//! mesh: closed (every edge in exactly two faces), edge- and vertex-manifold,
//! consistently oriented and facing outward, connected components, Euler
//! characteristic, degenerate and duplicate faces, and self-intersecting
//! triangle pairs. It works on any mesh, including other tools' meshes read from
//! OBJ, PLY or STL.
//!
//! Self-intersections are found with a [`Bvh`] over the triangle boxes and exact-
//! in-spirit predicates from [`crate::kernel::predicates`]; pairs that share a vertex or an edge
//! get their own tests. Given the morphology the mesh came from,
//! [`Mesh::check_with`] splits the intersecting pairs into those the
//! construction made and those where the skeleton itself overlaps (two branches
//! far apart in the tree passing through each other in space), by the tree path
//! between the two triangles' samples: see [`is_skeleton_overlap`].

use crate::input::morphology::{Morphology, NO_PARENT};
use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::disjoint_sets::face_components;
use crate::kernel::predicates::pair_intersects;
use crate::kernel::vector::{cross, norm, sub};
use crate::measure::report::{MAX_LISTED_PAIRS, MeshReport};
use crate::measure::skeleton::SkeletonMeasures;
use crate::mesh::{Mesh, MeshView};

impl Mesh {
    /// Checks topology, orientation and self-intersections.
    pub fn check(&self) -> MeshReport {
        let mut r = self.view().check(None);
        r.stats = self.stats.clone();
        r
    }

    /// What makes the mesh unsound as far as a check in linear time can
    /// tell: open, non-manifold or inward edges and faces, degenerate or
    /// duplicate faces, and the crossing pairs the overlap pass reported
    /// left (the construction's own count; [`Mesh::check`] searches every
    /// pair). Empty for a sound mesh. What `neuromesh mesh` and `batch`
    /// check on every mesh they write.
    pub fn quick_defects(&self) -> Vec<String> {
        let r = self.view().check_topology();
        let mut out = Vec::new();
        let mut say = |n: usize, what: &str| {
            if n > 0 {
                out.push(format!("{n} {what}"));
            }
        };
        say(r.boundary_edges, "boundary edges");
        say(r.nonmanifold_edges, "non-manifold edges");
        say(r.nonmanifold_vertices, "non-manifold vertices");
        say(r.misoriented_edges, "misoriented edges");
        say(r.inward_components, "inward components");
        say(r.degenerate_faces, "degenerate faces");
        say(r.duplicate_faces, "duplicate faces");
        say(
            self.stats.overlap_pairs_left as usize,
            "crossing pairs of parts left by the overlap pass",
        );
        out
    }

    /// Like [`Mesh::check`], and splits self-intersections into construction
    /// defects and skeleton overlaps using the vertices' sample labels.
    pub fn check_with(&self, morphology: &Morphology) -> MeshReport {
        let mut r = self.view().check(Some(morphology));
        r.stats = self.stats.clone();
        r
    }
}

impl MeshView<'_> {
    /// The report without the self-intersection search (which is most of the
    /// cost): closedness, manifoldness, orientation, components, measures.
    pub fn check_topology(&self) -> MeshReport {
        let mut r = MeshReport {
            vertices: self.vertices.len(),
            faces: self.faces.len(),
            area: self.area(),
            volume: self.volume(),
            ..MeshReport::default()
        };
        topology(self, &mut r);
        r
    }

    /// The full report. With a morphology, the mesh is compared point by
    /// point with the union of the skeleton's round cones
    /// ([`crate::Fidelity`]) and the skeleton's measures include the union's;
    /// with sample labels too, self-intersections are split into
    /// construction defects and skeleton overlaps and the soma's area is
    /// measured. The caller must have validated the view.
    pub fn check(&self, morphology: Option<&Morphology>) -> MeshReport {
        self.check_measuring(morphology, true)
    }

    /// [`MeshView::check`] without the union of round cones
    /// (`skeleton.union` is `None`; the NeuroMorpho-style measures are there).
    /// The union is a Monte Carlo estimate, and on cells of thousands of
    /// nested balls it costs far more than the rest of the check: this is
    /// for callers that only need the mesh's own soundness.
    pub fn check_without_union(&self, morphology: Option<&Morphology>) -> MeshReport {
        self.check_measuring(morphology, false)
    }

    fn check_measuring(&self, morphology: Option<&Morphology>, union: bool) -> MeshReport {
        let mut r = self.check_topology();
        let pairs = self_intersections(self);
        r.self_intersections = pairs.len();
        r.intersecting_pairs = pairs.iter().take(MAX_LISTED_PAIRS).copied().collect();
        let Some(m) = morphology else {
            return r;
        };
        r.fidelity = Some(super::fidelity::fidelity(self, m));
        r.skeleton = Some(if union {
            SkeletonMeasures::with_union(m)
        } else {
            SkeletonMeasures::of(m)
        });
        // The rest reads the vertices' sample labels.
        if self.vertex_sample.len() == self.vertices.len() {
            let depth = tree_depths(m);
            let skeleton = pairs
                .iter()
                .filter(|p| is_skeleton_overlap(self, m, &depth, **p))
                .count();
            r.skeleton_overlaps = Some(skeleton);
            r.construction_intersections = Some(pairs.len() - skeleton);
            let soma = m.soma_mask();
            let in_soma = |v: u32| {
                let s = self.vertex_sample[v as usize] as usize;
                s < soma.len() && soma[s]
            };
            r.soma_area = Some(
                (0..self.faces.len())
                    .filter(|&f| self.faces[f].iter().all(|&v| in_soma(v)))
                    .map(|f| self.face_area(f))
                    .sum(),
            );
        }
        r
    }
}

fn topology(mesh: &MeshView<'_>, r: &mut MeshReport) {
    let nv = mesh.vertices.len();
    // Directed edges sorted by their undirected key: a scan then sees each edge's uses.
    let mut edges: Vec<(u64, bool)> = Vec::with_capacity(mesh.faces.len() * 3);
    let mut used = vec![false; nv];
    let mut face_keys: Vec<[u32; 3]> = Vec::with_capacity(mesh.faces.len());
    let origin = mesh.center();
    for (fi, f) in mesh.faces.iter().enumerate() {
        for k in 0..3 {
            used[f[k] as usize] = true;
            let (a, b) = (f[k], f[(k + 1) % 3]);
            if a != b {
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                edges.push((key, a < b));
            }
        }
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            r.degenerate_faces += 1;
        } else {
            let [a, b, c] = mesh.triangle(fi, origin);
            let (e1, e2, e3) = (sub(b, a), sub(c, a), sub(c, b));
            let longest = crate::kernel::vector::dot(e1, e1)
                .max(crate::kernel::vector::dot(e2, e2))
                .max(crate::kernel::vector::dot(e3, e3));
            if norm(cross(e1, e2)) <= 1e-9 * longest {
                r.degenerate_faces += 1;
            }
        }
        let mut key = *f;
        key.sort_unstable();
        face_keys.push(key);
    }
    face_keys.sort_unstable();
    r.duplicate_faces = face_keys.windows(2).filter(|w| w[0] == w[1]).count();
    r.unreferenced_vertices = used.iter().filter(|u| !**u).count();

    edges.sort_unstable();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i;
        let (mut fwd, mut bwd) = (0, 0);
        while j < edges.len() && edges[j].0 == edges[i].0 {
            if edges[j].1 {
                fwd += 1
            } else {
                bwd += 1
            }
            j += 1;
        }
        r.edges += 1;
        match j - i {
            1 => r.boundary_edges += 1,
            2 => {
                if fwd != 1 || bwd != 1 {
                    r.misoriented_edges += 1;
                }
            }
            _ => r.nonmanifold_edges += 1,
        }
        i = j;
    }

    // Components by shared vertices, with signed volume per component.
    let component = face_components(mesh.faces, mesh.vertices.len());
    let mut comp_volume =
        vec![0.0f64; component.iter().map(|&c| c as usize + 1).max().unwrap_or(0)];
    for (fi, &k) in component.iter().enumerate() {
        let [a, b, c] = mesh.triangle(fi, origin);
        comp_volume[k as usize] += crate::kernel::vector::dot(a, cross(b, c)) / 6.0;
    }
    r.components = comp_volume.len();
    r.inward_components = comp_volume.iter().filter(|&&v| v < 0.0).count();
    let used_count = nv - r.unreferenced_vertices;
    r.euler_characteristic = used_count as i64 - r.edges as i64 + mesh.faces.len() as i64;
    r.nonmanifold_vertices = nonmanifold_vertices(mesh);
}

/// Counts vertices whose incident faces do not form a single fan: the "link"
/// (the opposite edges of the incident faces) must be one connected piece.
fn nonmanifold_vertices(mesh: &MeshView<'_>) -> usize {
    let nv = mesh.vertices.len();
    let mut count = vec![0u32; nv + 1];
    for f in mesh.faces {
        for &v in f {
            count[v as usize] += 1;
        }
    }
    let mut start = vec![0u32; nv + 1];
    for v in 0..nv {
        start[v + 1] = start[v] + count[v];
    }
    let mut fill = start.clone();
    let mut link = vec![[0u32; 2]; start[nv] as usize];
    for f in mesh.faces {
        for k in 0..3 {
            let v = f[k] as usize;
            link[fill[v] as usize] = [f[(k + 1) % 3], f[(k + 2) % 3]];
            fill[v] += 1;
        }
    }
    let mut bad = 0;
    let mut labels: Vec<u32> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    for v in 0..nv {
        let edges = &link[start[v] as usize..start[v + 1] as usize];
        if edges.len() < 2 {
            continue;
        }
        labels.clear();
        parent.clear();
        let local = |x: u32, labels: &mut Vec<u32>, parent: &mut Vec<usize>| -> usize {
            if let Some(p) = labels.iter().position(|&l| l == x) {
                p
            } else {
                labels.push(x);
                parent.push(parent.len());
                parent.len() - 1
            }
        };
        for e in edges {
            let a = local(e[0], &mut labels, &mut parent);
            let b = local(e[1], &mut labels, &mut parent);
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
        let pieces = (0..parent.len())
            .filter(|&i| root(&mut parent, i) == i)
            .count();
        if pieces > 1 {
            bad += 1;
        }
    }
    bad
}

fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// All pairs of faces that intersect and are not neighbours (or are neighbours
/// that overlap beyond their shared vertex or edge), sorted.
pub fn self_intersections(mesh: &MeshView<'_>) -> Vec<[u32; 2]> {
    // Absolute coordinates: the f32 values convert to f64 exactly, so the exact
    // predicates judge the mesh as stored.
    let origin = [0.0; 3];
    let tris: Vec<[[f64; 3]; 3]> = (0..mesh.faces.len())
        .map(|f| mesh.triangle(f, origin))
        .collect();
    let boxes: Vec<Aabb> = tris.iter().map(|t| Aabb::of(t)).collect();
    let bvh = Bvh::new(boxes);
    let degenerate = |f: [u32; 3]| f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
    bvh.overlapping_pairs(|i, j| {
        let (fi, fj) = (mesh.faces[i as usize], mesh.faces[j as usize]);
        !degenerate(fi)
            && !degenerate(fj)
            && pair_intersects(fi, fj, tris[i as usize], tris[j as usize])
    })
}

/// The sample a face mostly comes from: its first vertex's label.
fn face_sample(mesh: &MeshView<'_>, f: u32) -> u32 {
    mesh.vertex_sample[mesh.faces[f as usize][0] as usize]
}

/// Depth of every sample in the morphology's geometry tree.
pub fn tree_depths(m: &Morphology) -> Vec<u32> {
    let mut depth = vec![0u32; m.len()];
    for &i in m.order() {
        let p = m.parents()[i as usize];
        if p != NO_PARENT {
            depth[i as usize] = depth[p as usize] + 1;
        }
    }
    depth
}

/// Whether an intersecting face pair comes from the skeleton overlapping itself
/// rather than from the construction.
///
/// The two faces' samples `a` and `b` are joined by a path in the tree (or lie
/// in different trees: always an overlap). The pair is a skeleton overlap when
/// that path wanders away between them: some sample `x` on it is farther than
/// `r_x + r + D` from both (`r` being `a`'s or `b`'s radius), with the reach
/// `D = 3·(r_a + r_b)`. Then the skeleton leaves and comes back to where it was,
/// and a mesh of the union of round cones would have to merge the two parts.
/// The reach covers everything a junction builds: a secondary leaving at 20°
/// clears its primary about `3·(R + r)` from the branch point, and the faces
/// of its junction are labelled with samples on either side of that stretch.
/// The rule errs towards "construction": a thin branch that curls back into a
/// much thicker part of itself within that reach counts as construction.
pub fn is_skeleton_overlap(
    mesh: &MeshView<'_>,
    m: &Morphology,
    depth: &[u32],
    pair: [u32; 2],
) -> bool {
    let (a, b) = (face_sample(mesh, pair[0]), face_sample(mesh, pair[1]));
    if a as usize >= m.len() || b as usize >= m.len() {
        return false;
    }
    if m.tree_of()[a as usize] != m.tree_of()[b as usize] {
        return true;
    }
    let (pos, r, parents) = (m.positions(), m.radii(), m.parents());
    let (ra, rb) = (r[a as usize], r[b as usize]);
    let reach = 3.0 * (ra + rb);
    let (pa, pb) = (pos[a as usize], pos[b as usize]);
    let dist = crate::input::morphology::dist;
    let away = |x: u32| {
        let (px, rx) = (pos[x as usize], r[x as usize]);
        dist(px, pa) > ra + rx + reach && dist(px, pb) > rb + rx + reach
    };
    let (mut x, mut y) = (a, b);
    while x != y {
        if depth[x as usize] >= depth[y as usize] {
            x = parents[x as usize];
        } else {
            y = parents[y as usize];
        }
        if x == NO_PARENT || y == NO_PARENT {
            return true;
        }
        if away(x) || away(y) {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::cube;

    #[test]
    fn quick_defects_name_what_is_wrong() {
        let mut m = cube();
        assert!(m.quick_defects().is_empty());
        m.faces.pop();
        assert_eq!(m.quick_defects(), ["3 boundary edges"]);
        let mut m = cube();
        m.stats.overlap_pairs_left = 7;
        assert_eq!(
            m.quick_defects(),
            ["7 crossing pairs of parts left by the overlap pass"]
        );
    }

    #[test]
    fn closed_cube_is_valid() {
        let r = cube().check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.euler_characteristic, 2);
        assert_eq!(r.components, 1);
        assert_eq!(r.edges, 18);
        assert_eq!(r.self_intersections, 0);
    }

    #[test]
    fn removed_face_opens_the_cube() {
        let mut m = cube();
        m.faces.pop();
        let r = m.check();
        assert!(!r.is_closed());
        assert_eq!(r.boundary_edges, 3);
        assert_eq!(r.misoriented_edges, 0);
        assert_eq!(r.self_intersections, 0);
    }

    #[test]
    fn flipped_face_is_misoriented() {
        let mut m = cube();
        m.faces[3].swap(1, 2);
        let r = m.check();
        assert!(r.is_closed());
        assert_eq!(r.misoriented_edges, 3);
        assert!(!r.is_outward());
        assert_eq!(r.self_intersections, 0);
    }

    #[test]
    fn overlapping_copy_intersects() {
        let mut m = cube();
        let mut other = cube();
        for v in &mut other.vertices {
            for c in v.iter_mut() {
                *c += 0.5;
            }
        }
        m.append(&other);
        let r = m.check();
        assert!(r.is_closed() && r.is_manifold() && r.is_outward());
        assert_eq!(r.components, 2);
        assert!(r.self_intersections > 0);
        assert!(!r.is_valid());
    }

    #[test]
    fn pinched_vertex_is_nonmanifold() {
        // Two tetrahedra sharing one vertex.
        let v = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, -1.0],
        ];
        let tet = |a: u32, b: u32, c: u32, d: u32| vec![[a, c, b], [a, b, d], [a, d, c], [b, c, d]];
        let mut f = tet(0, 1, 2, 3);
        f.extend(tet(0, 4, 5, 6));
        let m = Mesh::new(v, f).unwrap();
        let r = m.check();
        assert_eq!(r.nonmanifold_vertices, 1);
        assert_eq!(r.nonmanifold_edges, 0);
    }

    #[test]
    fn degenerate_and_duplicate_faces() {
        let mut m = cube();
        m.faces.push(m.faces[0]);
        m.faces.push([0, 0, 1]);
        let r = m.check();
        assert_eq!(r.duplicate_faces, 1);
        assert_eq!(r.degenerate_faces, 1);
    }

    #[test]
    fn json_has_the_verdicts() {
        let j = cube().check().to_json();
        assert!(j.contains("\"closed\":true"));
        assert!(j.contains("\"self_intersections\":0"));
        assert!(j.starts_with('{') && j.ends_with('}'));
    }
}
