//! The soma (section 3.3 of the paper): a sphere point set with one cap
//! removed per trunk, triangulated by spade's constrained Delaunay
//! triangulation, and bridged to the trunks' first contours.
//!
//! * **Point set.** A Fibonacci sphere at about the trunks' edge length
//!   ([`spacing`]); the points under each trunk's *footprint* (the paper's
//!   C_trans: the trunk's first contour carried onto the sphere, see
//!   [`footprint_loop`]) and within half a spacing of it are removed.
//! * **Triangulation on the sphere with a planar CDT.** Stereographic
//!   projection from a pole P on the sphere, `x ↦ (x·e1, x·e2) / (1 − x·P)`,
//!   maps every circle on the sphere that misses P to a circle in the plane. A
//!   triangulation is Delaunay when no point lies inside a triangle's
//!   circumcircle; on the sphere the "circumcircle" is the circle through the
//!   triangle's three vertices, and being inside it means lying in the cap it
//!   bounds away from P. Both notions correspond under the projection, so the
//!   planar Delaunay triangulation of the projected points is the spherical
//!   one (the convex hull of the points, as long as P lies in an empty cap).
//!   P is the centre of the largest footprint, which is removed: the footprint
//!   maps to a convex polygon enclosing all other points, and the other
//!   footprints map to polygons inside it. Each footprint's edges are
//!   constraints; the faces inside the inner polygons and outside the outer one
//!   are dropped, the rest lifted back to the sphere.
//! * **Bridges.** The footprint and the trunk's first contour share their
//!   vertex order (one is the radial projection of the other), so rings
//!   interpolated between them, about one spacing apart, are joined quad by
//!   quad. The bridge lies in the cone from the centre over its footprint, so
//!   bridges of disjoint footprints cannot meet, nor meet the sphere's faces.
//! * **Overlapping footprints** (trunks leaving close together: the paper's
//!   "intersected copies") are resolved before the tubes are built: the
//!   thickest trunk keeps its footprint, and a trunk whose footprint would
//!   overlap one already kept is spliced onto the surface like a secondary
//!   branch (see [`crate::build::plan`]), starting beyond the kept trunk's
//!   volume.
//!   No footprint is ever cut, so the triangulation never sees crossing
//!   constraints.
//!
//! Without trunks (a soma alone, or every neurite hidden inside it) the pole is
//! one of the set's points: the triangulation covers everything but the pole's
//! neighbourhood, whose border (the planar convex hull) is fanned to the pole.

use glam::DVec3;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use crate::build::surface::Surface;
use crate::build::tube::Ring;

/// The soma as a sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: DVec3,
    /// Radius of the mesh's sphere (see [`mesh_radius`]).
    pub radius: f64,
}

/// Where a trunk meets the sphere: the cap under its first contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Unit direction from the centre to the cap's centre.
    pub dir: DVec3,
    /// Angular radius of the cap (radians).
    pub angle: f64,
}

/// Fewest and most points on a great circle of the soma's point set: the
/// soma is never coarser than a 24-gon nor finer than a 96-gon in section.
const MIN_SECTION_VERTICES: f64 = 24.0;
const MAX_SECTION_VERTICES: f64 = 96.0;

/// The sphere radius that gives an inscribed triangulation at angular spacing
/// `delta` about the area and volume of a sphere of radius `r`: flat
/// triangles between points on the sphere cut off a shell whose relative
/// thickness grows as `delta²`. Measured on the soma alone over the allowed
/// spacings (24- to 96-gon sections, 215 to 3,391 points): area within
/// +0.04 %, volume from −0.54 % (coarsest) to −0.03 % (finest).
pub fn mesh_radius(r: f64, delta: f64) -> f64 {
    r * (1.0 + 0.11 * delta * delta)
}

/// Point spacing on a soma of radius `r` whose trunks have contour edges of
/// mean length `edge` (None: no trunks): the edge length, kept between a
/// 96-gon's and a 24-gon's edge on a great circle.
pub fn spacing(r: f64, edge: Option<f64>) -> f64 {
    let tau = std::f64::consts::TAU;
    let (fine, coarse) = (
        tau * r / MAX_SECTION_VERTICES,
        tau * r / MIN_SECTION_VERTICES,
    );
    edge.unwrap_or(tau * r / 48.0).clamp(fine, coarse)
}

/// `n` nearly uniform unit vectors (the Fibonacci lattice).
pub fn fibonacci(n: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let rho = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            DVec3::new(rho * phi.cos(), rho * phi.sin(), z)
        })
        .collect()
}

