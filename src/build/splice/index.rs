//! A dynamic spatial index over the triangles of a [`Surface`].
//!
//! Splicing edits the surface (it removes the region Q and adds a bridge) and
//! keeps asking local questions: which triangle does this ray hit first, which
//! triangles lie near this bridge. A static BVH would have to be rebuilt after
//! every junction; a uniform grid fails when triangle sizes span three orders of
//! magnitude (a 0.05 µm axon beside a 10 µm trunk). This is a *multi-level* grid:
//! level L has cells of `base · 2^L`, and a triangle lives in the finest level
//! whose cells are at least as large as its box, so it touches at most eight
//! cells. Each level also keeps an occupancy pyramid (which cells 8, 64 and 512
//! times coarser hold anything), so a query over a large, mostly empty box
//! descends only into occupied regions instead of probing every fine cell.
//! Removal is lazy: dead triangles stay in the cells and callers skip them.
//!
//! The grid holds *items*, runs of consecutive triangle indices. The surface
//! is built band by band, so `CHUNK` consecutive triangles lie side by side;
//! indexing them as one box makes building the index over a whole cell 10-20x
//! cheaper (it was a third of the mesh time) for a small cost per query, which
//! tests each triangle of a visited run against the query box. Triangles added
//! later are items of one.

use glam::DVec3;

use crate::build::surface::Surface;
use crate::kernel::bvh::Aabb;
use crate::kernel::hash::FastMap;

/// Coarsening steps of the occupancy pyramid (each 8× per axis).
const PYRAMID: usize = 3;
/// A query enumerates at most about this many cells at any one scale.
const CELL_BUDGET: i64 = 512;
/// Consecutive triangles indexed as one item when the grid is built.
const CHUNK: u32 = 16;

/// One level of the grid: its cells and the occupancy of coarser cells.
#[derive(Debug, Clone, Default)]
struct Level {
    cells: FastMap<[i64; 3], Vec<u32>>,
    /// `occupied[s]` maps each cell of scale 8^(s+1) that contains any cell to
    /// its occupied children of scale 8^s, so a descent visits only those
    /// (probing all 512 children of a coarse cell was a fifth of the time
    /// of meshing an EM skeleton, medulla L1).
    occupied: [FastMap<[i64; 3], Vec<[i64; 3]>>; PYRAMID],
}

/// Triangles bucketed by position and size; see the module docs.
#[derive(Debug, Clone)]
pub struct TriangleGrid {
    base: f64,
    levels: Vec<Level>,
    /// Item `i` is the triangles `items[i][0]..items[i][1]`.
    items: Vec<[u32; 2]>,
    /// The box of each item's triangles (when the item was added).
    boxes: Vec<Aabb>,
    /// Per item: the query that last visited it.
    stamp: Vec<u32>,
    epoch: u32,
}

fn coarser(key: [i64; 3], scale: usize) -> [i64; 3] {
    let d = 1i64 << (3 * scale);
    key.map(|k| k.div_euclid(d))
}

impl TriangleGrid {
    /// An index over every triangle of `surface`, with the base cell from the
    /// median triangle size.
    #[cfg(test)]
    pub fn new(surface: &Surface) -> TriangleGrid {
        Self::new_where(surface, |_| true)
    }

    /// An index over the live triangles of `surface` whose boxes `keep`
    /// accepts (later insertions are not filtered).
    pub fn new_where(surface: &Surface, keep: impl Fn(&Aabb) -> bool) -> TriangleGrid {
        let mut sizes: Vec<f64> = (0..surface.tris.len())
            .step_by(1 + surface.tris.len() / 4096)
            .map(|t| extent(&tri_box(surface, t as u32)))
            .collect();
        sizes.sort_by(f64::total_cmp);
        let base = sizes
            .get(sizes.len() / 2)
            .copied()
            .unwrap_or(1.0)
            .max(1e-300);
        let mut g = TriangleGrid {
            base,
            levels: Vec::new(),
            items: Vec::new(),
            boxes: Vec::new(),
            stamp: Vec::new(),
            epoch: 0,
        };
        let n = surface.tris.len() as u32;
        for first in (0..n).step_by(CHUNK as usize) {
            let end = (first + CHUNK).min(n);
            let Some(b) = (first..end)
                .filter(|&t| surface.alive[t as usize])
                .map(|t| tri_box(surface, t))
                .reduce(|mut a, b| {
                    a.add(&b);
                    a
                })
            else {
                continue;
            };
            if keep(&b) {
                g.add_item(first, end, &b);
            }
        }
        g
    }

