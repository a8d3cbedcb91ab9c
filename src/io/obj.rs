//! Wavefront OBJ: `v x y z` and `f a b c` lines (1-based), written directly;
//! read through tobj.

use std::io::{self, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Writes `mesh` as OBJ text. Floats use Rust's shortest round-trip form, so
/// reading the file back gives the same f32 values.
///
/// # Errors
/// Whatever the writer returns.
pub fn write_obj(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    writeln!(
        w,
        "# neuromesh {}: {} vertices, {} triangles",
        env!("CARGO_PKG_VERSION"),
        mesh.vertices.len(),
        mesh.faces.len()
    )?;
    let mut line = String::with_capacity(96);
    for v in &mesh.vertices {
        use std::fmt::Write as _;
        line.clear();
        let _ = writeln!(line, "v {} {} {}", v[0], v[1], v[2]);
        w.write_all(line.as_bytes())?;
    }
    for f in &mesh.faces {
        use std::fmt::Write as _;
        line.clear();
        let _ = writeln!(line, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// Parses OBJ text (positions and faces; polygons are fan-triangulated, points
/// and lines ignored, several objects merged and welded).
///
/// # Errors
/// [`Error::MeshFile`] with tobj's reason.
pub fn read_obj(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = io::BufReader::new(bytes);
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| Error::mesh_file(path, 0, format!("not a valid OBJ file: {e}")))?;
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for model in &models {
        let offset = vertices.len() as u32;
        vertices.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]]),
        );
        faces.extend(
            model
                .mesh
                .indices
                .chunks_exact(3)
                .map(|f| [f[0] + offset, f[1] + offset, f[2] + offset]),
        );
    }
    if models.len() > 1 {
        (vertices, faces) = super::weld(vertices, faces);
    }
    Ok(Mesh {
        vertices,
        faces,
        ..Mesh::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_quads_and_several_objects() {
        let text = "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\no b\nv 0 0 0\nv 1 0 0\nv 0 0 1\nf 5 6 7\n";
        let m = read_obj(text.as_bytes(), Path::new("q.obj")).unwrap();
        assert_eq!(m.faces.len(), 3);
        assert_eq!(m.vertices.len(), 5);
    }

    #[test]
    fn bad_obj_is_a_mesh_file_error() {
        let e = read_obj(b"v 0 0 zero\nf 1 2 3\n", Path::new("bad.obj")).unwrap_err();
        assert!(
            e.to_string().starts_with("bad.obj: not a valid OBJ file"),
            "{e}"
        );
    }
}
