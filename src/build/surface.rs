//! The mesh under construction: f64 positions, sample labels and triangles that
//! can be removed (splicing cuts holes into tubes).
//!
//! Every stage appends here through [`Surface::vertex`] and [`Surface::triangle`]
//! and refers to vertices by the indices those return, so no stage does index
//! arithmetic on another stage's buffer. [`Surface::into_mesh`] drops removed
//! triangles and unused vertices and converts to the f32 output type.

use glam::DVec3;

use crate::mesh::{BuildStats, Mesh};

/// A point in a surface's history to roll back to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mark {
    /// Number of vertices at the mark.
    pub vertices: usize,
    /// Number of triangles at the mark.
    pub triangles: usize,
}

/// Where an appended surface's vertices and triangles begin in the surface it
/// was appended to ([`Surface::append`]): what turns indices into one into
/// indices into the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offset {
    /// Added to a vertex index.
    pub vertices: u32,
    /// Added to a triangle index.
    pub triangles: u32,
}

impl Offset {
    /// A vertex index moved by the offset.
    pub fn vertex(self, v: u32) -> u32 {
        v + self.vertices
    }

    /// A triangle index moved by the offset.
    pub fn triangle(self, t: u32) -> u32 {
        t + self.triangles
    }

    /// A range of vertex indices moved by the offset.
    pub fn vertex_range(self, r: std::ops::Range<u32>) -> std::ops::Range<u32> {
        self.vertex(r.start)..self.vertex(r.end)
    }

    /// A range of triangle indices moved by the offset.
    pub fn triangle_range(self, r: std::ops::Range<u32>) -> std::ops::Range<u32> {
        self.triangle(r.start)..self.triangle(r.end)
    }
}

/// A growing triangle soup with labels; see the module docs.
#[derive(Debug, Clone, Default)]
pub struct Surface {
    /// Vertex positions.
    pub pos: Vec<DVec3>,
    /// Sample index of each vertex.
    pub label: Vec<u32>,
    /// Triangles, counter-clockwise from outside.
    pub tris: Vec<[u32; 3]>,
    /// Whether each triangle is still part of the surface.
    pub alive: Vec<bool>,
}

impl Surface {
    /// An empty surface with room for `vertices` vertices.
    pub fn with_capacity(vertices: usize) -> Surface {
        Surface {
            pos: Vec::with_capacity(vertices),
            label: Vec::with_capacity(vertices),
            tris: Vec::with_capacity(2 * vertices),
            alive: Vec::with_capacity(2 * vertices),
        }
    }

    /// Adds a vertex and returns its index.
    #[inline]
    pub fn vertex(&mut self, p: DVec3, label: u32) -> u32 {
        self.pos.push(p);
        self.label.push(label);
        (self.pos.len() - 1) as u32
    }

    /// Adds a triangle and returns its index.
    #[inline]
    pub fn triangle(&mut self, a: u32, b: u32, c: u32) -> u32 {
        self.tris.push([a, b, c]);
        self.alive.push(true);
        (self.tris.len() - 1) as u32
    }

    /// The current size, to roll back to.
    pub fn mark(&self) -> Mark {
        Mark {
            vertices: self.pos.len(),
            triangles: self.tris.len(),
        }
    }

    /// Forgets every vertex and triangle added after `mark`.
    pub fn rollback(&mut self, mark: Mark) {
        self.pos.truncate(mark.vertices);
        self.label.truncate(mark.vertices);
        self.tris.truncate(mark.triangles);
        self.alive.truncate(mark.triangles);
    }

    /// The corners of triangle `t`.
    pub fn corners(&self, t: u32) -> [[f64; 3]; 3] {
        self.tris[t as usize].map(|k| self.pos[k as usize].to_array())
    }

    /// Appends `other`; the [`Offset`] that takes its indices to this
    /// surface's.
    pub fn append(&mut self, other: &Surface) -> Offset {
        let v0 = self.pos.len() as u32;
        let t0 = self.tris.len() as u32;
        self.pos.extend_from_slice(&other.pos);
        self.label.extend_from_slice(&other.label);
        self.tris
            .extend(other.tris.iter().map(|t| [t[0] + v0, t[1] + v0, t[2] + v0]));
        self.alive.extend_from_slice(&other.alive);
        Offset {
            vertices: v0,
            triangles: t0,
        }
    }

    /// The finished mesh: live triangles only, unused vertices dropped, f32.
    pub fn into_mesh(self, stats: BuildStats) -> Mesh {
        self.into_mesh_with(stats, Vec::new()).0
    }

    /// [`Surface::into_mesh`], also carrying a per-triangle value (empty for
    /// none) over to the mesh's faces.
    pub fn into_mesh_with(self, stats: BuildStats, mut per_tri: Vec<u32>) -> (Mesh, Vec<u32>) {
        let carry = per_tri.len() == self.tris.len();
        let Surface {
            pos,
            label,
            mut tris,
            alive,
        } = self;
        // The positions in f32 first, so that the f64 ones go before the
        // numbering's arrays and the mesh's vertices are made: on the
        // million-sample tree this was the whole run's resident peak, with
        // both position arrays alive (0.79 and 0.39 GB).
        let pos32: Vec<[f32; 3]> =
            crate::kernel::parallel::map(&pos, |p| [p.x as f32, p.y as f32, p.z as f32]);
        drop(pos);
        // The faces are the live triangles renumbered, compacted in place, so
        // the peak never holds two triangle arrays (a million-sample tree has
        // 70 million triangles).
        let mut remap = vec![u32::MAX; pos32.len()];
        let mut order: Vec<u32> = Vec::with_capacity(pos32.len());
        let mut live = 0;
        for t in 0..tris.len() {
            if !alive[t] {
                continue;
            }
            tris[live] = tris[t].map(|k| {
                let slot = &mut remap[k as usize];
                if *slot == u32::MAX {
                    *slot = order.len() as u32;
                    order.push(k);
                }
                *slot
            });
            if carry {
                per_tri[live] = per_tri[t];
            }
            live += 1;
        }
        per_tri.truncate(if carry { live } else { 0 });
        // Grown by doubling as parts were added: up to twice the room.
        per_tri.shrink_to_fit();
        tris.truncate(live);
        // Room for the pieces the overlap pass appends (a median 3 % of the
        // faces on the corpus): growing the array there copied it.
        tris.shrink_to(live + live / 16);
        let faces = tris;
        drop((alive, remap));
        let vertices = crate::kernel::parallel::map(&order, |&k| pos32[k as usize]);
        drop(pos32);
        let vertex_sample = crate::kernel::parallel::map(&order, |&k| label[k as usize]);
        (
            Mesh {
                vertices,
                faces,
                vertex_sample,
                stats,
                origin: [0.0; 3],
            },
            per_tri,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_triangles_and_their_lonely_vertices_disappear() {
        let mut s = Surface::default();
        let a = s.vertex(DVec3::ZERO, 0);
        let b = s.vertex(DVec3::X, 1);
        let c = s.vertex(DVec3::Y, 2);
        let d = s.vertex(DVec3::Z, 3);
        s.triangle(a, b, c);
        let t = s.triangle(a, c, d);
        s.alive[t as usize] = false;
        let m = s.into_mesh(BuildStats::default());
        assert_eq!(m.vertices.len(), 3);
        assert_eq!(m.faces, vec![[0, 1, 2]]);
        assert_eq!(m.vertex_sample, vec![0, 1, 2]);
    }
}
