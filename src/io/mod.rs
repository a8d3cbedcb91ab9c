//! Mesh files: OBJ (text), PLY (binary little-endian) and STL (binary), chosen by
//! the file extension.
//!
//! Writers stream through a buffered writer and never hold a second copy of the
//! mesh. Readers accept what other tools write, so `neuromesh check` works on any
//! mesh: OBJ through tobj (polygons are fan-triangulated, several objects are
//! merged), PLY in ASCII or binary little-endian with float or double positions,
//! and STL in binary or ASCII. STL stores no shared vertices, so its vertices are
//! welded by exact position; OBJ files with several objects are welded the same
//! way, because tobj numbers each object's vertices apart.

mod obj;
mod ply;
mod stl;
mod weld;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

pub use obj::{read_obj, write_obj};
pub use ply::{read_ply, write_ply};
pub use stl::{read_stl, write_stl};

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ, text.
    Obj,
    /// Stanford PLY, binary little-endian, with a per-vertex `sample` property.
    Ply,
    /// STL, binary.
    Stl,
}

impl Format {
    /// Every format, in the order help texts list them.
    pub const ALL: [Format; 3] = [Format::Obj, Format::Ply, Format::Stl];

    /// The format named by a path's extension (case-insensitive).
    ///
    /// # Errors
    /// [`Error::InvalidParam`] naming the extension when it is not obj, ply or stl.
    pub fn from_path(path: &Path) -> Result<Format> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        Format::from_extension(&ext).ok_or_else(|| Error::InvalidParam {
            name: "output",
            reason: format!(
                "cannot tell the mesh format of `{}`: use a .obj, .ply or .stl extension",
                path.display()
            ),
        })
    }

    /// The format for an extension without the dot (`"obj"`, `"PLY"`, …).
    pub fn from_extension(ext: &str) -> Option<Format> {
        match ext.to_ascii_lowercase().as_str() {
            "obj" => Some(Format::Obj),
            "ply" => Some(Format::Ply),
            "stl" => Some(Format::Stl),
            _ => None,
        }
    }

    /// The usual extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Stl => "stl",
        }
    }
}

/// Writes `mesh` to `path` in the format its extension names. The file is
/// written next to its destination and renamed into place, so an interrupted
/// write never leaves a truncated mesh behind.
///
/// # Errors
/// [`Error::InvalidParam`] for an unknown extension, [`Error::Io`] when writing fails.
pub fn write(path: impl AsRef<Path>, mesh: &Mesh) -> Result<()> {
    let path = path.as_ref();
    let format = Format::from_path(path)?;
    write_as(path, mesh, format)
}

/// Why writing `mesh` as `format` loses precision, if it does: binary STL
/// holds f32 coordinates only, so a mesh with an origin
/// ([`Mesh::origin`]) is rounded there to steps that can fold its thinnest
/// triangles into each other. OBJ and PLY keep it.
pub fn precision_warning(mesh: &Mesh, format: Format) -> Option<String> {
    if format != Format::Stl || mesh.origin == [0.0; 3] {
        return None;
    }
    let far = (0..3)
        .map(|a| {
            mesh.origin[a].abs()
                + mesh.vertices.iter().map(|v| v[a].abs()).fold(0.0, f32::max) as f64
        })
        .fold(0.0, f64::max);
    // Half the spacing of f32 values at `far`: 24 significant bits.
    let step = far * f64::from(f32::EPSILON) / 2.0;
    Some(format!(
        "STL stores f32 coordinates: {far:.0} units from the origin they are rounded to \
         {step:.1e}, which can make thin neurites' triangles cross; write .obj or .ply \
         (double precision for this mesh) to keep them exact"
    ))
}

/// The temporary files being written now, so that an interrupted process
/// can remove them ([`remove_unfinished`]).
static UNFINISHED: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// A temporary file listed in [`UNFINISHED`] while it lives.
struct Unfinished(std::path::PathBuf);

impl Unfinished {
    fn register(path: &Path) -> Unfinished {
        UNFINISHED
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(path.to_path_buf());
        Unfinished(path.to_path_buf())
    }
}

impl Drop for Unfinished {
    fn drop(&mut self) {
        let mut list = UNFINISHED
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(k) = list.iter().position(|p| *p == self.0) {
            list.swap_remove(k);
        }
    }
}

