//! A bounding-volume hierarchy over axis-aligned boxes.
//!
//! Used by the self-intersection check (a million triangles in about a second)
//! and by the junction builder to find the triangles near a branch point. It is
//! a plain binary tree split at the median of the longest axis of the box
//! centres: cheap to build, good enough for the well-spread triangles of a tube
//! mesh, and free of any per-query allocation.

/// An axis-aligned box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Upper corner.
    pub hi: [f64; 3],
}

impl Aabb {
    /// The empty box (grows to the first point added).
    pub const EMPTY: Aabb = Aabb {
        lo: [f64::INFINITY; 3],
        hi: [f64::NEG_INFINITY; 3],
    };

    /// The smallest box holding `points`.
    pub fn of(points: &[[f64; 3]]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.add_point(*p);
        }
        b
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn add_point(&mut self, p: [f64; 3]) {
        // Plain comparisons compile to one min or max instruction each
        // (coordinates are never NaN); `f64::min` adds NaN handling, which
        // made box building a visible share of the overlap pass.
        for a in 0..3 {
            self.lo[a] = if p[a] < self.lo[a] { p[a] } else { self.lo[a] };
            self.hi[a] = if p[a] > self.hi[a] { p[a] } else { self.hi[a] };
        }
    }

    /// Grows the box to hold `o`.
    #[inline]
    pub fn add(&mut self, o: &Aabb) {
        for a in 0..3 {
            self.lo[a] = if o.lo[a] < self.lo[a] {
                o.lo[a]
            } else {
                self.lo[a]
            };
            self.hi[a] = if o.hi[a] > self.hi[a] {
                o.hi[a]
            } else {
                self.hi[a]
            };
        }
    }

    /// The box grown by `margin` on every side.
    #[inline]
    pub fn inflated(&self, margin: f64) -> Aabb {
        Aabb {
            lo: [
                self.lo[0] - margin,
                self.lo[1] - margin,
                self.lo[2] - margin,
            ],
            hi: [
                self.hi[0] + margin,
                self.hi[1] + margin,
                self.hi[2] + margin,
            ],
        }
    }

    /// Whether `o` lies wholly inside this box.
    #[inline]
    pub fn contains(&self, o: &Aabb) -> bool {
        (0..3).all(|a| self.lo[a] <= o.lo[a] && o.hi[a] <= self.hi[a])
    }

    /// Whether the closed box holds point `p`.
    #[inline]
    pub fn holds_point(&self, p: [f64; 3]) -> bool {
        (0..3).all(|a| self.lo[a] <= p[a] && p[a] <= self.hi[a])
    }

    /// Whether the closed boxes overlap.
    #[inline]
    pub fn overlaps(&self, o: &Aabb) -> bool {
        self.lo[0] <= o.hi[0]
            && o.lo[0] <= self.hi[0]
            && self.lo[1] <= o.hi[1]
            && o.lo[1] <= self.hi[1]
            && self.lo[2] <= o.hi[2]
            && o.lo[2] <= self.hi[2]
    }

    /// Whether a ray `origin + t·dir`, t in [0, t_max], can meet the box.
    #[inline]
    pub fn hit_by_ray(&self, origin: [f64; 3], inv_dir: [f64; 3], t_max: f64) -> bool {
        let mut t0 = 0.0f64;
        let mut t1 = t_max;
        for a in 0..3 {
            let mut near = (self.lo[a] - origin[a]) * inv_dir[a];
            let mut far = (self.hi[a] - origin[a]) * inv_dir[a];
            if near > far {
                std::mem::swap(&mut near, &mut far);
            }
            // NaN from 0·∞ (ray parallel to a face plane, origin on it) keeps the box.
            if near.is_nan() || far.is_nan() {
                continue;
            }
            t0 = t0.max(near);
            t1 = t1.min(far);
            if t0 > t1 {
                return false;
            }
        }
        true
    }

    fn center(&self, a: usize) -> f64 {
        0.5 * (self.lo[a] + self.hi[a])
    }
}

#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    /// Leaf: first item; inner: index of the left child (the right one follows it).
    start: u32,
    /// Leaf: number of items (> 0); inner: 0.
    count: u32,
}

/// A static BVH over item boxes; items are reported by their index in the input.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
    boxes: Vec<Aabb>,
}

const LEAF_SIZE: usize = 4;

