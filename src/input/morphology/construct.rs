//! Steps 1 to 4 of the module docs: ids to indices, duplicates merged,
//! radii filled, soma and roots.

use std::collections::{HashMap, VecDeque};

use super::soma_fit::{fit_soma, largest_soma_group};
use super::{Cleaning, Morphology, NO_PARENT, Tree, dist};
use crate::error::{Error, Result};
use crate::input::swc::{RawSample, SwcFile};

pub(super) fn build(file: SwcFile) -> Result<Morphology> {
    let SwcFile {
        path,
        samples,
        comment_lines,
    } = file;
    let mut parent = link_parents(&samples, &path)?;
    let mut cleaning = Cleaning::default();
    let first_cycle = break_cycles(&samples, &mut parent, &mut cleaning);
    let kept = merge_duplicates(&samples, &parent, &mut cleaning);
    let Kept {
        ids,
        kinds,
        pos,
        lines,
        mut radius,
        file_parent,
    } = kept;
    let adj = Adjacency::of(&file_parent);
    let (tree_of, components) = trees_of(&file_parent, &adj);
    fill_missing_radii(
        &mut radius,
        &pos,
        &file_parent,
        &components,
        &kinds,
        &adj.start,
        &adj.list,
        &mut cleaning,
    );
    let (trees, parent, order) = rooted_at_somas(&components, &kinds, &pos, &radius, &adj);
    let (child_start, child_list) = children_of(&parent, trees.len());
    Ok(Morphology {
        name: path,
        ids,
        kinds,
        pos,
        radius,
        lines,
        file_parent,
        parent,
        child_start,
        child_list,
        order,
        tree_of,
        trees,
        cleaning,
        comment_lines,
        first_cycle,
    })
}

/// Step 1: each sample's parent as an index ([`NO_PARENT`] for a root); a
/// sample that is its own parent, or whose parent id does not exist, is an
/// error at its line.
fn link_parents(samples: &[RawSample], path: &str) -> Result<Vec<u32>> {
    // The reader refused repeated ids.
    let index = crate::input::swc::IdIndex::new(samples.iter().map(|s| s.id))
        .map_err(|(second, _)| Error::swc(path, samples[second].line as usize, "duplicate id"))?;
    let mut parent = vec![NO_PARENT; samples.len()];
    for (i, s) in samples.iter().enumerate() {
        if s.parent >= 0 {
            if s.parent == s.id {
                return Err(Error::swc(
                    path,
                    s.line as usize,
                    format!("sample {} is its own parent", s.id),
                ));
            }
            parent[i] = index.get(s.parent).ok_or_else(|| {
                Error::swc(
                    path,
                    s.line as usize,
                    format!("parent id {} does not exist", s.parent),
                )
            })?;
        }
    }
    Ok(parent)
}

/// The samples left after step 2, in file order, with their parents among
/// them.
struct Kept {
    ids: Vec<i64>,
    kinds: Vec<i32>,
    pos: Vec<[f64; 3]>,
    lines: Vec<u32>,
    radius: Vec<f64>,
    file_parent: Vec<u32>,
}

