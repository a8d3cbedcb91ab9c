//! Stanford PLY. Written binary little-endian with a per-vertex `sample`
//! property (the SWC sample each vertex comes from); read in ASCII or binary of
//! either byte order, with any numeric property types, keeping `x y z`, the
//! optional `sample` property and the face index lists.

use std::io::{self, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Writes `mesh` as binary little-endian PLY: float positions, or double
/// ones with the origin added for a mesh with an origin ([`Mesh::origin`]).
///
/// # Errors
/// Whatever the writer returns.
pub fn write_ply(w: &mut impl Write, mesh: &Mesh) -> io::Result<()> {
    let labelled = mesh.vertex_sample.len() == mesh.vertices.len() && !mesh.vertices.is_empty();
    // A mesh with an origin is written in double precision with the origin
    // added: f32 would round away the detail the local frame kept.
    let double = mesh.origin != [0.0; 3];
    let kind = if double { "double" } else { "float" };
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment neuromesh {}\nelement vertex {}\n\
         property {kind} x\nproperty {kind} y\nproperty {kind} z\n",
        env!("CARGO_PKG_VERSION"),
        mesh.vertices.len()
    )?;
    if labelled {
        w.write_all(b"property uint sample\n")?;
    }
    write!(
        w,
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.faces.len()
    )?;
    let mut buf = Vec::with_capacity(1 << 16);
    for (i, v) in mesh.vertices.iter().enumerate() {
        if double {
            for a in 0..3 {
                let c = mesh.origin[a] + f64::from(v[a]);
                buf.extend_from_slice(&c.to_le_bytes());
            }
        } else {
            for c in v {
                buf.extend_from_slice(&c.to_le_bytes());
            }
        }
        if labelled {
            buf.extend_from_slice(&mesh.vertex_sample[i].to_le_bytes());
        }
        if buf.len() >= 1 << 16 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    for f in &mesh.faces {
        buf.push(3);
        for k in f {
            buf.extend_from_slice(&k.to_le_bytes());
        }
        if buf.len() >= 1 << 16 {
            w.write_all(&buf)?;
            buf.clear();
        }
    }
    w.write_all(&buf)
}

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

#[derive(Clone, Copy)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

struct Property {
    name: String,
    /// `Some(count type)` for list properties.
    list: Option<Scalar>,
    value: Scalar,
}

struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

/// A cursor over the body that reads numbers in the file's encoding.
struct Body<'a> {
    bytes: &'a [u8],
    at: usize,
    enc: Encoding,
}

