//! Branch identification (paper §3.1): the tree → a list of unbranched paths.
//!
//! At every branch point the *best successor* continues the current branch and
//! every other child starts a *secondary* branch. As DESIGN.md reads the paper,
//! the best successor is the child whose direction deviates least from the
//! incoming direction; when the two smallest deviations differ by less than the
//! threshold `t` ([`crate::Params::angle_threshold`]), the child whose radius is
//! closer to the branch point's wins. The paper handles two children; any number
//! works here, each extra child being one more secondary.
//!
//! Each branch starts with the sample it grows out of (the branch point on its
//! primary, or the soma sample for a soma branch), so the resampled curve and the
//! first contours cover the gap that splicing later bridges. A tree without a
//! soma starts with one *root* branch at its root; there the incoming direction
//! is unknown, so the thickest child continues it.

use crate::input::morphology::Morphology;

/// Where a branch starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Attachment {
    /// The root branch of a tree without a soma: it starts at a free end.
    Root,
    /// A soma branch: it leaves the soma of tree `tree`.
    Soma {
        /// Index of the tree in [`Morphology::trees`].
        tree: u32,
    },
    /// A secondary branch growing out of `parent` at its sample number `at`.
    Secondary {
        /// Index of the primary branch.
        parent: u32,
        /// Position of the branch point in the primary's `samples`.
        at: u32,
    },
}

/// An unbranched path of samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// Sample indices in order; `samples[0]` is the branch point or soma sample
    /// it grows out of (for the root branch, the root itself).
    pub samples: Vec<u32>,
    /// Where it starts.
    pub attachment: Attachment,
}

impl Branch {
    /// The sample each contour vertex of the branch is labelled with, per
    /// point: a trunk's vertices carry neurite samples, never the soma's
    /// (the soma sample is only where the trunk's track begins).
    pub fn vertex_labels(&self) -> Vec<u32> {
        let mut labels = self.samples.clone();
        if matches!(self.attachment, Attachment::Soma { .. }) && labels.len() > 1 {
            labels[0] = labels[1];
        }
        labels
    }
}

/// Splits the morphology into branches, primaries before their secondaries.
pub fn identify(m: &Morphology, angle_threshold_deg: f64) -> Vec<Branch> {
    let soma = m.soma_mask();
    let threshold = angle_threshold_deg.to_radians();
    let mut branches: Vec<Branch> = Vec::new();
    // Work list of branches to grow: (first sample, second sample, attachment).
    let mut pending: Vec<(u32, u32, Attachment)> = Vec::new();
    for (ti, tree) in m.trees().iter().enumerate() {
        if let Some(tree_soma) = &tree.soma {
            for &s in &tree_soma.samples {
                for &c in m.children(s) {
                    if !soma[c as usize] {
                        pending.push((s, c, Attachment::Soma { tree: ti as u32 }));
                    }
                }
            }
        } else {
            let r = tree.root;
            let kids = m.children(r);
            if kids.is_empty() {
                // A lone sample: a branch of one point (meshed as a sphere-like capsule).
                branches.push(Branch {
                    samples: vec![r],
                    attachment: Attachment::Root,
                });
                continue;
            }
            let first = thickest(m, kids);
            // The root's other children grow out of the root branch's first sample.
            pending.push((r, first, Attachment::Root));
        }
        // Grow in FIFO order so primaries get lower ids than their secondaries.
        let mut head = 0;
        while head < pending.len() {
            let (start, second, attachment) = pending[head];
            head += 1;
            let id = branches.len() as u32;
            let mut samples = vec![start, second];
            if attachment == Attachment::Root {
                for &c in m.children(start) {
                    if c != second {
                        pending.push((start, c, Attachment::Secondary { parent: id, at: 0 }));
                    }
                }
            }
            let mut cur = second;
            loop {
                let kids = m.children(cur);
                if kids.is_empty() {
                    break;
                }
                let prev = samples[samples.len() - 2];
                let next = best_successor(m, prev, cur, kids, threshold);
                let at = (samples.len() - 1) as u32;
                for &c in kids {
                    if c != next {
                        pending.push((cur, c, Attachment::Secondary { parent: id, at }));
                    }
                }
                samples.push(next);
                cur = next;
            }
            branches.push(Branch {
                samples,
                attachment,
            });
        }
        pending.clear();
    }
    branches
}

fn thickest(m: &Morphology, kids: &[u32]) -> u32 {
    let r = m.radii();
    let mut best = kids[0];
    for &c in &kids[1..] {
        if r[c as usize] > r[best as usize] {
            best = c;
        }
    }
    best
}

/// Direction from `from` towards `to`, looking further down `to`'s first children
/// when the two coincide (zero-length segments).
fn direction(m: &Morphology, from: u32, to: u32) -> Option<[f64; 3]> {
    let p = m.positions();
    let mut target = to;
    for _ in 0..16 {
        let a = p[from as usize];
        let b = p[target as usize];
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if len > 0.0 {
            return Some([d[0] / len, d[1] / len, d[2] / len]);
        }
        target = *m.children(target).first()?;
    }
    None
}

