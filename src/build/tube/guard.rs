//! The guard that keeps a tube piece from crossing itself: every band (and
//! every cap) is checked against the earlier bands of its piece before it is
//! kept.
//!
//! * A band lies on or behind the plane of its end contour (the disc of its
//!   start contour clears that plane). A new band wholly in front of an older
//!   band's end plane cannot meet it; that settles nearly every pair at once.
//! * Otherwise, if the two bands' capsules (segment between centres, largest
//!   radius) are apart, they cannot meet either: every band triangle lies in
//!   its capsule.
//! * Otherwise the triangles are tested exactly ([`crate::kernel::predicates`]).
//!
//! Neighbours that share a contour are never compared: they meet only on that
//! contour's plane, along its edges.

use std::ops::Range;

use glam::DVec3;

use crate::build::surface::Surface;
use crate::build::tube::Ring;
use crate::kernel::hash::FastMap;
use crate::kernel::predicates;

/// A disc: centre, unit normal, radius.
#[derive(Debug, Clone, Copy)]
struct Disc {
    center: DVec3,
    normal: DVec3,
    radius: f64,
}

impl Disc {
    /// Smallest signed distance of the disc to the plane (c, n).
    fn lowest_above(&self, c: DVec3, n: DVec3) -> f64 {
        let cos = self.normal.dot(n).clamp(-1.0, 1.0);
        (self.center - c).dot(n) - self.radius * (1.0 - cos * cos).sqrt()
    }
}

/// What the guard knows about a band or a cap.
#[derive(Debug, Clone)]
pub(super) struct Part {
    /// The part lies on or behind this plane (centre, normal).
    end: (DVec3, DVec3),
    /// Two discs whose convex hull holds the part.
    hull: [Disc; 2],
    /// Capsule: segment and radius holding the part.
    capsule: (DVec3, DVec3, f64),
    /// Its triangles in the surface.
    tris: Range<u32>,
}

impl Part {
    pub(super) fn band(a: &Ring, b: &Ring, tris: Range<u32>) -> Part {
        let disc = |r: &Ring| Disc {
            center: r.center,
            normal: r.normal,
            radius: r.radius,
        };
        Part {
            end: (b.center, b.normal),
            hull: [disc(a), disc(b)],
            capsule: (a.center, b.center, a.radius.max(b.radius)),
            tris,
        }
    }

    /// A dome on `ring`, forward or backward, of height `h` (≥ the cap's).
    pub(super) fn cap(ring: &Ring, forward: bool, h: f64, tris: Range<u32>) -> Part {
        let dir = if forward { ring.normal } else { -ring.normal };
        let top = ring.center + dir * h;
        let base = Disc {
            center: ring.center,
            normal: ring.normal,
            radius: h,
        };
        Part {
            end: (top, dir),
            hull: [
                base,
                Disc {
                    center: top,
                    ..base
                },
            ],
            capsule: (ring.center, top, h),
            tris,
        }
    }

    fn in_front_of(&self, plane: (DVec3, DVec3)) -> bool {
        self.hull
            .iter()
            .all(|d| d.lowest_above(plane.0, plane.1) > 0.0)
    }
}

/// The parts of the piece under construction, in a uniform grid.
pub(super) struct Guard {
    cell: f64,
    grid: FastMap<[i64; 3], Vec<u32>>,
    parts: Vec<Part>,
    seen: Vec<u32>,
    epoch: u32,
}

impl Guard {
    pub(super) fn new(cell: f64) -> Guard {
        Guard {
            cell,
            grid: FastMap::default(),
            parts: Vec::new(),
            seen: Vec::new(),
            epoch: 0,
        }
    }

    fn cells(&self, p: &Part) -> impl Iterator<Item = [i64; 3]> + use<> {
        let (a, b, r) = p.capsule;
        let lo = ((a.min(b) - DVec3::splat(r)) / self.cell)
            .floor()
            .as_i64vec3();
        let hi = ((a.max(b) + DVec3::splat(r)) / self.cell)
            .floor()
            .as_i64vec3();
        (lo.x..=hi.x).flat_map(move |x| {
            (lo.y..=hi.y).flat_map(move |y| (lo.z..=hi.z).map(move |z| [x, y, z]))
        })
    }

    pub(super) fn add(&mut self, p: Part) -> u32 {
        let id = self.parts.len() as u32;
        for c in self.cells(&p) {
            self.grid.entry(c).or_default().push(id);
        }
        self.parts.push(p);
        self.seen.push(0);
        id
    }

    /// Removes the most recently added part.
    pub(super) fn pop(&mut self) {
        if let Some(p) = self.parts.pop() {
            let id = self.parts.len() as u32;
            for c in self.cells(&p) {
                if let Some(v) = self.grid.get_mut(&c) {
                    v.retain(|&x| x != id);
                }
            }
            self.seen.pop();
        }
    }

    /// Whether `new` meets any part other than those in `skip`.
    pub(super) fn collides(&mut self, surface: &Surface, new: &Part, skip: &[u32]) -> bool {
        self.epoch += 1;
        let epoch = self.epoch;
        // The new part's triangles and boxes, once for all the parts it is
        // compared with (computed when the first comparison needs them).
        let mut mine: Option<Band> = None;
        for c in self.cells(new) {
            let Some(ids) = self.grid.get(&c) else {
                continue;
            };
            for &id in ids {
                if self.seen[id as usize] == epoch || skip.contains(&id) {
                    continue;
                }
                self.seen[id as usize] = epoch;
                let old = &self.parts[id as usize];
                if new.in_front_of(old.end) {
                    continue;
                }
                let (a, b, r) = new.capsule;
                let (c2, d2, r2) = old.capsule;
                if predicates::segment_distance(a, b, c2, d2) > r + r2 {
                    continue;
                }
                let mine = mine.get_or_insert_with(|| Band::new(surface, new.tris.clone()));
                if mine.meets(surface, old.tris.clone()) {
                    return true;
                }
            }
        }
        false
    }
}

/// A part's triangles with their boxes, and the box of them all.
struct Band {
    tris: Vec<([[f64; 3]; 3], crate::kernel::bvh::Aabb)>,
    bounds: crate::kernel::bvh::Aabb,
}

impl Band {
    fn new(surface: &Surface, tris: Range<u32>) -> Band {
        let tris: Vec<_> = tris
            .map(|t| {
                let t = surface.corners(t);
                (t, crate::kernel::bvh::Aabb::of(&t))
            })
            .collect();
        let mut bounds = crate::kernel::bvh::Aabb::EMPTY;
        for (_, b) in &tris {
            bounds.add(b);
        }
        Band { tris, bounds }
    }

    /// Whether any of triangles `ys` intersects one of the band's.
    fn meets(&self, surface: &Surface, ys: Range<u32>) -> bool {
        ys.into_iter().any(|y| {
            let ty = surface.corners(y);
            let by = crate::kernel::bvh::Aabb::of(&ty);
            by.overlaps(&self.bounds)
                && self
                    .tris
                    .iter()
                    .any(|(tx, bx)| bx.overlaps(&by) && predicates::triangles_intersect(*tx, ty))
        })
    }
}
