//! Step 2 of a junction: the region Q grown from the target triangle, and
//! its boundary loop C_Q.

use glam::DVec3;

use super::splicer::Splicer;
use crate::build::splice::index::tri_box;
use crate::build::surface::Surface;
use crate::kernel::bvh::Aabb;

impl Splicer<'_> {
    /// Grows Q from `target`; `None` if it cannot be a disk of live, unlocked,
    /// foreign triangles.
    pub(super) fn grow_region(
        &mut self,
        tube_id: u32,
        target: u32,
        h: DVec3,
        axis: DVec3,
        rho: f64,
    ) -> Option<Vec<u32>> {
        let pad = 2.0 * rho;
        let ext = extent(&tri_box(self.surface, target));
        let query = Aabb::of(&[h.to_array()]).inflated(pad + 2.0 * ext);
        let inside = |t: u32, s: &Surface| -> bool {
            let f = s.tris[t as usize];
            let c = (s.pos[f[0] as usize] + s.pos[f[1] as usize] + s.pos[f[2] as usize]) / 3.0;
            let d = c - h;
            let perp = (d - d.dot(axis) * axis).length();
            perp <= rho && tri_normal(s, t).dot(axis) > 0.1
        };
        // Q only ever grows into `inside` triangles, so only they (and the
        // target) need to be in the local edge → triangles map.
        let mut near: Vec<u32> = vec![target];
        let surface = &*self.surface;
        self.grid.for_each_near(surface, &query, |t| {
            if t != target && inside(t, surface) {
                near.push(t);
            }
        });
        let mut edges: crate::kernel::hash::FastMap<(u32, u32), [u32; 2]> =
            crate::kernel::hash::FastMap::default();
        for &t in &near {
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                let key = (a.min(b), a.max(b));
                let slot = edges.entry(key).or_insert([u32::MAX; 2]);
                if slot[0] == u32::MAX {
                    slot[0] = t;
                } else {
                    slot[1] = t;
                }
            }
        }
        let mut q = vec![target];
        let mut in_q: crate::kernel::hash::FastSet<u32> = crate::kernel::hash::FastSet::default();
        in_q.insert(target);
        let mut head = 0;
        while head < q.len() {
            let t = q[head];
            head += 1;
            let f = self.surface.tris[t as usize];
            for e in 0..3 {
                let (a, b) = (f[e], f[(e + 1) % 3]);
                let Some(pair) = edges.get(&(a.min(b), a.max(b))) else {
                    continue;
                };
                for &n in pair {
                    if n == u32::MAX || in_q.contains(&n) {
                        continue;
                    }
                    if self.reserved[n as usize] || self.owner[n as usize] == tube_id {
                        continue;
                    }
                    in_q.insert(n);
                    q.push(n);
                }
            }
        }
        Some(q)
    }
}

fn extent(b: &Aabb) -> f64 {
    (0..3).map(|a| b.hi[a] - b.lo[a]).fold(0.0, f64::max)
}

pub(super) fn tri_normal(s: &Surface, t: u32) -> DVec3 {
    let f = s.tris[t as usize];
    let (a, b, c) = (
        s.pos[f[0] as usize],
        s.pos[f[1] as usize],
        s.pos[f[2] as usize],
    );
    (b - a).cross(c - a).normalize_or_zero()
}

/// The boundary of a triangle set as one loop of vertices, following the
/// triangles' own edge directions; `None` unless the set is a topological disk
/// (a single simple boundary loop and Euler characteristic 1).
pub fn boundary_loop(s: &Surface, q: &[u32]) -> Option<Vec<u32>> {
    use crate::kernel::hash::FastMap as HashMap;
    let mut directed: HashMap<(u32, u32), u32> = HashMap::default();
    for &t in q {
        let f = s.tris[t as usize];
        for e in 0..3 {
            *directed.entry((f[e], f[(e + 1) % 3])).or_insert(0) += 1;
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::default();
    let mut edges_total = 0usize;
    for (&(a, b), &count) in &directed {
        if count > 1 {
            return None; // two triangles run an edge the same way: not oriented
        }
        if directed.contains_key(&(b, a)) {
            if a < b {
                edges_total += 1;
            }
            continue;
        }
        edges_total += 1;
        if next.insert(a, b).is_some() {
            return None; // a vertex with two outgoing boundary edges: a pinch
        }
    }
    let start = *next.keys().min()?;
    let mut lp = vec![start];
    let mut v = next[&start];
    while v != start {
        if lp.len() > next.len() {
            return None;
        }
        lp.push(v);
        v = *next.get(&v)?;
    }
    if lp.len() != next.len() {
        return None; // several boundary loops: Q has a hole
    }
    let mut verts: Vec<u32> = q.iter().flat_map(|&t| s.tris[t as usize]).collect();
    verts.sort_unstable();
    verts.dedup();
    let euler = verts.len() as i64 - edges_total as i64 + q.len() as i64;
    (euler == 1).then_some(lp)
}
