//! The output type: a triangle mesh with a sample label on every vertex.
//!
//! Storage is plain arrays (`[f32; 3]` positions, `[u32; 3]` faces) so it crosses
//! into numpy without a copy and writes to any format directly. Measures are
//! computed in f64 around the mesh's centre, so a neuron far from the origin
//! (MouseLight coordinates are ~10⁴ µm) keeps its volume to full precision.
//!
//! Positions are stored relative to the mesh's [`Mesh::origin`], in f64. An
//! f32 holds 24 bits: at 12,000 µm from the coordinates' origin its step is
//! 0.001 µm, 4 % of a 0.025 µm glial process, and rounding every vertex there
//! tilts and folds the small triangles of thin neurites into their
//! neighbours; the radius floor that keeps contours distinct in f32 grows
//! with the coordinates too. So a cell far from the origin compared with its
//! size is meshed around a point near its centre ([`frame_origin`]) and keeps
//! the precision it would have at the origin; writers add the origin back in
//! f64.
//!
//! The quality report is `measure::check`'s.

use crate::error::{Error, Result};
use crate::kernel::vector::{bounds, cross, dot, norm, sub};

/// How the mesh was built: counts that say how faithful it is to the paper.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BuildStats {
    /// Branches meshed as tubes.
    pub branches: u32,
    /// Branches left out because they lie wholly inside another part of the mesh.
    pub branches_hidden: u32,
    /// Contours skipped because they crossed their predecessor.
    pub contours_skipped: u32,
    /// Junctions built with the paper's splice (region Q, middle contours).
    pub junctions_paper: u32,
    /// Junctions built by the paper's splice after moving the secondary's first
    /// contour further out.
    pub junctions_moved: u32,
    /// Junctions built by the fallback: the secondary reaches back into its
    /// parent and the overlap pass joins them as their union.
    pub junctions_fallback: u32,
    /// Branches that could not be joined and stay separate closed components.
    pub junctions_detached: u32,
    /// Neurites joined to a soma.
    pub soma_trunks: u32,
    /// Intersecting face pairs between parts (branches passing through each
    /// other, branches inside their parent) found before the union was taken.
    pub overlap_pairs: u32,
    /// Of those, pairs still in the mesh because the union could not be built
    /// there (0 when it was).
    pub overlap_pairs_left: u32,
    /// Branches whose stretch before their first clear contour was added as a
    /// filler and united with the rest (see `ARCHITECTURE.md`); 0 when the
    /// overlap pass could not take the fillers and the cell was meshed
    /// without them.
    pub fillers: u32,
    /// Samples merged while the file was cleaned: into their parent, at the
    /// same position, or into a sample they repeat ([`crate::repairs`] says
    /// each change in words).
    pub samples_merged: u32,
    /// Zero, negative, NaN or missing radii filled while cleaning.
    pub radii_filled: u32,
    /// Soma radii replaced (missing, or a thousand times thinner than the
    /// widest neighbour).
    pub soma_radii_replaced: u32,
    /// Cycles of parent links broken while cleaning.
    pub cycles_broken: u32,
    /// Radii raised to the radius floor (`min_radius`, and never below
    /// 1e-5 of the longest side of the cell's box).
    pub radii_raised: u32,
}

/// A triangle mesh. Faces wind counter-clockwise seen from outside.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions in the skeleton's units, relative to [`Mesh::origin`]:
    /// vertex `i` lies at `origin + vertices[i]` ([`Mesh::position`]).
    pub vertices: Vec<[f32; 3]>,
    /// Triangles as vertex indices.
    pub faces: Vec<[u32; 3]>,
    /// For each vertex, the index of the morphology sample it was made from
    /// (empty for meshes read from files).
    pub vertex_sample: Vec<u32>,
    /// Construction counts (zero for meshes read from files).
    pub stats: BuildStats,
    /// The point the vertices are measured from. Zero unless the mesh lies far
    /// from the coordinates' origin compared with its size ([`frame_origin`]).
    pub origin: [f64; 3],
}