    fn level_of(&self, b: &Aabb) -> usize {
        let e = extent(b);
        let mut level = 0;
        let mut cell = self.base;
        while cell < e && level < 60 {
            cell *= 2.0;
            level += 1;
        }
        level
    }

    fn cell_size(&self, level: usize) -> f64 {
        self.base * (1u64 << level.min(62)) as f64
    }

    fn cell_range(&self, b: &Aabb, level: usize) -> ([i64; 3], [i64; 3]) {
        let c = self.cell_size(level);
        let lo = b.lo.map(|v| (v / c).floor() as i64);
        let hi = b.hi.map(|v| (v / c).floor() as i64);
        (lo, hi)
    }

    /// Adds triangle `t` of `surface`.
    pub fn insert(&mut self, surface: &Surface, t: u32) {
        self.add_item(t, t + 1, &tri_box(surface, t));
    }

    fn add_item(&mut self, first: u32, end: u32, b: &Aabb) {
        let item = self.items.len() as u32;
        self.items.push([first, end]);
        self.boxes.push(*b);
        self.stamp.push(0);
        let level = self.level_of(b);
        while self.levels.len() <= level {
            self.levels.push(Level::default());
        }
        let (lo, hi) = self.cell_range(b, level);
        let lv = &mut self.levels[level];
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let key = [x, y, z];
                    let cell = lv.cells.entry(key).or_default();
                    if cell.is_empty() {
                        // Register the new cell with its parent, and a new
                        // parent with its own, up the pyramid.
                        for s in 0..PYRAMID {
                            let children = lv.occupied[s].entry(coarser(key, s + 1)).or_default();
                            let child = coarser(key, s);
                            let fresh = children.is_empty();
                            children.push(child);
                            if !fresh {
                                break;
                            }
                        }
                    }
                    cell.push(item);
                }
            }
        }
    }

    /// Calls `f` once with every live triangle whose box overlaps `query`.
    pub fn for_each_near(&mut self, surface: &Surface, query: &Aabb, mut f: impl FnMut(u32)) {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        let epoch = self.epoch;
        let (items, boxes) = (&self.items, &self.boxes);
        let mut visit = |item: u32, stamp: &mut Vec<u32>| {
            let slot = &mut stamp[item as usize];
            if *slot == epoch {
                return;
            }
            *slot = epoch;
            let b = &boxes[item as usize];
            if !b.overlaps(query) {
                return;
            }
            // A run wholly inside the query needs no test per triangle.
            let all = query.contains(b);
            let [first, end] = items[item as usize];
            for t in first..end {
                if surface.alive[t as usize] && (all || tri_box(surface, t).overlaps(query)) {
                    f(t);
                }
            }
        };
        let mut keys: Vec<[i64; 3]> = Vec::new();
        for level in 0..self.levels.len() {
            let (lo, hi) = self.cell_range(query, level);
            keys.clear();
            occupied_cells(&self.levels[level], lo, hi, &mut keys);
            for key in &keys {
                if let Some(ts) = self.levels[level].cells.get(key) {
                    for &t in ts {
                        visit(t, &mut self.stamp);
                    }
                }
            }
        }
    }

    /// The first live triangle hit by the ray `origin + s·dir`, 0 ≤ s ≤ `max`,
    /// among those `accept` allows: `(triangle, s)`.
    pub fn raycast(
        &mut self,
        surface: &Surface,
        origin: DVec3,
        dir: DVec3,
        max: f64,
        accept: impl Fn(u32) -> bool,
    ) -> Option<(u32, f64)> {
        let end = origin + dir * max;
        let query = Aabb {
            lo: origin.min(end).to_array(),
            hi: origin.max(end).to_array(),
        };
        let mut best: Option<(u32, f64)> = None;
        self.for_each_near(surface, &query, |t| {
            if !accept(t) {
                return;
            }
            let tri = surface.corners(t);
            if let Some(s) =
                crate::kernel::predicates::ray_triangle(origin.to_array(), dir.to_array(), tri)
                && s <= max
                && best.is_none_or(|(_, b)| s < b)
            {
                best = Some((t, s));
            }
        });
        best
    }
}

