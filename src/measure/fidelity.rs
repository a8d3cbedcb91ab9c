//! How faithful a mesh is to the skeleton it stands for, point by point: the
//! samples it leaves outside, and how far its vertices lie from the ideal
//! surface, the boundary of the union of the skeleton's round cones (each
//! soma one sphere).
//!
//! * **Samples.** Every neurite sample and every soma's centre must lie
//!   strictly inside the mesh. A point is inside when a ray from it crosses
//!   the surface an odd number of times; a ray that passes near an edge or
//!   a vertex, or starts on the surface, is not counted, and the next of a
//!   few fixed directions is tried (the majority decides if none is clear).
//!   The samples of a multi-point soma are its outline, not its inside, and
//!   are left out; its centre stands for it.
//! * **Deviation.** For a vertex outside the union, its distance to the
//!   union is the least of the round cones' distances (exact). For a vertex
//!   inside, it is at least its depth in the round cone that holds it
//!   deepest, which is what is reported: near the surface the two agree.
//!   Each distance is also given in the local radius, the radius of the
//!   sphere of the nearest (or deepest-holding) round cone at that place.
//!   The mean of the distances in file units is the surface mean error.
//!
//! The bounds a faithful mesh keeps are [`MAX_DEVIATION`] at the worst
//! vertex and [`P95_DEVIATION`] at the 95th percentile, in local radii.

use glam::DVec3;

use crate::input::morphology::Morphology;
use crate::kernel::bvh::{Aabb, Bvh};
use crate::kernel::round_cone::RoundCone;
use crate::kernel::vector::P3;
use crate::mesh::MeshView;

/// The worst vertex of a faithful mesh lies within this many local radii of
/// the union of round cones.
pub const MAX_DEVIATION: f64 = 0.25;

/// The 95th percentile of a faithful mesh's vertices lies within this many
/// local radii of the union of round cones.
pub const P95_DEVIATION: f64 = 0.05;

/// At most this many samples outside are listed in a report (all are
/// counted).
pub const MAX_LISTED_SAMPLES: usize = 100;

/// Distances of the vertices from the ideal surface.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Deviation {
    /// Median, 95th percentile and worst, in local radii.
    pub radii: [f64; 3],
    /// Median, 95th percentile and worst, in file units.
    pub units: [f64; 3],
    /// The mean distance in file units (surface mean error).
    pub mean: f64,
}

/// The point-by-point comparison of a mesh with the union of its
/// skeleton's round cones.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Fidelity {
    /// Samples tested: every neurite sample and every soma's centre.
    pub samples: usize,
    /// How many of them are not strictly inside the mesh.
    pub samples_outside: usize,
    /// The first 100 of those, as sample indices (a
    /// soma's centre as its first sample).
    pub outside: Vec<u32>,
    /// The vertices' distances from the union's boundary.
    pub deviation: Deviation,
}

impl Fidelity {
    /// Every sample inside, and the deviation within [`MAX_DEVIATION`] and
    /// [`P95_DEVIATION`].
    pub fn is_faithful(&self) -> bool {
        self.samples_outside == 0
            && self.deviation.radii[2] <= MAX_DEVIATION
            && self.deviation.radii[1] <= P95_DEVIATION
    }
}

/// The fidelity of `mesh` (its positions relative to `mesh.origin`) to
/// `morphology`, in the morphology's units.
pub fn fidelity(mesh: &MeshView<'_>, morphology: &Morphology) -> Fidelity {
    let cones = morphology.round_cones();
    let origin = mesh.origin;
    let absolute = |v: [f32; 3]| -> P3 { [0, 1, 2].map(|a| f64::from(v[a]) + origin[a]) };
    let tris: Vec<[P3; 3]> = mesh
        .faces
        .iter()
        .map(|f| f.map(|k| absolute(mesh.vertices[k as usize])))
        .collect();
    let faces = Bvh::new(tris.iter().map(|t| Aabb::of(t)).collect());
    let points = tested_samples(morphology);
    let outside: Vec<u32> = crate::kernel::parallel::flat_map_range(points.len(), |i| {
        let (sample, p) = points[i];
        if inside(&faces, &tris, p) {
            Vec::new()
        } else {
            vec![sample]
        }
    });
    let deviation = deviation(mesh, &cones, absolute);
    Fidelity {
        samples: points.len(),
        samples_outside: outside.len(),
        outside: outside.into_iter().take(MAX_LISTED_SAMPLES).collect(),
        deviation,
    }
}