impl Bvh {
    /// Builds the hierarchy over `boxes`.
    pub fn new(boxes: Vec<Aabb>) -> Bvh {
        let mut nodes = Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1);
        if boxes.is_empty() {
            return Bvh {
                nodes,
                items: Vec::new(),
                boxes,
            };
        }
        nodes.push(Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: boxes.len() as u32,
        });
        // Each item's centre beside its number, split in place: every level
        // reads them in order rather than through the item numbers. The
        // splits are those the numbers alone would give (the same
        // comparisons in the same order), so the tree is the same; the
        // bounds are filled bottom up once, by `refit`, rather than by a
        // pass over every node's items.
        let mut work: Vec<([f64; 3], u32)> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| ([b.center(0), b.center(1), b.center(2)], i as u32))
            .collect();
        let mut stack = vec![0usize];
        while let Some(ni) = stack.pop() {
            let (start, count) = (nodes[ni].start as usize, nodes[ni].count as usize);
            if count <= LEAF_SIZE {
                continue;
            }
            let slice = &mut work[start..start + count];
            let mut centers = Aabb::EMPTY;
            for (c, _) in slice.iter() {
                centers.add_point(*c);
            }
            let ext = [
                centers.hi[0] - centers.lo[0],
                centers.hi[1] - centers.lo[1],
                centers.hi[2] - centers.lo[2],
            ];
            let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
                0
            } else if ext[1] >= ext[2] {
                1
            } else {
                2
            };
            let mid = count / 2;
            slice.select_nth_unstable_by(mid, |a, b| a.0[axis].total_cmp(&b.0[axis]));
            let left = nodes.len();
            nodes.push(Node {
                bounds: Aabb::EMPTY,
                start: start as u32,
                count: mid as u32,
            });
            nodes.push(Node {
                bounds: Aabb::EMPTY,
                start: (start + mid) as u32,
                count: (count - mid) as u32,
            });
            nodes[ni].start = left as u32;
            nodes[ni].count = 0;
            stack.push(left);
            stack.push(left + 1);
        }
        let mut bvh = Bvh {
            nodes,
            items: work.into_iter().map(|(_, i)| i).collect(),
            boxes,
        };
        bvh.refit();
        bvh
    }

    /// Grows item `i`'s box to hold `p`. The nodes above it keep their
    /// bounds until [`Bvh::refit`]: call it before the next query.
    pub fn grow_item(&mut self, i: u32, p: [f64; 3]) {
        self.boxes[i as usize].add_point(p);
    }

    /// Sets every node's bounds from its items' boxes, bottom up: a node's
    /// children come after it in `nodes`, so one backward pass does it. A
    /// tree refitted after its items moved a little answers every query
    /// exactly, only a little slower than a new one, for a fraction of the
    /// cost of building it.
    pub fn refit(&mut self) {
        for ni in (0..self.nodes.len()).rev() {
            let Node { start, count, .. } = self.nodes[ni];
            let mut bounds = Aabb::EMPTY;
            if count > 0 {
                for &i in &self.items[start as usize..(start + count) as usize] {
                    bounds.add(&self.boxes[i as usize]);
                }
            } else {
                bounds = self.nodes[start as usize].bounds;
                bounds.add(&self.nodes[start as usize + 1].bounds);
            }
            self.nodes[ni].bounds = bounds;
        }
    }

    /// The box of item `i`.
    pub fn item_box(&self, i: u32) -> &Aabb {
        &self.boxes[i as usize]
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// Whether the hierarchy holds no items.
    #[cfg(any(test, feature = "internals"))]
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Calls `f` with every item whose box overlaps `query`.
    pub fn for_each_overlap(&self, query: &Aabb, f: impl FnMut(u32)) {
        self.for_each_where(|b| b.overlaps(query), f);
    }

    /// Calls `f` with every item whose box contains `query`.
    pub fn for_each_containing(&self, query: &Aabb, f: impl FnMut(u32)) {
        self.for_each_where(|b| b.contains(query), f);
    }

    /// Calls `f` with every item whose box passes `test`, where a box that
    /// fails it has no sub-box that passes (overlap or containment of a
    /// query box).
    fn for_each_where(&self, test: impl Fn(&Aabb) -> bool, mut f: impl FnMut(u32)) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; 64];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !test(&node.bounds) {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                for &i in &self.items[s..s + node.count as usize] {
                    if test(&self.boxes[i as usize]) {
                        f(i);
                    }
                }
            } else if top + 2 <= stack.len() {
                stack[top] = node.start;
                stack[top + 1] = node.start + 1;
                top += 2;
            }
        }
    }

    /// Calls `f` with every item whose box the ray segment can meet (each
    /// item's own box is tested: an item can be a run of many triangles).
    pub fn for_each_on_ray(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_max: f64,
        mut f: impl FnMut(u32),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = [1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]];
        let mut stack = [0u32; 64];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !node.bounds.hit_by_ray(origin, inv, t_max) {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                for &i in &self.items[s..s + node.count as usize] {
                    if self.boxes[i as usize].hit_by_ray(origin, inv, t_max) {
                        f(i);
                    }
                }
            } else if top + 2 <= stack.len() {
                stack[top] = node.start;
                stack[top + 1] = node.start + 1;
                top += 2;
            }
        }
    }
}

