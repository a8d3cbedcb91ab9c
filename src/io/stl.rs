//! STL: written binary (80-byte header, facet normals, no attributes); read
//! binary or ASCII, with vertices welded by exact position since STL does not
//! share them. Binary STL holds only f32: a mesh with an origin
//! ([`Mesh::origin`]) is written with the origin added and rounded, so a cell
//! far from the coordinates' origin loses precision there (use OBJ or PLY).

use std::io::{self, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::kernel::vector::{cross, norm};
use crate::mesh::Mesh;

/// Writes `mesh` as binary STL.
///
/// # Errors
/// Whatever the writer returns; `InvalidInput` for more than 2³² − 1 faces.
pub fn write_stl(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    let mut header = [b' '; 80];
    let text = format!("neuromesh {} binary STL", env!("CARGO_PKG_VERSION"));
    header[..text.len()].copy_from_slice(text.as_bytes());
    w.write_all(&header)?;
    let n = u32::try_from(mesh.faces.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many faces for STL"))?;
    w.write_all(&n.to_le_bytes())?;
    let mut buf = Vec::with_capacity(50 * 1024);
    for f in &mesh.faces {
        let p = f.map(|k| mesh.vertices[k as usize].map(f64::from));
        let n = cross(
            [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]],
            [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]],
        );
        let len = norm(n);
        let n = if len > 0.0 {
            n.map(|c| (c / len) as f32)
        } else {
            [0.0; 3]
        };
        for c in n {
            buf.extend_from_slice(&c.to_le_bytes());
        }
        for k in f {
            let v = mesh.vertices[*k as usize];
            for a in 0..3 {
                let c = (mesh.origin[a] + f64::from(v[a])) as f32;
                buf.extend_from_slice(&c.to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
        if buf.len() >= 50 * 1000 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

/// Parses binary or ASCII STL and welds identical vertices.
///
/// # Errors
/// [`Error::MeshFile`] if the size does not match the triangle count (binary)
/// or a `vertex` line is malformed (ASCII).
pub fn read_stl(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let binary_len = bytes
        .get(80..84)
        .map(|c| 84 + 50 * u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize);
    let mut vertices = Vec::new();
    if binary_len == Some(bytes.len()) {
        for tri in bytes[84..].chunks_exact(50) {
            for k in 0..3 {
                let at = 12 + 12 * k;
                let c = |i: usize| {
                    let b = &tri[at + 4 * i..at + 4 * i + 4];
                    f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                };
                vertices.push([c(0), c(1), c(2)]);
            }
        }
    } else if bytes.trim_ascii_start().starts_with(b"solid") {
        for (i, line) in String::from_utf8_lossy(bytes).lines().enumerate() {
            let mut words = line.split_whitespace();
            if words.next() == Some("vertex") {
                let v: Vec<f64> = words.filter_map(|w| w.parse().ok()).collect();
                if v.len() != 3 {
                    return Err(Error::mesh_file(
                        path,
                        i + 1,
                        format!("bad vertex line `{}`", line.trim()),
                    ));
                }
                vertices.push([v[0], v[1], v[2]]);
            }
        }
        if vertices.len() % 3 != 0 {
            return Err(Error::mesh_file(
                path,
                0,
                "vertex count is not a multiple of 3",
            ));
        }
    } else {
        return Err(Error::mesh_file(
            path,
            0,
            format!(
                "not an STL file: {} bytes do not match the binary triangle count and there is no `solid` header",
                bytes.len()
            ),
        ));
    }
    let faces = (0..vertices.len() as u32 / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    let (vertices, faces) = super::weld::weld(vertices, faces);
    Mesh::from_positions(&vertices, faces).map_err(|e| Error::mesh_file(path, 0, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_ascii_stl() {
        let text = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
                    endloop\nendfacet\nendsolid t\n";
        let m = read_stl(text.as_bytes(), Path::new("t.stl")).unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn rejects_garbage() {
        let e = read_stl(b"hello", Path::new("g.stl")).unwrap_err();
        assert!(e.to_string().contains("not an STL file"), "{e}");
    }
}
