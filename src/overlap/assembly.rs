//! Step 4 of a round: the kept faces made the mesh, their vertices
//! renumbered, all compacted in place.

use crate::kernel::vector::V3;
use crate::mesh::Mesh;

/// New number of every vertex used by a kept face, in the vertices' order
/// (`u32::MAX` for the others): the numbering [`assemble`] gives. A vertex
/// never moves up, so the old ones compact in place.
pub(super) fn renumbering(faces: &[[u32; 3]], kept: &[bool], n_vertices: usize) -> Vec<u32> {
    let mut remap = vec![u32::MAX; n_vertices];
    for (face, _) in faces.iter().zip(kept).filter(|x| *x.1) {
        for &k in face {
            remap[k as usize] = 0;
        }
    }
    let mut next = 0;
    for slot in &mut remap {
        if *slot == 0 {
            *slot = next;
            next += 1;
        }
    }
    remap
}

/// Makes `mesh` the kept faces with their used vertices renumbered by `remap`
/// (from [`renumbering`]), all compacted in place (the labels in `mesh`, the
/// faces in `faces`), and returns the part of each face (`owner_of(f)` for
/// face `f`); `label_from(k)` names the old vertex whose label vertex `k`
/// takes. In place, because on a large cell fresh arrays of the mesh's size
/// cost more in page faults than the copying itself. `all_pos` (the `n_old`
/// old vertices, then the new ones) is compacted the same way and becomes
/// `mesh.vertices`.
#[allow(clippy::too_many_arguments)]
pub(super) fn assemble(
    mesh: &mut Mesh,
    n_old: usize,
    mut faces: Vec<[u32; 3]>,
    kept: &[bool],
    mut all_pos: Vec<V3>,
    remap: &[u32],
    owner_of: impl Fn(usize) -> u32,
    label_from: impl Fn(u32) -> u32,
) -> Vec<u32> {
    let labels = !mesh.vertex_sample.is_empty();
    // The new vertices' labels, read before the old labels move.
    let new_labels: Vec<u32> = if labels {
        (n_old..all_pos.len())
            .filter(|&k| remap[k] != u32::MAX)
            .map(|k| mesh.vertex_sample[label_from(k as u32) as usize])
            .collect()
    } else {
        Vec::new()
    };
    if labels {
        let mut w = 0;
        for k in 0..n_old {
            if remap[k] != u32::MAX {
                debug_assert_eq!(remap[k] as usize, w);
                mesh.vertex_sample[w] = mesh.vertex_sample[k];
                w += 1;
            }
        }
        mesh.vertex_sample.truncate(w);
        // Exactly: pushed past its length, the array would double.
        mesh.vertex_sample.reserve_exact(new_labels.len());
        mesh.vertex_sample.extend_from_slice(&new_labels);
    }
    // Used vertices move down (never up).
    let mut w = 0;
    for k in 0..all_pos.len() {
        if remap[k] != u32::MAX {
            all_pos[w] = all_pos[k];
            w += 1;
        }
    }
    all_pos.truncate(w);
    mesh.vertices = all_pos;
    // Kept faces move down (never up), so the list compacts in place.
    let mut out_owner = Vec::with_capacity(faces.len());
    let mut w = 0;
    for f in 0..faces.len() {
        if kept[f] {
            faces[w] = faces[f].map(|k| remap[k as usize]);
            out_owner.push(owner_of(f));
            w += 1;
        }
    }
    faces.truncate(w);
    mesh.faces = faces;
    out_owner
}