impl Bvh {
    /// All pairs of distinct items whose boxes overlap and for which `keep`
    /// returns true, as `[smaller, larger]`, sorted.
    ///
    /// A simultaneous descent of the tree against itself visits every
    /// overlapping pair of nodes once, which is far cheaper than one query per
    /// item. The top of the descent is split into independent tasks that run in
    /// parallel when the `parallel` feature is on; the result does not depend on
    /// the number of threads.
    pub fn overlapping_pairs(
        &self,
        keep: impl Fn(u32, u32) -> bool + Sync + Send,
    ) -> Vec<[u32; 2]> {
        if self.nodes.is_empty() {
            return Vec::new();
        }
        // Expand the root pair breadth-first into enough independent tasks.
        let mut tasks: Vec<(u32, u32)> = vec![(0, 0)];
        let mut leaves: Vec<(u32, u32)> = Vec::new();
        while !tasks.is_empty() && tasks.len() < 512 {
            let mut next = Vec::with_capacity(tasks.len() * 3);
            for (a, b) in tasks {
                self.expand(a, b, &mut next, &mut leaves);
            }
            tasks = next;
        }
        tasks.extend(leaves);
        let mut pairs = crate::kernel::parallel::flat_map_range(tasks.len(), |t| {
            let mut out = Vec::new();
            let mut stack = vec![tasks[t]];
            let mut scratch = Vec::new();
            while let Some((a, b)) = stack.pop() {
                scratch.clear();
                let na = &self.nodes[a as usize];
                let nb = &self.nodes[b as usize];
                if na.count > 0 && nb.count > 0 {
                    self.leaf_pairs(a, b, &keep, &mut out);
                    continue;
                }
                self.expand(a, b, &mut scratch, &mut Vec::new());
                stack.extend_from_slice(&scratch);
            }
            out
        });
        pairs.sort_unstable();
        pairs
    }

    /// Pushes the child pairs of node pair (a, b) that may hold overlaps; a pair
    /// of two leaves goes to `leaves` instead.
    fn expand(&self, a: u32, b: u32, out: &mut Vec<(u32, u32)>, leaves: &mut Vec<(u32, u32)>) {
        let na = &self.nodes[a as usize];
        let nb = &self.nodes[b as usize];
        if a != b && !na.bounds.overlaps(&nb.bounds) {
            return;
        }
        match (na.count > 0, nb.count > 0) {
            (true, true) => leaves.push((a, b)),
            _ if a == b => {
                let (l, r) = (na.start, na.start + 1);
                out.push((l, l));
                out.push((r, r));
                out.push((l, r));
            }
            (false, leaf_b) => {
                // Descend the inner node (the larger one when both are inner).
                let volume = |n: &Node| {
                    let e = [
                        n.bounds.hi[0] - n.bounds.lo[0],
                        n.bounds.hi[1] - n.bounds.lo[1],
                        n.bounds.hi[2] - n.bounds.lo[2],
                    ];
                    e[0] * e[1] * e[2]
                };
                if leaf_b || volume(na) >= volume(nb) {
                    out.push((na.start, b));
                    out.push((na.start + 1, b));
                } else {
                    out.push((a, nb.start));
                    out.push((a, nb.start + 1));
                }
            }
            (true, false) => {
                out.push((a, nb.start));
                out.push((a, nb.start + 1));
            }
        }
    }

