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
    let n = samples.len();
    // The reader refused repeated ids.
    let index = crate::input::swc::IdIndex::new(samples.iter().map(|s| s.id))
        .map_err(|(second, _)| Error::swc(&path, samples[second].line as usize, "duplicate id"))?;
    let mut parent = vec![NO_PARENT; n];
    for (i, s) in samples.iter().enumerate() {
        if s.parent >= 0 {
            if s.parent == s.id {
                return Err(Error::swc(
                    &path,
                    s.line as usize,
                    format!("sample {} is its own parent", s.id),
                ));
            }
            parent[i] = index.get(s.parent).ok_or_else(|| {
                Error::swc(
                    &path,
                    s.line as usize,
                    format!("parent id {} does not exist", s.parent),
                )
            })?;
        }
    }
    check_acyclic(&samples, &parent, &path)?;

    // Merge duplicate consecutive points. The tolerance is relative to the
    // skeleton's extent so it works in nm and in µm alike.
    let extent = samples
        .iter()
        .flat_map(|s| s.pos)
        .fold(0f64, |m, v| m.max(v.abs()))
        .max(1e-30);
    let eps = 1e-9 * extent;
    let mut merged_into: Vec<u32> = (0..n as u32).collect();
    let mut radius: Vec<f64> = samples.iter().map(|s| s.radius).collect();
    let mut cleaning = Cleaning::default();
    for s in &samples {
        if !s.radius.is_finite() || s.radius < 0.0 {
            cleaning.negative_radii += 1;
        } else if s.radius == 0.0 {
            cleaning.zero_radii += 1;
        }
    }
    // Process in an order where parents come first so chains of duplicates collapse.
    let file_order = topological_order(&parent);
    for &i in &file_order {
        let i = i as usize;
        let p = parent[i];
        if p == NO_PARENT {
            continue;
        }
        let target = find(&mut merged_into, p);
        if dist(samples[i].pos, samples[target as usize].pos) <= eps
            && samples[i].kind == samples[target as usize].kind
        {
            merged_into[i] = target;
            if radius[i].is_finite() && radius[i] > radius[target as usize] {
                radius[target as usize] = radius[i];
            }
            cleaning.duplicates_merged += 1;
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
    let m = kept.len();
    let mut file_parent = vec![NO_PARENT; m];
    for (k, &i) in kept.iter().enumerate() {
        let p = parent[i];
        if p != NO_PARENT {
            file_parent[k] = new_index[find(&mut merged_into, p) as usize];
        }
    }
    let ids: Vec<i64> = kept.iter().map(|&i| samples[i].id).collect();
    let kinds: Vec<i32> = kept.iter().map(|&i| samples[i].kind).collect();
    let pos: Vec<[f64; 3]> = kept.iter().map(|&i| samples[i].pos).collect();
    let lines: Vec<u32> = kept.iter().map(|&i| samples[i].line).collect();
    let mut radius: Vec<f64> = kept.iter().map(|&i| radius[i]).collect();

    // Undirected adjacency, for tree discovery, re-rooting and radius filling.
    let mut degree = vec![0u32; m + 1];
    for (k, &p) in file_parent.iter().enumerate() {
        if p != NO_PARENT {
            degree[k] += 1;
            degree[p as usize] += 1;
        }
    }
    let adj_start = prefix_sum(&degree);
    let mut fill = adj_start.clone();
    let mut adj = vec![0u32; *adj_start.last().unwrap_or(&0) as usize];
    for (k, &p) in file_parent.iter().enumerate() {
        if p != NO_PARENT {
            adj[fill[k] as usize] = p;
            fill[k] += 1;
            adj[fill[p as usize] as usize] = k as u32;
            fill[p as usize] += 1;
        }
    }
    let neighbours = |k: usize| &adj[adj_start[k] as usize..adj_start[k + 1] as usize];

    // Trees: connected components, discovered from file roots in file order.
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
            for &q in neighbours(k) {
                if tree_of[q as usize] == NO_PARENT {
                    tree_of[q as usize] = t;
                    members.push(q);
                }
            }
        }
        components.push(members);
    }

    fill_missing_radii(
        &mut radius,
        &pos,
        &file_parent,
        &components,
        &kinds,
        &adj_start,
        &adj,
        &mut cleaning,
    );

    // Soma per tree, then re-root every tree at its soma (or keep the file root).
    let mut trees = Vec::with_capacity(components.len());
    let mut geo_parent = vec![NO_PARENT; m];
    let mut order = Vec::with_capacity(m);
    for members in &components {
        let soma_samples = largest_soma_group(members, &kinds, &neighbours);
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
        let soma = fit_soma(&soma_samples, &pos, &radius);
        trees.push(Tree {
            root,
            soma,
            len: members.len() as u32,
        });
    }

    let mut counts = vec![0u32; m + 1];
    for &p in &geo_parent {
        if p != NO_PARENT {
            counts[p as usize] += 1;
        }
    }
    let child_start = prefix_sum(&counts);
    let mut fill = child_start.clone();
    let mut child_list = vec![0u32; m - trees.len()];
    // Children in file order, which keeps the output deterministic and familiar.
    for (k, &p) in geo_parent.iter().enumerate() {
        if p != NO_PARENT {
            child_list[fill[p as usize] as usize] = k as u32;
            fill[p as usize] += 1;
        }
    }

    Ok(Morphology {
        name: path,
        ids,
        kinds,
        pos,
        radius,
        lines,
        file_parent,
        parent: geo_parent,
        child_start,
        child_list,
        order,
        tree_of,
        trees,
        cleaning,
        comment_lines,
    })
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

pub(super) fn check_acyclic(samples: &[RawSample], parent: &[u32], path: &str) -> Result<()> {
    let order = topological_order(parent);
    if order.len() == samples.len() {
        return Ok(());
    }
    let mut reached = vec![false; samples.len()];
    for &i in &order {
        reached[i as usize] = true;
    }
    // Every unreached sample is in a cycle or hangs below one; walk up from the
    // first one (in file order) until a sample repeats to find the cycle itself.
    let start = reached.iter().position(|r| !r).unwrap_or(0);
    let mut seen = HashMap::new();
    let mut walk = Vec::new();
    let mut k = start as u32;
    while !seen.contains_key(&k) {
        seen.insert(k, walk.len());
        walk.push(k);
        k = parent[k as usize];
    }
    let cycle = &walk[seen[&k]..];
    let first = cycle
        .iter()
        .copied()
        .min_by_key(|&i| samples[i as usize].line)
        .unwrap_or(k);
    let ids: Vec<String> = cycle
        .iter()
        .take(8)
        .map(|&i| samples[i as usize].id.to_string())
        .collect();
    let more = if cycle.len() > 8 { " → …" } else { "" };
    Err(Error::swc(
        path,
        samples[first as usize].line as usize,
        format!(
            "parent links form a cycle: {} → {}{more}",
            ids.join(" → "),
            samples[cycle[0] as usize].id
        ),
    ))
}

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
    let missing: Vec<bool> = radius.iter().map(|&r| !valid(r)).collect();
    let _ = &missing;
    let neighbours = |k: usize| &adj[adj_start[k] as usize..adj_start[k + 1] as usize];
    // Soma points first: their neighbours' radii decide the fallback.
    for k in 0..radius.len() {
        if missing[k] && kinds[k] == 1 {
            let best = neighbours(k)
                .iter()
                .map(|&q| radius[q as usize])
                .filter(|&r| valid(r))
                .fold(0f64, f64::max);
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