impl Mesh {
    /// A mesh from positions and faces, without labels.
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] if a face refers to a vertex that does not exist or a
    /// coordinate is not finite.
    pub fn new(vertices: Vec<[f32; 3]>, faces: Vec<[u32; 3]>) -> Result<Self> {
        let mesh = Mesh {
            vertices,
            faces,
            vertex_sample: Vec::new(),
            stats: BuildStats::default(),
            origin: [0.0; 3],
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// A mesh from f64 positions (as read from a file), stored around the
    /// origin [`frame_origin`] picks for them so no precision is lost to f32
    /// far from the coordinates' origin.
    ///
    /// # Errors
    /// As [`Mesh::new`].
    pub fn from_positions(positions: &[[f64; 3]], faces: Vec<[u32; 3]>) -> Result<Self> {
        let (lo, hi) = bounds(positions);
        let origin = frame_origin(lo, hi);
        let vertices = positions
            .iter()
            .map(|p| [0, 1, 2].map(|a| (p[a] - origin[a]) as f32))
            .collect();
        let mut mesh = Mesh::new(vertices, faces)?;
        mesh.origin = origin;
        Ok(mesh)
    }

    /// Position of vertex `i` in the skeleton's coordinates (origin added).
    pub fn position(&self, i: usize) -> [f64; 3] {
        let v = self.vertices[i];
        [0, 1, 2].map(|a| self.origin[a] + f64::from(v[a]))
    }

    /// Measures the vertices from `origin` instead (each is rounded to f32
    /// again; nothing moves when the origins are equal).
    pub fn set_origin(&mut self, origin: [f64; 3]) {
        if origin == self.origin {
            return;
        }
        let d = [0, 1, 2].map(|a| self.origin[a] - origin[a]);
        for v in &mut self.vertices {
            *v = moved(*v, d);
        }
        self.origin = origin;
    }

    /// Checks index ranges, label length and finiteness.
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] describing the first problem found.
    pub fn validate(&self) -> Result<()> {
        if self.vertices.len() > u32::MAX as usize {
            return Err(Error::InvalidMesh(format!(
                "{} vertices exceed the u32 index range",
                self.vertices.len()
            )));
        }
        self.view().validate()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// A borrowed view of the arrays, on which the measures and checks run.
    pub fn view(&self) -> MeshView<'_> {
        MeshView {
            vertices: &self.vertices,
            faces: &self.faces,
            vertex_sample: &self.vertex_sample,
            origin: self.origin,
        }
    }

    /// Centre of the vertices' bounding box, relative to [`Mesh::origin`]
    /// like the vertices; used to keep f64 sums well-conditioned.
    pub fn center(&self) -> [f64; 3] {
        self.view().center()
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        self.view().area()
    }

    /// Signed enclosed volume (divergence theorem): positive when the faces wind
    /// outward, meaningful when the mesh is closed.
    pub fn volume(&self) -> f64 {
        self.view().volume()
    }

    /// Keeps the faces `keep(f)` accepts and drops the vertices no kept face
    /// uses; both keep their order.
    pub fn retain_faces(&mut self, mut keep: impl FnMut(usize) -> bool) {
        let mut f = 0;
        self.faces.retain(|_| {
            f += 1;
            keep(f - 1)
        });
        let mut remap = vec![u32::MAX; self.vertices.len()];
        for face in &self.faces {
            for &v in face {
                remap[v as usize] = 0;
            }
        }
        let labels = self.vertex_sample.len() == self.vertices.len();
        let mut next = 0usize;
        for v in 0..remap.len() {
            if remap[v] == 0 {
                remap[v] = next as u32;
                self.vertices[next] = self.vertices[v];
                if labels {
                    self.vertex_sample[next] = self.vertex_sample[v];
                }
                next += 1;
            }
        }
        self.vertices.truncate(next);
        if labels {
            self.vertex_sample.truncate(next);
        }
        for face in &mut self.faces {
            *face = face.map(|v| remap[v as usize]);
        }
    }

    /// Appends `other`, renumbering its faces. Its vertices are measured
    /// from this mesh's origin (or this mesh takes `other`'s when it has no
    /// vertices).
    pub fn append(&mut self, other: &Mesh) {
        if self.vertices.is_empty() {
            self.origin = other.origin;
        }
        let offset = self.vertices.len() as u32;
        if other.origin == self.origin {
            self.vertices.extend_from_slice(&other.vertices);
        } else {
            let d = [0, 1, 2].map(|a| other.origin[a] - self.origin[a]);
            self.vertices
                .extend(other.vertices.iter().map(|&v| moved(v, d)));
        }
        self.faces.extend(
            other
                .faces
                .iter()
                .map(|f| [f[0] + offset, f[1] + offset, f[2] + offset]),
        );
        if !other.vertex_sample.is_empty() || !self.vertex_sample.is_empty() {
            self.vertex_sample.resize(offset as usize, u32::MAX);
            if other.vertex_sample.is_empty() {
                self.vertex_sample.resize(self.vertices.len(), u32::MAX);
            } else {
                self.vertex_sample.extend_from_slice(&other.vertex_sample);
            }
        }
    }
}

