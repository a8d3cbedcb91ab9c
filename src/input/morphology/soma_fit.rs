//! The soma of a tree from its type-1 samples: the largest connected group,
//! and the sphere that stands for it ([`super::SomaKind`]).

use std::collections::HashMap;

use super::{Soma, SomaKind, dist};

/// The largest connected group of type-1 samples in a tree (empty if none).
pub(super) fn largest_soma_group<'a>(
    members: &[u32],
    kinds: &[i32],
    neighbours: &impl Fn(usize) -> &'a [u32],
) -> Vec<u32> {
    let mut best: Vec<u32> = Vec::new();
    let mut seen: HashMap<u32, ()> = HashMap::new();
    for &s in members {
        if kinds[s as usize] != 1 || seen.contains_key(&s) {
            continue;
        }
        let mut group = vec![s];
        seen.insert(s, ());
        let mut head = 0;
        while head < group.len() {
            let k = group[head];
            head += 1;
            for &q in neighbours(k as usize) {
                if kinds[q as usize] == 1 && !seen.contains_key(&q) {
                    seen.insert(q, ());
                    group.push(q);
                }
            }
        }
        if group.len() > best.len() {
            best = group;
        }
    }
    best
}

pub(super) fn fit_soma(samples: &[u32], pos: &[[f64; 3]], radius: &[f64]) -> Option<Soma> {
    let (&first, _) = samples.split_first()?;
    let p = |i: u32| pos[i as usize];
    if samples.len() == 1 {
        return Some(Soma {
            kind: SomaKind::SinglePoint,
            samples: samples.to_vec(),
            center: p(first),
            radius: radius[first as usize],
        });
    }
    if samples.len() == 3
        && let Some((center, r)) = three_point(samples, pos, radius)
    {
        return Some(Soma {
            kind: SomaKind::ThreePoint,
            samples: samples.to_vec(),
            center,
            radius: r,
        });
    }
    let k = samples.len() as f64;
    let mut c = [0.0; 3];
    for &i in samples {
        for a in 0..3 {
            c[a] += p(i)[a] / k;
        }
    }
    let mean_dist = samples.iter().map(|&i| dist(p(i), c)).sum::<f64>() / k;
    // Coincident soma points have no spread: fall back to their mean radius.
    let r = if mean_dist > 0.0 {
        mean_dist
    } else {
        samples.iter().map(|&i| radius[i as usize]).sum::<f64>() / k
    };
    Some(Soma {
        kind: SomaKind::MultiPoint,
        samples: samples.to_vec(),
        center: c,
        radius: r,
    })
}

/// Recognises NeuroMorpho's 3-point soma in any orientation: one point with the
/// two others at ±r from it, on opposite sides.
pub(super) fn three_point(
    samples: &[u32],
    pos: &[[f64; 3]],
    radius: &[f64],
) -> Option<([f64; 3], f64)> {
    for (ci, &c) in samples.iter().enumerate() {
        let others: Vec<u32> = samples
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != ci)
            .map(|(_, &s)| s)
            .collect();
        let pc = pos[c as usize];
        let r = radius[c as usize];
        let (a, b) = (pos[others[0] as usize], pos[others[1] as usize]);
        let (da, db) = (dist(a, pc), dist(b, pc));
        let mid = [
            (a[0] + b[0]) / 2.0,
            (a[1] + b[1]) / 2.0,
            (a[2] + b[2]) / 2.0,
        ];
        let tol = 0.05 * r.max(da).max(db);
        if r > 0.0 && (da - r).abs() <= tol && (db - r).abs() <= tol && dist(mid, pc) <= tol {
            return Some((pc, r));
        }
    }
    None
}
