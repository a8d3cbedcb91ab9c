//! Wavefront OBJ: `v x y z` and `f a b c` lines (1-based), written directly;
//! read through tobj.

use std::io::{self, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Lines formatted per parallel task.
const LINES_PER_TASK: usize = 1 << 15;

/// Writes `mesh` as OBJ text. Floats use the shortest form that reads back as
/// the same f32 (ryu; small and large values in exponent form such as
/// `1.5E-7`, which every OBJ reader accepts); for a mesh with an origin
/// ([`Mesh::origin`]), the same for the f64 sum of origin and vertex.
///
/// Formatting text is most of the cost of an OBJ file (it took longer than
/// meshing), so blocks of lines are formatted in parallel and written in
/// order; the bytes do not depend on the number of threads.
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
    let o = mesh.origin;
    if o == [0.0; 3] {
        write_blocks(w, &mesh.vertices, |out, v| push_vertex(out, *v))?;
    } else {
        // The origin added in f64 keeps the local frame's precision.
        write_blocks(w, &mesh.vertices, |out, v| {
            push_vertex(out, [0, 1, 2].map(|a| o[a] + f64::from(v[a])));
        })?;
    }
    write_blocks(w, &mesh.faces, |out, f| {
        out.extend_from_slice(b"f ");
        push_u32(out, f[0] + 1);
        out.push(b' ');
        push_u32(out, f[1] + 1);
        out.push(b' ');
        push_u32(out, f[2] + 1);
        out.push(b'\n');
    })
}

/// Appends a `v x y z` line.
fn push_vertex<F: ryu::Float>(out: &mut Vec<u8>, v: [F; 3]) {
    let mut f = ryu::Buffer::new();
    out.extend_from_slice(b"v ");
    out.extend_from_slice(f.format_finite(v[0]).as_bytes());
    out.push(b' ');
    out.extend_from_slice(f.format_finite(v[1]).as_bytes());
    out.push(b' ');
    out.extend_from_slice(f.format_finite(v[2]).as_bytes());
    out.push(b'\n');
}

/// Formats `items` a line each, tasks of [`LINES_PER_TASK`] lines in parallel,
/// a few tasks at a time so the text in memory stays bounded.
fn write_blocks<T: Sync>(
    w: &mut impl Write,
    items: &[T],
    line: impl Fn(&mut Vec<u8>, &T) + Sync + Send,
) -> io::Result<()> {
    let tasks: Vec<&[T]> = items.chunks(LINES_PER_TASK).collect();
    for group in tasks.chunks(16) {
        let texts = crate::kernel::parallel::map(group, |chunk| {
            let mut out = Vec::with_capacity(chunk.len() * 40);
            for item in *chunk {
                line(&mut out, item);
            }
            out
        });
        for t in texts {
            w.write_all(&t)?;
        }
    }
    Ok(())
}

/// Appends the decimal digits of `n`.
fn push_u32(out: &mut Vec<u8>, mut n: u32) {
    let mut digits = [0u8; 10];
    let mut i = digits.len();
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.extend_from_slice(&digits[i..]);
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
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces = Vec::new();
    for model in &models {
        let offset = positions.len() as u32;
        positions.extend(
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
        (positions, faces) = super::weld::weld(positions, faces);
    }
    Mesh::from_positions(&positions, faces).map_err(|e| Error::mesh_file(path, 0, e.to_string()))
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

    #[test]
    fn floats_and_indices_read_back_exactly() {
        // Tiny, huge, negative and ordinary values, and more lines than one
        // parallel task holds (the read welds nothing: all points differ).
        let n = LINES_PER_TASK + 7;
        let vertices: Vec<[f32; 3]> = (0..n)
            .map(|i| {
                let x = i as f32;
                [x * 1.000_000_1e-7, -x * 3.3e5 - 0.1, 1.0 / (x + 3.0)]
            })
            .collect();
        let faces: Vec<[u32; 3]> = (0..n as u32 - 2).map(|i| [i, i + 1, i + 2]).collect();
        let mesh = Mesh {
            vertices,
            faces,
            ..Mesh::default()
        };
        let mut text = Vec::new();
        write_obj(&mut text, &mesh).unwrap();
        let back = read_obj(&text, Path::new("t.obj")).unwrap();
        assert_eq!(back.vertices, mesh.vertices);
        assert_eq!(back.faces, mesh.faces);
        let mut digits = Vec::new();
        for n in [0, 7, 10, 4_294_967_295] {
            digits.clear();
            push_u32(&mut digits, n);
            assert_eq!(digits, n.to_string().as_bytes());
        }
    }
}