/// `v` moved by `d`, rounded to f32 again.
fn moved(v: [f32; 3], d: [f64; 3]) -> [f32; 3] {
    [0, 1, 2].map(|a| (f64::from(v[a]) + d[a]) as f32)
}

/// The origin to store a mesh spanning the box `lo`..`hi` around.
///
/// Zero when no coordinate of the box exceeds three times its largest
/// half-size in absolute value: f32 positions there lose less than two
/// bits to a local frame, and the files of most tracings (centred on the
/// soma, or starting at 0) keep their exact f32 coordinates. Otherwise the
/// box's centre, rounded to a multiple of the largest power of two not above
/// its largest half-size: few binary digits, and within half that step of
/// the centre, so no local coordinate exceeds 1.5 half-sizes.
pub fn frame_origin(lo: [f64; 3], hi: [f64; 3]) -> [f64; 3] {
    let finite = lo.iter().chain(&hi).all(|c| c.is_finite());
    let half = (0..3).map(|a| (hi[a] - lo[a]) / 2.0).fold(0.0, f64::max);
    let far = (0..3)
        .map(|a| lo[a].abs().max(hi[a].abs()))
        .fold(0.0, f64::max);
    if !finite || far <= 3.0 * half {
        return [0.0; 3];
    }
    // A point-sized box still gets a step, from its distance to the origin.
    let size = if half > 0.0 { half } else { far * 1e-6 };
    let step = 2f64.powi(size.log2().floor() as i32);
    [0, 1, 2].map(|a| ((lo[a] + hi[a]) / 2.0 / step).round() * step)
}

/// The part of a face that belongs to no part: the construction marks its
/// somas so, and the overlap pass compares such faces with everything, one
/// face at a time. Every other face's part is a number the construction
/// gives (a tube piece, a bridge, a filler piece).
pub const NO_OWNER: u32 = u32::MAX;

/// Borrowed mesh arrays (from a [`Mesh`] or from numpy without a copy).
#[derive(Debug, Clone, Copy)]
pub struct MeshView<'a> {
    /// Vertex positions.
    pub vertices: &'a [[f32; 3]],
    /// Triangles.
    pub faces: &'a [[u32; 3]],
    /// Per-vertex sample labels, or empty.
    pub vertex_sample: &'a [u32],
    /// The point the positions are relative to ([`Mesh::origin`]).
    pub origin: [f64; 3],
}

