//! Shells a union can leave that are not membrane.

use crate::mesh::Mesh;

/// Removes the closed shells a union can leave that are not membrane: voids
/// (inward components, negative signed volume) and, with fillers, filler
/// pieces that touch nothing else (components whose every face `filler`
/// names).
///
/// A void is the inside of a ring of parts that crossed each other all
/// round it: fillers and the tubes around them (found by the random trees),
/// or in a tangle of traced branches (a jittered copy of a 260-tree BigNeuron
/// file enclosed one of 0.035 µm³ among its crossing tubes). A cell's
/// membrane has no cavity, whether the polygons made it or the round cones
/// have it too, and an inward shell would make the mesh fail "outward": it
/// is filled. That adds its volume (and drops its area) against the union of
/// round cones, a share of a share of a percent.
pub(super) fn drop_shells(mesh: &mut Mesh, filler: impl Fn(usize) -> bool) {
    let component = crate::kernel::disjoint_sets::face_components(&mesh.faces, mesh.vertices.len());
    let count = component.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    if count < 2 {
        return;
    }
    let mut volume = vec![0.0f64; count];
    let view = mesh.view();
    let c = view.center();
    for (f, &k) in component.iter().enumerate() {
        let [a, b, d] = view.triangle(f, c);
        volume[k as usize] += crate::kernel::vector::dot(a, crate::kernel::vector::cross(b, d));
    }
    let mut filler_only = vec![true; count];
    for (f, &k) in component.iter().enumerate() {
        if !filler(f) {
            filler_only[k as usize] = false;
        }
    }
    let drop: Vec<bool> = (0..count)
        .map(|k| volume[k] < 0.0 || filler_only[k])
        .collect();
    if !drop.contains(&true) || drop.iter().all(|&d| d) {
        return;
    }
    mesh.retain_faces(|f| !drop[component[f] as usize]);
}