/// The occupied cells of `level` within the cell range `lo..=hi`, found by
/// descending the occupancy pyramid from the finest scale whose cells under
/// the range number at most [`CELL_BUDGET`].
fn occupied_cells(level: &Level, lo: [i64; 3], hi: [i64; 3], out: &mut Vec<[i64; 3]>) {
    let count = |lo: [i64; 3], hi: [i64; 3]| -> i64 {
        (0..3)
            .map(|a| (hi[a] - lo[a] + 1).max(0))
            .fold(1i64, |acc, n| acc.saturating_mul(n))
    };
    let mut scale = 0;
    while scale < PYRAMID && count(coarser(lo, scale), coarser(hi, scale)) > CELL_BUDGET {
        scale += 1;
    }
    // Candidate cells at `scale`, then refined down to the fine cells.
    let mut cands: Vec<[i64; 3]> = Vec::new();
    let (clo, chi) = (coarser(lo, scale), coarser(hi, scale));
    for x in clo[0]..=chi[0] {
        for y in clo[1]..=chi[1] {
            for z in clo[2]..=chi[2] {
                let key = [x, y, z];
                let present = if scale == 0 {
                    level.cells.contains_key(&key)
                } else {
                    level.occupied[scale - 1].contains_key(&key)
                };
                if present {
                    cands.push(key);
                }
            }
        }
    }
    while scale > 0 {
        scale -= 1;
        let (flo, fhi) = (coarser(lo, scale), coarser(hi, scale));
        let within = |k: &[i64; 3]| (0..3).all(|a| k[a] >= flo[a] && k[a] <= fhi[a]);
        let next: Vec<[i64; 3]> = cands
            .iter()
            .filter_map(|c| level.occupied[scale].get(c))
            .flatten()
            .filter(|k| within(k))
            .copied()
            .collect();
        cands = next;
    }
    out.extend(cands);
}

/// Box of triangle `t`.
pub fn tri_box(surface: &Surface, t: u32) -> Aabb {
    Aabb::of(&surface.corners(t))
}

fn extent(b: &Aabb) -> f64 {
    (0..3).map(|a| b.hi[a] - b.lo[a]).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup() -> Surface {
        // Triangles of sizes 0.01 to 100 along the x axis.
        let mut s = Surface::default();
        for i in 0..40 {
            let size = 0.01 * 1.3f64.powi(i);
            let x = f64::from(i) * 3.0;
            let a = s.vertex(DVec3::new(x, 0.0, 0.0), 0);
            let b = s.vertex(DVec3::new(x + size, 0.0, 0.0), 0);
            let c = s.vertex(DVec3::new(x, size, 0.0), 0);
            s.triangle(a, b, c);
        }
        s
    }

    #[test]
    fn near_finds_what_brute_force_finds() {
        let s = soup();
        let mut g = TriangleGrid::new(&s);
        for (lo, hi) in [
            ([-1.0, -1.0, -1.0], [5.0, 1.0, 1.0]),
            ([50.0, 0.0, -1.0], [70.0, 80.0, 1.0]),
        ] {
            let q = Aabb { lo, hi };
            let mut got = Vec::new();
            g.for_each_near(&s, &q, |t| got.push(t));
            got.sort_unstable();
            let want: Vec<u32> = (0..s.tris.len() as u32)
                .filter(|&t| tri_box(&s, t).overlaps(&q))
                .collect();
            assert_eq!(got, want);
        }
    }

    #[test]
    fn dead_triangles_are_skipped_and_rays_hit_the_nearest() {
        let mut s = Surface::default();
        for z in [1.0, 2.0] {
            let a = s.vertex(DVec3::new(-1.0, -1.0, z), 0);
            let b = s.vertex(DVec3::new(1.0, -1.0, z), 0);
            let c = s.vertex(DVec3::new(0.0, 1.0, z), 0);
            s.triangle(a, b, c);
        }
        let mut g = TriangleGrid::new(&s);
        let hit = g.raycast(&s, DVec3::ZERO, DVec3::Z, 10.0, |_| true);
        assert_eq!(hit.map(|h| h.0), Some(0));
        s.alive[0] = false;
        let hit = g.raycast(&s, DVec3::ZERO, DVec3::Z, 10.0, |_| true);
        assert_eq!(hit.map(|h| h.0), Some(1));
        assert!(
            g.raycast(&s, DVec3::ZERO, DVec3::Z, 1.5, |_| true)
                .is_none()
        );
    }
}