/// Where a trunk's first contour meets the sphere, vertex by vertex, as unit
/// vectors from the centre: the contour projected radially (the paper's
/// C_trans, translated along the line to the centre until it lies on the
/// sphere, is the same loop up to the contour's tilt).
///
/// Why not the hull of the sphere and the contour's own sphere, which the
/// union of round cones follows: where a trunk's first sample sits near the
/// soma's surface that hull touches the sphere far out (half a hemisphere for
/// a trunk of a third of the soma's radius), so neighbouring trunks' caps would
/// overlap, while the volume between the hull and the radial bridge is a thin
/// wedge.
pub fn footprint_loop(sphere: &Sphere, pts: &[DVec3]) -> Vec<DVec3> {
    pts.iter()
        .map(|p| (*p - sphere.center).normalize_or_zero())
        .collect()
}

/// The cap spanned by a footprint loop (unit vectors).
pub fn footprint(units: &[DVec3]) -> Footprint {
    let dir = units.iter().copied().sum::<DVec3>().normalize_or_zero();
    let angle = units
        .iter()
        .map(|u| u.dot(dir).clamp(-1.0, 1.0).acos())
        .fold(0.0, f64::max);
    Footprint { dir, angle }
}

/// Whether two footprints come within `margin` radians of each other.
pub fn footprints_meet(a: &Footprint, b: &Footprint, margin: f64) -> bool {
    a.dir.dot(b.dir).clamp(-1.0, 1.0).acos() < a.angle + b.angle + margin
}

/// Number of Fibonacci points for angular spacing `delta`: each point owns an
/// equilateral-triangle pair of area `delta²·√3/2` of the unit sphere.
fn point_count(delta: f64) -> usize {
    let n = 4.0 * std::f64::consts::PI / (delta * delta * 3f64.sqrt() / 2.0);
    (n.ceil() as usize).clamp(32, 200_000)
}

/// Builds the soma into `surface` and bridges it to the first `rings` of its
/// trunks (whose footprints must be disjoint and whose vertices must lie
/// outside the sphere). `spacing` is the point spacing, `label` the sample the
/// soma's vertices carry. On failure the surface is left as it was.
///
/// # Errors
/// A static reason when the triangulation cannot be built as planned.
pub fn build(
    surface: &mut Surface,
    sphere: &Sphere,
    rings: &[Ring],
    spacing: f64,
    label: u32,
) -> Result<(), &'static str> {
    let mark = surface.mark();
    let result = build_unchecked(surface, sphere, rings, spacing, label);
    if result.is_err() {
        surface.rollback(mark);
    }
    result
}

fn build_unchecked(
    surface: &mut Surface,
    sphere: &Sphere,
    rings: &[Ring],
    spacing: f64,
    label: u32,
) -> Result<(), &'static str> {
    let (c, r) = (sphere.center, sphere.radius);
    // Footprints: each ring projected onto the sphere.
    let loops: Vec<Vec<DVec3>> = rings
        .iter()
        .map(|ring| {
            let pts: Vec<DVec3> = (0..ring.m)
                .map(|j| surface.pos[ring.vertex(j) as usize])
                .collect();
            footprint_loop(sphere, &pts)
        })
        .collect();
    if loops.iter().flatten().any(|u| *u == DVec3::ZERO) {
        return Err("a contour vertex at the soma centre");
    }
    let cover = triangulate_sphere(&loops, spacing / r)?;
    // Lift back: the set and the footprints on the mesh sphere.
    let first = surface.pos.len() as u32;
    let first_tri = surface.tris.len();
    for &u in &cover.points {
        surface.vertex(c + r * u, label);
    }
    let id = |i: usize| first + i as u32;
    let points = &cover.points;
    let outward = |f: [usize; 3]| {
        let [a, b, cc] = f.map(|i| points[i]);
        (b - a).cross(cc - a).dot(a + b + cc) > 0.0
    };
    for f in &cover.faces {
        if outward(*f) {
            surface.triangle(id(f[0]), id(f[1]), id(f[2]));
        } else {
            surface.triangle(id(f[0]), id(f[2]), id(f[1]));
        }
    }
    if !cover.holed {
        fan_to_pole(surface, first, cover.faces.len(), c + r * cover.pole, label);
    }
    for ((ring, &s), lp) in rings.iter().zip(&cover.starts).zip(&loops) {
        let footprint: Vec<u32> = (0..lp.len()).map(|j| id(s + j)).collect();
        bridge_to_ring(surface, sphere, ring, lp, &footprint, spacing);
    }
    loops_are_consistent(surface, first, first_tri, &cover.starts, &loops)
}