/// The points that must lie inside: each neurite sample, and each soma's
/// centre (standing for its first sample).
fn tested_samples(m: &Morphology) -> Vec<(u32, P3)> {
    let soma = m.soma_mask();
    let somas = m
        .trees()
        .iter()
        .filter_map(|t| t.soma.as_ref())
        .map(|s| (s.samples.first().copied().unwrap_or(0), s.center));
    let neurites = (0..m.len())
        .filter(|&i| !soma[i])
        .map(|i| (i as u32, m.positions()[i]));
    somas.chain(neurites).collect()
}

/// Ray directions for the inside test: fixed, far from the axes and from
/// each other, so that no grid-aligned surface runs along one.
const RAYS: [P3; 5] = [
    [0.5772, 0.6184, 0.5331],
    [-0.7013, 0.2213, 0.6776],
    [0.3103, -0.8431, 0.4391],
    [-0.4472, -0.5312, -0.7196],
    [0.8112, 0.1379, -0.5682],
];

/// Whether `p` lies strictly inside the closed surface of triangles `tris`.
fn inside(faces: &Bvh, tris: &[[P3; 3]], p: P3) -> bool {
    let mut votes = [0u32; 2];
    for dir in RAYS {
        let (mut hits, mut near) = (0u32, false);
        faces.for_each_on_ray(p, dir, f64::INFINITY, |f| {
            let (hit, close) =
                crate::kernel::predicates::ray_triangle_near(p, dir, tris[f as usize]);
            near |= close;
            hits += u32::from(hit.is_some());
        });
        let odd = hits % 2 == 1;
        if !near {
            return odd;
        }
        votes[usize::from(odd)] += 1;
    }
    votes[1] > votes[0]
}

/// The vertices' distances from the boundary of the union of `cones`
/// (`absolute` gives a vertex's position in the cones' frame).
fn deviation(
    mesh: &MeshView<'_>,
    cones: &[RoundCone],
    absolute: impl Fn([f32; 3]) -> P3 + Sync,
) -> Deviation {
    if cones.is_empty() || mesh.vertices.is_empty() {
        return Deviation::default();
    }
    let boxes: Vec<Aabb> = cones.iter().map(RoundCone::aabb).collect();
    let mut radii: Vec<f64> = cones.iter().map(|c| c.ra.max(c.rb)).collect();
    radii.sort_by(f64::total_cmp);
    let start = radii[radii.len() / 2].max(1e-300);
    let all = boxes.iter().fold(Aabb::EMPTY, |mut a, b| {
        a.add(b);
        a
    });
    let span = (0..3).map(|a| all.hi[a] - all.lo[a]).fold(0.0, f64::max);
    let bvh = Bvh::new(boxes);
    let distances: Vec<(f64, f64)> = crate::kernel::parallel::map(mesh.vertices, |&v| {
        let p = absolute(v);
        nearest_surface(&bvh, cones, p, start, span)
    });
    let mut units: Vec<f64> = distances.iter().map(|d| d.0).collect();
    let mut in_radii: Vec<f64> = distances.iter().map(|d| d.0 / d.1.max(1e-300)).collect();
    let mean = units.iter().sum::<f64>() / units.len() as f64;
    Deviation {
        radii: quantiles(&mut in_radii),
        units: quantiles(&mut units),
        mean,
    }
}

