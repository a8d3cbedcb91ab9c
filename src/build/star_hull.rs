//! Cells whose union of round cones is one star-shaped blob, meshed as a
//! radial surface around the centre of their largest sphere.
//!
//! Some platforms write codes into the SWC radius column (radii of
//! thousands on a cell a few hundred units across,
//! [`crate::input::plausibility`]). Their union of round cones is then a blob
//! a few times wider than the cell, and the paper's tubes cannot follow it:
//! each contour is swallowed by its neighbours, and the tubes that remain end
//! in flat caps where the union has half of a sphere.
//!
//! Such a union is star-shaped. Let the largest sphere of the skeleton have
//! centre `c` and radius `R`. A round cone with both end spheres inside it
//! lies inside it (it is their convex hull); every other round cone of these
//! cells has an end sphere that contains `c`, and so contains `c` itself. A
//! union of convex sets that all contain `c` meets every ray from `c` in one
//! segment from `c`, so its surface is the radial graph `c + ρ(u)·u`, where
//! `ρ(u)` is the farthest exit along `u` over the sphere and those cones.
//! When every cone passes this test the cell is meshed that way: the soma's
//! sphere point set and triangulation ([`crate::build::soma`]), with each unit
//! direction moved out to `ρ(u)`. A radial graph over a triangulated sphere
//! is closed and cannot cross itself as long as every triangle still faces
//! away from `c`, which is checked; when one does not (the surface turns too
//! fast between neighbouring directions) the cell goes the usual way.
//!
//! Each direction looks only at the cones that could reach past the best
//! exit found so far (bounds per run of cones and per cone), a tenth of the
//! work of testing every cone on a blob of tens of thousands of them.
//!
//! Ordinary cells never pass the test: a tip far from the soma has neither
//! end inside the largest sphere nor containing its centre. A cell whose
//! largest sphere is its soma goes the usual way too, so somas keep the
//! paper's construction (section 3.3).
//!
//! **Nearly star-shaped.** A blob where some cones miss the centre (the
//! samples jittered off it) is still meshed as `c + ρ(u)·u`, the same
//! farthest exit over every cone, when at most [`MAX_STRAY_SHARE`] of those
//! cones miss the centre and none of those reaches farther than
//! [`MAX_SPAN`] largest radii from it. That surface is the union's star
//! hull around `c`: closed, not crossing itself (the faces are checked as
//! above), holding the union and filling the hollows it leaves between rays,
//! a departure from the union of round cones of up to a few tens of per cent
//! in area. The usual way cannot mesh such a cell at all: its tubes,
//! swallowed by spheres a hundred segments wide, cross each other millions
//! of times. Of an ordinary cell's cones nearly all miss the centre, so it
//! still goes the usual way.

use glam::DVec3;

use crate::build::soma::{self, Sphere};
use crate::build::surface::Surface;
use crate::input::morphology::Morphology;
use crate::kernel::round_cone::RoundCone;
use crate::mesh::{BuildStats, Mesh};

/// Angular spacing of the directions: a 160-gon on a great circle, about
/// 9,400 directions and 19,000 triangles.
const DELTA: f64 = std::f64::consts::TAU / 160.0;

/// An end sphere contains the centre when the centre is this fraction of its
/// radius inside it, so `ρ` stays clear of zero.
const INSIDE: f64 = 0.99;

/// A union is meshed as its star hull around its largest sphere when at
/// most this share of the cones reaching out of that sphere miss its centre
/// (see the module documentation).
pub const MAX_STRAY_SHARE: f64 = 0.5;

/// A nearly star-shaped union is meshed as its hull only when every cone
/// missing the centre lies within this many largest radii of it: at that
/// distance the 160-gon's edge is an eighth of the radius, and farther out
/// (an elongated cell seen from one end) the radial surface loses the
/// shape.
pub const MAX_SPAN: f64 = 3.0;

/// Golden-section steps refining where along a cone a ray leaves it last.
const REFINE_STEPS: usize = 24;

/// The search inside a cone is skipped where it could move the surface out
/// by at most this fraction of the largest radius (0.001 % of it: a 10⁻⁵
/// share of the volume at most).
const SLACK: f64 = 1e-5;

/// The blob's centre, radius and the cones that reach out of its largest
/// sphere (with the sample each one labels its vertices with), if the
/// morphology's union of round cones is star-shaped around that centre as
/// the module describes.
struct Blob {
    center: DVec3,
    radius: f64,
    label: u32,
    /// The cones measured from the centre, in sample order (neighbours in
    /// the tree lie near each other), each with the sample it labels
    /// vertices with.
    cones: Vec<(RoundCone, u32)>,
    /// Runs of [`CHUNK`] consecutive cones, each with a ball holding them.
    chunks: Vec<Chunk>,
}