/// The sphere's triangulation between the footprints, on the unit sphere.
struct Cover {
    /// The point set, then each footprint's loop.
    points: Vec<DVec3>,
    /// Where each footprint's loop begins in `points`.
    starts: Vec<usize>,
    /// Triangles (indices into `points`), not yet oriented.
    faces: Vec<[usize; 3]>,
    /// The projection's pole: the largest footprint's centre, or a point of
    /// the set.
    pole: DVec3,
    /// Whether the pole lies in a footprint; if not, the hole around it is
    /// left for [`fan_to_pole`].
    holed: bool,
}

/// The Fibonacci point set of spacing `delta` (on the unit sphere) without
/// what lies under or next to a footprint `loops`, with those loops,
/// triangulated by spade in the stereographic projection from the largest
/// footprint's centre (circles stay circles, so the planar Delaunay is the
/// spherical one), the footprints' insides dropped.
fn triangulate_sphere(loops: &[Vec<DVec3>], delta: f64) -> Result<Cover, &'static str> {
    let prints: Vec<Footprint> = loops.iter().map(|lp| footprint(lp)).collect();
    let mut points: Vec<DVec3> = fibonacci(point_count(delta))
        .into_iter()
        .filter(|u| {
            prints
                .iter()
                .all(|f| u.dot(f.dir).clamp(-1.0, 1.0).acos() > f.angle + 0.5 * delta)
        })
        .collect();
    let outer = (0..prints.len()).max_by(|&a, &b| prints[a].angle.total_cmp(&prints[b].angle));
    let pole = match outer {
        Some(k) => prints[k].dir,
        None => points.pop().ok_or("no points")?,
    };
    let e1 = crate::kernel::vector::any_perpendicular(pole);
    let e2 = pole.cross(e1);
    let project = |u: DVec3| {
        let d = 1.0 - u.dot(pole);
        [u.dot(e1) / d, u.dot(e2) / d]
    };
    // All points on the unit sphere: the set, then each footprint's loop.
    let free = points.len();
    let mut starts = Vec::with_capacity(loops.len());
    for lp in loops {
        starts.push(points.len());
        points.extend_from_slice(lp);
    }
    let planar: Vec<[f64; 2]> = points.iter().map(|&u| project(u)).collect();
    if planar
        .iter()
        .any(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err("a point projects to infinity");
    }
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for (lp, &s) in loops.iter().zip(&starts) {
        let m = lp.len();
        edges.extend((0..m).map(|j| [s + j, s + (j + 1) % m]));
    }
    let mut conflict = false;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(
            planar.iter().map(|p| Point2::new(p[0], p[1])).collect(),
            edges,
            |_| conflict = true,
        )
        .map_err(|_| "spade refused the points")?;
    if conflict || cdt.num_vertices() != points.len() {
        return Err("footprints cross or points coincide");
    }
    let polygons: Vec<Vec<[f64; 2]>> = starts
        .iter()
        .zip(loops)
        .map(|(&s, lp)| planar[s..s + lp.len()].to_vec())
        .collect();
    let mut faces: Vec<[usize; 3]> = Vec::with_capacity(2 * points.len());
    for (v, centroid) in crate::kernel::planar::triangles_with_centroids(&cdt, &planar) {
        let keep = polygons.iter().enumerate().all(|(k, poly)| {
            let inside = crate::kernel::planar::inside_polygon(centroid, poly);
            if Some(k) == outer { inside } else { !inside }
        });
        if keep {
            faces.push(v);
        }
    }
    // A sphere with k holes bounded by B loop vertices and I inner points has
    // 2I + B + 2k − 4 triangles; a sphere without holes gets its pole fan.
    let boundary = points.len() - free;
    if outer.is_some() && faces.len() != 2 * free + boundary + 2 * loops.len() - 4 {
        return Err("the triangulation does not cover the sphere between the footprints");
    }
    Ok(Cover {
        points,
        starts,
        faces,
        pole,
        holed: outer.is_some(),
    })
}