impl Body<'_> {
    fn next(&mut self, t: Scalar) -> Option<f64> {
        if self.enc == Encoding::Ascii {
            while self.at < self.bytes.len() && self.bytes[self.at].is_ascii_whitespace() {
                self.at += 1;
            }
            let start = self.at;
            while self.at < self.bytes.len() && !self.bytes[self.at].is_ascii_whitespace() {
                self.at += 1;
            }
            return std::str::from_utf8(&self.bytes[start..self.at])
                .ok()?
                .parse()
                .ok();
        }
        let n = t.size();
        let raw = self.bytes.get(self.at..self.at + n)?;
        self.at += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.enc == Encoding::Big {
            b[..n].reverse();
        }
        Some(match t {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }
}

/// Parses a PLY file.
///
/// # Errors
/// [`Error::MeshFile`] with the header line or the element that is wrong.
pub fn read_ply(bytes: &[u8], path: &Path) -> Result<Mesh> {
    let bad = |line: usize, reason: String| Error::mesh_file(path, line, reason);
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n" || w == b"end_header\r")
        .ok_or_else(|| bad(1, "not a PLY file: no `end_header` line".to_owned()))?;
    let header = String::from_utf8_lossy(&bytes[..header_end]);
    let mut body_start = header_end + 11;
    if bytes.get(body_start - 1) == Some(&b'\r') && bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let (enc, elements) = read_header(&header, &bad)?;
    let mut body = Body {
        bytes: &bytes[body_start..],
        at: 0,
        enc,
    };
    let mut mesh = Mesh::default();
    let mut positions: Vec<[f64; 3]> = Vec::new();
    for el in &elements {
        read_element(el, &mut body, &mut mesh, &mut positions, &bad)?;
    }
    // Positions are read in f64 and stored around an origin near them, so a
    // double-precision file far from the coordinates' origin keeps its detail.
    let read = Mesh::from_positions(&positions, Vec::new()).map_err(|e| bad(0, e.to_string()))?;
    mesh.vertices = read.vertices;
    mesh.origin = read.origin;
    Ok(mesh)
}

/// The header's encoding and elements.
fn read_header(
    header: &str,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<(Encoding, Vec<Element>)> {
    let mut enc = None;
    let mut elements: Vec<Element> = Vec::new();
    for (i, line) in header.lines().enumerate() {
        let line_no = i + 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        let mut property = |list: Option<Scalar>, value: Scalar, name: &str| {
            let el = elements
                .last_mut()
                .ok_or_else(|| bad(line_no, "property before any element".to_owned()))?;
            el.props.push(Property {
                name: name.to_owned(),
                list,
                value,
            });
            Ok::<(), Error>(())
        };
        match words.as_slice() {
            ["ply"] if line_no == 1 => {}
            _ if line_no == 1 => {
                return Err(bad(1, "not a PLY file: first line is not `ply`".to_owned()));
            }
            ["format", f, _] => {
                enc = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(bad(line_no, format!("unknown PLY format `{other}`"))),
                });
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(Element {
                name: (*name).to_owned(),
                count: count
                    .parse()
                    .map_err(|_| bad(line_no, format!("bad element count `{count}`")))?,
                props: Vec::new(),
            }),
            ["property", "list", ct, vt, name] => {
                let (Some(ct), Some(vt)) = (Scalar::parse(ct), Scalar::parse(vt)) else {
                    return Err(bad(line_no, format!("unknown property type in `{line}`")));
                };
                property(Some(ct), vt, name)?;
            }
            ["property", t, name] => {
                let t = Scalar::parse(t)
                    .ok_or_else(|| bad(line_no, format!("unknown property type `{t}`")))?;
                property(None, t, name)?;
            }
            _ => return Err(bad(line_no, format!("unexpected header line `{line}`"))),
        }
    }
    let enc = enc.ok_or_else(|| bad(2, "missing `format` line".to_owned()))?;
    Ok((enc, elements))
}

/// Reads the rows of element `el` from `body`: a vertex's position into
/// `positions` and its `sample` into `mesh`, a face's polygon as a fan of
/// triangles into `mesh`; other elements are skipped.
fn read_element(
    el: &Element,
    body: &mut Body<'_>,
    mesh: &mut Mesh,
    positions: &mut Vec<[f64; 3]>,
    bad: &impl Fn(usize, String) -> Error,
) -> Result<()> {
    let is_vertex = el.name == "vertex";
    let is_face = el.name == "face";
    let xyz: Vec<Option<usize>> = ["x", "y", "z"]
        .iter()
        .map(|n| el.props.iter().position(|p| p.name == *n))
        .collect();
    if is_vertex && xyz.iter().any(Option::is_none) {
        return Err(bad(0, "vertex element lacks x, y or z".to_owned()));
    }
    let sample_prop = el.props.iter().position(|p| p.name == "sample");
    for row in 0..el.count {
        let truncated = || {
            bad(
                0,
                format!("file ends inside {} {row} of {}", el.name, el.count),
            )
        };
        let mut pos = [0f64; 3];
        let mut sample = None;
        for (pi, p) in el.props.iter().enumerate() {
            if let Some(ct) = p.list {
                let n = body.next(ct).ok_or_else(truncated)? as usize;
                let mut idx = Vec::with_capacity(n);
                for _ in 0..n {
                    idx.push(body.next(p.value).ok_or_else(truncated)?);
                }
                if is_face && (p.name == "vertex_indices" || p.name == "vertex_index") {
                    if n < 3 {
                        return Err(bad(0, format!("face {row} has {n} vertices")));
                    }
                    for k in 1..n - 1 {
                        mesh.faces
                            .push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
                    }
                }
            } else {
                let v = body.next(p.value).ok_or_else(truncated)?;
                if is_vertex {
                    if let Some(a) = xyz.iter().position(|&x| x == Some(pi)) {
                        pos[a] = v;
                    }
                    if sample_prop == Some(pi) {
                        sample = Some(v as u32);
                    }
                }
            }
        }
        if is_vertex {
            positions.push(pos);
            if let Some(s) = sample {
                mesh.vertex_sample.push(s);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_ascii_with_quads_and_extra_properties() {
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                    property float z\nproperty uchar red\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n\
                    0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n4 0 1 2 3\n";
        let m = read_ply(text.as_bytes(), Path::new("q.ply")).unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn truncated_binary_is_an_error() {
        let text = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n\
                     property float y\nproperty float z\nend_header\n\x00\x00\x00\x00";
        let e = read_ply(text, Path::new("t.ply")).unwrap_err();
        assert!(e.to_string().contains("file ends inside vertex"), "{e}");
    }

    #[test]
    fn not_a_ply() {
        assert!(read_ply(b"solid x\nend_header\n", Path::new("x.ply")).is_err());
    }
}