/// Cones per chunk: enough that a ray skips most of them a chunk at a time.
const CHUNK: usize = 32;

/// A run of cones and a ball (`center`, `radius`) that holds them all, so
/// no ray leaves them farther than `u·center + radius`.
struct Chunk {
    center: DVec3,
    radius: f64,
    cones: std::ops::Range<usize>,
}

impl Chunk {
    fn new(cones: &[(RoundCone, u32)], range: std::ops::Range<usize>) -> Chunk {
        let part = &cones[range.clone()];
        let center = part.iter().map(|(c, _)| c.a + c.b).sum::<DVec3>() / (2 * part.len()) as f64;
        let radius = part
            .iter()
            .map(|(c, _)| (c.a.distance(center) + c.ra).max(c.b.distance(center) + c.rb))
            .fold(0.0, f64::max);
        Chunk {
            center,
            radius,
            cones: range,
        }
    }

    /// No point of the chunk's cones lies farther along `u` than this.
    fn bound(&self, u: DVec3) -> f64 {
        u.dot(self.center) + self.radius
    }
}

/// The mesh of `morphology` (scaled by `scale`, stored around `origin`) as a
/// radial surface, when its union of round cones is a star-shaped blob
/// around its largest sphere, which is not a soma; `None` otherwise.
///
/// A union that is only nearly star-shaped is meshed as its star hull
/// (see the module documentation).
pub fn mesh(morphology: &Morphology, scale: f64, origin: [f64; 3]) -> Option<Mesh> {
    let blob = find(morphology, scale, origin)?;
    let mut surface = Surface::with_capacity(10_000);
    let unit = Sphere {
        center: DVec3::ZERO,
        radius: 1.0,
    };
    soma::build(&mut surface, &unit, &[], DELTA, blob.label).ok()?;
    // Flat triangles between points of a surface cut off a shell whose
    // thickness grows as the spacing squared; the soma's correction for it.
    let grow = soma::mesh_radius(1.0, DELTA);
    let reach: Vec<(f64, u32)> = crate::kernel::parallel::map(&surface.pos, |p| {
        let u = p.normalize();
        farthest_exit(&blob, u)
    });
    for (v, &(rho, label)) in reach.iter().enumerate() {
        let u = surface.pos[v].normalize();
        surface.pos[v] = blob.center + u * (rho * grow);
        surface.label[v] = label;
    }
    let faces_out = surface.tris.iter().all(|t| {
        let [a, b, c] = t.map(|k| surface.pos[k as usize] - blob.center);
        a.dot(b.cross(c)) > 0.0
    });
    faces_out.then(|| surface.into_mesh(BuildStats::default()))
}

/// The blob of `morphology`, if it is one, star-shaped or nearly (see the
/// module documentation).
fn find(morphology: &Morphology, scale: f64, origin: [f64; 3]) -> Option<Blob> {
    let somas = morphology
        .trees()
        .iter()
        .filter(|t| t.soma.is_some())
        .count();
    // The cones in the frame the mesh is built in, one at a time: the test
    // runs on every cell and fails at the first far tip of an ordinary one.
    let shift = DVec3::from_array(origin);
    let cones = || {
        morphology.labelled_round_cones().map(move |(c, sample)| {
            let c = RoundCone {
                a: c.a * scale - shift,
                ra: c.ra * scale,
                b: c.b * scale - shift,
                rb: c.rb * scale,
            };
            (c, sample)
        })
    };
    // The largest sphere: not a soma's (the first `somas` primitives).
    let (mut best, mut at, mut center, mut label) = (0usize, f64::NEG_INFINITY, DVec3::ZERO, 0);
    for (i, (c, sample)) in cones().enumerate() {
        for (p, r) in [(c.a, c.ra), (c.b, c.rb)] {
            if r > at {
                (best, at, center, label) = (i, r, p, sample);
            }
        }
    }
    if best < somas || !(at.is_finite() && at > 0.0) {
        return None;
    }
    let inside = |p: DVec3, r: f64| p.distance(center) + r <= at;
    let holds_center = |p: DVec3, r: f64| p.distance(center) <= INSIDE * r;
    let mut out = Vec::new();
    let mut strays = 0usize;
    for (c, sample) in cones() {
        if inside(c.a, c.ra) && inside(c.b, c.rb) {
            continue;
        }
        if !(holds_center(c.a, c.ra) || holds_center(c.b, c.rb)) {
            strays += 1;
            // Its directions are spaced for a surface within a few radii
            // of the centre: an elongated cell (a capsule seen from one
            // end) would be cut into long thin triangles.
            let reach = (c.a.distance(center) + c.ra).max(c.b.distance(center) + c.rb);
            if reach > MAX_SPAN * at {
                return None;
            }
            // Stop as soon as the share is out of reach (an ordinary cell,
            // half-way through its cones at most).
            if strays as f64 > MAX_STRAY_SHARE * morphology.len() as f64 {
                return None;
            }
        }
        // Measured from the centre from here on.
        let c = RoundCone {
            a: c.a - center,
            b: c.b - center,
            ..c
        };
        out.push((c, sample));
    }
    if strays as f64 > MAX_STRAY_SHARE * out.len() as f64 {
        return None;
    }
    let chunks = (0..out.len())
        .step_by(CHUNK)
        .map(|k| Chunk::new(&out, k..(k + CHUNK).min(out.len())))
        .collect();
    Some(Blob {
        center,
        radius: at,
        label,
        cones: out,
        chunks,
    })
}