/// Removes the temporary files of the writes in progress and returns how
/// many there were: what a process stopped by a signal calls before it
/// exits, so that it leaves no partial file beside its outputs (finished
/// outputs are whole: each is renamed into place at once).
pub fn remove_unfinished() -> usize {
    let list = UNFINISHED
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    for p in list.iter() {
        let _ = std::fs::remove_file(p);
    }
    list.len()
}

/// Writes `mesh` to `path` in `format`, atomically (temporary file + rename).
///
/// # Errors
/// [`Error::Io`] when the file cannot be created or written.
pub fn write_as(path: &Path, mesh: &Mesh, format: Format) -> Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let _unfinished = Unfinished::register(&tmp);
    let result = (|| -> std::io::Result<()> {
        let mut w = BufWriter::with_capacity(1 << 20, File::create(&tmp)?);
        write_to(&mut w, mesh, format)?;
        w.flush()?;
        drop(w);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}

/// Writes `mesh` as `format` to `w` (standard output, a buffer): what
/// [`write_as`] writes to its file.
///
/// # Errors
/// What writing to `w` gives.
pub fn write_to(w: &mut impl Write, mesh: &Mesh, format: Format) -> std::io::Result<()> {
    match format {
        Format::Obj => write_obj(w, mesh),
        Format::Ply => write_ply(w, mesh),
        Format::Stl => write_stl(w, mesh),
    }
}

/// Reads a mesh from an OBJ, PLY or STL file (by extension).
///
/// # Errors
/// [`Error::Io`] if the file cannot be read, [`Error::MeshFile`] if it is not a
/// valid mesh of its format.
pub fn read(path: impl AsRef<Path>) -> Result<Mesh> {
    let path = path.as_ref();
    // The file being read is the problem, not an output parameter.
    let format = Format::from_path(path).map_err(|_| {
        Error::mesh_file(
            path,
            0,
            "cannot tell the mesh format from the extension: use .obj, .ply or .stl",
        )
    })?;
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let mesh = match format {
        Format::Obj => read_obj(&bytes, path)?,
        Format::Ply => read_ply(&bytes, path)?,
        Format::Stl => read_stl(&bytes, path)?,
    };
    mesh.validate()
        .map_err(|e| Error::mesh_file(path, 0, e.to_string()))?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tests::cube;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("neuromesh-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn every_format_round_trips_the_cube() {
        let mut m = cube();
        m.vertex_sample = (0..8).collect();
        for ext in ["obj", "ply", "stl", "OBJ"] {
            let p = tmp(&format!("cube.{ext}"));
            write(&p, &m).unwrap();
            let back = read(&p).unwrap();
            assert_eq!(back.faces.len(), 12, "{ext}");
            let r = back.check();
            assert!(r.is_valid(), "{ext}: {r}");
            assert!((back.volume() - 1.0).abs() < 1e-6, "{ext}");
            // Readers may renumber vertices (tobj numbers them by first use), so
            // compare each face's corner positions, which must survive exactly.
            let corners = |mesh: &Mesh| -> Vec<[[f32; 3]; 3]> {
                mesh.faces
                    .iter()
                    .map(|f| f.map(|k| mesh.vertices[k as usize]))
                    .collect()
            };
            assert_eq!(corners(&back), corners(&m), "{ext}");
            if ext == "ply" {
                assert_eq!(back.vertex_sample, m.vertex_sample);
            }
        }
    }

    #[test]
    fn unknown_extension_is_a_clear_error() {
        let e = write(tmp("cube.xyz"), &cube()).unwrap_err();
        assert!(e.to_string().contains(".obj, .ply or .stl"), "{e}");
        // Reading: the file is named, no parameter is.
        let e = read("cells/cube.xyz").unwrap_err();
        assert!(matches!(e, Error::MeshFile { .. }), "{e:?}");
        assert!(
            e.to_string()
                .starts_with("cells/cube.xyz: cannot tell the mesh format"),
            "{e}"
        );
    }

    #[test]
    fn unwritable_destination_names_the_file() {
        let e = write("/nonexistent-dir/x.obj", &cube()).unwrap_err();
        assert!(e.to_string().starts_with("/nonexistent-dir/x.obj"), "{e}");
    }
}
