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

/// A part whose box spans more grid cells than this is kept out of the grid
/// and compared with every new part (and a new part as large is compared
/// with every part): a band or cap much wider than the piece's median radius
/// (the first band at a soma, a cap on a thick ring) would otherwise cost
/// millions of cell lookups, most of them empty.
const MAX_CELLS: f64 = 512.0;

/// The parts of the piece under construction, in a uniform grid (those
/// wider than [`MAX_CELLS`] cells in a list of their own).
pub(super) struct Guard {
    cell: f64,
    grid: FastMap<[i64; 3], Vec<u32>>,
    large: Vec<u32>,
    /// The candidates of the last [`Guard::collides`], kept for its buffer.
    scratch: Vec<u32>,
    parts: Vec<Part>,
    seen: Vec<u32>,
    epoch: u32,
}

impl Guard {
    pub(super) fn new(cell: f64) -> Guard {
        Guard {
            cell,
            grid: FastMap::default(),
            large: Vec::new(),
            scratch: Vec::new(),
            parts: Vec::new(),
            seen: Vec::new(),
            epoch: 0,
        }
    }

    /// The part's box in cell coordinates: lowest and highest cell.
    fn cell_box(&self, p: &Part) -> ([f64; 3], [f64; 3]) {
        let (a, b, r) = p.capsule;
        let lo = ((a.min(b) - DVec3::splat(r)) / self.cell).floor();
        let hi = ((a.max(b) + DVec3::splat(r)) / self.cell).floor();
        (lo.to_array(), hi.to_array())
    }

    /// Whether the part spans more than [`MAX_CELLS`] cells.
    fn is_large(&self, p: &Part) -> bool {
        let (lo, hi) = self.cell_box(p);
        let count = (0..3).map(|k| hi[k] - lo[k] + 1.0).product::<f64>();
        // NaN (a degenerate part) counts as large: it is compared with all.
        count.is_nan() || count > MAX_CELLS
    }

    fn cells(&self, p: &Part) -> impl Iterator<Item = [i64; 3]> + use<> {
        let (lo, hi) = self.cell_box(p);
        let (lo, hi) = (lo.map(|v| v as i64), hi.map(|v| v as i64));
        (lo[0]..=hi[0]).flat_map(move |x| {
            (lo[1]..=hi[1]).flat_map(move |y| (lo[2]..=hi[2]).map(move |z| [x, y, z]))
        })
    }

    pub(super) fn add(&mut self, p: Part) -> u32 {
        let id = self.parts.len() as u32;
        if self.is_large(&p) {
            self.large.push(id);
        } else {
            for c in self.cells(&p) {
                self.grid.entry(c).or_default().push(id);
            }
        }
        self.parts.push(p);
        self.seen.push(0);
        id
    }

    /// Removes the most recently added part.
    pub(super) fn pop(&mut self) {
        if let Some(p) = self.parts.pop() {
            let id = self.parts.len() as u32;
            if self.large.last() == Some(&id) {
                self.large.pop();
            } else {
                for c in self.cells(&p) {
                    if let Some(v) = self.grid.get_mut(&c) {
                        v.retain(|&x| x != id);
                    }
                }
            }
            self.seen.pop();
        }
    }

    /// The parts `new` may meet, into `out`: all of them when it is large,
    /// else those in its cells and the large ones (with repeats; the caller
    /// skips them).
    fn candidates(&self, new: &Part, out: &mut Vec<u32>) {
        out.clear();
        if self.is_large(new) {
            out.extend(0..self.parts.len() as u32);
            return;
        }
        out.extend_from_slice(&self.large);
        for c in self.cells(new) {
            if let Some(ids) = self.grid.get(&c) {
                out.extend_from_slice(ids);
            }
        }
    }

    /// Whether `new` meets any part other than those in `skip`.
    pub(super) fn collides(&mut self, surface: &Surface, new: &Part, skip: &[u32]) -> bool {
        self.epoch += 1;
        let epoch = self.epoch;
        // The new part's triangles and boxes, once for all the parts it is
        // compared with (computed when the first comparison needs them).
        let mut mine: Option<Band> = None;
        // One buffer for every call: this runs once per band.
        let mut candidates = std::mem::take(&mut self.scratch);
        self.candidates(new, &mut candidates);
        let mut meets = false;
        for &id in &candidates {
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
                meets = true;
                break;
            }
        }
        self.scratch = candidates;
        meets
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
