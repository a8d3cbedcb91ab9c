//! What a set of faces touches, and the nudge that moves the vertices of
//! faces at fault into general position for another round.

use crate::kernel::vector::{self, V3};
use crate::mesh::Mesh;

/// A nudge moves a vertex by up to this fraction of its shortest edge: far
/// below what the output shows, far above the f32 rounding that made the
/// contact degenerate.
const NUDGE: f64 = 1e-3;

/// The parts `owner[f]` for each `f` in `which`, sorted, once each.
pub(super) fn parts_of(owner: &[u32], which: &[u32]) -> Vec<u32> {
    let mut p: Vec<u32> = which.iter().map(|&f| owner[f as usize]).collect();
    p.sort_unstable();
    p.dedup();
    p
}

/// The vertices of `faces[f]` for each `f` in `which`, sorted, once each.
pub(super) fn vertices_of(faces: &[[u32; 3]], which: &[u32]) -> Vec<u32> {
    let mut v: Vec<u32> = which.iter().flat_map(|&f| faces[f as usize]).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Moves each of `vertices` by a pseudo-random offset of up to [`NUDGE`]
/// times its shortest edge (at least a few f32 steps), the same for every
/// run: general position for contacts that f32 coordinates made degenerate.
pub(super) fn nudge(mesh: &mut Mesh, vertices: &[u32], round: u64) {
    let places = nudged(&mesh.faces, &mesh.vertices, vertices, round);
    for (&v, p) in vertices.iter().zip(places) {
        mesh.vertices[v as usize] = p;
    }
}

/// Where [`nudge`] moves each of `vertices` (sorted, once each) of `faces`
/// with vertices `pos`. A round holds its vertices apart from the mesh
/// (see `resolve_once`), so it nudges through this and moves them itself.
pub(super) fn nudged(faces: &[[u32; 3]], pos: &[V3], vertices: &[u32], round: u64) -> Vec<V3> {
    // Only the edges at a nudged vertex are measured: a few hundred of a
    // million. The nudged vertices are marked in a bit set and their
    // shortest edges kept in a map, not in an array of the mesh's size.
    let marked = crate::kernel::bits::Bits::of(pos.len(), vertices.iter().copied());
    let is_marked = |k: u32| marked.has(k);
    let mut shortest: crate::kernel::hash::FastMap<u32, f64> =
        vertices.iter().map(|&v| (v, f64::INFINITY)).collect();
    for f in faces {
        if !f.iter().any(|&k| is_marked(k)) {
            continue;
        }
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            if !is_marked(a) && !is_marked(b) {
                continue;
            }
            let d = crate::kernel::vector::sub(vector::at(pos, a), vector::at(pos, b));
            let l = crate::kernel::vector::dot(d, d).sqrt();
            for k in [a, b] {
                if let Some(s) = shortest.get_mut(&k) {
                    *s = s.min(l);
                }
            }
        }
    }
    vertices
        .iter()
        .map(|&v| {
            let mut p = pos[v as usize];
            let scale = p.iter().fold(0f32, |m, x| m.max(x.abs()));
            let step = 8.0 * f64::from(scale.max(f32::MIN_POSITIVE)) * f64::from(f32::EPSILON);
            let amp = (NUDGE * shortest[&v]).max(step);
            let mut h =
                crate::kernel::hash::mix64(u64::from(v) ^ (round << 40) ^ 0x9e37_79b9_7f4a_7c15);
            for c in &mut p {
                h = crate::kernel::hash::mix64(h);
                let unit = (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
                *c = (f64::from(*c) + amp * unit) as f32;
            }
            p
        })
        .collect()
}