    fn leaf_pairs(
        &self,
        a: u32,
        b: u32,
        keep: &impl Fn(u32, u32) -> bool,
        out: &mut Vec<[u32; 2]>,
    ) {
        let na = &self.nodes[a as usize];
        let nb = &self.nodes[b as usize];
        let ia = &self.items[na.start as usize..(na.start + na.count) as usize];
        let ib = &self.items[nb.start as usize..(nb.start + nb.count) as usize];
        for (x, &i) in ia.iter().enumerate() {
            // Within one leaf, each unordered pair once.
            let from = if a == b { x + 1 } else { 0 };
            for &j in &ib[from..] {
                if self.boxes[i as usize].overlaps(&self.boxes[j as usize])
                    && keep(i.min(j), i.max(j))
                {
                    out.push([i.min(j), i.max(j)]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(x: f64) -> Aabb {
        Aabb {
            lo: [x, 0.0, 0.0],
            hi: [x + 1.0, 1.0, 1.0],
        }
    }

    /// `n` cubes of mixed sizes (0.5 to 0.5 + `sizes`) scattered over a
    /// `span` × 20 × 9 region.
    fn jumble(n: u32, span: f64, sizes: f64) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let f = f64::from(i);
                let (x, y, z) = ((f * 7.3) % span, (f * 3.1) % 20.0, (f * 1.7) % 9.0);
                let s = 0.5 + (f * 0.37) % sizes;
                Aabb {
                    lo: [x, y, z],
                    hi: [x + s, y + s, z + s],
                }
            })
            .collect()
    }

    #[test]
    fn finds_exactly_the_overlapping_boxes() {
        let boxes: Vec<Aabb> = (0..1000).map(|i| unit_box(f64::from(i) * 2.0)).collect();
        let bvh = Bvh::new(boxes.clone());
        let q = Aabb {
            lo: [10.5, 0.5, 0.5],
            hi: [14.2, 0.6, 0.6],
        };
        let mut found = Vec::new();
        bvh.for_each_overlap(&q, |i| found.push(i));
        found.sort_unstable();
        let expect: Vec<u32> = (0..1000u32)
            .filter(|&i| boxes[i as usize].overlaps(&q))
            .collect();
        assert_eq!(found, expect);
        assert_eq!(found, vec![5, 6, 7]);
    }

    #[test]
    fn self_pairs_match_brute_force() {
        let boxes = jumble(600, 50.0, 3.0);
        let bvh = Bvh::new(boxes.clone());
        let got = bvh.overlapping_pairs(|i, j| (i + j) % 3 != 0);
        let mut want = Vec::new();
        for i in 0..boxes.len() as u32 {
            for j in i + 1..boxes.len() as u32 {
                if boxes[i as usize].overlaps(&boxes[j as usize]) && (i + j) % 3 != 0 {
                    want.push([i, j]);
                }
            }
        }
        assert_eq!(got, want);
    }

    #[test]
    fn finds_exactly_the_containing_boxes() {
        // Sizes up to 12.5 in a 30-wide span: many boxes nest.
        let boxes = jumble(400, 30.0, 12.0);
        let bvh = Bvh::new(boxes.clone());
        let mut total = 0;
        for q in &boxes {
            let mut got = Vec::new();
            bvh.for_each_containing(q, |i| got.push(i));
            got.sort_unstable();
            let want: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].contains(q))
                .collect();
            assert_eq!(got, want);
            total += want.len();
        }
        // Each box holds itself; some hold others too.
        assert!(total > boxes.len(), "{total}");
        assert!(boxes[0].holds_point(boxes[0].lo) && !boxes[0].holds_point([-1.0, 0.0, 0.0]));
    }

    #[test]
    fn grown_and_refitted_tree_answers_like_a_new_one() {
        let mut boxes = jumble(500, 40.0, 3.0);
        let mut bvh = Bvh::new(boxes.clone());
        // Grow every seventh box towards a far corner and another inward.
        for i in (0..boxes.len() as u32).step_by(7) {
            let f = f64::from(i);
            for p in [[45.0 - f % 5.0, 1.0, 30.0], [f % 11.0, 25.0, -3.0]] {
                boxes[i as usize].add_point(p);
                bvh.grow_item(i, p);
            }
        }
        bvh.refit();
        let fresh = Bvh::new(boxes.clone());
        for q in jumble(60, 50.0, 8.0) {
            let (mut got, mut want) = (Vec::new(), Vec::new());
            bvh.for_each_overlap(&q, |i| got.push(i));
            fresh.for_each_overlap(&q, |i| want.push(i));
            got.sort_unstable();
            want.sort_unstable();
            let brute: Vec<u32> = (0..boxes.len() as u32)
                .filter(|&i| boxes[i as usize].overlaps(&q))
                .collect();
            assert_eq!(got, brute);
            assert_eq!(want, brute);
        }
        // The grown boxes reach the far corner: a query there finds them.
        let corner = Aabb {
            lo: [44.0, 0.5, 29.5],
            hi: [45.5, 1.5, 30.5],
        };
        let mut far = Vec::new();
        bvh.for_each_overlap(&corner, |i| far.push(i));
        assert!(!far.is_empty() && far.iter().all(|i| i % 7 == 0), "{far:?}");
    }

    #[test]
    fn ray_visits_boxes_along_it() {
        let boxes: Vec<Aabb> = (0..100).map(|i| unit_box(f64::from(i) * 2.0)).collect();
        let bvh = Bvh::new(boxes);
        let mut found = Vec::new();
        bvh.for_each_on_ray([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0], 6.0, |i| found.push(i));
        found.sort_unstable();
        assert_eq!(found, vec![0, 1, 2]);
    }
}