/// `ρ(u)` and the sample that gives it: the farthest exit along `u` from the
/// centre over the largest sphere and the cones.
///
/// A ball's exit along `u` is at most `u·q + r` (q its centre), so a chunk
/// whose ball ends before the best exit so far is skipped whole; the chunk
/// that reaches farthest along `u` goes first, to set a good best.
fn farthest_exit(blob: &Blob, u: DVec3) -> (f64, u32) {
    let (mut best, mut label) = (blob.radius, blob.label);
    let first = (0..blob.chunks.len())
        .max_by(|&i, &j| blob.chunks[i].bound(u).total_cmp(&blob.chunks[j].bound(u)));
    let Some(first) = first else {
        return (best, label);
    };
    let order = std::iter::once(first).chain((0..blob.chunks.len()).filter(|&k| k != first));
    for k in order {
        let chunk = &blob.chunks[k];
        if chunk.bound(u) <= best {
            continue;
        }
        for (cone, sample) in &blob.cones[chunk.cones.clone()] {
            // Along the cone the bound is linear, so its ends hold it.
            if u.dot(cone.a) + cone.ra <= best && u.dot(cone.b) + cone.rb <= best {
                continue;
            }
            let t = cone_exit(cone, u, best, SLACK * blob.radius);
            if t > best {
                (best, label) = (t, *sample);
            }
        }
    }
    (best, label)
}

/// The last point along the ray `t·u` from the centre inside the ball of
/// the cone at `s` (centre and radius interpolated), or −∞ when the ray's
/// line misses it.
fn ball_exit(cone: &RoundCone, u: DVec3, s: f64) -> f64 {
    let q = cone.a.lerp(cone.b, s);
    let r = cone.ra + (cone.rb - cone.ra) * s;
    let along = u.dot(q);
    let disc = along * along - q.length_squared() + r * r;
    if disc < 0.0 {
        f64::NEG_INFINITY
    } else {
        along + disc.sqrt()
    }
}

