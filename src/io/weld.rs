//! Merging the duplicated corners of a mesh file that lists each face's
//! vertices on their own (STL) or repeats them (some OBJ writers).

use std::collections::HashMap;

/// Merges vertices with bit-identical positions and renumbers the faces.
pub(super) fn weld(
    vertices: Vec<[f64; 3]>,
    faces: Vec<[u32; 3]>,
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut index: HashMap<[u64; 3], u32> = HashMap::with_capacity(vertices.len());
    let mut out = Vec::with_capacity(vertices.len());
    let remap: Vec<u32> = vertices
        .iter()
        .map(|v| {
            // +0.0 and -0.0 are the same point.
            let key = v.map(|c| if c == 0.0 { 0 } else { c.to_bits() });
            *index.entry(key).or_insert_with(|| {
                out.push(*v);
                (out.len() - 1) as u32
            })
        })
        .collect();
    let faces = faces
        .into_iter()
        .map(|f| f.map(|k| remap[k as usize]))
        .collect();
    (out, faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weld_merges_identical_points() {
        let (v, f) = weld(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [-0.0, 0.0, 0.0]],
            vec![[0, 1, 2]],
        );
        assert_eq!(v.len(), 2);
        assert_eq!(f, vec![[0, 1, 0]]);
    }
}