/// The child that continues the branch through `cur` (arriving from `prev`).
pub fn best_successor(m: &Morphology, prev: u32, cur: u32, kids: &[u32], threshold: f64) -> u32 {
    if kids.len() == 1 {
        return kids[0];
    }
    let incoming = direction(m, prev, cur);
    let angle = |c: u32| -> f64 {
        match (incoming, direction(m, cur, c)) {
            (Some(a), Some(b)) => (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
                .clamp(-1.0, 1.0)
                .acos(),
            _ => std::f64::consts::FRAC_PI_2,
        }
    };
    let mut ranked: Vec<(f64, usize, u32)> = kids
        .iter()
        .enumerate()
        .map(|(i, &c)| (angle(c), i, c))
        .collect();
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let (a0, _, c0) = ranked[0];
    let (a1, _, c1) = ranked[1];
    if a1 - a0 < threshold {
        let r = m.radii();
        let rc = r[cur as usize];
        if (r[c1 as usize] - rc).abs() < (r[c0 as usize] - rc).abs() {
            return c1;
        }
    }
    c0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::swc::SwcFile;

    fn morph(text: &str) -> Morphology {
        Morphology::from_file(SwcFile::parse(text.as_bytes(), "t.swc").unwrap()).unwrap()
    }

    #[test]
    fn straightest_child_continues() {
        // 3 → (4 straight on, 5 at 60°): 4 continues, 5 is secondary at sample 2.
        let m = morph(
            "1 3 0 0 0 1 -1\n2 3 1 0 0 1 1\n3 3 2 0 0 1 2\n4 3 3 0.1 0 1 3\n5 3 2.5 0.87 0 1 3\n",
        );
        let b = identify(&m, 10.0);
        assert_eq!(b.len(), 2);
        assert_eq!(b[0].samples, vec![0, 1, 2, 3]);
        assert_eq!(b[1].samples, vec![2, 4]);
        assert_eq!(b[1].attachment, Attachment::Secondary { parent: 0, at: 2 });
    }

    #[test]
    fn near_tie_goes_to_the_closer_radius() {
        // Children at +20° and −25°: within t = 10°, so the radius decides.
        let (s20, c20) = (20f64.to_radians().sin(), 20f64.to_radians().cos());
        let (s25, c25) = (25f64.to_radians().sin(), 25f64.to_radians().cos());
        let text = format!(
            "1 3 0 0 0 2 -1\n2 3 1 0 0 2 1\n3 3 {} {} 0 0.5 2\n4 3 {} {} 0 1.9 2\n",
            1.0 + c20,
            s20,
            1.0 + c25,
            -s25
        );
        let m = morph(&text);
        let b = identify(&m, 10.0);
        assert_eq!(b[0].samples, vec![0, 1, 3], "radius 1.9 is closer to 2");
        // With a 1° threshold the angle alone decides.
        let b = identify(&m, 1.0);
        assert_eq!(b[0].samples, vec![0, 1, 2]);
    }

    #[test]
    fn multifurcation_gives_one_secondary_per_extra_child() {
        let mut text = String::from("1 3 0 0 0 1 -1\n2 3 1 0 0 1 1\n");
        for k in 0..6 {
            let a = f64::from(k) * 0.5;
            text.push_str(&format!(
                "{} 3 {} {} 0 0.5 2\n",
                k + 3,
                1.0 + a.cos(),
                a.sin()
            ));
        }
        let m = morph(&text);
        let b = identify(&m, 10.0);
        assert_eq!(b.len(), 6);
        assert_eq!(b[0].samples, vec![0, 1, 2]);
        assert!(
            b[1..]
                .iter()
                .all(|x| x.attachment == Attachment::Secondary { parent: 0, at: 1 })
        );
    }

    #[test]
    fn soma_branches_start_at_the_soma() {
        let m =
            morph("1 1 0 0 0 5 -1\n2 3 6 0 0 1 1\n3 3 9 0 0 1 2\n4 3 -6 0 0 1 1\n5 3 0 6 0 1 1\n");
        let b = identify(&m, 10.0);
        assert_eq!(b.len(), 3);
        assert!(
            b.iter()
                .all(|x| x.samples[0] == 0 && x.attachment == Attachment::Soma { tree: 0 })
        );
        assert_eq!(b[0].samples, vec![0, 1, 2]);
    }

    #[test]
    fn root_with_several_children_splits_at_its_first_sample() {
        let m = morph("1 3 0 0 0 1 -1\n2 3 1 0 0 2 1\n3 3 -1 0 0 1 1\n4 3 2 0 0 1 2\n");
        let b = identify(&m, 10.0);
        assert_eq!(b[0].samples, vec![0, 1, 3]);
        assert_eq!(b[1].samples, vec![0, 2]);
        assert_eq!(b[1].attachment, Attachment::Secondary { parent: 0, at: 0 });
    }

    #[test]
    fn every_sample_but_somas_is_in_exactly_one_branch_as_non_first() {
        let m = morph(
            "1 1 0 0 0 3 -1\n2 3 4 0 0 1 1\n3 3 8 0 0 1 2\n4 3 9 2 0 1 3\n5 3 9 -2 0 1 3\n6 3 10 3 0 1 4\n",
        );
        let b = identify(&m, 10.0);
        let mut seen = vec![0; m.len()];
        for x in &b {
            for &s in &x.samples[1..] {
                seen[s as usize] += 1;
            }
        }
        assert_eq!(seen, vec![0, 1, 1, 1, 1, 1]);
    }
}