impl MeshView<'_> {
    /// Checks that every face index is in range and every coordinate finite.
    ///
    /// # Errors
    /// [`Error::InvalidMesh`] describing the first problem.
    pub fn validate(&self) -> Result<()> {
        let n = self.vertices.len();
        if let Some((i, v)) = self
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| v.iter().any(|c| !c.is_finite()))
        {
            return Err(Error::InvalidMesh(format!(
                "vertex {i} is not finite: {v:?}"
            )));
        }
        if let Some((i, f)) = self
            .faces
            .iter()
            .enumerate()
            .find(|(_, f)| f.iter().any(|&k| k as usize >= n))
        {
            return Err(Error::InvalidMesh(format!(
                "face {i} refers to vertex {} but there are only {n} vertices",
                f.iter().max().copied().unwrap_or(0)
            )));
        }
        if !self.vertex_sample.is_empty() && self.vertex_sample.len() != n {
            return Err(Error::InvalidMesh(format!(
                "vertex_sample has {} entries for {n} vertices",
                self.vertex_sample.len()
            )));
        }
        Ok(())
    }

    /// Centre of the bounding box.
    pub fn center(&self) -> [f64; 3] {
        if self.vertices.is_empty() {
            return [0.0; 3];
        }
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in self.vertices {
            for a in 0..3 {
                lo[a] = lo[a].min(f64::from(v[a]));
                hi[a] = hi[a].max(f64::from(v[a]));
            }
        }
        [
            (lo[0] + hi[0]) / 2.0,
            (lo[1] + hi[1]) / 2.0,
            (lo[2] + hi[2]) / 2.0,
        ]
    }

    /// Triangle `f` as f64 points relative to `origin`.
    pub(crate) fn triangle(&self, f: usize, origin: [f64; 3]) -> [[f64; 3]; 3] {
        let t = self.faces[f];
        let p = |k: u32| {
            let v = self.vertices[k as usize];
            [
                f64::from(v[0]) - origin[0],
                f64::from(v[1]) - origin[1],
                f64::from(v[2]) - origin[2],
            ]
        };
        [p(t[0]), p(t[1]), p(t[2])]
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        (0..self.faces.len()).map(|f| self.face_area(f)).sum()
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: usize) -> f64 {
        let [a, b, d] = self.triangle(f, [0.0; 3]);
        0.5 * norm(cross(sub(b, a), sub(d, a)))
    }

    /// Signed enclosed volume.
    pub fn volume(&self) -> f64 {
        let c = self.center();
        (0..self.faces.len())
            .map(|f| {
                let [a, b, d] = self.triangle(f, c);
                dot(a, cross(b, d)) / 6.0
            })
            .sum()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The unit cube [0,1]³ as 12 outward triangles.
    pub(crate) fn cube() -> Mesh {
        let v: Vec<[f32; 3]> = (0..8)
            .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
            .collect();
        let f = vec![
            [0, 2, 1],
            [1, 2, 3], // z = 0
            [4, 5, 6],
            [5, 7, 6], // z = 1
            [0, 1, 4],
            [1, 5, 4], // y = 0
            [2, 6, 3],
            [3, 6, 7], // y = 1
            [0, 4, 2],
            [2, 4, 6], // x = 0
            [1, 3, 5],
            [3, 7, 5], // x = 1
        ];
        Mesh::new(v, f).unwrap()
    }

    #[test]
    fn cube_area_and_volume() {
        let m = cube();
        assert!((m.area() - 6.0).abs() < 1e-12);
        assert!((m.volume() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn volume_is_translation_invariant_far_from_origin() {
        let mut m = cube();
        for v in &mut m.vertices {
            v[0] += 10_000.0;
        }
        assert!((m.volume() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn frame_origin_is_zero_near_the_origin_and_central_far_from_it() {
        // Centred on the soma, or starting at 0 (image coordinates): zero.
        assert_eq!(
            frame_origin([-80.0, -50.0, -3.0], [120.0, 60.0, 4.0]),
            [0.0; 3]
        );
        assert_eq!(
            frame_origin([0.0, 0.0, 0.0], [512.0, 300.0, 80.0]),
            [0.0; 3]
        );
        // An atlas cell 300 wide at 12,000: its centre on a grid of 128.
        let (lo, hi) = ([11_850.0, 5_000.0, 7_900.0], [12_150.0, 5_200.0, 8_100.0]);
        let o = frame_origin(lo, hi);
        assert_eq!(o, [12_032.0, 5_120.0, 8_064.0]);
        for a in 0..3 {
            assert!((lo[a] - o[a]).abs() <= 1.5 * 150.0 && (hi[a] - o[a]).abs() <= 1.5 * 150.0);
        }
        // A single far point, and boxes that are not finite.
        let p = frame_origin([1e4; 3], [1e4; 3]);
        assert!(p.iter().all(|&c| (c - 1e4).abs() < 0.01), "{p:?}");
        assert_eq!(frame_origin([f64::NAN; 3], [1.0; 3]), [0.0; 3]);
    }

    #[test]
    fn positions_far_away_keep_their_precision() {
        let far = [
            [12_345.678_9, -23_456.789_1, 5_432.1],
            [12_345.679_0, -23_456.789_1, 5_432.1],
            [12_345.678_9, -23_456.789_0, 5_432.1],
        ];
        let m = Mesh::from_positions(&far, vec![[0, 1, 2]]).unwrap();
        assert_ne!(m.origin, [0.0; 3]);
        for (i, p) in far.iter().enumerate() {
            for a in 0..3 {
                assert!(
                    (m.position(i)[a] - p[a]).abs() < 1e-9,
                    "{:?} {p:?}",
                    m.position(i)
                );
            }
        }
        // Appending a mesh with another origin moves its vertices into ours.
        let mut c = cube();
        c.set_origin([-1.0, 0.0, 0.0]);
        assert_eq!(c.position(7), [1.0, 1.0, 1.0]);
        let mut d = cube();
        d.append(&c);
        assert_eq!(d.position(15), [1.0, 1.0, 1.0]);
    }

    #[test]
    fn rejects_bad_indices_and_nan() {
        assert!(Mesh::new(vec![[0.0; 3]], vec![[0, 0, 1]]).is_err());
        assert!(Mesh::new(vec![[f32::NAN, 0.0, 0.0]], vec![]).is_err());
    }

    #[test]
    fn append_offsets_faces() {
        let mut a = cube();
        let b = cube();
        a.append(&b);
        assert_eq!(a.faces.len(), 24);
        assert_eq!(a.faces[12], [8, 10, 9]);
        assert!((a.volume() - 2.0).abs() < 1e-12);
    }
}