/// The bridge from a trunk's footprint on the sphere (`lp` on the unit
/// sphere, its vertices `footprint`) to its first ring, in rings about one
/// `spacing` apart.
fn bridge_to_ring(
    surface: &mut Surface,
    sphere: &Sphere,
    ring: &Ring,
    lp: &[DVec3],
    footprint: &[u32],
    spacing: f64,
) {
    let (c, r) = (sphere.center, sphere.radius);
    let m = lp.len();
    let far = (0..m)
        .map(|j| surface.pos[ring.vertex(j as u32) as usize].distance(c + r * lp[j]))
        .fold(0.0, f64::max);
    let levels = ((far / spacing).round() as usize).clamp(1, 64);
    let mut below: Vec<u32> = footprint.to_vec();
    for k in 1..=levels {
        let above: Vec<u32> = if k == levels {
            (0..m as u32).map(|j| ring.vertex(j)).collect()
        } else {
            let t = k as f64 / levels as f64;
            (0..m)
                .map(|j| {
                    let top = surface.pos[ring.vertex(j as u32) as usize];
                    let p = (c + r * lp[j]).lerp(top, t);
                    surface.vertex(p, ring.label)
                })
                .collect()
        };
        for j in 0..m {
            let jn = (j + 1) % m;
            surface.triangle(below[j], below[jn], above[j]);
            surface.triangle(below[jn], above[jn], above[j]);
        }
        below = above;
    }
}

/// Closes the hole around the pole (the border of the triangulated faces,
/// the last `faces` triangles) with a fan.
fn fan_to_pole(surface: &mut Surface, first_vertex: u32, faces: usize, pole: DVec3, label: u32) {
    let start = surface.tris.len() - faces;
    let mut directed: crate::kernel::hash::FastSet<(u32, u32)> =
        crate::kernel::hash::FastSet::default();
    for t in &surface.tris[start..] {
        for e in 0..3 {
            directed.insert((t[e], t[(e + 1) % 3]));
        }
    }
    let border: Vec<(u32, u32)> = directed
        .iter()
        .filter(|&&(a, b)| a >= first_vertex && !directed.contains(&(b, a)))
        .copied()
        .collect();
    let apex = surface.vertex(pole, label);
    for (a, b) in border {
        surface.triangle(b, a, apex);
    }
}

/// Proof that the soma's faces and the bridges meet edge to edge with opposite
/// directions along every footprint (so the orientation is consistent).
fn loops_are_consistent(
    surface: &Surface,
    first: u32,
    first_tri: usize,
    starts: &[usize],
    loops: &[Vec<DVec3>],
) -> Result<(), &'static str> {
    let mut directed: crate::kernel::hash::FastMap<(u32, u32), u32> =
        crate::kernel::hash::FastMap::default();
    for t in &surface.tris[first_tri..] {
        for e in 0..3 {
            *directed.entry((t[e], t[(e + 1) % 3])).or_insert(0) += 1;
        }
    }
    for (&s, lp) in starts.iter().zip(loops) {
        let m = lp.len();
        for j in 0..m {
            let (a, b) = (first + (s + j) as u32, first + (s + (j + 1) % m) as u32);
            if directed.get(&(a, b)) != Some(&1) || directed.get(&(b, a)) != Some(&1) {
                return Err("a footprint's faces and bridge disagree in orientation");
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::BuildStats;

    fn alone(radius: f64) -> crate::Mesh {
        let mut s = Surface::with_capacity(1000);
        let sphere = Sphere {
            center: DVec3::new(1.0, 2.0, 3.0),
            radius: mesh_radius(radius, spacing(radius, None) / radius),
        };
        build(&mut s, &sphere, &[], spacing(radius, None), 0).expect("sphere");
        s.into_mesh(BuildStats::default())
    }

    #[test]
    fn a_soma_alone_is_a_closed_sphere_within_one_percent() {
        let m = alone(5.0);
        let r = m.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        let pi = std::f64::consts::PI;
        let (a, v) = (4.0 * pi * 25.0, 4.0 / 3.0 * pi * 125.0);
        assert!((m.area() / a - 1.0).abs() < 0.01, "area {}", m.area() / a);
        assert!(
            (m.volume() / v - 1.0).abs() < 0.01,
            "volume {}",
            m.volume() / v
        );
    }

    #[test]
    fn fibonacci_points_are_unit_and_spread() {
        let p = fibonacci(500);
        assert!(p.iter().all(|u| (u.length() - 1.0).abs() < 1e-12));
        let mean = p.iter().copied().sum::<DVec3>() / 500.0;
        assert!(mean.length() < 1e-2);
    }

    #[test]
    fn footprints_of_opposite_caps_do_not_meet() {
        let a = Footprint {
            dir: DVec3::X,
            angle: 0.3,
        };
        let b = Footprint {
            dir: -DVec3::X,
            angle: 0.3,
        };
        assert!(!footprints_meet(&a, &b, 0.1));
        assert!(footprints_meet(&a, &a, 0.0));
    }
}