/// The distance from `p` to the boundary of the union of `cones` (see the
/// module docs) and the local radius there, looking first within `start`
/// of `p` and then twice as far each time, up to `span`.
fn nearest_surface(bvh: &Bvh, cones: &[RoundCone], p: P3, start: f64, span: f64) -> (f64, f64) {
    let point = DVec3::from_array(p);
    let mut reach = start;
    loop {
        let query = Aabb::of(&[p]).inflated(reach);
        // The least distance from outside, and the deepest hold from inside.
        let (mut out, mut deep) = ((f64::INFINITY, 1.0), (0.0, 0.0));
        bvh.for_each_overlap(&query, |i| {
            let (d, r) = cones[i as usize].sdf_and_radius(point);
            if d < out.0 {
                out = (d, r);
            }
            if -d > deep.0 {
                deep = (-d, r);
            }
        });
        if deep.0 > 0.0 {
            return deep;
        }
        if out.0 <= reach || reach >= span {
            return (out.0.max(0.0), out.1);
        }
        reach *= 2.0;
    }
}

/// The median, 95th percentile and largest of `values` (reordered).
fn quantiles(values: &mut [f64]) -> [f64; 3] {
    let n = values.len();
    let at = |values: &mut [f64], q: f64| {
        let k = ((q * (n - 1) as f64).round() as usize).min(n - 1);
        *values.select_nth_unstable_by(k, f64::total_cmp).1
    };
    [at(values, 0.5), at(values, 0.95), at(values, 1.0)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    /// A straight path of `n` samples 2 apart, radius `r`, as a morphology.
    fn rod(n: usize, r: f64) -> Morphology {
        let ids: Vec<i64> = (1..=n as i64).collect();
        let parents: Vec<i64> = (0..n as i64).map(|i| if i == 0 { -1 } else { i }).collect();
        let xyz: Vec<[f64; 3]> = (0..n).map(|i| [2.0 * i as f64, 0.0, 0.0]).collect();
        Morphology::from_arrays(&ids, &vec![3; n], &xyz, &vec![r; n], &parents).expect("valid")
    }

    #[test]
    fn a_mesh_of_the_rod_holds_its_samples_near_its_surface() {
        let m = rod(10, 1.0);
        let mesh = crate::mesh_morphology(&m, &crate::Params::default()).expect("meshes");
        let f = fidelity(&mesh.view(), &m);
        assert_eq!((f.samples, f.samples_outside), (10, 0), "{f:?}");
        assert!(f.deviation.radii[2] < MAX_DEVIATION, "{f:?}");
        assert!(f.deviation.mean < 0.05, "{f:?}");
    }

    #[test]
    fn a_mesh_too_small_leaves_samples_out_and_deviates() {
        let m = rod(10, 1.0);
        let mut mesh = crate::mesh_morphology(&m, &crate::Params::default()).expect("meshes");
        // Shrunk to half its size about the rod's first sample: the far
        // samples are left out, and every vertex moves off the surface.
        for v in &mut mesh.vertices {
            *v = v.map(|c| c * 0.5);
        }
        let f = fidelity(&mesh.view(), &m);
        assert!(f.samples_outside >= 4, "{f:?}");
        assert!(f.deviation.radii[2] > 0.4 && !f.is_faithful(), "{f:?}");
        assert!(f.outside.iter().all(|&s| s >= 5), "{:?}", f.outside);
    }

    #[test]
    fn distances_inside_and_outside_a_sphere_are_exact() {
        let cones = [RoundCone::sphere(DVec3::ZERO, 2.0)];
        let bvh = Bvh::new(cones.iter().map(RoundCone::aabb).collect());
        let (d, r) = nearest_surface(&bvh, &cones, [3.0, 0.0, 0.0], 0.5, 10.0);
        assert!((d - 1.0).abs() < 1e-12 && r == 2.0);
        let (d, _) = nearest_surface(&bvh, &cones, [0.0, 1.5, 0.0], 0.5, 10.0);
        assert!((d - 0.5).abs() < 1e-12);
        let empty = Mesh::default();
        assert_eq!(
            deviation(&empty.view(), &cones, |v| v.map(f64::from)),
            Deviation::default()
        );
    }
}