/// The last point along the ray `t·u` inside the round cone, if it is
/// beyond `best`: the largest ball exit over the cone's balls. The set of
/// (s, t) with `t·u` in the ball at `s` is convex, so the exit is concave in
/// `s` where the line meets the ball: the better end, then a golden-section
/// search between the ends, run only where an upper bound says the inside
/// of the cone could beat them and `best` by more than `slack`.
fn cone_exit(cone: &RoundCone, u: DVec3, best: f64, slack: f64) -> f64 {
    // Along the cone, the part of q across the ray is linear in s: its
    // least length m bounds the exit by `max u·q + sqrt(max r² − m²)`.
    let (pa, pb) = (cone.a - u * u.dot(cone.a), cone.b - u * u.dot(cone.b));
    let d = pb - pa;
    let s = if d.length_squared() > 0.0 {
        (-pa.dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let m2 = (pa + d * s).length_squared();
    let r_max = cone.ra.max(cone.rb);
    if r_max * r_max <= m2 {
        return f64::NEG_INFINITY;
    }
    let bound = u.dot(cone.a).max(u.dot(cone.b)) + (r_max * r_max - m2).sqrt();
    if bound <= best {
        return f64::NEG_INFINITY;
    }
    let ends = ball_exit(cone, u, 0.0).max(ball_exit(cone, u, 1.0));
    if bound <= ends.max(best) + slack || cone.a.distance(cone.b) <= (cone.ra - cone.rb).abs() {
        // Nothing inside can gain more than `slack`, or one end's ball holds
        // the other and the cone is that ball.
        return ends;
    }
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (ball_exit(cone, u, x1), ball_exit(cone, u, x2));
    for _ in 0..REFINE_STEPS {
        if f1 < f2 {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = ball_exit(cone, u, x2);
        } else {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = ball_exit(cone, u, x1);
        }
    }
    ends.max(f1).max(f2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(rows: &[([f64; 3], f64, i64)]) -> Morphology {
        cell_of_types(&vec![3; rows.len()], rows)
    }

    /// Samples with ids 1, 2, … of the given types.
    fn cell_of_types(types: &[i32], rows: &[([f64; 3], f64, i64)]) -> Morphology {
        let ids: Vec<i64> = (1..=rows.len() as i64).collect();
        let xyz: Vec<[f64; 3]> = rows.iter().map(|r| r.0).collect();
        let radii: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let parents: Vec<i64> = rows.iter().map(|r| r.2).collect();
        Morphology::from_arrays(&ids, types, &xyz, &radii, &parents).expect("valid")
    }

    #[test]
    fn a_swollen_chain_is_its_union_as_one_closed_surface() {
        // Radii far beyond the segment lengths, as radius codes give, and a
        // thin tail inside the largest ball.
        let m = cell(&[
            ([0.0, 0.0, 0.0], 40.0, -1),
            ([3.0, 0.0, 0.0], 100.0, 1),
            ([6.0, 1.0, 0.0], 100.0, 2),
            ([9.0, 2.0, 1.0], 80.0, 3),
            ([12.0, 2.0, 1.0], 5.0, 4),
            ([30.0, 2.0, 1.0], 5.0, 5),
        ]);
        let mesh = mesh(&m, 1.0, [0.0; 3]).expect("a blob");
        let r = mesh.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        let u = crate::measure::union::measure_morphology(&m);
        let (ea, ev) = (mesh.area() / u.area - 1.0, mesh.volume() / u.volume - 1.0);
        assert!(
            ea.abs() < 0.01 && ev.abs() < 0.01,
            "area {ea:+.4}, volume {ev:+.4}"
        );
    }

    #[test]
    fn radius_codes_off_the_centre_mesh_as_the_star_hull() {
        // The swollen chain with a side branch whose balls miss the largest
        // ball's centre (117 and 157 from it, radius 60): not star-shaped
        // about it, but nearly.
        let rows = [
            ([0.0, 0.0, 0.0], 40.0, -1),
            ([3.0, 0.0, 0.0], 100.0, 1),
            ([6.0, 1.0, 0.0], 100.0, 2),
            ([9.0, 2.0, 1.0], 80.0, 3),
            ([12.0, 2.0, 1.0], 90.0, 4),
            ([15.0, 2.0, 1.0], 90.0, 5),
            ([120.0, 0.0, 0.0], 60.0, 6),
            ([160.0, 10.0, 0.0], 60.0, 7),
        ];
        let m = cell(&rows);
        let hull = mesh(&m, 1.0, [0.0; 3]).expect("a nearly star-shaped blob");
        let r = hull.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.components, 1);
        // The hull holds the union and here fills only the waist between
        // the side ball and the rest.
        let u = crate::measure::union::measure_morphology(&m);
        let ev = hull.volume() / u.volume - 1.0;
        assert!((-0.01..0.05).contains(&ev), "volume {ev:+.4}");
        // The same shape with radii a hundred times smaller, below the
        // segments' lengths: its thin cones miss the centre, and it goes
        // the usual way.
        let small = cell(&rows.map(|(p, r, parent)| (p, r / 100.0, parent)));
        assert!(mesh(&small, 1.0, [0.0; 3]).is_none());
    }

    #[test]
    fn a_capsule_seen_from_one_end_is_not_a_blob() {
        // One of its two cones misses the end sphere's centre (half of
        // them), but it reaches 21 radii away: the tubes mesh it.
        let m = cell(&[
            ([0.0; 3], 1.0, -1),
            ([10.0, 0.0, 0.0], 1.0, 1),
            ([20.0, 0.0, 0.0], 1.0, 2),
        ]);
        assert!(mesh(&m, 1.0, [0.0; 3]).is_none());
    }

    #[test]
    fn ordinary_cells_and_somas_are_not_blobs() {
        // A tip far from the largest ball.
        let m = cell(&[
            ([0.0, 0.0, 0.0], 2.0, -1),
            ([10.0, 0.0, 0.0], 1.0, 1),
            ([20.0, 0.0, 0.0], 1.0, 2),
        ]);
        assert!(find(&m, 1.0, [0.0; 3]).is_none());
        // A soma with a short neurite inside it: the soma's construction.
        let m = cell_of_types(&[1, 3], &[([0.0; 3], 5.0, -1), ([1.0, 0.0, 0.0], 0.5, 1)]);
        assert!(find(&m, 1.0, [0.0; 3]).is_none());
    }
}