/// Step 2: duplicate consecutive points merged into their parents (the
/// parent keeps the larger radius and adopts the children), the survivors
/// compacted in file order; the missing radii and the merges counted into
/// `cleaning`.
fn merge_duplicates(samples: &[RawSample], parent: &[u32], cleaning: &mut Cleaning) -> Kept {
    let n = samples.len();
    // Two points are one where they differ by the noise of writing the same
    // coordinates: a tolerance relative to their own magnitude works in nm
    // and in µm alike, and one outlying coordinate elsewhere in the file
    // cannot make it swallow whole branches.
    let magnitude = |p: [f64; 3]| p.iter().fold(1e-30f64, |m, v| m.max(v.abs()));
    let eps = |a: [f64; 3], b: [f64; 3]| 1e-9 * magnitude(a).max(magnitude(b));
    let mut merged_into: Vec<u32> = (0..n as u32).collect();
    let mut radius: Vec<f64> = samples.iter().map(|s| s.radius).collect();
    for s in samples {
        if !s.radius.is_finite() || s.radius < 0.0 {
            cleaning.negative_radii += 1;
        } else if s.radius == 0.0 {
            cleaning.zero_radii += 1;
        }
    }
    // Process in an order where parents come first so chains of duplicates collapse.
    for &i in &topological_order(parent) {
        let i = i as usize;
        let p = parent[i];
        if p == NO_PARENT {
            continue;
        }
        let target = find(&mut merged_into, p);
        let (a, b) = (samples[i].pos, samples[target as usize].pos);
        if dist(a, b) <= eps(a, b) && samples[i].kind == samples[target as usize].kind {
            merged_into[i] = target;
            if radius[i].is_finite() && radius[i] > radius[target as usize] {
                radius[target as usize] = radius[i];
            }
            cleaning.duplicates_merged += 1;
        }
    }
    // Copies: a sample at exactly the place and of the type of another
    // whose parent is (after merging) the same, or a root on another root
    // (several fragments of one reconstruction each carrying the soma, or a
    // cell written twice), is merged into the first; parents first, so a
    // copied subtree collapses onto its original. Meshed apart, the two
    // would be coincident surfaces, which no union can separate.
    let mut first: HashMap<(u32, i32, [u64; 3]), u32> = HashMap::new();
    for &i in &topological_order(parent) {
        if merged_into[i as usize] != i {
            continue;
        }
        let p = parent[i as usize];
        let up = if p == NO_PARENT {
            NO_PARENT
        } else {
            find(&mut merged_into, p)
        };
        let s = &samples[i as usize];
        let key = (up, s.kind, s.pos.map(f64::to_bits));
        match first.get(&key) {
            Some(&j) if j != i => {
                merged_into[i as usize] = j;
                if radius[i as usize].is_finite() && radius[i as usize] > radius[j as usize] {
                    radius[j as usize] = radius[i as usize];
                }
                cleaning.copies_merged += 1;
            }
            _ => {
                first.insert(key, i);
            }
        }
    }
    // Compact the survivors, keeping file order.
    let mut new_index = vec![NO_PARENT; n];
    let mut kept = Vec::with_capacity(n);
    for i in 0..n {
        if merged_into[i] == i as u32 {
            new_index[i] = kept.len() as u32;
            kept.push(i);
        }
    }
    let mut file_parent = vec![NO_PARENT; kept.len()];
    for (k, &i) in kept.iter().enumerate() {
        let p = parent[i];
        if p != NO_PARENT {
            file_parent[k] = new_index[find(&mut merged_into, p) as usize];
        }
    }
    Kept {
        ids: kept.iter().map(|&i| samples[i].id).collect(),
        kinds: kept.iter().map(|&i| samples[i].kind).collect(),
        pos: kept.iter().map(|&i| samples[i].pos).collect(),
        lines: kept.iter().map(|&i| samples[i].line).collect(),
        radius: kept.iter().map(|&i| radius[i]).collect(),
        file_parent,
    }
}

/// The undirected adjacency of a forest given by its parent links, for tree
/// discovery, re-rooting and radius filling.
struct Adjacency {
    /// Where each sample's neighbours begin in `list` (one more entry ends
    /// the last).
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Adjacency {
    fn of(parent: &[u32]) -> Adjacency {
        let m = parent.len();
        let mut degree = vec![0u32; m + 1];
        for (k, &p) in parent.iter().enumerate() {
            if p != NO_PARENT {
                degree[k] += 1;
                degree[p as usize] += 1;
            }
        }
        let start = prefix_sum(&degree);
        let mut fill = start.clone();
        let mut list = vec![0u32; *start.last().unwrap_or(&0) as usize];
        for (k, &p) in parent.iter().enumerate() {
            if p != NO_PARENT {
                list[fill[k] as usize] = p;
                fill[k] += 1;
                list[fill[p as usize] as usize] = k as u32;
                fill[p as usize] += 1;
            }
        }
        Adjacency { start, list }
    }

    /// The neighbours of sample `k`.
    fn of_sample(&self, k: usize) -> &[u32] {
        &self.list[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// The trees: connected components, discovered from file roots in file
/// order. The tree of every sample, and each tree's samples.
fn trees_of(file_parent: &[u32], adj: &Adjacency) -> (Vec<u32>, Vec<Vec<u32>>) {
    let m = file_parent.len();
    let mut tree_of = vec![NO_PARENT; m];
    let mut components: Vec<Vec<u32>> = Vec::new();
    for root in 0..m {
        if file_parent[root] != NO_PARENT || tree_of[root] != NO_PARENT {
            continue;
        }
        let t = components.len() as u32;
        let mut members = vec![root as u32];
        tree_of[root] = t;
        let mut head = 0;
        while head < members.len() {
            let k = members[head] as usize;
            head += 1;
            for &q in adj.of_sample(k) {
                if tree_of[q as usize] == NO_PARENT {
                    tree_of[q as usize] = t;
                    members.push(q);
                }
            }
        }
        components.push(members);
    }
    (tree_of, components)
}

/// Step 4: each tree's soma, and the tree re-rooted at it (or kept at its
/// file root): the trees, every sample's parent, and the samples in an
/// order where parents come first.
fn rooted_at_somas(
    components: &[Vec<u32>],
    kinds: &[i32],
    pos: &[[f64; 3]],
    radius: &[f64],
    adj: &Adjacency,
) -> (Vec<Tree>, Vec<u32>, Vec<u32>) {
    let m = kinds.len();
    let neighbours = |k: usize| adj.of_sample(k);
    let mut trees = Vec::with_capacity(components.len());
    let mut geo_parent = vec![NO_PARENT; m];
    let mut order = Vec::with_capacity(m);
    for members in components {
        let soma_samples = largest_soma_group(members, kinds, &neighbours);
        let root = soma_samples.first().copied().unwrap_or(members[0]);
        // BFS over undirected edges gives the re-rooted parent links.
        let start = order.len();
        order.push(root);
        geo_parent[root as usize] = NO_PARENT;
        let mut head = start;
        while head < order.len() {
            let k = order[head];
            head += 1;
            for &q in neighbours(k as usize) {
                if q != root && geo_parent[q as usize] == NO_PARENT && q != geo_parent[k as usize] {
                    geo_parent[q as usize] = k;
                    order.push(q);
                }
            }
        }
        let soma = fit_soma(&soma_samples, pos, radius);
        trees.push(Tree {
            root,
            soma,
            len: members.len() as u32,
        });
    }
    (trees, geo_parent, order)
}

/// The children of every sample, in file order (which keeps the output
/// deterministic and familiar), as a start per sample (one more entry ends
/// the last) and a list.
fn children_of(parent: &[u32], n_trees: usize) -> (Vec<u32>, Vec<u32>) {
    let m = parent.len();
    let mut counts = vec![0u32; m + 1];
    for &p in parent {
        if p != NO_PARENT {
            counts[p as usize] += 1;
        }
    }
    let child_start = prefix_sum(&counts);
    let mut fill = child_start.clone();
    let mut child_list = vec![0u32; m - n_trees];
    for (k, &p) in parent.iter().enumerate() {
        if p != NO_PARENT {
            child_list[fill[p as usize] as usize] = k as u32;
            fill[p as usize] += 1;
        }
    }
    (child_start, child_list)
}

pub(super) fn prefix_sum(counts: &[u32]) -> Vec<u32> {
    let mut start = Vec::with_capacity(counts.len());
    let mut acc = 0u32;
    for &c in counts {
        start.push(acc);
        acc += c;
    }
    start
}

pub(super) fn find(merged_into: &mut [u32], mut i: u32) -> u32 {
    while merged_into[i as usize] != i {
        let next = merged_into[i as usize];
        merged_into[i as usize] = merged_into[next as usize];
        i = next;
    }
    i
}

/// Parents before children; assumes the links are acyclic.
pub(super) fn topological_order(parent: &[u32]) -> Vec<u32> {
    let n = parent.len();
    let mut counts = vec![0u32; n + 1];
    for &p in parent {
        if p != NO_PARENT {
            counts[p as usize] += 1;
        }
    }
    let start = prefix_sum(&counts);
    let mut fill = start.clone();
    let mut children = vec![0u32; n];
    let mut roots = Vec::new();
    for (i, &p) in parent.iter().enumerate() {
        if p == NO_PARENT {
            roots.push(i as u32);
        } else {
            children[fill[p as usize] as usize] = i as u32;
            fill[p as usize] += 1;
        }
    }
    let mut order = roots;
    let mut head = 0;
    while head < order.len() {
        let k = order[head] as usize;
        head += 1;
        order.extend_from_slice(&children[start[k] as usize..start[k + 1] as usize]);
    }
    order
}

/// Step 1b: parent cycles broken. In each cycle of parent links, the sample
/// that comes first in the file loses its parent link and becomes a root
/// (parents normally come before their children, so the link back from it
/// is the one out of order); the samples hanging below a cycle stay where
/// they are. Counted into `cleaning`; the first cycle's line and ids are
/// returned for the error of a caller that refuses cycles
/// ([`Morphology::refuse_cycles`]). Linear in the samples.
fn break_cycles(
    samples: &[RawSample],
    parent: &mut [u32],
    cleaning: &mut Cleaning,
) -> Option<(u32, String)> {
    let order = topological_order(parent);
    if order.len() == samples.len() {
        return None;
    }
    // 0: not seen, 1: on the walk under way, 2: settled (reached from a root,
    // or walked before).
    let mut state = vec![0u8; samples.len()];
    for &i in &order {
        state[i as usize] = 2;
    }
    let mut first = None;
    let mut walk = Vec::new();
    for start in 0..samples.len() {
        if state[start] != 0 {
            continue;
        }
        walk.clear();
        let mut k = start as u32;
        // Every sample not reached from a root has a parent: a cycle is met.
        while state[k as usize] == 0 {
            state[k as usize] = 1;
            walk.push(k);
            k = parent[k as usize];
        }
        if state[k as usize] == 1 {
            let from = walk.iter().position(|&w| w == k).unwrap_or(0);
            let cycle = &walk[from..];
            let cut = cycle
                .iter()
                .copied()
                .min_by_key(|&i| samples[i as usize].line)
                .unwrap_or(k);
            if first.is_none() {
                let ids: Vec<String> = cycle
                    .iter()
                    .take(8)
                    .map(|&i| samples[i as usize].id.to_string())
                    .collect();
                let more = if cycle.len() > 8 { " → …" } else { "" };
                first = Some((
                    samples[cut as usize].line,
                    format!(
                        "parent links form a cycle: {} → {}{more}",
                        ids.join(" → "),
                        samples[cycle[0] as usize].id
                    ),
                ));
            }
            parent[cut as usize] = NO_PARENT;
            cleaning.cycles_broken += 1;
        }
        for &w in &walk {
            state[w as usize] = 2;
        }
    }
    first
}

/// A soma point's radius below this fraction of its widest neighbour's is
/// taken as missing.
const TINY_SOMA: f64 = 1e-3;

pub(super) fn fill_missing_radii(
    radius: &mut [f64],
    pos: &[[f64; 3]],
    parent: &[u32],
    components: &[Vec<u32>],
    kinds: &[i32],
    adj_start: &[u32],
    adj: &[u32],
    cleaning: &mut Cleaning,
) {
    let valid = |r: f64| r.is_finite() && r > 0.0;
    let neighbours = |k: usize| &adj[adj_start[k] as usize..adj_start[k + 1] as usize];
    let widest_neighbour = |k: usize, radius: &[f64]| {
        neighbours(k)
            .iter()
            .map(|&q| radius[q as usize])
            .filter(|&r| valid(r))
            .fold(0f64, f64::max)
    };
    // A soma point a thousand times thinner than a neighbour holds no soma
    // (a radius of 1e-30 written for "unknown"): its trunks would all leave
    // one point and cross each other. It counts as missing.
    let missing: Vec<bool> = (0..radius.len())
        .map(|k| {
            !valid(radius[k])
                || (kinds[k] == 1 && radius[k] < TINY_SOMA * widest_neighbour(k, radius))
        })
        .collect();
    // Soma points first: their neighbours' radii decide the fallback.
    for k in 0..radius.len() {
        if missing[k] && kinds[k] == 1 {
            let best = widest_neighbour(k, radius);
            if best > 0.0 {
                radius[k] = 1.5 * best;
                cleaning.soma_radius_fallbacks += 1;
            }
        }
    }
    // Multi-source BFS from every valid radius: a missing radius takes the value
    // of the nearest valid sample in tree hops.
    let mut queue: VecDeque<u32> = (0..radius.len() as u32)
        .filter(|&k| valid(radius[k as usize]))
        .collect();
    let mut done: Vec<bool> = radius.iter().map(|&r| valid(r)).collect();
    while let Some(k) = queue.pop_front() {
        for &q in neighbours(k as usize) {
            if !done[q as usize] {
                done[q as usize] = true;
                radius[q as usize] = radius[k as usize];
                cleaning.radii_from_neighbours += 1;
                queue.push_back(q);
            }
        }
    }
    // Trees without a single valid radius.
    for members in components {
        if members.iter().all(|&k| done[k as usize]) {
            continue;
        }
        let mut seg: Vec<f64> = members
            .iter()
            .filter(|&&k| parent[k as usize] != NO_PARENT)
            .map(|&k| dist(pos[k as usize], pos[parent[k as usize] as usize]))
            .filter(|&d| d > 0.0)
            .collect();
        seg.sort_by(f64::total_cmp);
        let median = seg.get(seg.len() / 2).copied().unwrap_or(1.0);
        let r = 0.25 * median;
        for &k in members {
            if !done[k as usize] {
                radius[k as usize] = if kinds[k as usize] == 1 { 1.5 * r } else { r };
                if kinds[k as usize] == 1 {
                    cleaning.soma_radius_fallbacks += 1;
                } else {
                    cleaning.radii_from_default += 1;
                }
            }
        }
    }
}
